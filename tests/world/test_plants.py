"""Species, models and the shrub cache (seed 004 A.4, 4.11, 4.12)."""

import numpy as np
import pytest

from sylva.data import find
from sylva.world import SPECIES, PlantLibrary, Species
from sylva.world.blocks import texture_id
from sylva.world.hashing import UINT_MAX, hash1d, hash2d
from sylva.world.plants import SHRUB_STAGES, SHRUBS, engine_program


def test_shrub_cache_index_is_a_position_hash():
    lib = PlantLibrary(seed=17, shrub_count=12)
    assert lib.cache_size == 24
    for x, z in ((0, 0), (5, -3), (1000, 77)):
        want = int(hash2d(x, z, seed=17) / UINT_MAX * 24)
        assert lib.shrub_entry(x, z) == want
    xs = np.arange(-300, 300)
    idx = lib.shrub_entry(xs, xs * 3)
    assert idx.min() == 0 and idx.max() == 23
    assert idx.tolist() == [lib.shrub_entry(int(x), int(x) * 3) for x in xs]


def test_shrub_cache_index_is_stable():
    # pinned: the same seed and position give the same cache entry on every machine
    lib = PlantLibrary(seed=4, shrub_count=12)
    cols = ((0, 0), (1, 0), (0, 1), (-7, 12), (123, 456))
    assert [lib.shrub_entry(x, z) for x, z in cols] == [1, 17, 21, 15, 3]
    assert [lib.shrub_key(lib.shrub_entry(x, z)) for x, z in cols] == [
        "shrub_a#1", "shrub_b#5", "shrub_b#9", "shrub_b#3", "shrub_a#3"]
    assert lib.shrub_salts()[:3].tolist() == [3988905115, 2565835663, 3783491478]
    # the index depends on the position only, not on how many shrubs were asked before
    assert PlantLibrary(seed=4, shrub_count=12).shrub_entry(123, 456) == 3


def test_shrub_salt_chain_and_stages():
    lib = PlantLibrary(seed=9, shrub_count=6)
    salts = lib.shrub_salts()
    assert salts[0] == hash1d(9)
    assert all(salts[i + 1] == hash1d(int(salts[i])) for i in range(len(salts) - 1))
    assert lib.shrub_key(0) == "shrub_a#0" and lib.shrub_key(7) == "shrub_b#1"
    for entry in (0, 1, 2, 6, 10):
        b = lib.blocks(lib.shrub_key(entry))
        d, s = SHRUB_STAGES[(entry % 6) % 3]
        assert b.derivations == d and b.scale == pytest.approx(s)
    # bigger stages grow more blocks on average
    small = np.mean([len(lib.blocks(lib.shrub_key(e))) for e in (0, 3, 6, 9)])
    large = np.mean([len(lib.blocks(lib.shrub_key(e))) for e in (2, 5, 8, 11)])
    assert large > small


@pytest.mark.parametrize("name", ["acacia", "oak", "birch", "jungle", "baobab", "cactus"])
def test_every_species_grows_on_its_base(name):
    lib = PlantLibrary(seed=3, tree_variants=4)
    key = f"{name}#1"
    m = lib.model(key)
    assert m.n_triangles > 0
    lo, hi = m.bounds()
    assert lo[1] == pytest.approx(0.0, abs=1e-5), "the model's base is at y = 0"
    assert hi[1] > 0.5
    b = lib.blocks(key)
    first = b.center[0]
    assert abs(first[0]) < 1e-5 and abs(first[2]) < 1e-5  # rooted above the origin
    assert lib.model(key) is m  # cached


def test_oak_and_birch_share_the_model_not_the_textures():
    lib = PlantLibrary(seed=3, tree_variants=4)
    oak, birch = lib.blocks("oak#2"), lib.blocks("birch#2")
    assert SPECIES["oak"].program() is SPECIES["birch"].program()
    mo, mb = lib.model("oak#2"), lib.model("birch#2")
    assert texture_id("bark") in mo.material_ids and texture_id("bark_white") in mb.material_ids
    assert texture_id("bark_white") not in mo.material_ids
    assert len(oak) > 20 and len(birch) > 20


def test_tree_keys_follow_position_salts():
    lib = PlantLibrary(seed=5, tree_variants=None)
    assert lib.tree_key("acacia", 3, 4) == f"acacia@{hash2d(3, 4, seed=5)}"
    b = lib.blocks(lib.tree_key("acacia", 3, 4))
    assert len(b) > 10 and lib.model(lib.tree_key("acacia", 3, 4)).n_triangles > 0
    lib8 = PlantLibrary(seed=5, tree_variants=8)
    keys = {lib8.tree_key("oak", x, 0) for x in range(200)}
    assert keys == {f"oak#{i}" for i in range(8)}


def test_engine_programs_ship_with_sylva():
    assert len(engine_program("shrubs", 1).rules) > 0
    assert engine_program("jungle", 1).settings["shrink"] == pytest.approx(0.8)
    assert engine_program("acacia").settings["yaw"] == 45.0
    assert all(engine_program(s, 0).settings["turtle"] == "engine" for s in SHRUBS and ("tree",))


def test_any_sylva_lsystem_can_be_a_plant():
    sp = Species.from_lsystem("bush", find("abop-1.24a-plant").path, height=5.0, derivations=3)
    lib = PlantLibrary(seed=1, species={**SPECIES, "bush": sp})
    m = lib.model("bush#0")
    lo, hi = m.bounds()
    assert hi[1] - lo[1] == pytest.approx(5.0, rel=1e-4) and lo[1] == pytest.approx(0.0, abs=1e-5)
    assert set(np.unique(m.material_ids)) <= {texture_id("bark"), texture_id("leaves")}


def test_a_sylva_tree_species_can_be_a_plant():
    sp = Species.from_tree("hazel", "hazel_shrub", height=3.0)
    lib = PlantLibrary(seed=1, species={**SPECIES, "hazel": sp})
    m = lib.model("hazel#0")
    lo, hi = m.bounds()
    assert hi[1] == pytest.approx(3.0, rel=1e-4) and lo[1] == pytest.approx(0.0, abs=1e-5)
    assert texture_id("leaves") in m.material_ids and texture_id("bark") in m.material_ids
