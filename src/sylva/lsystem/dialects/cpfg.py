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

Read: the C preprocessor's directives and comments that cpfg files use (:mod:`._cpp`:
``#define`` with parameters, ``#include``, ``#ifdef`` / ``#if`` …; a ``#`` that is not the
first character of a line is the module ``#``, cpfg's width increment); ``Lsystem:``
(the name); ``derivation length:``; ``seed:``; ``Axiom:``; ``ignore:`` and ``consider:``;
productions ``[lc <] pred [> rc] [: condition] --> successor [: probability]`` (a condition
``*`` means none, a successor ``*`` is the empty word; probabilities are weights);
``decomposition`` (the productions after it are decomposition rules, applied after every
step until none applies); ``homomorphism`` (the productions after it are drawn, not
derived: without a ``maximum depth:`` they are seed 001's render rules, ``->>``, one pass;
with one they are interpretation rules, applied again to what they make);
``maximum depth:`` (in those two sections: the most passes, cpfg's default 1; rules that
still apply after them are an error; the axiom is not decomposed before the first step,
as in cpfg); the view file's ``tropism direction:`` (normalised, as cpfg does), ``initial
elasticity:`` and ``elasticity increment:`` (cpfg's old tropism, stepped by ``_``);
``endlsystem`` (the rest of the file is ignored); the query modules ``?P(x,y,z)``
``?H`` ``?U`` ``?L``, which the turtle sets between steps to its position, heading, up and
left vector (:mod:`sylva.lsystem.environment`).  Inside expressions ``^`` is cpfg's power
(sylva's ``**``).  The turtle is ABOP's (``turtle = abop``), with cpfg's ``@`` functions
(``@O @v @M @R``, ``@Gs @Gc @Ge @Gt``, and ``@Ts(k, e)`` / ``@Ti`` / ``@Td`` whose first
parameter is the index of a view file's ``tropism:`` or ``torque:`` line).
A production may run over several lines: a line that
is not a keyword, a section or a production continues the successor above it, and so does
any line after one that ends with ``\\``.  Statement blocks (:mod:`._cpfg_statements`):
``Define: { array a[10]; }`` and ``Start: { … }`` run when the file is read (``Start:`` runs
before the first step), and the globals they leave are the program's constants, which
conditions and successors read; ``StartEach: { … }`` and ``EndEach: { … }`` run before and
after every derivation step (:attr:`Program.statements`: the engine compiles the rules again
over the new globals each step, on its general road; a global first set in them starts at
0; homomorphism rules see the values ``Start:`` left); ``End: { … }`` is read but not run (it
cannot change the word).  Several ``Lsystem: N … endlsystem`` blocks are cpfg's
sub-L-systems (:mod:`._cpfg_sub`): the first is the main one, the productions,
decomposition and homomorphism of L-system N rewrite only the modules between a call
``?(N, s)`` and its ``$``.  A context ``*`` is none (``* < A``).  A file
without ``seed:`` is deterministic, as in cpfg: the first applicable production in the
file's order rewrites a module (the setting ``first_match``), probabilities are ignored.
A module matches a predecessor or context module only with as many parameters (ABOP p. 41,
cpfg's ``PredDiff``; the setting ``exact_arity``, made where it changes a derivation).
``group`` is an error that names it (cpfg has no production groups; they are lpfg's).

The reader turns each line into one line of sylva's ``.lsys`` language and parses that, so
errors name the file's (or the included file's) lines and columns (a column right of a
``^`` that became ``**`` may be off by one per power).

Examples
--------
>>> p = parse("Lsystem: tree\\nderivation length: 2\\nseed: 1\\nAxiom: A\\nA --> F[+A]A : 0.5\\n"
...           "A --> F[-A]A : 0.5\\nendlsystem\\n")
>>> p.dialect, p.name, p.steps, p.turtle, len(p.rules)
('cpfg', 'tree', 2, 'abop', 2)
"""

from __future__ import annotations

import copy
import math
import re
import warnings
from dataclasses import replace
from pathlib import Path

from ...errors import LSystemSyntaxError, SylvaError, SylvaWarning
from .._arity import differs
from ..ast import Num, Program, Span
from ..expr import evaluate_constant
from . import (
    _cpfg_blocks,
    _cpfg_env,
    _cpfg_functions,
    _cpfg_production,
    _cpfg_statements,
    _cpfg_sub,
    _cpfg_view,
    _cpp,
    lsysvis,
)

__all__ = ["parse"]

_KEY = re.compile(r"\s*(lsystem|derivation\s+length|seed|axiom|ignore|consider|maximum\s+depth"
                  r"|tropism\s+direction|initial\s+elasticity|elasticity\s+increment)"
                  r"\s*:(.*)\Z", re.IGNORECASE)  # fmt: skip
_VIEW = {"tropism direction": "tropism", "initial elasticity": "elasticity",
         "elasticity increment": "elasticity_step"}  # fmt: skip
#: cpfg constructs that sylva does not read, named in the error (with the reason).
_BLOCK = re.compile(r"\s*(define|start|starteach|endeach|end)\s*:\s*(?=\{)", re.IGNORECASE)
_UNSUPPORTED = re.compile(r"\s*(ring\s+l-?system|start\s*:|starteach\s*:|endeach\s*:"
                          r"|end\s*:|define\s*:|group\b|sub-?l-?system)",
                          re.IGNORECASE)  # fmt: skip
_UNSUPPORTED_WHY: dict[str, str] = {
    "group": "cpfg has no production groups: neither its manual nor its parser knows "
             "'group'; lpfg's 'group N:' sections are read by neither cpfg nor sylva's cpfg "
             "reader. Expected sub-L-systems ('Lsystem: 2' blocks called by ?(2, s) … $), "
             "or the .lsys language's 'group N:' sections with 'group = …'",
}
_RING = re.compile(r"\s*ring\s+l-?system\s*\Z", re.IGNORECASE)
#: A line that begins a production whose arrow comes later: ``M(t) : 1 {x=0.5*R^t;}``.
_HEAD = re.compile(r"[^{}]*:\s*\{|[^{}]*:[^{}]*\{[^}]*(?<![=!<>])=(?!=)|.*:\s*\Z"
                   r"|[^:(]*(?:\([^)]*\))?[^:(]*[<>][^:]*:(?!\s*[-+]?[\d.]+\s*\Z)")
_LABEL = re.compile(r'@L\(\s*"(?:[^"\\]|\\.)*"\s*(,|\))')


def _label(m) -> str:
    """``@L("fmt", x)`` as ``@L(x)``, ``@L("text")`` as ``@L``: a label draws nothing."""
    return "@L(" if m.group(1) == "," else "@L"


_OTHER_ARROW = re.compile(r"-+>|<-+|=>|-o>")  # not cpfg's arrow: an error, not a head


def _other_arrow(text: str) -> bool:
    """Whether ``text`` holds an arrow that is not cpfg's (``->``, ``<-``, ``=>``) outside
    parentheses and before a condition's ``:`` (``x<-1`` in a condition is no arrow)."""
    colon = _outside_parens(text, ":")
    out, depth = [], 0
    for ch in text if colon < 0 else text[:colon]:
        depth += (ch == "(") - (ch == ")")
        out.append(ch if depth <= 0 and ch != ")" else " ")
    return bool(_OTHER_ARROW.search("".join(out)))


_AXIOM = re.compile(r"\s*axiom\s*:", re.IGNORECASE)
_SECTION = re.compile(r"\s*(homomorphism|decomposition|endlsystem)\b(.*)\Z", re.IGNORECASE)


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


def _production(line: str, render: bool, where):
    """The ``.lsys`` rule of a production line, where its parts came from (pairs of (column
    in the rule, column in the line), both 0-based, one per part), and its statement blocks:
    None, or ``(pre, pre column, post, post column)`` with the hoisted calls in ``calls``
    (:mod:`._cpfg_production`)."""
    at = line.index("-->")
    lhs, rhs = line[:at], line[at + 3 :]
    cond_at = _outside_parens(lhs, ":")
    blocks = None
    rename: dict = {}
    calls_pre: list = []
    calls_post: list = []
    if cond_at >= 0:
        cond = lhs[cond_at + 1 :]
        try:
            pre, pre_at, cond, post, post_at = _cpfg_production.split_blocks(cond)
        except ValueError as e:
            raise where("a statement block '{' of this production does not close, or text "
                        "follows its post-condition block; expected pred : {pre} condition "
                        "{post} --> successor", cond_at + 2 + e.args[0]) from None  # fmt: skip
        cond = cond.strip()
        rename = {n: f"_b_{n}" for n in _ASSIGNED.findall(f"{pre or ''};{post or ''}")
                  if n in lsysvis.SPECIAL_VARIABLES}  # fmt: skip
        if pre is not None or post is not None:
            blocks = (pre, cond_at + 1 + pre_at, post, cond_at + 1 + post_at)
        if cond and cond != "*":
            cond = _cpfg_production.hoist(cond, calls_pre, rename, successor=False)
        lhs = _quote_equals(lhs[:cond_at]) + (f": {_power(cond)}" if cond and cond != "*"
                                              else "")  # fmt: skip
    else:
        lhs = _quote_equals(lhs)
    rhs = _LABEL.sub(_label, rhs)  # @L("%.f", c): the label's text is not kept
    succ, prob = _split_probability(rhs)
    if render and prob is not None:
        raise where("a homomorphism production takes no probability", line.rindex(":") + 1)
    if prob is not None:
        prob = _cpfg_production.hoist(prob, calls_post, rename, successor=False)
    succ = _cpfg_production.hoist(succ, calls_post, rename, successor=True)
    head = lhs.rstrip()
    arrow = "->>" if render else (f"->({_power(prob)})" if prob else "->")
    parts = [(0, 0)]
    if prob and prob in line:
        parts.append((len(head) + 4, line.rindex(prob)))
    succ_at = at + 3 + len(succ) - len(succ.lstrip())
    parts.append((len(head) + len(arrow) + 2, succ_at))
    succ = "" if succ.strip() == "*" else succ  # cpfg's '*' is the empty word
    if calls_pre or calls_post:
        blocks = blocks or (None, 0, None, 0)
    if blocks is not None:
        blocks = (*blocks, calls_pre, calls_post, rename)
    succ = _quote_equals(succ)
    return f"{head} {arrow} {_in_parens_power(succ.strip())}", sorted(parts), blocks


def _quote_equals(word: str) -> str:
    """cpfg's module ``=`` outside parentheses as ``.lsys``'s ``"="``."""
    if "=" not in word:
        return word
    out, depth = [], 0
    for ch in word:
        depth += (ch == "(") - (ch == ")")
        out.append('"="' if ch == "=" and depth <= 0 else ch)
    return "".join(out)


_ASSIGNED = re.compile(r"\b([A-Za-z_][A-Za-z0-9_]*)\s*(?:[-+*/]?=(?!=)|\+\+|--)")


_PROBABILITY = re.compile(r"\s*(?:[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?|[A-Za-z_]\w*)\s*\Z")


def _condition_head(text: str) -> bool:
    """Whether ``text`` is a production's head whose arrow comes on a later line: it has a
    ``:`` outside parentheses followed by a condition (``@M(x,y,z) : (x<0)``), not by a
    successor's probability (``… : 0.4``, ``… : P``)."""
    k = _outside_parens(text, ":")
    return k >= 0 and not _PROBABILITY.match(text[k + 1 :])


def _outside_parens(text: str, char: str) -> int:
    """The first index of ``char`` outside parentheses and braces (or -1)."""
    depth = 0
    for k, ch in enumerate(text):
        depth += (ch in "({") - (ch in ")}")
        if ch == char and depth == 0:
            return k
    return -1


def _quote_hash(line: _cpp.Line) -> _cpp.Line:
    """cpfg's ``#`` module (width increment) outside parentheses as ``.lsys``'s ``"#"``."""
    if "#" not in line.text:
        return line
    text, origin, depth = [], [], 0
    for ch, at in zip(line.text, line.origin, strict=False):
        depth += (ch == "(") - (ch == ")")
        piece = '"#"' if ch == "#" and depth <= 0 else ch
        text.append(piece)
        origin.extend([at] * len(piece))
    return _cpp.Line("".join(text), origin + line.origin[-1:], line.define)


def _logical_lines(pre: _cpp.Result) -> list[_cpp.Line]:
    """The preprocessed lines with multi-line productions and statement blocks joined: a
    line that is not empty, a keyword, a section or a production continues the production
    right above it (cpfg reads a successor over several lines), and so does any line after
    one that ends with ``\\``; a block ``Start: {`` runs to its closing brace.
    The joined production takes the first line's place; the others become empty."""
    out: list[_cpp.Line] = []
    open_at: int | None = None  # index in out of the production that may continue
    forced = False
    depth = block_at = 0  # of braces in an open statement block; where it began
    head_at: int | None = None  # a production head whose arrow is on a later line
    axiom_open = False  # the line that may continue is the axiom's
    for line in pre.lines:
        text = line.text
        if depth > 0:  # a statement block continues
            out[block_at] = out[block_at] + _cpp.Line(" ", [line.origin[0]] * 2) + line
            out.append(_cpp.Line("", line.origin[-1:]))
            depth += text.count("{") - text.count("}")
            continue
        if _BLOCK.match(text):
            block_at, depth, open_at = len(out), text.count("{") - text.count("}"), None
            out.append(line)
            continue
        plain = bool(text.strip()) and line.define is None
        if head_at is not None and plain:  # a production's head before its arrow
            out[head_at] = out[head_at] + _cpp.Line(" ", [line.origin[0]] * 2) + line
            out.append(_cpp.Line("", line.origin[-1:]))
            if "-->" in text:
                open_at, head_at = head_at, None
                stripped = out[open_at].text.rstrip()
                forced = stripped.endswith("\\")
                if forced:
                    out[open_at] = out[open_at].slice(0, len(stripped) - 1)
            continue
        continues = open_at is not None and plain and (
            forced or ("-->" not in text and not _KEY.match(text) and not _SECTION.match(text)
                       and not _UNSUPPORTED.match(text) and not _HEAD.match(text)
                       and not _other_arrow(text) and not _condition_head(text)
                       and not (axiom_open and _outside_parens(text, ":") >= 0)))  # fmt: skip
        if continues:
            body = line.slice(0, len(text.rstrip()))
            forced = body.text.endswith("\\")
            if forced:
                body = body.slice(0, len(body.text) - 1)
            out[open_at] = out[open_at] + _cpp.Line(" ", [body.origin[0]] * 2) + body
            out.append(_cpp.Line("", line.origin[-1:]))
            continue
        forced = False
        if plain and ("-->" in text or _AXIOM.match(text)):  # both may run on
            open_at = len(out)
            axiom_open = "-->" not in text
            stripped = text.rstrip()
            if stripped.endswith("\\"):
                forced = True
                line = line.slice(0, len(stripped) - 1)
        else:  # anything else, an empty line too, ends the production
            open_at = None
            if (plain and not _KEY.match(text) and not _SECTION.match(text)
                    and not _UNSUPPORTED.match(text) and not _other_arrow(text)
                    and any(c in text for c in ":<>")):  # fmt: skip
                head_at = len(out)  # pred : {…} condition … on lines before its arrow
        out.append(line)
    return out


def _relocate(err: LSystemSyntaxError, lines: list[_cpp.Line], parts: dict,
              pre: _cpp.Result) -> LSystemSyntaxError:  # fmt: skip
    """``err``, raised on a translated line, pointed at the cpfg line it came from."""
    if err.line is None or not 1 <= err.line <= len(lines):
        return err
    column = err.column
    if column is not None and err.line in parts:
        here, there = max((p for p in parts[err.line] if p[0] <= column - 1), default=(0, 0))
        column = column - here + there
    file, number, col = lines[err.line - 1].at(column or 1)
    return type(err)(err.message, filename=file, line=number,
                     column=col if column is not None else None,
                     source_line=pre.sources.get((file, number)))  # fmt: skip


def _remap(span: Span | None, lines: list[_cpp.Line]) -> Span | None:
    """A span of the translation as the place in the user's files."""
    if span is None or not 1 <= span.line <= len(lines):
        return span
    file, number, col = lines[span.line - 1].at(span.column)
    return Span(number, col, file)


def parse(text: str, filename: str | None = None, *, view=None, colormap=None,
          materials=None, environment=None) -> Program:
    """Read a cpfg L-system (see the module notes); errors name the file, line and column.

    ``view`` is the view file (:mod:`._cpfg_view`): a path, ``None`` for the ``.v`` beside
    ``filename`` (same stem) if there is one, or ``False`` for none.  Its settings apply
    where the L-system does not set its own; lines sylva cannot honour are warned about
    (:class:`~sylva.errors.SylvaWarning`).

    ``colormap`` and ``materials`` are the colour map (``cpfg -m file.map``) and material
    file (``cpfg -M file.mat``) of cpfg's command line (paths): they replace the view
    file's ``color map:`` / ``material:`` (settings ``colormap`` and ``materials``).

    ``environment`` is the environment file (``cpfg -e plant.e``) of an open L-system: its
    program is answered by the built-in environment :mod:`._cpfg_env` maps it to (the
    program's ``environment`` setting), or it is an
    :class:`~._cpfg_env.EnvironmentProgramError` naming the program.
    """
    env_spec = None if environment is None else _cpfg_env.environment_spec(environment)
    pre = _cpp.preprocess(text, filename)
    lines = [_quote_hash(line) for line in _logical_lines(pre)]
    out: list[str] = []
    parts: dict[int, list[tuple[int, int]]] = {}
    name: str | None = None
    render = False
    ended = False
    books = _cpfg_sub.Books()  # the file's L-systems: the main one, then sub-L-systems
    trop_at = None
    ring = False
    seen_rule = False
    section = "production"
    depths: dict[str, tuple[str, LSystemSyntaxError]] = {}
    recursive = _homomorphism_has_depth([ln.text for ln in lines])
    steps_col = 1
    src: list[_cpp.Line] = []  # the logical line of each line of ``out``
    each: dict[str, tuple] = {}  # StartEach / EndEach: (statements, where)
    each_text: list[str] = []
    block_src: dict[int, tuple] = {}  # line of out -> (blocks, logical line, where)
    top: list[tuple[str, _cpp.Line]] = []  # assignments that go before everything
    seed = _seed_of(lines)
    vpath = None if view is False else (_cpfg_view.view_path(filename) if view is None
                                        else Path(view))  # fmt: skip
    functions = _cpfg_functions.load_functions(vpath)
    globals_ = None
    for logical in lines:

        def emit(translated: str, _l=logical) -> None:
            out.append(translated)
            src.append(_l)

        def where(message: str, column: int = 1, _l=logical) -> LSystemSyntaxError:
            return pre.error(message, _l.at(column))

        line = logical.text.rstrip()
        if ended and (m := _KEY.match(line)) and m.group(1).lower() == "lsystem":
            books.start(m.group(2).strip(), where)  # a sub-L-system (cpfg's manual §7.2)
            ended, render, section = False, False, "production"
            emit("production:")
            continue
        if (ended and logical.define is None) or not line.strip():
            emit("")
            continue
        if logical.define is not None and ended and logical.define not in pre.values:
            emit("")  # a macro between L-systems: cpp has expanded its uses
            continue
        if logical.define is not None and seen_rule and logical.define in pre.values:
            # cpp's #define may follow the rules; its value is known: set it before them
            top.append((f"{logical.define} = {pre.values[logical.define]!r}", logical))
            emit("")
            continue
        if logical.define is not None:
            emit(f"{logical.define} = {_power(line.strip())}")
            lead = len(line) - len(line.lstrip())
            parts[len(out)] = [(0, 0), (len(logical.define) + 3, lead)]
            continue
        if m := _BLOCK.match(line):
            kind = " ".join(m.group(1).lower().split())
            if books.current and kind != "define":
                raise where(f"cpfg's '{m.group(1)}:' block in sub-L-system {books.current} is "
                            "not supported by sylva's cpfg reader (cpfg runs it per call of "
                            "the sub-L-system); expected it in the main L-system",
                            m.start(1) + 1)  # fmt: skip
            if kind in ("starteach", "endeach"):  # noqa: SIM102
                tree = _cpfg_statements.parse_block(
                    logical.text[m.end() :], lambda msg, o, _m=m: where(msg, _m.end() + o + 1))
                file, at_line, _ = logical.at(1)
                each[kind] = (tree, f"{file or '<string>'}:{at_line} ({m.group(1)}: block)")
                each_text.append(logical.text)
                emit("")
                continue
            if globals_ is None:
                globals_ = _new_globals(seed, functions)
                globals_.values.update(pre.values)  # the #define constants, read only
            for name, value in _block(logical, m, kind, globals_, where, pre):
                top.append((f"{name} = {value!r}", logical))  # Start: runs before all
            emit("")
            continue
        if _RING.match(line):
            ring = True
            emit("")
            continue
        if m := _UNSUPPORTED.match(line):
            construct = " ".join(m.group(1).split())
            if construct.lower().startswith("ring"):
                raise where("expected 'ring lsystem' alone on its line (cpfg's ring "
                            "L-system, whose last module is followed by its first)",
                            m.start(1) + 1)  # fmt: skip
            raise where(f"cpfg's {construct!r} is not supported by sylva's cpfg reader "
                        f"({_UNSUPPORTED_WHY.get(construct.lower(), 'not implemented yet')})",
                        m.start(1) + 1)  # fmt: skip
        if m := _SECTION.match(line):
            key = m.group(1).lower()
            section = key
            if key == "decomposition":
                render = False
                emit("decomposition:")
            elif key == "homomorphism":
                render = not recursive  # no maximum depth: seed 001's render rules
                emit("production:" if render else "interpretation:")
            else:
                ended = True
                emit("")
            continue
        if (m := _KEY.match(line)) and "-->" not in line:  # AXIOM : c --> is a rule
            key = " ".join(m.group(1).lower().split())
            value = m.group(2).strip()
            if books.current and key in ("axiom", "derivation length", "seed"):
                emit("")  # cpfg: the main L-system's; a sub-L-system's serve it run alone
                continue
            if key == "axiom" and value:
                books.calls += [(t, lambda msg, _c=c, _w=where: _w(msg, _c + 1))
                                for t, c in _cpfg_sub.calls_in(m.group(2), m.start(2))]
                value = _axiom_calls(value, globals_ or _new_globals(seed, functions), pre,
                                     where, m.start(2) + 1)  # fmt: skip
            if key == "lsystem":
                name = value or None
                books.main_id = _cpfg_sub.label_number(value)
                emit("")
            elif key == "derivation length":
                emit(f"steps = {value}")
                at = m.start(2) + len(m.group(2)) - len(m.group(2).lstrip())
                parts[len(out)] = [(0, 0), (8, at)]  # "steps = " is 8 characters
                steps_col = at + 1
            elif key == "maximum depth":
                if section not in _DEPTH_OF:
                    raise where("'maximum depth:' belongs in a decomposition or homomorphism "
                                "section; expected it after 'decomposition' or "
                                "'homomorphism'", 1 + len(line) - len(line.lstrip()))  # fmt: skip
                had = depths.get(_DEPTH_OF[section])
                if had is not None and books.current and had[0] != value:
                    raise where(f"this {section}'s maximum depth {value!r} differs from the "
                                f"main L-system's {had[0]!r}; sylva's cpfg reader keeps one "
                                "per section for the file (expected the same)",
                                line.index(":") + 2)  # fmt: skip
                depths[_DEPTH_OF[section]] = (value, where("", line.index(":") + 2))
                emit("")
            elif key in _VIEW:
                emit(f"{_VIEW[key]} = {_power(value)}")
                if key == "tropism direction":
                    trop_at = where("the tropism direction is the zero vector; expected a "
                                    "direction such as 0,-1,0", line.index(":") + 2)  # fmt: skip
            else:
                if key in ("consider", "ignore"):  # cpfg lets brackets be listed: they
                    # are always considered (the word's tree), as cpfg does
                    value = value.replace("[", " ").replace("]", " ")
                    books.context[books.current] = (
                        key, frozenset(c for c in value if not c.isspace()),
                        where("", m.start(1) + 1))  # fmt: skip
                    if books.current:  # a sub-L-system's: checked against the main's
                        emit("")
                        continue
                emit(f"{key} = {_in_parens_power(value)}")
            continue
        if "-->" in line:
            seen_rule = True
            succ_at = line.index("-->") + 3
            books.calls += [(t, lambda msg, _c=c, _w=where: _w(msg, _c + 1))
                            for t, c in _cpfg_sub.calls_in(line[succ_at:], succ_at)]
            for piece in _multi_predecessor(_null_contexts(line)):
                if books.current:
                    books.rule_lsystem[len(out) + 1] = books.current
                rule, parts[len(out) + 1], blocks = _production(piece, render, where)
                if blocks is not None:
                    block_src[len(out) + 1] = (blocks, logical, where)
                emit(rule)
            continue
        raise where(
            "expected a production 'pred --> successor', a 'keyword: value' line, "
            "#define, homomorphism or endlsystem",
            len(line) - len(line.lstrip()) + 1,
        )
    runtime = None
    if block_src:
        if globals_ is None:
            globals_ = _new_globals(seed, functions)
            globals_.values.update(pre.values)
        runtime = _cpfg_blocks.Runtime(globals_)
        made = _make_blocks(block_src, runtime, pre, each, top, lines)
    if block_src and not each:  # the blocks' globals start afresh with each derivation
        each["blocks"] = (None, "")
    each_names = set().union(*(_cpfg_statements.assigned_names(t) for t, _ in
                                each.values() if t is not None)) if each else set()  # fmt: skip
    statements = None
    if each:
        globals_ = globals_ or _new_globals(seed, functions)
        if globals_ is not None and not globals_.values:
            globals_.values.update(pre.values)
        known = set(globals_.values)
        fresh = sorted(set().union(*(_cpfg_statements.assigned_names(t) for t, _ in
                                     each.values() if t is not None)) - known)  # fmt: skip
        for k in fresh:  # a global first set between steps starts at 0
            globals_.values[k] = 0.0
        top.extend((f"{k} = 0.0", lines[0]) for k in fresh)
        statements = _cpfg_statements.Schedule(globals_, each.get("starteach"),
                                               each.get("endeach"),
                                               "\n".join(each_text), runtime)  # fmt: skip
    if top:  # before every use
        out[:0] = [t for t, _ in top]
        src[:0] = [ln for _, ln in top]
        parts = {k + len(top): v for k, v in parts.items()}
    try:
        program = lsysvis.parse("\n".join(out), filename)
    except LSystemSyntaxError as err:  # semantic errors too: the subclass is kept
        raise _relocate(err, src, parts, pre) from None
    settings = dict(program.settings)
    settings.setdefault("turtle", "abop")
    if env_spec is not None:
        settings["environment"] = env_spec
    if "tropism" in settings:  # cpfg normalises the direction (interpret.c)
        t = settings["tropism"]
        norm = sum(c * c for c in t) ** 0.5  # type: ignore[union-attr]
        if norm == 0.0:
            raise trop_at
        settings["tropism"] = tuple(c / norm for c in t)  # type: ignore[union-attr]
    for key, value in _cpfg_view.load_view(view, filename).items():
        settings.setdefault(key, value)
    settings.setdefault("width_step", 0.0)  # cpfg's ! and # step by the view's increment
    # cpfg's command line (-m file.map, -M file.mat) names the colours: they win over the
    # view file's, as cpfg's options do
    if materials is not None:
        settings["materials"] = str(materials)
        settings.pop("colormap", None)
    elif colormap is not None:
        settings["colormap"] = str(colormap)
        settings.pop("materials", None)
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
        at = _remap(Span(at.line, steps_col, at.filename), src)
    raw_rules = books.check(program.rules, program.constants, len(top))
    if (contexts := books.context_sets(raw_rules)) is not None:
        settings["sublsystem_context"] = contexts  # each L-system its own ignore:
    if not _has_seed(lines) and _competing(raw_rules):
        # lsys_input.y: an L-system without seed: is deterministic; generate.c's FindProd
        # takes the first applicable production in the file's order (probabilities are
        # ignored, with cpfg's warning "Probability given for deterministic production")
        settings["first_match"] = 1.0
    if differs(program.axiom, raw_rules):
        # ABOP p. 41 and generate.c's PredDiff: a module matches a predecessor or context
        # module of as many parameters only (``A --> B`` leaves ``A(1)``); set only where
        # that changes a word, so the rest still convert to .lsys
        settings["exact_arity"] = 1.0
    rules = tuple(r if r.span is None else replace(r, span=_remap(r.span, src))
                  for r in raw_rules)  # fmt: skip
    if settings.get("first_match"):
        _warn_ignored_probability(rules, filename)
    if block_src:
        rules, written = _attach_blocks(raw_rules, rules, made,
                                        (set(globals_.values) - set(pre.values)) | each_names,
                                        len(top))  # fmt: skip
        if written:
            statements.written = written
    return program.replace(settings=settings, dialect="cpfg", name=name or program.name,
                           steps_at=at, rules=rules, statements=statements, ring=ring,
                           **fields)  # fmt: skip


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


def _has_seed(lines: list[_cpp.Line]) -> bool:
    """Whether an L-system of the file has a ``seed:`` line (cpfg's stochastic L-system)."""
    return any((m := _KEY.match(ln.text)) and m.group(1).lower() == "seed" for ln in lines)


def _warn_ignored_probability(rules, file: str | None) -> None:
    """cpfg's warning "Probability given for deterministic production", once, at the first
    production whose probability an L-system without ``seed:`` ignores."""
    for r in rules:
        if not (isinstance(r.weight, Num) and r.weight.value == 1.0):
            at = r.span
            where = (f"{at.filename or file or '<string>'}:{at.line}:{at.column}: "
                     if at is not None else f"{file or '<string>'}: ")  # fmt: skip
            warnings.warn(f"{where}probability given for a production of an L-system without "
                          "'seed:'; as in cpfg, the first applicable production in the file's "
                          "order rewrites the module and probabilities are ignored (add a "
                          "'seed:' line for a stochastic L-system)", SylvaWarning,
                          stacklevel=4)  # fmt: skip
            return


def _competing(rules) -> bool:
    """Whether two rules of one kind and L-system rewrite the same module (then cpfg's
    first applicable production and a draw among them may differ)."""
    seen = set()
    for r in rules:
        key = (r.lsystem, r.phase, r.render, r.group, r.predecessor.symbol)
        if key in seen:
            return True
        seen.add(key)
    return False


def _seed_of(lines: list[_cpp.Line]) -> int:
    """The ``seed:`` of the L-system (0 without one), for the statements' random numbers."""
    for line in lines:
        m = _KEY.match(line.text)
        if m and m.group(1).lower() == "seed":
            try:
                return int(float(m.group(2)))
            except ValueError:
                return 0
    return 0


def _block(logical: _cpp.Line, m, kind: str, g, where, pre) -> list[tuple[str, float]]:
    """Run a ``Define:`` or ``Start:`` block (``End:`` is only read: it runs after the last
    step, where it cannot change the word); the globals it leaves, as constants."""
    text = logical.text[m.end() :]
    start = m.end()

    def error(message: str, offset: int) -> LSystemSyntaxError:
        return where(message, start + offset + 1)

    tree = _cpfg_statements.parse_block(text, error)
    if kind == "end":
        return []
    file, number, _ = logical.at(1)
    _cpfg_statements.run(tree, g, f"{file or '<string>'}:{number} ({m.group(1)}: block)")
    if kind == "define":
        return []
    clash = sorted(set(g.values) & lsysvis.SPECIAL_VARIABLES)
    if clash:
        raise where(f"the global variable {clash[0]!r} is also a sylva setting; expected "
                    "another name", 1)  # fmt: skip
    return sorted((k, v) for k, v in g.values.items() if pre.values.get(k) != v)


def _make_blocks(block_src: dict, runtime, pre, each: dict, top: list, lines) -> dict:
    """The :class:`~._cpfg_blocks.Block` of each production with statement blocks, by its
    line in the translation; declares the variables they set as constants (0) so that the
    rule's condition and successor may name them."""
    made = {}
    declared = {t.split(" = ")[0] for t, _ in top}
    for out_line, (blocks, logical, where) in block_src.items():
        pre_t, pre_c, post_t, post_c, calls_pre, calls_post, rename = blocks

        def tree(text, calls, col, _w=where):
            if text is None and not calls:
                return None
            body = (text or "") + "".join(f" {v} = {c};" for v, c in calls)
            return _cpfg_statements.parse_block(
                body, lambda msg, o, _c=col: _w(msg, _c + min(o, len(text or "")) + 1))

        pre_tree = tree(pre_t, calls_pre, pre_c)
        post_tree = tree(post_t, calls_post, post_c)
        names = _cpfg_blocks.assigned(pre_tree) | _cpfg_blocks.assigned(post_tree)
        outputs = sorted(rename.get(n, n) for n in names)
        file, number, _ = logical.at(1)
        block = _cpfg_blocks.Block(pre_tree, post_tree, outputs, runtime,
                                   f"{file or '<string>'}:{number} (production block)",
                                   logical.text, rename, names)  # fmt: skip
        made[out_line] = (block, where, pre_c if pre_t is not None else post_c)
        for name in outputs:
            if name not in declared and name not in runtime.initial.values:
                top.append((f"{name} = 0.0", lines[0]))
                declared.add(name)
    return made


def _attach_blocks(raw_rules, rules, made: dict, globals_names: set, shift: int) -> tuple:
    """``rules`` with their blocks (a rule with blocks is conditional: ``1`` without one),
    and the globals the blocks assign (the engine then applies the productions one module
    at a time, in word order, as cpfg does, so each application sees the last one's)."""
    out = []
    written: set[str] = set()
    for raw, rule in zip(raw_rules, rules, strict=True):
        entry = made.get(raw.span.line - shift) if raw.span is not None else None
        if entry is None:
            out.append(rule)
            continue
        block, where, col = entry
        params = {n for p in (*rule.left, rule.predecessor, *rule.right) for n in p.params}
        clash = sorted((block.assigned - params) & globals_names)
        if clash:
            block.globals_written = frozenset(block.rename.get(n, n) for n in clash)
            written |= block.globals_written
        from ..ast import Num

        out.append(replace(rule, block=block,
                           condition=rule.condition if rule.condition is not None
                           else Num(1.0)))  # fmt: skip
    return tuple(out), frozenset(written)


def _new_globals(seed: int, functions: dict):
    g = _cpfg_statements.Globals(seed)
    g.functions = dict(functions)
    return g


def _axiom_calls(value: str, g, pre, where, column: int) -> str:
    """The axiom with each call of a function sylva's expressions lack (``func``, ``ran``
    …) replaced by its value, computed once when the file is read, as cpfg does."""
    calls: list = []
    text = _cpfg_production.hoist(value, calls, {}, successor=True)
    if not calls:
        return value
    g = copy.deepcopy(g)
    g.values.update({k: v for k, v in pre.values.items() if k not in g.values})
    for var, call in calls:
        tree = _cpfg_statements.parse_block(f"{var} = {call};",
                                            lambda msg, o: where(msg, column))  # fmt: skip
        _cpfg_statements.run(tree, g, "the axiom")
        text = re.sub(rf"\b{var}\b", repr(g.values[var]), text)
    return text


def _pred_modules(text: str) -> list[str]:
    """The modules of a predecessor string ``XF(x)`` (``?P(x)`` and ``"#"`` are one each)."""
    mods, k, n = [], 0, len(text)
    while k < n:
        ch = text[k]
        if ch.isspace():
            k += 1
            continue
        if ch == '"':
            end = text.find('"', k + 1)
            j = n if end < 0 else end + 1
        elif ch == "?" and k + 1 < n and text[k + 1].isalpha():
            j = k + 2
        else:
            j = k + 1
        while j < n and text[j] == " ":
            j += 1
        if j < n and text[j] == "(":
            depth = 0
            for q in range(j, n):
                depth += (text[q] == "(") - (text[q] == ")")
                if depth == 0:
                    j = q + 1
                    break
            else:
                j = n
        mods.append(text[k:j].strip())
        k = j
    return mods


def _null_contexts(line: str) -> str:
    """``line`` without a context that is cpfg's ``*`` (no context: ``* < A`` is ``A``,
    ``B > *`` is ``B``; ``lsys_input.y`` reads ``*`` there as the empty context).

    >>> _null_contexts("* < #(d) : d<200 --> #(d*2)"), _null_contexts("B > * : * --> C")
    ('    #(d) : d<200 --> #(d*2)', 'B     : * --> C')
    """
    at = line.index("-->")
    lhs = line[:at]
    c = _outside_parens(lhs, ":")
    head, rest = (lhs, line[at:]) if c < 0 else (lhs[:c], line[c:])
    lt = _outside_parens(head, "<")
    if lt >= 0 and head[:lt].strip() == "*":
        head = " " * (lt + 1) + head[lt + 1 :]  # spaces: the columns stay
    gt = _outside_parens(head, ">")
    if gt >= 0 and head[gt + 1 :].strip() == "*":
        head = head[:gt] + " " * (len(head) - gt)
    return head + rest


def _multi_predecessor(line: str) -> list[str]:
    """cpfg's strict predecessor of several modules, ``lc < A B > rc : c --> s``, as the
    productions sylva has (each module rewritten alone): ``lc < A > B rc : c --> s`` and
    ``lc A < B > rc : c --> *`` (the others are erased where the first is rewritten)."""
    at = line.index("-->")
    lhs, rhs = line[:at], line[at + 3 :]
    c = _outside_parens(lhs, ":")
    head, cond = (lhs, "") if c < 0 else (lhs[:c], lhs[c:])
    lt = _outside_parens(head, "<")
    left, rest = (head[:lt].strip(), head[lt + 1 :]) if lt >= 0 else ("", head)
    gt = _outside_parens(rest, ">")
    pred, right = (rest[:gt], rest[gt + 1 :].strip()) if gt >= 0 else (rest, "")
    mods = _pred_modules(pred)
    if len(mods) < 2 or "*" in mods:
        return [line]
    out = []
    succ, prob = _split_probability(rhs)
    for k, m in enumerate(mods):
        lc = " ".join([left, *mods[:k]]).strip()
        rc = " ".join([*mods[k + 1 :], right]).strip()
        h = (f"{lc} < " if lc else "") + m + (f" > {rc}" if rc else "")
        out.append(f"{h} {cond} -->{rhs}" if k == 0 else f"{h} {cond} --> *")
    return out
