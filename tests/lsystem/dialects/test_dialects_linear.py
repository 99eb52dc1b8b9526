"""Reading a file stays linear in its length (issue 23): no per-line work over all known names.

The hint that lists the known names of an unknown-variable error was built for every
assignment and every rule, copying every name each time, so 80,000 assignments took 37 s.
These tests count that work instead of timing it.
"""

from __future__ import annotations

import pytest

from sylva.errors import LSystemSemanticError, LSystemSyntaxError
from sylva.lsystem.dialects import cpfg, lsysvis


def _lsys(n: int) -> str:
    lines = ["v0 = 1.5"]
    lines += [f"v{i} = v{i - 1} + 1" for i in range(1, n)]  # expressions: the full parser
    lines += [f"w{i} = {i}" for i in range(n)]  # literals: the fast path
    lines += ["axiom = A(v0)"]
    lines += [f"A(x) : x > v{i} -> A(x + w{i})" for i in range(n)]
    return "\n".join(lines) + "\n"


@pytest.fixture
def hints(monkeypatch):
    calls = []
    real = lsysvis._known_hint

    def counting(names, what):
        calls.append(what)
        return real(names, what)

    monkeypatch.setattr(lsysvis, "_known_hint", counting)
    return calls


@pytest.mark.parametrize("n", [50, 100])
def test_a_valid_file_never_builds_the_hint(hints, n):
    p = lsysvis.parse(_lsys(n))
    assert len(p.constants) == 2 * n and len(p.rules) == n
    assert p.constants[f"v{n - 1}"] == 1.5 + (n - 1)
    assert hints == []


def test_cpfg_defines_never_build_the_hint(hints):
    text = "\n".join(f"#define D{i} {i}*2" for i in range(100))
    text += "\nLsystem: 1\nAxiom: A(D1)\nA(x) --> A(x+D99)\nendlsystem\n"
    p = cpfg.parse(text)
    assert p.constants["D99"] == 198.0
    assert hints == []


def test_names_are_read_without_copying():
    """Membership in the rule's known names looks at the two mappings, copying neither."""

    class Counting(dict):
        iterations = 0

        def __iter__(self):
            Counting.iterations += 1
            return super().__iter__()

        def keys(self):
            Counting.iterations += 1
            return super().keys()

    known = lsysvis._Names({"x": 1}, Counting(a=1.0, b=2.0))
    assert "a" in known and "x" in known and "z" not in known
    assert Counting.iterations == 0
    assert list(known) == ["x", "a", "b"] and len(known) == 3


def test_the_hint_still_names_what_is_known():
    text = "\n".join(f"v{i} = {i}" for i in range(20)) + "\nx = v3 + nope\naxiom = F\n"
    with pytest.raises(LSystemSemanticError) as e:
        lsysvis.parse(text)
    msg = e.value.message
    assert "unknown variable 'nope'" in msg and "known here: v0, v1," in msg
    assert "v11 …" in msg and "v12" not in msg
    assert e.value.line == 21


def test_the_rule_hint_names_parameters_then_globals():
    with pytest.raises(LSystemSemanticError) as e:
        lsysvis.parse("g = 2\naxiom = A(1)\nA(x) -> A(x * y)\n")
    assert "known here: x, g" in e.value.message
    assert (e.value.line, e.value.column) == (3, 15)


@pytest.mark.parametrize(
    ("line", "value"),
    [("a = 2", 2.0), ("a=-0.5 # half", -0.5), ("  a = .5e1", 5.0), ("a = 1e3", 1000.0)],
)
def test_literal_assignments_read_as_before(line, value):
    assert lsysvis.parse(f"{line}\naxiom = F\n").constants == {"a": value}


@pytest.mark.parametrize(
    ("text", "where", "words"),
    [
        ("a = 1\na = 2\naxiom = F", (2, 1), "already assigned on line 1"),
        ("True = 1\naxiom = F", (1, 1), "is a constant"),
        ("a = 1e999\naxiom = F", (1, 5), "too large"),
        ("axiom = F\nF -> G\na = 1", (3, 1), "after the rules"),
        ("steps = 1.5\naxiom = F", (1, 9), "whole number"),
        ("bg = 1\naxiom = F", (1, 6), "3 components"),
        ("axiom = 1\nF -> F", None, None),
    ],
)
def test_literal_assignments_keep_their_checks(text, where, words):
    if where is None:  # a number is a module in the axiom
        assert [m.symbol for m in lsysvis.parse(text).axiom] == ["1"]
        return
    with pytest.raises(LSystemSyntaxError) as e:
        lsysvis.parse(text)
    assert words in e.value.message
    assert (e.value.line, e.value.column) == where
