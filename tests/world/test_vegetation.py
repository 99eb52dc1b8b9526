"""Plant placement: on solid ground, never in water or on steep slopes, chunk independent."""

import numpy as np
import pytest

from sylva.world import Biome, World, WorldConfig, columns, place, voxels
from sylva.world.blocks import OPAQUE


@pytest.fixture(scope="module")
def area():
    cfg = WorldConfig(seed=31, chunk_size=16)
    x0, z0, w, d = -40, 10, 96, 96
    p = place(cfg, x0, z0, w, d)
    f = columns(cfg, x0 - 1, z0 - 1, w + 2, d + 2)
    v = voxels(cfg, f)
    return cfg, (x0, z0, w, d), p, f, v


def test_every_plant_stands_on_a_solid_block(area):
    cfg, (x0, z0, w, d), p, f, v = area
    assert len(p) > 100
    assert np.any(~np.char.startswith(p.keys, "grass"))  # trees or shrubs, not only grass
    for (x, z), pos in zip(p.column, p.position):
        i, k = x - (x0 - 1), z - (z0 - 1)
        y = int(pos[1]) - 1
        assert pos[0] == x + 0.5 and pos[2] == z + 0.5
        assert OPAQUE[v[i, y, k]], "the ground block must be solid"
        assert v[i, y + 1, k] == 0, "the plant's own block must be air (not water)"
        assert y == f.height[i, k]
        assert y >= cfg.sea_level and f.biome[i, k] != Biome.WATER
        nb = f.height[[i - 1, i + 1, i, i], [k, k, k - 1, k + 1]]
        assert np.max(np.abs(nb - y)) <= cfg.max_slope, "no plants on steep slopes"


def test_placement_does_not_depend_on_chunking():
    cfg = WorldConfig(seed=31, chunk_size=16)
    whole = place(cfg, 0, 0, 32, 32)
    parts = [place(cfg, x, z, 16, 16) for x in (0, 16) for z in (0, 16)]
    a = sorted(zip(whole.keys.tolist(), map(tuple, whole.position.tolist())))
    b = sorted(k for p in parts for k in zip(p.keys.tolist(), map(tuple, p.position.tolist())))
    assert a == b


def test_trees_are_spaced_and_grass_avoids_them(area):
    _, _, p, _, _ = area
    trees = ~np.char.startswith(p.keys, "grass")
    cols = {tuple(c) for c in p.column[trees].tolist()}
    grass = {tuple(c) for c in p.column[~trees].tolist()}
    assert not cols & grass
    # the positive-offset rule: no two trees at (x, z) and (x+1, z), (x, z+1), (x+1, z+1)
    for x, z in cols:
        assert (x + 1, z) not in cols and (x, z + 1) not in cols and (x + 1, z + 1) not in cols


def test_placement_is_deterministic():
    cfg = WorldConfig(seed=5, chunk_size=16)
    a, b = place(cfg, 0, 0, 40, 40), place(cfg, 0, 0, 40, 40)
    np.testing.assert_array_equal(a.keys, b.keys)
    np.testing.assert_array_equal(a.position, b.position)


def test_no_vegetation_and_overrides():
    assert len(place(WorldConfig(seed=5, vegetation=False), 0, 0, 20, 20)) == 0
    everywhere = {b.name.lower(): ["cactus"] for b in Biome}
    p = place(WorldConfig(seed=5, plants=everywhere, grass=False), 0, 0, 60, 60)
    assert len(p) > 0 and all(k.startswith("cactus#") for k in p.keys.tolist())


def test_world_plants_stand_on_solid_blocks(small_store):
    world = World(small_store.config, size=(48, 32))
    n = 0
    for ch in small_store:
        v = world.chunk(ch.cx, ch.cz, keep_voxels=True).voxels
        x0, z0 = ch.origin
        for (x, z), pos in zip(ch.plants.column, ch.plants.position):
            y = int(pos[1]) - 1
            assert OPAQUE[v[x - x0, y, z - z0]] and v[x - x0, y + 1, z - z0] == 0
            n += 1
    assert n == small_store.n_plants > 0
