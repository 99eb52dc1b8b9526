"""The block text format shared by tree configurations and material databases.

A file is a sequence of blocks.  A block starts with a header in brackets and holds
``name = value`` lines until the next header::

    # a comment runs to the end of the line
    [global]
    Levels = 3                    # integer
    Scale  = 13.0 ± 3.0           # float with a deviation ("+-" works too)
    BarkMaterial = "bark.aspen"   # text

    [level 1]
    DownAngle = 60 ± -50          # a negative deviation selects a special mode

    [material leaf.aspen]
    color = 0.25 0.45 0.12        # several numbers: a vector (material files only)
    double_sided = true

Value kinds: a quoted string is *text*; ``true``/``false`` is *bool*; a number without a
decimal point, exponent or deviation is *int*; any other number, or a number followed by
``± d`` / ``+- d``, is *float*; two or more numbers are a *vector*.  Errors are
:class:`~sylva.errors.LSystemSyntaxError` with the file, line, column and a caret.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

from ..errors import LSystemSyntaxError

__all__ = ["Block", "Entry", "parse_blocks"]

_NUMBER = r"[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?"
_HEADER = re.compile(r"^\[\s*([A-Za-z_][\w.\-]*)(?:\s+([^\]]*?))?\s*\]$")
_ENTRY = re.compile(r"^(\w[\w.\-]*)\s*=\s*(.*)$")
_DEV = re.compile(rf"^({_NUMBER})\s*(?:±|\+-|\+/-)\s*({_NUMBER})$")
_INT = re.compile(r"^[+-]?\d+$")
_FLOAT = re.compile(rf"^{_NUMBER}$")


@dataclass(frozen=True)
class Entry:
    """One ``name = value`` line.

    Attributes
    ----------
    name : str
    kind : {"int", "float", "text", "bool", "vector"}
    value : int, float, str, bool or tuple of float
    deviation : float
        The ``± d`` part of a float (0 when absent).
    line, column : int
        1-based position of the value in the source.
    """

    name: str
    kind: str
    value: object
    deviation: float = 0.0
    line: int = 0
    column: int = 0


@dataclass
class Block:
    """A bracketed header (``kind`` and optional ``argument``) and its entries in order."""

    kind: str
    argument: str | None
    line: int
    entries: list[Entry] = field(default_factory=list)


def _strip_comment(line: str) -> str:
    out, quote = [], None
    for ch in line:
        if quote:
            out.append(ch)
            if ch == quote:
                quote = None
        elif ch in "\"'":
            quote = ch
            out.append(ch)
        elif ch == "#":
            break
        else:
            out.append(ch)
    return "".join(out).rstrip()


def _value(raw: str, text: str, lineno: int, col: int, filename: str | None):
    s = raw.strip()
    if not s:
        raise LSystemSyntaxError.at("expected a value after '='", text, lineno, col, filename)
    if s[0] in "\"'":
        if len(s) < 2 or s[-1] != s[0]:
            raise LSystemSyntaxError.at(
                f"unterminated text: expected a closing {s[0]}", text, lineno, col, filename
            )
        return "text", s[1:-1], 0.0
    low = s.lower()
    if low in ("true", "false"):
        return "bool", low == "true", 0.0
    m = _DEV.match(s)
    if m:
        return "float", float(m.group(1)), float(m.group(2))
    if _INT.match(s):
        return "int", int(s), 0.0
    if _FLOAT.match(s):
        return "float", float(s), 0.0
    parts = s.split()
    if len(parts) > 1 and all(_FLOAT.match(p) for p in parts):
        return "vector", tuple(float(p) for p in parts), 0.0
    raise LSystemSyntaxError.at(
        f"cannot read value {s!r}: expected a number, 'number ± deviation', "
        "a quoted text, true/false or a list of numbers",
        text, lineno, col, filename,
    )


def parse_blocks(text: str, filename: str | None = None) -> list[Block]:
    """Parse the block format into a list of :class:`Block`.

    Examples
    --------
    >>> b = parse_blocks('[global]\\nScale = 13 ± 3\\nName = "aspen"\\n')
    >>> b[0].kind, [(e.name, e.kind, e.value, e.deviation) for e in b[0].entries]
    ('global', [('Scale', 'float', 13.0, 3.0), ('Name', 'text', 'aspen', 0.0)])
    """
    blocks: list[Block] = []
    for lineno, raw in enumerate(text.splitlines(), start=1):
        line = _strip_comment(raw)
        stripped = line.strip()
        if not stripped:
            continue
        indent = len(line) - len(line.lstrip())
        if stripped.startswith("["):
            m = _HEADER.match(stripped)
            if not m:
                raise LSystemSyntaxError.at(
                    "malformed block header: expected '[kind]' or '[kind argument]'",
                    text, lineno, indent + 1, filename,
                )
            blocks.append(Block(m.group(1).lower(), m.group(2), lineno))
            continue
        m = _ENTRY.match(stripped)
        if not m:
            raise LSystemSyntaxError.at(
                "expected 'name = value' or a '[block]' header", text, lineno, indent + 1, filename
            )
        if not blocks:
            raise LSystemSyntaxError.at(
                "a parameter before any block: expected a '[global]' or '[level N]' header first",
                text, lineno, indent + 1, filename,
            )
        col = indent + m.start(2) + 1
        kind, value, dev = _value(m.group(2), text, lineno, col, filename)
        blocks[-1].entries.append(Entry(m.group(1), kind, value, dev, lineno, col))
    return blocks
