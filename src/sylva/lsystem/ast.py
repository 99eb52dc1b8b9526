"""The common program of every dialect: frozen dataclasses.

A dialect parses text into a :class:`Program`; the engine derives words from it; the turtle
reads its :attr:`Program.settings`.  Nothing here knows about any text syntax.

Examples
--------
>>> from sylva.lsystem.ast import Module, Num, Pattern, Program, Rule
>>> p = Program(axiom=(Module("a"),), rules=(Rule(Pattern("a"), (Module("b"),)),))
>>> p.rules[0].predecessor.symbol
'a'
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from types import MappingProxyType

__all__ = [
    "MAX_STEPS",
    "Binary",
    "Call",
    "Expr",
    "Module",
    "Num",
    "Pattern",
    "Program",
    "Rule",
    "Span",
    "Unary",
    "Var",
]

BRACKETS = frozenset("[]")

#: The most derivation steps sylva derives in one request.  Real systems ask for tens of
#: steps; a file (``steps``, ``iteration``, ``derivation length``) or ``-n`` asking for more
#: is refused up front, so that ``steps = 1e23`` is an error and not a run without end.
MAX_STEPS = 100_000


@dataclass(frozen=True, slots=True)
class Span:
    """Where something was written: 1-based line and column in ``filename``."""

    line: int
    column: int
    filename: str | None = None


# --------------------------------------------------------------------------- expressions
@dataclass(frozen=True, slots=True)
class Num:
    """A numeric literal (``True`` is 1.0, ``False`` is 0.0)."""

    value: float


@dataclass(frozen=True, slots=True)
class Var:
    """A variable: a bound parameter or a global constant."""

    name: str
    span: Span | None = field(default=None, compare=False)


@dataclass(frozen=True, slots=True)
class Unary:
    """``-x`` or ``!x``."""

    op: str
    operand: Expr


@dataclass(frozen=True, slots=True)
class Binary:
    """``l op r`` for the operators of seed 001 §3.4."""

    op: str
    left: Expr
    right: Expr


@dataclass(frozen=True, slots=True)
class Call:
    """A call of one of the built-in functions (``sin``, ``sqrt``, ``sum`` …)."""

    func: str
    args: tuple[Expr, ...]
    span: Span | None = field(default=None, compare=False)


Expr = Num | Var | Unary | Binary | Call


# --------------------------------------------------------------------------- modules
@dataclass(frozen=True, slots=True)
class Module:
    """A module with formal parameters, as in a successor or the axiom: ``F(l*2)``."""

    symbol: str
    args: tuple[Expr, ...] = ()


@dataclass(frozen=True, slots=True)
class Pattern:
    """A module with binding names, as in a predecessor or context: ``A(x, y)``.

    In a right context ``Pattern("[")`` and ``Pattern("]")`` delimit lateral subtrees.
    """

    symbol: str
    params: tuple[str, ...] = ()


@dataclass(frozen=True, slots=True)
class Rule:
    """One production ``left < predecessor > right : condition ->(weight) successor``.

    ``render`` marks a render rule (``->>``), applied once to make the word the turtle
    draws.  ``weight`` is an expression (usually a constant) evaluated per application.
    ``phase`` says when the rule applies: ``"production"`` (a derivation step),
    ``"decomposition"`` (after every step, again and again until no rule applies, at most
    :attr:`Program.decomposition_depth` times) or ``"interpretation"`` (so to the word the
    turtle draws, at most :attr:`Program.interpretation_depth` times); cpfg's and L-Py's
    sections of those names.  ``group`` is the table (ABOP §1.4 table L-systems, L-Py's
    ``group``) of a production: 0, the default, is used in every step, another group only
    in the steps :attr:`Program.group` chooses it.  ``lsystem`` is the sub-L-system
    (cpfg's sub-L-systems, ABOP §… compound plants) whose modules a production rewrites: 0
    the main one, ``n`` the modules between a call ``?(n)`` and its ``$``
    (:mod:`sylva.lsystem._sublsystems`).
    """

    predecessor: Pattern
    successor: tuple[Module, ...] = ()
    left: tuple[Pattern, ...] = ()
    right: tuple[Pattern, ...] = ()
    condition: Expr | None = None
    weight: Expr = Num(1.0)
    render: bool = False
    span: Span | None = field(default=None, compare=False)
    phase: str = "production"
    group: int = 0
    lsystem: int = 0
    #: cpfg's statement blocks of the production (:class:`~.dialects._cpfg_blocks.Block`):
    #: run by the engine around the condition; ``None`` for every other rule.
    block: object | None = None

    @property
    def has_context(self) -> bool:
        return bool(self.left or self.right)

    @property
    def tier(self) -> int:
        """Priority tier of seed 001: 0 conditional, 1 context, 2 context-free."""
        if self.condition is not None:
            return 0
        return 1 if self.has_context else 2


def _freeze(mapping: Mapping | None) -> Mapping:
    return MappingProxyType(dict(mapping or {}))


@dataclass(frozen=True)
class Program:
    """An L-system in any dialect.

    Attributes
    ----------
    axiom : tuple of Module
        The initial word; its parameters are expressions over :attr:`constants`.
    rules : tuple of Rule
        Productions and render rules, in the order written.
    constants : Mapping[str, float]
        Global numeric constants (user variables), in the order assigned.
    ignore : frozenset of str
        Symbols skipped when contexts are matched.
    consider : frozenset of str or None
        When set, only these symbols (and brackets) are seen by context matching.
    settings : Mapping[str, object]
        Special variables for the turtle and renderer (``rot``, ``len``, ``thick``,
        ``color``, ``bg``, ``detail``, the ``*_delta`` increments, ``reduction``, ``yaw`` …)
        and ``turtle``, the name of the command table (``"lsys"``, ``"abop"``,
        ``"classic"``, ``"engine"``).  Only what the source set is present; the turtle
        supplies the defaults of its dialect.
    steps : int or None
        The number of derivation steps the source asks for (``iteration`` of seed 000,
        ``steps`` in ``.lsys``), if any.
    seed : int or None
        The random seed the source asks for, if any.
    dialect : str
        The language the program was read from.
    name : str or None
        A name (file stem, or the engine format's index).
    filename : str or None
        Where the program was read from.
    decomposition_depth, interpretation_depth : int
        The most passes of decomposition (after each step) and interpretation rules (cpfg's
        ``maximum depth:``, default 1); rules that still apply after them are an error.
    group : Expr or None
        Which group of productions (tables, ABOP §1.4) each step uses: an expression over
        ``step`` (the number of steps done before it, from 0) and the global constants.
        ``None`` uses group 0 only.
    steps_at : Span or None
        Where the source set :attr:`steps` (the start of its value), for errors about it.
    statements : object or None
        Statements that run between derivation steps and change the global constants
        (cpfg's ``StartEach:`` / ``EndEach:`` blocks): an object with ``fresh()`` (the
        globals at the start, with ``numbers()``), ``before(globals, step)`` and
        ``after(globals, step)``.  Programs with them take the engine's general road.
    ring : bool
        cpfg's ``ring lsystem``: the word is a ring, its last module followed by its first,
        for the contexts of every rule (the engine's general road).
    """

    axiom: tuple[Module, ...]
    rules: tuple[Rule, ...] = ()
    constants: Mapping[str, float] = field(default_factory=dict)
    ignore: frozenset[str] = frozenset()
    consider: frozenset[str] | None = None
    settings: Mapping[str, object] = field(default_factory=dict)
    steps: int | None = None
    seed: int | None = None
    dialect: str = "lsys"
    name: str | None = None
    filename: str | None = field(default=None, compare=False)
    decomposition_depth: int = 1
    interpretation_depth: int = 1
    group: Expr | None = None
    steps_at: Span | None = field(default=None, compare=False)
    statements: object | None = None
    ring: bool = False

    def __post_init__(self) -> None:
        object.__setattr__(self, "axiom", tuple(self.axiom))
        object.__setattr__(self, "rules", tuple(self.rules))
        object.__setattr__(self, "constants", _freeze(self.constants))
        object.__setattr__(self, "settings", _freeze(self.settings))
        object.__setattr__(self, "ignore", frozenset(self.ignore))
        if self.consider is not None:
            object.__setattr__(self, "consider", frozenset(self.consider))

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Program):
            return NotImplemented
        return (
            self.axiom == other.axiom
            and self.rules == other.rules
            and dict(self.constants) == dict(other.constants)
            and self.ignore == other.ignore
            and self.consider == other.consider
            and dict(self.settings) == dict(other.settings)
            and self.steps == other.steps
            and self.seed == other.seed
            and self.decomposition_depth == other.decomposition_depth
            and self.interpretation_depth == other.interpretation_depth
            and self.group == other.group
            and self.statements == other.statements
            and self.ring == other.ring
        )

    __hash__ = None  # type: ignore[assignment]

    @property
    def productions(self) -> tuple[Rule, ...]:
        """The rules used for derivation (of every group; not render rules)."""
        return tuple(r for r in self.rules if not r.render and r.phase == "production")

    @property
    def decompositions(self) -> tuple[Rule, ...]:
        """The decomposition rules."""
        return tuple(r for r in self.rules if not r.render and r.phase == "decomposition")

    @property
    def interpretations(self) -> tuple[Rule, ...]:
        """The interpretation rules (cpfg's recursive homomorphism)."""
        return tuple(r for r in self.rules if not r.render and r.phase == "interpretation")

    @property
    def groups(self) -> tuple[int, ...]:
        """The groups the productions use, sorted (``(0,)`` without tables)."""
        return tuple(sorted({0, *(r.group for r in self.productions)}))

    @property
    def render_rules(self) -> tuple[Rule, ...]:
        """The render rules (``->>``)."""
        return tuple(r for r in self.rules if r.render)

    @property
    def turtle(self) -> str:
        """The name of the turtle command table this program is written for."""
        return str(self.settings.get("turtle", "lsys"))

    def replace(self, **changes) -> Program:
        """A copy with some fields changed."""
        from dataclasses import replace

        if "steps" in changes and "steps_at" not in changes:
            changes["steps_at"] = None  # the new count was not written there
        return replace(self, **changes)
