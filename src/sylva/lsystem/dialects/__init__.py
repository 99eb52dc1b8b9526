"""The four L-system languages, read into the common :class:`~sylva.lsystem.ast.Program`.

* ``"lsys"`` — the LSysVis language of seed 001 (``.lsys``): ``axiom = F``, ``F -> F[+F]F``;
  see :mod:`~sylva.lsystem.dialects.lsysvis`.
* ``"classic"`` — the input files of seed 000: ``iteration: 7``, ``axiom: A``,
  ``rule: A -> FA``; see :mod:`~sylva.lsystem.dialects.classic`.
* ``"engine"`` — the voxel engine of seed 004, several systems per file: ``45.0 45.0 0.8``,
  ``^uA``, ``A > +uE``; see :mod:`~sylva.lsystem.dialects.engine`.
* ``"cpfg"`` — L-Studio's and ABOP's language (seed 003 §5.10): ``Lsystem: 1``,
  ``Axiom: F(1)``, ``F(x) --> F(x*2) : 0.4``, ``homomorphism``; see
  :mod:`~sylva.lsystem.dialects.cpfg`.

:func:`load` reads a file or a text, :func:`detect` picks the dialect, :func:`dumps` writes any
program as ``.lsys`` text that reads back to an equal program.

Examples
--------
>>> p = loads("iteration: 1\\nangle: 90\\naxiom: F\\nrule: F -> F+F\\n")
>>> p.dialect, p.steps
('classic', 1)
>>> print(dumps(p), end="")
turtle = classic
steps = 1
rot = 90
axiom = F
<BLANKLINE>
F -> F+F
>>> loads(dumps(p)) == p
True
"""

from __future__ import annotations

import codecs
import os
import re
from collections.abc import Callable
from pathlib import Path
from types import SimpleNamespace

from ...errors import LSystemSemanticError, LSystemSyntaxError, SylvaError
from ..ast import Program
from . import classic, cpfg, engine, lsysvis
from ._writer import format_expr, format_program, format_rule, format_word
from .lsysvis import parse_expr, parse_rule, parse_word

__all__ = [
    "DIALECTS",
    "detect",
    "dumps",
    "format_expr",
    "format_rule",
    "format_word",
    "load",
    "load_all",
    "loads",
    "parse_expr",
    "parse_rule",
    "parse_word",
]


def _single(parse: Callable[[str, str | None], Program]):
    return lambda text, filename=None: [parse(text, filename)]


#: name -> namespace with ``parse(text, filename) -> Program`` and
#: ``parse_all(text, filename) -> list[Program]``.
DIALECTS = {
    "lsys": SimpleNamespace(
        name="lsys", parse=lsysvis.parse, parse_all=_single(lsysvis.parse), format=format_program
    ),
    "classic": SimpleNamespace(
        name="classic", parse=classic.parse, parse_all=_single(classic.parse), format=classic.format
    ),
    "engine": SimpleNamespace(
        name="engine", parse=engine.parse, parse_all=engine.parse_all, format=engine.format
    ),
    "cpfg": SimpleNamespace(
        name="cpfg", parse=cpfg.parse, parse_all=_single(cpfg.parse), format=format_program
    ),
}
_ALIASES = {
    "lsysvis": "lsys", "seed000": "classic", "seed001": "lsys", "seed004": "engine",
    "lstudio": "cpfg", "l-studio": "cpfg",
}  # fmt: skip

_CLASSIC_LINE = re.compile(
    r"\s*(iteration|angle|reduction|radius|thickness|axiom|rule)\s*:", re.IGNORECASE
)
_PATHLIKE_TEXT = re.compile(r"[^\n=<>]*\.(lsys|ls|txt|l)\Z", re.IGNORECASE)
_CPFG_LINE = re.compile(r"\s*(lsystem\s*:|derivation\s+length\s*:|endlsystem\b)", re.IGNORECASE)


def detect(text: str, filename: str | os.PathLike | None = None) -> str:
    """The dialect of a text: ``"lsys"``, ``"classic"``, ``"engine"`` or ``"cpfg"``.

    A ``.lsys`` file is ``lsys`` and a ``.l`` file ``cpfg``.  Otherwise the content decides:
    three numbers on the first line that is not blank or a comment make ``engine``; an
    ``Lsystem:``, ``derivation length:`` or ``endlsystem`` line makes ``cpfg``; a
    ``keyword:`` line of seed 000 (``iteration:``, ``axiom:``, ``rule:`` …) makes
    ``classic``; anything else is ``lsys``.

    Examples
    --------
    >>> detect("45.0 45.0 0.8\\nX\\nX > F")
    'engine'
    >>> detect("iteration: 2\\naxiom: F")
    'classic'
    >>> detect("Lsystem: 1\\nAxiom: F\\nF --> FF\\nendlsystem")
    'cpfg'
    >>> detect("axiom = F")
    'lsys'
    """
    if filename is not None and Path(filename).suffix.lower() == ".lsys":
        return "lsys"
    if filename is not None and Path(filename).suffix.lower() == ".l":
        return "cpfg"
    lines = text.removeprefix("\ufeff").splitlines()
    for line in lines:
        s = line.strip()
        if not s or s.startswith(("#", ";")):
            continue
        if engine.HEADER.match(s):
            return "engine"
        break
    if any(_CPFG_LINE.match(line) for line in lines):
        return "cpfg"
    if any(_CLASSIC_LINE.match(line) for line in lines):
        return "classic"
    return "lsys"


def _dialect(name: str | None, text: str, filename: str | None) -> SimpleNamespace:
    if name is None:
        return DIALECTS[detect(text, filename)]
    key = _ALIASES.get(name.lower(), name.lower())
    if key not in DIALECTS:
        raise ValueError(f"unknown dialect {name!r}; expected one of {', '.join(sorted(DIALECTS))}")
    return DIALECTS[key]


def _decode(data: bytes) -> str:
    """Text of a file in UTF-8 (with or without BOM), UTF-16 with BOM, or a legacy 8-bit
    encoding (cp1250, the Czech Windows default of the LSysVis thesis, then Latin-1)."""
    if data.startswith(codecs.BOM_UTF8):
        return data[len(codecs.BOM_UTF8) :].decode("utf-8", errors="replace")
    if data.startswith((codecs.BOM_UTF16_LE, codecs.BOM_UTF16_BE)):
        return data.decode("utf-16", errors="replace")
    for encoding in ("utf-8", "cp1250"):
        try:
            return data.decode(encoding)
        except UnicodeDecodeError:
            pass
    return data.decode("latin-1")


def _read(source, filename: str | None) -> tuple[str, str | None]:
    """(text, filename) of a path, a file object, bytes or a text."""
    if isinstance(source, os.PathLike):
        path = Path(source)
        return _decode(path.read_bytes()), filename or str(path)
    if isinstance(source, bytes):
        return _decode(source), filename
    if hasattr(source, "read"):
        data = source.read()
        name = filename or getattr(source, "name", None)
        text = _decode(data) if isinstance(data, bytes) else str(data)
        return text, name if isinstance(name, str) else None
    if not isinstance(source, str):
        raise TypeError(f"expected a path, a file or a text, got {type(source).__name__}")
    if "\n" not in source and "\r" not in source and 0 < len(source) < 4096:
        try:
            is_file = os.path.isfile(source)
        except (OSError, ValueError):
            is_file = False
        if is_file:
            return _decode(Path(source).read_bytes()), filename or source
        if _PATHLIKE_TEXT.fullmatch(source.strip()) and " " not in source.strip():
            raise LSystemSyntaxError(
                f"no such file: {source!r}; expected a path to an existing file or "
                "the text of an L-system",
                filename=filename,
            )
    return source, filename


def _pick(programs: list[Program], index: int | None, name: str | None, what: str) -> Program:
    if index is not None:
        if not -len(programs) <= index < len(programs):
            raise LSystemSemanticError(
                f"index {index} is out of range: the {what} holds {len(programs)} L-system(s)",
                filename=name,
            )
        return programs[index]
    if len(programs) != 1:
        raise LSystemSemanticError(
            f"the {what} holds {len(programs)} L-systems; expected exactly one "
            "(read them all with load_all, or pick one with index=)",
            filename=name,
        )
    return programs[0]


def load_all(source, *, filename: str | None = None, dialect: str | None = None) -> list[Program]:
    """Read every L-system of a file or text (the engine format holds several).

    Parameters
    ----------
    source : str, path-like, bytes or file object
        A path to an existing file, or the text itself.
    filename : str, optional
        The name used in error messages (defaults to the path).
    dialect : {"lsys", "classic", "engine", "cpfg"}, optional
        Force a dialect instead of detecting it (see :func:`detect`).

    Returns
    -------
    list of Program
    """
    text, name = _read(source, filename)
    return _dialect(dialect, text, name).parse_all(text, name)


def load(
    source,
    *,
    filename: str | None = None,
    dialect: str | None = None,
    index: int | None = None,
    view=None,
) -> Program:
    """Read one L-system from a file or a text.

    Parameters
    ----------
    source : str, path-like, bytes or file object
        A path to an existing file, or the text itself.
    filename : str, optional
        The name used in error messages (defaults to the path).
    dialect : {"lsys", "classic", "engine", "cpfg"}, optional
        Force a dialect instead of detecting it (by extension, then by content; see
        :func:`detect`).
    index : int, optional
        Which system to return when the file holds several (engine format).  Without it a
        file with several systems is an error.
    view : path-like or False, optional
        cpfg only: its view file (``.v``).  By default the one beside the file, same stem,
        if there is one; ``False`` reads none.

    Returns
    -------
    Program

    Raises
    ------
    LSystemSyntaxError
        For text that does not parse (:class:`~sylva.errors.LSystemSemanticError` for text
        that means nothing valid), naming the file, line and column.
    OSError
        When a path cannot be read.

    Examples
    --------
    >>> load("axiom = F\\nF -> FF").rules[0].successor
    (Module(symbol='F', args=()), Module(symbol='F', args=()))
    """
    text, name = _read(source, filename)
    ns = _dialect(dialect, text, name)
    if ns.name == "cpfg":
        return _pick([cpfg.parse(text, name, view=view)], index, name, "file")
    if view is not None:
        raise SylvaError(f"view= (a cpfg view file) is for cpfg files; {name or 'this'} "
                         f"is {ns.name}")
    return _pick(ns.parse_all(text, name), index, name, "file")


def loads(
    text: str,
    *,
    filename: str | None = None,
    dialect: str | None = None,
    index: int | None = None,
    view=None,
) -> Program:
    """Read one L-system from a text (never a path); see :func:`load`.

    Examples
    --------
    >>> loads("0 90 0.7\\nX\\nX > U[&X][^X]UX").dialect
    'engine'
    """
    if not isinstance(text, str):
        raise TypeError(f"expected a str, got {type(text).__name__}")
    ns = _dialect(dialect, text, filename)
    if ns.name == "cpfg":
        return _pick([cpfg.parse(text, filename, view=view)], index, filename, "text")
    if view is not None:
        raise SylvaError(f"view= (a cpfg view file) is for cpfg texts; this is {ns.name}")
    return _pick(ns.parse_all(text, filename), index, filename, "text")


def dumps(program: Program) -> str:
    """A program as ``.lsys`` text; ``loads(dumps(p)) == p`` for every program a dialect reads.

    Raises
    ------
    ValueError
        For something ``.lsys`` cannot write (see :func:`~._writer.format_program`).
    """
    return format_program(program)
