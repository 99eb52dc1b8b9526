"""Open L-systems (Měch & Prusinkiewicz 1996): communication modules ?E that an environment
fills between steps, through the vectorised protocol of sylva.lsystem.environment."""

from __future__ import annotations

import numpy as np
import pytest

import sylva
from sylva.errors import LSystemSyntaxError, SylvaError
from sylva.lsystem import Derivation, loads
from sylva.lsystem.environment import Communication, has_communication
from sylva.plant import turtle_locate


def test_the_environment_receives_every_module_of_the_step_at_once_and_writes_back():
    # the axiom's modules: F(1) ?E(7) [ +(90) F(2) ?E(8, 9) ] ?E()  and rules that read ?E
    p = loads(
        "axiom = F(1) ?E(7) [ +(90) F(2) ?E(8, 9) ] ?E\n"
        "?E(a, b) : a > 100 -> ?E(a, b) X\n"
    )
    calls: list[Communication] = []

    def env(c: Communication) -> np.ndarray:
        calls.append(c)
        out = c.params.copy()
        out[:, 0] = 100 + c.step * 10 + np.arange(len(c))  # 100, 101 ... on the axiom
        return out

    d = Derivation(p, environment=env, locate=turtle_locate(p))
    c = calls[0]
    assert c.step == 0 and len(c) == 3
    assert c.index.tolist() == [1, 5, 7]  # word positions of the ?E modules
    assert c.counts.tolist() == [1, 2, 0]
    np.testing.assert_array_equal(c.params[:, 0], [7, 8, np.nan])
    np.testing.assert_array_equal(c.params[1], [8, 9])
    # the turtle's state there: (0, 1, 0) heading up; (-2, 1, 0) heading -X after +(90)
    np.testing.assert_allclose(c.positions, [[0, 1, 0], [-2, 1, 0], [0, 1, 0]], atol=1e-12)
    np.testing.assert_allclose(c.heading, [[0, 1, 0], [-1, 0, 0], [0, 1, 0]], atol=1e-12)
    # written back (a module keeps its own number of parameters)
    assert [v for s, v in d.word if s == "?E"] == [(100.0,), (101.0, 9.0), ()]
    # the next step's productions read them: a > 100 only for the second
    w = d.advance(1)
    assert "".join(s for s, _ in w) == "F?E[+F?EX]?E"
    assert calls[1].step == 1 and len(calls[1]) == 3
    assert [v for s, v in w if s == "?E"] == [(110.0,), (111.0, 9.0), ()]


def test_lsys_and_cpfg_spell_the_module_alike():
    lsys = loads("axiom = A ?E(1)\nA > ?E(x) : x > 0 -> B\n")
    cpfg = loads("lsystem: 1\nderivation length: 1\naxiom: A ?E(1)\nA > ?E(x) : x > 0 --> B\n"
                 "endlsystem\n", dialect="cpfg")  # fmt: skip
    assert [m.symbol for m in cpfg.axiom] == ["A", "?E"] == [m.symbol for m in lsys.axiom]
    env = lambda c: c.params  # noqa: E731 - keeps the values
    for p in (lsys, cpfg):
        assert has_communication(p)
        assert str(Derivation(p, environment=env).advance(1)) == 'B"?E"(1)'
    # the writer quotes ? so that "?" E reads back as two modules, ?E as one
    assert sylva.loads(sylva.dumps(lsys)).axiom == lsys.axiom
    assert [m.symbol for m in loads('axiom = "?"E').axiom] == ["?", "E"]


def test_without_an_environment_the_derivation_says_how_to_give_one():
    p = loads("axiom = A\nA -> A ?E(0)\n", filename="open.lsys")
    with pytest.raises(SylvaError, match=r"open.lsys:2:1: .*expected an environment"):
        Derivation(p)


@pytest.mark.parametrize(
    ("answer", "message"),
    [
        (lambda c: np.zeros(len(c)), r"step 0: environment 'bad' returned shape \(2,\); "
         r"expected \(2, 2\): one row per \?E module \(2 in the word, the first at word "
         r"position 1\)"),
        (lambda c: np.zeros((len(c), 3)), r"returned shape \(2, 3\); expected \(2, 2\)"),
        (lambda c: 1 / 0, r"step 0: environment 'bad' raised ZeroDivisionError: division by "
         r"zero \(while answering 2 \?E module\(s\), the first at word position 1\)"),
        (lambda c: [["a", "b"]] * 2, r"returned list; expected float values"),
        (lambda c: np.where(c.index[:, None] > 2, np.inf, 0.0) * np.ones((1, 2)),
         r"gave inf to parameter 1 of the \?E module at word position 3; expected finite"),
    ],
)
def test_a_bad_environment_is_an_error_naming_step_and_module(answer, message):
    def bad(c):
        return answer(c)

    p = loads("axiom = A ?E(1, 2) B ?E(3)")
    with pytest.raises(SylvaError, match=message):
        Derivation(p, environment=bad)


def test_a_bad_environment_later_names_the_step_it_failed_in():
    p = loads("axiom = A ?E(0)\nA -> A\n?E(n) -> ?E(n)\n")

    def env(c):
        if c.step == 3:
            raise ValueError("out of light")
        return c.params

    d = Derivation(p, environment=env)
    d.advance(2)
    with pytest.raises(SylvaError, match=r"step 3: environment 'env' raised ValueError: out"):
        d.advance(1)
    assert d.step == 2  # the word stays that of the last good step


def test_the_environment_directive_is_read_checked_and_written_back():
    p = loads("environment = obstacle(shape = box, y = 2, sx = 3)\naxiom = A ?E(0)")
    assert p.settings["environment"] == "obstacle(shape = box, y = 2, sx = 3)"
    assert sylva.loads(sylva.dumps(p)).settings == p.settings
    with pytest.raises(LSystemSyntaxError, match=r":1:15: unknown environment 'fog'; "
                       r"expected light, obstacle, density, world"):  # fmt: skip
        loads("environment = fog\naxiom = A")
    with pytest.raises(LSystemSyntaxError, match=r":1:21: the light environment has no "
                       r"option 'vox'"):  # fmt: skip
        loads("environment = light(vox = 1)\naxiom = A")
    with pytest.raises(LSystemSyntaxError, match=r":1:30: unknown shape 'cube'"):
        loads("environment = obstacle(shape=cube)\naxiom = A")


@pytest.mark.parametrize("dialect", ["classic", "engine"])
def test_the_one_character_dialects_have_no_communication_module(dialect):
    text = {"classic": "iteration: 2\naxiom: F?E\nrule: F -> FF\n",
            "engine": "0 90 0.7\nX?E\nX > U\n"}[dialect]  # fmt: skip
    with pytest.raises(LSystemSyntaxError, match=r":2:\d: '\?E' is a communication module "
                       rf"\(open L-systems\) of cpfg and .lsys, which the {dialect} format"):
        loads(text, dialect=dialect)


def test_the_fast_roads_are_not_taken_with_an_environment():
    p = loads("axiom = A ?E(0)\nA -> AB\nB -> A\n")
    d = Derivation(p, environment=lambda c: c.params + 1)
    assert not d.is_d0l
    d.advance(5)
    assert [v for s, v in d.word if s == "?E"] == [(6.0,)]  # axiom + 5 steps
