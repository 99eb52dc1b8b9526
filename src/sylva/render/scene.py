"""Scenes on the GPU: meshes uploaded once, drawn per material, plus the ground plane and sky.

A :class:`GpuScene` holds one merged copy of a :class:`~sylva.geometry.mesh.Scene` in vertex and
index buffers, with its triangles sorted by material so that each material is one draw call.
Upload once and render many frames (a turntable) from it.

Materials map to the Phong shader as follows: ``color`` (times the vertex colours) is the
diffuse and ambient colour; ``roughness`` r gives the shininess ``2 / r⁴ − 2`` (clipped to
[1, 1000]) and the specular strength ``1 − r``; ``texture`` ``"bark"``, ``"leaf"`` or
``"grass"`` selects a procedural GLSL texture, a path to an image file an image texture (with
an optional specular map beside it named ``<stem>_specular<suffix>``), anything else nothing;
``double_sided`` turns back-face culling off and lights both sides; ``alpha_cutoff`` discards
fragments whose alpha is below it.  Materials with alpha below 1 and no cut-off are blended
after the opaque ones (unsorted, as in seed 004 §3.3).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import moderngl
import numpy as np

from sylva.geometry.mesh import Material, Mesh, Scene

__all__ = [
    "GROUND_SCALE",
    "SKY_GROUND_SCALE",
    "TEXTURE_KINDS",
    "GpuScene",
    "Ground",
    "MaterialRange",
    "Sky",
    "billboard_pivots",
    "material_shading",
]

#: Procedural textures the shader knows, by ``Material.texture`` name.
TEXTURE_KINDS = {"bark": 2, "leaf": 3, "grass": 4}
TEX_NONE, TEX_IMAGE = 0, 1
#: Default ground side, in units of the scene's largest extent.
GROUND_SCALE = 4.0
#: Default ground side under a sky that fades the ground into the horizon.
SKY_GROUND_SCALE = 10.0
_IMAGE_SUFFIXES = (".png", ".jpg", ".jpeg", ".bmp", ".tga", ".tif", ".tiff", ".webp", ".gif",
                   ".rgb", ".rgba", ".sgi", ".bw")  # the last four: SGI images (cpfg's)


def material_shading(material: Material) -> dict:
    """The shader's view of a material.

    Returns
    -------
    dict
        ``kind`` (int texture kind), ``image`` (Path or None), ``shininess``, ``specular``
        (floats), ``color`` (4 floats), ``double_sided`` (bool), ``alpha_cutoff`` (float, −1
        for none) and ``blend`` (bool).
    """
    name = material.texture
    kind, image = TEX_NONE, None
    if name:
        key = name.lower()
        if key in TEXTURE_KINDS:
            kind = TEXTURE_KINDS[key]
        elif Path(name).suffix.lower() in _IMAGE_SUFFIXES:
            kind, image = TEX_IMAGE, Path(name)
    r = float(np.clip(material.roughness, 0.0, 1.0))
    shininess = float(np.clip(2.0 / max(r, 1e-3) ** 4 - 2.0, 1.0, 1000.0))
    color = tuple(float(c) for c in material.color)
    cutoff = -1.0 if material.alpha_cutoff is None else float(material.alpha_cutoff)
    return {
        "kind": kind,
        "image": image,
        "shininess": shininess,
        "specular": 1.0 - r,
        "color": color,
        "double_sided": bool(material.double_sided),
        "alpha_cutoff": cutoff,
        "blend": color[3] < 1.0 and material.alpha_cutoff is None and kind != TEX_IMAGE,
    }


@dataclass
class Ground:
    """A square ground plane under the plant, with the procedural grass texture by default.

    Parameters
    ----------
    height : float, optional
        Its Y; default the lowest Y of the scene.
    size : float, optional
        Its side; default 4 × the larger of the scene's width, depth and height (10 × under
        a :class:`Sky` with ``ground_fade``, so that the faded ground reaches the haze).
    center : tuple of 2 float, optional
        Its (x, z) centre; default the centre of the scene's footprint.
    material : Material
        Its surface.
    """

    height: float | None = None
    size: float | None = None
    center: tuple[float, float] | None = None
    material: Material = field(
        default_factory=lambda: Material(
            "ground", color=(0.20, 0.42, 0.10, 1.0), roughness=0.95, texture="grass"
        )
    )

    def mesh(self, bounds, scale: float = GROUND_SCALE) -> Mesh:
        """The plane as a two-triangle :class:`Mesh` for a scene with ``bounds`` ``(2, 3)``.

        ``scale`` times the scene's largest extent is the side when ``size`` is not set.
        """
        b = np.asarray(bounds, np.float64)
        ext = b[1] - b[0]
        size = self.size if self.size is not None else scale * max(float(ext.max()), 1e-3)
        y = float(b[0, 1]) if self.height is None else float(self.height)
        if self.center is None:
            cx, cz = 0.5 * (b[0, 0] + b[1, 0]), 0.5 * (b[0, 2] + b[1, 2])
        else:
            cx, cz = self.center
        h = size / 2
        v = np.array(
            [[cx - h, y, cz - h], [cx + h, y, cz - h], [cx + h, y, cz + h], [cx - h, y, cz + h]]
        )
        uv = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], np.float32)
        idx = np.array([[0, 2, 1], [0, 3, 2]], np.uint32)  # counter-clockwise seen from +Y
        n = np.tile(np.array([[0.0, 1.0, 0.0]], np.float32), (4, 1))
        return Mesh(v, idx, normals=n, uvs=uv, materials=[self.material], name="ground")


@dataclass
class Sky:
    """A clear-day sky behind 3D views: a vertical gradient from the horizon to the zenith.

    Each background pixel takes its colour from the elevation of the ray through it: the
    ``horizon`` colour at and below the horizon, blending to the ``zenith`` colour straight
    up by the power curve ``1 - (1 - sin(elevation)) ** exponent``.  Orthographic cameras,
    whose rays are all parallel, use the rays of a perspective camera with their ``fov`` for
    the gradient.

    Parameters
    ----------
    zenith : tuple of 3 float
        sRGB colour straight up (components in [0, 1]).
    horizon : tuple of 3 float
        sRGB colour of the haze at and below the horizon.
    ground_fade : bool
        Fade the ground plane into the ``horizon`` colour with distance from its centre
        (from 25 % to 50 % of its side), so that its square edge vanishes in the haze; a
        ground of default size then grows to 10 × the scene's extent.
    exponent : float
        Shape of the gradient (> 0; the larger, the sooner the blue comes in above the
        horizon; 1 blends linearly in ``sin(elevation)``).

    Examples
    --------
    >>> Sky().zenith
    (0.33, 0.55, 0.85)
    >>> Sky(horizon=(1.0, 0.9, 0.8), ground_fade=False).ground_fade
    False
    """

    zenith: tuple[float, float, float] = (0.33, 0.55, 0.85)
    horizon: tuple[float, float, float] = (0.80, 0.87, 0.94)
    ground_fade: bool = True
    exponent: float = 3.0

    def __post_init__(self) -> None:
        for name in ("zenith", "horizon"):
            value = getattr(self, name)
            try:
                rgb = tuple(float(c) for c in value)
            except (TypeError, ValueError) as exc:
                raise TypeError(f"Sky.{name} must be 3 numbers, got {value!r}") from exc
            if len(rgb) != 3 or not all(0.0 <= c <= 1.0 for c in rgb):
                raise ValueError(f"Sky.{name} must be 3 numbers in [0, 1], got {value!r}")
            setattr(self, name, rgb)
        if not float(self.exponent) > 0:
            raise ValueError(f"Sky.exponent must be > 0, got {self.exponent!r}")
        self.exponent = float(self.exponent)
        self.ground_fade = bool(self.ground_fade)

    def color(self, direction) -> np.ndarray:
        """The sRGB colour ``float64[..., 3]`` seen along world ``direction`` ``(..., 3)``."""
        d = np.asarray(direction, np.float64)
        s = np.clip(d[..., 1] / np.linalg.norm(d, axis=-1), 0.0, 1.0)
        t = (1.0 - (1.0 - s) ** self.exponent)[..., None]
        return (1.0 - t) * np.asarray(self.horizon) + t * np.asarray(self.zenith)


@dataclass(frozen=True)
class MaterialRange:
    """One draw call: ``count`` triangles from triangle ``first`` with ``material``."""

    material: Material
    first: int
    count: int


def billboard_pivots(mesh: Mesh, selected: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Per vertex, the centre and plane normal of the billboard piece it belongs to.

    The pieces are the connected components of the ``selected`` triangles (one per leaf).

    Returns
    -------
    pivot : float32[n, 4]
        The piece's centroid and 1 (0 for vertices of no selected triangle).
    axis : float32[n, 3]
        The piece's area-weighted mean normal.
    """
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    n = mesh.n_vertices
    tris = mesh.indices[selected].astype(np.int64)
    pivot = np.zeros((n, 4), np.float32)
    axis = np.zeros((n, 3), np.float32)
    if tris.size == 0:
        return pivot, axis
    rows = np.concatenate([tris[:, 0], tris[:, 1]])
    cols = np.concatenate([tris[:, 1], tris[:, 2]])
    graph = coo_matrix((np.ones(rows.size, np.int8), (rows, cols)), shape=(n, n))
    k, label = connected_components(graph, directed=False)
    used = np.zeros(n, bool)
    used[tris.ravel()] = True
    v = mesh.vertices.astype(np.float64)
    cnt = np.maximum(np.bincount(label[used], minlength=k), 1)
    centre = np.stack([np.bincount(label[used], v[used, j], k) for j in range(3)], 1)
    centre /= cnt[:, None]
    fn = np.cross(v[tris[:, 1]] - v[tris[:, 0]], v[tris[:, 2]] - v[tris[:, 0]])
    lt = label[tris[:, 0]]
    nsum = np.stack([np.bincount(lt, fn[:, j], k) for j in range(3)], 1)
    nsum /= np.maximum(np.linalg.norm(nsum, axis=1, keepdims=True), 1e-30)
    pivot[used, :3] = centre[label[used]]
    pivot[used, 3] = 1.0
    axis[used] = nsum[label[used]]
    return pivot, axis


class GpuScene:
    """A scene uploaded to a context.

    Use :meth:`sylva.render.Renderer.upload` to make one; call :meth:`release` (or use it as a
    context manager) to free its GPU memory.

    Attributes
    ----------
    bounds : float64[2, 3]
        The scene's bounding box.
    ranges : list of MaterialRange
        Draw calls, opaque materials first.
    n_triangles : int
    has_uv, has_colors : bool
        Whether the mesh had texture coordinates (bark falls back to global stripes if not)
        and vertex colours; they choose the shader variant.
    """

    def __init__(
        self,
        ctx: moderngl.Context,
        scene: Scene | Mesh,
        depth_program: moderngl.Program,
    ) -> None:
        mesh = scene if isinstance(scene, Mesh) else scene.merged()
        self.ctx = ctx
        self.name = mesh.name
        self.n_triangles = mesh.n_triangles
        self.has_uv = mesh.uvs is not None
        self.has_colors = mesh.colors is not None
        self.has_billboards = False
        self.bounds = np.asarray(mesh.bounds(), np.float64)
        self._shadow_cache: dict = {}
        self._buffers: list = []
        self.depth_vao = None
        self._vaos: dict[int, moderngl.VertexArray] = {}
        self._content: list = []
        self._ibo = None
        self.ranges: list[MaterialRange] = []
        if self.n_triangles == 0:
            return
        mids = mesh.triangle_materials()
        if mids.size and (mids.min() < 0 or mids.max() >= len(mesh.materials)):
            raise ValueError(
                f"mesh {mesh.name!r} has material ids outside 0..{len(mesh.materials) - 1}"
            )
        order = np.argsort(mids, kind="stable")
        indices = np.ascontiguousarray(mesh.indices[order])
        counts = np.bincount(mids, minlength=len(mesh.materials))
        starts = np.concatenate([[0], np.cumsum(counts)[:-1]])
        ranges = [
            MaterialRange(mat, int(s), int(c))
            for mat, s, c in zip(mesh.materials, starts, counts)
            if c
        ]
        self.ranges = sorted(ranges, key=lambda r: material_shading(r.material)["blend"])
        pos = self._buffer(mesh.vertices)
        content = [(pos, "3f", "in_position"), (self._buffer(mesh.normals), "3f", "in_normal")]
        if self.has_uv:
            content.append((self._buffer(mesh.uvs), "2f", "in_uv"))
        if self.has_colors:
            content.append((self._buffer(mesh.colors), "4f", "in_color"))
        bill = np.array([bool(getattr(m, "billboard", False)) for m in mesh.materials])
        if bill.any() and bill[mids].any():
            self.has_billboards = True
            pivot, axis = billboard_pivots(mesh, bill[mids])
            content.append((self._buffer(pivot), "4f", "in_pivot"))
            content.append((self._buffer(axis), "3f", "in_axis"))
        self._content = content
        self._ibo = self._buffer(indices)
        self.depth_vao = ctx.vertex_array(
            depth_program,
            [(pos, "3f", "in_position")],
            index_buffer=self._ibo,
            index_element_size=4,
        )

    @property
    def empty(self) -> bool:
        """True when there is nothing to draw."""
        return self._ibo is None

    def vao_for(self, program: moderngl.Program) -> moderngl.VertexArray:
        """The vertex array binding these buffers to ``program`` (made once per program)."""
        key = id(program)
        if key not in self._vaos:
            content = [c for c in self._content if program.get(c[2], None) is not None]
            self._vaos[key] = self.ctx.vertex_array(
                program, content, index_buffer=self._ibo, index_element_size=4
            )
        return self._vaos[key]

    def _buffer(self, array: np.ndarray) -> moderngl.Buffer:
        buf = self.ctx.buffer(np.ascontiguousarray(array).tobytes())
        self._buffers.append(buf)
        return buf

    @property
    def extent(self) -> float:
        """Length of the bounding box diagonal."""
        return float(np.linalg.norm(self.bounds[1] - self.bounds[0]))

    def forget_shadows(self) -> None:
        """Drop the cached shadow maps (the next render draws them again)."""
        for entry in self._shadow_cache.values():
            entry.release()
        self._shadow_cache.clear()

    def release(self) -> None:
        """Free the buffers (the object cannot draw afterwards)."""
        self.forget_shadows()
        for obj in (*self._vaos.values(), self.depth_vao, *self._buffers):
            if obj is not None:
                obj.release()
        self._vaos.clear()
        self._buffers = []
        self._content = []
        self.depth_vao = self._ibo = None
        self.ranges = []

    def __enter__(self) -> GpuScene:
        return self

    def __exit__(self, *exc) -> None:
        self.release()
