"""Writing a :class:`~sylva.lsystem.ast.Program` as ``.lsys`` text (seed 001).

The text reads back to an equal program: ``lsysvis.parse(format_program(p)) == p`` for every
program a dialect reads.  Expressions are printed with the fewest parentheses that keep their
structure under the precedence of :data:`~sylva.lsystem.dialects.lsysvis.PRECEDENCE`.

Examples
--------
>>> from sylva.lsystem.ast import Binary, Num, Var
>>> format_expr(Binary("*", Binary("+", Var("x"), Num(1.0)), Num(2.0)))
'(x + 1) * 2'
"""

from __future__ import annotations

import math
import re
from collections.abc import Iterable, Sequence

from ..ast import Binary, Call, Expr, Module, Num, Pattern, Program, Rule, Unary, Var
from ..lstring import format_number
from .lsysvis import (
    COLOUR_SETTINGS,
    DEPTHS,
    NUMERIC_SETTINGS,
    PRECEDENCE,
    RIGHT_ASSOCIATIVE,
    SECTIONS,
    SPECIAL_VARIABLES,
    TURTLES,
)

__all__ = [
    "format_expr",
    "format_module",
    "format_pattern",
    "format_program",
    "format_rule",
    "format_symbol",
    "format_word",
]

_IDENT = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\Z")
# "?" is quoted so that a module ? before P, H, U, L or E is not read back as a query module.
_NOT_BARE = set('()"#<>:=[]?')
_UNARY_PRECEDENCE = 9  # above every binary operator, ** included (seed 001 §3.4)
_ATOM = 10


def format_symbol(name: str) -> str:
    """A module name as ``.lsys`` writes it: bare when one plain character, else quoted.

    >>> format_symbol("F"), format_symbol("leaf"), format_symbol("<"), format_symbol("[")
    ('F', '"leaf"', '"<"', '[')
    """
    if name in ("[", "]"):
        return name
    if not name or '"' in name or not name.isprintable():
        raise ValueError(f"the module name {name!r} cannot be written in .lsys")
    if len(name) == 1 and name not in _NOT_BARE and not name.isspace():
        return name
    return f'"{name}"'


def _number(v: float) -> str:
    v = float(v)
    if not math.isfinite(v):
        raise ValueError(f"the number {v} cannot be written in .lsys")
    return format_number(v)


def _expr(e: Expr) -> tuple[str, int]:
    """Text of ``e`` and the precedence of its outermost operator."""
    if isinstance(e, Num):
        return _number(e.value), _ATOM
    if isinstance(e, Var):
        if not _IDENT.match(e.name) or e.name in ("True", "False"):
            raise ValueError(f"{e.name!r} cannot be written as a variable name")
        return e.name, _ATOM
    if isinstance(e, Call):
        if not _IDENT.match(e.func):
            raise ValueError(f"{e.func!r} cannot be written as a function name")
        return f"{e.func}({', '.join(_expr(a)[0] for a in e.args)})", _ATOM
    if isinstance(e, Unary):
        if e.op not in ("-", "!"):
            raise ValueError(f"unknown unary operator {e.op!r}")
        text, prec = _expr(e.operand)
        # A number right after '-' would read as a negative literal: keep the negation.
        if prec < _UNARY_PRECEDENCE or isinstance(e.operand, (Num, Unary)):
            text = f"({text})"
        return e.op + text, _UNARY_PRECEDENCE
    if isinstance(e, Binary):
        p = PRECEDENCE.get(e.op)
        if p is None:
            raise ValueError(f"unknown binary operator {e.op!r}")
        lt, lp = _expr(e.left)
        rt, rp = _expr(e.right)
        right_assoc = e.op in RIGHT_ASSOCIATIVE
        if lp < p or (lp == p and right_assoc):
            lt = f"({lt})"
        if rp < p or (rp == p and not right_assoc):
            rt = f"({rt})"
        return f"{lt} {e.op} {rt}", p
    raise ValueError(f"not an expression: {e!r}")


def format_expr(expr: Expr) -> str:
    """An expression as text, with the fewest parentheses that keep its structure.

    >>> from sylva.lsystem.dialects.lsysvis import parse_expr
    >>> format_expr(parse_expr("((a - b) - (c - d)) ** (2 ** 3)"))
    '(a - b - (c - d)) ** 2 ** 3'
    """
    try:
        return _expr(expr)[0]
    except RecursionError:
        raise ValueError("the expression is nested too deeply to write") from None


def format_module(m: Module) -> str:
    """``F(x * 2, 1)``."""
    if m.symbol in ("[", "]"):
        if m.args:
            raise ValueError(f"'{m.symbol}' cannot have parameters")
        return m.symbol
    text = format_symbol(m.symbol)
    if m.args:
        text += "(" + ", ".join(format_expr(a) for a in m.args) + ")"
    return text


def format_pattern(p: Pattern) -> str:
    """``A(x, y)``."""
    if p.symbol in ("[", "]"):
        if p.params:
            raise ValueError(f"'{p.symbol}' cannot have parameters")
        return p.symbol
    for name in p.params:
        if not _IDENT.match(name) or name in ("True", "False"):
            raise ValueError(f"{name!r} cannot be written as a parameter name")
    text = format_symbol(p.symbol)
    if p.params:
        text += "(" + ", ".join(p.params) + ")"
    return text


def format_word(modules: Iterable[Module]) -> str:
    """A word: modules one after another.

    >>> format_word([Module("F", (Num(1.0),)), Module("["), Module("leaf"), Module("]")])
    'F(1)["leaf"]'
    """
    return "".join(format_module(m) for m in modules)


def _patterns(ps: Sequence[Pattern]) -> str:
    return "".join(format_pattern(p) for p in ps)


def format_rule(rule: Rule) -> str:
    """One rule line.

    >>> from sylva.lsystem.dialects.lsysvis import parse_rule
    >>> format_rule(parse_rule("b<a(x):x>1->(3)ab(x+1)"))
    'b < a(x) : x > 1 ->(3) ab(x + 1)'
    """
    text = ""
    if rule.left:
        text += _patterns(rule.left) + " < "
    if rule.predecessor.symbol in ("[", "]"):
        raise ValueError("a bracket cannot be a predecessor")
    text += format_pattern(rule.predecessor)
    if rule.right:
        text += " > " + _patterns(rule.right)
    if rule.condition is not None:
        text += " : " + format_expr(rule.condition)
    text += " ->>" if rule.render else " ->"
    if rule.weight != Num(1.0):
        text += f"({format_expr(rule.weight)})"
    if rule.successor:
        text += " " + format_word(rule.successor)
    return text


def _variable_name(name: str) -> str:
    if not _IDENT.match(name) or name in SPECIAL_VARIABLES or name in ("True", "False"):
        raise ValueError(f"{name!r} cannot be written as a global variable")
    return name


def format_program(program: Program) -> str:
    """A program as ``.lsys`` text: settings and variables, the axiom, then the rules.

    Raises
    ------
    ValueError
        For something ``.lsys`` cannot write: a setting it does not know, a module name
        with a double quote, a non-finite number, an empty axiom.

    Examples
    --------
    >>> from sylva.lsystem.dialects.lsysvis import parse
    >>> print(format_program(parse("rot=30\\naxiom=F\\nF->F[+F][-F]F")), end="")
    rot = 30
    axiom = F
    <BLANKLINE>
    F -> F[+F][-F]F
    """
    lines: list[str] = []
    if any(r.block is not None for r in program.rules):
        raise ValueError("cpfg's statement blocks of productions have no .lsys spelling")
    if program.statements is not None:
        raise ValueError("statements between steps (cpfg's StartEach:/EndEach:) have no "
                         ".lsys form")  # fmt: skip
    settings = dict(program.settings)
    unknown = set(settings) - set(NUMERIC_SETTINGS) - set(COLOUR_SETTINGS)
    unknown -= {"turtle", "environment"}
    if unknown:
        raise ValueError(f"settings without a .lsys form: {', '.join(sorted(unknown))}")
    if "turtle" in settings:
        turtle = str(settings["turtle"])
        if turtle not in TURTLES:
            raise ValueError(f"unknown turtle {turtle!r}")
        lines.append(f"turtle = {turtle}")
    if "environment" in settings:
        lines.append(f"environment = {settings['environment']}")
    if program.steps is not None:
        lines.append(f"steps = {int(program.steps)}")
    if program.seed is not None:
        lines.append(f"seed = {int(program.seed)}")
    for name in DEPTHS:
        depth = int(getattr(program, name))
        if depth != 1:
            lines.append(f"{name} = {depth}")
    for name in NUMERIC_SETTINGS:
        if name in settings:
            lines.append(f"{name} = {_number(settings[name])}")  # type: ignore[arg-type]
    for name in COLOUR_SETTINGS:
        if name in settings:
            rgb = tuple(settings[name])  # type: ignore[arg-type]
            if len(rgb) != 3:
                raise ValueError(f"{name!r} needs 3 components, got {len(rgb)}")
            lines.append(f"{name} = " + ", ".join(_number(c) for c in rgb))
    for name, value in program.constants.items():
        lines.append(f"{_variable_name(name)} = {_number(value)}")
    for name, symbols in (("ignore", program.ignore), ("consider", program.consider or ())):
        if set(symbols) & {"[", "]"}:
            raise ValueError(f"brackets cannot be in the {name} set")
    if program.ignore:
        lines.append("ignore = " + "".join(format_symbol(s) for s in sorted(program.ignore)))
    if program.consider is not None:
        lines.append(
            ("consider = " + "".join(format_symbol(s) for s in sorted(program.consider))).rstrip()
        )
    if program.group is not None:
        lines.append(f"group = {format_expr(program.group)}")
    if not program.axiom:
        raise ValueError("the axiom is empty")
    lines.append("axiom = " + format_word(program.axiom))
    if program.rules:
        lines.append("")
        section = ("production", 0, 0)
        for r in program.rules:
            lsys = getattr(r, "lsystem", 0)
            if (r.phase, r.group, lsys) != section:
                if r.phase not in SECTIONS or ((r.group or lsys) and r.phase != "production"):
                    raise ValueError(f"a rule of phase {r.phase!r} in group {r.group}")
                if r.group and lsys:
                    raise ValueError(f"a rule of group {r.group} in sub-L-system {lsys}")
                section = (r.phase, r.group, lsys)
                lines.append(f"group {int(r.group)}:" if r.group else
                             f"lsystem {int(lsys)}:" if lsys else f"{r.phase}:")  # fmt: skip
            lines.append(format_rule(r))
    return "\n".join(lines) + "\n"
