"""cpfg's sub-L-systems: several ``Lsystem: N … endlsystem`` blocks in one file.

As cpfg reads them (its manual §7.2, and ``lsys_input.y`` / ``generate.c`` /
``interpret.c``): the first L-system of the file is the main one; its axiom, its
``derivation length:`` and its ``seed:`` are the model's (those of the others are read
but ignored: a sub-L-system's axiom serves only when its file is run alone).  Every
L-system is numbered by its label (``Lsystem: 2``; cpfg takes the label's leading
number, so a label that is not a number is 0).  A call ``?(N, s) … $`` in a successor
starts sub-L-system ``N``: the modules between the call and its ``$`` are rewritten by
``N``'s productions only, decomposed by its decomposition and drawn through its
homomorphism (the call module belongs to the caller, ``$`` to the callee); the turtle
draws them ``s`` times as large (:mod:`sylva.lsystem._sublsystems`, the turtle's
SUBCALL).  In sylva each production carries the number of its L-system
(:attr:`~sylva.lsystem.ast.Rule.lsystem`, 0 for the main one).

This module holds the reader's bookkeeping: the calls found in successors, the labels,
and the checks made once the whole file is read.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field, replace

from ...errors import LSystemSyntaxError, SylvaError
from ..expr import evaluate_constant

__all__ = ["Books", "calls_in", "label_number"]

_LEADING_NUMBER = re.compile(r"\s*[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?")


def label_number(label: str) -> int:
    """The number cpfg gives an L-system's label: ``(int) atof(label)``.

    >>> label_number("2"), label_number(" 3.7 tree"), label_number("tree")
    (2, 3, 0)
    """
    m = _LEADING_NUMBER.match(label)
    return int(float(m.group(0))) if m else 0


def calls_in(word: str, start: int = 0) -> list[tuple[str, int]]:
    """The sub-L-system calls ``?(N, …)`` of a successor or axiom ``word``: per call, the
    text of ``N`` and its 0-based column (``start`` plus its index in ``word``).  Only
    ``?(`` outside parentheses counts: inside them ``?`` is C's conditional operator
    (``#define MAX(a,b) ((a)>(b)?(a):(b))``).

    >>> calls_in("F?(2,1.25)A$[?( 3 )B$] G(x>0?(1):(2))")
    [('2', 3), ('3', 16)]
    """
    out, depth, k, n = [], 0, 0, len(word)
    while k < n:
        ch = word[k]
        if ch == "(":
            depth += 1
        elif ch == ")":
            depth = max(0, depth - 1)
        elif ch == "?" and depth == 0 and k + 1 < n and word[k + 1] == "(":
            j, d = k + 2, 0
            while j < n and not (d == 0 and word[j] in ",)"):
                d += (word[j] == "(") - (word[j] == ")")
                j += 1
            arg = word[k + 2 : j]
            lead = len(arg) - len(arg.lstrip())
            out.append((arg.strip(), start + k + 2 + lead))
        k += 1
    return out


@dataclass
class Books:
    """What the reader notes about the L-systems of one file as it goes."""

    #: the number of the L-system being read; 0 for the main one (the file's first)
    current: int = 0
    #: the main L-system's own label number (cpfg's id; a call to it reaches it too)
    main_id: int = 0
    #: sylva number -> the error to raise at its ``Lsystem:`` line (for messages)
    labels: dict[int, LSystemSyntaxError] = field(default_factory=dict)
    #: line of the translation (1-based) -> the L-system of the rule written there
    rule_lsystem: dict[int, int] = field(default_factory=dict)
    #: (the callee's text, a function making the error at it) per call
    calls: list = field(default_factory=list)
    #: L-system -> its ignore/consider line: (key, symbols, error at the line)
    context: dict[int, tuple[str, frozenset, LSystemSyntaxError]] = field(default_factory=dict)

    def start(self, label: str, where) -> None:
        """A later ``Lsystem:`` line: the L-system that its productions belong to."""
        number = label_number(label)
        at = where("", 1)
        if number < 1:
            raise where(f"a sub-L-system's label is its number, which ?({label or 'N'}, s) "
                        f"calls; got {label!r}, expected a whole number >= 1 such as "
                        "'Lsystem: 2'", 1)  # fmt: skip
        if number == self.main_id or number in self.labels:
            first = "the main L-system's" if number == self.main_id else "an earlier"
            raise where(f"L-system {number} is already defined ({first} label); expected "
                        "each L-system of the file to have its own number", 1)  # fmt: skip
        self.labels[number] = at
        self.current = number

    def check(self, rules: tuple, constants: dict, shift: int) -> tuple:
        """``rules`` (of the translation, in order) each marked with its L-system, with
        the main L-system's productions repeated as its own number's when a call names it;
        raises the error of a call to an L-system the file lacks."""
        known = {0, self.main_id, *self.labels}
        called: set[int] = set()
        for text, make in self.calls:
            try:
                v = float(text)
            except ValueError:
                from .lsysvis import parse_expr

                try:
                    v = evaluate_constant(parse_expr(text.replace("^", "**")), constants)
                except (SylvaError, ArithmeticError, ValueError, TypeError):
                    continue  # computed from the module's parameters: cpfg finds it then
            if not (v == v and abs(v) < 2**31):  # noqa: PLR0124 - NaN
                continue
            n = int(v)  # cpfg: (int) of the first parameter
            if n not in known:
                have = ", ".join(str(k) for k in sorted(known - {0} or {self.main_id}))
                raise make(f"?({text}, s) calls L-system {n}, which this file does not "
                           f"define; expected one of its L-systems' numbers ({have})")
            called.add(n)
        out = []
        for r in rules:
            k = self.rule_lsystem.get(r.span.line - shift, 0) if r.span is not None else 0
            out.append(replace(r, lsystem=k) if k else r)
        if self.main_id >= 1 and self.main_id in called and self.labels:
            out += [replace(r, lsystem=self.main_id) for r in out if r.lsystem == 0]
        return tuple(out)

    def context_sets(self, rules) -> dict | None:
        """cpfg's context tables per L-system (``lsys_input.y``: each L-system has its own
        ``ignore:`` / ``consider:``, and one without either considers every module), for
        the engine's setting ``sublsystem_context``: ``{number: (ignored, considered or
        None)}`` for the L-systems with context productions, or None where they all have
        the main L-system's (then ``Program.ignore`` / ``consider`` serve all)."""
        with_context = {r.lsystem for r in rules if r.has_context}
        if not self.labels or not with_context:
            return None

        def spec(k: int) -> tuple:
            key, symbols = self.context.get(0 if k == self.main_id else k,
                                            ("ignore", frozenset(), None))[:2]
            symbols = tuple(sorted(symbols - {'"'}))  # '"#"' is the module #
            return (symbols, None) if key == "ignore" else ((), symbols)

        main = spec(0)
        if all(spec(k) == main for k in with_context):
            return None
        return {k: spec(k) for k in sorted(with_context)}
