"""Writing a generated world: GLB with instanced plants, the atlas tiles, the biome map.

Examples
--------
>>> import io, tempfile
>>> from sylva.world.terrain import WorldConfig
>>> from sylva.world.world import World
>>> with World(WorldConfig(seed=1, chunk_size=8), size=(8, 8)).generate(workers=1) as st:
...     buf = io.BytesIO()
...     with tempfile.TemporaryDirectory() as tiles:
...         n = write_world_glb(st, buf, tiles=tiles)
>>> buf.getvalue()[:4]
b'glTF'
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..geometry.exchange.gltf_instanced import InstancedMesh, write_glb_instanced
from .atlas import make_atlas, tile_materials
from .plants import PlantLibrary
from .store import WorldStore as ChunkStore

__all__ = ["write_world_glb"]


def write_world_glb(store: ChunkStore, target, *, tiles, library: PlantLibrary | None = None,
                    tile_size: int = 32, grass: bool = True, impostor=None,
                    near: float | None = None) -> dict:  # fmt: skip
    """Write the terrain and every plant of ``store`` as one ``.glb``.

    The terrain is one static mesh with one material per block texture; each plant model
    (shrub cache entry, tree variant, grass tuft) is written once and drawn at all its
    positions through ``EXT_mesh_gpu_instancing``.

    Parameters
    ----------
    store : ChunkStore
    target : path or binary file object
    tiles : path
        Folder for the texture tiles (PNG) that get embedded (and the atlas, ``atlas.png``).
    library : PlantLibrary, optional
    tile_size : int
        Pixels per texture tile.
    grass : bool
        Include grass tufts.
    impostor : callable, optional
        ``impostor(key, mesh, folder) -> Mesh or None``: the impostor of a plant model
        (crossed quads whose material's ``texture`` is an image file in ``folder``), made
        above this package (it renders: :func:`sylva._impostor.world_impostor`).
    near : float, optional
        With ``impostor``: plants (not grass) farther than this from the centre of the
        world (in x, z, block units) are drawn as their model's impostor.

    Returns
    -------
    dict
        ``models``, ``instances``, ``terrain_triangles``, ``impostor_instances``.
    """
    cfg = store.config
    atlas = make_atlas(tile_size, cfg.seed)
    folder = Path(tiles)
    paths = atlas.save_tiles(folder)
    atlas.save(folder / "atlas.png")
    materials = tile_materials({k: str(v) for k, v in paths.items()})
    lib = library or PlantLibrary.for_config(cfg)
    lib.materials = materials
    terrain = store.terrain_mesh(materials)
    inst = []
    n = n_far = 0
    b = terrain.bounds()
    centre = 0.5 * (b[0] + b[1])
    for key, group in store.instances().items():
        if not grass and key.startswith("grass#"):
            continue
        mesh = lib.model(key)
        rot = group.rotation() if key.startswith("grass#") else None
        n += len(group)
        t = np.asarray(group.translation)
        if impostor is not None and near is not None and not key.startswith("grass#"):
            far = np.hypot(t[:, 0] - centre[0], t[:, 2] - centre[2]) > float(near)
            quads = impostor(key, mesh, folder) if far.any() else None
            if quads is not None:
                n_far += int(far.sum())
                inst.append(InstancedMesh(quads, t[far], None, name=f"{key}#impostor"))
                t = t[~far]
                if not len(t):
                    continue
        inst.append(InstancedMesh(mesh, t, rot, name=key))  # rot: grass only, never split
    write_glb_instanced([terrain], inst, target, name="world")
    return {"models": len(inst), "instances": n, "terrain_triangles": terrain.n_triangles,
            "impostor_instances": n_far}
