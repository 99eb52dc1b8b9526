"""Any text at all: the readers of the four dialects raise only SylvaError (never another
exception)."""

from __future__ import annotations

import warnings

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from sylva.errors import SylvaError, SylvaWarning
from sylva.lsystem.ast import Program
from sylva.lsystem.dialects import load, loads, parse_expr, parse_rule, parse_word

# Characters that matter to the four languages, mixed with anything at all.
_SYNTAX = list("()[]\"#,;<>:=-+*/%!&|^\\$~{}.'@ \t\n") + ["->", "->>", "**", "&&", "||", "<="]
_WORDS = ["axiom", "ignore", "bg", "rot", "seed", "steps", "turtle", "iteration:", "rule:", "x",
          # cpfg (L-Studio): its statements, preprocessor and arrows
          "Lsystem:", "derivation length:", "Axiom:", "endlsystem", "homomorphism",
          "decomposition", "maximum depth:", "consider:", "ignore:", "seed:", "#define ",
          "#include ", "#if ", "#endif", "-->", "/*", "*/", "//", "\n"]
_TOKENS = st.sampled_from(_SYNTAX + _WORDS + list("AFXabx019") + ["1.5", "-2", "e5", "True"])
_TEXT = st.one_of(
    st.text(max_size=80),
    st.lists(_TOKENS, max_size=40).map("".join),
    st.lists(st.one_of(_TOKENS, st.text(max_size=3)), max_size=30).map("".join),
)
_FUZZ = settings(max_examples=120, deadline=None, suppress_health_check=[HealthCheck.too_slow])


def _only_sylva_errors(fn, *args, **kwargs):
    try:
        with warnings.catch_warnings():  # a SylvaWarning is a message too, not a traceback
            warnings.simplefilter("ignore", SylvaWarning)
            out = fn(*args, **kwargs)
    except SylvaError as e:
        assert str(e)  # every error has a message
        return None
    return out


@pytest.mark.parametrize("dialect", ["lsys", "classic", "engine", "cpfg"])
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


_CPFG = st.lists(st.sampled_from([
    "Lsystem: 1\n", "derivation length: 3\n", "Axiom: F(1)\n", "F(x) --> F(x*2) [+F(1)]\n",
    "A < B > C : x > 1 --> D\n", "homomorphism\n", "X(x) --> ;F(x)\n", "endlsystem\n",
    "#define N 2\n", "#ifdef N\n", "#endif\n", "ignore: +-\n", "seed: 7\n", "/* a\n", "*/\n",
]) | _TEXT, max_size=12).map("".join)


@_FUZZ
@given(text=_CPFG)
def test_cpfg_statements_in_any_order_raise_only_sylva_errors(text):
    out = _only_sylva_errors(loads, text, dialect="cpfg")
    assert out is None or isinstance(out, Program)
