"""The turtle's branches as lines: the compact binary of the studio's and the widget's preview.

While a slider is dragged, the studio and the notebook widget draw the plant's branches as
one-pixel lines (a ``THREE.LineSegments``, no triangles), the full frame replacing them when
the drag stops.  The bytes are laid out as the page's vertex buffers take them, so that the
page does no work per branch:

* ``n * 6`` float32: the two end points of each branch (``x0 y0 z0 x1 y1 z1``);
* ``n * 8`` uint8: the colour of each end point, linear RGB scaled to 0..255 and an alpha
  byte of 255 (both ends take the branch's colour).

That is 32 bytes a branch, against the 44 of the instanced rows and about 300 of the mesh's
glTF.  Nothing else of the plant (leaves, polygons, widths) is in the preview.

Examples
--------
>>> import sylva
>>> g = sylva.grow("axiom = F\\nF -> F[+F]F", 2).geometry
>>> data = line_bytes(g)
>>> len(data) == 32 * g.n_segments
True
>>> line_count(data) == g.n_segments
True
"""

from __future__ import annotations

import numpy as np

__all__ = ["BYTES_PER_LINE", "line_bytes", "line_count"]

#: Bytes a branch takes: 6 float32 end-point coordinates and 2 RGBA8 colours.
BYTES_PER_LINE = 32


def line_bytes(geometry) -> bytes:
    """The branches of a turtle :class:`~sylva.turtle.Geometry` as preview lines.

    Parameters
    ----------
    geometry : Geometry
        What :func:`sylva.turtle.interpret` returned (``seg_start``, ``seg_end``,
        ``seg_color``).

    Returns
    -------
    bytes
        ``n * 6`` float32 end points, then ``n * 8`` uint8 RGBA colours (see the module).
    """
    g = geometry
    n = int(g.n_segments)
    out = np.empty(BYTES_PER_LINE * n, np.uint8)
    pos = out[: 24 * n].view(np.float32).reshape(n, 2, 3)
    pos[:, 0] = g.seg_start[:n]
    pos[:, 1] = g.seg_end[:n]
    col = out[24 * n:].reshape(n, 2, 4)
    rgb = np.clip(np.asarray(g.seg_color[:n], np.float32), 0.0, 1.0)
    col[:, :, :3] = (rgb * 255.0 + 0.5).astype(np.uint8)[:, None, :]
    col[:, :, 3] = 255
    return out.tobytes()


def line_count(data: bytes) -> int:
    """How many branches a preview's bytes hold."""
    return len(data) // BYTES_PER_LINE
