"""Every species looks like its own Weber–Penn envelope, seen from the side.

Each shipped species is grown to its ``Age`` (seed 3) at ``quality=0.3`` (the last stem
level thinned, the same foliage on fewer twigs: the silhouette is the trunk's branches'),
and :func:`sylva.tree.likeness.likeness` compares its side silhouette (stem points and leaf
blades rasterised on a 64 × 64 grid) with the envelope its parameters promise
(``Shape``, ``BaseSize``, ``Ratio`` and the pruning envelope).

Tolerances, and why:

* crown base within 0.15 of the height of ``BaseSize``: the crown's lowest twigs hang or
  rise from their branch by ``DownAngle`` and ``Curve`` (a willow's whips, an oak's limbs),
  and the trunk's lowest branch sits up to one bud spacing above ``BaseSize``;
* crown width / height within a factor 0.45 … 2 of the envelope's: the envelope lays the
  trunk's branches out straight at their down angle, while ``Curve``, ``CurveBack``,
  ``AttractionUp`` and trunk splits (``BaseSplits``, ``SegSplits``) bend or widen them (a
  fir's limbs droop, a bamboo's culms splay);
* IoU >= 0.45: on a 64-cell grid the envelope is the outline of branch *lengths*; leaves and
  twigs stand out of it by a cell or two all round and the crown is not filled to the axis,
  which costs a compact crown about half its union; a tree of the wrong shape (a cone for a
  sphere, a mound for a hemisphere on a clear trunk) scores below 0.3.

A palm (``BaseSize`` >= 0.8) is a rosette of fronds at the top of a bare trunk: its envelope
is its fronds laid out at their down angle and curvature (and a fan palm's fans).

"""

import numpy as np
import pytest

from sylva.tree import Tree, species_names
from sylva.tree.likeness import likeness

NOT_YET: set[str] = set()  # species that do not meet it yet (xfail, kept visible)


def test_the_library_has_the_sapling_and_arbaro_set():
    names = set(species_names())
    wanted = {"quaking_aspen", "black_tupelo", "black_oak", "weeping_willow", "sassafras",
              "lombardy_poplar", "european_larch", "balsam_fir", "douglas_fir", "small_pine",
              "palm", "fan_palm", "silver_birch", "acer", "apple", "hill_cherry", "bamboo",
              "sphere_tree"}
    assert wanted <= names and len(names) >= 18


@pytest.fixture(scope="module")
def grown():
    cache = {}

    def get(name):
        if name not in cache:
            cache[name] = likeness(Tree(name, seed=3, quality=0.3).grow())
        return cache[name]
    return get


@pytest.mark.parametrize("name", [
    pytest.param(n, marks=pytest.mark.xfail(strict=True, reason="not like its envelope yet"))
    if n in NOT_YET else n for n in species_names()])
def test_mature_silhouette_is_its_envelope(grown, name):
    r = grown(name)
    assert abs(r.crown_base - r.expected_base) <= 0.15, (r.crown_base, r.expected_base)
    assert 0.45 <= r.width_ratio / r.expected_width_ratio <= 2.0, (
        r.width_ratio, r.expected_width_ratio)
    assert r.iou >= 0.45, r.iou


def test_the_measure_tells_shapes_apart(grown):
    """The same silhouette against another species' envelope scores worse: the IoU measures
    shape, not just size."""
    pine, oak = Tree("scots_pine", seed=3, quality=0.3), Tree("black_oak", seed=3, quality=0.3)
    from sylva.tree.likeness import envelope_mask
    r = grown("scots_pine")
    # the pine's silhouette against an oak-shaped envelope of the same height and width
    n = r.mask.shape[0]
    ext_half = max(0.5 * r.width_ratio * r.height, 0.5 * r.height) * 1.1
    ext = (ext_half, -0.02 * r.height, 0)
    env = envelope_mask(oak, r.height, 0.5 * r.width_ratio * r.height, ext, n)
    wrong = np.count_nonzero(r.mask & env) / np.count_nonzero(r.mask | env)
    assert wrong < r.iou - 0.15
    assert pine.base_size > oak.base_size


def test_oak_willow_and_pine_read_as_themselves(grown):
    oak, willow, pine = grown("black_oak"), grown("weeping_willow"), grown("scots_pine")
    # the oak: a clear trunk under a crown wider than half its height
    assert oak.crown_base > 0.12 and oak.width_ratio > 0.55
    # the willow: foliage down to near the ground all round (the curtain of whips)
    assert willow.crown_base < 0.12 and willow.width_ratio > 0.45
    # the pine: a crown only on the top half, not a cone from the ground (a spruce)
    assert pine.crown_base > 0.45
