"""The seed 000 format against the thesis's input files (Tables 5.1–5.3) and the Hilbert curve."""

from __future__ import annotations

import pytest
from _dialect_examples import (
    BUSH_STOCHASTIC,
    BUSH_WITH_LEAVES,
    BUSH_WITHOUT_LEAVES,
    HILBERT_3D,
    counts,
    rewrite,
)

from sylva.errors import LSystemSyntaxError
from sylva.lsystem.ast import Module, Num, Pattern, Span
from sylva.lsystem.dialects import classic, loads


def test_bush_without_leaves_table_5_1():
    p = classic.parse(BUSH_WITHOUT_LEAVES, "bush.txt")
    assert p.dialect == "classic" and p.name == "bush" and p.steps == 7
    assert p.settings == {"turtle": "classic", "rot": 22.5}
    assert p.axiom == (Module("A"),)
    a, f, s = p.rules
    assert a.predecessor == Pattern("A")
    assert "".join(m.symbol for m in a.successor) == "[&FA]/////[&FA]////////[&FA]"
    assert "".join(m.symbol for m in f.successor) == "S/////F"  # spaces are ignored
    assert s.predecessor == Pattern("S") and s.successor == (Module("F"),)
    assert a.span == Span(11, 7, "bush.txt")
    # seed 000 §3.6: at n = 7 length 40888, F = 3891, A = 2187, S = 1284, '[' = 3279
    word = rewrite(p, 7)
    c = counts(word)
    assert (len(word), c["F"], c["A"], c["S"], c["["]) == (40888, 3891, 2187, 1284, 3279)


def test_bush_with_leaves_table_5_2_utf8_comment_and_optional_settings():
    p = loads(BUSH_WITH_LEAVES)
    assert p.dialect == "classic"
    assert p.settings == {"turtle": "classic", "rot": 22.5, "reduction": 0.95, "radius": 0.3}
    # seed 000 §3.7: at n = 7 length 49915, F = 3891, L = 1284, X = 2607, '[' = 4563
    word = rewrite(p, 7)
    c = counts(word)
    assert (len(word), c["F"], c["L"], c["X"], c["["]) == (49915, 3891, 1284, 2607, 4563)


def test_bush_stochastic_table_5_3_equal_weights():
    p = loads(BUSH_STOCHASTIC)
    by_symbol: dict[str, int] = {}
    for r in p.rules:
        by_symbol[r.predecessor.symbol] = by_symbol.get(r.predecessor.symbol, 0) + 1
        assert r.weight == Num(1.0) and r.tier == 2
    assert by_symbol == {"A": 4, "F": 1, "S": 2, "X": 2}
    assert "".join(m.symbol for m in p.rules[3].successor) == "[&FXA]////////[&FXA]////////"


def test_hilbert_curve():
    p = loads(HILBERT_3D)
    assert p.steps == 2 and p.settings["rot"] == 90.0
    rules = {r.predecessor.symbol: "".join(m.symbol for m in r.successor) for r in p.rules}
    assert rules["A"] == "B-F+CFC+F-D&F^D-F+&&CFC+F+B//"
    assert rules["B"] == "A&F^CFB^F^D^^-F-D^|F^B|FC^F^A//"
    assert rules["C"] == "|D^|F^B-F+C^F^A&&FA&F^C+F+B^F^D//"
    assert rules["D"] == "|CFB-F+B|FA&F^A&&FB-F+B|FC//"
    # seed 000 §3.2: lengths 29, 271, 2155 and 7, 63, 511 segments for n = 1, 2, 3
    for n, length, segments in [(1, 29, 7), (2, 271, 63), (3, 2155, 511)]:
        word = rewrite(p, n)
        assert (len(word), word.count("F")) == (length, segments)


def test_keywords_in_any_case_and_thickness():
    p = loads("ITERATION: 3\nangle: 25.7 ; degrees\nThickness: 2\naxiom:F\nRULE: F -> FF")
    assert p.steps == 3
    assert p.settings == {"turtle": "classic", "rot": 25.7, "thickness": 2.0}
    assert p.rules[0].successor == (Module("F"), Module("F"))


@pytest.mark.parametrize(
    ("text", "line", "words"),
    [
        ("RULE: F -> FF\naxiom:F", 2, "'axiom' after 'rule' (line 1)"),
        ("iteration: 2\naxiom: F\nangle: 30\n", 3, "'angle' after 'axiom' (line 2)"),
        ("angle: 30\niteration: 2\naxiom: F\n", 2, "'iteration' after 'angle' (line 1)"),
        ("radius: 1\nreduction: 0.9\naxiom: F\n", 2, "'reduction' after 'radius'"),
        ("axiom: F\nrule: F -> G\nradius: 1\n", 3, "'radius' after 'rule' (line 2)"),
    ],
)
def test_keywords_out_of_the_thesis_order_are_an_error(text, line, words):
    # seed 000, Table 3.2: iteration, angle, reduction, radius, axiom, rules
    with pytest.raises(LSystemSyntaxError) as e:
        classic.parse(text)
    assert (e.value.line, e.value.column) == (line, 1) and words in e.value.message


@pytest.mark.parametrize("rule", ["rule: F ->", "rule: F ->   ; nothing", "rule:F->"])
def test_an_empty_successor_is_an_error(rule):
    # seed 000: "the successor is non-empty (at least one symbol)"
    with pytest.raises(LSystemSyntaxError) as e:
        classic.parse(f"axiom: F\n{rule}\n")
    assert e.value.line == 2 and "the successor is empty" in e.value.message
    assert e.value.column == rule.index("->") + 3


def test_minimal_file():
    p = classic.parse("axiom: F\nrule: F -> G\n")
    assert p.steps is None and p.settings == {"turtle": "classic"}


def test_format_refuses_an_empty_successor():
    p = loads("axiom = F\nF ->\n")
    with pytest.raises(ValueError, match="empty successor"):
        classic.format(p)


def test_every_printable_character_but_comment_and_quote_is_a_symbol():
    p = classic.parse("axiom: (,)<>:=#{}.F\n")
    assert [m.symbol for m in p.axiom] == list("(,)<>:=#{}.F")


def test_literal_backslash_ampersand_is_two_symbols():
    # seed 000 §8.1: the LaTeX artefact `\&` would mean roll right, then pitch down
    p = classic.parse("axiom: A\nrule: A -> [\\&FA]\n")
    assert [m.symbol for m in p.rules[0].successor] == ["[", "\\", "&", "F", "A", "]"]


def test_format_writes_the_classic_format_back():
    p = classic.parse(BUSH_WITH_LEAVES)
    text = classic.format(p)
    assert text.startswith("iteration: 7\nangle: 22.5\nreduction: 0.95\nradius: 0.3\naxiom: A\n")
    assert classic.parse(text) == p


def test_format_refuses_what_the_format_cannot_hold():
    with pytest.raises(ValueError, match="cannot write the module"):
        classic.format(loads("axiom = F(1)"))
    with pytest.raises(ValueError, match="cannot write the rule"):
        classic.format(loads("axiom = F\nA < F -> G"))
    with pytest.raises(ValueError, match="weights"):
        classic.format(loads("axiom = F\nF ->(2) G"))
