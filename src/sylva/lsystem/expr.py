"""Parameter expressions, compiled from our own parse tree into NumPy closures.

User text never reaches :func:`eval` or :func:`exec`: a dialect parses it into the
:mod:`~sylva.lsystem.ast` expression nodes, and :func:`compile_expr` turns those into a tree
of small Python closures over NumPy ufuncs.  A compiled expression evaluates *vectorised*:
every bound variable is an array holding its value for every rule application of one step,
so one call evaluates a condition or a parameter for all instances of a rule at once.

Semantics follow seed 001 §3.4: every value is a double; ``True`` is 1 and ``False`` 0; a
number is *true* when ``|x| >= 1``; ``%`` is ``fmod``; ``<<``/``>>`` work on truncated
integers; trigonometric functions take radians.  Division by zero gives ``inf``/``nan``
as in IEEE arithmetic.

Examples
--------
>>> import numpy as np
>>> from sylva.lsystem.ast import Binary, Num, Var
>>> f = compile_expr(Binary("*", Var("x"), Num(2.0)), bound=("x",))
>>> f({"x": np.array([1.0, 2.5])}, 2).tolist()
[2.0, 5.0]
>>> evaluate_constant(Binary("+", Var("a"), Num(1.0)), {"a": 41.0})
42.0
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence

import numpy as np

from ..errors import LSystemSemanticError
from .ast import Binary, Call, Expr, Num, Unary, Var

__all__ = [
    "FUNCTIONS",
    "CompiledExpr",
    "compile_expr",
    "evaluate_constant",
    "free_variables",
    "truth",
]

Env = Mapping[str, np.ndarray]
CompiledExpr = Callable[[Env, int], np.ndarray]


def truth(x: np.ndarray) -> np.ndarray:
    """Seed 001's truthiness: ``|x| >= 1`` (so 0.5 is false and -1 is true)."""
    return np.abs(x) >= 1.0


def _sum(*args):
    out = args[0]
    for a in args[1:]:
        out = out + a
    return out


def _shift(op):
    def f(a, b):
        ai = np.trunc(a).astype(np.int64)
        bi = np.clip(np.trunc(b), 0, 63).astype(np.int64)
        return (np.left_shift(ai, bi) if op == "<<" else np.right_shift(ai, bi)).astype(
            np.float64
        )

    return f


# name -> (callable on float64 arrays, minimum arity, maximum arity or None)
FUNCTIONS: dict[str, tuple[Callable, int, int | None]] = {
    "sum": (_sum, 1, None),
    "sqrt": (np.sqrt, 1, 1),
    "sin": (np.sin, 1, 1),
    "cos": (np.cos, 1, 1),
    "tan": (np.tan, 1, 1),
    "abs": (np.abs, 1, 1),
    "pow": (np.power, 2, 2),
    # beyond the thesis, the usual functions of cpfg and L-Py
    "asin": (np.arcsin, 1, 1),
    "acos": (np.arccos, 1, 1),
    "atan": (np.arctan, 1, 1),
    "atan2": (np.arctan2, 2, 2),
    "exp": (np.exp, 1, 1),
    "log": (np.log, 1, 1),
    "floor": (np.floor, 1, 1),
    "ceil": (np.ceil, 1, 1),
    "round": (np.round, 1, 1),
    "min": (lambda *a: _reduce(np.minimum, a), 1, None),
    "max": (lambda *a: _reduce(np.maximum, a), 1, None),
    "sign": (np.sign, 1, 1),
    "deg": (np.degrees, 1, 1),
    "rad": (np.radians, 1, 1),
}


def _reduce(f, args):
    out = args[0]
    for a in args[1:]:
        out = f(out, a)
    return out


def _as_float(x):
    return np.asarray(x, dtype=np.float64)


_BINARY: dict[str, Callable] = {
    "+": np.add,
    "-": np.subtract,
    "*": np.multiply,
    "/": np.true_divide,
    "%": np.fmod,
    "**": np.power,
    "^": np.power,
    "<<": _shift("<<"),
    ">>": _shift(">>"),
    "<": lambda a, b: _as_float(np.less(a, b)),
    ">": lambda a, b: _as_float(np.greater(a, b)),
    "<=": lambda a, b: _as_float(np.less_equal(a, b)),
    ">=": lambda a, b: _as_float(np.greater_equal(a, b)),
    "==": lambda a, b: _as_float(np.equal(a, b)),
    "!=": lambda a, b: _as_float(np.not_equal(a, b)),
    "&&": lambda a, b: _as_float(truth(a) & truth(b)),
    "||": lambda a, b: _as_float(truth(a) | truth(b)),
}

_UNARY: dict[str, Callable] = {
    "-": np.negative,
    "+": lambda a: a,
    "!": lambda a: _as_float(~truth(a)),
}


def free_variables(expr: Expr) -> set[str]:
    """The variable names an expression reads."""
    if isinstance(expr, Var):
        return {expr.name}
    if isinstance(expr, Unary):
        return free_variables(expr.operand)
    if isinstance(expr, Binary):
        return free_variables(expr.left) | free_variables(expr.right)
    if isinstance(expr, Call):
        out: set[str] = set()
        for a in expr.args:
            out |= free_variables(a)
        return out
    return set()


def _error(message: str, node) -> LSystemSemanticError:
    span = getattr(node, "span", None)
    if span is not None:
        return LSystemSemanticError(
            message, filename=span.filename, line=span.line, column=span.column
        )
    return LSystemSemanticError(message)


def compile_expr(
    expr: Expr,
    *,
    bound: Sequence[str] = (),
    constants: Mapping[str, float] | None = None,
) -> CompiledExpr:
    """Compile an expression into ``f(env, n) -> float64[n]``.

    Parameters
    ----------
    expr : Expr
        The parse tree.
    bound : sequence of str
        Names bound per application (read from ``env``); they shadow ``constants``.
    constants : mapping of str to float
        Global constants, folded in at compile time.

    Returns
    -------
    callable
        ``f(env, n)`` where ``env`` maps each bound name to a ``float64[n]`` array; the
        result is a ``float64[n]`` array.

    Raises
    ------
    LSystemSemanticError
        For a variable that is neither bound nor a constant, an unknown function, or a
        call with the wrong number of arguments.
    """
    constants = constants or {}
    bound_set = set(bound)

    def build(node) -> tuple[bool, object]:
        # returns (is_constant, value-or-closure)
        if isinstance(node, Num):
            return True, float(node.value)
        if isinstance(node, Var):
            if node.name in bound_set:
                name = node.name
                return False, lambda env, n: env[name]
            if node.name in constants:
                return True, float(constants[node.name])
            if node.name in ("True", "true"):
                return True, 1.0
            if node.name in ("False", "false"):
                return True, 0.0
            known = sorted(bound_set | set(constants))
            hint = f" (known here: {', '.join(known)})" if known else ""
            raise _error(f"unknown variable {node.name!r}{hint}", node)
        if isinstance(node, Unary):
            f = _UNARY.get(node.op)
            if f is None:
                raise _error(f"unknown operator {node.op!r}", node)
            c, v = build(node.operand)
            if c:
                return True, float(f(np.float64(v)))
            return False, lambda env, n, f=f, v=v: f(v(env, n))
        if isinstance(node, Binary):
            f = _BINARY.get(node.op)
            if f is None:
                raise _error(f"unknown operator {node.op!r}", node)
            cl, vl = build(node.left)
            cr, vr = build(node.right)
            if cl and cr:
                with np.errstate(all="ignore"):
                    return True, float(f(np.float64(vl), np.float64(vr)))
            if cl:
                return False, lambda env, n, f=f, a=vl, b=vr: f(a, b(env, n))
            if cr:
                return False, lambda env, n, f=f, a=vl, b=vr: f(a(env, n), b)
            return False, lambda env, n, f=f, a=vl, b=vr: f(a(env, n), b(env, n))
        if isinstance(node, Call):
            spec = FUNCTIONS.get(node.func)
            if spec is None:
                raise _error(
                    f"unknown function {node.func!r}; expected one of "
                    + ", ".join(sorted(FUNCTIONS)),
                    node,
                )
            f, lo, hi = spec
            k = len(node.args)
            if k < lo or (hi is not None and k > hi):
                want = str(lo) if hi == lo else f"at least {lo}" if hi is None else f"{lo}–{hi}"
                raise _error(f"{node.func}() takes {want} argument(s), got {k}", node)
            parts = [build(a) for a in node.args]
            if all(c for c, _ in parts):
                with np.errstate(all="ignore"):
                    return True, float(f(*[np.float64(v) for _, v in parts]))
            fns = [(c, v) for c, v in parts]

            def call(env, n, f=f, fns=fns):
                return f(*[v if c else v(env, n) for c, v in fns])

            return False, call
        raise _error(f"not an expression: {node!r}", node)

    is_const, value = build(expr)
    if is_const:
        const = float(value)  # type: ignore[arg-type]

        def constant(env, n, const=const):
            return np.full(n, const)

        constant.constant = const  # type: ignore[attr-defined]
        return constant
    inner = value

    def run(env, n, inner=inner):
        with np.errstate(all="ignore"):
            out = inner(env, n)
        out = np.asarray(out, dtype=np.float64)
        if out.shape != (n,):
            out = np.broadcast_to(out, (n,)).copy()
        return out

    run.constant = None  # type: ignore[attr-defined]
    return run


def evaluate_constant(expr: Expr, constants: Mapping[str, float] | None = None) -> float:
    """Evaluate an expression that uses only ``constants``.

    >>> from sylva.lsystem.ast import Call, Num
    >>> round(evaluate_constant(Call("sqrt", (Num(2.0),))), 6)
    1.414214
    """
    f = compile_expr(expr, constants=constants)
    v = float(f({}, 1)[0])
    if math.isnan(v):
        return v
    return v
