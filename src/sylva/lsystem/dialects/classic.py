"""The input format of seed 000 ("classic"): ``keyword: value`` lines.

::

    ;number of iterations
    iteration: 7
    angle: 22.5
    reduction: 0.95     ; optional: thickness ratio of the next segment
    radius: 0.3         ; optional: initial trunk radius
    axiom: A
    rule: A -> [&FXA]///// [&FXA]//////// [&FXA]
    rule: F -> S ///// F

Comments start with ``;`` and run to the end of the line (they may hold any UTF-8 text);
blank lines are allowed; whitespace inside a word is ignored; every symbol is one
character and carries no parameters.  Several rules for one symbol choose uniformly among
themselves (equal weights; the engine makes the choice).

The keywords come in the order of the thesis's Table 3.2 (``iteration``, ``angle``,
``reduction``, ``radius``, then ``axiom`` and the rules; ``thickness`` of Table 3.1 goes with
``radius``) and a successor holds at least one symbol: a file out of order or with an empty
successor is an error naming the line.  Leniencies: keywords in any letter case, and
``iteration``, ``angle``, ``reduction`` and ``radius`` may be left out.  Each keyword but
``rule`` may appear once.  A symbol is any printable character but ``;`` (the comment) and
``"`` (which ``.lsys`` cannot write).

The program has ``steps = iteration`` and the settings ``turtle = "classic"``, ``rot =
angle`` and, when given, ``reduction``, ``radius`` and ``thickness``.

Examples
--------
>>> p = parse("iteration: 2\\nangle: 90\\naxiom: A\\nrule: A -> AB\\n")
>>> p.steps, p.settings["rot"], [m.symbol for m in p.rules[0].successor]
(2, 90.0, ['A', 'B'])
"""

from __future__ import annotations

import re
from pathlib import Path

from ...errors import LSystemSemanticError
from ..ast import MAX_STEPS, Module, Num, Pattern, Program, Rule, Span
from ._diagnostics import Where, char_symbols, join_words

__all__ = ["KEYWORDS", "format", "parse"]

#: The keywords of the format, in the order Table 3.2 writes them.
KEYWORDS: tuple[str, ...] = (
    "iteration",
    "angle",
    "reduction",
    "radius",
    "thickness",
    "axiom",
    "rule",
)
#: Each keyword's place in the order of Table 3.2 (thickness, of Table 3.1, beside radius).
_ORDER = {"iteration": 0, "angle": 1, "reduction": 2, "radius": 3, "thickness": 3, "axiom": 4,
          "rule": 5}  # fmt: skip
_SETTING = {"angle": "rot", "reduction": "reduction", "radius": "radius", "thickness": "thickness"}
_KEYWORD = re.compile(r"\s*([A-Za-z_]+)\s*:")
_WORD = re.compile(r"\s*([A-Za-z_]+)")
_INT = re.compile(r"\s*([+-]?\d+)\s*\Z")
_FLOAT = re.compile(r"\s*([+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)\s*\Z")


def _strip_comment(line: str) -> str:
    i = line.find(";")
    return line if i < 0 else line[:i]


def _symbols(text: str, offset: int, where: Where, what: str) -> list[tuple[str, int]]:
    """The one-character symbols of ``text`` (spaces dropped) with their columns."""
    return char_symbols(text, offset, where, what, ";", "classic")


def parse(text: str, filename: str | None = None) -> Program:
    """Read a seed 000 input file.

    Parameters
    ----------
    text : str
        The whole file.
    filename : str, optional
        For error messages; its stem names the program.

    Returns
    -------
    Program
        With ``dialect="classic"``.

    Raises
    ------
    LSystemSyntaxError
        With the file, line, column and what was expected.
    """
    if text.startswith("\ufeff"):
        text = text[1:]
    seen: dict[str, int] = {}
    settings: dict[str, object] = {"turtle": "classic"}
    steps: int | None = None
    steps_at: Span | None = None
    axiom: tuple[Module, ...] | None = None
    rules: list[Rule] = []
    last: tuple[str, int] | None = None  # the previous keyword and its line
    for lineno, raw in enumerate(text.splitlines(), 1):
        line = _strip_comment(raw)
        if not line.strip():
            continue
        where = Where(raw, lineno, filename)
        first = len(line) - len(line.lstrip()) + 1
        m = _KEYWORD.match(line)
        if not m:
            word = _WORD.match(line)
            if word and word.group(1).lower() in KEYWORDS:
                raise where.error(f"expected ':' after {word.group(1)!r}", word.end(1) + 1)
            raise where.error(
                "expected 'keyword: value' with a keyword among " + join_words(KEYWORDS),
                first,
            )
        keyword = m.group(1).lower()
        if keyword not in KEYWORDS:
            raise where.error(
                f"unknown keyword {m.group(1)!r}; expected " + join_words(KEYWORDS), first
            )
        if last is not None and _ORDER[keyword] < _ORDER[last[0]]:
            raise where.error(
                f"{keyword!r} after {last[0]!r} (line {last[1]}); expected the order of seed "
                "000: iteration, angle, reduction, radius, axiom, then the rules",
                first,
            )
        last = (keyword, lineno)
        if keyword != "rule":
            if keyword in seen:
                raise where.semantic(
                    f"{keyword!r} is already given on line {seen[keyword]}; expected it once",
                    first,
                )
            seen[keyword] = lineno
        value = line[m.end() :]
        value_col = m.end() + len(value) - len(value.lstrip()) + 1
        if keyword == "iteration":
            n = _INT.match(value)
            if not n or int(n.group(1)) < 0:
                raise where.error("expected a whole number of iterations >= 0", value_col)
            steps = int(n.group(1))
            if steps > MAX_STEPS:
                raise where.semantic(
                    f"'iteration' is {steps:.3g}; expected at most {MAX_STEPS:,} derivation "
                    "steps (sylva.lsystem.MAX_STEPS)",
                    value_col,
                )
            steps_at = Span(lineno, value_col, filename)
        elif keyword in _SETTING:
            x = _FLOAT.match(value)
            if not x:
                raise where.error("expected a number (with a decimal point, e.g. 22.5)", value_col)
            settings[_SETTING[keyword]] = float(x.group(1))
        elif keyword == "axiom":
            syms = _symbols(value, m.end(), where, "the axiom")
            if not syms:
                raise where.error("the axiom is empty; expected symbols such as 'F'", value_col)
            axiom = tuple(Module(s) for s, _ in syms)
        else:
            rules.append(_rule(value, m.end(), value_col, where))
    if axiom is None:
        lines = text.splitlines()
        raise LSystemSemanticError(
            "no axiom: expected a line 'axiom: ...'",
            filename=filename,
            line=1,
            column=1,
            source_line=lines[0] if lines else None,
        )
    return Program(
        axiom=axiom,
        rules=tuple(rules),
        settings=settings,
        steps=steps,
        steps_at=steps_at,
        dialect="classic",
        name=Path(filename).stem if filename else None,
        filename=filename,
    )


def _rule(value: str, offset: int, value_col: int, where: Where) -> Rule:
    stripped = value.lstrip()
    if not stripped:
        raise where.error("the rule is empty; expected 'X -> successor'", value_col)
    pred = stripped[0]
    rest = stripped[1:]
    after = rest.lstrip()
    arrow_col = value_col + 1 + len(rest) - len(after)
    if not after.startswith("->"):
        raise where.error(
            f"expected '->' after the predecessor {pred!r} (a predecessor is one symbol)",
            arrow_col,
        )
    if pred in "[]":
        raise where.semantic(
            f"'{pred}' cannot be a predecessor: brackets are never rewritten", value_col
        )
    _symbols(pred, value_col - 1, where, "the predecessor")
    succ_offset = arrow_col + 1  # 0-based index just after '->'
    succ = _symbols(after[2:], succ_offset, where, "the successor")
    if not succ:
        raise where.error(
            "the successor is empty; expected at least one symbol after '->' (seed 000)",
            succ_offset + 1,
        )
    return Rule(
        predecessor=Pattern(pred),
        successor=tuple(Module(s) for s, _ in succ),
        span=Span(where.lineno, value_col, where.filename),
    )


def format(program: Program) -> str:  # noqa: A001 - the dialect's writer, as DESIGN names it
    """Write a program in the seed 000 format.

    Only programs the format can hold are written: one-character symbols without
    parameters, context-free rules without conditions, equal weights, no render rules.

    Raises
    ------
    ValueError
        Naming what the format cannot hold.
    """
    lines = []
    if program.steps is not None:
        lines.append(f"iteration: {int(program.steps)}")
    settings = dict(program.settings)
    for keyword, name in _SETTING.items():
        if name in settings:
            lines.append(f"{keyword}: {float(settings[name])!r}")  # type: ignore[arg-type]

    def word(mods) -> str:
        for m in mods:
            if len(m.symbol) != 1 or m.symbol in ';"' or m.symbol.isspace() or m.args:
                raise ValueError(f"the classic format cannot write the module {m!r}")
        return "".join(m.symbol for m in mods)

    lines.append(f"axiom: {word(program.axiom)}")
    for r in program.rules:
        if r.has_context or r.condition is not None or r.render or r.predecessor.params:
            raise ValueError(f"the classic format cannot write the rule {r!r}")
        if r.weight != Num(1.0):
            raise ValueError("the classic format has no rule weights")
        if not r.successor:
            raise ValueError("the classic format cannot write an empty successor")
        lines.append(f"rule: {word([Module(r.predecessor.symbol)])} -> {word(r.successor)}")
    return "\n".join(lines) + "\n"
