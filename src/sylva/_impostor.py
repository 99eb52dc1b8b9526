"""Impostors: a plant baked from several sides into an atlas and drawn on crossed quads.

The last level of detail of a plant (seed 002 §3.2: "several crossed billboards that are
not turned toward the viewer give an illusion of volume").  :func:`bake_impostor`
renders the plant offscreen with sylva's renderer (orthographic, no ground, transparent
background) from ``views`` directions spread over 180° about the vertical axis, each
into one tile of an atlas:

* ``color`` ``uint8[h, views·w, 4]``: the unlit albedo (sRGB) and the coverage as alpha;
* ``normal`` ``uint8[h, views·w, 3]``: the surface normal in the tile's tangent space
  (x right, y up, z toward the viewer, each ``(n + 1) / 2``; the glTF normal-map
  convention), so engines light the impostor as they light the plant.

Each view becomes a double-sided quad through the plant's vertical axis, facing that
view, textured with its tile (alpha-tested at 0.5); two views give the classic cross.
Row 0 of an atlas is its top; the quads' ``v`` runs up (sylva's and OpenGL's
convention), and writers that use the other (glTF) flip the image.

Examples
--------
>>> import numpy as np
>>> from sylva.geometry.mesh import Mesh, Scene
>>> tri = Mesh(np.array([[-1, 0, 0], [1, 0, 0], [0, 2, 0]]), np.array([[0, 1, 2]]))
>>> imp = bake_impostor(Scene([tri]), views=2, size=32)
>>> imp.scene.n_triangles, imp.color.shape
(4, (32, 64, 4))
"""

from __future__ import annotations

import dataclasses
import os
from dataclasses import dataclass

import numpy as np

from .geometry.exchange.gltf_lod import png_bytes
from .geometry.lod import LodChain, LodError, LodLevel, wind_attribute
from .geometry.mesh import Material, Mesh, Scene

__all__ = ["Impostor", "add_impostor", "bake_impostor", "png_bytes", "textured_scene",
           "world_impostor"]

#: The impostor material's name (its images are keyed by it).
MATERIAL = "impostor"


@dataclass
class Impostor:
    """A baked impostor.

    Attributes
    ----------
    scene : Scene
        The crossed quads (one mesh, material :data:`MATERIAL`, a ``WIND`` attribute).
    color : uint8[h, w, 4]
    normal : uint8[h, w, 3]
    yaws : list of float
        The view of each tile, degrees about +Y.
    """

    scene: Scene
    color: np.ndarray
    normal: np.ndarray
    yaws: list

    def images(self) -> dict:
        return {MATERIAL: {"color": self.color, "normal": self.normal}}


def _check(views, size) -> tuple[int, int]:
    try:
        v, s = int(views), int(size)
    except (TypeError, ValueError):
        raise LodError(f"impostor: views and size must be whole numbers, got {views!r}, "
                       f"{size!r}") from None
    if not 1 <= v <= 16:
        raise LodError(f"impostor views: expected 1…16, got {v}")
    if not 8 <= s <= 4096:
        raise LodError(f"impostor size: expected 8…4096 pixels, got {s}")
    return v, s


def _normal_scene(scene: Scene, right, up, back) -> Scene:
    """The scene with every surface white and its tangent-space normal as vertex colour
    (pre-distorted so that the renderer's unlit sRGB output is the linear encoding)."""
    basis = np.stack([right, up, back], axis=1)
    out = []
    for m in scene.meshes:
        n = m.normals.astype(np.float64) @ basis
        n[n[:, 2] < 0] *= -1.0  # double-sided leaves: the side toward the viewer
        enc = np.clip((n + 1.0) / 2.0, 0.0, 1.0) ** 2.2
        mats = [Material(f"n_{k}", color=(1, 1, 1, 1), double_sided=True,
                         alpha_cutoff=mat.alpha_cutoff) for k, mat in enumerate(m.materials)]
        out.append(Mesh(m.vertices, m.indices, normals=m.normals, colors=enc,
                        material_ids=m.material_ids, materials=mats, name=m.name))
    return Scene(out, name=scene.name)


def bake_impostor(scene: Scene, *, views: int = 2, size: int = 256, msaa: int = 4) -> Impostor:
    """Render ``scene`` from ``views`` sides into an atlas and make its crossed quads.

    Parameters
    ----------
    scene : Scene
        The plant (LOD0).
    views : int
        Views (and quads), spread over 180° about +Y (1…16).
    size : int
        Tile height in pixels (the width follows the plant's proportions).
    msaa : int
        Multisampling of the colour pass.
    """
    from .render.camera import Camera
    from .render.offscreen import Renderer

    views, size = _check(views, size)
    b = scene.bounds().astype(np.float64)
    centre = 0.5 * (b[0] + b[1])
    pts = np.concatenate([m.vertices for m in scene.meshes if m.n_vertices]) if any(
        m.n_vertices for m in scene.meshes) else np.zeros((1, 3))
    radius = float(np.max(np.hypot(pts[:, 0] - centre[0], pts[:, 2] - centre[2]))) * 1.02
    height = float(b[1, 1] - b[0, 1]) * 1.02
    radius = max(radius, 1e-3 * max(height, 1e-6), 1e-6)
    height = max(height, 1e-6)
    w = max(8, int(round(size * 2 * radius / height)))
    h = size
    world_h = height
    world_w = world_h * w / h  # the tile's aspect, so that pixels stay square
    r = Renderer.default()
    colors, normals, verts, uvs = [], [], [], []
    yaws = [180.0 * i / views for i in range(views)]
    for i, yaw in enumerate(yaws):
        cam = Camera(mode="orthographic", target=centre, yaw=yaw, pitch=0.0,
                     distance=4.0 * (radius + height), height=world_h)
        right, up, back = (np.asarray(v, np.float64) for v in cam.basis())
        rgba = r.render(scene, (w, h), cam, transparent=True, ground=False, lit=False,
                        shadows=False, msaa=msaa)
        colors.append(rgba)
        nrm = r.render(_normal_scene(scene, right, up, back), (w, h), cam, transparent=True,
                       ground=False, lit=False, shadows=False, msaa=0, textures=False)
        normals.append(nrm[..., :3])
        c = [centre + sx * 0.5 * world_w * right + sy * 0.5 * world_h * up
             for sx, sy in ((-1, -1), (1, -1), (1, 1), (-1, 1))]
        verts.append(np.array(c))
        u0, u1 = i / views, (i + 1) / views
        uvs.append(np.array([[u0, 0], [u1, 0], [u1, 1], [u0, 1]], np.float32))
    color = np.concatenate(colors, axis=1)
    normal = np.concatenate(normals, axis=1)
    # where nothing was drawn the normal map says "toward the viewer"
    normal[color[..., 3] == 0] = (128, 128, 255)
    V = np.concatenate(verts)
    nv = V.shape[0]
    I = (np.array([[0, 1, 2], [0, 2, 3]])[None] + 4 * np.arange(views)[:, None, None])
    bases = [Camera(mode="orthographic", yaw=y).basis() for y in yaws]
    N = np.repeat(np.stack([bs[2] for bs in bases]), 4, axis=0)
    # the tangent runs along u (the view's right); normal × tangent is up (w = +1)
    T = np.repeat(np.stack([np.append(bs[0], 1.0) for bs in bases]), 4, axis=0)
    flex = np.clip((V[:, 1] - b[0, 1]) / height, 0.0, 1.0)
    mat = Material(MATERIAL, color=(1.0, 1.0, 1.0, 1.0), roughness=0.9, double_sided=True,
                   alpha_cutoff=0.5)
    mesh = Mesh(V, I.reshape(-1, 3), normals=N, uvs=np.concatenate(uvs), materials=[mat],
                name="impostor", attributes={"TANGENT": T,
                                             "WIND": wind_attribute(np.zeros(nv), 0.0, flex, 0.0)})
    return Impostor(Scene([mesh], name=scene.name), color, normal, yaws)


def add_impostor(chain: LodChain, *, views: int = 2, size: int = 256,
                 coverage: float | None = None) -> LodChain:
    """``chain`` with an impostor of its LOD0 as a last level (the same object)."""
    from .geometry.lod import COVERAGE

    if coverage is None:
        last = chain.levels[-1].coverage
        coverage = min(COVERAGE[-1], 0.5 * last)
    imp = bake_impostor(chain.levels[0].scene, views=views, size=size)
    chain.levels.append(LodLevel(imp.scene, float(coverage), "impostor", imp.images(),
                                 name=f"LOD{len(chain.levels)}"))
    return chain


def textured_scene(level: LodLevel, folder) -> Scene:
    """An impostor level whose material points at its colour atlas saved in ``folder``
    (so that :func:`sylva.render.render` draws it)."""
    from ._atomic import atomic_write

    out = []
    for m in level.scene.meshes:
        mats = []
        for mat in m.materials:
            img = level.images.get(mat.name)
            if img is not None:
                path = os.path.join(os.fspath(folder), f"{mat.name}_color.png")
                with atomic_write(path, "wb") as fh:
                    fh.write(png_bytes(img["color"]))
                mat = dataclasses.replace(mat, texture=path)
            mats.append(mat)
        out.append(dataclasses.replace(m, materials=mats))
    return Scene(out, name=level.scene.name)


def world_impostor(size: int = 128, views: int = 2):
    """A callback for :func:`sylva.world.export.write_world_glb`'s ``impostor``: bakes a
    plant model and saves its colour atlas in the tiles folder (embedded by the writer)."""
    from ._atomic import atomic_write
    from .geometry.exchange._common import safe_name

    def make(key: str, mesh: Mesh, folder) -> Mesh | None:
        if mesh.n_triangles == 0:
            return None
        imp = bake_impostor(Scene([mesh], name=key), views=views, size=size)
        path = os.path.join(os.fspath(folder), f"impostor_{safe_name(key)}.png")
        with atomic_write(path, "wb") as fh:
            fh.write(png_bytes(imp.color))
        (quads,) = imp.scene.meshes
        mat = dataclasses.replace(quads.materials[0], name=f"impostor_{safe_name(key)}",
                                  texture=path)
        return dataclasses.replace(quads, materials=[mat], name=f"{key}#impostor")

    return make
