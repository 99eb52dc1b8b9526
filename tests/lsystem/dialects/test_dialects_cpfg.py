"""cpfg (L-Studio, ABOP), read through the .lsys parser line for line (seed 003 §5.10)."""

from __future__ import annotations

import numpy as np
import pytest

from sylva.errors import LSystemSyntaxError
from sylva.lsystem import derive, load, loads
from sylva.lsystem.dialects import detect, dumps

# seed 003 §5.10, the "L-system" tab of L-Studio, verbatim
LISTING = """#define N 2.2

Lsystem: 1
derivation length: 7

seed: 2454

Axiom: F(1)
F(x) --> X(x*N) [+F(1)] F[-F(1)] F[+F(1)] !F(1) : 0.4
F(x) --> X(x) [-F(1)+F(1)] !F(1) : 0.6

homomorphism
X(x) --> ;F(x)

endlsystem
"""


def test_the_lstudio_listing_reads_as_the_shipped_example():
    p = loads(LISTING)
    q = load("src/sylva/data/examples/36-seed003-lstudio-tree.lsys")
    assert p.dialect == "cpfg" and p.name == "1" and p.turtle == "abop"
    assert (p.steps, p.seed, dict(p.constants)) == (7, 2454, {"N": 2.2})
    assert p.rules == q.rules and p.axiom == q.axiom
    assert [r.render for r in p.rules] == [False, False, True]
    assert [r.weight.value for r in p.productions] == [0.4, 0.6]
    # the same word; cpfg keeps parameters as 32-bit floats, the .lsys as doubles
    a, b = derive(p, 5, seed=3), derive(q, 5, seed=3)
    names = [a.alphabet.names[i] for i in a.ids.tolist()]
    assert names == [b.alphabet.names[i] for i in b.ids.tolist()]
    assert np.array_equal(a.offsets, b.offsets)
    assert np.allclose(a.values, b.values, rtol=1e-6) and not np.array_equal(a.values, b.values)
    assert np.array_equal(a.values, a.values.astype(np.float32))
    assert loads(dumps(p)) == p  # and it converts to .lsys without change of meaning


def test_contexts_conditions_powers_and_comments():
    text = """/* ABOP-style: a signal in a
       context-sensitive, parametric system */
Lsystem: signal // a name
derivation length: 3
ignore: +-
Axiom: B(2) a A(1)
B(x) < a > A(y) : x^2 > y --> b(x+y^2)   // condition and powers
A(y) : * --> A(y*2)
endlsystem
this line is past the end and ignored
"""
    p = loads(text)
    assert p.ignore == frozenset("+-")
    w = derive(p, 1)
    assert str(w) == "B(2)b(3)A(2)"


def test_detection():
    assert detect(LISTING) == "cpfg"
    assert detect("A --> B", "plant.l") == "cpfg"
    assert detect("axiom = F") == "lsys"


@pytest.mark.parametrize(
    "text, line, column, words",
    [
        ("/* one\ntwo */\nLsystem: 1\nAxiom: F\nF --> F[+F\nendlsystem", 5, None, "']'"),
        ("Lsystem: 1\nAxiom: F\nF(x) --> F(x*)[+F : 0.5\n", 3, 14, "expression"),
        ("Lsystem: 1\nAxiom: F\nF(x) : y > 1 --> F(x)\n", 3, 8, "unknown variable 'y'"),
        ("Lsystem: 1\nAxiom: F\nmaximum depth: 2\n", 3, 1, "belongs in a decomposition"),
        ("#include <lpfgall.h>\nLsystem: 1\n", 1, 11, "#include lpfgall.h: cannot read"),
        ("#pragma once\nLsystem: 1\n", 1, 1, "#pragma is not supported"),
        ("Lsystem: 1\nAxiom: F\nF -> FF\n", 3, 1, "production"),
        ("Lsystem: 1\nAxiom: F\nhomomorphism\nF --> G : 0.5\n", 4, None, "probability"),
    ],
)
def test_errors_name_the_line(text, line, column, words):
    with pytest.raises(LSystemSyntaxError) as e:
        loads(text, filename="plant.l")
    err = e.value
    assert err.filename == "plant.l" and err.line == line
    if column is not None:
        assert err.column == column
    assert words in str(err)
    assert err.source_line == text.split("\n")[line - 1]  # the user's line, not a translation
