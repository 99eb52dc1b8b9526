"""Query modules ?P ?H ?U ?L (cpfg; Prusinkiewicz, James & Měch 1994, "Synthetic topiary").

After each derivation step, and on the axiom before the first, the turtle interprets the
word and every query module receives the turtle's state at it, so that the next step's
productions can test it.
"""

from __future__ import annotations

import numpy as np
import pytest

import sylva
from sylva.data import find
from sylva.errors import LSystemSyntaxError, SylvaError
from sylva.lsystem import Derivation, derive, loads
from sylva.lsystem.environment import QUERY_MODULES, has_queries
from sylva.plant import grow, growth_scenes, turtle_query
from sylva.turtle import interpret


def _values(word, name):
    return np.array([p for s, p in word if s == name])


def test_a_query_module_is_one_module_in_lsys_and_two_when_quoted_or_spaced():
    p = loads('axiom = ?P(1,2,3)"?"P ? P ?H(0,0,0)?U(0,0,0)?L(0,0,0)')
    assert [m.symbol for m in p.axiom] == ["?P", "?", "P", "?", "P", "?H", "?U", "?L"]
    assert set(QUERY_MODULES) == {"?P", "?H", "?U", "?L"}
    assert has_queries(p)
    assert not has_queries(loads('axiom = "?"P F'))
    # the written word reads back as the same modules
    assert sylva.loads(sylva.dumps(p)).axiom == p.axiom


def test_positions_and_frames_of_a_known_word():
    # The lsys turtle starts at the origin with H = +Y, L = -X, U = +Z (turtle/interpreter.py),
    # and + turns left about U: H toward L.  By hand:
    #   F(1)   : position (0, 1, 0)
    #   ?P     : (0, 1, 0); ?H (0, 1, 0)
    #   +(90)  : H = old L = (-1, 0, 0), L = -old H = (0, -1, 0), U = (0, 0, 1)
    #   F(2)   : position (0, 1, 0) + 2·(-1, 0, 0) = (-2, 1, 0)
    #   ?P ?H ?U ?L: (-2, 1, 0), (-1, 0, 0), (0, 0, 1), (0, -1, 0)
    p = loads("axiom = F(1) ?P(0,0,0) ?H(9,9,9) +(90) F(2) ?P(0,0,0) ?H(9,9,9) ?U(9,9,9) "
              "?L(9,9,9)")  # fmt: skip
    word = Derivation(p, query=turtle_query(p)).word  # set on the axiom, before step 1
    np.testing.assert_allclose(_values(word, "?P"), [[0, 1, 0], [-2, 1, 0]], atol=1e-12)
    np.testing.assert_allclose(_values(word, "?H"), [[0, 1, 0], [-1, 0, 0]], atol=1e-12)
    np.testing.assert_allclose(_values(word, "?U"), [[0, 0, 1]], atol=1e-12)
    np.testing.assert_allclose(_values(word, "?L"), [[0, -1, 0]], atol=1e-12)
    # sylva.derive wires the turtle in; the modules' other parameters stay the same
    w = sylva.derive(p, 0)
    assert [m for m in w if m[0] == "F"] == [("F", (1.0,)), ("F", (2.0,))]
    np.testing.assert_allclose(_values(w, "?P"), [[0, 1, 0], [-2, 1, 0]], atol=1e-12)


def test_a_query_module_is_not_drawn():
    p = loads("axiom = F(1) ?P(0,0,0) +(90) ?H(0,0,0) F(2) [?U(0,0,0) F(1)]")
    q = loads("axiom = F(1) +(90) F(2) [F(1)]")
    a, b = interpret(sylva.derive(p, 0), p), interpret(sylva.derive(q, 0), q)
    np.testing.assert_allclose(a.seg_start, b.seg_start)
    np.testing.assert_allclose(a.seg_end, b.seg_end)


def test_the_next_step_tests_the_query():
    # a stem that grows while its tip is below y = 2.5, as cpfg's ?P examples do: the tip
    # is at y = 1, 2, 3 after steps 0, 1, 2, so two steps grow and the third does not
    src = "axiom = F(1) ?P(0,0,0) A\n?P(x,y,z) < A : y < 2.5 -> F(1) ?P(0,0,0) A\n"
    p = loads(src)
    w = sylva.derive(p, 6)
    assert str(w).count("F") == 3
    np.testing.assert_allclose(_values(w, "?P")[:, 1], [1, 2, 3], atol=1e-12)


SPHERE = """\
# topiary: buds grow while they are inside a sphere of radius R about (0, C, 0)
R = 4
C = 3.5
axiom = ?P(0,0,0) A
?P(x,y,z) < A : x*x + (y-C)*(y-C) + z*z < R*R -> F(1) [+(32) ?P(0,0,0) A] [-(32) /(90) ?P(0,0,0) A]
"""


def test_topiary_every_tip_stays_inside_the_sphere_plus_one_segment():
    p = loads(SPHERE)
    d = Derivation(p, query=turtle_query(p))
    word = d.advance(10)
    g = interpret(word, p)
    centre, r = np.array([0.0, 3.5, 0.0]), 4.0
    ends = np.linalg.norm(g.seg_end - centre, axis=1)
    starts = np.linalg.norm(g.seg_start - centre, axis=1)
    assert 50 < g.n_segments < 2**10 - 1  # the full binary tree would have 1023
    # a segment grows only from a bud inside the sphere, and it is 1 long
    assert (starts < r + 1e-9).all()
    assert (ends <= r + 1 + 1e-9).all()
    assert (ends > r).any()  # and the pruning is what stopped it
    # every bud's ?P is where the turtle stands after the segment below it
    qp = _values(word, "?P")
    dist = np.linalg.norm(qp[:, None, :] - np.vstack([[0, 0, 0], g.seg_end])[None], axis=2)
    assert dist.min(axis=1).max() < 1e-9
    # in the next step each bud inside the sphere becomes two and each outside stays
    def buds(w):
        mods = list(w)
        at = np.array([mods[i - 1][1] for i, (s, _) in enumerate(mods) if s == "A"])
        assert all(mods[i - 1][0] == "?P" for i, (s, _) in enumerate(mods) if s == "A")
        return at, np.linalg.norm(at - centre, axis=1) < r

    at, inside = buds(word)
    assert 0 < inside.sum() < inside.size
    at2, _ = buds(d.advance(1))
    assert len(at2) == len(at) + inside.sum()
    kept = np.linalg.norm(at[~inside][:, None] - at2[None], axis=2).min(axis=1)
    assert kept.max() < 1e-9


def test_topiary_in_the_cpfg_spelling_gives_the_same_word():
    cpfg = """\
#define R 4
#define C 3.5
Lsystem: topiary
derivation length: 12
Axiom: ?P(0,0,0) A
?P(x,y,z) < A : x*x + (y-C)*(y-C) + z*z < R*R --> F(1) [+(32) ?P(0,0,0) A] [-(32) /(90) ?P(0,0,0) A]
endlsystem
"""
    c = loads(cpfg, dialect="cpfg")
    lsys = loads("turtle = abop\n" + SPHERE)
    a = sylva.derive(c)
    b = sylva.derive(lsys, 12)
    assert str(a) == str(b)
    assert str(a).count("F") > 50


def test_grow_and_growth_scenes_answer_the_queries():
    p = loads(SPHERE)
    plant = grow(p, 12)
    assert plant.geometry.n_segments == str(plant.word).count("F") > 50
    scenes = list(growth_scenes(p, 3, substeps=2))
    assert len(scenes) == 1 + 3 * 2


def test_without_a_query_callback_the_engine_says_so():
    p = loads("axiom = A\nA -> F ?P(0,0,0) A\n")
    with pytest.raises(SylvaError, match=r"<string>:2:1: .*query modules.*expected a query"):
        derive(p, 2)
    with pytest.raises(SylvaError, match="query callback"):
        Derivation(p)


@pytest.mark.parametrize(
    ("answer", "message"),
    [
        (lambda w, i: np.zeros((len(i), 2)), r"step 0: .*shape \(1, 2\); expected \(1, 3\)"),
        (lambda w, i: np.full((len(i), 3), np.nan), "step 0: .*not finite"),
        (lambda w, i: 1 / 0, "step 0: the query callback raised ZeroDivisionError"),
        (lambda w, i: "abc", "step 0: .*expected float values"),
    ],
)
def test_a_bad_query_callback_is_an_error_naming_the_step(answer, message):
    p = loads("axiom = ?P(0,0,0)")
    with pytest.raises(SylvaError, match=message):
        Derivation(p, query=answer)


def test_the_callback_is_vectorised_and_called_on_the_axiom_and_every_step():
    calls = []

    def query(word, index):
        calls.append(index.tolist())
        return np.tile([len(calls), 0, 0], (len(index), 1))

    p = loads("axiom = ?P(0,0,0)\n?P(x,y,z) -> ?P(x,y,z) ?H(0,0,0)\n")
    w = derive(p, 2, query=query)
    assert calls == [[0], [0, 1], [0, 1, 2]]
    assert _values(w, "?P").tolist() == [[3, 0, 0]]


@pytest.mark.parametrize(
    ("dialect", "text", "line", "column"),
    [
        ("classic", "iteration: 2\naxiom: F?P\nrule: F -> FF\n", 2, 9),
        ("classic", "iteration: 2\naxiom: F\nrule: F -> F?U\n", 3, 13),
        ("engine", "0 90 0.7\nX?H\nX > U\n", 2, 2),
        ("engine", "0 90 0.7\nX\nX > U?L\n", 3, 6),
    ],
)
def test_a_query_module_in_a_dialect_without_them_is_an_error(dialect, text, line, column):
    with pytest.raises(LSystemSyntaxError) as exc:
        loads(text, dialect=dialect)
    assert f"<string>:{line}:{column}:" in str(exc.value)
    assert "query module" in str(exc.value) and dialect in str(exc.value)
    # written apart, they are the two one-character symbols they always were
    spaced = text.replace("?", "? ")
    assert [m.symbol for m in loads(spaced, dialect=dialect).axiom][:1]


def test_the_topiary_example_is_clipped_to_its_ball():
    p = sylva.load(find("40-sylva-topiary-query").path)
    plant = grow(p)
    c, r = np.array([0.0, p.constants["C"], 0.0]), p.constants["R"]
    ends = np.linalg.norm(plant.geometry.seg_end - c, axis=1)
    # the trunk's 0.9 rises to the ball; every twig of 0.45 starts inside it
    assert ends.max() <= r + 0.45 + 1e-9
    assert plant.geometry.n_leaves > 100 and plant.geometry.n_segments > 1000


def test_the_command_line_and_the_studio_answer_the_queries(capsys, tmp_path):
    from sylva.cli import main
    from sylva.studio._limits import Limits
    from sylva.studio._work import new_derivation

    f = tmp_path / "stem.lsys"
    f.write_text("axiom = F(1) ?P(0,0,0) A\n?P(x,y,z) < A : y < 2.5 -> F(1) ?P(0,0,0) A\n")
    assert main(["derive", str(f), "-n", "5"]) == 0
    out = capsys.readouterr().out.strip()
    assert out == 'F(1)"?P"(0,1,0)F(1)"?P"(0,2,0)F(1)"?P"(0,3,0)A'
    p = loads(f.read_text())
    d = new_derivation(p, seed=1, limits=Limits(), trace=True)
    assert str(d.advance(5)) == out
