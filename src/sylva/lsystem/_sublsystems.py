"""Sub-L-systems (cpfg): which L-system's productions rewrite each module of a word.

A call ``?(n[, s])`` starts sub-L-system ``n`` and ``$`` ends the innermost call, as cpfg
reads them (``generate.c``: the ``?`` module pushes the L-system named by its first
parameter, ``$`` pops it).  The call module belongs to the caller, ``$`` to the callee, and
the modules between to ``n``; calls nest, and a ``$`` without a call is a plain module of
the main L-system (0).  ``?`` without parameters is no call.  The engine then lets a
production of sub-L-system ``k`` (:attr:`Rule.lsystem`) rewrite only the modules of
``k``; neither module draws anything (:func:`silence`).

Examples
--------
>>> from sylva.lsystem.lstring import ModuleString
>>> scope(ModuleString.from_text('A"?"(2)B"?"(3)C$D$E')).tolist()
[0, 0, 2, 2, 3, 3, 2, 2, 0]
"""

from __future__ import annotations

import numpy as np

from .lstring import ModuleString
from .matching import ignored_table

__all__ = ["CALL", "END", "ContextTables", "scope", "scope_if", "silence"]

#: The call and end modules.
CALL, END = "?", "$"


def scope(word: ModuleString) -> np.ndarray:
    """``int64[n]``: the sub-L-system of every module of ``word`` (0: the main one)."""
    out = np.zeros(len(word), np.int64)
    call, end = word.alphabet.get(CALL), word.alphabet.get(END)
    if call < 0:
        return out
    ids = word.ids
    is_call = ids == call
    if word.has_params:
        is_call &= word.nparams > 0
    else:
        is_call[:] = False
    marks = np.flatnonzero(is_call | (ids == end) if end >= 0 else is_call)
    if marks.size == 0:
        return out
    stack = [0]
    last = 0
    values, offsets = word.values, word.offsets
    for pos in marks.tolist():
        if is_call[pos]:
            out[last : pos + 1] = stack[-1]
            stack.append(int(values[offsets[pos]]))
            last = pos + 1
        elif len(stack) > 1:
            out[last : pos + 1] = stack[-1]
            stack.pop()
            last = pos + 1
    out[last:] = stack[-1]
    return out


def scope_if(word: ModuleString, on: bool) -> np.ndarray | None:
    """:func:`scope` of ``word`` where the program has sub-L-systems (``on``), else None."""
    return scope(word) if on else None


class ContextTables:
    """cpfg's sub-L-systems with their own ``ignore:`` / ``consider:`` (the program's
    setting ``sublsystem_context``, ``{n: (ignored, considered or None)}``, which the cpfg
    reader sets only where they differ): the table a rule of each matches contexts with."""

    def __init__(self, sets: dict, alphabet) -> None:
        self.ids = {int(k): ([alphabet.id(x) for x in ig],
                             None if co is None else [alphabet.id(x) for x in co])
                    for k, (ig, co) in sets.items()}  # fmt: skip
        self.tables: dict[int, np.ndarray] = {}

    @classmethod
    def of(cls, program, alphabet) -> ContextTables | None:
        sets = program.settings.get("sublsystem_context")
        return cls(sets, alphabet) if sets else None

    def get(self, word: ModuleString, rule, default: np.ndarray | None) -> np.ndarray | None:
        """The table of ``rule``'s (compiled) sub-L-system, or ``default`` (the program's)."""
        k = rule.rule.lsystem
        if default is None or k not in self.ids:
            return default
        t = self.tables.get(k)
        if t is None or t.shape[0] < len(word.alphabet):
            t = self.tables[k] = ignored_table(len(word.alphabet), *self.ids[k])
        return t


def silence(word: ModuleString) -> ModuleString:
    """``word`` with every end ``$`` made a ``?`` without parameters, which the turtle
    ignores (so ``$`` is not ABOP's roll to vertical); the same length, so indices hold."""
    end, call = word.alphabet.get(END), word.alphabet.get(CALL)
    if end < 0 or call < 0 or not (word.ids == end).any():
        return word
    ids = np.where(word.ids == end, word.ids.dtype.type(call), word.ids)
    if not word.has_params:
        return ModuleString(word.alphabet, ids)
    return ModuleString(word.alphabet, ids, word.offsets, word.values)
