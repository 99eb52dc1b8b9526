"""The parallel turtle (one subtree per thread) gives exactly the serial walk's geometry."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from sylva.lsystem.lstring import ModuleString
from sylva.turtle import _kernels as K
from sylva.turtle import interpret, interpreter, trace
from sylva.turtle.tables import TABLES, compile_table

from .words import expand

FIELDS = (
    "seg_start", "seg_end", "seg_radius", "seg_color", "seg_material", "seg_module",
    "seg_parent", "seg_depth", "seg_ref", "leaf_pos", "leaf_frame", "leaf_size", "leaf_color",
    "leaf_material", "leaf_module",
)  # fmt: skip


@pytest.fixture(autouse=True)
def _compiled(monkeypatch):
    # the parallel walk is the compiled one: small words on a cold cache would take the
    # interpreted road (sylva._jit.road), which walks in one thread
    monkeypatch.setenv("SYLVA_JIT", "always")


def _both(monkeypatch, fn, *args, **kw):
    """``fn`` walked in parallel and serially, and how many subtrees the threads walked."""
    walked = []
    walk = interpreter._walk_subtrees

    def spy(sel, *rest):
        walked.append(sel.shape[0])
        return walk(sel, *rest)

    monkeypatch.setattr(interpreter, "SUBTREE_MIN", 1)
    monkeypatch.setattr(interpreter, "PARALLEL_MIN", 0)
    monkeypatch.setattr(interpreter, "_threads", lambda: 2)
    monkeypatch.setattr(interpreter, "_walk_subtrees", spy)
    par = fn(*args, **kw)
    monkeypatch.setattr(interpreter, "PARALLEL_MIN", 10**18)
    ser = fn(*args, **kw)
    return par, ser, sum(walked)


def _subtrees(text: str, dialect: str = "abop") -> int:
    w = ModuleString.from_text(text)
    ops, _ = compile_table(TABLES[dialect], w.alphabet.names)
    return K.scan_word(w.ids, ops, 1, max(len(w) // 4, 1))[1].shape[0]


def _same(par, ser):
    for f in FIELDS:
        a, b = getattr(par, f), getattr(ser, f)
        assert a.shape == b.shape, f
        assert np.array_equal(a, b), f


def test_scan_picks_maximal_disjoint_pairs():
    # [ab] (4) and [c[d]] (6) are the largest pairs of at most 6 modules; [d] lies inside
    w = ModuleString.from_text("F[ab]F[c[d]]F[efghijk]")
    ops, _ = compile_table(TABLES["abop"], w.alphabet.names)
    counts, sel = K.scan_word(w.ids, ops, 2, 6)
    assert sel[:, :2].tolist() == [[1, 4], [6, 11]]
    # F/G ordinals before and after each pair: 1 F before [ab], 2 before [c[d]]
    assert sel[:, 2].tolist() == [1, 2] and sel[:, 4].tolist() == [1, 2]
    assert counts[0] == 3 and counts[4] == 2


def test_plant_matches_serial(monkeypatch):
    text = expand("X", {"X": "F[&+X]/[&-X]\\[^X]FX~", "F": "FF"}, 6)
    assert _subtrees(text) >= 2
    par, ser, walked = _both(monkeypatch, interpret, text, dialect="abop", rot=28, thick=0.1,
                             thick_factor=0.9)  # fmt: skip
    assert walked >= 2
    assert par.n_segments > 1000 and par.n_leaves > 100
    _same(par, ser)


def test_holes_and_parameters_match_serial(monkeypatch):
    # F(0) draws nothing: its slot is dropped and the parents renumbered
    text = "F(1)[+F(0)F(2)[-F(1)]F(0)]F(3)[^F(0)[&F(1)~]]/F(1)" * 40
    assert _subtrees(text) >= 2
    par, ser, walked = _both(monkeypatch, interpret, text, dialect="abop", rot=30)
    assert walked >= 2
    assert par.n_segments == text.count("F(") - text.count("F(0)")
    assert par.seg_parent.max() < par.n_segments
    _same(par, ser)


def test_trace_matches_serial(monkeypatch):
    text = expand("X", {"X": "F[+X][-X]FX", "F": "FF"}, 4)
    par, ser, walked = _both(monkeypatch, trace, text, dialect="abop", rot=25)
    assert walked >= 2
    assert np.array_equal(par.positions, ser.positions)
    assert np.array_equal(par.frames, ser.frames)


def test_polygons_and_cut_walk_serially(monkeypatch):
    text = "F[+F{.+F.-F.}][-F%F]F[&F]F" * 4
    par, ser, walked = _both(monkeypatch, interpret, text, dialect="abop", rot=40)
    assert walked == 0
    _same(par, ser)
    assert np.array_equal(par.poly_vertices, ser.poly_vertices)


_SYMS = ["F", "F", "f", "G", "+", "-", "&", "^", "\\", "/", "|", "$", "!", "'", "~", "[", "]"]


@settings(max_examples=60, deadline=None)
@given(st.lists(st.sampled_from(_SYMS), min_size=1, max_size=200))
def test_random_words_match_serial(syms):
    text = "".join(syms)
    mp = pytest.MonkeyPatch()
    try:
        par, ser, _ = _both(mp, interpret, text, dialect="abop", rot=33, thick=0.2)
    finally:
        mp.undo()
    _same(par, ser)


def test_long_random_word_matches_serial(monkeypatch):
    rng = np.random.default_rng(7)
    parts, depth = [], 0
    for sym in rng.choice(_SYMS, 4000):
        if sym == "]" and depth == 0:
            continue
        depth += {"[": 1, "]": -1}.get(sym, 0)
        parts.append(sym)
    text = "".join(parts)
    par, ser, walked = _both(monkeypatch, interpret, text, dialect="abop", rot=33, thick=0.2)
    assert walked >= 2 and par.n_segments > 200
    _same(par, ser)


def _brackets(text: str) -> tuple[int, dict[int, int], bool]:
    """Deepest bracket, partner of each [, and whether every ] has a [ (a ] with no [ before
    it is ignored, as the turtle ignores it)."""
    stack, partner, deepest, balanced = [], {}, 0, True
    for i, ch in enumerate(text):
        if ch == "[":
            stack.append(i)
            deepest = max(deepest, len(stack))
        elif ch == "]":
            if stack:
                partner[stack.pop()] = i
            else:
                balanced = False
    return deepest, partner, balanced and not stack


@settings(max_examples=80, deadline=None)
@given(st.lists(st.sampled_from(_SYMS), min_size=1, max_size=120), st.integers(1, 5))
def test_scan_in_ranges_counts_like_one_pass(syms, parts):
    text = "".join(syms)
    w = ModuleString.from_text(text)
    ops, _ = compile_table(TABLES["abop"], w.alphabet.names)
    n = len(w)
    bounds = [n * k // parts for k in range(parts + 1)]
    counts, sel = K.scan_merge(
        [K.scan_range(w.ids, ops, bounds[k], bounds[k + 1], 2, 8) for k in range(parts)]
    )
    whole, _ = K.scan_word(w.ids, ops, 2, 8)
    for k in (0, 1, 2, 3, 5):  # draws, leaves, polygon room, polygons, serial-only
        assert counts[k] == whole[k]
    assert counts[0] == text.count("F") + text.count("G")
    assert counts[1] == text.count("~")
    deepest, partner, balanced = _brackets(text)
    assert counts[4] >= deepest  # never less than the turtle's stack needs
    if balanced:
        assert counts[4] == deepest
    end = -1
    for a, b, ns0, nl0, ns1, nl1 in sel.tolist():
        # a bracket pair of 2…8 modules, inside one range, after the previous pair
        assert partner.get(a) == b and 2 <= b - a + 1 <= 8 and a > end
        assert any(lo <= a and b < hi for lo, hi in zip(bounds, bounds[1:]))
        # the F/G and leaf ordinals around it, counted over the whole word
        inner = text[a : b + 1]
        assert ns0 == text[:a].count("F") + text[:a].count("G")
        assert ns1 == ns0 + inner.count("F") + inner.count("G")
        assert nl0 == text[:a].count("~") and nl1 == nl0 + inner.count("~")
        end = b
