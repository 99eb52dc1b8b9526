"""Expressions: seed 001 §3.4 semantics, compiled without eval."""

import math

import numpy as np
import pytest

from sylva.errors import LSystemSemanticError
from sylva.lsystem.ast import Binary, Call, Num, Unary, Var
from sylva.lsystem.expr import compile_expr, evaluate_constant, truth


def ev(expr, **env):
    names = tuple(env)
    f = compile_expr(expr, bound=names)
    return f({k: np.asarray([v], float) for k, v in env.items()}, 1)[0]


def test_truthiness_is_abs_at_least_one():
    # seed 001: |x| >= 1 is true; 0.5 is false, -1 is true
    assert truth(np.array([0.5, -1.0, 1.0, 0.0, 0.99])).tolist() == [
        False, True, True, False, False,
    ]
    assert ev(Unary("!", Var("x")), x=0.5) == 1.0
    assert ev(Binary("&&", Var("x"), Num(1.0)), x=0.5) == 0.0
    assert ev(Binary("||", Var("x"), Num(0.0)), x=-1.0) == 1.0


def test_arithmetic_is_double_with_fmod_and_integer_shifts():
    assert ev(Binary("%", Num(7.5), Num(2.0))) == 1.5
    assert ev(Binary("%", Num(-7.0), Num(3.0))) == math.fmod(-7.0, 3.0)
    assert ev(Binary("<<", Num(3.9), Num(2.0))) == 12.0
    assert ev(Binary(">>", Num(17.0), Num(2.0))) == 4.0
    assert ev(Binary("**", Num(2.0), Num(10.0))) == 1024.0
    assert ev(Binary("/", Num(1.0), Num(0.0))) == math.inf


def test_functions_take_radians():
    assert ev(Call("sin", (Num(math.pi / 2),))) == 1.0
    assert ev(Call("sum", (Num(1.0), Num(2.0), Var("y"))), y=3.0) == 6.0
    assert ev(Call("pow", (Num(2.0), Num(0.5)))) == math.sqrt(2.0)


def test_bound_names_shadow_constants():
    f = compile_expr(
        Binary("+", Var("x"), Var("k")), bound=("x",), constants={"x": 100.0, "k": 1.0}
    )
    assert f({"x": np.array([1.0, 2.0])}, 2).tolist() == [2.0, 3.0]


def test_constants_fold():
    f = compile_expr(Binary("*", Var("k"), Num(2.0)), constants={"k": 21.0})
    assert f.constant == 42.0
    assert evaluate_constant(Binary("-", Num(1.0), Num(0.25))) == 0.75


def test_unknown_names_are_semantic_errors():
    with pytest.raises(LSystemSemanticError, match="unknown variable 'q'"):
        compile_expr(Var("q"), bound=("x",))
    with pytest.raises(LSystemSemanticError, match="unknown function"):
        compile_expr(Call("system", (Num(1.0),)))
    with pytest.raises(LSystemSemanticError, match="takes 1"):
        compile_expr(Call("sin", (Num(1.0), Num(2.0))))
