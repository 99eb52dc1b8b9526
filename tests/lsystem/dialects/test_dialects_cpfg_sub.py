"""cpfg's sub-L-systems (its manual §7.2): several ``Lsystem: N … endlsystem`` blocks in one
file, called by ``?(N, s) … $`` from successors.  Small models of our own; each derived
word is worked out by hand from cpfg's rules:

* the first L-system is the main one: its axiom and derivation length are the model's, the
  others' are ignored (they serve a sub-L-system run alone);
* the modules between ``?(N, s)`` and its ``$`` are rewritten by N's productions only (and
  drawn through N's homomorphism); ``?(N, s)`` belongs to the caller, ``$`` to N;
* a module no production of its L-system matches is copied;
* the turtle draws a sub-L-system ``s`` times as large.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import sylva
from sylva.errors import SylvaError, SylvaWarning
from sylva.lsystem import Derivation
from sylva.lsystem.dialects import cpfg
from sylva.lsystem.lstring import ModuleString
from sylva.plant import grow

THREE = """\
#define S 0.5
Lsystem: 1
derivation length: 3
Axiom: A
A --> E B ?(2,S) C $ A
B --> BB
endlsystem

Lsystem: 2
derivation length: 9
Axiom: Z
C --> B D ?(3) E $
B --> X
endlsystem

Lsystem: 3
derivation length: 1
Axiom: E
E --> EE
D --> Y
homomorphism
E --> G
endlsystem
"""


def _w(text: str) -> str:
    return str(ModuleString.from_text(text))


def test_three_lsystems_derived_by_hand():
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # a second L-system is read, not warned about
        p = cpfg.parse(THREE, "three.l", view=False)
    assert p.steps == 3  # the main L-system's; 2's '9' and 3's '1' are ignored
    assert [(r.predecessor.symbol, r.lsystem) for r in p.productions] == [
        ("A", 0), ("B", 0), ("C", 2), ("B", 2), ("E", 3), ("D", 3)]  # fmt: skip
    words = [str(w) for w in sylva.iterate(p, 3)]
    # main: A, B; 2: C, B; 3: E, D.  E in the main L-system and D in 2 have no
    # production there: they are copied.  2's axiom Z appears nowhere.
    assert words == [
        _w("A"),
        _w("E B ?(2,0.5) C $ A"),
        _w("E BB ?(2,0.5) B D ?(3) E $ $ E B ?(2,0.5) C $ A"),
        _w("E BBBB ?(2,0.5) X D ?(3) EE $ $ E BB ?(2,0.5) B D ?(3) E $ $ E B ?(2,0.5) C $ A"),
    ]
    # written as .lsys (lsystem 2: / lsystem 3: sections) and read back, the same words
    assert str(sylva.derive(sylva.loads(sylva.dumps(p)), 3)) == words[3]
    d = Derivation(p)
    d.advance(3)
    # 3's homomorphism E --> G draws only 3's E's; the main L-system's E stay E, and the
    # calls' $ draw nothing (sylva writes a silent $ as a bare ?)
    assert str(d.render_word()) == _w(
        "E BBBB ?(2,0.5) X D ?(3) GG ? ? E BB ?(2,0.5) B D ?(3) G ? ? E B ?(2,0.5) C ? A")


def test_each_lsystem_decomposes_its_own_modules():
    # after each step every L-system's decomposition applies to its own modules only
    text = ("Lsystem: 1\nderivation length: 1\nAxiom: A?(2)A$\nA --> X\ndecomposition\n"
            "X --> K\nendlsystem\nLsystem: 2\nAxiom: A\nA --> X\ndecomposition\n"
            "X --> M\nendlsystem\n")  # fmt: skip
    assert str(sylva.derive(cpfg.parse(text, view=False))) == _w("K?(2)M$")


def test_a_call_back_to_the_main_lsystem():
    # cpfg numbers the main L-system by its label too: ?(1) inside 2 calls it back
    text = ("Lsystem: 1\nderivation length: 3\nAxiom: A\nA --> ?(2)B$\nendlsystem\n"
            "Lsystem: 2\nAxiom: B\nB --> ?(1)A$C\nendlsystem\n")  # fmt: skip
    p = cpfg.parse(text, view=False)
    words = [str(w) for w in sylva.iterate(p, 3)]
    assert words[1:] == [_w("?(2)B$"), _w("?(2)?(1)A$C$"), _w("?(2)?(1)?(2)B$$C$")]


def test_a_null_context_is_no_context():
    # cpfg reads '*' as a context as the empty one: '* < B' is 'B', 'A > *' is 'A'
    text = ("Lsystem: 1\nderivation length: 1\nAxiom: AB\n* < B --> C\nA > * : * --> D\n"
            "endlsystem\n")  # fmt: skip
    p = cpfg.parse(text, view=False)
    assert str(sylva.derive(p)) == "DC"
    assert not any(r.has_context for r in p.rules)


@pytest.mark.parametrize(
    ("line", "want"),
    [
        ("", "A+X?(2)A+B$"),  # 2 has no ignore: (cpfg: it considers all): '+' hides the A
        ("consider: AB\n", "A+X?(2)A+Y$"),  # 2 skips '+' too
        ("ignore: +\n", "A+X?(2)A+Y$"),  # the main one's
        ("ignore: A\n", "A+X?(2)A+B$"),  # 2 skips the A itself: no A on B's left
    ],
)
def test_each_lsystem_matches_contexts_with_its_own_ignore(line, want):
    # cpfg keeps an ignore table per L-system: the main one's 'ignore: +' lets its
    # A < B see through '+'; sub-L-system 2's productions match with 2's own table
    text = ("Lsystem: 1\nderivation length: 1\nignore: +\nAxiom: A+B?(2)A+B$\n"
            "A < B --> X\nendlsystem\n"
            f"Lsystem: 2\nAxiom: B\n{line}A < B --> Y\nendlsystem\n")
    p = cpfg.parse(text, view=False)
    assert str(sylva.derive(p)) == _w(want)
    for kw in ({"trace": True}, {"lineage": True}):  # the other roads agree
        assert str(Derivation(p, **kw).advance(1)) == _w(want)


def test_a_defined_macro_calls_a_sub_lsystem_from_an_included_file(tmp_path):
    # vlab's Sedge: '#define SPIKE ?(2,1.25)s$' before the main L-system, the
    # sub-L-system in a file #included after it, with #defines of its own
    (tmp_path / "spike.l").write_text("#define RATE 2\nlsystem: 2\nderivation length: 5\n"
                                      "axiom: s\ns --> F(1)\nF(x) --> F(x*RATE)\n"
                                      "endlsystem\n")  # fmt: skip
    main = tmp_path / "plant.l"
    main.write_text("#define SPIKE ?(2,1.25)s$\nlsystem: 1\nderivation length: 3\n"
                    "axiom: A\nA --> F(1)SPIKE\nF(x) --> F(x+1)\nendlsystem\n"
                    '#include "spike.l"\n')  # fmt: skip
    p = cpfg.parse(main.read_text(), str(main), view=False)
    # step 1: F(1) ?(2,1.25) s $; 2: F(2) ?(2,1.25) F(1) $ (main's F(x+1), 2's s);
    # 3: F(3) ?(2,1.25) F(2) $ (2's F(x*RATE) doubles)
    assert str(sylva.derive(p)) == _w("F(3)?(2,1.25)F(2)$")


def test_a_scaled_call_draws_its_sub_lsystem_smaller():
    text = ("Lsystem: 1\nderivation length: 2\nAxiom: F(1)A\nA --> ?(2,0.5)F(1)B$F(1)\n"
            "endlsystem\nLsystem: 2\nAxiom: B\nB --> F(2)\nendlsystem\n")  # fmt: skip
    p = cpfg.parse(text, view=False)
    ends = grow(p).geometry.seg_end[:, 1].round(12).tolist()
    # the word F(1) ?(2,0.5) F(1) F(2) $ F(1): F(1) to 1; in 2 at half size F(1) to 1.5
    # and F(2) to 2.5; after $ at full size F(1) to 3.5
    assert ends == [1.0, 1.5, 2.5, 3.5]
    assert np.allclose(grow(p).geometry.seg_end[:, [0, 2]], 0.0)


@pytest.mark.parametrize(
    ("text", "where", "message"),
    [
        ("Lsystem: 1\nAxiom: A\nA --> F[?(3,0.5)B$]\nendlsystem\n"
         "Lsystem: 2\nAxiom: B\nendlsystem\n", ":3:11:",
         r"\?\(3, s\) calls L-system 3, which this file does not define; expected one of "
         r"its L-systems' numbers \(1, 2\)"),
        ("Lsystem: 1\nAxiom: F?(2)A$\nendlsystem\n", ":2:11:", r"calls L-system 2"),
        ("Lsystem: 1\nAxiom: A\nendlsystem\nLsystem: 1\nAxiom: B\nendlsystem\n", ":4:1:",
         r"L-system 1 is already defined \(the main L-system's label\)"),
        ("Lsystem: 1\nAxiom: A\nendlsystem\nLsystem: leaf\nAxiom: B\nendlsystem\n", ":4:1:",
         r"a sub-L-system's label is its number"),
        ("Lsystem: 1\nAxiom: A\nendlsystem\nLsystem: 2\nAxiom: B\nStart: {x=1;}\n"
         "endlsystem\n", ":6:1:", r"'Start:' block in sub-L-system 2 is not supported"),
        ("Lsystem: 1\nAxiom: A\ngroup 1:\nA --> B\nendlsystem\n", ":3:1:",
         r"cpfg's 'group' is not supported.*cpfg has no production groups"),
    ],
)
def test_bad_sub_lsystems_are_errors_with_the_place(text, where, message):
    with pytest.raises(SylvaError, match=message) as e:
        cpfg.parse(text, "bad.l", view=False)
    assert str(e.value).startswith(f"bad.l{where}")


def test_a_call_computed_from_a_parameter_is_not_checked_when_read():
    # ?(n) with n a module's parameter: cpfg finds the L-system when the call is made
    text = ("Lsystem: 1\nderivation length: 1\nAxiom: A(2)\nA(n) --> ?(n)B$\nendlsystem\n"
            "Lsystem: 2\nAxiom: B\nB --> C\nendlsystem\n")  # fmt: skip
    assert str(sylva.derive(cpfg.parse(text, view=False))) == _w("?(2)B$")


def test_an_lsystem_without_seed_takes_the_first_applicable_production():
    # lsys_input.y: without seed: an L-system is deterministic, and generate.c's FindProd
    # takes the first production in the file that applies, whatever its kind (a draw
    # among applicable ones would make vlab's Sedge start its male spike only sometimes:
    # A(a,t) : a==30 and A(a,t) : t<10 both apply at a = 30)
    text = ("Lsystem: 1\nderivation length: 1\nAxiom: A(1)A(5)BBC\nA(x) : x>3 --> X\n"
            "A(x) : x>0 --> Y\nB --> P : 0.5\nB --> Q : 0.5\nC --> R\nB < C --> S\n"
            "endlsystem\n")  # fmt: skip
    # cpfg warns "Probability given for deterministic production"; so does sylva, once,
    # at the first such production (line 6), instead of ignoring it without a word
    with pytest.warns(SylvaWarning, match=r"^b\.l:6:1: probability given .* without 'seed:'"):
        p = cpfg.parse(text, "b.l", view=False)
    for seed in range(4):  # A(1): only the second applies; A(5): both, the first wins;
        # B: P, its probability ignored; C: the context-free rule comes first in the file
        assert str(sylva.derive(p, seed=seed)) == "YXPPR"
    assert str(Derivation(p, trace=True).advance(1)) == "YXPPR"
    # with a seed: line the L-system is stochastic: the productions are drawn again
    q = cpfg.parse(text.replace("Axiom:", "seed: 7\nAxiom:"), view=False)
    assert "first_match" not in q.settings
    assert len({str(sylva.derive(q, seed=s))[2:4] for s in range(12)}) > 1
