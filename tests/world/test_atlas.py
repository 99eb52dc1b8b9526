"""The block texture atlas."""

import numpy as np
import pytest

from sylva.world import TEXTURES, make_atlas, tile_image, tile_materials


@pytest.fixture(scope="module")
def atlas():
    return make_atlas(tile=16, seed=2)


def test_atlas_layout_and_determinism(atlas):
    assert atlas.names == TEXTURES
    h, w, c = atlas.image.shape
    assert c == 4 and h % 16 == 0 and w % 16 == 0
    assert np.array_equal(atlas.tile("dirt"), tile_image("dirt", 16, 2))
    assert not np.array_equal(atlas.tile("dirt"), tile_image("dirt", 16, 3))
    # tiles differ from each other and are opaque except the grass tuft
    assert not np.array_equal(atlas.tile("sand"), atlas.tile("greysand"))
    for name in TEXTURES:
        a = atlas.tile(name)[..., 3]
        assert (a == 255).all() or name == "grass_tuft"
    tuft = atlas.tile("grass_tuft")[..., 3]
    assert 0 < np.count_nonzero(tuft) < tuft.size


def test_grass_side_is_green_on_top_and_brown_below(atlas):
    side = atlas.tile("grass_side").astype(int)
    top, bottom = side[0].mean(axis=0), side[-1].mean(axis=0)
    assert top[1] > top[0]  # green dominates
    assert bottom[0] > bottom[2]  # dirt: more red than blue


def test_rects_and_atlas_uvs(atlas):
    u0, v0, u1, v1 = atlas.rect("stone")
    assert 0 <= u0 < u1 <= 1 and 0 <= v0 < v1 <= 1
    uv = atlas.atlas_uvs(np.array([[0.0, 0.0], [1.0, 1.0]]), np.array([0, 0]))
    assert np.all(uv[:, 0] >= u0) and np.all(uv[:, 0] <= u1)
    assert np.all(uv[:, 1] >= v0) and np.all(uv[:, 1] <= v1)


def test_materials(tmp_path, atlas):
    paths = atlas.save_tiles(tmp_path)
    mats = tile_materials({k: str(v) for k, v in paths.items()})
    assert [m.name for m in mats] == [f"block_{t}" for t in TEXTURES]
    tuft = mats[TEXTURES.index("grass_tuft")]
    assert tuft.alpha_cutoff == 0.5 and tuft.double_sided
    assert all(p.is_file() for p in paths.values())
    with pytest.raises(KeyError):
        tile_image("lava")
