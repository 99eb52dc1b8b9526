"""cpfg's contour files (``.con``, made by vlab's cuspy): the cross-sections of generalised
cylinders that a view file's ``contour: id file`` names and ``@#(id)`` selects (the cpfg
manual §5.5 and §8.1.5).

Formats, as cpfg's ``general.c`` reads them:

* ``cver 1 1`` / ``cver 1 2`` / ``cver 1 3``: ``name: …``, ``points: n m`` (``n`` points
  written, ``m`` after multiplicities), ``type: o|c[r|e]`` (open or closed, regular or
  end-point interpolating), with 1.3 ``samples: k`` and optional ``background …`` (two
  lines) and ``markers: k`` (k lines) lines; then ``n`` lines ``x y z multiplicity``;
* the older ``n dim closed|open`` first line, then ``n`` points of ``dim`` numbers.

:func:`read_contour` returns a :class:`Contour`: the control points of the planar
B-spline (multiplicities expanded) and whether it is closed; the view file's contours are
the setting ``contours`` (id -> Contour), for the generalised cylinders' drawing.
"""

from __future__ import annotations

import re
from pathlib import Path
from typing import NamedTuple

from ...errors import LSystemSyntaxError

__all__ = ["Contour", "load_contour", "read_contour"]

_FLOAT = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?"
_POINT = re.compile(rf"\s*({_FLOAT})\s+({_FLOAT})\s+({_FLOAT})\s+(\d+)\s*\Z")


class Contour(NamedTuple):
    """A contour: the control points ``(x, y, z)`` of its B-spline (each repeated by its
    multiplicity) and whether it closes; ``samples`` is cuspy's sampling (1.3 files)."""

    points: tuple[tuple[float, float, float], ...]
    closed: bool
    samples: int | None = None


def read_contour(text: str, filename: str | None = None) -> Contour:
    """The contour of a ``.con`` file's text (see the module notes).

    Raises
    ------
    LSystemSyntaxError
        For a header or a point that does not read, naming the file, line and column.

    Examples
    --------
    >>> c = read_contour("cver 1 2\\nname: a\\npoints: 2 3\\ntype: or\\n0 0 0 2\\n1 0 0 1\\n")
    >>> c.points, c.closed
    (((0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (1.0, 0.0, 0.0)), False)
    """
    lines = text.removeprefix("\ufeff").replace("\r", "").split("\n")

    def err(k: int, message: str, column: int = 1) -> LSystemSyntaxError:
        src = lines[k] if k < len(lines) else ""
        return LSystemSyntaxError(message, filename=filename, line=k + 1, column=column,
                                  source_line=src)  # fmt: skip

    first = lines[0] if lines else ""
    m = re.match(r"\s*cver\s+(\d+)\s+(\d+)\s*\Z", first)
    if m is None:
        return _old(lines, err)
    version = (int(m.group(1)), int(m.group(2)))
    if version not in ((1, 1), (1, 2), (1, 3)):
        raise err(0, f"contour format {version[0]}.{version[1]} is not known; expected "
                  "cver 1 1, 1 2 or 1 3 (or the older 'n dim closed|open' header)")  # fmt: skip
    k = 2  # after 'name: …'
    m = re.match(r"\s*points:\s*(\d+)\s+(\d+)\s*\Z", lines[k] if k < len(lines) else "")
    if m is None:
        raise err(k, "expected 'points: n m' (the points written, and with their "
                  "multiplicities)")  # fmt: skip
    n, total = int(m.group(1)), int(m.group(2))
    k += 1
    kind = lines[k].strip() if k < len(lines) else ""
    if not kind.startswith("type:") or not kind[5:].strip():
        raise err(k, "expected 'type: o' or 'type: c' (open or closed)")
    closed = kind[5:].strip()[0] == "c" if version > (1, 1) else not kind[5:].strip(
        ).startswith("open")  # fmt: skip
    k += 1
    samples = None
    if version == (1, 3):
        m = re.match(r"\s*samples:\s*(\d+)\s*\Z", lines[k] if k < len(lines) else "")
        if m is None:
            raise err(k, "expected 'samples: k'")
        samples = int(m.group(1))
        k += 1
        if k < len(lines) and lines[k].startswith("b"):  # background image: skipped
            k += 2
        m = re.match(r"\s*markers:\s*(\d+)", lines[k] if k < len(lines) else "")
        if m is not None:
            k += 1 + int(m.group(1))
    points: list[tuple[float, float, float]] = []
    for _ in range(n):
        while k < len(lines) and not lines[k].strip():
            k += 1
        if k >= len(lines):
            last = max((i for i, t in enumerate(lines) if t.strip()), default=0)
            raise err(last, f"the file ends after {len(points)} of its points; expected "
                      f"{total}")  # fmt: skip
        m = _POINT.match(lines[k])
        if m is None:
            raise err(k, "expected a point 'x y z multiplicity'",
                      len(lines[k]) - len(lines[k].lstrip()) + 1)  # fmt: skip
        p = (float(m.group(1)), float(m.group(2)), float(m.group(3)))
        points.extend([p] * int(m.group(4)))
        k += 1
    if len(points) != total:
        raise err(2, f"points: {n} {total}: the multiplicities make {len(points)} points, "
                  f"not {total}")  # fmt: skip
    return Contour(tuple(points), closed, samples)


def _old(lines, err) -> Contour:
    m = re.match(r"\s*(\d+)\s+(\d+)\s+(\w+)", lines[0] if lines else "")
    if m is None:
        raise err(0, "expected 'cver 1 3' (cuspy's contour header) or 'n dim closed|open'")
    n, dim, closed = int(m.group(1)), int(m.group(2)), m.group(3) == "closed"
    if dim not in (2, 3):
        raise err(0, f"a contour's points have 2 or 3 coordinates, not {dim}",
                  m.start(2) + 1)  # fmt: skip
    words = " ".join(lines[1:]).split()
    if len(words) < n * dim:
        raise err(len(lines) - 1, f"expected {n} points of {dim} numbers, found "
                  f"{len(words)} numbers")  # fmt: skip
    try:
        v = [float(w) for w in words[: n * dim]]
    except ValueError as exc:
        raise err(1, f"a contour point is not a number ({exc})") from None
    pts = [tuple(v[i * dim : i * dim + dim]) + ((0.0,) if dim == 2 else ()) for i in range(n)]
    return Contour(tuple(pts), closed)  # type: ignore[arg-type]


def load_contour(name: str, view: str | None) -> Contour:
    """The contour in the file ``name``, relative to the view file ``view``'s folder."""
    path = Path(name)
    if not path.is_absolute() and view and not view.startswith("<"):
        path = Path(view).parent / path
    data = path.read_bytes()  # OSError: the caller names the view line
    return read_contour(data.decode("latin-1"), str(path))
