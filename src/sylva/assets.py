"""Baking: the procedural materials the renderer draws, as images that travel with an export.

The renderer draws bark, leaves and grass with GLSL functions of the texture coordinates
(``render/shaders/textures.glsl``).  Bark and leaf are texture graphs
(:mod:`sylva.texture.graph.surface`): the renderer runs their GLSL and :func:`bake_scene`
evaluates the same graphs over the unit square of uv with the fused CPU kernel; grass is
baked from its GLSL on the renderer's OpenGL context.  The result goes
into each material as :class:`~sylva.geometry.mesh.MaterialImages`: a base colour (sRGB,
with a leaf's outline as alpha), a tangent-space normal map from the pattern's relief and a
roughness map from its specular map.  The writers of :mod:`sylva.geometry.exchange` that
can carry images (glTF, OBJ/MTL, USD, POV-Ray) then reference them.

Bark lives in stem coordinates (``u`` around, ``v`` along in circumferences of the stem's
base radius) on lattices that repeat once per unit of ``u`` and ``v``: the baked bark tiles
around and along every stem, and its grain follows each stem's radius.  A leaf's alpha is
the outline of its blade in uv: the union of the uv triangles of the faces that use the
leaf material, so a blade keeps its shape whatever the leaf geometry is.

This module sits above ``geometry``, ``texture`` and ``render`` (it may import them all);
the exporters never import it.

Examples
--------
>>> from sylva.geometry.mesh import Material
>>> m = bake_material(Material("bark", (0.3, 0.22, 0.15, 1.0), texture="bark"), 16)
>>> m.images.size, m.images.normal.shape, m.color == (0.3, 0.22, 0.15, 1.0)
((16, 16), (16, 16, 3), True)
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np

from .errors import SylvaError
from .geometry.mesh import Material, Scene, with_images

__all__ = [
    "BAKED_TEXTURES",
    "IMAGE_FORMATS",
    "TEXTURE_SIZES",
    "bake_material",
    "bake_scene",
    "check_texture_size",
    "leaf_coverage",
    "textured_export",
]

#: The procedural textures baked, by ``Material.texture`` name (the renderer's kinds).
BAKED_TEXTURES = {"bark": 2, "leaf": 3, "grass": 4}

#: Allowed image sizes: powers of two (mipmapped, repeat-wrapped textures in every engine).
TEXTURE_SIZES = tuple(2**k for k in range(3, 13))

#: The export formats that reference images (the others carry colours only).
IMAGE_FORMATS = ("glb", "gltf", "obj", "usd", "usda", "usdc", "pov")

#: Relief depth of the normal maps, in units of the tile (a groove of 1 % of the tile).
NORMAL_DEPTH = {"bark": 0.006, "leaf": 0.004, "grass": 0.0}


def check_texture_size(size, option: str = "size") -> int:
    """``size`` as an int, or a SylvaError naming ``option`` and the allowed sizes.

    >>> check_texture_size("256")
    256
    >>> check_texture_size(300, "--textures")
    Traceback (most recent call last):
    ...
    sylva.errors.SylvaError: --textures: expected a power of two from 8 to 4096, got 300
    """
    try:
        value = int(str(size).strip())
    except ValueError:
        value = None
    if value is None or value not in TEXTURE_SIZES:
        raise SylvaError(f"{option}: expected a power of two from {TEXTURE_SIZES[0]} to "
                         f"{TEXTURE_SIZES[-1]}, got {size}")  # fmt: skip
    return value


# --------------------------------------------------------------------------- GL baking
def _bake_fields(kind: int, color, size: int) -> tuple[np.ndarray, np.ndarray]:
    """``(rgba float32[size, size, 4], height float32[size, size])``: linear albedo and
    specular map, and relief, row ``j`` at ``v = (j + 0.5) / size``."""
    import moderngl

    from .render._programs import compile_program
    from .render.context import get_context

    ctx = get_context()
    prog = compile_program(ctx, "bake.vert.glsl", "bake.frag.glsl",
                           defines=(f"TEXTURE_KIND {kind}",))  # fmt: skip
    prog["u_color"].value = tuple(float(c) for c in color[:3])
    prog["u_size"].value = (float(size), float(size))
    quad = np.array([[-1, -1], [1, -1], [-1, 1], [1, 1]], np.float32)
    vbo = ctx.buffer(quad.tobytes())
    vao = ctx.vertex_array(prog, [(vbo, "2f", "in_position")])
    targets = [ctx.texture((size, size), 4, dtype="f4") for _ in range(2)]
    fbo = ctx.framebuffer(color_attachments=targets)
    try:
        fbo.use()
        ctx.viewport = (0, 0, size, size)
        ctx.disable(moderngl.BLEND | moderngl.DEPTH_TEST)
        vao.render(moderngl.TRIANGLE_STRIP)
        rgba = np.frombuffer(fbo.read(components=4, attachment=0, dtype="f4"), np.float32)
        hgt = np.frombuffer(fbo.read(components=4, attachment=1, dtype="f4"), np.float32)
    finally:
        for obj in (fbo, *targets, vao, vbo, prog):
            obj.release()
    return rgba.reshape(size, size, 4).copy(), hgt.reshape(size, size, 4)[:, :, 0].copy()


def _surface_fields(tex: str, color, size: int) -> tuple[np.ndarray, np.ndarray]:
    """:func:`_bake_fields` of bark and leaf on the CPU: their texture graphs
    (:mod:`sylva.texture.graph.surface`, whose GLSL the renderer runs) at the pixel centres,
    combined with the material's colour as ``textures.glsl``'s ``sylva_bark`` and
    ``sylva_leaf`` combine them."""
    from .texture.graph.surface import bake_surface

    t = bake_surface(tex, size)
    base = np.asarray(color[:3], np.float64)
    rgba = np.empty((size, size, 4), np.float32)
    if tex == "bark":
        rgba[:, :, :3] = base * t[:, :, :1]
        rgba[:, :, 3] = t[:, :, 1]
        return rgba, t[:, :, 2].astype(np.float32)
    bright = np.minimum(base * 1.7 + (0.06, 0.07, 0.03), 1.0)
    dark = base * t[:, :, :1]
    rgba[:, :, :3] = dark + t[:, :, 1:2] * (bright - dark)
    rgba[:, :, 3] = t[:, :, 2]
    return rgba, t[:, :, 3].astype(np.float32)


def _srgb(linear: np.ndarray) -> np.ndarray:
    """uint8 sRGB of linear values in [0, 1] (the renderer's gamma: 2.2)."""
    return np.round(np.clip(linear, 0.0, 1.0) ** (1.0 / 2.2) * 255.0).astype(np.uint8)


def _normal_map(height: np.ndarray, depth: float) -> np.ndarray:
    """Tangent-space normals of a periodic relief (``depth``: its amplitude in tile units),
    glTF's convention: red +u, green up the image (towards smaller ``v``), blue out."""
    n = height.shape[0]
    # central differences per unit of uv; the relief is periodic (np.roll wraps)
    du = (np.roll(height, -1, axis=1) - np.roll(height, 1, axis=1)) * (n / 2.0)
    dv = (np.roll(height, -1, axis=0) - np.roll(height, 1, axis=0)) * (n / 2.0)
    v = np.stack([-depth * du, depth * dv, np.ones_like(height)], axis=-1)
    v /= np.linalg.norm(v, axis=-1, keepdims=True)
    return np.round((v + 1.0) * 127.5).clip(0, 255).astype(np.uint8)


def leaf_coverage(meshes, name: str, size: int) -> np.ndarray | None:
    """``bool[size, size]``: the pixels of the uv square covered by the triangles (in uv)
    of the faces of ``meshes`` whose material is ``name`` — a leaf blade's outline —
    grown by one pixel so that filtering never eats the edge; None when no such face has
    uvs.  Row ``j`` is at ``v = (j + 0.5) / size``."""
    tris = []
    for mesh in meshes:
        if mesh.uvs is None or mesh.n_triangles == 0:
            continue
        ids = [k for k, m in enumerate(mesh.materials) if m.name == name]
        if not ids:
            continue
        sel = np.isin(mesh.triangle_materials(), ids)
        if sel.any():
            tris.append(mesh.uvs[mesh.indices[sel]].astype(np.float64))
    if not tris:
        return None
    t = np.concatenate(tris)
    # every leaf shares its template's uvs: rasterize each distinct triangle once
    t = np.unique(np.round(t.reshape(-1, 6), 5), axis=0).reshape(-1, 3, 2)
    if len(t) > 4096:  # uvs of a general mesh, not a leaf template: no outline to cut
        return None
    c = (np.arange(size) + 0.5) / size
    px, py = np.meshgrid(c, c)  # px: u (columns), py: v (rows)
    mask = np.zeros((size, size), bool)
    for (ax, ay), (bx, by), (cx, cy) in t:
        det = (bx - ax) * (cy - ay) - (cx - ax) * (by - ay)
        if abs(det) < 1e-12:
            continue
        lo_x, hi_x = min(ax, bx, cx), max(ax, bx, cx)
        lo_y, hi_y = min(ay, by, cy), max(ay, by, cy)
        j0, j1 = max(int(lo_y * size) - 1, 0), min(int(hi_y * size) + 2, size)
        i0, i1 = max(int(lo_x * size) - 1, 0), min(int(hi_x * size) + 2, size)
        if j0 >= j1 or i0 >= i1:
            continue
        x, y = px[j0:j1, i0:i1], py[j0:j1, i0:i1]
        w1 = ((x - ax) * (cy - ay) - (cx - ax) * (y - ay)) / det
        w2 = ((bx - ax) * (y - ay) - (x - ax) * (by - ay)) / det
        eps = 1.0 / size  # about a pixel of slack: a point on the edge counts
        mask[j0:j1, i0:i1] |= (w1 >= -eps) & (w2 >= -eps) & (w1 + w2 <= 1 + eps)
    grown = mask.copy()  # one pixel wider (not wrapped: a blade does not tile)
    grown[1:] |= mask[:-1]
    grown[:-1] |= mask[1:]
    grown[:, 1:] |= mask[:, :-1]
    grown[:, :-1] |= mask[:, 1:]
    return grown


def _image_material(material: Material, path: Path) -> Material:
    from PIL import Image

    with Image.open(path) as im:
        rgba = np.asarray(im.convert("RGBA"))
    return with_images(material, rgba, alpha_cutoff=material.alpha_cutoff or 0.5)


def bake_material(material: Material, size: int = 256, *, coverage=None) -> Material:
    """``material`` with baked images, when its ``texture`` is a procedural texture the
    renderer draws (``bark``, ``leaf``, ``grass``) or an image file; else unchanged.

    Parameters
    ----------
    material : Material
    size : int
        Width and height of the images, a power of two (see :func:`check_texture_size`).
    coverage : bool[size, size] or None
        The alpha of the colour image (a leaf's outline, :func:`leaf_coverage`); None:
        opaque.

    Returns
    -------
    Material
        The same material (colour, roughness and texture name kept, for the renderer and
        the writers without images) carrying :class:`~sylva.geometry.mesh.MaterialImages`.
    """
    size = check_texture_size(size)
    tex = material.texture
    if tex is None:
        return material
    kind = BAKED_TEXTURES.get(tex)
    if kind is None:
        path = Path(tex)
        if path.suffix.lower() in (".png", ".jpg", ".jpeg") and path.is_file():
            return _image_material(material, path)
        return material
    if tex in ("bark", "leaf"):  # texture graphs, baked by the CPU kernel
        rgba, height = _surface_fields(tex, material.color, size)
    else:
        rgba, height = _bake_fields(kind, material.color, size)
    alpha = np.full((size, size), 255, np.uint8)
    if coverage is not None:
        alpha = np.where(coverage, 255, 0).astype(np.uint8)
    base = np.concatenate([_srgb(rgba[:, :, :3]), alpha[:, :, None]], axis=2)
    # the renderer's specular strength is (1 - roughness) * spec map: the same as roughness
    rough = 1.0 - (1.0 - float(material.roughness)) * np.clip(rgba[:, :, 3], 0.0, 1.0)
    rough8 = np.round(np.clip(rough, 0.0, 1.0) * 255.0).astype(np.uint8)
    depth = NORMAL_DEPTH.get(tex, 0.0)
    normal = _normal_map(height, depth) if depth > 0 else None
    return with_images(material, base, normal, rough8, alpha_cutoff=0.5)


def bake_scene(scene: Scene, size: int = 256) -> Scene:
    """``scene`` with every textured material baked (:func:`bake_material`; a material
    shared by several meshes is baked once, a leaf's alpha is its blades' outline).

    The meshes keep their arrays (nothing is copied); only their material lists change.

    Examples
    --------
    >>> import numpy as np
    >>> from sylva.geometry.mesh import Mesh
    >>> leaf = Material("leaf", (0.2, 0.5, 0.1, 1.0), texture="leaf", double_sided=True)
    >>> m = Mesh(np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]]), np.array([[0, 1, 2]]),
    ...          uvs=np.array([[0.5, 0], [1, 1], [0, 1]]), materials=[leaf])
    >>> baked = bake_scene(Scene([m]), 16)
    >>> img = baked.meshes[0].materials[0].images
    >>> bool(img.base_color[0, 0, 3] == 0 and img.base_color[12, 8, 3] == 255)
    True
    """
    size = check_texture_size(size)
    done: dict[str, Material] = {}
    meshes = []
    for mesh in scene.meshes:
        mats = []
        for mat in mesh.materials:
            if mat.name not in done:
                cov = None
                if mat.texture == "leaf" or (mat.alpha_cutoff is not None and mat.texture):
                    cov = leaf_coverage(scene.meshes, mat.name, size)
                done[mat.name] = bake_material(mat, size, coverage=cov)
            mats.append(done[mat.name])
        meshes.append(replace(mesh, materials=mats))
    return Scene(meshes, name=scene.name)


def textured_export(scene: Scene, fmt: str, size, option: str = "--textures") -> Scene:
    """``scene`` baked for an export to ``fmt`` at ``size`` (the CLI's ``--textures``):
    a SylvaError naming ``option`` for a bad size or a format that carries no images."""
    size = check_texture_size(size, option)
    if fmt not in IMAGE_FORMATS:
        raise SylvaError(f"{option}: {fmt.upper()} files carry no images; write one of "
                         + ", ".join("." + f for f in IMAGE_FORMATS) + " (or leave "
                         f"{option} out)")  # fmt: skip
    return bake_scene(scene, size)
