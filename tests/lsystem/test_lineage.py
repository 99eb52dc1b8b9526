"""Randomness keyed by lineage: a module's draws come from its ancestry, not its position."""

from __future__ import annotations

import numpy as np

from sylva.lsystem import Derivation, derive, loads
from sylva.lsystem._lineage import lineage_keys

PLANT = """\
seed = 11
axiom = [B][A]
A ->(1) A[+A]
A ->(1) AA-
B ->(1) {b1}
B ->(1) {b2}
"""


def _branches(word) -> list[str]:
    """The text of each top-level bracket pair of ``word``."""
    text, out, depth, start = word.to_text(), [], 0, 0
    for i, ch in enumerate(text):
        if ch == "[":
            depth += 1
            if depth == 1:
                start = i
        elif ch == "]":
            depth -= 1
            if depth == 0:
                out.append(text[start : i + 1])
    return out


def test_editing_one_branch_leaves_the_others_identical():
    before = loads(PLANT.format(b1="B[-B]", b2="BB+"))
    after = loads(PLANT.format(b1="BBB[-B]B", b2="B"))  # the B branch's rules edited
    a0 = _branches(derive(before, 7, lineage=True))
    a1 = _branches(derive(after, 7, lineage=True))
    assert a0[0] != a1[0]  # the edited branch changed
    assert a0[1] == a1[1]  # the A branch did not, although it moved in the word
    assert len(a0[1]) > 200
    # drawn by position, the same edit reshuffles the A branch too
    p0 = _branches(derive(before, 7))
    p1 = _branches(derive(after, 7))
    assert p0[1] != p1[1]


def test_keys_follow_the_ancestry():
    d = Derivation(loads("seed = 2\naxiom = AB\nA -> CA\nB -> B"), lineage=True)
    k0 = d.keys.copy()
    d.advance()
    # C and A are children 0 and 1 of A; B, rewritten, is child 0 of B
    assert d.keys.tolist() == lineage_keys(k0[[0, 0, 1]], np.array([0, 1, 0])).tolist()
    d.back()
    assert np.array_equal(d.keys, k0)


def test_lineage_is_reproducible_and_keeps_roads_apart_from_positions():
    p = loads("seed = 5\naxiom = F\nF ->(1) F[+F]F\nF ->(1) F[-F]\nF ->(1) FF")
    a = derive(p, 6, lineage=True)
    assert a == derive(p, 6, lineage=True)
    assert Derivation(p, lineage=True, trace=True).advance(6) == a
    assert len(a) > 50
