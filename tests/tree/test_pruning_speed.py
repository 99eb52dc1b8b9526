"""The quick Weber–Penn pruning is the published scheme: the same trees as the slow road.

The pruning trials (``weber_penn._envelope_exit``) used to regrow each trial stem, and its
split clones, as full :class:`~sylva.tree.weber_penn.Branch` components; they now grow only
the runs' curves and move the random streams past the draws they skip.  The slow road is
kept here, as it was, as the reference: the pruned species grown both ways must be the
same trees (every stem's pruned length, every joint and leaf bit for bit).  And the draw
skipping must follow the real components draw for draw, which is checked against the
streams of every run of the grown trees.
"""

import numpy as np
import pytest

from sylva.tree import Tree
from sylva.tree import weber_penn as wp


def _envelope_exit_by_branches(plan, key, world, memo=None):
    """The pruning trial as it was before the quick road (a slow reference): the trial
    stem and its split clones are built as full Branch components."""
    tree = plan.tree
    first = wp.Branch(plan, 0, np.eye(3), key, parent_world=world)
    stack = [(first, world)]
    keep = None
    seg = plan.seg_length
    while stack:
        b, w = stack.pop()
        pts = b.points @ w[:3, :3].T + w[:3, 3]
        out = ~tree.inside_envelope(pts)
        if np.any(out):
            k = int(np.argmax(out))
            arc = b.arc0 + max(k - 1, 0) * seg
            keep = arc if keep is None else min(keep, arc)
            continue
        if b.k1 < plan.curve_res and (keep is None or b.arc1 < keep):
            nxt = w @ b.primary.matrix
            for c in b._continuations(plan.time_at_length(b.arc1), nxt):
                _REFERENCE_CLONES.append(c)
                stack.append((c, nxt))
    return keep


_REFERENCE_CLONES: list = []


def _grown(name, age, quality):
    t = Tree(name, seed=5, quality=quality).grow(age)
    geo = t.geometry()
    return t, geo


@pytest.mark.parametrize("name, age, quality", [
    ("weeping_willow", 9.0, 0.2),  # splits on every level, attraction up, whips near ground
    ("hill_cherry", 25.0, 0.5),  # splits at levels 0 and 1
    ("sphere_tree", 8.0, 0.2),
])
def test_quick_pruning_grows_the_trees_of_the_slow_road(monkeypatch, name, age, quality):
    quick, qgeo = _grown(name, age, quality)
    _REFERENCE_CLONES.clear()
    cut = []
    pruned_length = wp._pruned_length

    def counted(plan_of, length, key, world):
        out = pruned_length(plan_of, length, key, world)
        cut.append(out < length)
        return out

    monkeypatch.setattr(wp, "_envelope_exit", _envelope_exit_by_branches)
    monkeypatch.setattr(wp, "_pruned_length", counted)
    slow, sgeo = _grown(name, age, quality)
    lengths = {b.key: b.plan.length for b in slow.branches()}
    assert len(lengths) > 20
    assert {b.key: b.plan.length for b in quick.branches()} == lengths
    # the envelope shortened stems, and (willow, cherry) the trials went through clones
    assert sum(cut) > 5
    if name != "sphere_tree":
        assert len(_REFERENCE_CLONES) > 10
    for field in ("joint_matrix", "joint_parent", "leaf_pos", "leaf_frame", "leaf_size"):
        assert np.array_equal(getattr(qgeo, field), getattr(sgeo, field)), field


@pytest.mark.parametrize("name", ["weeping_willow", "small_pine", "hill_cherry"])
def test_skipped_draws_are_the_draws_of_the_runs(name):
    """For every run of the tree: its own stream, moved on by ``_skip_run_draws`` (and by
    the split's draws where it split), is where the run's stream is."""
    t = Tree(name, seed=2, quality=0.3).grow(10.0)
    runs = t.branches()
    split = 0
    for b in runs:
        rng = np.random.default_rng([t.seed & 0xFFFFFFFF, *b.key])
        wp._skip_run_draws(b.plan, b.arc0, b.arc1, b.k1, b.share, rng)
        clones = [c for c in b.primary.children if isinstance(c, wp.Branch)]
        if clones:
            frames = wp._split_frames(b.plan, b.n_split, rng)
            assert len(frames) == len(clones)
            for f, c in zip(frames, clones):
                assert np.array_equal(f, c.frames[0])
            split += 1
        assert rng.bit_generator.state == b.rng.bit_generator.state, b.key
    assert split > 5


@pytest.mark.parametrize("name", ["weeping_willow", "hill_cherry"])
def test_the_trials_remembered_draws_are_the_draws_of_the_runs(name):
    """The pruning trials of one stem read each run's stream once (``_TrialStream``): the
    counts, the step reached and the split frames are those of the grown runs' own
    streams, read in any order (a later trial may ask for an earlier step)."""
    t = Tree(name, seed=2, quality=0.3).grow(10.0)
    seed = t.seed & 0xFFFFFFFF
    split = 0
    for b in t.branches():
        clones = [c for c in b.primary.children if isinstance(c, wp.Branch)]
        if not clones:
            continue
        ts = wp._TrialStream(seed, *b.key)
        ts.uniform_at(40)  # moved past the steps asked next: it must start again
        for _ in range(2):  # drawn, then remembered
            pos = wp._skipped_draws(b.plan, b.arc0, b.arc1, b.share, ts.uniform_at)
            frames = ts.split_frames(b.plan, b.n_split, pos)
            assert len(frames) == len(clones)
            for f, c in zip(frames, clones):
                assert f.tobytes() == c.frames[0].tobytes()
        rng = np.random.default_rng([seed, *b.key])
        rng.bit_generator.advance(pos)
        wp._split_frames(b.plan, b.n_split, rng)
        assert rng.bit_generator.state == b.rng.bit_generator.state, b.key
        split += 1
    assert split > 5


def test_the_compiled_envelope_test_decides_as_tree_inside_envelope():
    """The trials test each run's points by a kernel (``_kernels.envelope_exit``); its
    answer is the first point ``Tree.inside_envelope`` puts outside, or -2 (too near the
    envelope to tell without NumPy's own powers), never another index."""
    from sylva.tree._kernels import envelope_exit

    t = Tree("weeping_willow", seed=1)
    rng = np.random.default_rng(4)
    st = max(t.scale_tree, 1e-9)
    asked = 0
    for prune in ((0.5, 0.5, 0.5, 0.5), (0.9, 0.2, 1.3, 0.7), (1.0, 0.6, 3.0, 1.0), t.prune):
        t.prune = prune
        width, peak, low, high = prune
        peak = min(max(peak, 1e-6), 1 - 1e-6)
        for _ in range(300):
            n = int(rng.integers(1, 12))
            pts = rng.uniform([-0.6 * st, -0.1 * st, -0.6 * st], [0.6 * st, 1.1 * st, 0.6 * st],
                              (n, 3))
            if rng.uniform() < 0.2:
                pts[int(rng.integers(n)), 0] = np.nan
            out = ~t.inside_envelope(pts)
            want = int(np.argmax(out)) if np.any(out) else -1
            got = envelope_exit(pts, st, st * max(1.0 - t.base_size, 1e-9), width, peak,
                                low, high)
            asked += got == -2
            assert got in (want, -2)
    assert asked < 300  # the kernel decides most by itself (NaN points it leaves to NumPy)


def test_the_trials_decide_on_the_run_points_as_on_numpys():
    """``_kernels.envelope_exit_local`` decides a run from its own points and the run's
    world matrix, without NumPy's BLAS product; where it decides (not -3) its answer is
    ``envelope_exit``'s on NumPy's points, also for points put on the envelope to the last
    bits, and a willow's trials need NumPy's points for none of their runs."""
    from sylva.tree._kernels import envelope_exit, envelope_exit_local

    t = Tree("weeping_willow", seed=1)
    rng = np.random.default_rng(5)
    st = max(t.scale_tree, 1e-9)
    denom = st * max(1.0 - t.base_size, 1e-9)
    decided = 0
    for prune in ((0.5, 0.5, 0.5, 0.5), (0.9, 0.2, 1.3, 0.7), (0.7, 0.3, 0.0, 2.0), t.prune):
        width, peak, low, high = prune
        peak = min(max(peak, 1e-6), 1 - 1e-6)
        for _ in range(400):
            n = int(rng.integers(1, 12))
            q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
            w = np.eye(4)
            w[:3, :3] = q
            w[:3, 3] = rng.uniform([-0.3 * st, 0, -0.3 * st], [0.3 * st, 0.8 * st, 0.3 * st])
            P = np.cumsum(rng.normal(size=(n, 3)) * st * 0.1, 0)
            if rng.uniform() < 0.4:  # a point on the envelope, or a hair's breadth off it
                r = rng.choice([rng.uniform(-0.05, 1.05), 0.0, 1.0, 1.0 - peak])
                e = float(wp.envelope(r, prune)) * st
                e *= 1.0 + rng.choice([0.0, 1e-15, -1e-15, 1e-13, -1e-13, 1e-9])
                a = rng.uniform(0, 2 * np.pi)
                target = np.array([e * np.cos(a), st - r * denom, e * np.sin(a)])
                P[int(rng.integers(n))] = w[:3, :3].T @ (target - w[:3, 3])
            if rng.uniform() < 0.05:
                P[int(rng.integers(n)), int(rng.integers(3))] = np.nan
            want = envelope_exit(P @ w[:3, :3].T + w[:3, 3], st, denom, width, peak, low, high)
            got = envelope_exit_local(P, w, st, denom, width, peak, low, high)
            if got != -3:
                decided += 1
                assert got == want
    assert decided > 1000
    asked = []
    local = wp.envelope_exit_local

    def spy(*args):
        k = local(*args)
        asked.append(k == -3)
        return k

    try:
        wp.envelope_exit_local = spy
        Tree("weeping_willow", seed=3).grow(20.0)
    finally:
        wp.envelope_exit_local = local
    assert len(asked) > 100 and not any(asked)
