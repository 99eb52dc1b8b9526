"""Triangle meshes and scenes: what geometry builders make and exporters and renderers read.

A :class:`Mesh` is a set of NumPy arrays (indexed triangles with per-vertex attributes and a
material index per triangle).  A :class:`Scene` is a list of meshes with a shared material
table.  Both are plain data; builders live in :mod:`sylva.geometry.build`.

Examples
--------
>>> import numpy as np
>>> m = Mesh(np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], np.float32),
...          np.array([[0, 1, 2]], np.uint32))
>>> m.n_vertices, m.n_triangles
(3, 1)
>>> m.normals[0].tolist()
[0.0, 0.0, 1.0]
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field, replace

import numpy as np

__all__ = ["Material", "MaterialImages", "Mesh", "Scene", "with_images"]


@dataclass(frozen=True, eq=False)
class MaterialImages:
    """Baked images of a material, as arrays, for the writers that reference images.

    All images share one size and are laid over the mesh's ``uvs`` (``v = 0`` the first
    row: glTF's and Pillow's convention, top row first, with ``v`` growing down the image).

    Attributes
    ----------
    base_color : uint8[h, w, 4]
        sRGB colour with a linear alpha (a leaf's outline: 0 outside the blade).
    normal : uint8[h, w, 3] or None
        Tangent-space normal map, ``(n + 1) / 2 · 255`` (OpenGL/glTF convention, +Y up).
    roughness : uint8[h, w] or None
        Linear roughness, 0 smooth … 255 rough.
    name : str
        A stem for the image files (``<name>_color.png`` …).
    """

    base_color: np.ndarray
    normal: np.ndarray | None = None
    roughness: np.ndarray | None = None
    name: str = "texture"

    def __post_init__(self) -> None:
        from ..errors import SylvaError

        bc = np.ascontiguousarray(self.base_color, dtype=np.uint8)
        if bc.ndim != 3 or bc.shape[2] != 4 or bc.shape[0] < 1 or bc.shape[1] < 1:
            raise SylvaError(f"base_color: expected uint8[h, w, 4], got shape {bc.shape}")
        object.__setattr__(self, "base_color", bc)
        if self.normal is not None:
            n = np.ascontiguousarray(self.normal, dtype=np.uint8)
            if n.shape != bc.shape[:2] + (3,):
                raise SylvaError(f"normal: expected uint8{list(bc.shape[:2]) + [3]}, "
                                 f"got shape {n.shape}")  # fmt: skip
            object.__setattr__(self, "normal", n)
        if self.roughness is not None:
            r = np.ascontiguousarray(self.roughness, dtype=np.uint8)
            if r.shape != bc.shape[:2]:
                raise SylvaError(f"roughness: expected uint8{list(bc.shape[:2])}, "
                                 f"got shape {r.shape}")  # fmt: skip
            object.__setattr__(self, "roughness", r)

    @property
    def size(self) -> tuple[int, int]:
        """``(width, height)`` in pixels."""
        return int(self.base_color.shape[1]), int(self.base_color.shape[0])

    @property
    def has_alpha(self) -> bool:
        """Whether any pixel is not fully opaque (a cut-out)."""
        return bool((self.base_color[:, :, 3] < 255).any())


@dataclass(frozen=True)
class Material:
    """A surface description shared by exporters and the renderer.

    Attributes
    ----------
    name : str
        Unique key in the scene's material table.
    color : tuple of 4 float
        Base colour, linear RGBA in [0, 1].
    roughness, metallic : float
        PBR factors (exporters that know them write them; Phong maps roughness to shininess).
    texture : str or None
        Name of a procedural texture (``"bark"``, ``"leaf"``, ``"grass"`` …) or an image path.
    double_sided : bool
        Leaves and flat polygons are double-sided.
    alpha_cutoff : float or None
        Alpha-test threshold (billboards, textured leaves).
    billboard : bool
        Seed 002's billboard flag: each connected piece of the surface (a leaf) turns its
        front toward the camera about its centre.  The renderer does this; formats without
        such a flag write the surface as modelled and say it where they can (glTF material
        ``extras.billboard``, USD ``sylva:billboard``; see :mod:`sylva.geometry.lod`).
    images : MaterialImages or None
        Baked images (base colour, normal, roughness) that writers which carry images
        reference instead of :attr:`color` (see :func:`with_images`); not compared.
    """

    name: str
    color: tuple[float, float, float, float] = (0.8, 0.8, 0.8, 1.0)
    roughness: float = 0.8
    metallic: float = 0.0
    texture: str | None = None
    double_sided: bool = False
    alpha_cutoff: float | None = None
    billboard: bool = False
    images: MaterialImages | None = field(default=None, compare=False, repr=False)


def with_images(material: Material, base_color, normal=None, roughness=None, *,
                alpha_cutoff: float | None = 0.5) -> Material:
    """``material`` carrying baked images: an RGBA colour image, and optionally a normal map
    and a roughness map of the same size (see :class:`MaterialImages` for the layouts).

    The image carries the colour: writers that reference it write a white colour factor
    (glTF multiplies ``baseColorFactor`` by the texture), while the material's
    :attr:`~Material.color`, kept, is what writers without images (PLY, STL, OpenSCAD) and
    the renderer's procedural textures use.  When the image has transparent pixels (a
    leaf's outline, an impostor) the material gets ``alpha_cutoff`` and is double-sided.

    Examples
    --------
    >>> import numpy as np
    >>> rgba = np.zeros((4, 4, 4), np.uint8); rgba[1:3, 1:3] = 255
    >>> m = with_images(Material("card", (0.2, 0.5, 0.1, 1.0)), rgba)
    >>> m.images.size, m.alpha_cutoff, m.double_sided, m.color
    ((4, 4), 0.5, True, (0.2, 0.5, 0.1, 1.0))
    """
    imgs = MaterialImages(base_color, normal, roughness, name=material.name)
    cut = alpha_cutoff if imgs.has_alpha else material.alpha_cutoff
    return replace(material, images=imgs, alpha_cutoff=cut,
                   double_sided=material.double_sided or cut is not None)


def _face_normals(vertices: np.ndarray, indices: np.ndarray) -> np.ndarray:
    tri = vertices[indices]
    n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    return n


def vertex_normals(vertices: np.ndarray, indices: np.ndarray) -> np.ndarray:
    """Area-weighted vertex normals, ``float32[n, 3]`` (zero-area fans give +Z)."""
    fn = _face_normals(vertices.astype(np.float64), indices)
    vn = np.zeros((vertices.shape[0], 3), np.float64)
    for k in range(3):
        np.add.at(vn, indices[:, k], fn)
    length = np.linalg.norm(vn, axis=1, keepdims=True)
    out = np.where(length > 1e-20, vn / np.where(length > 1e-20, length, 1.0), [0.0, 0.0, 1.0])
    return out.astype(np.float32)


@dataclass
class Mesh:
    """Indexed triangles with per-vertex attributes.

    Attributes
    ----------
    vertices : float32[n, 3]
    indices : uint32[m, 3]
        Counter-clockwise triangles seen from outside (right-handed, Y up).
    normals : float32[n, 3]
        Unit normals; computed from the triangles when not given.
    uvs : float32[n, 2] or None
        Texture coordinates (for branches: u around, v along the length).
    colors : float32[n, 4] or None
        Linear RGBA vertex colours.
    material_ids : int32[m] or None
        Index into :attr:`materials` per triangle (0 when absent).
    materials : list of Material
        The materials the indices refer to.
    attributes : dict of str to float32[n, k], optional
        Extra per-vertex data that exporters write as custom attributes (glTF
        ``_NAME``), e.g. ``"WIND"``: the wind data of :mod:`sylva.geometry.lod`.
    """

    vertices: np.ndarray
    indices: np.ndarray
    normals: np.ndarray | None = None
    uvs: np.ndarray | None = None
    colors: np.ndarray | None = None
    material_ids: np.ndarray | None = None
    materials: list[Material] = field(default_factory=lambda: [Material("default")])
    name: str = "mesh"
    attributes: dict[str, np.ndarray] | None = None

    def __post_init__(self) -> None:
        self.vertices = np.ascontiguousarray(self.vertices, dtype=np.float32).reshape(-1, 3)
        self.indices = np.ascontiguousarray(self.indices, dtype=np.uint32).reshape(-1, 3)
        if self.normals is None:
            self.normals = vertex_normals(self.vertices, self.indices)
        else:
            self.normals = np.ascontiguousarray(self.normals, dtype=np.float32).reshape(-1, 3)
        if self.uvs is not None:
            self.uvs = np.ascontiguousarray(self.uvs, dtype=np.float32).reshape(-1, 2)
        if self.colors is not None:
            c = np.asarray(self.colors, dtype=np.float32)
            if c.ndim == 2 and c.shape[1] == 3:
                c = np.concatenate([c, np.ones((c.shape[0], 1), np.float32)], axis=1)
            self.colors = np.ascontiguousarray(c).reshape(-1, 4)
        if self.material_ids is not None:
            self.material_ids = np.ascontiguousarray(self.material_ids, dtype=np.int32).ravel()
        if self.attributes:
            n = self.vertices.shape[0]
            self.attributes = {
                str(k): np.ascontiguousarray(v, dtype=np.float32).reshape(n, -1)
                for k, v in self.attributes.items()
            }
        else:
            self.attributes = None

    @property
    def n_vertices(self) -> int:
        return int(self.vertices.shape[0])

    @property
    def n_triangles(self) -> int:
        return int(self.indices.shape[0])

    def bounds(self) -> np.ndarray:
        """``float32[2, 3]``: the minimum and maximum corner (zeros for an empty mesh)."""
        if self.n_vertices == 0:
            return np.zeros((2, 3), np.float32)
        return np.stack([self.vertices.min(axis=0), self.vertices.max(axis=0)])

    def triangle_materials(self) -> np.ndarray:
        """``int32[m]`` material index of every triangle."""
        if self.material_ids is None:
            return np.zeros(self.n_triangles, np.int32)
        return self.material_ids

    @staticmethod
    def merge(meshes: Sequence[Mesh], name: str = "mesh") -> Mesh:
        """One mesh holding all of ``meshes``; materials are unified by name."""
        meshes = [m for m in meshes if m.n_vertices]
        if not meshes:
            return Mesh(np.zeros((0, 3)), np.zeros((0, 3)), name=name)
        table: dict[str, int] = {}
        materials: list[Material] = []
        verts, idx, nrm, uvs, cols, mids = [], [], [], [], [], []
        base = 0
        any_uv = any(m.uvs is not None for m in meshes)
        any_col = any(m.colors is not None for m in meshes)
        extra: dict[str, int] = {}
        for m in meshes:
            for k, v in (m.attributes or {}).items():
                extra[k] = max(extra.get(k, 0), v.shape[1])
        attrs: dict[str, list] = {k: [] for k in extra}
        for m in meshes:
            remap = np.empty(len(m.materials), np.int32)
            for k, mat in enumerate(m.materials):
                if mat.name not in table:
                    table[mat.name] = len(materials)
                    materials.append(mat)
                remap[k] = table[mat.name]
            verts.append(m.vertices)
            nrm.append(m.normals)
            idx.append(m.indices + np.uint32(base))
            if any_uv:
                uvs.append(m.uvs if m.uvs is not None else np.zeros((m.n_vertices, 2), np.float32))
            if any_col:
                cols.append(
                    m.colors if m.colors is not None else np.ones((m.n_vertices, 4), np.float32)
                )
            mids.append(remap[m.triangle_materials()])
            for k, width in extra.items():
                a = (m.attributes or {}).get(k)
                z = np.zeros((m.n_vertices, width), np.float32)
                if a is not None:
                    z[:, : a.shape[1]] = a
                attrs[k].append(z)
            base += m.n_vertices
        return Mesh(
            np.concatenate(verts),
            np.concatenate(idx),
            normals=np.concatenate(nrm),
            uvs=np.concatenate(uvs) if any_uv else None,
            colors=np.concatenate(cols) if any_col else None,
            material_ids=np.concatenate(mids),
            materials=materials,
            name=name,
            attributes={k: np.concatenate(v) for k, v in attrs.items()} or None,
        )


@dataclass
class Scene:
    """Meshes to export or render together (each may have a transform-free placement)."""

    meshes: list[Mesh] = field(default_factory=list)
    name: str = "scene"

    def __init__(self, meshes: Iterable[Mesh] = (), name: str = "scene") -> None:
        self.meshes = list(meshes)
        self.name = name

    def add(self, mesh: Mesh) -> Scene:
        self.meshes.append(mesh)
        return self

    def bounds(self, skip: Iterable[str] = ()) -> np.ndarray:
        """``float32[2, 3]``: the box of the meshes, except those named in ``skip`` (e.g.
        ``("background",)``: the plant without a cpfg background scene)."""
        skip = set(skip)
        boxes = [m.bounds() for m in self.meshes if m.n_vertices and m.name not in skip]
        if not boxes:
            return np.zeros((2, 3), np.float32)
        b = np.stack(boxes)
        return np.stack([b[:, 0].min(axis=0), b[:, 1].max(axis=0)])

    def merged(self) -> Mesh:
        return Mesh.merge(self.meshes, name=self.name)

    @property
    def n_triangles(self) -> int:
        return sum(m.n_triangles for m in self.meshes)
