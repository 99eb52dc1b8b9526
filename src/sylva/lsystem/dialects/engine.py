"""The L-system format of the voxel engine of seed 004 (§4.3): several systems per file.

::

    45.0 45.0 0.8          <- header: yaw pitch shrink (three numbers) starts a system
    # comment lines start with '#'
    ^uA1S&F+F+F+F          <- the axiom (one token)
    U > uU                 <- productions "letter > successor"
    A > +uuE
    A > -uE

Every production's letter is one character; several productions for one letter choose
uniformly (equal weights; the engine makes the choice).  Symbols are single characters
without parameters: anything printable but ``#`` (a comment) and ``"`` (which ``.lsys``
cannot write).

Leniencies over the original parser (seed 004 §4.3 compatibility notes): whitespace around
``>`` and at the ends of lines may be anything (the original wants exactly ``c > ``);
whitespace inside the axiom or a successor is dropped (the turtle ignores it anyway); a
``#`` after a production starts a comment; a successor may be empty.

Each program has the settings ``turtle = "engine"``, ``yaw``, ``pitch`` and ``shrink``.

Examples
--------
>>> [p] = parse_all("0 90 0.7\\nX\\nX > U[&X][^X]UX\\nU > UU\\n")
>>> p.settings["yaw"], p.settings["pitch"], len(p.rules)
(0.0, 90.0, 2)
"""

from __future__ import annotations

import re
from pathlib import Path

from ...errors import LSystemSemanticError
from ..ast import Module, Num, Pattern, Program, Rule, Span
from ._diagnostics import Where, char_symbols

__all__ = ["format", "parse", "parse_all"]

_NUM = r"[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?"
HEADER = re.compile(rf"\s*({_NUM})\s+({_NUM})\s+({_NUM})\s*\Z")
_PRODUCTION = re.compile(r"\s*(\S)\s*>(.*)\Z", re.DOTALL)


def _symbols(text: str, offset: int, where: Where, what: str) -> list[str]:
    return [ch for ch, _ in char_symbols(text, offset, where, what, "#", "engine")]


class _System:
    def __init__(self, header: tuple[float, float, float], lineno: int) -> None:
        self.header = header
        self.lineno = lineno
        self.axiom: tuple[Module, ...] | None = None
        self.rules: list[Rule] = []


def parse_all(text: str, filename: str | None = None) -> list[Program]:
    """Read every L-system of an engine-format file.

    Parameters
    ----------
    text : str
        The whole file.
    filename : str, optional
        For error messages; its stem (with ``[i]`` when the file holds several systems)
        names the programs.

    Returns
    -------
    list of Program
        In file order, each with ``dialect="engine"``.

    Raises
    ------
    LSystemSyntaxError
        With the file, line, column and what was expected.
    """
    if text.startswith("\ufeff"):
        text = text[1:]
    systems: list[_System] = []
    lines = text.splitlines()
    for lineno, raw in enumerate(lines, 1):
        stripped = raw.strip()
        if not stripped or stripped.startswith("#"):
            continue
        where = Where(raw, lineno, filename)
        line = raw.split("#", 1)[0]
        first = len(line) - len(line.lstrip()) + 1
        h = HEADER.match(line)
        current = systems[-1] if systems else None
        if h:
            if current is not None and current.axiom is None:
                raise where.error(
                    "expected the axiom of the system that starts on line "
                    f"{current.lineno}, not another header",
                    first,
                )
            header = (float(h.group(1)), float(h.group(2)), float(h.group(3)))
            systems.append(_System(header, lineno))
        elif current is None:
            raise where.error(
                "expected a header line 'yaw pitch shrink' (three numbers, e.g. 45.0 45.0 0.8)",
                first,
            )
        elif current.axiom is None:
            syms = _symbols(line, 0, where, "the axiom")
            current.axiom = tuple(Module(s) for s in syms)
        else:
            m = _PRODUCTION.match(line)
            if not m:
                raise where.error(
                    "expected a production 'c > successor' or a header line "
                    "'yaw pitch shrink' that starts the next system",
                    first,
                )
            pred = m.group(1)
            if pred in "[]":
                raise where.semantic(
                    f"'{pred}' cannot be a predecessor: brackets are never rewritten", first
                )
            _symbols(pred, first - 1, where, "the predecessor")
            succ = _symbols(m.group(2), m.start(2), where, "the successor")
            current.rules.append(
                Rule(
                    predecessor=Pattern(pred),
                    successor=tuple(Module(s) for s in succ),
                    span=Span(lineno, first, filename),
                )
            )
    if systems and systems[-1].axiom is None:
        last = systems[-1]
        raise LSystemSemanticError(
            "the file ends before the axiom; expected an axiom line after the header",
            filename=filename,
            line=last.lineno,
            column=1,
            source_line=lines[last.lineno - 1],
        )
    stem = Path(filename).stem if filename else None
    out = []
    for i, s in enumerate(systems):
        yaw, pitch, shrink = s.header
        name = stem if stem is None or len(systems) == 1 else f"{stem}[{i}]"
        out.append(
            Program(
                axiom=s.axiom or (),
                rules=tuple(s.rules),
                settings={"turtle": "engine", "yaw": yaw, "pitch": pitch, "shrink": shrink},
                dialect="engine",
                name=name,
                filename=filename,
            )
        )
    return out


def parse(text: str, filename: str | None = None) -> Program:
    """Read an engine-format file that holds exactly one L-system.

    Raises
    ------
    LSystemSyntaxError
        When the file holds no system or several (read those with :func:`parse_all`).
    """
    programs = parse_all(text, filename)
    if len(programs) != 1:
        raise LSystemSemanticError(
            f"the file holds {len(programs)} L-systems; expected exactly one "
            "(read them all with load_all, or pick one with index=)",
            filename=filename,
        )
    return programs[0]


def format(programs: Program | list[Program]) -> str:  # noqa: A001
    """Write one program or several in the engine format.

    Only programs the format can hold are written: one-character symbols without
    parameters, context-free rules without conditions, equal weights, no render rules.

    Raises
    ------
    ValueError
        Naming what the format cannot hold.
    """
    if isinstance(programs, Program):
        programs = [programs]
    chunks = []
    for p in programs:
        s = dict(p.settings)
        header = " ".join(
            repr(float(s.get(k, d)))  # type: ignore[arg-type]
            for k, d in (("yaw", 0.0), ("pitch", 0.0), ("shrink", 1.0))
        )

        def word(mods) -> str:
            for m in mods:
                if len(m.symbol) != 1 or m.symbol in '#"' or m.symbol.isspace() or m.args:
                    raise ValueError(f"the engine format cannot write the module {m!r}")
            return "".join(m.symbol for m in mods)

        lines = [header, word(p.axiom)]
        for r in p.rules:
            if r.has_context or r.condition is not None or r.render or r.predecessor.params:
                raise ValueError(f"the engine format cannot write the rule {r!r}")
            if r.weight != Num(1.0):
                raise ValueError("the engine format has no rule weights")
            lines.append(f"{word([Module(r.predecessor.symbol)])} > {word(r.successor)}")
        chunks.append("\n".join(lines))
    return "\n".join(chunks) + "\n"
