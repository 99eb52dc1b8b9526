"""cpfg's production statement blocks, ``pred : {pre} condition {post} --> successor``.

A production may carry two C-like blocks (the grammar of :mod:`._cpfg_statements`): the
*pre-condition* block runs before its condition is evaluated, the *post-condition* block
after the condition held, before the successor is made.  Their assignments are seen by the
condition (the pre block's) and by the successor and probability (both).

sylva runs a block *vectorised*: one run per rule and step over all the applications of the
rule at once, every variable an array with one value per application; ``if`` / ``else``,
``while``, ``do`` and ``for`` run under masks (a row takes part in a branch or a loop turn
only while its condition holds), so each application sees exactly the values a scalar run of
cpfg gives it.  A block reads the rule's parameters (and may assign them: ``{t=t-PL;} t>0
--> A(t)`` uses the new ``t``), the program's constants and globals (``#define``,
``Define:``/``Start:``, as ``StartEach:``/``EndEach:`` leave them), and cpfg's functions
(``ran``, ``nran``, ``bran``, ``biran``, ``srand``, ``func``, ``curveX`` … see
:mod:`._cpfg_functions`); ``printf`` prints nothing.  A block that runs more than
:data:`~._cpfg_statements.STEP_BUDGET` statements and loop turns in one run stops with a
:class:`~sylva.errors.SylvaError` naming its file and line.

A block that assigns a global variable (``count = count + 1`` where ``count`` is a ``Start:``
global) changes it for the applications that follow, as in cpfg: the engine then applies the
program's productions one module at a time, in word order (cpfg's own order), and the
conditions, blocks and successors read the global's running value
(:attr:`Block.globals_written`, the program's ``statements.written``).  Not supported (an
error that names them, when the file is read): writing an array element, and declaring
arrays in a production block.
"""

from __future__ import annotations

import math

import numpy as np
from lark import Token, Tree

from ...errors import SylvaError
from ..expr import FUNCTIONS
from ._cpfg_statements import _OUTPUT, STEP_BUDGET

__all__ = ["Block", "Runtime"]


class Runtime:
    """Where the blocks of a program find the globals of the running derivation:
    :attr:`current` (set by the program's statement schedule each step), else
    :attr:`initial` (what ``Define:`` / ``Start:`` left)."""

    def __init__(self, initial):
        self.initial = initial
        self.current = None

    @property
    def globals(self):
        return self.current if self.current is not None else self.initial


class _Budget(Exception):
    pass


class Block:
    """The pre- and post-condition blocks of one production (parsed trees, or None).

    ``outputs`` are the names the blocks assign that are not parameters of the rule; the
    engine binds them per application (:meth:`wrap`).
    """

    def __init__(self, pre, post, outputs, runtime: Runtime, where: str, source: str,
                 rename: dict | None = None, assigned_names=()):
        self.pre, self.post = pre, post
        self.rename = dict(rename or {})  # block name -> bound name (``len`` -> ``_b_len``)
        self._back = {v: k for k, v in self.rename.items()}
        self.assigned = frozenset(assigned_names)
        self.outputs = tuple(outputs)
        self.runtime = runtime
        self.where = where
        self.source = source
        #: the globals it assigns: cpfg carries them from one application to the next
        self.globals_written: frozenset[str] = frozenset()

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Block):
            return NotImplemented
        return self.source == other.source and self.where == other.where

    __hash__ = None  # type: ignore[assignment]

    def __repr__(self) -> str:
        return f"Block({self.source!r})"

    def wrap(self, cond, constants):
        """The rule's compiled condition ``cond`` (or None) as one that runs the blocks:
        ``f(env, n)`` runs the pre block over ``env`` (the rule's bound arrays, which it
        updates with what the blocks assign), the condition (C's truth: not zero), and the
        post block where it held; it returns 1.0 where the rule applies, else 0.0."""
        consts = dict(constants or {})

        def run(env, n):
            if self.globals_written and n > 1:  # one application after the other
                rows = []
                for r in range(n):
                    one = {k: np.asarray(v)[r : r + 1] for k, v in env.items()}
                    rows.append((one, run(one, 1)))
                for k in env:
                    env[k] = np.concatenate([one[k] for one, _ in rows])
                for k in {k for one, _ in rows for k in one} - set(env):
                    env[k] = np.concatenate([one[k] for one, _ in rows])
                return np.concatenate([ok for _, ok in rows])
            g = self.runtime.globals
            back, ren = self._back, self.rename
            vals = {back.get(k, k): np.asarray(v, np.float64) for k, v in env.items()}
            for name in self.globals_written:  # their running values
                vals[back.get(name, name)] = np.full(n, float(g.values.get(name, 0.0)))
            for name in self.outputs:
                vals.setdefault(back.get(name, name), np.zeros(n))
            ctx = _Ctx(g, consts, n, self.where)
            try:
                if self.pre is not None:
                    ctx.exec(self.pre, vals, np.ones(n, np.bool_))
                env.update({ren.get(k, k): v for k, v in vals.items()})
                ok = np.ones(n, np.bool_) if cond is None else np.asarray(cond(env, n)) != 0
                if self.post is not None and ok.any():
                    ctx.exec(self.post, vals, ok)
                    env.update({ren.get(k, k): v for k, v in vals.items()})
                for name in self.globals_written:  # carried to the next application
                    g.values[name] = float(vals[back.get(name, name)][-1])
            except _Budget:
                raise SylvaError(f"{self.where}: the statement block ran past "
                                 f"{STEP_BUDGET:,} steps (a loop that never ends?); "
                                 "stopped") from None  # fmt: skip
            return ok.astype(np.float64)

        return run


def _truth(v) -> np.ndarray:
    return np.asarray(v) != 0


class _Ctx:
    def __init__(self, g, constants, n, where):
        self.g, self.constants, self.n, self.where = g, constants, n, where
        self.left = STEP_BUDGET
        self.mask = np.ones(n, np.bool_)

    def tick(self):
        self.left -= 1
        if self.left < 0:
            raise _Budget

    def error(self, message: str) -> SylvaError:
        return SylvaError(f"{self.where}: {message}")

    # ------------------------------------------------------------------ statements
    def exec(self, node, vals, mask) -> None:
        self.tick()
        self.mask = mask  # the rows this statement runs for (index checks look at them)
        kind, ch = node.data, node.children
        if kind in ("start", "block"):
            for c in ch:
                self.exec(c, vals, mask)
        elif kind == "if_":
            c = _truth(self.eval(ch[0], vals))
            if (mask & c).any():
                self.exec(ch[1], vals, mask & c)
            if len(ch) > 2 and ch[2] is not None and (mask & ~c).any():
                self.exec(ch[2], vals, mask & ~c)
        elif kind == "while_":
            m = mask & _truth(self.eval(ch[0], vals))
            while m.any():
                self.tick()
                self.exec(ch[1], vals, m)
                self.mask = m
                m = m & _truth(self.eval(ch[0], vals))
        elif kind == "do_":
            m = mask
            while m.any():
                self.tick()
                self.exec(ch[0], vals, m)
                self.mask = m
                m = m & _truth(self.eval(ch[1], vals))
        elif kind == "for_":
            init, cond, step, body = ch
            if init is not None:
                self.exec(init, vals, mask)
            m = mask if cond is None else mask & _truth(self.eval(cond, vals))
            while m.any():
                self.tick()
                self.exec(body, vals, m)
                if step is not None:
                    self.exec(step, vals, m)
                self.mask = m
                if cond is not None:
                    m = m & _truth(self.eval(cond, vals))
        elif kind == "assign":
            target, op, value = ch
            v = self.eval(value, vals)
            name = self._scalar(target)
            if str(op) != "=":
                old = self._var(name, vals)
                with np.errstate(all="ignore"):
                    v = {"+=": old + v, "-=": old - v, "*=": old * v,
                         "/=": old / v}[str(op)]  # fmt: skip
            self._store(name, v, vals, mask)
        elif kind in ("post", "pre"):
            target, op = (ch[0], ch[1]) if kind == "post" else (ch[1], ch[0])
            name = self._scalar(target)
            self._store(name, self._var(name, vals) + (1.0 if str(op) == "++" else -1.0),
                        vals, mask)  # fmt: skip
        elif kind == "expr_stmt":  # C's expression statement: evaluated, the value dropped
            self.eval(ch[0], vals)
        elif kind == "call_stmt":
            self._call(str(ch[0]), [c for c in ch[1:] if c is not None], vals, mask)
        elif kind == "arrays":
            raise self.error("arrays are declared in Define:, not in a production's block")
        else:  # pragma: no cover - the grammar makes no other statement
            raise self.error(f"cannot run {kind}")

    def _scalar(self, target) -> str:
        if len(target.children) > 1 and target.children[1] is not None:
            raise self.error(f"writing the array element {target.children[0]}[…] in a "
                             "production's block is not supported (it is a global, changed "
                             "from one application to the next)")  # fmt: skip
        return str(target.children[0])

    def _store(self, name, v, vals, mask) -> None:
        v = np.broadcast_to(np.asarray(v, np.float64), (self.n,))
        old = vals.get(name)
        if old is None:
            old = np.zeros(self.n)
        vals[name] = np.where(mask, v, old)

    def _var(self, name, vals) -> np.ndarray:
        if name in vals:
            return vals[name]
        g = self.g
        if name in g.values:
            return np.full(self.n, g.values[name])
        if name in self.constants:
            return np.full(self.n, float(self.constants[name]))
        ids = g.functions.get("__ids__", {})
        if name in ids:  # a function's name stands for its number
            return np.full(self.n, float(ids[name]))
        raise self.error(f"unknown variable {name!r}; expected a parameter of the rule, a "
                         "global or a variable the block sets first")  # fmt: skip

    # ------------------------------------------------------------------ expressions
    def eval(self, node, vals) -> np.ndarray:
        if isinstance(node, Token):  # pragma: no cover - numbers and names are wrapped
            return np.full(self.n, float(node))
        kind, ch = node.data, node.children
        if kind == "number":
            return np.full(self.n, float(ch[0]))
        if kind == "var":
            return self._var(str(ch[0]), vals)
        if kind == "index":
            name = str(ch[0])
            arr = self.g.arrays.get(name)
            if arr is None:
                raise self.error(f"{name} is not an array; expected 'array {name}[n];' in "
                                 "Define:")  # fmt: skip
            dims = self.g.dims.get(name, (len(arr),))
            subs = [self.eval(c, vals) for c in ch[1:]]
            if len(subs) != len(dims):
                raise self.error(f"{name} has {len(dims)} dimension(s), indexed with "
                                 f"{len(subs)}")  # fmt: skip
            flat = np.zeros(self.n, np.int64)
            for i, size in zip(subs, dims, strict=True):
                bad = (i < 0) | (i >= size) | (i != np.trunc(i))
                if (bad & self.mask).any():  # rows the statement runs for: an error
                    raise self.error(f"index {i[bad & self.mask][0]:g} of {name} is "
                                     f"outside 0..{size - 1}")  # fmt: skip
                flat = flat * size + np.where(bad, 0, i).astype(np.int64)
            return np.asarray(arr, np.float64)[flat]
        if kind == "call":
            return self._call(str(ch[0]), [c for c in ch[1:] if c is not None], vals, None)
        if kind == "string":
            raise self.error("a string is only an argument of printf")
        with np.errstate(all="ignore"):
            if kind == "unary":
                v = self.eval(ch[1], vals)
                return {"-": lambda: -v, "+": lambda: v,
                        "!": lambda: (v == 0).astype(np.float64)}[str(ch[0])]()  # fmt: skip
            if kind == "power":
                return np.power(self.eval(ch[0], vals), self.eval(ch[1], vals))
            if kind == "ternary":
                c = _truth(self.eval(ch[0], vals))
                return np.where(c, self.eval(ch[1], vals), self.eval(ch[2], vals))
            if kind == "or_":
                out = np.zeros(self.n, np.bool_)
                for c in ch:
                    out |= _truth(self.eval(c, vals))
                return out.astype(np.float64)
            if kind == "and_":
                out = np.ones(self.n, np.bool_)
                for c in ch:
                    out &= _truth(self.eval(c, vals))
                return out.astype(np.float64)
            if kind == "binary":
                v = self.eval(ch[0], vals)
                for k in range(1, len(ch), 2):
                    v = _BINARY[str(ch[k])](v, self.eval(ch[k + 1], vals))
                return v
        raise self.error(f"cannot evaluate {kind}")  # pragma: no cover

    def _call(self, name, args, vals, mask) -> np.ndarray:
        n = self.n
        if name in _OUTPUT:  # output only: sylva prints and writes nothing
            return np.zeros(n)
        x = [self.eval(a, vals) for a in args]
        g = self.g

        def want(k):
            if len(x) != k:
                raise self.error(f"{name} takes {k} argument(s), got {len(x)}")

        if name == "srand":
            want(1)
            g.rng = np.random.Generator(np.random.PCG64(int(x[0][0]) & (2**63 - 1)))
            return np.zeros(n)
        if name in _RANDOM:
            want(_RANDOM[name][0])
            return _RANDOM[name][1](g.rng, n, *x)
        if name in _VECTOR:
            want(_VECTOR[name][0])
            with np.errstate(all="ignore"):
                return np.asarray(_VECTOR[name][1](*x), np.float64)
        if name in g.functions and name != "__ids__":
            return np.asarray(g.functions[name](*x), np.float64) + np.zeros(n)
        spec = FUNCTIONS.get(name)
        if spec is None:
            known = ", ".join(sorted({*FUNCTIONS, *_RANDOM, *_VECTOR, *g.functions,
                                      "srand"} - {"__ids__"}))  # fmt: skip
            raise self.error(f"unknown function {name!r}; expected one of {known}")
        f, lo, hi = spec
        if len(x) < lo or (hi is not None and len(x) > hi):
            raise self.error(f"{name} takes {lo}..{hi} argument(s), got {len(x)}")
        with np.errstate(all="ignore"):
            return np.asarray(f(*x), np.float64) + np.zeros(n)


def _div(a, b):
    with np.errstate(all="ignore"):
        return np.true_divide(a, b)


_BINARY = {
    "+": np.add, "-": np.subtract, "*": np.multiply, "/": _div,
    "%": lambda a, b: np.where(b != 0, np.fmod(a, np.where(b != 0, b, 1.0)), math.nan),
    "<": lambda a, b: (a < b).astype(np.float64),
    "<=": lambda a, b: (a <= b).astype(np.float64),
    ">": lambda a, b: (a > b).astype(np.float64),
    ">=": lambda a, b: (a >= b).astype(np.float64),
    "==": lambda a, b: (a == b).astype(np.float64),
    "!=": lambda a, b: (a != b).astype(np.float64),
}  # fmt: skip

_RANDOM = {
    "ran": (1, lambda rng, n, x: rng.random(n) * x),
    "nran": (2, lambda rng, n, m, s: m + s * rng.standard_normal(n)),
    "bran": (2, lambda rng, n, a, b: rng.beta(np.maximum(a, 1e-9), np.maximum(b, 1e-9))),
    "biran": (2, lambda rng, n, k, p: rng.binomial(np.maximum(k, 0).astype(np.int64),
                                                    np.clip(p, 0, 1)).astype(np.float64)),
}  # fmt: skip

#: cpfg's trigonometry is in degrees (its D_TO_R / R_TO_D around C's functions)
DEGREES = {
    "sin": (1, lambda x: np.sin(np.radians(x))), "cos": (1, lambda x: np.cos(np.radians(x))),
    "tan": (1, lambda x: np.tan(np.radians(x))), "asin": (1, lambda x: np.degrees(np.arcsin(x))),
    "acos": (1, lambda x: np.degrees(np.arccos(x))),
    "atan": (1, lambda x: np.degrees(np.arctan(x))),
    "atan2": (2, lambda y, x: np.degrees(np.arctan2(y, x))),
}  # fmt: skip

_VECTOR = {
    "trunc": (1, np.trunc), "sign": (1, np.sign), "fabs": (1, np.abs),
    "min": (2, np.minimum), "max": (2, np.maximum),
    "frac": (1, lambda x: x - np.floor(x)), **DEGREES,
}  # fmt: skip

#: The functions a cpfg expression may call that sylva's expressions do not have, or that
#: draw random numbers: a call to one outside a block is moved into one (the reader).
BLOCK_ONLY = frozenset({*_RANDOM, *_VECTOR, "srand", "func", "curveX", "curveY", "curveZ",
                        "curveGAL", "printf"}) - {"min", "max", "sign"}  # fmt: skip


def assigned(tree) -> set[str]:
    """The plain names the statements of ``tree`` assign."""
    if tree is None:
        return set()
    return {str(t.children[0]) for t in tree.find_data("lvalue")}


def is_tree(x) -> bool:
    return isinstance(x, Tree)
