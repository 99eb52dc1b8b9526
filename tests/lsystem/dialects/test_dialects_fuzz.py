"""Any text at all: the readers raise only SylvaError (never another exception)."""

from __future__ import annotations

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from sylva.errors import SylvaError
from sylva.lsystem.ast import Program
from sylva.lsystem.dialects import load, loads, parse_expr, parse_rule, parse_word

# Characters that matter to the three languages, mixed with anything at all.
_SYNTAX = list("()[]\"#,;<>:=-+*/%!&|^\\$~{}.'@ \t\n") + ["->", "->>", "**", "&&", "||", "<="]
_WORDS = ["axiom", "ignore", "bg", "rot", "seed", "steps", "turtle", "iteration:", "rule:", "x"]
_TOKENS = st.sampled_from(_SYNTAX + _WORDS + list("AFXabx019") + ["1.5", "-2", "e5", "True"])
_TEXT = st.one_of(
    st.text(max_size=80),
    st.lists(_TOKENS, max_size=40).map("".join),
    st.lists(st.one_of(_TOKENS, st.text(max_size=3)), max_size=30).map("".join),
)
_FUZZ = settings(max_examples=120, deadline=None, suppress_health_check=[HealthCheck.too_slow])


def _only_sylva_errors(fn, *args, **kwargs):
    try:
        out = fn(*args, **kwargs)
    except SylvaError as e:
        assert str(e)  # every error has a message
        return None
    return out


@pytest.mark.parametrize("dialect", ["lsys", "classic", "engine"])
@_FUZZ
@given(text=_TEXT)
def test_any_text_raises_only_sylva_errors(dialect, text):
    out = _only_sylva_errors(loads, text, dialect=dialect)
    assert out is None or isinstance(out, Program)


@_FUZZ
@given(text=_TEXT)
def test_load_any_text_raises_only_sylva_errors(text):
    out = _only_sylva_errors(load, text)
    assert out is None or isinstance(out, Program)


@_FUZZ
@given(text=_TEXT)
def test_axiom_and_rule_lines_raise_only_sylva_errors(text):
    _only_sylva_errors(loads, "axiom = " + text)
    _only_sylva_errors(loads, "x = 1\naxiom = F\nF -> " + text)
    _only_sylva_errors(loads, "axiom = F\n" + text + " -> F")
    _only_sylva_errors(loads, "axiom = F\nA(x) : " + text + " -> F")


@_FUZZ
@given(text=_TEXT)
def test_helpers_raise_only_sylva_errors(text):
    _only_sylva_errors(parse_rule, text)
    _only_sylva_errors(parse_expr, text)
    _only_sylva_errors(parse_word, text)
    _only_sylva_errors(parse_word, text, evaluate=True)
