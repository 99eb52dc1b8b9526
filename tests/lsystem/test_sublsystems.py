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
