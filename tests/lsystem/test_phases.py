"""Decomposition and interpretation rules with a maximum depth; groups (table L-systems).

Decomposition rules (cpfg's ``decomposition``, L-Py's ``decomposition:``) rewrite the word
after every production step, again and again until no rule applies, at most ``maximum
depth`` times; interpretation rules (cpfg's recursive ``homomorphism``, L-Py's
``interpretation:``) do so to the word the turtle draws.  Groups are the tables of ABOP
§1.4's table L-systems: the step's group is chosen by an expression of the step number.
"""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from sylva.errors import LSystemSemanticError, LSystemSyntaxError, SylvaError
from sylva.lsystem import Derivation, derive, dumps, iterate, load, loads

CHAIN = """\
decomposition_depth = 2
axiom = A
A -> AB
decomposition:
B -> CC
C -> D
"""


def test_a_decomposition_chain_runs_to_its_end_after_every_step():
    # step 1: A -> AB; B -> CC (pass 1); C -> D (pass 2); nothing applies on pass 3
    words = [str(w) for w in iterate(loads(CHAIN), 3)]
    assert words == ["A", "ADD", "ADDDD", "ADDDDDD"]


def test_a_decomposition_past_its_maximum_depth_names_the_module_and_step():
    p = loads(CHAIN.replace("decomposition_depth = 2", "decomposition_depth = 1"),
              filename="chain.lsys")  # fmt: skip
    with pytest.raises(LSystemSemanticError) as info:
        derive(p, 3)
    e = info.value
    assert "after step 1" in e.message and "maximum depth 1" in e.message
    assert "module 1 ('C')" in e.message
    assert (e.filename, e.line) == ("chain.lsys", 6)  # the rule that still applies: C -> D


def test_a_decomposition_that_never_ends_is_an_error():
    p = loads("decomposition_depth = 50\naxiom = A\nA -> A\ndecomposition:\nB -> B\nA -> AB")
    with pytest.raises(LSystemSemanticError, match="of the axiom goes deeper than its maximum"):
        derive(p, 1)


def test_the_axiom_is_decomposed_too():
    assert str(derive(loads("axiom = B\ndecomposition:\nB -> CC"), 0)) == "CC"


def test_decomposition_keeps_parameters_and_conditions():
    p = loads(
        "decomposition_depth = 10\naxiom = S(3)\nS(n) -> S(n)\ndecomposition:\n"
        "S(n) : n > 0 -> F(n)S(n - 1)\nS(n) : n == 0 -> X"
    )
    assert derive(p, 1).to_text() == "F(3)F(2)F(1)X"


def test_interpretation_rules_recurse_in_the_drawn_word_only():
    p = loads("interpretation_depth = 2\naxiom = A\ninterpretation:\nA -> B[C]\nB -> F\nC -> +F")
    d = Derivation(p)
    assert str(d.word) == "A"
    assert str(d.render_word()) == "F[+F]"
    word, src = d.render_word_sources()
    assert str(word) == "F[+F]" and src.tolist() == [0] * 5
    with pytest.raises(LSystemSemanticError, match="interpretation of the axiom"):
        Derivation(p.replace(interpretation_depth=1)).render_word()


def test_render_rules_stay_one_pass():
    # seed 001's ->> rules apply once, however they chain
    d = Derivation(loads("axiom = A\nA ->> B\nB ->> C"))
    assert str(d.render_word()) == "B"


CPFG = """\
Lsystem: 1
derivation length: 2
Axiom: A
A --> AB
decomposition
maximum depth: 3
B --> CC
C --> D
homomorphism
maximum depth: 2
D --> E[E]
E --> F
endlsystem
"""


def test_cpfg_decomposition_homomorphism_and_maximum_depth():
    p = load(CPFG, dialect="cpfg")
    assert (p.decomposition_depth, p.interpretation_depth) == (3, 2)
    assert [r.phase for r in p.rules] == ["production"] + ["decomposition"] * 2 + [
        "interpretation"
    ] * 2
    d = Derivation(p)
    d.advance(2)
    assert str(d.word) == "ADDDD"
    assert str(d.render_word()) == "A" + "F[F]" * 4
    assert loads(dumps(p)) == p


def test_cpfg_homomorphism_without_depth_stays_a_render_pass():
    p = load(CPFG.replace("maximum depth: 2\n", ""), dialect="cpfg")
    assert all(r.render for r in p.rules[3:])
    d = Derivation(p)
    d.advance(1)
    assert str(d.render_word()) == "AE[E]E[E]"  # one pass: E is not rewritten again


def test_cpfg_star_is_the_empty_successor():
    p = load("Lsystem: 1\nAxiom: AB\nB --> *\nendlsystem\n", dialect="cpfg")
    assert str(derive(p, 1)) == "A"


def test_cpfg_maximum_depth_must_be_a_whole_number():
    with pytest.raises(LSystemSyntaxError, match="maximum depth") as info:
        load(CPFG.replace("maximum depth: 3", "maximum depth: 0.5"), dialect="cpfg")
    assert info.value.line == 6
    with pytest.raises(LSystemSyntaxError, match="belongs in a decomposition") as info:
        load("Lsystem: 1\nmaximum depth: 3\nAxiom: A\nendlsystem\n", dialect="cpfg")
    assert info.value.line == 2


# --------------------------------------------------------------------------- tables
T0L = """\
group = step % 2 + 1
axiom = a
group 1:
a -> aa
group 2:
a -> aaa
"""


def test_a_table_l_system_alternates_its_two_tables():
    # the T0L system of two tables {a -> a^2} and {a -> a^3} used alternately (Rozenberg
    # and Salomaa, The Mathematical Theory of L Systems, 1980): a^(2^i 3^j)
    lengths = [len(w) for w in iterate(loads(T0L), 6)]
    assert lengths == [1, 2, 6, 12, 36, 72, 216]


def test_rules_outside_groups_apply_in_every_step():
    # ABOP's developmental switch: a vegetative table, then a flowering one; F grows in both
    p = loads("k = 3\ngroup = (step >= k) + 1\naxiom = A\nF -> FF\n"
              "group 1:\nA -> F[B]A\ngroup 2:\nA -> K\n")  # fmt: skip
    assert str(derive(p, 3)) == "FFFF[B]FF[B]F[B]A"
    assert str(derive(p, 4)) == "FFFFFFFF[B]FFFF[B]FF[B]K"


def test_without_a_group_expression_only_group_0_applies():
    p = loads("axiom = a\na -> ab\ngroup 1:\nb -> c")
    assert str(derive(p, 2)) == "abb"


def test_groups_on_every_road_give_the_same_word():
    text = "group = step % 3\nseed = 7\naxiom = F\nF -> F[+F]\ngroup 1:\nF ->(1) FF\nF ->(2) F-F\n"
    p = loads(text)
    fast = derive(p, 6)
    d = Derivation(p, trace=True)  # the traced derivation takes the general road
    assert d.advance(6) == fast
    assert d.origin_rules.max() < len(p.productions)


def test_decomposition_on_every_road_gives_the_same_word():
    p = loads("seed = 3\naxiom = A\nA ->(1) AB\nA ->(1) BA\ndecomposition:\nB -> [C]")
    assert Derivation(p, trace=True).advance(5) == derive(p, 5)


def test_tables_round_trip_and_read_errors():
    p = loads(T0L)
    assert [r.group for r in p.rules] == [1, 2]
    assert loads(dumps(p)) == p
    with pytest.raises(LSystemSyntaxError, match="group's number") as info:
        loads("axiom = a\ngroup:\na -> b")
    assert info.value.line == 2
    with pytest.raises(LSystemSemanticError, match="unknown variable 'n'") as info:
        loads("group = n % 2\naxiom = a")
    assert (info.value.line, info.value.column) == (1, 9)
    with pytest.raises(SylvaError, match="expected a whole number"):
        derive(loads("group = step / 2\naxiom = a\na -> b"), 2)


_BODIES = st.text(alphabet="AB+-", min_size=0, max_size=5).map(
    lambda s: s[:2] + ("[" + s[2:] + "]" if len(s) > 2 else "")
)


@settings(max_examples=40, deadline=None)
@given(
    st.lists(st.tuples(st.integers(0, 2), st.sampled_from("AB"), _BODIES, st.integers(1, 4)),
             min_size=1, max_size=6),
    st.integers(0, 2**32),
    st.booleans(),
)  # fmt: skip
def test_tables_and_decomposition_give_one_word_on_every_road(rules, seed, decompose):
    lines = ["group = step % 3", "axiom = A[B]A"]
    for g in range(3):
        mine = [f"{a} ->({w}) {b}" for gg, a, b, w in rules if gg == g]
        if mine:
            lines += [f"group {g}:" if g else "production:", *mine]
    if decompose:
        lines += ["decomposition:", "- -> +"]
    p = loads("\n".join(lines))
    fast = derive(p, 4, seed=seed)
    general = Derivation(p, seed=seed, trace=True)  # the traced road is the general one
    assert general.advance(4) == fast
    assert Derivation(p, seed=seed, lineage=True).advance(4) == derive(p, 4, seed=seed,
                                                                        lineage=True)
