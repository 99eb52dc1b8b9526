"""A POV-Ray 3.7 scene: ``mesh2`` objects, a camera framing the plant, lights (seed 002's
second back end, which wrote "a textual scene description for POV-Ray").

POV-Ray is left-handed with +Y up; sylva is right-handed with +Y up, so z is negated (in
points and normals).  Each (mesh, material) becomes a ``mesh2`` with its vertex, normal and
uv vectors and a texture from the material; vertex colours (the tint times the material
colour, :func:`~._common.shaded_colors`) become a ``texture_list`` of the distinct colours,
referenced per vertex.  A material with baked images (written beside a path target) is a
``uv_mapping`` ``image_map`` pigment instead (uvs as ``u, 1 - v``: POV-Ray's ``v`` runs up
the image).  Render with ``povray +Iplant.pov +W800 +H600``.

Examples
--------
>>> import io, numpy as np
>>> from sylva.geometry.mesh import Mesh
>>> m = Mesh(np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]]), np.array([[0, 1, 2]]))
>>> out = io.StringIO(); write_pov(m, out)
>>> "mesh2" in out.getvalue() and "camera" in out.getvalue()
True
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
    rows,
    shaded_colors,
    target_path,
)
from ._textures import scene_images, stem_of, v_up, write_companions

__all__ = ["write_pov"]


def write_pov(
    scene,
    target: PathOrFile,
    *,
    background: tuple[float, float, float] = (1.0, 1.0, 1.0),
    camera_angle: float = 35.0,
) -> None:
    """Write a POV-Ray scene to a path or a text file object."""
    scene = as_scene(scene)
    lo, hi = scene.bounds().astype(np.float64)
    center = (lo + hi) / 2.0
    radius = max(float(np.linalg.norm(hi - lo)) / 2.0, 1e-6)
    if scene.n_triangles == 0:  # nothing to draw: POV-Ray refuses a camera at its look_at
        center, radius = np.zeros(3), 1.0
    dist = radius / np.tan(np.radians(camera_angle) / 2.0) * 1.1
    cx, cy, cz = center[0], center[1], -center[2]
    images = {}
    with contextlib.ExitStack() as stack:
        if isinstance(target, (str, os.PathLike)):
            images = scene_images(scene, stem_of(target_path(target)))
        if images:  # the images beside, appearing with the scene (the scene last)
            group = stack.enter_context(AtomicGroup())
            write_companions(group, os.path.dirname(os.fspath(target)), images)
            fh = stack.enter_context(group.open(target, "w", main=True))
        else:
            fh = stack.enter_context(open_target(target, binary=False))
        w = fh.write
        w(f"// sylva: {scene.name}\n#version 3.7;\nglobal_settings {{ assumed_gamma 1.0 }}\n")
        r, g, b = background
        w(f"background {{ rgb <{r:.4g},{g:.4g},{b:.4g}> }}\n")
        w(
            f"camera {{ location <{cx:.6g},{cy + 0.2 * dist:.6g},{cz - dist:.6g}> "
            f"look_at <{cx:.6g},{cy:.6g},{cz:.6g}> angle {camera_angle:.6g} }}\n"
        )
        w(
            f"light_source {{ <{cx + dist:.6g},{cy + 2 * dist:.6g},{cz - dist:.6g}> "
            "color rgb <1,1,1> }\n"
        )
        w(f"light_source {{ <{cx - dist:.6g},{cy + dist:.6g},{cz - dist:.6g}> "
          "color rgb <0.35,0.35,0.4> shadowless }\n")  # fmt: skip
        for mesh in scene.meshes:
            shaded = shaded_colors(mesh) if mesh.colors is not None else None
            for mid, tris in material_groups(mesh):
                idx = mesh.indices[tris]
                used, inv = np.unique(idx, return_inverse=True)
                faces = inv.reshape(-1, 3)
                p = mesh.vertices[used].astype(np.float64)
                p[:, 2] *= -1.0
                nrm = mesh.normals[used].astype(np.float64)
                nrm[:, 2] *= -1.0
                mat = material_of(mesh, mid)
                finish = (
                    f"finish {{ diffuse 0.75 specular {max(0.0, 1 - mat.roughness) * 0.5:.3g} }}"
                )
                w(f"// {mesh.name} / {mat.name}\nmesh2 {{\n")
                w(
                    f"  vertex_vectors {{ {len(p)},\n"
                    + rows("  <%.7g,%.7g,%.7g>,", p)[:-2]
                    + "\n  }\n"
                )
                w(
                    f"  normal_vectors {{ {len(p)},\n"
                    + rows("  <%.5g,%.5g,%.5g>,", nrm)[:-2]
                    + "\n  }\n"
                )
                if mesh.uvs is not None:
                    uv = v_up(mesh.uvs[used])
                    w(f"  uv_vectors {{ {len(p)},\n" + rows("  <%.6g,%.6g>,", uv)[:-2] + "\n  }\n")
                files = images.get(mat.name) if mesh.uvs is not None else None
                if files:
                    w(f"  face_indices {{ {len(faces)},\n"
                      + rows("  <%d,%d,%d>,", faces)[:-2] + "\n  }\n")  # fmt: skip
                    w(f'  texture {{ uv_mapping pigment {{ image_map {{ png "{files["color"][0]}" '
                      f"interpolate 2 }} }} {finish} }}\n")  # fmt: skip
                elif shaded is not None:
                    cols = shaded[used, :3]
                    uniq, cidx = np.unique(np.round(cols, 3), axis=0, return_inverse=True)
                    cidx = cidx.reshape(-1)
                    w(f"  texture_list {{ {len(uniq)},\n")
                    for c in uniq.tolist():
                        w(f"    texture {{ pigment {{ rgb <{c[0]:.4g},{c[1]:.4g},{c[2]:.4g}> }} "
                          f"{finish} }}\n")  # fmt: skip
                    w("  }\n")
                    fi = np.concatenate([faces, cidx[faces]], axis=1)
                    w(f"  face_indices {{ {len(faces)},\n"
                      + rows("  <%d,%d,%d>,%d,%d,%d,", fi)[:-2] + "\n  }\n")  # fmt: skip
                else:
                    w(f"  face_indices {{ {len(faces)},\n"
                      + rows("  <%d,%d,%d>,", faces)[:-2] + "\n  }\n")  # fmt: skip
                    r, g, b, a = (float(x) for x in mat.color)
                    w(f"  texture {{ pigment {{ rgbt <{r:.4g},{g:.4g},{b:.4g},{1 - a:.4g}> }} "
                      f"{finish} }}\n")  # fmt: skip
                w("}\n")
