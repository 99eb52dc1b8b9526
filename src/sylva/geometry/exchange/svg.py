"""SVG drawings of 2D systems (Koch curves, the dragon …) and flat projections.

Given turtle :class:`~sylva.geometry.records.Geometry`, segments become stroked paths
(consecutive segments joined into one polyline, stroke width = the segment's width, or a
hairline of ``hairline`` times the drawing size when the width is 0 or ``widths=False``),
polygons filled paths, leaves small filled outlines and blocks squares, all projected onto
the XY plane (x right, y up; SVG's y axis is flipped).  Given a mesh or scene, triangles are
projected orthographically onto XY and painted far to near (by mean z) with a flat,
Lambert-shaded material colour.

Examples
--------
>>> import io
>>> from sylva.turtle import interpret
>>> out = io.StringIO()
>>> write_svg(interpret("F-F-F-F", dialect="abop", rot=90), out)
>>> out.getvalue().count("<path")
1
"""

from __future__ import annotations

from xml.sax.saxutils import quoteattr

import numpy as np

from ..build import leaf_template
from ..mesh import Mesh, Scene
from ..records import Geometry
from ._common import PathOrFile, as_scene, open_target

__all__ = ["write_svg"]


def _hex(c) -> str:
    r, g, b = (int(round(min(max(float(x), 0.0), 1.0) * 255)) for x in c[:3])
    return f"#{r:02x}{g:02x}{b:02x}"


def _fmt(x: float) -> str:
    return f"{x:.5g}"


def _header(lo, hi, margin, size, background):
    w, h = hi[0] - lo[0], hi[1] - lo[1]
    ext = max(w, h, 1e-9)
    m = margin * ext
    vb = (lo[0] - m, -(hi[1] + m), w + 2 * m, h + 2 * m)
    scale = size / max(vb[2], vb[3])
    out = [
        '<?xml version="1.0" encoding="UTF-8"?>',
        f'<svg xmlns="http://www.w3.org/2000/svg" width="{_fmt(vb[2] * scale)}" '
        f'height="{_fmt(vb[3] * scale)}" viewBox="{" ".join(_fmt(v) for v in vb)}">',
    ]
    if background is not None:
        out.append(
            f'<rect x="{_fmt(vb[0])}" y="{_fmt(vb[1])}" width="{_fmt(vb[2])}" '
            f'height="{_fmt(vb[3])}" fill="{_hex(background)}"/>'
        )
    return out, ext


def _geometry_svg(g: Geometry, margin, size, background, hairline, widths) -> list[str]:
    pts = g.points()
    lo = pts.min(axis=0) if pts.size else np.zeros(3)
    hi = pts.max(axis=0) if pts.size else np.ones(3)
    if background is None and g.background is not None:
        background = g.background
    out, ext = _header(lo, hi, margin, size, background)
    hair = hairline * ext
    # ---------------------------------------------------------------- polygons (under lines)
    for i in range(g.n_polygons):
        p = g.polygon(i)
        d = "M" + " L".join(f"{_fmt(x)} {_fmt(-y)}" for x, y in p[:, :2].tolist()) + " Z"
        out.append(f'<path d="{d}" fill="{_hex(g.poly_color[i])}" stroke="none"/>')
    # ---------------------------------------------------------------- segments
    n = g.n_segments
    if n:
        width = 2.0 * g.seg_radius.mean(axis=1) if widths else np.zeros(n)
        width = np.where(width > 0, width, hair)
        key_col = [_hex(c) for c in g.seg_color]
        s0 = g.seg_start[:, :2]
        s1 = g.seg_end[:, :2]
        groups: dict[tuple[str, str], list[str]] = {}
        last_end = None
        last_key = None
        for i in range(n):
            key = (key_col[i], _fmt(width[i]))
            x0, y0 = s0[i]
            x1, y1 = s1[i]
            part = f"L{_fmt(x1)} {_fmt(-y1)}"
            if (
                key != last_key
                or last_end is None
                or abs(last_end[0] - x0) + abs(last_end[1] - y0) > 1e-9 * ext
            ):
                part = f"M{_fmt(x0)} {_fmt(-y0)} " + part
            groups.setdefault(key, []).append(part)
            last_end = (x1, y1)
            last_key = key
        for (col, w), parts in groups.items():
            out.append(
                f'<path d="{" ".join(parts)}" fill="none" stroke="{col}" stroke-width="{w}" '
                'stroke-linecap="round" stroke-linejoin="round"/>'
            )
    # ---------------------------------------------------------------- leaves and blocks
    if g.n_leaves:
        tv, _, _ = leaf_template()
        outline = np.concatenate([tv[[0]], tv[1::3][:-1], tv[[-1]], tv[3::3][::-1]])
        for i in range(g.n_leaves):
            fr = g.leaf_frame[i]
            basis = np.stack([-fr[1], fr[0], fr[2]])
            q = g.leaf_pos[i] + (outline @ basis) * float(g.leaf_size[i])
            d = "M" + " L".join(f"{_fmt(x)} {_fmt(-y)}" for x, y in q[:, :2].tolist()) + " Z"
            out.append(f'<path d="{d}" fill="{_hex(g.leaf_color[i])}" stroke="none"/>')
    for i in range(g.n_blocks):
        c = g.block_center[i]
        s = float(g.block_size[i])
        fill = _hex(g.materials[g.block_buffer[i] % len(g.materials)].color)
        out.append(
            f'<rect x="{_fmt(c[0] - s / 2)}" y="{_fmt(-c[1] - s / 2)}" width="{_fmt(s)}" '
            f'height="{_fmt(s)}" fill="{fill}"/>'
        )
    out.append("</svg>")
    return out


def _scene_svg(scene: Scene, margin, size, background) -> list[str]:
    mesh: Mesh = scene.merged()
    lo, hi = scene.bounds().astype(np.float64) if mesh.n_vertices else np.zeros((2, 3))
    out, _ = _header(lo, hi, margin, size, background)
    if mesh.n_triangles:
        tri = mesh.vertices[mesh.indices].astype(np.float64)
        n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
        ln = np.linalg.norm(n, axis=1)
        keep = ln > 0
        light = np.array([0.3, 0.5, 0.81])
        shade = np.abs((n[keep] / ln[keep, None]) @ light) * 0.75 + 0.25
        tri = tri[keep]
        mats = mesh.triangle_materials()[keep]
        table = np.array([m.color[:3] for m in mesh.materials])
        col = table[mats] * shade[:, None]
        order = np.argsort(tri[:, :, 2].mean(axis=1), kind="stable")
        for k in order.tolist():
            (x0, y0, _), (x1, y1, _), (x2, y2, _) = tri[k].tolist()
            c = _hex(col[k])
            d = f"M{_fmt(x0)} {_fmt(-y0)} L{_fmt(x1)} {_fmt(-y1)} L{_fmt(x2)} {_fmt(-y2)} Z"
            out.append(f'<path d="{d}" fill="{c}" stroke={quoteattr(c)} stroke-width="0"/>')
    out.append("</svg>")
    return out


def write_svg(
    obj,
    target: PathOrFile,
    *,
    size: float = 800.0,
    margin: float = 0.02,
    background=None,
    hairline: float = 0.002,
    widths: bool = True,
) -> None:
    """Write an SVG drawing of turtle geometry (lines) or of a mesh scene (triangles).

    Parameters
    ----------
    obj : Geometry, Scene or Mesh
    target : path or text file
    size : float
        Pixel size of the longer side.
    margin : float
        Margin as a fraction of the drawing's extent.
    background : 3 floats, optional
        Fill colour behind the drawing (default: the program's ``bg``, else none).
    hairline : float
        Stroke width of zero-width segments, relative to the drawing's extent.
    widths : bool
        Use the segments' widths (``False``: every segment is a hairline).
    """
    if isinstance(obj, Geometry):
        lines = _geometry_svg(obj, margin, size, background, hairline, widths)
    else:
        lines = _scene_svg(as_scene(obj), margin, size, background)
    with open_target(target, binary=False) as fh:
        fh.write("\n".join(lines) + "\n")
