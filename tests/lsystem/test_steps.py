"""Step counts are checked before any step is derived (issue 23: ``steps = 1e23`` ran forever).

Two checks: a documented maximum (:data:`MAX_STEPS`), and the module limit against a lower
bound of the word's growth (:func:`growth_floor`), which is exact for D0L systems.
"""

from __future__ import annotations

import numpy as np
import pytest

from sylva.errors import GrowthLimitError, LSystemSemanticError, StepsError
from sylva.lsystem import Derivation, derive, iterate, loads
from sylva.lsystem._steps import growth_floor
from sylva.lsystem.ast import MAX_STEPS
from sylva.lsystem.engine import _compiled, check_steps


@pytest.mark.parametrize(
    ("text", "dialect", "where"),
    [
        ("steps = 1e23\naxiom = F\nF -> F\n", "lsys", (1, 9)),
        (f"axiom = F\nsteps = {MAX_STEPS + 1}\n", "lsys", (2, 9)),
        ("iteration: 100000000000000000000000\naxiom: F\n", "classic", (1, 12)),
        ("Lsystem: 1\nderivation length:  1e23\nAxiom: F\nendlsystem\n", "cpfg", (2, 21)),
    ],
)
def test_a_file_asking_for_too_many_steps_is_refused_where_it_says_so(text, dialect, where):
    with pytest.raises(LSystemSemanticError) as e:
        loads(text, dialect=dialect, filename="plant.x")
    assert (e.value.line, e.value.column) == where
    assert f"at most {MAX_STEPS:,}" in e.value.message and e.value.filename == "plant.x"


def test_the_maximum_itself_is_accepted():
    assert loads(f"steps = {MAX_STEPS}\naxiom = F\n").steps == MAX_STEPS


def test_an_api_count_above_the_maximum_is_refused_before_deriving():
    p = loads("axiom = F\nF -> F\n")  # never grows: only the maximum can stop it
    with pytest.raises(StepsError) as e:
        derive(p, 10**23)
    assert e.value.fits is None and "at most 100,000" in str(e.value)
    with pytest.raises(StepsError):
        next(iterate(p, MAX_STEPS + 1))
    with pytest.raises(StepsError):
        Derivation(p).advance(10**23)
    assert len(derive(p, 50)) == 1


@pytest.mark.parametrize(
    ("text", "limit", "first", "exact"),
    [
        ("axiom = F\nF -> FF", 1000, 10, True),  # 2**10 > 1000: exact for D0L
        ("axiom = F\nF -> FF", 1024, 11, True),
        ("axiom = a\na -> ab\nb -> a", 1000, 15, True),  # Fibonacci: 987 at step 14
        ("axiom = A(1)\nA(x) -> A(x + 1)[B(x)]A(x / 2)", 10_000, 12, True),  # parameters
        ("axiom = F\nF ->(2) FFF\nF -> FF", 1000, 10, False),  # stochastic: at least doubles
        ("axiom = A\nA -> AB", 1000, 1000, True),  # linear, extrapolated past 64 steps
        ("axiom = A\nA -> AB\nB -> BC", 5000, 100, False),  # quadratic, bounded linearly
    ],
)
def test_growth_floor_finds_a_step_by_which_every_derivation_passed_the_limit(
    text, limit, first, exact
):
    p = loads(text)
    comp = _compiled(p)
    counts = np.bincount(comp.axiom.ids, minlength=len(comp.alphabet))
    k = growth_floor(comp.productions, counts, MAX_STEPS, limit)
    assert k is not None and k >= first  # never before the word can have passed it
    assert k == first if exact else k <= 2 * first
    assert len(derive(p, k, limit=10**9, seed=1)) > limit  # a true bound
    assert growth_floor(comp.productions, counts, k - 1, limit) is None


@pytest.mark.parametrize(
    "text",
    [
        "axiom = F\nF -> F",  # stays
        "axiom = F\nF -> FF\nF ->",  # may vanish
        "axiom = A(1)\nA(x) : x < 3 -> A(x + 1)B",  # a condition may stop it
        "axiom = BA\nB < A -> AA",  # a context may not match
        "axiom = F\nF ->(0) FF",  # a rule of weight 0 never applies
        "axiom = F%\nF -> FF",  # the cut removes modules
    ],
)
def test_growth_floor_claims_nothing_it_cannot_prove(text):
    p = loads(text) if "->(0)" not in text else _weight_zero_program()
    comp = _compiled(p)
    counts = np.bincount(comp.axiom.ids, minlength=len(comp.alphabet))
    assert growth_floor(comp.productions, counts, MAX_STEPS, 10) is None


def _weight_zero_program():
    from sylva.lsystem.ast import Module, Num, Pattern, Program, Rule

    rule = Rule(Pattern("F"), (Module("F"), Module("F")), weight=Num(0.0))
    return Program(axiom=(Module("F"),), rules=(rule,))


def test_more_steps_than_the_limit_allows_is_an_error_up_front_naming_the_file(tmp_path):
    f = tmp_path / "grow.lsys"
    f.write_text("axiom = A\nsteps  =  90000\nA -> AB\n")
    from sylva.lsystem import load

    p = load(f)
    with pytest.raises(StepsError) as e:
        check_steps(p, limit=1000)
    err = e.value
    assert (err.filename, err.line, err.column) == (str(f), 2, 11)
    text = str(err)
    assert text.startswith(f"{f}:2:11: steps = 90,000:") and "steps  =  90000" in text
    assert "by step 1,000" in text and err.fits == 999


def test_an_option_is_named_when_the_count_is_not_the_files():
    p = loads("steps = 3\naxiom = F\nF -> FF\n")
    with pytest.raises(StepsError) as e:
        check_steps(p, 40, limit=1000, option="-n")
    assert str(e.value).startswith("-n 40: every word") and e.value.line is None
    assert check_steps(p, limit=1000) == 3


def test_derive_keeps_the_last_word_that_fits_when_growth_is_fast():
    p = loads("axiom = F\nF -> FF")
    with pytest.raises(GrowthLimitError) as e:
        derive(p, 30, limit=1000)
    assert isinstance(e.value, StepsError)
    assert e.value.step == 9 and len(e.value.word) == 512
