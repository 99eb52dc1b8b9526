"""The LSysVis language (``.lsys``, seed 001 §3): text to :class:`~sylva.lsystem.ast.Program`.

One file holds one L-system.  Each line is empty, a comment (``#`` to the end of the line), one
assignment ``name = value`` or one rule; all assignments come before the rules and ``axiom``
must be assigned::

    # a simple L-system (seed 001, Source code 1)
    rot = 30
    axiom = F
    F -> F[+F][-F]F

Rules are ``[left <] predecessor [> right] [: condition] -> [(weight)] [successor]``; ``->>``
makes a render rule.  The grammar is the data file ``lsys.lark``, parsed with Lark's LALR
parser one line at a time (like the thesis's parser), so a 1,000-rule file reads in a
fraction of a second.

Choices where the thesis is silent (seed 001 §9)
-----------------------------------------------
* **Module names.** A one-character name is any printable non-space character that is not
  syntax, so ABOP words such as ``{ } . ' % ! ; , @ $ | ~ & ^ \\ / + -`` and digits read as
  they are.  ``(`` ``)`` ``"`` ``#`` are always syntax and ``[`` ``]`` are the brackets.
  ``<`` ``>`` ``:`` ``=`` are syntax of rules and assignments and are never bare module names:
  write them quoted, ``"<"``.  ``,`` is syntax only inside parentheses.  Longer names are
  quoted, ``"leaf"``; a quoted name may hold any character but ``"`` and a line break, and
  ``"F"`` is the same module as ``F``.  Whitespace may stand anywhere between tokens, also
  between a module and its parameters: ``; (0, 0.7, 0)`` is ``;`` with three parameters.
* **Expressions** follow §3.4 with its recommended precedence (highest first): unary ``-``
  ``!``; ``**`` (right associative); ``* / %``; ``+ -``; ``<< >>``; ``< <= > >=``; ``== !=``;
  ``&&``; ``||``.  Unary minus binds tighter than ``**``, so ``-x**2`` is ``(-x)**2``.  A
  minus sign written directly before a number is part of the literal (``-4`` is
  ``Num(-4.0)``); ``- 4`` and ``-(4)`` are a negation.  ``True``/``False`` are 1 and 0.
  Functions are those of :data:`sylva.lsystem.expr.FUNCTIONS` (the thesis's ``sum sqrt sin
  cos tan abs pow`` and a few more); trigonometric functions take **radians** (turtle angles
  are in degrees).
* **Global variables** are constants evaluated when the file is read; an expression may use
  the user variables assigned before it.  Special variables are settings, not variables: an
  expression cannot read ``rot``.  Assigning a name twice is an error.
* **Colours** ``bg`` and ``color`` are clamped to [0, 1] as the thesis says; ``color_delta``
  is not.  The axiom's parameters are evaluated at once (the program stores numbers).
* **Brackets** must balance in the axiom and in every successor; a right context may leave
  them open, as cpfg's do (``A > [B``: a branch that begins with ``B`` follows; ``F > G]H``:
  ``G`` ends the branch and ``H`` follows it; matched module by module, see
  :mod:`sylva.lsystem._walk`); a left context holds no brackets; brackets never carry
  parameters and are never predecessors.  A rule binding one name twice is an error.

Extensions (so that every dialect converts to ``.lsys`` and back)
------------------------------------------------------------------
``seed = N``
    The random seed (the thesis's future work, §7), a non-negative integer.
``steps = N``
    The default number of derivation steps.
``consider = symbols``
    ABOP's consider set: context matching sees only these symbols (and the brackets).
``turtle = lsys | abop | classic | engine``
    Which turtle command table draws the word (default ``lsys``).
``reduction radius thickness`` (seed 000) and ``yaw pitch shrink`` (seed 004)
    Numeric settings of the other dialects' turtles.
``tropism = x, y, z``, ``elasticity = e``, ``elasticity_step = s``
    ABOP §2.3 tropism (``lsys`` and ``abop`` turtles): after every step the heading turns
    by ``e·|H × T|`` about ``H × T`` toward ``T`` (default ``T = 0, -1, 0``, gravity).
    ``@Ts(e)`` sets a branch's elasticity, ``@Ti(d)`` / ``@Td(d)`` add or take ``d``
    (default ``elasticity_step``).  ``@O(d)`` draws a sphere of diameter ``d``, ``@v``
    rolls to vertical (ABOP's ``$``), ``@M(x, y, z)`` moves to a point, ``@R(hx, hy, hz[,
    ux, uy, uz])`` sets the heading (and up).  ``@`` is a module of its own; the letters
    after it name the function, as in cpfg, and an ``@`` followed by anything else is an
    error.
``environment = light`` (or ``obstacle``, ``world``; options in parentheses)
    The environment of an open L-system (Měch & Prusinkiewicz 1996): between steps it
    sets the parameters of the communication modules ``?E(…)``
    (:mod:`sylva.lsystem.environment`, :mod:`sylva.environments`), e.g. ``environment =
    obstacle(shape = box, y = 2, sx = 3)``.
``decomposition:``, ``interpretation:``, ``production:``, ``group N:`` (section lines)
    The rules after ``decomposition:`` rewrite the word after every step (and the axiom),
    again and again until none applies, at most ``decomposition_depth = N`` times (default
    1; rules that still apply then are an error that names the module and the step).  The
    rules after ``interpretation:`` do so to the word the turtle draws, at most
    ``interpretation_depth`` times; seed 001's ``->>`` rules still apply once.  The rules
    after ``group N:`` are the productions of table ``N`` (ABOP §1.4's table L-systems,
    L-Py's groups); ``group = expression`` (of ``step``, the steps done before, from 0, and
    the global variables) picks each step's table, and the rules outside any group apply
    in every step.  ``production:`` returns to those.
``lsystem N:`` (a section line; N >= 1) and the calls ``?(N)`` … ``$``
    Sub-L-systems (cpfg's, for compound plants): the productions after ``lsystem N:``
    rewrite only the modules between a call ``?(N)`` and its ``$`` (calls nest; ``?(N)``
    belongs to the caller, ``$`` to the callee); the main productions only the others.
    ``?`` and ``$`` draw nothing, so in a program with sub-L-systems ``$`` is not ABOP's
    roll to vertical (write ``@v``).  Any other section line returns to the main L-system.

Special variables go to :attr:`Program.settings` (only those the file sets; ``bg``, ``color``
and ``color_delta`` as 3-tuples of floats, ``turtle`` as a string, the rest as floats), user
variables to :attr:`Program.constants`, ``seed``/``steps`` to :attr:`Program.seed` /
:attr:`Program.steps`, ``ignore``/``consider`` to :attr:`Program.ignore` /
:attr:`Program.consider`.

Examples
--------
>>> p = parse("rot = 30\\naxiom = F\\nF -> F[+F][-F]F\\n")
>>> p.settings["rot"], len(p.rules), p.rules[0].span.line
(30.0, 1, 3)
>>> r = parse_rule("A(x) : x > 1 -> B(x / 2)")
>>> r.condition == Binary(">", Var("x"), Num(1.0))
True
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable, Collection, Iterable, Mapping
from contextvars import ContextVar
from dataclasses import dataclass, replace
from functools import cache
from importlib import resources
from itertools import islice
from pathlib import Path

from lark import Lark, Token, Transformer
from lark.exceptions import (
    UnexpectedCharacters,
    UnexpectedEOF,
    UnexpectedInput,
    UnexpectedToken,
    VisitError,
)

from ...errors import LSystemSemanticError, LSystemSyntaxError, SylvaError
from ..ast import (
    MAX_STEPS,
    Binary,
    Call,
    Expr,
    Module,
    Num,
    Pattern,
    Program,
    Rule,
    Span,
    Unary,
    Var,
)
from ..environment import EnvironmentSpecError, parse_environment
from ..expr import FUNCTIONS, evaluate_constant, free_variables
from ._diagnostics import Where, describe_expected, join_words

__all__ = [
    "COLOUR_SETTINGS",
    "NUMERIC_SETTINGS",
    "PRECEDENCE",
    "RIGHT_ASSOCIATIVE",
    "SPECIAL_VARIABLES",
    "TURTLES",
    "parse",
    "parse_expr",
    "parse_rule",
    "parse_word",
]

#: Numeric special variables: Table 1 of seed 001 and the settings of seeds 000 and 004.
NUMERIC_SETTINGS: tuple[str, ...] = (
    "detail",
    "len",
    "thick",
    "rot",
    "len_delta",
    "thick_delta",
    "rot_delta",
    "reduction",
    "radius",
    "thickness",
    "yaw",
    "pitch",
    "shrink",
    "elasticity",
    "elasticity_step",
    "width_step",
)
#: Three-component special variables, and whether each is clamped to [0, 1] (the colours
#: ``bg``, ``color``, ``color_delta`` and the tropism vector).
COLOUR_SETTINGS: Mapping[str, bool] = {
    "bg": True,
    "color": True,
    "color_delta": False,
    "tropism": False,
}
#: The turtle command tables ``turtle = ...`` may name.
TURTLES: tuple[str, ...] = ("lsys", "abop", "classic", "engine")
#: Every name with a special meaning on the left of ``=``.
#: Whole-number program fields: the most passes of decomposition and interpretation rules.
DEPTHS: tuple[str, ...] = ("decomposition_depth", "interpretation_depth")
SPECIAL_VARIABLES: frozenset[str] = frozenset(
    (*NUMERIC_SETTINGS, *COLOUR_SETTINGS, *DEPTHS, "axiom", "ignore", "consider", "seed",
     "steps", "turtle", "group", "environment")
)  # fmt: skip
#: The section headers among the rules and the phase of the rules after them.
SECTIONS: Mapping[str, str] = {
    "production": "production",
    "decomposition": "decomposition",
    "interpretation": "interpretation",
    "group": "production",
    "lsystem": "production",
}
_SECTION_LINE = re.compile(
    r"\s*(production|decomposition|interpretation|group|lsystem)\b(?!\s*=)"
)

#: The functions that follow ``@`` in a word (cpfg's ``@O @v @M @R @Ts @Ti @Td``), for the
#: turtles that read them; ``T`` is followed by one of its own letters.
AT_FUNCTIONS: Mapping[str, frozenset[str]] = {
    "O": frozenset(),
    "v": frozenset(),
    "M": frozenset(),
    "R": frozenset(),
    "T": frozenset("sidxf"),
    # cpfg's: circle, disc, generalised cylinders, sides, contour, label
    "c": frozenset(),
    "o": frozenset(),
    "G": frozenset("scetr"),
    "!": frozenset(),
    "#": frozenset(),
    "L": frozenset(),
}
_AT_TURTLES = ("lsys", "abop")

_BLANK = re.compile(r"\s*(?:#.*)?\Z", re.DOTALL)
_ASSIGN = re.compile(r"\s*([A-Za-z_][A-Za-z0-9_]*)\s*=(?![=>])")
_LEADING_NAME = re.compile(r"\s*([A-Za-z_][A-Za-z0-9_]*)\b\s*")
_DIGITS = re.compile(r"\s*(\d+)\s*(?:#.*)?\Z", re.DOTALL)
#: ``name = number`` (NUMBER or NEG_NUMBER of lsys.lark): the common line, read without Lark.
_LITERAL_ASSIGN = re.compile(
    r"\s*([A-Za-z_][A-Za-z0-9_]*)\s*=\s*(-?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*(?:#.*)?\Z",
    re.DOTALL,
)
#: Names a plain number cannot be assigned to (they have their own checks and meanings).
_NOT_PLAIN = (SPECIAL_VARIABLES - set(NUMERIC_SETTINGS)) | {"True", "False"}
_WORD_NAME = re.compile(r"\s*([A-Za-z_][A-Za-z0-9_]*)\s*(?:#.*)?\Z", re.DOTALL)

_WHERE: ContextVar[Where] = ContextVar("sylva_lsys_where")


# --------------------------------------------------------------------------- the parser
@dataclass(slots=True)
class _Item:
    """A module or bracket as written, before it becomes a Module or Pattern."""

    symbol: str
    column: int
    bracket: bool
    params: tuple | None  # binding-name tokens or expressions; None without parentheses
    params_column: int


#: Binary operators and their precedence (higher binds tighter), seed 001 §3.4.
PRECEDENCE: Mapping[str, int] = {
    "||": 1,
    "&&": 2,
    "==": 3,
    "!=": 3,
    "<": 4,
    "<=": 4,
    ">": 4,
    ">=": 4,
    "<<": 5,
    ">>": 5,
    "+": 6,
    "-": 6,
    "*": 7,
    "/": 7,
    "%": 7,
    "**": 8,
}
#: Right-associative operators.
RIGHT_ASSOCIATIVE: frozenset[str] = frozenset({"**"})


def _group(items: list) -> Expr:
    """Group ``operand op operand op …`` by :data:`PRECEDENCE` (precedence climbing)."""
    operands: list[Expr] = [items[0]]
    ops: list[str] = []
    for i in range(1, len(items), 2):
        op = str(items[i])
        p = PRECEDENCE[op]
        while ops:
            top = PRECEDENCE[ops[-1]]
            if top > p or (top == p and op not in RIGHT_ASSOCIATIVE):
                right = operands.pop()
                operands.append(Binary(ops.pop(), operands.pop(), right))
            else:
                break
        ops.append(op)
        operands.append(items[i + 1])
    while ops:
        right = operands.pop()
        operands.append(Binary(ops.pop(), operands.pop(), right))
    return operands[0]


class _Build(Transformer):
    """Callbacks run by the LALR parser as it reduces (no parse tree is built).

    Each callback receives the list of its rule's children.
    """

    # ---- symbols and words
    def symbol(self, c):
        tok = c[0]
        name = str(tok)
        if tok.type == "LONGNAME":
            name = name[1:-1]
            where = _WHERE.get()
            if not name:
                raise where.error(
                    "empty quoted name; expected a module name between the quotes", tok.column
                )
            if name in ("[", "]"):
                raise where.error(
                    f"a bracket is written without quotes: {name} (brackets are not modules)",
                    tok.column,
                )
            if not name.isprintable():
                raise where.error("a quoted name may hold only printable characters", tok.column)
        elif not name.isprintable():
            raise _WHERE.get().error(
                f"unexpected character {name!r}; expected a printable module name", tok.column
            )
        return (name, tok.column, False)

    def bracket(self, c):
        return (str(c[0]), c[0].column, True)

    def pparams(self, c):
        return tuple(t for t in c if isinstance(t, Token) and t.type == "NAME"), c[0].column

    def fparams(self, c):
        return tuple(x for x in c if x is not None and not isinstance(x, Token)), c[0].column

    def litem(self, c):
        (name, col, bracket), params = c
        if params is None:
            return _Item(name, col, bracket, None, col)
        return _Item(name, col, bracket, params[0], params[1])

    sitem = litem

    def litems(self, c):
        return c

    def lctx(self, c):
        return (c[0] or [], c[1].column)

    def pred(self, c):
        return c[0]

    def rctx(self, c):
        return (c[1] or [], c[0].column)

    def cond(self, c):
        return (c[1], c[0].column)

    def arrow(self, c):
        return c[0]

    def weight(self, c):
        return (c[1], c[0].column)

    def succ(self, c):
        return c

    def rule(self, c):
        return c

    word = succ
    symbols = succ

    def exprs(self, c):
        out = []
        col = None
        for x in c:
            if isinstance(x, Token):
                col = x.end_column
            else:
                out.append((x, col))
        return out

    def expr_only(self, c):
        return c[0]

    def section(self, c):
        return c

    # ---- expressions
    def chain(self, c):
        return _group(c)

    def unary(self, c):
        op, operand = c
        if op.type == "PLUS":
            return operand
        return Unary(str(op), operand)

    def number(self, c):
        tok = c[0]
        v = float(tok)
        if not math.isfinite(v):
            raise _WHERE.get().error(f"the number {tok} is too large", tok.column)
        return Num(v)

    def var(self, c):
        tok = c[0]
        name = str(tok)
        if name == "True":
            return Num(1.0)
        if name == "False":
            return Num(0.0)
        where = _WHERE.get()
        return Var(name, Span(where.lineno, tok.column, where.filename))

    def call(self, c):
        name = c[0]
        args = tuple(x for x in c[2:] if x is not None and not isinstance(x, Token))
        where = _WHERE.get()
        spec = FUNCTIONS.get(str(name))
        if spec is None:
            raise where.semantic(
                f"unknown function {str(name)!r}; expected one of " + join_words(sorted(FUNCTIONS)),
                name.column,
            )
        _, lo, hi = spec
        k = len(args)
        if k < lo or (hi is not None and k > hi):
            want = str(lo) if hi == lo else f"at least {lo}" if hi is None else f"{lo} to {hi}"
            plural = "" if want == "1" else "s"
            raise where.semantic(f"{name}() expected {want} argument{plural}, got {k}", name.column)
        return Call(str(name), args, Span(where.lineno, name.column, where.filename))

    def paren(self, c):
        return c[1]


@cache
def _parser() -> Lark:
    grammar = resources.files(__package__).joinpath("lsys.lark").read_text(encoding="utf-8")
    return Lark(
        grammar,
        parser="lalr",
        lexer="contextual",
        start=["rule", "word", "symbols", "exprs", "expr_only", "section"],
        maybe_placeholders=True,
        transformer=_Build(),
    )


def _parse(text: str, start: str, where: Where):
    token = _WHERE.set(where)
    try:
        return _parser().parse(text, start=start)
    except UnexpectedInput as e:
        raise _translate(e, where) from None
    except VisitError as e:  # pragma: no cover - callbacks raise directly under LALR
        if isinstance(e.orig_exc, SylvaError):
            raise e.orig_exc from None
        raise
    except RecursionError:
        raise where.error("the line is nested too deeply to read", 1) from None
    finally:
        _WHERE.reset(token)


def _translate(e: UnexpectedInput, where: Where) -> LSystemSyntaxError:
    """A Lark error as a located message that says what was expected."""
    line = where.line
    if isinstance(e, UnexpectedCharacters):
        col = e.column
        ch = line[col - 1] if 0 < col <= len(line) else ""
        expected = set(e.allowed or ())
        if ch == '"':
            return where.error("unterminated quoted name; expected a closing '\"'", col)
        if line[col - 1 : col + 1] == "=>":
            return where.error(
                "'=>' is not an arrow; expected '->' (or '->>' for a render rule)", col
            )
        if ch == "=" and "EQ" in expected:
            return where.error("unexpected '='; expected an operator (compare with '==')", col)
        if ch in "<>:=" and "SYMBOL" in expected:
            msg = (
                f"unexpected '{ch}': it is syntax and cannot be a one-character module name "
                f'(write it quoted, "{ch}"); expected {describe_expected(expected)}'
            )
            return where.error(msg, col)
        what = f"character {ch!r}" if ch else "end of the line"
        return where.error(f"unexpected {what}; expected {describe_expected(expected)}", col)
    if isinstance(e, UnexpectedToken):
        tok = e.token
        expected = set(e.accepts or e.expected or ())
        if tok.type == "$END":
            return where.error(
                f"unexpected end of the line; expected {describe_expected(expected)}",
                where.end_column(),
            )
        return where.error(
            f"unexpected '{tok}'; expected {describe_expected(expected)}", tok.column
        )
    if isinstance(e, UnexpectedEOF):
        return where.error(
            f"unexpected end of the line; expected {describe_expected(e.expected)}",
            where.end_column(),
        )
    return where.error(str(e), getattr(e, "column", 1) or 1)  # pragma: no cover


# --------------------------------------------------------------------------- semantics
def _check_vars(expr: Expr, known: Collection[str], where: Where, hint: Callable[[], str]) -> None:
    """Raise at the first variable of ``expr`` that is not in ``known``.

    ``hint`` builds the end of the message; it is called only when a variable is unknown,
    so that reading a file with many names stays linear in its length.
    """
    stack = [expr]
    while stack:
        node = stack.pop()
        if isinstance(node, Var):
            if node.name not in known:
                col = node.span.column if node.span else 1
                if node.name in SPECIAL_VARIABLES:
                    extra = (
                        f"; {node.name!r} is a special variable (a setting), which expressions "
                        "cannot read; expected a user variable"
                    )
                else:
                    extra = hint()
                raise where.semantic(f"unknown variable {node.name!r}{extra}", col)
        elif isinstance(node, Unary):
            stack.append(node.operand)
        elif isinstance(node, Binary):
            stack.append(node.right)
            stack.append(node.left)
        elif isinstance(node, Call):
            stack.extend(reversed(node.args))


def _known_hint(names: Iterable[str], what: str) -> str:
    """``; expected WHAT (known here: a, b, …)``, naming at most 12 of ``names``."""
    shown = list(islice(names, 13))
    if not shown:
        return f"; expected {what}"
    listed = ", ".join(shown[:12]) + (" …" if len(shown) > 12 else "")
    return f"; expected {what} (known here: {listed})"


class _Names(Collection[str]):
    """The names of several mappings seen as one collection, without copying them."""

    __slots__ = ("_parts",)

    def __init__(self, *parts: Collection[str]) -> None:
        self._parts = parts

    def __contains__(self, name: object) -> bool:
        return any(name in p for p in self._parts)

    def __iter__(self):
        seen: set[str] = set()
        for p in self._parts:
            for name in p:
                if name not in seen:
                    seen.add(name)
                    yield name

    def __len__(self) -> int:
        return sum(1 for _ in self)


def _evaluate(expr: Expr, column: int, where: Where, constants: Mapping[str, float]) -> float:
    _check_vars(
        expr,
        constants,
        where,
        lambda: _known_hint(constants, "a variable assigned on an earlier line"),
    )
    try:
        value = float(evaluate_constant(expr, constants))  # IEEE: 1/0 is inf, checked below
    except SylvaError as e:
        raise where.semantic(getattr(e, "message", str(e)), column) from None
    except (ArithmeticError, ValueError, TypeError) as e:
        raise where.semantic(f"cannot evaluate this value: {e}", column) from None
    except RecursionError:
        raise where.semantic(
            "the expression is nested too deeply to evaluate; expected a simpler one", column
        ) from None
    if not math.isfinite(value):
        raise where.semantic(
            f"the value is {value}; expected a finite number (a division by zero or overflow?)",
            column,
        )
    return value


def _balance(items: list[_Item], where: Where, what: str, open_ok: bool = False) -> None:
    """Check that the brackets of ``items`` balance, and that they carry no parameters
    (``open_ok``: a right context may leave its brackets open, as cpfg's do)."""
    stack: list[_Item] = []
    for it in items:
        if not it.bracket:
            continue
        if it.params is not None:
            raise where.semantic(
                f"'{it.symbol}' cannot have parameters: brackets are not modules",
                it.params_column,
            )
        if it.symbol == "[":
            stack.append(it)
        elif not stack:
            if open_ok:
                continue
            raise where.semantic(f"unmatched ']' in {what}; expected a '[' before it", it.column)
        else:
            stack.pop()
    if stack and not open_ok:
        raise where.semantic(f"unclosed '[' in {what}; expected a matching ']'", stack[-1].column)


def _modules(items: list[_Item], where: Where, what: str) -> list[tuple[Module, _Item]]:
    _balance(items, where, what)
    return [(Module(it.symbol, tuple(it.params or ())), it) for it in items]


def _check_at(items: list[_Item], where: Where) -> None:
    """Every ``@`` of a written word followed by a function in :data:`AT_FUNCTIONS`."""
    want = "@O, @o, @c, @v, @M, @R, @Ts, @Ti, @Td, @Tx, @Tf, @Gs, @Gc, @Ge, @Gt, @Gr, @!, @# or @L"
    for k, it in enumerate(items):
        if it.bracket or it.symbol != "@":
            continue
        if it.params is not None:
            raise where.semantic(
                f"'@' takes no parameters: they belong to its function; expected {want}",
                it.params_column,
            )
        nxt = items[k + 1] if k + 1 < len(items) else None
        if nxt is None or nxt.bracket or nxt.symbol not in AT_FUNCTIONS:
            got = f"'@{nxt.symbol}'" if nxt is not None else "'@' at the end of the word"
            raise where.semantic(f"unknown @ module {got}; expected {want}", it.column)
        subs = AT_FUNCTIONS[nxt.symbol]
        if subs:
            last = items[k + 2] if k + 2 < len(items) else None
            if last is None or last.bracket or last.symbol not in subs:
                got = f"'@{nxt.symbol}{last.symbol}'" if last is not None else f"'@{nxt.symbol}'"
                raise where.semantic(f"unknown @ module {got}; expected {want}", it.column)


def _first_column(line: str) -> int:
    return len(line) - len(line.lstrip()) + 1


def _check_weight(w: Expr, column: int, bindings, constants, where: Where) -> None:
    """A weight known when the file is read must be a positive finite number (seed 001
    §2.2: weights are positive).  One that reads the rule's parameters is evaluated per
    application: where it is 0 or negative the rule does not apply there, and a value that
    is not a finite number is an error of the derivation."""
    names = free_variables(w)
    if names & set(bindings):
        return
    if names and not isinstance(constants, Mapping):
        return  # the values of the globals are not known here
    value = _evaluate(w, column, where, constants or {})
    if not value > 0:
        raise where.semantic(
            f"the weight is {value:g}; expected a positive number (seed 001 §2.2: every "
            "rule has a positive weight; to switch a rule off, give it a condition)",
            column,
        )


def _build_rule(parts, where: Where, constants: Collection[str] | None) -> Rule:
    lctx, pred, rctx, cond, arrow, weight, succ = parts
    bindings: dict[str, int] = {}

    def pattern(it: _Item) -> Pattern:
        if it.bracket:
            if it.params is not None:
                raise where.semantic(
                    f"'{it.symbol}' cannot have parameters: brackets are not modules",
                    it.params_column,
                )
            return Pattern(it.symbol)
        names = []
        for tok in it.params or ():
            name = str(tok)
            if name in bindings:
                raise where.semantic(
                    f"the parameter name {name!r} is bound twice in this rule; "
                    "expected a different name",
                    tok.column,
                )
            if name in ("True", "False"):
                raise where.semantic(f"{name} is a constant; expected a parameter name", tok.column)
            bindings[name] = tok.column
            names.append(name)
        return Pattern(it.symbol, tuple(names))

    left: list[Pattern] = []
    if lctx is not None:
        items, lt_col = lctx
        if not items:
            raise where.error("empty left context; expected modules before '<'", lt_col)
        for it in items:
            if it.bracket:
                raise where.semantic(
                    f"a left context cannot contain '{it.symbol}': it is the path of modules "
                    "towards the root (seed 001 §2.5); expected modules only",
                    it.column,
                )
        left = [pattern(it) for it in items]
    if len(pred) > 1:
        raise where.error(
            f"the predecessor is one module, but {len(pred)} are written; expected '<' after "
            "a left context, '>' before a right context, ':' or an arrow '->'",
            pred[1].column,
        )
    p = pred[0]
    if p.bracket:
        raise where.semantic(
            f"'{p.symbol}' cannot be a predecessor: brackets are never rewritten", p.column
        )
    predecessor = pattern(p)
    right: list[Pattern] = []
    if rctx is not None:
        items, gt_col = rctx
        if not items:
            raise where.error("empty right context; expected modules after '>'", gt_col)
        _balance(items, where, "the right context", open_ok=True)
        right = [pattern(it) for it in items]

    if constants is None:
        known: Collection[str] | None = None
    else:
        known = _Names(bindings, constants)

        def hint() -> str:
            return _known_hint(known, "a parameter of the rule or a global variable")

    def check(expr: Expr) -> None:
        if known is not None:
            _check_vars(expr, known, where, hint)

    condition = None
    if cond is not None:
        condition = cond[0]
        check(condition)
    w: Expr = Num(1.0)
    if weight is not None:
        w = weight[0]
        check(w)
        _check_weight(w, weight[1] + 1, bindings, constants, where)
    successor = []
    for m, _ in _modules(succ, where, "the successor"):
        for a in m.args:
            check(a)
        successor.append(m)
    return Rule(
        predecessor=predecessor,
        successor=tuple(successor),
        left=tuple(left),
        right=tuple(right),
        condition=condition,
        weight=w,
        render=arrow.type == "RARROW",
        span=Span(where.lineno, _first_column(where.line), where.filename),
    )


# --------------------------------------------------------------------------- the file
class _Reader:
    """Reads one ``.lsys`` file line by line into the parts of a Program."""

    def __init__(self, filename: str | None) -> None:
        self.filename = filename
        self.constants: dict[str, float] = {}
        self.settings: dict[str, object] = {}
        self.assigned: dict[str, int] = {}
        self.axiom: tuple[Module, ...] | None = None
        self.ignore: frozenset[str] = frozenset()
        self.consider: frozenset[str] | None = None
        self.seed: int | None = None
        self.steps: int | None = None
        self.steps_at: Span | None = None
        self.rules: list[Rule] = []
        self.first_rule_line: int | None = None
        self.at_words: list[tuple[list[_Item], Where]] = []  # checked once the turtle is known
        self.phase = "production"  # of the rules that follow: set by section headers
        self.group = 0
        self.lsystem = 0  # of the productions that follow: set by 'lsystem N:'
        self.group_expr: Expr | None = None
        self.depths: dict[str, int] = {}

    def read(self, text: str) -> None:
        if text.startswith("\ufeff"):
            text = text[1:]
        settings, constants, assigned = self.settings, self.constants, self.assigned
        for lineno, line in enumerate(text.splitlines(), 1):
            fast = _LITERAL_ASSIGN.match(line)
            if fast and self.first_rule_line is None:
                name = fast.group(1)
                if name not in assigned and name not in _NOT_PLAIN:
                    v = float(fast.group(2))
                    if math.isfinite(v):  # else the full path names the error
                        assigned[name] = lineno
                        (settings if name in NUMERIC_SETTINGS else constants)[name] = v
                        continue
            if _BLANK.match(line):
                continue
            where = Where(line, lineno, self.filename)
            if _SECTION_LINE.match(line):
                if self.first_rule_line is None:
                    self.first_rule_line = lineno
                self.section(_parse(line, "section", where), where)
                continue
            m = _ASSIGN.match(line)
            if m:
                if self.first_rule_line is not None:
                    raise where.error(
                        f"assignment of {m.group(1)!r} after the rules (the first rule is on "
                        f"line {self.first_rule_line}); expected every assignment before the rules",
                        m.start(1) + 1,
                    )
                self.assign(m, where)
            else:
                if self.first_rule_line is None:
                    self.first_rule_line = lineno
                try:
                    parts = _parse(line, "rule", where)
                except LSystemSyntaxError:
                    lead = _LEADING_NAME.match(line)
                    if lead and lead.group(1) in SPECIAL_VARIABLES:
                        raise where.error(
                            f"expected '=' after {lead.group(1)!r} to assign it "
                            "(a rule would need an arrow '->')",
                            lead.end() + 1,
                        ) from None
                    raise
                rule = _build_rule(parts, where, self.constants)
                if self.phase != "production" or self.group or self.lsystem:
                    rule = replace(rule, phase=self.phase, group=self.group,
                                   lsystem=self.lsystem)  # fmt: skip
                self.rules.append(rule)
                if any(it.symbol == "@" and not it.bracket for it in parts[-1]):
                    self.at_words.append((parts[-1], where))

    def section(self, parts, where: Where) -> None:
        kw, number, _colon = parts
        name = str(kw)
        self.lsystem = 0
        if name in ("group", "lsystem"):
            what = "a group" if name == "group" else "a sub-L-system"
            if number is None:
                raise where.error(
                    f"expected the {name}'s number: '{name} 1:'", where.end_column()
                )
            v = float(number)
            low = 0 if name == "group" else 1
            if not v.is_integer() or v < low:
                raise where.semantic(
                    f"{what} is a whole number >= {low}, got {number}", number.column
                )
            if name == "group":
                self.group = int(v)
            else:
                self.group, self.lsystem = 0, int(v)
        elif number is not None:
            raise where.error(
                f"'{name}:' takes no number; expected ':' after {name!r}", number.column
            )
        else:
            self.group = 0
        self.phase = SECTIONS[name]

    def assign(self, m: re.Match, where: Where) -> None:
        name = m.group(1)
        name_col = m.start(1) + 1
        if name in self.assigned:
            raise where.semantic(
                f"{name!r} is already assigned on line {self.assigned[name]}; "
                "expected one assignment per name: global variables are constants",
                name_col,
            )
        if name in ("True", "False"):
            raise where.semantic(f"{name} is a constant and cannot be assigned", name_col)
        self.assigned[name] = where.lineno
        line = where.line
        value_col = m.end() + 1
        rest = line[m.end() :]
        value_col += len(rest) - len(rest.lstrip())
        padded = " " * m.end() + rest  # keeps Lark's columns equal to the line's
        if name == "axiom":
            items = _parse(padded, "word", where)
            if not items:
                raise where.error("the axiom is empty; expected a word such as 'F'", value_col)
            if any(it.symbol == "@" and not it.bracket for it in items):
                self.at_words.append((items, where))
            axiom = []
            for mod, it in _modules(items, where, "the axiom"):
                args = tuple(
                    Num(_evaluate(a, it.params_column, where, self.constants)) for a in mod.args
                )
                axiom.append(Module(mod.symbol, args))
            self.axiom = tuple(axiom)
        elif name in ("ignore", "consider"):
            syms = _parse(padded, "symbols", where)
            for _sym, col, bracket in syms:
                if bracket:
                    why = (
                        "brackets cannot be ignored: they give the word its tree structure"
                        if name == "ignore"
                        else "brackets are always considered; leave them out"
                    )
                    raise where.semantic(f"{why}; expected module names", col)
            names = frozenset(s for s, _, _ in syms)
            if name == "ignore":
                self.ignore = names
            else:
                self.consider = names
        elif name == "group":
            expr = _parse(padded, "expr_only", where)
            _check_vars(
                expr,
                {"step", *self.constants},
                where,
                lambda: _known_hint(["step", *self.constants], "'step' or a global variable"),
            )
            self.group_expr = expr
        elif name == "environment":
            text = rest.split("#")[0].strip()
            try:
                parse_environment(text)
            except EnvironmentSpecError as exc:
                raise where.semantic(f"{exc}", value_col + exc.column) from None
            self.settings["environment"] = text
        elif name == "turtle":
            t = _WORD_NAME.match(rest)
            if not t or t.group(1) not in TURTLES:
                raise where.semantic(
                    f"unknown turtle {rest.split('#')[0].strip()!r}; expected "
                    + join_words(TURTLES),
                    value_col,
                )
            self.settings["turtle"] = t.group(1)
        else:
            self.assign_numbers(name, name_col, value_col, padded, where)

    def assign_numbers(
        self, name: str, name_col: int, value_col: int, padded: str, where: Where
    ) -> None:
        parts = _parse(padded, "exprs", where)
        cols = [value_col if c is None else _skip_spaces(where.line, c) for _, c in parts]
        want = 3 if name in COLOUR_SETTINGS else 1
        if len(parts) != want:
            if name == "tropism":
                msg = (
                    f"'tropism' is a vector: expected 3 components (x, y, z, separated by "
                    f"commas), got {len(parts)}"
                )
            elif want == 3:
                msg = (
                    f"{name!r} is a colour: expected 3 components (red, green, blue between "
                    f"0 and 1, separated by commas), got {len(parts)}"
                )
            else:
                msg = f"{name!r} expected one number, got {len(parts)} separated by commas"
            raise where.semantic(msg, cols[min(len(cols), want + 1) - 1] if cols else value_col)
        values = [
            _evaluate(expr, col, where, self.constants) for (expr, _), col in zip(parts, cols)
        ]
        if name in COLOUR_SETTINGS:
            if COLOUR_SETTINGS[name]:
                values = [min(max(v, 0.0), 1.0) for v in values]
            self.settings[name] = tuple(values)
        elif name in NUMERIC_SETTINGS:
            self.settings[name] = values[0]
        elif name in DEPTHS:
            v = values[0]
            if not v.is_integer() or v < 1:
                raise where.semantic(f"{name!r} expected a whole number >= 1, got {v:g}", value_col)
            self.depths[name] = int(v)
        elif name in ("seed", "steps"):
            digits = _DIGITS.match(padded)
            if digits:  # exact, also beyond 2**53
                n = int(digits.group(1))
            else:
                v = values[0]
                if not v.is_integer() or v < 0:
                    raise where.semantic(
                        f"{name!r} expected a whole number >= 0, got {v:g}", value_col
                    )
                n = int(v)
            if name == "steps":
                if n > MAX_STEPS:
                    big = f"{n:,}" if n < 10**12 else f"{float(n):.3g}"
                    raise where.semantic(
                        f"'steps' is {big}; expected at most {MAX_STEPS:,} derivation steps "
                        "(sylva.lsystem.MAX_STEPS)",
                        value_col,
                    )
                self.steps_at = Span(where.lineno, value_col, self.filename)
            setattr(self, name, n)
        else:
            self.constants[name] = values[0]

    def program(self, text: str) -> Program:
        if self.settings.get("turtle", "lsys") in _AT_TURTLES:
            for items, where in self.at_words:
                _check_at(items, where)
        if self.axiom is None:
            lines = text.splitlines()
            line = self.first_rule_line or 1
            msg = "no axiom: every L-system must assign 'axiom' (e.g. 'axiom = F')"
            if self.first_rule_line:
                msg += " before its rules"
            raise LSystemSemanticError(
                msg,
                filename=self.filename,
                line=line,
                column=1,
                source_line=lines[line - 1] if lines else None,
            )
        return Program(
            axiom=self.axiom,
            rules=tuple(self.rules),
            constants=self.constants,
            ignore=self.ignore,
            consider=self.consider,
            settings=self.settings,
            steps=self.steps,
            steps_at=self.steps_at,
            seed=self.seed,
            dialect="lsys",
            name=Path(self.filename).stem if self.filename else None,
            filename=self.filename,
            group=self.group_expr,
            **self.depths,
        )


def _skip_spaces(line: str, col: int) -> int:
    i = col - 1
    while i < len(line) and line[i].isspace():
        i += 1
    return i + 1


# --------------------------------------------------------------------------- public API
def parse(text: str, filename: str | None = None) -> Program:
    """Read an ``.lsys`` text.

    Parameters
    ----------
    text : str
        The whole file.
    filename : str, optional
        Used in error messages and kept in :attr:`Program.filename`; its stem names the
        program.

    Returns
    -------
    Program

    Raises
    ------
    LSystemSyntaxError
        For text that does not parse; :class:`LSystemSemanticError` (a subclass) for text
        that parses but means nothing valid (an unknown variable, unbalanced brackets, a
        missing axiom …).  Every error names the file, line and column and says what was
        expected.

    Examples
    --------
    >>> p = parse("axiom = a\\na -> b\\nb -> aa")
    >>> [str(r.predecessor.symbol) for r in p.rules]
    ['a', 'b']
    """
    reader = _Reader(filename)
    reader.read(text)
    return reader.program(text)


def _single_line(text: str, what: str, filename: str | None) -> Where:
    lines = [ln for ln in text.splitlines() if ln.strip()]
    if len(lines) > 1:
        second = text.splitlines().index(lines[1]) + 1
        raise LSystemSyntaxError.at(
            f"{what} is one line; expected the end of the text", text, second, 1, filename
        )
    return Where(lines[0] if lines else "", 1, filename)


def parse_rule(
    text: str,
    *,
    constants: Collection[str] | Mapping[str, float] | None = None,
    filename: str | None = None,
) -> Rule:
    """Parse one rule, e.g. ``"A(x) : x>1 -> B(x/2)"``.

    Parameters
    ----------
    text : str
        One rule line.
    constants : collection of str, optional
        The global variable names the rule may read.  When given, any other variable that
        is not a parameter of the rule is an error; when ``None`` variables are not checked.
    filename : str, optional
        For error messages.

    Examples
    --------
    >>> r = parse_rule("b < a ->(2) ab")
    >>> r.left, r.predecessor, [m.symbol for m in r.successor], r.weight
    ((Pattern(symbol='b', params=()),), Pattern(symbol='a', params=()), ['a', 'b'], Num(value=2.0))
    """
    where = _single_line(text, "a rule", filename)
    if not where.line.strip() or _ASSIGN.match(where.line):
        raise where.error(
            "expected a rule such as 'A -> B' (an assignment is not a rule)",
            _first_column(where.line),
        )
    return _build_rule(_parse(where.line, "rule", where), where, constants)


def parse_expr(text: str, *, filename: str | None = None) -> Expr:
    """Parse one expression, e.g. ``"x*2 + 1"``.

    Examples
    --------
    >>> parse_expr("-x**2") == Binary("**", Unary("-", Var("x")), Num(2.0))
    True
    >>> parse_expr("2 ** -1")
    Binary(op='**', left=Num(value=2.0), right=Num(value=-1.0))
    """
    where = _single_line(text, "an expression", filename)
    return _parse(where.line, "expr_only", where)


def parse_word(
    text: str,
    *,
    constants: Mapping[str, float] | None = None,
    evaluate: bool = False,
    filename: str | None = None,
) -> tuple[Module, ...]:
    """Parse a word such as ``"F(1)[+A(x*2)]"`` into modules.

    Parameters
    ----------
    text : str
        The word (one line).  Brackets must balance.
    constants : mapping of str to float, optional
        Global variables; with ``evaluate=True`` the parameters are evaluated against them
        (as for ``axiom``) and become numbers.
    evaluate : bool
        Evaluate the parameters now (every variable must be in ``constants``).

    Examples
    --------
    >>> [m.symbol for m in parse_word('a"jmeno1"[b(5, 6)"dlouhe_jmeno"(9.5, -4)]')]
    ['a', 'jmeno1', '[', 'b', 'dlouhe_jmeno', ']']
    """
    where = _single_line(text, "a word", filename)
    items = _parse(where.line, "word", where)
    mods = _modules(items, where, "the word")
    if not evaluate:
        return tuple(m for m, _ in mods)
    consts = dict(constants or {})
    return tuple(
        Module(m.symbol, tuple(Num(_evaluate(a, it.params_column, where, consts)) for a in m.args))
        for m, it in mods
    )
