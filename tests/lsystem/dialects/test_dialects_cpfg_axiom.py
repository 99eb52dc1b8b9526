"""cpfg does not decompose the axiom: its first step rewrites the axiom as written and then
decomposes what the step made (``control.c`` puts the axiom in the string as it is;
``generate.c``'s ``ApplyProd`` decomposes each successor and each copied module).  vlab's
11-CPFG/Ring builds its ring of segments by decomposing ``X(NR)`` and moves the one ``A``
around it: decomposed before the first step, ``A`` was one segment ahead of cpfg's."""

from __future__ import annotations

import numpy as np

from sylva.lsystem import Derivation, loads
from sylva.lsystem.dialects import cpfg
from sylva.turtle import interpret

RING = """Lsystem: 0
ring lsystem
derivation length: 1
Axiom: X(4)
A < B --> A
A --> B
decomposition
maximum depth: 10
X(n) : n>1 --> X(n-1)B
X(n) : n==1 --> A
homomorphism
A --> ;(1)[+(90)F(2)]-(45)f-(45)
B --> ;(2)[+(90)F(2)]-(45)f-(45)
endlsystem
"""


def test_the_axiom_stays_as_written_and_the_first_step_decomposes():
    p = cpfg.parse(RING, view=False)
    d = Derivation(p)
    assert str(d.word) == "X(4)"
    words = [str(d.advance(1)) for _ in range(5)]
    # step 1 decomposes X(4) (no production rewrites it); then A moves right, and from
    # the last place to the first: the ring's left neighbour of the first is the last
    assert words == ["ABBB", "BABB", "BBAB", "BBBA", "ABBB"]


def test_the_ring_draws_the_a_first_after_one_step():
    p = cpfg.parse(RING, view=False)
    d = Derivation(p)
    d.advance(p.steps)
    g = interpret(d.render_word(), p)
    first = np.flatnonzero(g.seg_material == g.seg_material[0])
    assert first.tolist() == [0]  # one bar of colour 1, the first, at the start
    assert np.allclose(g.seg_end[0], [-2.0, 0.0, 0.0], atol=1e-12)


def test_other_dialects_still_decompose_the_axiom():
    p = loads("decomposition_depth = 5\naxiom = X(3)\ndecomposition:\n"
              "X(n) : n > 1 -> X(n - 1) B\nX(n) : n == 1 -> A\n")
    assert str(Derivation(p).word) == "ABB"
