"""The pruning envelope, the stem taper and the leaf sizes clamp their values without
``np.clip``'s Python-level dispatch (thousands of calls on a few values per tree); the
clamps must give ``np.clip``'s values bit for bit (NaN and -0 kept, as NumPy's clip keeps
them), so the trees are the same.  The ``np.clip`` forms are kept here as the slow
references."""

import math
import struct

import numpy as np

from sylva.tree import Tree, events, model
from sylva.tree import weber_penn as wp

_EDGES = [-math.inf, -2.0, -1e-300, -0.0, 0.0, 5e-324, 0.3, 0.5, 1.0 - 1e-16, 1.0,
          1.0 + 1e-15, 2.9999999, 3.0, 3.5, math.inf, math.nan]


def _envelope_by_clip(ratio, prune=None):
    """weber_penn.envelope as it was (the reference)."""
    width, peak, low, high = prune or (0.5, 0.5, 0.5, 0.5)
    peak = min(max(peak, 1e-6), 1 - 1e-6)
    r = np.asarray(ratio, np.float64)
    c = np.clip(r, 0.0, 1.0)
    upper = (c / (1.0 - peak)) ** high
    lower = ((1.0 - c) / peak) ** low
    out = width * np.where(c < 1.0 - peak, upper, lower)
    return np.where((r >= 0.0) & (r <= 1.0), out, 0.0)


def test_the_clamps_are_np_clip_bit_for_bit():
    rng = np.random.default_rng(3)
    r = np.concatenate([_EDGES, rng.uniform(-0.5, 1.5, 200)])
    for prune in (None, (0.5, 0.5, 0.5, 0.5), (0.9, 0.2, 1.3, 0.7), (1.0, 0.6, 3.0, 1.0)):
        assert wp.envelope(r, prune).tobytes() == _envelope_by_clip(r, prune).tobytes()
    for x in _EDGES:
        assert struct.pack("d", wp._clip03(x)) == struct.pack("d", float(np.clip(x, 0.0, 3.0)))
    # the leaves' form (sizes_at) is the same expression on [0, 1]
    a = np.array(_EDGES)
    assert np.minimum(np.maximum(0.0, a), 1.0).tobytes() == np.clip(a, 0.0, 1.0).tobytes()
    # and the growth curves' clamp of arrays (the leaves' birth times), scalars as before
    assert events._clip01(a).tobytes() == np.clip(a, 0.0, 1.0).tobytes()
    for x in _EDGES:
        want = min(max(float(x), 0.0), 1.0)
        for v in (x, np.float64(x), np.array(x)):
            assert struct.pack("d", events._clip01(v)) == struct.pack("d", want)


def test_a_pruned_tree_is_the_tree_of_the_reference_envelope(monkeypatch):
    quick = Tree("weeping_willow", seed=3, quality=0.2).grow(9.0)
    qgeo = quick.geometry()
    monkeypatch.setattr(model, "envelope", _envelope_by_clip)
    slow = Tree("weeping_willow", seed=3, quality=0.2).grow(9.0)
    sgeo = slow.geometry()
    assert {b.key: b.plan.length for b in quick.branches()} == {
        b.key: b.plan.length for b in slow.branches()}
    assert len(slow.branches()) > 20
    for field in ("joint_matrix", "joint_parent", "leaf_pos", "leaf_frame", "leaf_size"):
        assert getattr(qgeo, field).tobytes() == getattr(sgeo, field).tobytes(), field


def test_the_leaves_lookups_are_where_many_bit_for_bit():
    """The leaves place themselves with ``_where_points`` (positions) and
    ``_segments_at`` (frames): the numbers of ``Branch._where_many``, on every run."""
    t = Tree("silver_birch", seed=4, quality=0.3).grow(8.0)
    rng = np.random.default_rng(1)
    runs = t.branches()
    assert len(runs) > 20
    for b in runs:
        s = np.concatenate([[b.arc0, b.arc1, b.arc0 - 1.0, b.arc1 + 1.0],
                            rng.uniform(b.arc0, b.arc1, 7)])
        i, p, f = b._where_many(s)
        j, q = b._where_points(s)
        assert i.tobytes() == j.tobytes() and p.tobytes() == q.tobytes()
        assert b.frames[b._segments_at(s) + 1].tobytes() == f.tobytes()


def _rx_many_numpy(a):
    """weber_penn._rx_many as it was (the reference)."""
    c, s = np.cos(a), np.sin(a)
    out = np.zeros((len(a), 3, 3))
    out[:, 0, 0] = 1.0
    out[:, 1, 1], out[:, 1, 2], out[:, 2, 1], out[:, 2, 2] = c, -s, s, c
    return out


def _ry_many_numpy(a):
    c, s = np.cos(a), np.sin(a)
    out = np.zeros((len(a), 3, 3))
    out[:, 1, 1] = 1.0
    out[:, 0, 0], out[:, 0, 2], out[:, 2, 0], out[:, 2, 2] = c, s, -s, c
    return out


def test_the_compiled_rotations_are_numpys_bit_for_bit():
    """Leaf frames and stem curves turn by compiled rotation matrices: NumPy's float64
    ``cos``/``sin`` are the C library's, so the kernel's matrices are NumPy's to the bit."""
    rng = np.random.default_rng(5)
    edges = np.array([0.0, -0.0, 1e-300, math.pi, -math.pi / 2, 1e5, -1e9])  # angles are finite
    for a in (edges, rng.uniform(-7, 7, 5000), np.radians(rng.uniform(0, 360, 999)),
              np.cumsum(rng.normal(0, 0.3, 40)), np.zeros(0)):
        assert wp._rx_many(a).tobytes() == _rx_many_numpy(a).tobytes()
        assert wp._ry_many(a).tobytes() == _ry_many_numpy(a).tobytes()


def test_the_compiled_run_lookup_is_numpys_bit_for_bit():
    """``Branch._where_points`` (and ``_segments_at``) by a kernel: NumPy's floor division,
    clamp and point arithmetic, to the bit, on arc lengths around and on segment ends."""
    from sylva.tree._kernels import where_points

    rng = np.random.default_rng(0)
    for trial in range(3000):
        m = int(rng.integers(1, 17))
        seg = float(rng.uniform(0.001, 3)) * 10.0 ** int(rng.integers(-3, 2))
        arc0 = float(rng.integers(0, 5) * seg)
        P, F = rng.normal(size=(m + 1, 3)), rng.normal(size=(m + 1, 3, 3))
        s = arc0 + rng.uniform(-0.1, m + 0.1, int(rng.integers(0, 30))) * seg
        if trial % 3 == 0 and len(s):
            s[0] = arc0 + int(rng.integers(0, m + 1)) * seg  # on a segment's end
        i = np.minimum(np.maximum(((s - arc0) // seg).astype(np.int64), 0), m - 1)
        p = P[i] + F[i + 1, :, 1] * (s - arc0 - i * seg)[:, None]
        j, q = where_points(s, arc0, seg, m - 1, P, F)
        assert j.tobytes() == i.tobytes() and q.tobytes() == p.tobytes()


def test_the_compiled_leaf_turns_are_numpys_bit_for_bit():
    """``leaves._crown_leaves`` works out its spiral's arcs, segments and rotation stacks in
    one kernel: the numbers of the NumPy form it replaced, on the same draws."""
    from sylva.tree._kernels import crown_leaf_turns

    rng = np.random.default_rng(8)
    for _ in range(400):
        n, m = int(rng.integers(1, 40)), int(rng.integers(1, 12))
        seg = float(rng.uniform(0.01, 2.0))
        a0 = float(rng.integers(0, 4)) * seg
        a1 = a0 + m * seg
        rot, rdev, down, ddev = (float(x) for x in rng.uniform([0, 0, -90, 0],
                                                              [360, 40, 90, 30]))
        u_arc, u_rot = rng.uniform(0.2, 0.8, n), rng.uniform(-1, 1, n)
        phi0 = float(rng.uniform(0, 360))
        u_down, u_twist = rng.uniform(-1, 1, n), rng.uniform(-30, 30, n)
        arcs = a0 + (np.arange(n) + u_arc) / n * (a1 - a0)
        phi = np.radians(phi0 + np.cumsum(rot + u_rot * rdev))
        theta = np.radians(np.abs(down + u_down * ddev))
        idx = np.minimum(np.maximum(((arcs - a0) // seg).astype(np.int64), 0), m - 1)
        got = crown_leaf_turns(a0, a1, u_arc, rot, rdev, u_rot, phi0, down, ddev, u_down,
                               u_twist, seg, m - 1)
        want = (arcs, idx, _ry_many_numpy(phi), _rx_many_numpy(theta),
                _ry_many_numpy(np.radians(u_twist)))
        for g, w in zip(got, want):
            assert g.tobytes() == w.tobytes()


def test_the_compiled_cone_profile_is_numpys_bit_for_bit():
    """``StemPlan.profile`` of a cone without flare (most stems) by one kernel call."""
    from sylva.tree._kernels import cone_profile

    rng = np.random.default_rng(9)
    for _ in range(500):
        s = np.concatenate([rng.uniform(-0.1, 3.0, int(rng.integers(0, 20))), [0.0]])
        current = float(rng.uniform(1e-9, 3.0))
        taper = float(rng.choice([0.0, 0.5, 0.95, 1.0, rng.uniform(0, 1)]))
        z = np.minimum(np.maximum(s / current, 0.0), 1.0)
        want = np.maximum(1.0 - taper * z, 0.02 * (1 - z) + 0.004)
        assert cone_profile(s, current, taper).tobytes() == want.tobytes()


def test_the_compiled_frame_turn_is_einsums_bit_for_bit():
    """``TreeTurtle`` turns frames into the plant frame by a kernel (``turn_frames``):
    ``np.einsum("ij,njk->nik", m[:3, :3], f)[start:]``'s numbers, on rotations and on the
    identity (the ZScale turtle's), ``-0.0`` included."""
    from sylva.tree._kernels import turn_frames

    rng = np.random.default_rng(11)
    for _ in range(300):
        n = int(rng.integers(1, 30))
        m = np.eye(4)
        if rng.uniform() < 0.8:
            q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
            m[:3, :3] = q * rng.uniform(0.5, 2.0)
        f = rng.normal(size=(n, 3, 3)) * 10.0 ** rng.uniform(-5, 5)
        f[rng.uniform(size=f.shape) < 0.1] = -0.0
        start = int(rng.integers(0, 2))
        want = np.einsum("ij,njk->nik", m[:3, :3], f)[start:]
        assert turn_frames(m, f, start).tobytes() == want.tobytes()


def test_the_crown_spiral_from_one_draw_is_the_uniform_calls():
    """``_crown_leaves`` draws a run's 5n + 1 doubles in one ``random`` call and works out
    the spiral in ``crown_leaf_spiral``: the numbers of the five ``uniform`` calls it made
    one after another (and of ``crown_leaf_turns`` on them), from the same stream."""
    from sylva.tree._kernels import crown_leaf_spiral, crown_leaf_turns

    rng = np.random.default_rng(12)
    for k in range(200):
        n, m = int(rng.integers(1, 40)), int(rng.integers(1, 12))
        seg = float(rng.uniform(0.01, 2.0))
        a0 = float(rng.integers(0, 4)) * seg
        rot, rdev, down, ddev, size, sdev = (float(x) for x in rng.uniform(
            [0, 0, -90, 0, 0.01, 0], [360, 40, 90, 30, 0.5, 0.1]))
        old = np.random.default_rng([k, 3])
        u_arc, u_rot = old.uniform(0.2, 0.8, n), old.uniform(-1, 1, n)
        phi0 = float(old.uniform(0, 360))
        u_down, u_twist = old.uniform(-1, 1, n), old.uniform(-30, 30, n)
        sizes = size + old.uniform(-1, 1, n) * sdev
        want = (*crown_leaf_turns(a0, a0 + m * seg, u_arc, rot, rdev, u_rot, phi0, down, ddev,
                                  u_down, u_twist, seg, m - 1), sizes)
        got = crown_leaf_spiral(np.random.default_rng([k, 3]).random(5 * n + 1), a0,
                                a0 + m * seg, rot, rdev, down, ddev, size, sdev, seg, m - 1)
        for g, w in zip(got, want):
            assert g.tobytes() == w.tobytes()


def test_the_world_up_is_the_gemv_where_it_answers():
    """``world_up`` gives ``w[:3, :3].T @ (0, 1, 0)`` as row 1 of ``w`` only where that is
    NumPy's product to the bit; rows with a zero (whose sign BLAS decides) and non-finite
    matrices it leaves to NumPy."""
    from sylva.tree._kernels import world_up

    rng = np.random.default_rng(13)
    up = np.array([0.0, 1.0, 0.0])
    answered = 0
    for _ in range(2000):
        w = rng.normal(size=(4, 4)) * 10.0 ** rng.uniform(-200, 200, (4, 4))
        if rng.uniform() < 0.3:
            w[int(rng.integers(3)), int(rng.integers(3))] = rng.choice([0.0, -0.0, np.nan])
        out = np.empty(3)
        if world_up(w, out):
            answered += 1
            assert out.tobytes() == (w[:3, :3].T @ up).tobytes()
        else:
            assert not (np.isfinite(w[:3, :3]).all() and w[1, :3].all())
    assert answered > 1000
