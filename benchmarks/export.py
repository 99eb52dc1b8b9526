"""Writing a GLB with levels of detail of the 1 M-segment benchmark plant, against trimesh.

Run: ``python benchmarks/export.py [--segments 1000000] [--detail 8] [--impostor]
[--textures 512]``

The plant is the one of ``benchmarks/mesh.py`` (every X splits into three pitched, rolled
branches; about a million segments).  In one run, after a small warm-up that compiles the
kernels:

* ``lods``: :func:`sylva.geometry.lod.plant_lods` — LOD0 (the tube mesh with ``_WIND``
  data), LOD1 and LOD2 meshed again from the turtle records;
* ``impostor`` (with ``--impostor``): baking the colour + normal atlas of LOD0 offscreen
  (:func:`sylva._impostor.add_impostor`; llvmpipe on a machine without a GPU);
* ``textures`` (with ``--textures SIZE``): baking every mesh level's materials to images
  (:func:`sylva.assets.bake_scene`, what ``sylva export --lod 3 --textures SIZE`` does), so
  that the GLB is textured;
* ``sylva glb``: :func:`~sylva.geometry.exchange.gltf_lod.write_lod_glb` of all the levels
  (``MSFT_lod``), and :func:`~sylva.geometry.exchange.gltf.write_glb` of LOD0 alone;
* ``trimesh glb``: ``trimesh.Trimesh(LOD0's vertices, faces, vertex_normals)``'s
  ``export(file_type="glb")`` of the same untextured mesh (trimesh builds its own
  buffers; the Trimesh is made before the clock starts, with ``process=False``);
* the ratios of the writing times (sylva LOD0 / trimesh: the same mesh; sylva all levels /
  trimesh), and the bytes per triangle of each file.

The figures are wall-clock seconds of one run each (files in a temporary folder).
"""

from __future__ import annotations

import argparse
import importlib.util
import os
import sys
import tempfile
import time
from pathlib import Path


def _mesh_module():
    spec = importlib.util.spec_from_file_location("bench_mesh", Path(__file__).with_name("mesh.py"))
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--segments", type=int, default=1_000_000)
    ap.add_argument("--detail", type=int, default=8)
    ap.add_argument("--impostor", action="store_true", help="bake an impostor level too")
    ap.add_argument("--textures", type=int, default=None, metavar="SIZE",
                    help="bake the materials of every level to SIZE x SIZE images first")
    args = ap.parse_args(argv)
    import trimesh

    from sylva.geometry.exchange.gltf import write_glb
    from sylva.geometry.exchange.gltf_lod import write_lod_glb
    from sylva.geometry.lod import plant_lods
    from sylva.turtle import interpret

    bm = _mesh_module()
    # warm-up: compile the turtle and mesh kernels on a small plant
    plant_lods(interpret(bm.plant_word(2000), dialect="abop", rot=22.5, thick=0.1))
    word = bm.plant_word(args.segments)
    g = interpret(word, dialect="abop", rot=22.5, thick=0.1)
    print(f"plant: {g.n_segments:,} segments, detail {args.detail}")
    t0 = time.perf_counter()
    chain = plant_lods(g, detail=args.detail)
    t_lod = time.perf_counter() - t0
    tris = [lv.n_triangles for lv in chain.levels]
    print(f"lods: {t_lod:.2f} s; triangles " + ", ".join(
        f"LOD{i} {t:,} ({t / tris[0]:.1%})" for i, t in enumerate(tris)))
    if args.impostor:
        from sylva._impostor import add_impostor

        t0 = time.perf_counter()
        add_impostor(chain, size=256)
        print(f"impostor: {time.perf_counter() - t0:.2f} s (256 px views, 2 views)")
    if args.textures:
        from sylva.cli._lod import bake_chain

        t0 = time.perf_counter()
        bake_chain(chain, args.textures)
        print(f"textures: {time.perf_counter() - t0:.2f} s ({args.textures} px, every level)")
    lod0 = chain.levels[0].scene.merged()
    with tempfile.TemporaryDirectory() as tmp:
        paths = {k: os.path.join(tmp, f"{k}.glb") for k in ("lods", "lod0", "trimesh")}
        t0 = time.perf_counter()
        write_lod_glb(chain, paths["lods"])
        t_lods = time.perf_counter() - t0
        t0 = time.perf_counter()
        write_glb(lod0, paths["lod0"])
        t_lod0 = time.perf_counter() - t0
        tm = trimesh.Trimesh(vertices=lod0.vertices, faces=lod0.indices,
                             vertex_normals=lod0.normals, process=False)
        t0 = time.perf_counter()
        data = tm.export(file_type="glb")
        with open(paths["trimesh"], "wb") as fh:
            fh.write(data)
        t_tri = time.perf_counter() - t0
        size = {k: os.path.getsize(p) for k, p in paths.items()}
    total = sum(lv.n_triangles for lv in chain.levels)
    print(f"sylva glb, {len(chain)} levels: {t_lods:.2f} s, {size['lods'] / 1e6:.1f} MB, "
          f"{size['lods'] / total:.1f} bytes/triangle (all levels' triangles)")
    print(f"sylva glb, LOD0 only: {t_lod0:.2f} s, {size['lod0'] / 1e6:.1f} MB, "
          f"{size['lod0'] / tris[0]:.1f} bytes/triangle")
    print(f"trimesh glb, LOD0 (untextured): {t_tri:.2f} s, {size['trimesh'] / 1e6:.1f} MB, "
          f"{size['trimesh'] / tris[0]:.1f} bytes/triangle")
    print(f"ratio sylva/trimesh, same mesh: {t_lod0 / t_tri:.2f}; "
          f"all levels / trimesh's LOD0: {t_lods / t_tri:.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
