"""Weber & Penn's taper (nTaper 0–3), ZScale, envelope pruning and leaf shapes, checked
against the paper's formulas written out again here."""

import math

import numpy as np
import pytest

from sylva.tree import Tree
from sylva.tree.meshing import LEAF_SHAPES, leaf_blade, leaf_outline, leaf_shape_index
from sylva.tree.parameters import ParameterManager
from sylva.tree.weber_penn import stem_profile

BASE = """
[global]
Shape = 7
BaseSize = 0.3
Scale = 10
Levels = 3
Ratio = 0.02
RatioPower = 1.2
Leaves = 8
LeafScale = 0.2
AttractionUp = 0.5
Age = 40
{glob}
[level 0]
Length = 1
Taper = {taper0}
CurveRes = 5
Curve = 0 ± 20
GrowTime = 10
ThickenTime = 10
[level 1]
DownAngle = 60 ± 10
Rotate = 140
Branches = 24
Length = 0.45 ± 0.05
Taper = 1
CurveRes = 5
Curve = -20 ± 30
GrowTime = 3
[level 2]
DownAngle = 45 ± 10
Rotate = 140
Branches = 8
Length = 0.5
Taper = 1
CurveRes = 3
Curve = 0 ± 20
GrowTime = 1
"""


def make(seed=5, taper0=1.0, **glob) -> Tree:
    extra = "\n".join(f"{k} = {v}" for k, v in glob.items())
    return Tree(ParameterManager.from_text(BASE.format(glob=extra, taper0=taper0), seed=seed))


def paper_radius(Z, length, radius, taper):
    """Weber & Penn 1995, section 4.3 (stem radius), one point, as printed."""
    if taper < 1:
        unit = taper
    elif taper < 2:
        unit = 2 - taper
    else:
        unit = 0
    taper_z = radius * (1 - unit * Z)
    if taper < 1:
        return taper_z
    z2 = (1 - Z) * length
    depth = 1 if (taper < 2 or z2 < taper_z) else taper - 2
    z3 = z2 if taper < 2 else abs(z2 - 2 * taper_z * int(z2 / (2 * taper_z) + 0.5))
    if taper < 2 and z3 >= taper_z:
        return taper_z
    return (1 - depth) * taper_z + depth * math.sqrt(taper_z**2 - (z3 - taper_z) ** 2)


# -- taper ---------------------------------------------------------------------------------
@pytest.mark.parametrize("taper", [0.0, 0.4, 1.0, 1.3, 1.5, 2.0, 2.2, 2.5, 3.0])
def test_stem_profile_is_the_papers_formula(taper):
    length_, rad = 2.0, 0.1
    Z = np.linspace(0.0, 1.0, 1001)
    want = np.array([paper_radius(z, length_, rad, taper) for z in Z]) / rad
    assert np.allclose(stem_profile(Z * length_, length_, rad, taper), want, atol=1e-12)


def _mature_trunk(taper, ratio):
    t = make(taper0=taper, Levels=1, Ratio=ratio, Flare=0, Leaves=0).grow(200.0)
    trunk = t.root
    assert trunk.plan.taper == taper and trunk.k1 == trunk.plan.curve_res  # no splits
    P, F, rad, arcs, _ = trunk.grown_points(t.age)
    return trunk.plan, rad, arcs


def test_spherical_end_taper_15():
    plan, rad, arcs = _mature_trunk(1.5, 0.05)
    length_, r0 = plan.length, plan.radius
    assert arcs[-1] == pytest.approx(length_) and rad[-1] == pytest.approx(0.0, abs=1e-12)
    want = np.array([paper_radius(a / length_, length_, r0, 1.5) for a in arcs])
    assert np.allclose(rad, want, rtol=1e-9, atol=1e-12)
    # rings were added on the round end: several within taper_z of the tip
    taper_tip = r0 * (1 - 0.5)
    assert np.sum(arcs > length_ - taper_tip) >= 4
    # the end is a sphere of radius taper_z: the radius rises like √(2 taper_z d − d²)
    end = arcs > length_ - 0.25 * taper_tip
    d = length_ - arcs[end]
    assert np.all(rad[end] > 0.9 * np.sqrt(2 * 0.5 * r0 * d - d * d) - 1e-12)


def test_periodic_taper_25():
    plan, rad, arcs = _mature_trunk(2.5, 0.05)  # 10 nodes along the trunk
    length_, r0 = plan.length, plan.radius
    assert length_ / (2 * r0) == pytest.approx(10.0)
    assert np.all(rad <= r0 * (1 + 1e-12))  # never above the untapered radius
    want = np.array([paper_radius(a / length_, length_, r0, 2.5) for a in arcs])
    assert np.all(np.diff(arcs) > 0)
    # (√ is steep at the pinches: round-off in z2 shows there as ~1e-8)
    assert np.allclose(rad, want, rtol=0, atol=1e-6 * r0)
    # local minima of the radius: every stem diameter, counted from the tip, pinched to
    # (1 − depth) · r with depth = Taper − 2
    inner = np.nonzero((rad[1:-1] < rad[:-2]) & (rad[1:-1] < rad[2:]))[0] + 1
    assert len(inner) >= 8
    from_tip = length_ - arcs[inner]
    k = from_tip / (2 * r0)
    assert np.allclose(k, np.round(k), atol=1e-6)
    assert np.allclose(np.diff(np.sort(from_tip)), 2 * r0, rtol=1e-6)
    assert np.allclose(rad[inner], 0.5 * r0, rtol=1e-6)
    # and the stem is periodic: the profile repeats after a stem diameter
    mid = (arcs > 2 * r0) & (arcs < length_ - 4 * r0)
    s = arcs[mid]
    here = stem_profile(s, length_, r0, 2.5)
    there = stem_profile(s + 2 * r0, length_, r0, 2.5)
    assert np.allclose(here, there, atol=1e-9)


def test_growing_periodic_stem_keeps_its_nodes_and_a_round_tip():
    t = make(taper0=2.5, Levels=1, Ratio=0.05, Flare=0, Leaves=0)
    plan = t.root.plan
    length_, r0 = plan.length, plan.radius
    cur = 0.6 * length_
    s = np.linspace(0, cur, 4001)
    prof = plan.profile(s, cur)
    assert prof[-1] == pytest.approx(0.0, abs=1e-12)  # round tip at the current end
    far = s < cur - 2 * r0  # away from the tip the nodes are the mature ones
    assert np.allclose(prof[far], stem_profile(s[far], length_, r0, 2.5), atol=1e-12)


def test_taper_up_to_one_is_unchanged():
    a = make(taper0=1.0).grow(12.0).geometry()
    plan = make(taper0=1.0).root.plan
    s = np.linspace(0, plan.length, 50)
    assert np.allclose(plan.profile(s, plan.length),
                       np.maximum(1 - s / plan.length, 0.02 * (1 - s / plan.length) + 0.004))
    assert a.n_joints > 0


# -- ZScale ----------------------------------------------------------------------------------
def test_zscale_halves_the_height_and_keeps_the_width():
    one = make(seed=9).grow(20.0).geometry()
    half = make(seed=9, ZScale=0.5).grow(20.0).geometry()
    assert one.n_joints == half.n_joints
    p1, p2 = one.joint_matrix[:, :3, 3], half.joint_matrix[:, :3, 3]
    assert np.allclose(p2[:, 1], 0.5 * p1[:, 1])
    assert np.allclose(p2[:, [0, 2]], p1[:, [0, 2]])
    assert p2[:, 1].max() == pytest.approx(0.5 * p1[:, 1].max())
    # frames stay rotations (skinning and wind need them), tangents follow the scaled curve
    R = half.joint_matrix[:, :3, :3]
    assert np.allclose(np.einsum("nji,njk->nik", R, R), np.eye(3), atol=1e-9)
    assert np.allclose(np.linalg.det(R), 1.0)
    ls = Tree(make(seed=9).params).grow(20.0)
    assert ls.stats()["height"] > make(seed=9, ZScale=0.5).grow(20.0).stats()["height"] * 1.8


def test_zscale_variation_is_drawn_per_seed():
    z = {make(seed=s, ZScale="1 ± 0.3").zscale for s in range(8)}
    assert len(z) == 8 and all(0.7 <= v <= 1.3 for v in z)
    assert make(seed=3, ZScale="1 ± 0.3").zscale == make(seed=3, ZScale="1 ± 0.3").zscale


# -- pruning ---------------------------------------------------------------------------------
PRUNE = {"PruneWidth": 0.22, "PruneWidthPeak": 0.4, "PrunePowerLow": 0.5,
         "PrunePowerHigh": 0.8}


def paper_inside(points, scale_tree, base_size, width, peak, low, high):
    """Weber & Penn 1995, section 4.8 (pruning): inside the envelope or not."""
    out = []
    for x, y, z in points:  # sylva is +Y up; the paper's z is our y
        r = math.hypot(x, z)
        ratio = (scale_tree - y) / (scale_tree * (1 - base_size))
        if ratio < 0 or ratio > 1:
            env = 0.0
        elif ratio < 1 - peak:
            env = (ratio / (1 - peak)) ** high
        else:
            env = ((1 - ratio) / peak) ** low
        out.append(r / scale_tree < width * env)
    return np.array(out)


def _levels_1_up(geo):
    keep = geo.joint_level >= 1
    return geo.joint_matrix[keep, :3, 3]


def test_prune_ratio_one_keeps_every_branch_inside_the_envelope():
    free = make(seed=4, **PRUNE).grow(60.0)
    pruned = make(seed=4, PruneRatio=1, **PRUNE).grow(60.0)
    args = (10.0, 0.3, PRUNE["PruneWidth"], PRUNE["PruneWidthPeak"], PRUNE["PrunePowerLow"],
            PRUNE["PrunePowerHigh"])
    p_free = _levels_1_up(free.geometry())
    assert not paper_inside(p_free, *args).all()  # the envelope is narrow enough to matter
    p = _levels_1_up(pruned.geometry())
    assert len(p) > 50 and paper_inside(p, *args).all()
    lengths = {b.key: b.plan.length for b in free.branches() if b.level >= 1}
    shorter = [b.plan.length < lengths[b.key] - 1e-9 for b in pruned.branches()
               if b.level >= 1 and b.key in lengths]
    assert any(shorter)
    # the trunk is never pruned
    assert pruned.root.plan.length == free.root.plan.length


def test_prune_ratio_zero_is_the_unpruned_tree_and_half_is_between():
    plain = make(seed=4).grow(60.0)
    zero = make(seed=4, PruneRatio=0, **PRUNE).grow(60.0)
    ga, gb = plain.geometry(), zero.geometry()
    assert np.array_equal(ga.joint_matrix, gb.joint_matrix)
    assert np.array_equal(ga.leaf_pos, gb.leaf_pos)
    full = {b.key: b.plan.length for b in make(seed=4, PruneRatio=1, **PRUNE).grow(60.0)
            .branches() if b.level == 1 and b.k0 == 0}
    free = {b.key: b.plan.length for b in plain.branches() if b.level == 1 and b.k0 == 0}
    half = {b.key: b.plan.length for b in make(seed=4, PruneRatio=0.5, **PRUNE).grow(60.0)
            .branches() if b.level == 1 and b.k0 == 0}
    common = set(full) & set(free) & set(half)
    assert common
    for k in common:
        assert half[k] == pytest.approx(0.5 * (full[k] + free[k]))


def test_pruned_tree_is_the_same_tree_at_the_same_time():
    a = make(seed=6, PruneRatio=1, **PRUNE).grow(8.0).grow(60.0).geometry()
    b = make(seed=6, PruneRatio=1, **PRUNE).grow(60.0).geometry()
    assert np.array_equal(a.joint_matrix, b.joint_matrix)
    assert np.array_equal(a.leaf_pos, b.leaf_pos)


# -- leaf shapes -----------------------------------------------------------------------------
def _area(o):
    x, y = o[:, 0], o[:, 1]
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


@pytest.mark.parametrize("width", [1.0, 0.4])
def test_leaf_outlines(width):
    expect = {"ellipse": math.pi / 4, "triangle": 0.5, "square": 1.0, "hexagon": 0.75,
              "blade": 0.634}
    outlines = {}
    for k, name in enumerate(LEAF_SHAPES):
        o = leaf_outline(name, width)
        assert leaf_shape_index(name) == k
        w = 1.0 if name == "disc" else width
        box = w * 1.0
        assert np.allclose(o[0], [0, 0])  # starts at the stalk
        assert o[:, 1].min() == pytest.approx(0) and o[:, 1].max() == pytest.approx(1)
        assert np.abs(o[:, 0]).max() == pytest.approx(w / 2)
        a = _area(o)
        assert a > 0  # counter-clockwise, closed (the last edge returns to the start)
        if name in expect:
            assert a / box == pytest.approx(expect[name], rel=0.01), name
        # mirror symmetric about the main vein
        mirrored = o * [-1, 1]
        d = np.linalg.norm(mirrored[:, None, :] - o[None, :, :], axis=2).min(1)
        assert d.max() < 1e-9, name
        # the triangles of the mesh cover the outline exactly
        v, uv, tri = leaf_blade(width, name)
        a_tri = v[tri[:, 1], :2] - v[tri[:, 0], :2], v[tri[:, 2], :2] - v[tri[:, 0], :2]
        cross = a_tri[0][:, 0] * a_tri[1][:, 1] - a_tri[0][:, 1] * a_tri[1][:, 0]
        assert np.all(cross >= -1e-12) and 0.5 * cross.sum() == pytest.approx(a)
        assert uv[:, 0].min() >= 0 and uv[:, 0].max() <= 1
        outlines[name] = o
    assert _area(outlines["disc"]) == pytest.approx(math.pi / 4, rel=0.01)
    assert 0.25 < _area(outlines["palm"]) / width < 0.45
    # distinct: no two outlines cover the same region
    names = list(outlines)
    for i, a in enumerate(names):
        for b in names[i + 1:]:
            if width == 1.0 and {a, b} == {"ellipse", "disc"}:
                continue  # a unit-width ellipse is the disc
            pa, pb = outlines[a], outlines[b]
            gap = max(np.linalg.norm(pa[:, None] - pb[None], axis=2).min(1).max(),
                      np.linalg.norm(pb[:, None] - pa[None], axis=2).min(1).max())
            assert gap > 0.02 or abs(_area(pa) - _area(pb)) > 0.02, (a, b)


def test_leaf_shape_names_and_errors():
    assert leaf_shape_index("oval") == 1 and leaf_shape_index("Hex") == 6
    assert leaf_shape_index(" 4 ") == 4
    for bad in (10, -1, "leafy", 1.5):
        with pytest.raises(ValueError):
            leaf_shape_index(bad)


@pytest.mark.parametrize("shape", ['"triangle"', "4", '"disc"'])
def test_tree_meshes_with_its_leaf_shape(shape):
    t = make(seed=2, LeafShape=shape, Levels=2).grow(15.0)
    k = leaf_shape_index(shape.strip('"'))
    assert t.leaf_shape == k
    tm = t.mesh()
    n_leaves = t.stats()["leaves"]
    v, _, tri = leaf_blade(1.0, k)
    assert n_leaves > 0
    assert np.sum(tm.vertex_leaf >= 0) == len(v) * n_leaves
    leaf_mats = [i for i, m in enumerate(tm.mesh.materials) if m.double_sided]
    assert np.isin(tm.mesh.triangle_materials(), leaf_mats).sum() == len(tri) * n_leaves
    assert np.isfinite(tm.mesh.vertices).all() and len(tm.flutter) == tm.mesh.n_vertices
    if k == 2:  # the disc is round whatever LeafScaleX says
        leaf = tm.mesh.vertices[tm.vertex_leaf == np.max(tm.vertex_leaf)]
        c = leaf.mean(0)
        rad = np.linalg.norm(leaf - c, axis=1)
        assert rad.max() / rad.min() < 1.01


def test_growth_animation_of_a_squashed_tree_ends_at_its_bind_pose():
    from sylva.tree import growth_animation

    a = growth_animation(make(seed=9, ZScale=0.5), 2.0, 20.0, seconds=1.0, fps=4)
    assert np.allclose(a.translation[-1], a.bind_matrices[:, :3, 3], atol=1e-6)
    # and the joints sit at the squashed heights of the mesh, not the tree's own
    top = a.bind_matrices[:, 1, 3].max()
    assert top == pytest.approx(make(seed=9, ZScale=0.5).grow(20.0).stats()["height"], rel=0.2)


def test_compiled_bend_is_the_python_loop(monkeypatch):
    """The compiled attraction-up / ground-clearance loop gives the Python loop's stems."""
    from sylva.tree.weber_penn import Branch

    diffs = []
    compiled = Branch._bend

    def both(self, F, P, curve, seg, up, att, pw):
        F2, P2 = F.copy(), P.copy()
        compiled(self, F, P, curve, seg, up, att, pw)
        Branch._bend_py(self, F2, P2, curve, seg, up, att, pw)
        diffs.append(max(np.abs(F - F2).max(), np.abs(P - P2).max()))

    monkeypatch.setattr(Branch, "_bend", both)
    Tree("weeping_willow", seed=3, quality=0.3).grow(8.0)  # hanging whips: both features
    assert len(diffs) > 50 and max(diffs) < 1e-12
