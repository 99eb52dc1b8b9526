"""The turtle's branches as the compact binaries the studio's and the widget's pages draw.

:func:`branch_rows` are the full frame of a large plant: one instanced cylinder a row.
:func:`line_bytes` are the preview while a slider is dragged.

While a slider is dragged, the studio and the notebook widget draw the plant's branches as
one-pixel lines (a ``THREE.LineSegments``, no triangles), the full frame replacing them when
the drag stops.  The bytes are laid out as the page's vertex buffers take them, so that the
page does no work per branch:

* ``n * 6`` float32: the two end points of each branch (``x0 y0 z0 x1 y1 z1``);
* ``n * 8`` uint8: the colour of each end point, linear RGB scaled to 0..255 and an alpha
  byte of 255 (both ends take the branch's colour).

That is 32 bytes a line, against the 44 a branch of the instanced rows and about 300 of
the mesh's glTF.  Consecutive branches that continue each other (the next starts where the
last ended, in the same direction and colour: ``F -> FF``'s chains) are one line: a
one-pixel line looks the same drawn once or in pieces, and the page draws a third of the
lines for ABOP's fig. 1.24d.  Nothing else of the plant (leaves, polygons, widths) is in
the preview.

Examples
--------
>>> import sylva
>>> g = sylva.grow("axiom = F\\nF -> F[+F]F", 2).geometry
>>> data = line_bytes(g)
>>> line_count(data) == g.n_segments == 9
True
>>> chain = sylva.grow("axiom = F\\nF -> FF", 3).geometry   # 8 branches in a row
>>> line_count(line_bytes(chain)), line_count(line_bytes(chain, merge=False))
(1, 8)
"""

from __future__ import annotations

import numpy as np

__all__ = ["BYTES_PER_LINE", "branch_rows", "line_bytes", "line_count"]

#: Bytes a branch takes: 6 float32 end-point coordinates and 2 RGBA8 colours.
BYTES_PER_LINE = 32


def line_bytes(geometry, *, merge: bool = True) -> bytes:
    """The branches of a turtle :class:`~sylva.turtle.Geometry` as preview lines.

    Parameters
    ----------
    geometry : Geometry
        What :func:`sylva.turtle.interpret` returned (``seg_start``, ``seg_end``,
        ``seg_color``).
    merge : bool
        Draw consecutive branches that continue each other as one line (see the module).

    Returns
    -------
    bytes
        ``n * 6`` float32 end points, then ``n * 8`` uint8 RGBA colours (see the module).
    """
    g = geometry
    m = int(g.n_segments)
    start, end, color = g.seg_start[:m], g.seg_end[:m], g.seg_color[:m]
    if merge and m > 1:
        first, last = _runs(_continues(start, end, color))
        start, end, color = start[first], end[last], color[first]
    n = len(start)
    out = np.empty(BYTES_PER_LINE * n, np.uint8)
    pos = out[: 24 * n].view(np.float32).reshape(n, 2, 3)
    pos[:, 0] = start
    pos[:, 1] = end
    col = out[24 * n:].reshape(n, 2, 4)
    rgb = np.clip(np.asarray(color, np.float32), 0.0, 1.0)
    col[:, :, :3] = (rgb * 255.0 + 0.5).astype(np.uint8)[:, None, :]
    col[:, :, 3] = 255
    return out.tobytes()


def branch_rows(geometry, *, merge: bool = True) -> bytes:
    """The branches as float32 rows ``start xyz, end xyz, r0, r1, linear rgb`` (11 floats
    each): what the pages draw as instanced cylinders (seed 001 §6.7's shared prism with
    per-segment instance data), a fraction of the bytes of their mesh.

    With ``merge``, consecutive branches of one width that continue each other (as
    :func:`line_bytes` merges them, and ``r0 == r1`` for both) are one row: the page draws
    the same cylinder either way, from fewer instances.

    Examples
    --------
    >>> import numpy as np, sylva
    >>> chain = sylva.grow("axiom = F\\nF -> FF", 3).geometry
    >>> rows = np.frombuffer(branch_rows(chain), np.float32).reshape(-1, 11)
    >>> rows[:, :6].round(3).tolist()           # eight unit branches, one row
    [[0.0, 0.0, 0.0, 0.0, 8.0, 0.0]]
    >>> len(branch_rows(chain, merge=False)) // 44
    8
    """
    g = geometry
    m = int(g.n_segments)
    start, end, radius, color = g.seg_start[:m], g.seg_end[:m], g.seg_radius[:m], g.seg_color[:m]
    if merge and m > 1:
        r = radius
        even = (r[1:, 0] == r[1:, 1]) & (r[:-1, 0] == r[:-1, 1]) & (r[1:, 0] == r[:-1, 0])
        cont = _continues(start, end, color)
        cont[1:] &= even
        first, last = _runs(cont)
        start, end, radius, color = start[first], end[last], radius[first], color[first]
    rows = np.empty((len(start), 11), np.float32)
    rows[:, 0:3] = start
    rows[:, 3:6] = end
    rows[:, 6:8] = radius
    rows[:, 8:11] = color
    return rows.tobytes()


def _runs(cont: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The first and last index of each run of branches continuing the one before."""
    first = np.flatnonzero(~cont)
    last = np.empty_like(first)
    last[:-1] = first[1:] - 1
    last[-1] = len(cont) - 1
    return first, last


def _continues(start: np.ndarray, end: np.ndarray, color: np.ndarray) -> np.ndarray:
    """Per branch: it starts where the one before ended (to a millionth of the plant's
    size), in the same direction (to 1e-4 rad) and colour."""
    scale = float(np.abs(end).max(initial=0.0)) or 1.0
    a, b = end[1:] - start[1:], end[:-1] - start[:-1]
    touch = np.abs(start[1:] - end[:-1]).max(axis=1) <= 1e-6 * scale
    cx = a[:, 1] * b[:, 2] - a[:, 2] * b[:, 1]
    cy = a[:, 2] * b[:, 0] - a[:, 0] * b[:, 2]
    cz = a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]
    dot = (a * b).sum(axis=1)
    parallel = (cx * cx + cy * cy + cz * cz <= 1e-8 * dot * dot) & (dot > 0)
    same = (color[1:] == color[:-1]).all(axis=1)
    out = np.zeros(len(start), bool)
    out[1:] = touch & parallel & same
    return out


def line_count(data: bytes) -> int:
    """How many branches a preview's bytes hold."""
    return len(data) // BYTES_PER_LINE
