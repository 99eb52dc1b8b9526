"""Terrain fields and voxel columns: determinism, chunk independence, structure."""

import numpy as np
import pytest

from sylva.world import Biome, Block, WorldConfig, WorldConfigError, columns, voxels


def test_same_seed_same_fields_other_seed_other_fields():
    a = columns(WorldConfig(seed=3), -20, 40, 64, 48)
    b = columns(WorldConfig(seed=3), -20, 40, 64, 48)
    c = columns(WorldConfig(seed=4), -20, 40, 64, 48)
    for name in ("height", "humidity", "temperature", "biome"):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name))
    assert not np.array_equal(a.height, c.height)


def test_fields_do_not_depend_on_the_rectangle():
    cfg = WorldConfig(seed=8)
    big = columns(cfg, 0, 0, 80, 80)
    for x0, z0, w, d in ((0, 0, 7, 9), (33, 17, 20, 31), (79, 79, 1, 1)):
        part = columns(cfg, x0, z0, w, d)
        for name in ("height", "humidity", "temperature", "biome"):
            np.testing.assert_array_equal(
                getattr(part, name), getattr(big, name)[x0 : x0 + w, z0 : z0 + d]
            )


def test_field_ranges_and_water():
    cfg = WorldConfig(seed=2)
    f = columns(cfg, 0, 0, 200, 200)
    assert f.height.min() >= 1 and f.height.max() <= cfg.height - 2
    assert f.humidity.max() <= 9 and f.temperature.max() <= 9
    water = f.biome == Biome.WATER
    np.testing.assert_array_equal(water, f.height < cfg.sea_level)
    # several biomes occur in a 200 x 200 area
    assert len(np.unique(f.biome)) >= 4


def test_smoothing_limits_steps_between_neighbours():
    f = columns(WorldConfig(seed=5, amplitude=80.0), 0, 0, 120, 120)
    steps = np.abs(np.diff(f.height.astype(int), axis=0))
    # smoothing snaps every column whose 4-neighbourhood spans more than 3 blocks, so
    # cliffs are rare: most neighbour steps are small
    assert np.mean(steps <= 3) > 0.97


def test_voxel_columns():
    cfg = WorldConfig(seed=6)
    f = columns(cfg, 0, 0, 40, 40)
    v = voxels(cfg, f)
    assert v.shape == (40, cfg.height, 40) and v.dtype == np.uint8
    for i, k in ((0, 0), (5, 17), (39, 39), (20, 3)):
        h = f.height[i, k]
        col = v[i, :, k]
        assert col[h] != Block.AIR and col[h] != Block.WATER
        assert np.all(col[: max(h - 2, 0)] == Block.STONE)  # stone from 3 blocks down
        above = col[h + 1 :]
        if h < cfg.sea_level:
            assert np.all(np.isin(above[: cfg.sea_level - h], [Block.WATER, Block.ICE]))
            assert np.all(above[cfg.sea_level - h :] == Block.AIR)
        else:
            assert np.all(above == Block.AIR)


def test_caves_only_remove_underground_blocks():
    cfg = WorldConfig(seed=6, caves=True)
    f = columns(cfg, 0, 0, 24, 24)
    plain = voxels(WorldConfig(seed=6), f)
    caves = voxels(cfg, f)
    removed = (plain != 0) & (caves == 0)
    assert removed.any()
    assert np.all((caves == plain) | removed)
    ii, yy, kk = np.nonzero(removed)
    assert np.all(yy < f.height[ii, kk])  # the surface block stays


@pytest.mark.parametrize(
    "kw", [{"chunk_size": 2}, {"height": 4}, {"sea_level": 500}, {"tree_variants": 0},
           {"shrub_count": 2}, {"max_slope": -1}, {"wavelength": 0}],
)
def test_config_validation(kw):
    with pytest.raises(WorldConfigError):
        WorldConfig(**kw)
