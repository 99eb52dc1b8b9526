"""cpfg's statements: the C-like blocks of ``Define:``, ``Start:`` and ``End:``.

The grammar is the data file ``cpfg_statements.lark`` (Lark, LALR): blocks ``{ … }``,
``if`` / ``else``, ``while``, ``do … while``, ``for``, ``array a[10], b[3];`` declarations,
assignments ``= += -= *= /=``, ``++`` / ``--`` (before or after), calls; expressions with C's
operators and cpfg's ``^`` (power).  The statements are walked by :func:`run`, never given to
``eval``; a block that runs more than :data:`STEP_BUDGET` statements and loop turns stops
with a :class:`~sylva.errors.SylvaError` that names the block's file and line.

Functions: those of sylva's expressions (:data:`sylva.lsystem.expr.FUNCTIONS`: ``floor``,
``exp``, ``log`` …) and cpfg's ``ran(x)`` (uniform in [0, x)), ``nran(mean, sd)`` (normal),
``srand(s)`` (reseeds both), ``trunc``, ``sign``, ``fabs``, ``min``, ``max``, and cpfg's
trigonometry in degrees, as cpfg computes it: ``sin``, ``cos``, ``tan`` of degrees,
``asin``, ``acos``, ``atan``, ``atan2(y, x)`` in degrees.  The random numbers come from
NumPy's PCG64 seeded with the L-system's ``seed:`` (0 without one): the same on every machine.
"""

from __future__ import annotations

import math
from functools import cache
from importlib import resources

import numpy as np
from lark import Lark, Token, Tree
from lark.exceptions import UnexpectedCharacters, UnexpectedEOF, UnexpectedToken

from ...errors import SylvaError
from ..expr import FUNCTIONS

__all__ = ["STEP_BUDGET", "Globals", "parse_block", "run"]

#: The most statements and loop turns one block may run (a loop that never ends stops here).
STEP_BUDGET = 1_000_000


@cache
def _parser() -> Lark:
    grammar = resources.files(__package__).joinpath("cpfg_statements.lark").read_text("utf-8")
    return Lark(grammar, parser="lalr", propagate_positions=True)


def parse_block(text: str, error) -> Tree:
    """The statements of ``text``; ``error(message, offset)`` makes the error of a bad one."""
    try:
        return _parser().parse(text)
    except UnexpectedToken as e:
        got = "the end of the block" if e.token.type == "$END" else repr(str(e.token))
        at = e.token.start_pos if e.token.start_pos is not None else len(text)
        raise error(f"unexpected {got} in a statement block; expected a C statement",
                    at) from None  # fmt: skip
    except UnexpectedCharacters as e:
        raise error(f"unexpected {text[e.pos_in_stream]!r} in a statement block",
                    e.pos_in_stream) from None  # fmt: skip
    except UnexpectedEOF:
        raise error("the statement block ends too early", len(text)) from None


class Globals:
    """The global variables and arrays of a cpfg L-system, and its random stream."""

    def __init__(self, seed: int = 0):
        self.values: dict[str, float] = {}
        self.arrays: dict[str, list[float]] = {}
        self.dims: dict[str, tuple[int, ...]] = {}  # of arrays of several dimensions
        self.rng = np.random.Generator(np.random.PCG64(seed))
        #: cpfg's functions of the view file's files (``func``, ``curveX`` …): name -> f(*x)
        self.functions: dict = {}

    def numbers(self) -> dict[str, float]:
        return dict(self.values)


class _Budget(Exception):
    pass


def run(tree: Tree, g: Globals, where: str, budget: int = STEP_BUDGET) -> None:
    """Run the statements of ``tree`` over ``g``; ``where`` names the block in errors."""
    state = [budget]
    try:
        _exec(tree, g, state, where)
    except _Budget:
        raise SylvaError(f"{where}: the statement block ran past {budget:,} steps (a loop that "
                         "never ends?); stopped") from None  # fmt: skip
    except (ArithmeticError, ValueError, IndexError) as e:
        raise SylvaError(f"{where}: {e}") from None


def _tick(state):
    state[0] -= 1
    if state[0] < 0:
        raise _Budget


def _exec(node, g: Globals, state, where: str) -> None:
    _tick(state)
    kind = node.data
    ch = node.children
    if kind in ("start", "block"):
        for c in ch:
            _exec(c, g, state, where)
    elif kind == "if_":
        if _eval(ch[0], g, where):
            _exec(ch[1], g, state, where)
        elif len(ch) > 2 and ch[2] is not None:
            _exec(ch[2], g, state, where)
    elif kind == "while_":
        while _eval(ch[0], g, where):
            _tick(state)
            _exec(ch[1], g, state, where)
    elif kind == "do_":
        while True:
            _tick(state)
            _exec(ch[0], g, state, where)
            if not _eval(ch[1], g, where):
                break
    elif kind == "for_":
        init, cond, step, body = ch
        if init is not None:
            _exec(init, g, state, where)
        while cond is None or _eval(cond, g, where):
            _tick(state)
            _exec(body, g, state, where)
            if step is not None:
                _exec(step, g, state, where)
    elif kind == "arrays":
        for d in ch:
            name, sizes, init = str(d.children[0]), d.children[1:-2], d.children[-1]
            if d.children[-2] is not None and str(d.children[-2]) != "=":
                raise SylvaError(f"{where}: {name} {d.children[-2]} …: expected '=' in a "
                                 "declaration")  # fmt: skip
            if not sizes:  # a scalar declaration: float x = 1;
                g.values[name] = _eval(init, g, where) if init is not None else 0.0
                continue
            dims = [_eval(e, g, where) for e in sizes]
            n = math.prod(dims)
            if not (all(k == int(k) and k > 0 for k in dims) and n <= 1_000_000):
                raise SylvaError(f"{where}: array {name}{dims}: expected sizes of 1 or more, "
                                 "1,000,000 elements at most")  # fmt: skip
            n = int(n)
            g.arrays[name] = [0.0] * n
            g.dims[name] = tuple(int(k) for k in dims)
            items = [] if init is None else (
                [c for c in init.children if c is not None]
                if isinstance(init, Tree) and init.data == "init_list" else [init])  # fmt: skip
            if len(items) > n:
                raise SylvaError(f"{where}: {len(items)} values for array {name} of {n}")
            for k, item in enumerate(items):
                g.arrays[name][k] = _eval(item, g, where)
    elif kind == "assign":
        target, op, value = ch
        v = _eval(value, g, where)
        if op != "=":
            old = _load(target, g, where)
            v = {"+=": old + v, "-=": old - v, "*=": old * v, "/=": _div(old, v)}[str(op)]
        _store(target, g, v, where)
    elif kind in ("post", "pre"):
        target, op = (ch[0], ch[1]) if kind == "post" else (ch[1], ch[0])
        _store(target, g, _load(target, g, where) + (1.0 if op == "++" else -1.0), where)
    elif kind == "call_stmt":
        _call(str(ch[0]), [c for c in ch[1:] if c is not None], g, where)
    elif kind == "expr_stmt":  # C's expression statement: evaluated, the value dropped
        _eval(ch[0], g, where)
    else:  # pragma: no cover - the grammar makes no other statement
        raise SylvaError(f"{where}: cannot run {kind}")


def _div(a: float, b: float) -> float:
    if b == 0.0:
        return math.copysign(math.inf, a) if a else math.nan
    return a / b


def flat_index(name: str, idx: list, g: Globals, where: str) -> int:
    """The element of array ``name`` at the indices ``idx`` (row-major)."""
    dims = g.dims.get(name, (len(g.arrays[name]),))
    if len(idx) != len(dims):
        raise SylvaError(f"{where}: {name} has {len(dims)} dimension(s), indexed with "
                         f"{len(idx)}")  # fmt: skip
    flat = 0
    for i, size in zip(idx, dims, strict=True):
        if not (0 <= i < size) or i != int(i):
            raise SylvaError(f"{where}: index {i:g} of {name} is outside 0..{size - 1}")
        flat = flat * size + int(i)
    return flat


def _index(target, g: Globals, where: str) -> tuple[str, int | None]:
    name = str(target.children[0])
    subs = [c for c in target.children[1:] if c is not None]
    if not subs:
        return name, None
    if name not in g.arrays:
        raise SylvaError(f"{where}: {name} is not an array; expected 'array {name}[n];' in "
                         "Define:")  # fmt: skip
    return name, flat_index(name, [_eval(c, g, where) for c in subs], g, where)


def _load(target, g: Globals, where: str) -> float:
    name, i = _index(target, g, where)
    if i is not None:
        return g.arrays[name][i]
    return _var(name, g, where)


def _store(target, g: Globals, value: float, where: str) -> None:
    name, i = _index(target, g, where)
    if i is not None:
        g.arrays[name][i] = float(value)
    elif name in g.arrays:
        raise SylvaError(f"{where}: {name} is an array; expected {name}[index]")
    else:
        g.values[name] = float(value)


def _var(name: str, g: Globals, where: str) -> float:
    if name in g.values:
        return g.values[name]
    ids = g.functions.get("__ids__", {})
    if name in ids:  # cpfg names a function by its number or by its name
        return float(ids[name])
    raise SylvaError(f"{where}: unknown variable {name!r}; expected a variable set before")


def _truth(v: float) -> float:
    return 1.0 if v else 0.0


def _eval(node, g: Globals, where: str) -> float:
    if isinstance(node, Token):  # pragma: no cover - numbers and names are wrapped
        return float(node)
    kind, ch = node.data, node.children
    if kind == "number":
        return float(ch[0])
    if kind == "var":
        return _var(str(ch[0]), g, where)
    if kind == "index":
        return _load(Tree("lvalue", ch), g, where)
    if kind == "call":
        return _call(str(ch[0]), [c for c in ch[1:] if c is not None], g, where)
    if kind == "unary":
        v = _eval(ch[1], g, where)
        return {"-": -v, "+": v, "!": _truth(not v)}[str(ch[0])]
    if kind == "ternary":
        return _eval(ch[1] if _eval(ch[0], g, where) else ch[2], g, where)
    if kind == "string":
        raise SylvaError(f"{where}: a string is only an argument of printf")
    if kind == "power":
        return float(_eval(ch[0], g, where) ** _eval(ch[1], g, where))
    if kind == "or_":
        return _truth(any(_eval(c, g, where) for c in ch))
    if kind == "and_":
        return _truth(all(_eval(c, g, where) for c in ch))
    if kind == "binary":
        v = _eval(ch[0], g, where)
        for k in range(1, len(ch), 2):
            op, r = str(ch[k]), _eval(ch[k + 1], g, where)
            v = _BINARY[op](v, r)
        return v
    raise SylvaError(f"{where}: cannot evaluate {kind}")  # pragma: no cover


_BINARY = {
    "+": lambda a, b: a + b,
    "-": lambda a, b: a - b,
    "*": lambda a, b: a * b,
    "/": _div,
    "%": lambda a, b: math.fmod(a, b) if b else math.nan,
    "<": lambda a, b: _truth(a < b),
    "<=": lambda a, b: _truth(a <= b),
    ">": lambda a, b: _truth(a > b),
    ">=": lambda a, b: _truth(a >= b),
    "==": lambda a, b: _truth(a == b),
    "!=": lambda a, b: _truth(a != b),
}


def _srand(g: Globals, s: float) -> float:
    g.rng = np.random.Generator(np.random.PCG64(int(s) & (2**63 - 1)))
    return 0.0


#: cpfg's output calls: ``printf``, and C's file output that cpfg's blocks may use
#: (``fp = fopen("out.txt", "w"); fprintf(fp, …); fclose(fp);``); sylva runs them as
#: nothing (``fopen`` gives 0) and writes no file.
_OUTPUT = frozenset({"printf", "fprintf", "fflush", "fopen", "fclose", "fputs", "puts"})

_CPFG = {
    "ran": (1, lambda g, x: float(g.rng.random() * x)),
    "nran": (2, lambda g, m, s: float(g.rng.normal(m, s))),
    "srand": (1, _srand),
    "trunc": (1, lambda g, x: float(math.trunc(x))),
    "sign": (1, lambda g, x: float((x > 0) - (x < 0))),
    "fabs": (1, lambda g, x: abs(x)),
    # cpfg's trigonometry is in degrees (its D_TO_R / R_TO_D around C's functions)
    "sin": (1, lambda g, x: math.sin(math.radians(x))),
    "cos": (1, lambda g, x: math.cos(math.radians(x))),
    "tan": (1, lambda g, x: math.tan(math.radians(x))),
    "asin": (1, lambda g, x: math.degrees(math.asin(x)) if -1 <= x <= 1 else math.nan),
    "acos": (1, lambda g, x: math.degrees(math.acos(x)) if -1 <= x <= 1 else math.nan),
    "atan": (1, lambda g, x: math.degrees(math.atan(x))),
    "atan2": (2, lambda g, y, x: math.degrees(math.atan2(y, x))),
    "min": (2, lambda g, a, b: min(a, b)),
    "max": (2, lambda g, a, b: max(a, b)),
    "frac": (1, lambda g, x: x - math.floor(x)),
    "bran": (2, lambda g, a, b: float(g.rng.beta(a, b))),
    "biran": (2, lambda g, n, p: float(g.rng.binomial(int(n), p))),
}


def _call(name: str, args, g: Globals, where: str) -> float:
    if name in _OUTPUT:  # output only: sylva prints and writes nothing
        return 0.0
    if name in g.functions and name != "__ids__":
        return float(g.functions[name](*[_eval(a, g, where) for a in args]))
    values = [_eval(a, g, where) for a in args]
    if name in _CPFG:
        n, f = _CPFG[name]
        if len(values) != n:
            raise SylvaError(f"{where}: {name} takes {n} argument(s), got {len(values)}")
        return float(f(g, *values))
    spec = FUNCTIONS.get(name)
    if spec is None:
        known = ", ".join(sorted({*FUNCTIONS, *_CPFG}))
        raise SylvaError(f"{where}: unknown function {name!r}; expected one of {known}")
    f, lo, hi = spec
    if len(values) < lo or (hi is not None and len(values) > hi):
        raise SylvaError(f"{where}: {name} takes {lo}..{hi} argument(s), got {len(values)}")
    with np.errstate(all="ignore"):
        return float(f(*values))


def assigned_names(tree: Tree) -> set[str]:
    """The plain variables that the statements of ``tree`` assign (not arrays)."""
    return {str(t.children[0]) for t in tree.find_data("lvalue") if len(t.children) == 1}


class Schedule:
    """cpfg's ``StartEach:`` and ``EndEach:`` blocks, for :attr:`Program.statements`: the
    engine runs :meth:`before` ahead of each derivation step and :meth:`after` behind it,
    over its own copy of the globals (:meth:`fresh`: as ``Start:`` left them)."""

    def __init__(self, initial: Globals, before=None, after=None, source: str = "",
                 runtime=None):
        self.initial = initial
        self.runtime = runtime  # where production blocks find the running globals
        self._before = before  # (tree, where) or None
        self._after = after
        self.source = source
        #: the globals production blocks assign (the engine's one-module-at-a-time road)
        self.written: frozenset[str] = frozenset()

    def live_values(self) -> dict:
        """The running globals, as production blocks leave them."""
        g = self.runtime.globals if self.runtime is not None else self.initial
        return g.values

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Schedule):
            return NotImplemented
        return self.source == other.source and self.initial.values == other.initial.values

    __hash__ = None  # type: ignore[assignment]

    def fresh(self) -> Globals:
        import copy

        g = copy.deepcopy(self.initial)
        if self.runtime is not None:
            self.runtime.current = g
        return g

    def before(self, g: Globals, step: int) -> None:
        if self.runtime is not None:
            self.runtime.current = g
        if self._before is not None:
            run(self._before[0], g, f"{self._before[1]}, before step {step + 1}")

    def after(self, g: Globals, step: int) -> None:
        if self._after is not None:
            run(self._after[0], g, f"{self._after[1]}, after step {step + 1}")
