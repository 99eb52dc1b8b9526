"""Rule weights as seed 001 §2.2 says (issue 23): a weight is a positive number.

A weight known when the file is read (a number, or an expression over global variables)
that is 0, negative or not a finite number is an error at its column.  A weight that reads
the rule's parameters is evaluated per application: where it is 0 or negative the rule does
not apply (like a false condition), and a value that is not a finite number stops the
derivation with an error naming the rule.
"""

from __future__ import annotations

import pytest

from sylva.errors import LSystemSemanticError
from sylva.lsystem import derive, loads


@pytest.mark.parametrize(
    ("weight", "words"),
    [
        ("0", "the weight is 0; expected a positive number"),
        ("-2", "the weight is -2; expected a positive number"),
        ("-0", "expected a positive number"),
        ("g", "the weight is 0;"),  # g = 0 below
        ("g - 1", "the weight is -1;"),
        ("1/0", "the value is inf; expected a finite number"),
        ("0/0", "the value is nan; expected a finite number"),
    ],
)
def test_a_weight_known_when_read_must_be_positive(weight, words):
    text = f"g = 0\naxiom = F\nF ->({weight}) G\nF -> H\n"
    with pytest.raises(LSystemSemanticError) as e:
        loads(text)
    assert (e.value.line, e.value.column) == (3, 6) and words in e.value.message


def test_cpfg_probabilities_are_weights_too():
    text = "Lsystem: 1\nAxiom: F\nF --> G : 0\nF --> H : 1\nendlsystem\n"
    with pytest.raises(LSystemSemanticError) as e:
        loads(text, dialect="cpfg")
    assert e.value.line == 3 and "the weight is 0" in e.value.message


@pytest.mark.parametrize("weight", ["1", "0.25", "3", "g + 1", "True"])
def test_positive_weights_are_read(weight):
    p = loads(f"g = 0\naxiom = F\nF ->({weight}) G\n")
    assert len(derive(p, 1, seed=1)) == 1


def test_a_parameter_weight_of_zero_or_less_does_not_apply_there():
    p = loads("axiom = F(1)F(2)F(3)F(4)\nF(x) ->(x - 2) G\nF(x) ->(1e-12) H\n")
    for seed in range(5):
        word = derive(p, 1, seed=seed).to_text()
        assert word[:2] == "HH"  # weights -1 and 0: only H applies
        assert word[2:] == "GG"  # weights 1 and 2 against 1e-12


def test_a_parameter_weight_that_is_not_a_number_stops_the_derivation():
    p = loads("axiom = F(1)F(2)\nF(x) ->(1 / (x - 1)) G\nF(x) -> H\n", filename="w.lsys")
    with pytest.raises(LSystemSemanticError) as e:
        derive(p, 1, seed=1)
    assert e.value.line == 2 and "the weight is inf; expected a finite number" in str(e.value)
