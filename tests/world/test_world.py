"""Whole worlds: determinism, streaming to disk, parallel generation, scenes, biome maps."""

import numpy as np
import pytest

from sylva.errors import SylvaError
from sylva.world import (
    Biome,
    Instances,
    World,
    WorldConfig,
    WorldStore,
    expand_instances,
    generate_chunk,
    load_chunk,
)
from sylva.world.chunks import (
    generate_chunks,
)
from sylva.world.plants import grass_tuft_mesh


def _same(a, b):
    np.testing.assert_array_equal(a.quads, b.quads)
    np.testing.assert_array_equal(a.biome, b.biome)
    np.testing.assert_array_equal(a.height, b.height)
    np.testing.assert_array_equal(a.plants.keys, b.plants.keys)
    np.testing.assert_array_equal(a.plants.position, b.plants.position)


def test_blocks_of_chunks_equal_single_chunks():
    cfg = WorldConfig(seed=13, chunk_size=8)
    block = generate_chunks(cfg, -1, 2, 3, 2, bounds=(-8, 16, 12, 32))
    assert [(c.cx, c.cz) for c in block] == [(-1, 2), (0, 2), (1, 2), (-1, 3), (0, 3), (1, 3)]
    for c in block:
        _same(c, generate_chunk(cfg, c.cx, c.cz, bounds=(-8, 16, 12, 32)))
    w = World(cfg, size=(40, 24))
    blocks = w.blocks(16)
    assert sum(b[2] * b[3] for b in blocks) == len(w.chunk_coords()) == 15


def test_chunk_round_trip(tmp_path):
    c = generate_chunk(WorldConfig(seed=3, chunk_size=8), 2, -1, keep_voxels=True)
    d = load_chunk(c.save(tmp_path / "c.npz"))
    _same(c, d)
    np.testing.assert_array_equal(c.voxels, d.voxels)
    assert (d.cx, d.cz, d.size, d.origin) == (2, -1, 8, (16, -8))


def test_same_seed_same_world(small_store, small_cfg, tmp_path):
    again = World(small_cfg, size=(48, 32)).generate(tmp_path, workers=1)
    assert len(again) == len(small_store) == 6
    for a, b in zip(small_store, again):
        _same(a, b)
    other = World(WorldConfig(seed=12, chunk_size=16), size=(48, 32)).chunk(0, 0)
    assert not np.array_equal(other.height, next(iter(small_store)).height)


def test_store_chunks_equal_generated_chunks(small_store, small_cfg):
    w = World(small_cfg, size=(48, 32))
    chunks = list(small_store)
    assert [(c.cx, c.cz) for c in chunks] == w.chunk_coords()
    for c in chunks:
        _same(c, w.chunk(c.cx, c.cz))


def test_store_reads_back_from_disk(small_store):
    again = WorldStore(small_store.directory)
    assert again.config.seed == small_store.config.seed
    assert again.n_quads == small_store.n_quads > 0
    assert again.size == (48, 32)


def test_owned_store_removes_its_folder():
    store = World(WorldConfig(seed=1, chunk_size=8), size=(8, 8)).generate(workers=1)
    folder = store.directory
    assert (folder / "manifest.json").is_file()
    store.close()
    assert not folder.exists()


def test_biome_map_matches_the_fields(small_store, small_cfg):
    img = small_store.biome_map()
    assert img.shape == (32, 48, 3) and img.dtype == np.uint8
    biomes = World(small_cfg, size=(48, 32)).biome_map()
    from sylva.world import biome_image

    np.testing.assert_array_equal(img, biome_image(biomes))


def test_scene_and_instances(small_store):
    inst = small_store.instances()
    assert sum(len(v) for v in inst.values()) == small_store.n_plants
    assert list(inst) == sorted(inst)
    scene = small_store.scene()
    terrain = scene.meshes[0]
    assert terrain.n_triangles == 2 * small_store.n_quads
    lo, hi = terrain.bounds()
    np.testing.assert_allclose(lo[[0, 2]], [0, 0])
    np.testing.assert_allclose(hi[[0, 2]], [48, 32])
    assert len(scene.meshes) == 1 + len(inst)


def test_expand_instances_rotates_about_y():
    m = grass_tuft_mesh(0)
    inst = Instances("grass#0", np.array([[1, 2, 3], [0, 0, 0]], np.float32),
                     np.array([0.0, np.pi / 2], np.float32))
    e = expand_instances(m, inst)
    assert e.n_vertices == 2 * m.n_vertices
    np.testing.assert_allclose(e.vertices[: m.n_vertices], m.vertices + [1, 2, 3], atol=1e-6)
    v = m.vertices.astype(float)
    rot = np.stack([v[:, 2], v[:, 1], -v[:, 0]], 1)  # +90 degrees about +Y
    np.testing.assert_allclose(e.vertices[m.n_vertices :], rot, atol=1e-6)
    q = inst.rotation()
    np.testing.assert_allclose(np.linalg.norm(q, axis=1), 1.0)


def test_world_extent_and_chunks():
    w = World(WorldConfig(seed=1, chunk_size=16), size=(40, 17), origin=(16, -16))
    assert w.chunk_coords() == [(1, -1), (2, -1), (3, -1), (1, 0), (2, 0), (3, 0)]
    assert w.bounds == (16, -16, 56, 1)
    with pytest.raises(SylvaError):
        World(WorldConfig(), size=(0, 4))


def test_water_world_has_water_biome():
    cfg = WorldConfig(seed=2, sea_level=60, chunk_size=8)
    c = generate_chunk(cfg, 0, 0)
    assert (c.biome == Biome.WATER).all()
    assert not any(k for k in c.plants.keys.tolist())
