"""cpfg matches a module to a predecessor or context module only with the same number of
parameters (ABOP p. 41; cpfg's ``PredDiff``); sylva's own ``.lsys`` keeps "at least as
many".  Each case is a small model of ours, its words worked out by hand."""

from __future__ import annotations

import pytest

import sylva
from sylva.lsystem import Derivation
from sylva.lsystem.dialects import cpfg, dumps, loads


def _cpfg(axiom: str, rules: str, steps: int = 1) -> str:
    text = f"Lsystem: 1\nderivation length: {steps}\nAxiom: {axiom}\n{rules}\nendlsystem\n"
    p = cpfg.parse(text, view=False)
    assert p.settings["exact_arity"] == 1.0  # set: each model here needs it
    return str(sylva.derive(p, steps))


def _lsys(axiom: str, rules: str, steps: int = 1) -> str:
    p = loads(f"axiom = {axiom}\n{rules.replace('-->', '->')}\n")
    return str(sylva.derive(p, steps))


@pytest.mark.parametrize(
    ("axiom", "rules", "in_cpfg", "in_lsys"),
    [
        # vlab's insect-realistic: a parameter-free predecessor leaves f(90)
        ("f(90) f", "f --> F", "f(90)F", "FF"),
        ("A(1,2) A(3)", "A(x) --> B(x)", "A(1,2)B(3)", "B(1)B(3)"),
        # a context module of another count: no match in cpfg
        ("B(1) A B(1,2) A", "B(x) < A --> C(x)", "B(1)C(1)B(1,2)A", "B(1)C(1)B(1,2)C(1)"),
        ("A B(1) A B(2,3)", "A > B(x) --> D(x)", "D(1)B(1)AB(2,3)", "D(1)B(1)D(2)B(2,3)"),
        # parameter-free rules with contexts (the compiled context road) on a word with some
        ("A B(1) A B", "A > B --> D", "AB(1)DB", "DB(1)DB"),
        # a lateral branch of the wrong count is passed over for the next one
        ("A[B(1,2)][B(5)]", "A > [B(x)] --> D(x)", "D(5)[B(1,2)][B(5)]",
         "D(1)[B(1,2)][B(5)]"),
    ],
)
def test_the_parameter_count_must_be_equal_in_cpfg_only(axiom, rules, in_cpfg, in_lsys):
    assert _cpfg(axiom, rules) == in_cpfg
    assert _lsys(axiom, rules) == in_lsys


def test_cpfg_walk_and_ring_contexts_count_parameters():
    # an open bracket in the right context takes cpfg's walk (sylva.lsystem._walk)
    assert _cpfg("A[B(1)]A[B]", "A > [B --> D") == "A[B(1)]D[B]"
    # a ring: the first A's left neighbour is the last module, B(1, 2) then B(2)
    assert _cpfg("A B(2) B(1,2)", "ring lsystem\nB(x) < A --> C(x)") == "AB(2)B(1,2)"
    assert _cpfg("A B(1,2) B(2)", "ring lsystem\nB(x) < A --> C(x)") == "C(2)B(1,2)B(2)"


def test_decomposition_and_homomorphism_count_parameters():
    text = ("Lsystem: 1\nderivation length: 1\nAxiom: A\nA --> X(1) X Y(2)\n"
            "decomposition\nX --> Z Z\nhomomorphism\nY --> G\nY(a) --> H(a)\nZ(a) --> K\n"
            "endlsystem\n")  # fmt: skip
    d = Derivation(cpfg.parse(text, view=False))
    d.advance(1)
    assert str(d.word) == "X(1)ZZY(2)"  # X(1) is not decomposed by X --> Z Z
    assert str(d.render_word()) == "X(1)ZZH(2)"  # nor Y(2) drawn by Y --> G, Z by Z(a)


def test_only_where_it_matters():
    # every module of every word has the count its patterns name: no setting, and the
    # program still converts to .lsys
    p = cpfg.parse("Lsystem: 1\nAxiom: A(1) B\nA(x) --> A(x+1) B\nB --> F\nendlsystem\n",
                   view=False)  # fmt: skip
    assert "exact_arity" not in p.settings
    assert loads(dumps(p)) == p
    q = cpfg.parse("Lsystem: 1\nAxiom: A(1)\nA --> B\nendlsystem\n", view=False)
    with pytest.raises(ValueError, match="exact_arity"):
        dumps(q)  # .lsys cannot say it: refused, not converted to another meaning


def test_the_growth_floor_knows_a_module_can_stay():
    # f --> f f doubles f but leaves f(1) and f(2): the word stays f(1)f(2) in cpfg; the
    # count before the steps (engine's check_steps) must not take f(1) to double
    text = "Lsystem: 1\nderivation length: 30\nAxiom: f(1) g\ng --> f(2)\nf --> f f\nendlsystem\n"
    p = cpfg.parse(text, view=False)
    assert str(sylva.derive(p, 30, limit=1000)) == "f(1)f(2)"
