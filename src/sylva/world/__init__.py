"""Voxel worlds: terrain, biomes, chunks, greedy meshing and L-system vegetation (seed 004).

The pipeline::

    cfg = WorldConfig(seed=7, chunk_size=32)
    world = World(cfg, size=(512, 512))
    with world.generate("world.zarr") as store:   # Dask tasks -> Zarr + Parquet store
        scene = store.scene()                # terrain skin + plants, for sylva.render
        plants = store.instances()           # model key -> instance transforms (glTF)
    region = sylva.world.open("world.zarr")[0:64, 0:64]   # read a piece back

* :mod:`~sylva.world.terrain` — heights, humidity, temperature and biomes from octave
  noise; voxel columns, water, optional caves.
* :mod:`~sylva.world.biomes` — the 10 × 10 humidity/temperature table and surface blocks.
* :mod:`~sylva.world.meshing` — the visible skin, greedy-merged.
* :mod:`~sylva.world.executor` — seed 004's salted L-system executor.
* :mod:`~sylva.world.plants`, :mod:`~sylva.world.vegetation` — species, plant cache and
  placement.
* :mod:`~sylva.world.atlas` — the block texture atlas from procedural textures.
* :mod:`~sylva.world.chunks`, :mod:`~sylva.world.world` — chunks and their generation as
  Dask tasks (:mod:`sylva.cluster`).
* :mod:`~sylva.world.store` — the world store (Zarr arrays, Parquet plant tables, GLB
  models); :func:`open` reads it in pieces.
* :mod:`~sylva.world.tiles` — OGC 3D Tiles output for engines.

Examples
--------
>>> c = generate_chunk(WorldConfig(seed=1, chunk_size=8), 0, 0)
>>> c.biome.shape
(8, 8)
"""

from .atlas import Atlas, make_atlas, tile_image, tile_materials
from .biomes import BIOME_TABLE, SURFACE, Biome, candidates, select
from .blocks import FACE_TEXTURES, TEXTURES, Block
from .chunks import Chunk, generate_chunk, load_chunk
from .executor import PlantBlocks, derive, grow, scale_derivations, step
from .hashing import hash01, hash1d, hash2d, hash3d, limited
from .meshing import quads_to_mesh, skin_quads
from .plants import SPECIES, PlantLibrary, Species, blocks_mesh
from .store import Instances, Region, WorldStore, biome_image, expand_instances, open_world
from .terrain import ColumnFields, WorldConfig, WorldConfigError, columns, voxels
from .vegetation import BIOME_PLANTS, Placement, place
from .world import World

#: The store of a generated world (the name before the Zarr store).
ChunkStore = WorldStore
open = open_world  # noqa: A001  (sylva.world.open(path)[x0:x1, z0:z1])

__all__ = [
    "BIOME_PLANTS",
    "BIOME_TABLE",
    "FACE_TEXTURES",
    "SPECIES",
    "SURFACE",
    "TEXTURES",
    "Atlas",
    "Biome",
    "Block",
    "Chunk",
    "ChunkStore",
    "ColumnFields",
    "Instances",
    "Placement",
    "PlantBlocks",
    "PlantLibrary",
    "Region",
    "Species",
    "World",
    "WorldConfig",
    "WorldConfigError",
    "WorldStore",
    "biome_image",
    "blocks_mesh",
    "candidates",
    "columns",
    "derive",
    "expand_instances",
    "generate_chunk",
    "grow",
    "hash01",
    "hash1d",
    "hash2d",
    "hash3d",
    "limited",
    "load_chunk",
    "make_atlas",
    "open_world",
    "place",
    "quads_to_mesh",
    "scale_derivations",
    "select",
    "skin_quads",
    "step",
    "tile_image",
    "tile_materials",
    "voxels",
]
