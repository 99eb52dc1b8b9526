"""The cpfg language of L-Studio and ABOP (seed 003 §5.10): ``Lsystem: … endlsystem``.

::

    #define N 2.2
    Lsystem: 1
    derivation length: 7
    seed: 2454
    Axiom: F(1)
    F(x) --> X(x*N) [+F(1)] F[-F(1)] F[+F(1)] !F(1) : 0.4
    F(x) --> X(x) [-F(1)+F(1)] !F(1) : 0.6
    homomorphism
    X(x) --> ;F(x)
    endlsystem

Read: ``/* … */`` and ``//`` comments; ``#define NAME value`` (a constant); ``Lsystem:``
(the name); ``derivation length:``; ``seed:``; ``Axiom:``; ``ignore:`` and ``consider:``;
productions ``[lc <] pred [> rc] [: condition] --> successor [: probability]`` (a condition
``*`` means none, a successor ``*`` is the empty word; probabilities are weights);
``decomposition`` (the productions after it are decomposition rules, applied after every
step until none applies); ``homomorphism`` (the productions after it are drawn, not
derived: without a ``maximum depth:`` they are seed 001's render rules, ``->>``, one pass;
with one they are interpretation rules, applied again to what they make);
``maximum depth:`` (in those two sections: the most passes, cpfg's default 1; rules that
still apply after them are an error); the view file's ``tropism direction:`` (normalised,
as cpfg does), ``initial elasticity:`` and ``elasticity increment:`` (ABOP §2.3 tropism);
``endlsystem`` (the rest of the file is ignored).  Inside expressions ``^`` is cpfg's power
(sylva's ``**``).  The turtle is ABOP's (``turtle = abop``), with cpfg's ``@`` functions
(``@O @v @M @R``, and ``@Ts(1, e)`` / ``@Ti`` / ``@Td`` whose first parameter is the
tropism's index: sylva has one, 1).  Not supported, with an error that says so:
``#include``.

The reader turns each line into one line of sylva's ``.lsys`` language and parses that, so
errors name the file's lines and columns (a column right of a ``^`` that became ``**`` may
be off by one per power).

Examples
--------
>>> p = parse("Lsystem: tree\\nderivation length: 2\\nAxiom: A\\nA --> F[+A]A : 0.5\\n"
...           "A --> F[-A]A : 0.5\\nendlsystem\\n")
>>> p.dialect, p.name, p.steps, p.turtle, len(p.rules)
('cpfg', 'tree', 2, 'abop', 2)
"""

from __future__ import annotations

import math
import re

from ...errors import LSystemSyntaxError, SylvaError
from ..ast import Program, Span
from ..expr import evaluate_constant
from . import lsysvis

__all__ = ["parse"]

_KEY = re.compile(r"\s*(lsystem|derivation\s+length|seed|axiom|ignore|consider|maximum\s+depth"
                  r"|tropism\s+direction|initial\s+elasticity|elasticity\s+increment)"
                  r"\s*:(.*)\Z", re.IGNORECASE)  # fmt: skip
_VIEW = {"tropism direction": "tropism", "initial elasticity": "elasticity",
         "elasticity increment": "elasticity_step"}  # fmt: skip
_DEFINE = re.compile(r"\s*#\s*define\s+([A-Za-z_]\w*)\s+(.+?)\s*\Z")
_SECTION = re.compile(r"\s*(homomorphism|decomposition|endlsystem)\b(.*)\Z", re.IGNORECASE)


def _strip_comments(text: str) -> str:
    """``/* … */`` and ``//`` comments blanked out, line breaks kept (so are columns)."""
    out = []
    i, n = 0, len(text)
    while i < n:
        if text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        elif text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            out.append(" " * (j - i))
            i = j
        else:
            out.append(text[i])
            i += 1
    return "".join(out)


def _power(expr: str) -> str:
    """cpfg's ``^`` (power) as ``**``."""
    return expr.replace("^", "**")


def _in_parens_power(word: str) -> str:
    """``^`` inside parentheses is a power; outside it is the pitch-up module."""
    out, depth = [], 0
    for ch in word:
        depth += (ch == "(") - (ch == ")")
        out.append("**" if ch == "^" and depth > 0 else ch)
    return "".join(out)


def _split_probability(rhs: str) -> tuple[str, str | None]:
    """The successor and the probability after its last ``:`` outside parentheses."""
    depth = 0
    for k in range(len(rhs) - 1, -1, -1):
        ch = rhs[k]
        depth += (ch == ")") - (ch == "(")
        if ch == ":" and depth == 0:
            return rhs[:k], rhs[k + 1 :].strip()
    return rhs, None


def _production(line: str, render: bool, where) -> tuple[str, list[tuple[int, int]]]:
    """The ``.lsys`` rule of a production line, and where its parts came from: pairs of
    (column in the rule, column in the line), both 0-based, one per part."""
    at = line.index("-->")
    lhs, rhs = line[:at], line[at + 3 :]
    cond_at = lhs.find(":")
    if cond_at >= 0:
        cond = lhs[cond_at + 1 :].strip()
        lhs = lhs[:cond_at] + (f": {_power(cond)}" if cond and cond != "*" else "")
    succ, prob = _split_probability(rhs)
    if render and prob is not None:
        raise where("a homomorphism production takes no probability", line.rindex(":") + 1)
    head = lhs.rstrip()
    arrow = "->>" if render else (f"->({_power(prob)})" if prob else "->")
    parts = [(0, 0)]
    if prob:
        parts.append((len(head) + 4, line.rindex(prob)))
    succ_at = at + 3 + len(succ) - len(succ.lstrip())
    parts.append((len(head) + len(arrow) + 2, succ_at))
    succ = "" if succ.strip() == "*" else succ  # cpfg's '*' is the empty word
    return f"{head} {arrow} {_in_parens_power(succ.strip())}", sorted(parts)


def _relocate(err: LSystemSyntaxError, lines: list[str], parts: dict) -> LSystemSyntaxError:
    """``err``, raised on a translated line, pointed at the cpfg line it came from."""
    if err.line is None or not 1 <= err.line <= len(lines):
        return err
    column = err.column
    if column is not None and err.line in parts:
        here, there = max((p for p in parts[err.line] if p[0] <= column - 1), default=(0, 0))
        column = column - here + there
    return type(err)(err.message, filename=err.filename, line=err.line, column=column,
                     source_line=lines[err.line - 1].rstrip())  # fmt: skip


def parse(text: str, filename: str | None = None) -> Program:
    """Read a cpfg L-system (see the module notes); errors name the file, line and column."""
    original = text.removeprefix("\ufeff").split("\n")
    lines = _strip_comments(text.removeprefix("\ufeff")).split("\n")
    out: list[str] = []
    parts: dict[int, list[tuple[int, int]]] = {}
    name: str | None = None
    render = False
    ended = False
    trop_at = None
    section = "production"
    depths: dict[str, tuple[str, LSystemSyntaxError]] = {}
    recursive = _homomorphism_has_depth(lines)
    steps_col = 1
    for number, raw in enumerate(lines, start=1):

        def where(message: str, column: int = 1, _n=number, _raw=raw) -> LSystemSyntaxError:
            return LSystemSyntaxError(message, filename=filename, line=_n, column=column,
                                      source_line=_raw)  # fmt: skip

        line = raw.rstrip()
        if ended or not line.strip():
            out.append("")
            continue
        if m := _DEFINE.match(line):
            out.append(f"{m.group(1)} = {_power(m.group(2))}")
            continue
        if line.lstrip().startswith("#"):
            word = line.split()[0]
            raise where(f"{word} is not supported; expected #define NAME value",
                        line.index("#") + 1)  # fmt: skip
        if m := _SECTION.match(line):
            key = m.group(1).lower()
            section = key
            if key == "decomposition":
                render = False
                out.append("decomposition:")
            elif key == "homomorphism":
                render = not recursive  # no maximum depth: seed 001's render rules
                out.append("production:" if render else "interpretation:")
            else:
                ended = True
                out.append("")
            continue
        if m := _KEY.match(line):
            key = " ".join(m.group(1).lower().split())
            value = m.group(2).strip()
            if key == "lsystem":
                name = value or None
                out.append("")
            elif key == "derivation length":
                out.append(f"steps = {value}")
                at = m.start(2) + len(m.group(2)) - len(m.group(2).lstrip())
                parts[number] = [(0, 0), (8, at)]  # "steps = " is 8 characters
                steps_col = at + 1
            elif key == "maximum depth":
                if section not in _DEPTH_OF:
                    raise where("'maximum depth:' belongs in a decomposition or homomorphism "
                                "section; expected it after 'decomposition' or "
                                "'homomorphism'", 1 + len(line) - len(line.lstrip()))  # fmt: skip
                depths[_DEPTH_OF[section]] = (value, where("", line.index(":") + 2))
                out.append("")
            elif key in _VIEW:
                out.append(f"{_VIEW[key]} = {_power(value)}")
                if key == "tropism direction":
                    trop_at = where("the tropism direction is the zero vector; expected a "
                                    "direction such as 0,-1,0", line.index(":") + 2)  # fmt: skip
            else:
                out.append(f"{key} = {_in_parens_power(value)}")
            continue
        if "-->" in line:
            rule, parts[number] = _production(line, render, where)
            out.append(rule)
            continue
        raise where(
            "expected a production 'pred --> successor', a 'keyword: value' line, "
            "#define, homomorphism or endlsystem",
            len(line) - len(line.lstrip()) + 1,
        )
    try:
        program = lsysvis.parse("\n".join(out), filename)
    except LSystemSyntaxError as err:  # semantic errors too: the subclass is kept
        raise _relocate(err, original, parts) from None
    settings = dict(program.settings)
    settings.setdefault("turtle", "abop")
    if "tropism" in settings:  # cpfg normalises the direction (interpret.c)
        t = settings["tropism"]
        norm = sum(c * c for c in t) ** 0.5  # type: ignore[union-attr]
        if norm == 0.0:
            raise trop_at
        settings["tropism"] = tuple(c / norm for c in t)  # type: ignore[union-attr]
    fields = {}
    for field, (text, at) in depths.items():
        try:
            v = evaluate_constant(lsysvis.parse_expr(_power(text)), program.constants)
        except (SylvaError, ArithmeticError, ValueError, TypeError):
            v = float("nan")
        if not (math.isfinite(v) and v == int(v) and v >= 1):
            raise LSystemSyntaxError(f"maximum depth {text!r}: expected a whole number >= 1",
                                     filename=at.filename, line=at.line, column=at.column,
                                     source_line=at.source_line)  # fmt: skip
        fields[field] = int(v)
    at = program.steps_at
    if at is not None:
        at = Span(at.line, steps_col, at.filename)
    return program.replace(settings=settings, dialect="cpfg", name=name or program.name,
                           steps_at=at, **fields)  # fmt: skip


_DEPTH_OF = {"decomposition": "decomposition_depth", "homomorphism": "interpretation_depth"}


def _homomorphism_has_depth(lines: list[str]) -> bool:
    """Whether the homomorphism section sets a ``maximum depth:`` (cpfg's recursion)."""
    inside = False
    for line in lines:
        if m := _SECTION.match(line):
            inside = m.group(1).lower() == "homomorphism"
        elif inside and (k := _KEY.match(line)) and "depth" in k.group(1).lower():
            return True
    return False
