"""Predefined surfaces: bicubic Bézier patches, cpfg's ``.s`` surface files, and sylva's own
leaf and petal.

cpfg draws ``~X`` as the surface named ``X`` by a ``surface: X file.s scale [s t]`` line of
the view file (the cpfg manual §6.7.1 and §8.1.5; the file format is the one of vlab's
surface editor, bezieredit, in the vlab Tools manual §5.4):

* a header: ``xmin xmax ymin ymax zmin zmax`` (the bounds), an optional ``PRECISION S: i
  T: j``, then ``CONTACT POINT X: x Y: y Z: z`` (where the surface meets the turtle),
  ``END POINT`` (where the turtle stands after it), ``HEADING`` and ``UP`` (the surface's
  vectors matched to the turtle's H and U) and ``SIZE: x`` (the surface units that make
  one unit of ``F``);
* then one group per patch: its name, ``TOP COLOR: i DIFFUSE: x BOTTOM COLOR: j DIFFUSE: y``,
  the names of its eight neighbours (``AL: A: AR:`` / ``L: R:`` / ``BL: B: BR:``, ``~`` for
  none) and its 16 control points, four rows of four ``x y z``.

A point ``p`` of the surface is drawn at ``P + k·(x'·L + y'·H + z'·U)`` with ``P`` the turtle's
position, ``(H, L, U)`` its frame, ``k = scale / SIZE`` times the module's parameter
(``~X(k)``), and ``x' = (p − c)·l``, ``y' = (p − c)·h``, ``z' = (p − c)·u`` the coordinates of
``p`` about the contact point ``c`` in the surface's own frame (``h`` the heading, ``l = h × u``
and ``u`` the up vector made orthogonal to ``h``), as cpfg's ``patches.c`` places it.

:data:`BUILTIN` holds sylva's own surfaces, ``leaf`` and ``petal`` (one patch each, after
ABOP Fig. 3.x's leaves and petals: control points written for sylva), which every program
can draw as ``~"leaf"`` / ``~"petal"`` (``.lsys``) without a view file.

Examples
--------
>>> s = BUILTIN["leaf"]
>>> len(s.patches), s.size
(1, 1.0)
>>> v, uv, tris = s.template(4, 4)
>>> v.shape, tris.shape
((25, 3), (32, 3))
>>> read_surface(format_surface(s)) == s
True
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .._atomic import atomic_write
from ..errors import LSystemSyntaxError, SylvaError

__all__ = [
    "BUILTIN",
    "NEIGHBOURS",
    "Patch",
    "Surface",
    "bernstein",
    "evaluate_patch",
    "format_surface",
    "load_surface",
    "read_surface",
    "write_surface",
]

#: The neighbour slots of a patch, in the order of the file.
NEIGHBOURS = ("AL", "A", "AR", "L", "R", "BL", "B", "BR")
#: Polygons along each side of a patch when neither the view file nor the ``.s`` says.
DEFAULT_PRECISION = 5


def bernstein(t) -> np.ndarray:
    """``float64[..., 4]``: the cubic Bernstein polynomials ``C(3,i)·tⁱ·(1 − t)³⁻ⁱ`` at ``t``."""
    t = np.asarray(t, np.float64)[..., None]
    i = np.arange(4)
    return np.array([1.0, 3.0, 3.0, 1.0]) * t**i * (1.0 - t) ** (3 - i)


def evaluate_patch(points, u, v) -> np.ndarray:
    """Points ``Σᵢ Σⱼ Bᵢ(u)·Bⱼ(v)·Pᵢⱼ`` of the bicubic Bézier patch ``points`` (``[4, 4, 3]``:
    row ``i``, column ``j``) at parameters ``u`` (along the rows' index) and ``v`` (along a
    row), which broadcast together; ``float64[..., 3]``."""
    p = np.asarray(points, np.float64).reshape(4, 4, 3)
    bu, bv = bernstein(u), bernstein(v)
    bu, bv = np.broadcast_arrays(bu, bv)
    return np.einsum("...i,...j,ijc->...c", bu, bv, p)


@dataclass(frozen=True, eq=False)
class Patch:
    """One bicubic Bézier patch of a :class:`Surface`.

    Attributes
    ----------
    points : float64[4, 4, 3]
        The control points, row by row as the file lists them.
    name : str
    colors : tuple of (int, float, int, float)
        ``TOP COLOR``, its ``DIFFUSE``, ``BOTTOM COLOR``, its ``DIFFUSE`` (0: the turtle's).
    neighbours : tuple of 8 str
        The patches at :data:`NEIGHBOURS` (``"~"``: none).
    """

    points: np.ndarray
    name: str = "patch"
    colors: tuple[int, float, int, float] = (0, 0.0, 0, 0.0)
    neighbours: tuple[str, ...] = ("~",) * 8

    def __post_init__(self) -> None:
        p = np.array(self.points, np.float64)
        if p.size != 48 or not np.all(np.isfinite(p)):
            raise SylvaError(f"patch {self.name!r}: expected 16 finite control points "
                             f"(4 rows of 4 x y z), got {p.size} numbers")  # fmt: skip
        object.__setattr__(self, "points", p.reshape(4, 4, 3))
        if len(self.neighbours) != 8:
            raise SylvaError(f"patch {self.name!r}: expected 8 neighbours {NEIGHBOURS}")

    def __eq__(self, other) -> bool:
        return (isinstance(other, Patch) and self.name == other.name
                and self.colors == other.colors and self.neighbours == other.neighbours
                and np.array_equal(self.points, other.points))  # fmt: skip

    __hash__ = None  # type: ignore[assignment]


def _unit(v, what: str) -> np.ndarray:
    v = np.asarray(v, np.float64).reshape(3)
    n = float(np.linalg.norm(v))
    if not n > 0.0:
        raise SylvaError(f"the surface's {what} vector is zero; expected a direction")
    return v / n


@dataclass(frozen=True, eq=False)
class Surface:
    """A predefined surface: Bézier patches and how they meet the turtle.

    Attributes
    ----------
    patches : tuple of Patch
    contact, end : float64[3]
        The contact point (placed at the turtle) and the end point.
    heading, up : float64[3]
        The surface's vectors matched to the turtle's H and U.
    size : float
        Surface units per unit length of ``F``.
    precision : tuple of 2 int or None
        The file's ``PRECISION S: T:`` (polygons along a patch's rows and columns).
    """

    patches: tuple[Patch, ...]
    contact: np.ndarray = field(default_factory=lambda: np.zeros(3))
    end: np.ndarray = field(default_factory=lambda: np.zeros(3))
    heading: np.ndarray = field(default_factory=lambda: np.array([0.0, 1.0, 0.0]))
    up: np.ndarray = field(default_factory=lambda: np.array([0.0, 0.0, 1.0]))
    size: float = 1.0
    precision: tuple[int, int] | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "patches", tuple(self.patches))
        if not self.patches:
            raise SylvaError("a surface needs at least one patch")
        for k in ("contact", "end", "heading", "up"):
            object.__setattr__(self, k, np.array(getattr(self, k), np.float64).reshape(3))
        if not (np.isfinite(self.size) and self.size > 0.0):
            raise SylvaError(f"the surface's SIZE must be > 0, got {self.size}")
        object.__setattr__(self, "size", float(self.size))

    def __eq__(self, other) -> bool:
        return (isinstance(other, Surface) and self.patches == other.patches
                and self.size == other.size and self.precision == other.precision
                and all(np.array_equal(getattr(self, k), getattr(other, k))
                        for k in ("contact", "end", "heading", "up")))  # fmt: skip

    __hash__ = None  # type: ignore[assignment]

    @property
    def bounds(self) -> np.ndarray:
        """``float64[3, 2]``: min and max of the control points per axis (the header's)."""
        p = np.concatenate([q.points.reshape(-1, 3) for q in self.patches])
        return np.stack([p.min(axis=0), p.max(axis=0)], axis=1)

    def frame(self) -> np.ndarray:
        """``float64[3, 3]``: rows ``l = h × u``, ``h``, ``u`` (``u`` made orthogonal to ``h``)."""
        h = _unit(self.heading, "heading")
        u = _unit(self.up, "up")
        left = np.cross(h, u)
        if not np.linalg.norm(left) > 1e-12:
            raise SylvaError("the surface's heading and up vectors are parallel")
        left /= np.linalg.norm(left)
        return np.stack([left, h, np.cross(left, h)])

    def local(self, points) -> np.ndarray:
        """``points`` of the surface in the turtle's terms: ``(x', y', z')`` about the contact
        point, divided by :attr:`size` (x' along L, y' along H, z' along U)."""
        q = np.asarray(points, np.float64) - self.contact
        return q @ self.frame().T / self.size

    def template(self, s: int | None = None, t: int | None = None, scale: float = 1.0):
        """The tessellated patches as a leaf template of :func:`~sylva.geometry.build.build_leaves`.

        Each patch is a grid of ``s × t`` quads (``s`` along the rows' index, ``t`` along a
        row; default the file's precision, else :data:`DEFAULT_PRECISION`), two triangles
        each, facing the surface's up side.  The template's frame is the one of
        :func:`~sylva.geometry.build.leaf_template`: x to the right (−L), y along H, z along
        U, so its x is ``−x'``; lengths are ``scale / size`` surface units.

        Returns
        -------
        vertices : float64[m, 3]; uvs : float32[m, 2]; tris : int64[k, 3]
        """
        ps, pt = self.precision or (DEFAULT_PRECISION, DEFAULT_PRECISION)
        s = int(s or ps)
        t = int(t or pt)
        if s < 1 or t < 1:
            raise SylvaError(f"surface precision must be at least 1 x 1, got {s} x {t}")
        uu, vv = np.meshgrid(np.linspace(0, 1, s + 1), np.linspace(0, 1, t + 1), indexing="ij")
        quad = (np.arange(s)[:, None] * (t + 1) + np.arange(t)[None, :]).ravel()
        a, b, c, d = quad, quad + 1, quad + t + 1, quad + t + 2
        grid = np.concatenate([np.stack([a, c, d], 1), np.stack([a, d, b], 1)])
        verts, uvs, tris = [], [], []
        base = 0
        for patch in self.patches:
            p = self.local(evaluate_patch(patch.points, uu, vv).reshape(-1, 3)) * scale
            p[:, 0] = -p[:, 0]
            tri = grid.copy()
            e1 = p[tri[:, 1]] - p[tri[:, 0]]
            e2 = p[tri[:, 2]] - p[tri[:, 0]]
            if np.cross(e1, e2)[:, 2].sum() < 0.0:  # face the up side
                tri = tri[:, ::-1]
            verts.append(p)
            uvs.append(np.stack([vv.ravel(), uu.ravel()], 1))
            tris.append(tri + base)
            base += p.shape[0]
        return (np.concatenate(verts), np.concatenate(uvs).astype(np.float32),
                np.concatenate(tris).astype(np.int64))  # fmt: skip

    def texture_uvs(self, s: int | None = None, t: int | None = None,
                    per_surface: bool = False) -> np.ndarray:  # fmt: skip
        """cpfg's texture coordinates of the vertices of :meth:`template` (same ``s``, ``t``),
        ``float32[m, 2]`` with ``v = 0`` at the image's bottom row (OpenGL's ``(s, t)``).

        Per patch (the default, the cpfg manual §8.1.7): ``(i / s, j / t)`` at the ``i``-th
        step along the rows' index and the ``j``-th along a row, so that each patch carries
        the whole image.  Per surface (``S:``): the vertex's coordinates along the turtle's
        left and heading, each scaled to [0, 1] over the whole surface, as cpfg's
        ``patches.c`` maps the image into the surface's plane.

        Examples
        --------
        >>> uv = BUILTIN["leaf"].texture_uvs(2, 2)
        >>> uv[:3].tolist()
        [[0.0, 0.0], [0.0, 0.5], [0.0, 1.0]]
        """
        if per_surface:
            v = self.template(s, t)[0]
            left, head = -v[:, 0], v[:, 1]  # the template's x is to the right (-L)
            out = np.stack([left, head], 1)
            lo, hi = out.min(axis=0), out.max(axis=0)
            out = (out - lo) / np.where(hi > lo, hi - lo, 1.0)
            return out.astype(np.float32)
        ps, pt = self.precision or (DEFAULT_PRECISION, DEFAULT_PRECISION)
        s, t = int(s or ps), int(t or pt)
        uu, vv = np.meshgrid(np.linspace(0, 1, s + 1), np.linspace(0, 1, t + 1), indexing="ij")
        one = np.stack([uu.ravel(), vv.ravel()], 1)
        return np.tile(one, (len(self.patches), 1)).astype(np.float32)


# --------------------------------------------------------------------------- reading
_TOKEN = re.compile(r"\S+")
_NUM = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?\Z")


class _Reader:
    def __init__(self, text: str, filename: str | None) -> None:
        self.text, self.filename = text, filename
        self.lines = text.split("\n")
        self.toks = [(m.group(), n, m.start() + 1)
                     for n, line in enumerate(self.lines, start=1)
                     for m in _TOKEN.finditer(line)]  # fmt: skip
        self.i = 0

    def error(self, message: str, k: int | None = None) -> LSystemSyntaxError:
        k = self.i if k is None else k
        if k < len(self.toks):
            _, line, col = self.toks[k]
        else:
            line, col = len(self.lines), len(self.lines[-1]) + 1
        src = self.lines[line - 1].rstrip("\r") if 0 < line <= len(self.lines) else None
        return LSystemSyntaxError(message, filename=self.filename, line=line, column=col,
                                  source_line=src)  # fmt: skip

    def peek(self) -> str | None:
        return self.toks[self.i][0] if self.i < len(self.toks) else None

    def take(self) -> str:
        if self.i >= len(self.toks):
            raise self.error("unexpected end of the surface file")
        self.i += 1
        return self.toks[self.i - 1][0]

    def number(self, what: str) -> float:
        tok = self.take()
        if not _NUM.match(tok):
            raise self.error(f"{what}: expected a number, got {tok!r}", self.i - 1)
        return float(tok)

    def keyword(self, *words: str) -> None:
        for w in words:
            tok = self.take()
            if tok.upper() != w:
                raise self.error(f"expected {' '.join(words)!r}, got {tok!r}", self.i - 1)

    def vector(self, *title: str) -> np.ndarray:
        self.keyword(*title)
        out = []
        for axis in "XYZ":
            self.keyword(f"{axis}:")
            out.append(self.number(f"{' '.join(title)} {axis}"))
        return np.array(out)


def read_surface(text: str, filename: str | None = None) -> Surface:
    """The :class:`Surface` of a ``.s`` file's text (the layout in the module docstring).

    Raises
    ------
    LSystemSyntaxError
        For text that is not such a file, naming the file, line and column and what was
        expected there.
    """
    r = _Reader(text.removeprefix("\ufeff"), filename)
    for _ in range(6):
        r.number("the bounds xmin xmax ymin ymax zmin zmax")
    precision = None
    if (r.peek() or "").upper() == "PRECISION":
        r.keyword("PRECISION", "S:")
        si = r.number("PRECISION S")
        r.keyword("T:")
        ti = r.number("PRECISION T")
        precision = (max(int(si), 1), max(int(ti), 1))
    contact = r.vector("CONTACT", "POINT")
    end = r.vector("END", "POINT")
    heading = r.vector("HEADING")
    up = r.vector("UP")
    r.keyword("SIZE:")
    at = r.i
    size = r.number("SIZE")
    if not size > 0.0:
        raise r.error(f"SIZE: expected a number > 0, got {size:g}", at)
    patches = []
    while r.peek() is not None:
        name = r.take()
        r.keyword("TOP", "COLOR:")
        tc = r.number("TOP COLOR")
        r.keyword("DIFFUSE:")
        td = r.number("DIFFUSE")
        r.keyword("BOTTOM", "COLOR:")
        bc = r.number("BOTTOM COLOR")
        r.keyword("DIFFUSE:")
        bd = r.number("DIFFUSE")
        nb = []
        for slot in NEIGHBOURS:
            r.keyword(f"{slot}:")
            nb.append(r.take())
        pts = [r.number(f"patch {name!r}: control point") for _ in range(48)]
        patches.append(Patch(np.array(pts), name, (int(tc), td, int(bc), bd), tuple(nb)))
    if not patches:
        raise r.error("expected at least one patch after SIZE:")
    try:
        surface = Surface(tuple(patches), contact, end, heading, up, size, precision)
        surface.frame()
    except SylvaError as e:
        raise r.error(str(e), at) from None
    return surface


def load_surface(path) -> Surface:
    """:func:`read_surface` of the file at ``path`` (a :class:`~sylva.errors.SylvaError`
    naming it when it cannot be read)."""
    path = Path(path)
    try:
        data = path.read_bytes()
    except OSError as e:
        raise SylvaError(f"{path}: cannot read the surface file ({e.strerror or e})") from None
    return read_surface(data.decode("latin-1"), str(path))


def _g(x: float) -> str:
    return repr(float(x)) if float(x) != int(x) else f"{float(x):.1f}"


def format_surface(surface: Surface) -> str:
    """``surface`` as the text of a ``.s`` file (numbers written exactly: it reads back
    equal)."""
    b = surface.bounds
    out = ["  ".join(f"{_g(b[k, 0])} {_g(b[k, 1])}" for k in range(3))]
    if surface.precision is not None:
        out.append(f"PRECISION S: {surface.precision[0]} T: {surface.precision[1]}")
    for title, v in (("CONTACT POINT", surface.contact), ("END POINT", surface.end),
                     ("HEADING", surface.heading), ("UP", surface.up)):  # fmt: skip
        out.append(f"{title}  X: {_g(v[0])} Y: {_g(v[1])} Z: {_g(v[2])}")
    out.append(f"SIZE: {_g(surface.size)}")
    for p in surface.patches:
        tc, td, bc, bd = p.colors
        nb = dict(zip(NEIGHBOURS, p.neighbours))
        out += [p.name,
                f"TOP COLOR: {tc} DIFFUSE: {_g(td)} BOTTOM COLOR: {bc} DIFFUSE: {_g(bd)}",
                f"AL: {nb['AL']} A: {nb['A']} AR: {nb['AR']}",
                f"L: {nb['L']} R: {nb['R']}",
                f"BL: {nb['BL']} B: {nb['B']} BR: {nb['BR']}"]  # fmt: skip
        out += ["  ".join(" ".join(_g(c) for c in pt) for pt in row) for row in p.points]
    return "\n".join(out) + "\n"


def write_surface(surface: Surface, path) -> Path:
    """Write ``surface`` as a ``.s`` file at ``path`` (atomically); returns the path."""
    path = Path(path)
    with atomic_write(path, "w") as fh:
        fh.write(format_surface(surface))
    return path


# --------------------------------------------------------------------------- sylva's own
def _builtin(rows) -> Surface:
    return Surface((Patch(np.array(rows, np.float64), "patch"),), precision=(6, 4))


#: sylva's own surfaces (control points written for sylva, in the manner of ABOP's leaf
#: and petal figures): contact point at the base, heading +y, up +z, one unit long.
BUILTIN: dict[str, Surface] = {
    # an ovate leaf: a narrow base, widest at a third of its length, a pointed tip, the
    # margins raised a little over a midrib that droops towards the tip
    "leaf": _builtin([
        [(-0.04, 0.0, 0.0), (-0.015, 0.0, 0.0), (0.015, 0.0, 0.0), (0.04, 0.0, 0.0)],
        [(-0.50, 0.30, 0.10), (-0.18, 0.34, 0.02), (0.18, 0.34, 0.02), (0.50, 0.30, 0.10)],
        [(-0.34, 0.78, 0.04), (-0.12, 0.82, -0.04), (0.12, 0.82, -0.04), (0.34, 0.78, 0.04)],
        [(-0.02, 1.0, -0.12), (-0.007, 1.0, -0.12), (0.007, 1.0, -0.12), (0.02, 1.0, -0.12)],
    ]),
    # an obovate, cupped petal: a narrow claw, broadest near the rounded tip, the edges
    # curled up
    "petal": _builtin([
        [(-0.03, 0.0, 0.0), (-0.01, 0.0, 0.0), (0.01, 0.0, 0.0), (0.03, 0.0, 0.0)],
        [(-0.28, 0.35, 0.10), (-0.10, 0.35, 0.0), (0.10, 0.35, 0.0), (0.28, 0.35, 0.10)],
        [(-0.46, 0.85, 0.20), (-0.16, 0.92, 0.05), (0.16, 0.92, 0.05), (0.46, 0.85, 0.20)],
        [(-0.18, 1.0, 0.14), (-0.06, 1.06, 0.08), (0.06, 1.06, 0.08), (0.18, 1.0, 0.14)],
    ]),
}
