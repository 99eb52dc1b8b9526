"""The engine format of seed 004 against the acacia and the parser test vector (§4.7–4.8)."""

from __future__ import annotations

import pytest
from _dialect_examples import ACACIA, TEST_VECTOR, rewrite

from sylva.errors import LSystemSemanticError
from sylva.lsystem.ast import Module, Num, Pattern, Span
from sylva.lsystem.dialects import engine, load_all, loads


def test_parser_test_vector():
    p = engine.parse(TEST_VECTOR)
    assert p.dialect == "engine"
    assert p.settings == {"turtle": "engine", "yaw": 0.0, "pitch": 90.0, "shrink": 0.7}
    assert p.axiom == (Module("X"),)
    assert rewrite(p, 0) == "X"
    assert rewrite(p, 1) == "U[&X][^X]UX"
    assert rewrite(p, 2) == "UU[&U[&X][^X]UX][^U[&X][^X]UX]UUU[&X][^X]UX"


def test_acacia():
    p = engine.parse(ACACIA, "acacia.txt")
    assert p.name == "acacia"
    assert p.settings == {"turtle": "engine", "yaw": 45.0, "pitch": 45.0, "shrink": 0.8}
    assert "".join(m.symbol for m in p.axiom) == "^uA1S&F+F+F+F"
    preds = [r.predecessor.symbol for r in p.rules]
    assert preds == ["U"] + ["A"] * 6 + ["E"] * 3
    assert all(r.weight == Num(1.0) and not r.has_context for r in p.rules)
    assert "".join(m.symbol for m in p.rules[7].successor) == "x[++++UE1S&F+F+F+F]+UE"
    assert p.rules[0].span == Span(5, 1, "acacia.txt")


def test_several_systems_in_one_file():
    text = ACACIA + "\n# the second one\n" + TEST_VECTOR
    a, b = load_all(text, filename="plants.txt")
    assert a == engine.parse(ACACIA) and b == engine.parse(TEST_VECTOR)
    assert (a.name, b.name) == ("plants[0]", "plants[1]")
    assert loads(text, index=1) == b
    with pytest.raises(LSystemSemanticError, match="holds 2 L-systems"):
        loads(text)
    with pytest.raises(LSystemSemanticError, match="holds 2 L-systems"):
        engine.parse(text)


def test_lenient_whitespace_and_comments():
    text = (
        "  1.5\t-2  3e-1 \n\n   # comment\n  X Y  \nX>U [ & X ]\n  U   >   UU   # trailing\nY >\n"
    )
    p = engine.parse(text)
    assert p.settings == {"turtle": "engine", "yaw": 1.5, "pitch": -2.0, "shrink": 0.3}
    assert p.axiom == (Module("X"), Module("Y"))
    assert [m.symbol for m in p.rules[0].successor] == list("U[&X]")
    assert p.rules[1].successor == (Module("U"), Module("U"))
    assert p.rules[2].successor == ()
    assert p.rules[0].predecessor == Pattern("X")


def test_greater_than_as_a_letter():
    p = engine.parse("0 0 1\n>\n> > >F\n")
    assert p.rules[0].predecessor == Pattern(">")
    assert [m.symbol for m in p.rules[0].successor] == [">", "F"]


def test_empty_file_holds_no_systems():
    assert engine.parse_all("# nothing\n\n") == []
    with pytest.raises(LSystemSemanticError, match="holds 0"):
        loads("# nothing", dialect="engine")


def test_format_round_trip():
    programs = load_all(ACACIA + TEST_VECTOR)
    assert engine.parse_all(engine.format(programs)) == programs
    assert engine.parse(engine.format(programs[1])) == programs[1]
