"""Sub-L-systems (cpfg's ?(n) … $ calls, for compound plants): the productions after
``lsystem N:`` rewrite only the modules between a call ?(N) and its $."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import sylva
from sylva.errors import LSystemSyntaxError
from sylva.lsystem import Derivation, derive, loads, rewrite
from sylva.lsystem._sublsystems import scope
from sylva.lsystem.lstring import ModuleString
from sylva.plant import grow

COMPOUND = """
axiom = K A
A -> I [ ?(1) B $ ] A
lsystem 1:
B -> K [ ?(2) C $ ] B
K -> KK
lsystem 2:
C -> L
I -> II
"""


def _w(text: str) -> str:
    return str(ModuleString.from_text(text))


def test_a_compound_word_derived_by_hand():
    p = loads(COMPOUND)
    assert [r.lsystem for r in p.rules] == [0, 1, 1, 2, 2]
    words = [str(w) for w in sylva.iterate(p, 3)]
    # by hand (main: A; sub-L-system 1: B, K; 2: C, I).  K and I outside their
    # sub-L-systems stay; ?(n) belongs to the caller, $ to the callee.
    assert words == [
        _w("K A"),
        _w("K I[?(1)B$]A"),
        _w("K I[?(1)K[?(2)C$]B$] I[?(1)B$]A"),
        _w("K I[?(1)KK[?(2)L$]K[?(2)C$]B$] I[?(1)K[?(2)C$]B$] I[?(1)B$]A"),
    ]
    # the traced and the lineage roads, and one rewrite of the word, agree
    for kw in ({"trace": True}, {"lineage": True}):
        d = Derivation(p, **kw)
        assert str(d.advance(3)) == words[3]
    assert str(rewrite(p, ModuleString.from_text(words[2], d.alphabet), step=2)) == words[3]


def test_the_scope_of_every_module():
    w = ModuleString.from_text('A ?(2) B ?(3) C $ D $ E $ F ? G')
    # an unmatched $ is the main L-system's, a ? without parameters is no call
    assert scope(w).tolist() == [0, 0, 2, 2, 3, 3, 2, 2, 0, 0, 0, 0, 0]


def test_the_calls_draw_nothing():
    p = loads("axiom = F(1) [ ?(1) +(30) F(1) $ ] &(20) $ F(1)\nlsystem 1:\nX -> X\n")
    q = loads("axiom = F(1) [ +(30) F(1) ] &(20) F(1)")
    a, b = grow(p).geometry, grow(q).geometry
    np.testing.assert_allclose(a.seg_end, b.seg_end, atol=1e-12)


def test_sub_lsystems_are_written_and_read_back():
    p = loads(COMPOUND)
    text = sylva.dumps(p)
    assert "lsystem 1:" in text and "lsystem 2:" in text
    assert sylva.loads(text) == p


@pytest.mark.parametrize(
    ("line", "message"),
    [
        ("lsystem:", r"expected the lsystem's number: 'lsystem 1:'"),
        ("lsystem 0:", r"a sub-L-system is a whole number >= 1, got 0"),
        ("lsystem 1.5:", r"a sub-L-system is a whole number >= 1, got 1.5"),
    ],
)
def test_a_bad_sub_lsystem_header_is_an_error(line, message):
    with pytest.raises(LSystemSyntaxError, match=message):
        loads(f"axiom = A\n{line}\nA -> B\n", dialect="lsys")


bodies = st.text(alphabet="AB", min_size=0, max_size=3)


@settings(max_examples=40, deadline=None)
@given(
    st.lists(st.tuples(st.integers(0, 2), st.sampled_from("AB"), bodies, st.integers(1, 3),
                       st.sampled_from(["", "[?(1)B$]", "?(2)A$", "[?(1)?(2)B$A$]"])),
             min_size=1, max_size=6),
    st.integers(0, 2**32),
)
def test_every_road_gives_the_same_word_with_sub_lsystems(rules, seed):
    lines: dict[int, list[str]] = {0: [], 1: [], 2: []}
    for k, a, b, w, call in rules:
        lines[k].append(f"{a} ->({w}) {b}{call}")
    text = "axiom = A ?(1) B $ ?(2) A [ B ] $\n" + "\n".join(lines[0])
    for k in (1, 2):
        if lines[k]:
            text += f"\nlsystem {k}:\n" + "\n".join(lines[k])
    p = loads(text)
    plain = derive(p, 3, seed=seed)
    for kw in ({"trace": True}, {}):
        d = Derivation(p, seed=seed, **kw)
        for _ in range(3):
            d.advance(1)
        assert d.word == plain


def test_the_compound_inflorescence_example_keeps_each_rule_in_its_sub_lsystem():
    from sylva.data import find

    p = sylva.load(find("43-sylva-compound-inflorescence").path)
    w = sylva.derive(p)
    lengths = [v[0] for s, v in w if s == "F"]
    # the main axis: F(0.6) and six F(0.45), untouched by sub-L-system 1's F rule; the
    # racemes' internodes start at 0.2 and elongate by 1.15 a step up to 0.35 and more
    assert lengths.count(0.45) == 6 and lengths.count(0.6) == 1
    raceme = [x for x in lengths if x not in (0.45, 0.6)]
    assert raceme and min(raceme) >= 0.2 and max(raceme) > 0.35
    assert any(abs(x - 0.2 * 1.15**3) < 1e-9 for x in raceme)
    # flowers (sub-L-system 2) opened into five petals each
    assert sum(1 for s, _ in w if s == "~") % 5 == 0 and any(s == "~" for s, _ in w)


def test_a_scaled_call_draws_its_sub_lsystem_s_times_as_large():
    # cpfg: ?(n, s) multiplies lengths (with and without a parameter), widths set by !(w),
    # surfaces and spheres by s up to its $, and the width at the call by s (back at $)
    p = loads("turtle = abop\nrot = 90\nthick = 0.2\naxiom = F(1) ?(1, 0.5) A $ F(1)\n"
              "lsystem 1:\nA -> F F(2) [ +F(2) ] [ ?(2, 0.5) B $ ] !(0.4) ~(2) @O(1)\n"
              "lsystem 2:\nB -> F\n")  # fmt: skip
    g = grow(p, 2).geometry
    ends = g.seg_end.round(12).tolist()
    # F(1): 0 -> 1; F: 1 -> 1.5; F(2): -> 2.5; [+F(2)]: 1 along -X; [?(2,0.5) F]: 0.25;
    # after $: F(1) at full size from 2.5 -> 3.5
    assert ends == [[0.0, 1.0, 0.0], [0.0, 1.5, 0.0], [0.0, 2.5, 0.0], [-1.0, 2.5, 0.0],
                    [0.0, 2.75, 0.0], [0.0, 3.5, 0.0]]  # fmt: skip
    radius = g.seg_radius[:, 0]
    # width 0.2 (radius 0.1), x 0.5 in 1, x 0.25 in 2; !(0.4) in 1 sets 0.4 x 0.5 = 0.2,
    # and the end of 1 gives it back x 2: the last F has radius 0.2
    assert np.allclose(radius, [0.1, 0.05, 0.05, 0.05, 0.025, 0.2])
    assert g.leaf_size.tolist() == [1.0] and g.leaf_pos.round(12).tolist() == [[0.0, 2.5, 0.0]]
    # the sphere @O(1) in sub-L-system 1 has diameter 0.5
    sphere = g.poly_vertices - [0.0, 2.5, 0.0]
    assert np.isclose(np.linalg.norm(sphere, axis=1).max(), 0.25)
    # a call without a scale, or with 1, draws as before
    same = loads("turtle = abop\naxiom = F ?(1) F $ ?(1, 1) F $ F\n")
    assert grow(same, 0).geometry.seg_end[:, 1].tolist() == [1.0, 2.0, 3.0, 4.0]


def test_render_rules_of_a_sub_lsystem_draw_only_its_modules():
    # cpfg draws each sub-L-system through its own homomorphism: a ->> rule after
    # 'lsystem 1:' rewrites only the modules between ?(1) and $, the others stay
    p = loads("axiom = A ?(1) A $ A\nlsystem 1:\nA ->> B\n")
    d = Derivation(p)
    assert str(d.render_word()) == _w("A ?(1) B ? A")  # the silent $ is a bare ?
    assert str(sylva.lsystem.render_word(p, d.word)) == _w("A ?(1) B ? A")
