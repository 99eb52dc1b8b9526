"""Context matching on the axial tree: seed 001 T9/T10, ignore sets, kernels = reference."""

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from sylva.lsystem.lstring import ModuleString
from sylva.lsystem.matching import (
    ignored_table,
    left_context,
    match_left,
    match_right,
    right_context,
)

WORD = "a[bc]d[e[f][g]h]i"  # seed 001 Figure 1


def test_t9_left_context_of_h_is_ade():
    w = ModuleString.from_text(WORD)
    h = w.symbols().index("h")
    assert [w.symbols()[i] for i in left_context(w, h, list("ade"))] == list("ade")
    assert left_context(w, h, list("ae")) is None  # d is on the path
    assert left_context(w, h, list("g")) is None  # a sibling branch is not an ancestor


def test_t10_every_right_context_of_a_matches():
    w = ModuleString.from_text(WORD)
    for rc in ["di", "[b]", "[bc]", "[b]d[e]", "[b]d[e]i", "d[eh]i", "d[e[f][g]]"]:
        assert right_context(w, 0, list(rc)) is not None, rc
        pat = [w.alphabet.id(c) for c in rc]
        ok, _ = match_right(w, np.array([0]), pat, [0] * len(pat), ignored_table(w))
        assert ok[0], rc


def test_t10_non_matching_right_contexts():
    w = ModuleString.from_text(WORD)
    for rc in ["i", "[c]", "d[f]", "d[e]x", "[b][b]", "d[e[g][f]]"]:
        assert right_context(w, 0, list(rc)) is None, rc
        pat = [w.alphabet.id(c) for c in rc]
        ok, _ = match_right(w, np.array([0]), pat, [0] * len(pat), ignored_table(w))
        assert not ok[0], rc


def test_t4_ignored_symbols_are_skipped():
    w = ModuleString.from_text("xia")
    assert left_context(w, 2, ["x"], ignore={"i"}) == [0]
    assert left_context(w, 2, ["x"]) is None
    ign = ignored_table(w, [w.alphabet.id("i")])
    ok, pos = match_left(w, np.array([2]), [w.alphabet.id("x")], [0], ign)
    assert ok[0] and pos[0, 0] == 0


def test_ignored_symbol_is_matched_when_the_pattern_wants_it():
    w = ModuleString.from_text("x+a")
    ign = ignored_table(w, [w.alphabet.id("+")])
    ok, pos = match_left(w, np.array([2]), [w.alphabet.id("+")], [0], ign)
    assert ok[0] and pos[0, 0] == 1


def test_parameter_count_limits_a_match():
    w = ModuleString.from_text("k(3)la(1)")
    ids = [w.alphabet.id("k"), w.alphabet.id("l")]
    ok, _ = match_left(w, np.array([2]), ids, [1, 0], ignored_table(w))
    assert ok[0]
    ok, _ = match_left(w, np.array([2]), ids, [2, 0], ignored_table(w))
    assert not ok[0]


def _balanced(tokens):
    out, depth = [], 0
    for c in tokens:
        if c == "]":
            if depth == 0:
                continue
            depth -= 1
        elif c == "[":
            depth += 1
        out.append(c)
    return "".join(out + ["]"] * depth)


words = st.lists(st.sampled_from(list("abc+[]")), min_size=1, max_size=40).map(_balanced)
patterns = st.lists(st.sampled_from(list("abc+[]")), min_size=1, max_size=8).map(_balanced)


@settings(max_examples=300, deadline=None)
@given(words, patterns, st.booleans())
def test_right_kernel_equals_backtracking_reference(text, pattern, ignore_plus):
    w = ModuleString.from_text(text)
    pat = [w.alphabet.id(c) for c in pattern]
    ign_names = {"+"} if ignore_plus else set()
    ign = ignored_table(w, [w.alphabet.id(c) for c in ign_names])
    cands = np.flatnonzero(w.ids > 1)
    if cands.size == 0:
        return
    ok, _ = match_right(w, cands, pat, [0] * len(pat), ign)
    for c, k in zip(cands, ok):
        ref = right_context(w, int(c), list(pattern), ignore=ign_names)
        assert bool(k) == (ref is not None), (text, pattern, int(c))


@settings(max_examples=300, deadline=None)
@given(words, st.lists(st.sampled_from(list("abc+")), min_size=1, max_size=4), st.booleans())
def test_left_kernel_equals_reference(text, pattern, ignore_plus):
    w = ModuleString.from_text(text)
    pat = [w.alphabet.id(c) for c in pattern]
    ign_names = {"+"} if ignore_plus else set()
    ign = ignored_table(w, [w.alphabet.id(c) for c in ign_names])
    cands = np.flatnonzero(w.ids > 1)
    if cands.size == 0:
        return
    ok, pos = match_left(w, cands, pat, [0] * len(pat), ign)
    for c, k, p in zip(cands, ok, pos):
        ref = left_context(w, int(c), list(pattern), ignore=ign_names)
        assert bool(k) == (ref is not None)
        if ref is not None:
            assert p.tolist() == ref
