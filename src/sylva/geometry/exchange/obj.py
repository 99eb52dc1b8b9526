"""Wavefront OBJ with its MTL material library.

Vertices carry their colour (the vertex tint times the material colour) as the common
``v x y z r g b`` extension when the mesh has vertex colours; ``vt`` (``u, 1 - v``: OBJ's
``v`` runs up the image, sylva's down) and ``vn`` follow;
faces are grouped by ``usemtl``.  Writing to a path also writes ``<stem>.mtl`` beside it
(``mtllib``), and the PNGs of baked material images (``map_Kd``, ``map_d``, ``norm``,
``map_Pr``); writing to a file object writes the MTL to ``mtl_file`` when given (without
images).  OBJ has
no up axis of its own; importers (Blender's among them) assume +Y, sylva's, which
``up="y"`` (the default) keeps; ``up="z"`` rotates to +Z.

Examples
--------
>>> import io, numpy as np
>>> from sylva.geometry.mesh import Mesh
>>> m = Mesh(np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]]), np.array([[0, 1, 2]]))
>>> out = io.StringIO(); write_obj(m, out)
>>> [l for l in out.getvalue().splitlines() if l.startswith("f ")]
['f 1//1 2//2 3//3']
"""

from __future__ import annotations

import contextlib
import os

import numpy as np

from ..._atomic import AtomicGroup
from ._common import (
    PathOrFile,
    as_scene,
    material_groups,
    material_of,
    open_target,
    oriented_scene,
    rows,
    safe_name,
    shaded_colors,
    target_path,
)
from ._textures import mtl_maps, scene_images, stem_of, v_up, write_companions

__all__ = ["mtl_text", "write_obj"]


def mtl_text(scene, images: dict | None = None) -> str:
    """The MTL library of every material in ``scene`` (unique by name).

    ``images``: ``{material name: {slot: (file name, bytes)}}`` of the baked images
    written beside (:func:`._textures.image_files`), referenced as ``map_Kd``, ``map_d``,
    ``norm`` and ``map_Pr``; a textured material's ``Kd`` is white (the image is its
    colour)."""
    scene = as_scene(scene)
    images = images or {}
    seen: dict[str, object] = {}
    for mesh in scene.meshes:
        for mat in mesh.materials:
            seen.setdefault(safe_name(mat.name), mat)
    out = ["# sylva material library"]
    for name, mat in seen.items():
        r, g, b, a = mat.color  # type: ignore[attr-defined]
        files = images.get(mat.name)  # type: ignore[attr-defined]
        if files:
            r = g = b = 1.0
        shininess = max(1.0, (1.0 - float(mat.roughness)) ** 2 * 1000.0)  # type: ignore[attr-defined]
        out += [
            f"newmtl {name}",
            f"Ka {r:.6g} {g:.6g} {b:.6g}",
            f"Kd {r:.6g} {g:.6g} {b:.6g}",
            "Ks 0.04 0.04 0.04",
            f"Ns {shininess:.6g}",
            f"d {a:.6g}",
            "illum 2",
        ]
        if files:
            out += mtl_maps(files)
        elif mat.texture:  # type: ignore[attr-defined]
            out.append(f"# procedural texture: {mat.texture}")  # type: ignore[attr-defined]
        out.append("")
    return "\n".join(out) + "\n"


def write_obj(scene, target: PathOrFile, *, mtl_file=None, up: str = "y") -> None:
    """Write OBJ (text) to a path or a text file object, with an MTL library."""
    scene = oriented_scene(as_scene(scene), up)
    path = target_path(target)
    mtl_name = None
    with contextlib.ExitStack() as stack:
        if path is not None and isinstance(target, (str, os.PathLike)):
            # The .mtl and the .obj appear together or not at all, the .obj last.
            group = stack.enter_context(AtomicGroup())
            mtl_path = os.path.splitext(path)[0] + ".mtl"
            mtl_name = os.path.basename(mtl_path)
            images = scene_images(scene, stem_of(path))
            write_companions(group, os.path.dirname(path), images)
            with group.open(mtl_path, "w") as fh:
                fh.write(mtl_text(scene, images))
            fh = stack.enter_context(group.open(path, "w", main=True))
        else:
            if mtl_file is not None:
                mtl_file.write(mtl_text(scene))
                mtl_name = os.path.basename(getattr(mtl_file, "name", "materials.mtl"))
            fh = stack.enter_context(open_target(target, binary=False))
        _write_obj_body(fh, scene, mtl_name)


def _write_obj_body(fh, scene, mtl_name) -> None:
    fh.write(f"# sylva OBJ: {scene.name}\n")
    if mtl_name:
        fh.write(f"mtllib {mtl_name}\n")
    vbase = 1
    tbase = 1
    for mesh in scene.meshes:
        if mesh.n_vertices == 0:
            continue
        fh.write(f"o {safe_name(mesh.name)}\n")
        if mesh.colors is not None:
            vc = np.concatenate([mesh.vertices, shaded_colors(mesh)[:, :3]], axis=1)
            fh.write(rows("v %.7g %.7g %.7g %.4g %.4g %.4g", vc))
        else:
            fh.write(rows("v %.7g %.7g %.7g", mesh.vertices))
        has_uv = mesh.uvs is not None
        if has_uv:
            fh.write(rows("vt %.6g %.6g", v_up(mesh.uvs)))  # OBJ's v runs up the image
        fh.write(rows("vn %.5g %.5g %.5g", mesh.normals))
        for mid, tris in material_groups(mesh):
            fh.write(f"usemtl {safe_name(material_of(mesh, mid).name)}\n")
            idx = mesh.indices[tris].astype(np.int64) + vbase
            if has_uv:
                rep = idx.repeat(3, axis=1)
                if tbase != vbase:
                    rep[:, 1::3] += tbase - vbase
                fh.write(rows("f %d/%d/%d %d/%d/%d %d/%d/%d", rep))
            else:
                rep = idx.repeat(2, axis=1)
                fh.write(rows("f %d//%d %d//%d %d//%d", rep))
        vbase += mesh.n_vertices
        tbase += mesh.n_vertices if has_uv else 0
