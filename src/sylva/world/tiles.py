"""OGC 3D Tiles 1.1 from a world store: a quadtree of glTF tiles an engine streams.

:func:`write_tileset` writes ``OUT/tileset.json`` and ``OUT/tiles/L/I_J.glb``:

* the **leaves** cover ``leaf_columns`` × ``leaf_columns`` columns each: the terrain skin of
  their chunks at full resolution, and every plant standing on them drawn through
  ``EXT_mesh_gpu_instancing`` (one instanced mesh per plant model, the grass tufts turned
  by their yaw); ``geometricError`` 0;
* each **coarser level** halves the resolution: a tile of level ``L`` (``f = 2^(leaf − L)``
  columns per sample) holds the skin of the store's voxels sampled every ``f`` voxels on
  each axis, scaled back by ``f`` — the same number of voxels as a leaf, over ``f²`` times
  the area — and, given an ``impostor`` baker, the plants at least ``f`` blocks in size
  (their largest extent) as **impostors**: crossed quads textured with the plant baked
  from two sides (:func:`sylva._impostor.world_impostor`; colour and alpha, alpha-tested),
  one ``EXT_mesh_gpu_instancing`` mesh per plant model, baked once per model (a Dask task
  each) and embedded in each tile that shows it; grass and smaller plants are left out.
  Its ``geometricError`` is ``f`` (blocks, i.e. metres): the terrain sampled every ``f``
  blocks is off by less than ``f``, and so is a left-out plant (smaller than ``f``); the
  impostor's parallax is not counted.  Children ``REPLACE`` it.

Tile content is glTF 2.0 binary (3D Tiles 1.1 takes glTF directly): +Y up, as glTF
wants; the tileset's bounding boxes are in the tileset's Z-up frame (the glTF ``y`` is the
tileset's ``z`` and the glTF ``z`` is the tileset's ``−y``), as the 3D Tiles specification
says for glTF content.  No root transform is given: the world sits at the tileset's origin
(give the root a ``transform`` to place it on the globe in CesiumJS).  Every tile is a
Dask task (:mod:`sylva.cluster`) that reads only its piece of the store.

Examples
--------
>>> import tempfile, json
>>> from pathlib import Path
>>> from sylva.world import World, WorldConfig
>>> d = tempfile.mkdtemp()
>>> store = World(WorldConfig(seed=3, chunk_size=8), size=(32, 16)).generate(d + "/w.zarr")
>>> info = write_tileset(store, d + "/tiles", leaf_columns=16, workers=1)
>>> info["levels"], info["tiles"]
(2, 3)
>>> json.loads(Path(d, "tiles", "tileset.json").read_text())["asset"]["version"]
'1.1'
"""

from __future__ import annotations

import dataclasses
import json
import math
from pathlib import Path

import numpy as np

from .._atomic import atomic_path, atomic_write, make_folder
from ..errors import SylvaError
from ..geometry.exchange.gltf_instanced import InstancedMesh, write_glb_instanced
from .blocks import TEXTURES, Block
from .chunks import _shift
from .meshing import quads_to_mesh, skin_quads
from .store import WorldStore

__all__ = ["plan_tiles", "write_tileset"]

#: Room above the terrain's layers for the plants in a tile's bounding box.
PLANT_HEADROOM = 48


def plan_tiles(store: WorldStore, leaf_columns: int) -> tuple[int, list[dict]]:
    """The quadtree of a store: ``(levels, tiles)``, each tile a dict with ``level``,
    ``i``, ``j`` and its columns ``x0, z0, x1, z1`` (clipped to the world)."""
    s = store.config.chunk_size
    if leaf_columns < s or leaf_columns % s:
        raise SylvaError(f"leaf_columns must be a multiple of the chunk size {s}, got "
                         f"{leaf_columns}")  # fmt: skip
    bx0, bz0, bx1, bz1 = store.bounds
    gx0, gz0 = store.base
    ntx = math.ceil((bx1 - gx0) / leaf_columns)
    ntz = math.ceil((bz1 - gz0) / leaf_columns)
    levels = 1 + max(0, math.ceil(math.log2(max(ntx, ntz))))
    tiles = []
    for level in range(levels):
        span = leaf_columns << (levels - 1 - level)
        for j in range(math.ceil((bz1 - gz0) / span)):
            for i in range(math.ceil((bx1 - gx0) / span)):
                x0, z0 = gx0 + i * span, gz0 + j * span
                tiles.append({"level": level, "i": i, "j": j,
                              "x0": max(x0, bx0), "z0": max(z0, bz0),
                              "x1": min(x0 + span, bx1), "z1": min(z0 + span, bz1)})  # fmt: skip
    return levels, tiles


def _materials(folder: Path):
    from .atlas import tile_materials

    return tile_materials({t: str(folder / "textures" / f"{t}.png") for t in TEXTURES})


def _impostor_task(job) -> dict:
    """One Dask task: bake the impostors of some plant models; ``{key: (size, quads)}``."""
    from .plants import PlantLibrary

    path, out, keys, impostor = job
    store = WorldStore(path)
    lib = PlantLibrary.for_config(store.config)
    lib.materials = _materials(Path(out))
    res = {}
    for key in keys:
        mesh = lib.model(key)
        if mesh.n_triangles == 0:
            continue
        b = mesh.bounds()
        size = float(np.max(b[1] - b[0]))
        if size < 2:  # too small for the finest coarse level (f = 2)
            continue
        quads = impostor(key, mesh, Path(out) / "textures")
        if quads is not None:
            res[key] = (size, quads)
    return res


def _leaf(store: WorldStore, t: dict, materials, grass: bool):
    from .plants import PlantLibrary

    region = store[t["x0"] : t["x1"], t["z0"] : t["z1"]]
    terrain = quads_to_mesh(region.quads(), materials=materials, name="terrain")
    lib = PlantLibrary.for_config(store.config)
    lib.materials = materials
    inst = []
    for key, group in region.instances().items():
        if not grass and key.startswith("grass#"):
            continue
        rot = group.rotation() if key.startswith("grass#") else None
        inst.append(InstancedMesh(lib.model(key), group.translation, rot, name=key))
    return terrain, inst


def _far_plants(store: WorldStore, t: dict, f: int, impostors: dict) -> list:
    """The impostors of the plants of at least ``f`` blocks standing in the tile."""
    keep = {k: q for k, (size, q) in impostors.items() if size >= f}
    if not keep:
        return []
    region = store[t["x0"] : t["x1"], t["z0"] : t["z1"]]
    return [InstancedMesh(keep[key], group.translation, None, name=f"{key}#impostor")
            for key, group in region.instances().items() if key in keep]  # fmt: skip


def _coarse(store: WorldStore, t: dict, f: int, materials):
    import zarr

    arr = zarr.open_array(str(store.path / "voxels"), mode="r", zarr_format=3)
    xs = np.arange(t["x0"], t["x1"], f) - store.base[0]
    zs = np.arange(t["z0"], t["z1"], f) - store.base[1]
    ys = np.arange(0, store.config.height, f)
    vox = np.asarray(arr.oindex[xs, ys, zs], np.uint8)
    pad = np.full((vox.shape[0] + 2, vox.shape[1], vox.shape[2] + 2), Block.AIR, np.uint8)
    pad[1:-1, :, 1:-1] = vox
    quads = skin_quads(pad) if pad.any() else np.zeros((0, 7), np.int32)
    quads[:, 1:4] += _shift(quads[:, 0], -1, -1)
    m = quads_to_mesh(quads, materials=materials, name=f"terrain_{f}")
    v = m.vertices.astype(np.float64) * f + np.array([t["x0"], 0.0, t["z0"]])
    uvs = None if m.uvs is None else m.uvs * f
    return dataclasses.replace(m, vertices=v.astype(np.float32), uvs=uvs)


def _tile_task(job) -> dict:
    """One Dask task: the content of one tile."""
    path, out, t, levels, grass, impostors = job
    store = WorldStore(path)
    out = Path(out)
    materials = _materials(out)
    f = 1 << (levels - 1 - t["level"])
    if f == 1:
        terrain, inst = _leaf(store, t, materials, grass)
    else:
        terrain, inst = _coarse(store, t, f, materials), _far_plants(store, t, f, impostors)
    n_inst = sum(len(i) for i in inst)
    res = {**t, "triangles": int(terrain.n_triangles), "instances": n_inst, "uri": None,
           "impostors": n_inst if f > 1 else 0}  # fmt: skip
    pts = [terrain.vertices] if terrain.n_triangles else []
    for i in inst:  # each instance's model box (a crown reaches past its column)
        if len(i) and i.mesh.n_vertices:
            b = i.mesh.bounds().astype(np.float64)
            pts += [i.translation + b[0], i.translation + b[1]]
    if pts:  # the content's extent (coarse samples may pass the world's edge)
        p = np.concatenate([np.asarray(q, np.float64).reshape(-1, 3) for q in pts])
        lo, hi = p.min(0), p.max(0)
        res["x0"], res["z0"] = min(t["x0"], float(lo[0])), min(t["z0"], float(lo[2]))
        res["x1"], res["z1"] = max(t["x1"], float(hi[0])), max(t["z1"], float(hi[2]))
    if terrain.n_triangles == 0 and n_inst == 0:
        return res
    uri = f"tiles/{t['level']}/{t['i']}_{t['j']}.glb"
    make_folder(out / "tiles" / str(t["level"]))
    with atomic_path(out / uri) as tmp:
        write_glb_instanced([terrain] if terrain.n_triangles else [], inst, tmp,
                            name=f"tile_{t['level']}_{t['i']}_{t['j']}")  # fmt: skip
    res["uri"] = uri
    return res


def _box(t: dict, height: float) -> list[float]:
    """A 3D Tiles box (Z up) around the tile's columns, glTF ``(x, y, z)`` → ``(x, −z, y)``."""
    hx, hz, hy = (t["x1"] - t["x0"]) / 2, (t["z1"] - t["z0"]) / 2, height / 2
    cx, cz, cy = t["x0"] + hx, t["z0"] + hz, hy
    return [cx, -cz, cy, hx, 0.0, 0.0, 0.0, hz, 0.0, 0.0, 0.0, hy]


def write_tileset(store: WorldStore, out, *, leaf_columns: int | None = None,
                  scheduler: str | None = None, workers: int | None = None,
                  grass: bool = True, progress=False, runner=None,
                  impostor=None) -> dict:  # fmt: skip
    """Write ``store`` as a 3D Tiles 1.1 tileset in the folder ``out``.

    Parameters
    ----------
    store : WorldStore
    out : path
        The folder (created) for ``tileset.json``, ``tiles/`` and ``textures/``.
    leaf_columns : int, optional
        Columns per side of a leaf tile (a multiple of the chunk size; default 4 chunks).
    scheduler, workers
        As for :meth:`~sylva.world.World.generate`.
    grass : bool
        Include grass tufts in the leaves.
    progress : bool or callable
    runner : sylva.cluster.Runner, optional
        Run on this runner instead of connecting for this call.
    impostor : callable, optional
        ``impostor(key, mesh, folder) -> Mesh or None``: the impostor of a plant model
        (crossed quads whose material's ``texture`` is an image file in ``folder``), made
        above this package (it renders: :func:`sylva._impostor.world_impostor`; the CLI
        passes it).  Without it the coarse levels hold terrain only.

    Returns
    -------
    dict
        ``levels``, ``tiles`` (with content), ``triangles``, ``instances`` (impostors
        included), ``impostors`` (instances drawn as impostors in the coarse levels) and
        ``impostor_models``.
    """
    from ..cluster import using
    from .atlas import make_atlas

    out = Path(out)
    if out.suffix.lower() == ".json" or (out.exists() and not out.is_dir()):
        raise SylvaError(f"--format 3dtiles writes a folder: expected a folder, got {str(out)!r}")
    leaf = leaf_columns or 4 * store.config.chunk_size
    levels, tiles = plan_tiles(store, leaf)
    make_folder(out)
    make_atlas(32, store.config.seed).save_tiles(out / "textures")
    keys = [k for k in store.manifest.get("models", []) if not k.startswith("grass#")]
    bake = [] if impostor is None or levels < 2 else [
        (str(store.path), str(out), keys[i : i + 4], impostor) for i in range(0, len(keys), 4)]
    results = {}
    impostors: dict = {}
    with using(runner, scheduler, workers=workers, tasks=len(tiles) + len(bake)) as run:
        if bake:
            make_folder(out / "textures")
            for r in run.map(_impostor_task, bake, progress=progress, unit="bake"):
                impostors.update(r)
        jobs = [(str(store.path), str(out), t, levels, grass, impostors) for t in tiles]
        for r in run.map(_tile_task, jobs, progress=progress, unit="tile"):
            results[(r["level"], r["i"], r["j"])] = r
    height = float(store.config.height + PLANT_HEADROOM)

    def node(level: int, i: int, j: int) -> dict:
        r = results[(level, i, j)]
        f = 1 << (levels - 1 - level)
        tile = {"boundingVolume": {"box": _box(r, height)},
                "geometricError": 0.0 if f == 1 else float(f)}  # fmt: skip
        if r["uri"]:
            tile["content"] = {"uri": r["uri"]}
        if f > 1:
            tile["refine"] = "REPLACE"
            kids = [node(level + 1, 2 * i + a, 2 * j + b) for b in (0, 1) for a in (0, 1)
                    if (level + 1, 2 * i + a, 2 * j + b) in results]  # fmt: skip
            if kids:
                tile["children"] = kids
        return tile

    root = node(0, 0, 0)
    root.setdefault("refine", "REPLACE")
    doc = {"asset": {"version": "1.1", "generator": "sylva world --format 3dtiles"},
           "geometricError": 2.0 * max(root["geometricError"], 1.0), "root": root,
           "extras": {"seed": store.config.seed, "size": list(store.size),
                      "origin": list(store.origin), "levels": levels,
                      "leaf_columns": leaf}}  # fmt: skip
    with atomic_write(out / "tileset.json", "w") as fh:
        fh.write(json.dumps(doc, indent=1))
    with_content = [r for r in results.values() if r["uri"]]
    return {"levels": levels, "tiles": len(with_content),
            "triangles": sum(r["triangles"] for r in with_content),
            "instances": sum(r["instances"] for r in with_content),
            "impostors": sum(r["impostors"] for r in with_content),
            "impostor_models": len(impostors)}  # fmt: skip
