"""Build L-systems in Python code instead of text files.

:func:`define` takes the axiom and the rules as the ``.lsys`` language writes them (each
string parsed by our own parser, never evaluated), or as :class:`~sylva.lsystem.ast.Rule`
objects, or as a ``{predecessor: successor}`` mapping for context-free systems, and the
settings as keyword arguments.  The result is an ordinary :class:`Program`: derive it,
draw it, or write it out with :func:`~sylva.lsystem.dumps`.

Examples
--------
>>> from sylva.lsystem import derive, dumps
>>> koch = define("F++F++F", "F -> F-F++F-F", rot=60, steps=2)
>>> len(derive(koch))
112
>>> tree = define("A(1)", "A(s) : s < 3 -> F(s)[+A(s*R)][-A(s*R)]", constants={"R": 2})
>>> str(derive(tree, 2))
'F(1)[+F(2)[+A(4)][-A(4)]][-F(2)[+A(4)][-A(4)]]'
>>> algae = define("a", {"a": "ab", "b": "a"})
>>> str(derive(algae, 5))
'abaababaabaab'
>>> print(dumps(define("F", "F -> F[+F]F", rot=25.7)), end="")
rot = 25.7
axiom = F
<BLANKLINE>
F -> F[+F]F
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping

from ..errors import LSystemSemanticError
from .ast import Module, Program, Rule
from .dialects import parse_rule, parse_word
from .expr import evaluate_constant

__all__ = ["define"]

_SETTING_KINDS = {
    "turtle": str,
}


def define(
    axiom: str | Iterable[Module],
    *rules: str | Rule | Mapping[str, str] | Iterable[str | Rule],
    constants: Mapping[str, float] | None = None,
    ignore: str | Iterable[str] = (),
    consider: str | Iterable[str] | None = None,
    steps: int | None = None,
    seed: int | None = None,
    name: str | None = None,
    **settings,
) -> Program:
    """Make a :class:`Program` from Python values.

    Parameters
    ----------
    axiom : str or iterable of Module
        The initial word, e.g. ``"F(1)[+A]"``; parameters may use ``constants``.
    *rules : str, Rule, mapping or iterable of those
        Rules in ``.lsys`` syntax (``"b < a -> ab"``, ``"A(x) : x > 1 -> B(x/2)"``,
        ``"X ->> F"`` for a render rule), :class:`Rule` objects, or a mapping
        ``{"F": "FF"}`` of context-free rules.
    constants : mapping of str to float, optional
        Global constants the expressions may use.
    ignore, consider : str or iterable of str
        Symbols skipped (or, for ``consider``, the only symbols seen) by context matching.
        A string is split into one-character symbols.
    steps, seed : int, optional
        The default number of steps and the seed.
    name : str, optional
    **settings
        Special variables for the turtle: ``rot``, ``len``, ``thick``, ``color``, ``bg``,
        ``detail``, the ``*_delta`` increments, ``turtle`` (command table) …

    Raises
    ------
    LSystemSyntaxError
        When a rule or the axiom does not parse (the message points at the column).
    """
    consts = {k: float(v) for k, v in (constants or {}).items()}
    if isinstance(axiom, str):
        ax = parse_word(axiom, constants=consts, evaluate=True, filename="<axiom>")
    else:
        ax = tuple(axiom)
    out: list[Rule] = []

    def add(item) -> None:
        if isinstance(item, Rule):
            out.append(item)
        elif isinstance(item, str):
            out.append(parse_rule(item, constants=consts, filename="<rule>"))
        elif isinstance(item, Mapping):
            for pred, succ in item.items():
                out.append(parse_rule(f"{pred} -> {succ}", constants=consts,
                                      filename="<rule>"))
        elif isinstance(item, Iterable):
            for x in item:
                add(x)
        else:
            raise LSystemSemanticError(
                f"a rule must be a string, a Rule or a mapping, not {type(item).__name__}"
            )

    for r in rules:
        add(r)

    def symbols(x) -> frozenset[str]:
        if isinstance(x, str):
            return frozenset(c for c in x if not c.isspace())
        return frozenset(x)

    clean: dict[str, object] = {}
    for key, value in settings.items():
        if key in _SETTING_KINDS or isinstance(value, str):
            clean[key] = str(value)
        elif isinstance(value, (tuple, list)):
            clean[key] = tuple(float(v) for v in value)
        else:
            clean[key] = float(evaluate_constant_value(value))
    return Program(
        axiom=ax,
        rules=tuple(out),
        constants=consts,
        ignore=symbols(ignore),
        consider=None if consider is None else symbols(consider),
        settings=clean,
        steps=steps,
        seed=seed,
        name=name,
    )


def evaluate_constant_value(value) -> float:
    """A number given as a Python number or an expression object."""
    if isinstance(value, (int, float)):
        return float(value)
    return evaluate_constant(value)
