"""How many parameters a module needs to match a pattern: at least as many, or exactly.

sylva's engine lets a module match a predecessor or context module of its letter when it
has *at least* the parameters the pattern names (a pattern without parameters matches
every module of its letter).  ABOP (p. 41) and cpfg (``generate.c``'s ``PredDiff``, for the
strict predecessor and each context module) want *the same number*: ``A --> B`` does not
rewrite ``A(1)``.  The cpfg reader asks for that by the program setting ``exact_arity``
(:func:`differs` says where it changes anything).

The context kernels take a pattern's arity encoded (:func:`need`): ``a >= 0`` is "at least
``a``", ``-(a + 1)`` is "exactly ``a``".

Examples
--------
>>> need(np.array([0, 2]), True).tolist(), need(np.array([0, 2]), False).tolist()
([-1, -3], [0, 2])
>>> pred_ok(np.array([0, 1, 2]), np.array([0, 1, 2]), 1, True).tolist()
[False, True, False]
"""

from __future__ import annotations

from collections.abc import Iterable

import numpy as np

__all__ = ["arity_ok", "differs", "need", "pred_ok"]


def need(arity: np.ndarray, exact: bool) -> np.ndarray:
    """The arities of a context pattern as the kernels read them (``-(a + 1)``: exactly)."""
    return -arity - 1 if exact else arity


def arity_ok(have: int, want: int) -> bool:
    """Whether a module with ``have`` parameters meets an encoded arity ``want``."""
    return have >= want if want >= 0 else have == -want - 1


def pred_ok(nparams: np.ndarray | None, undecided: np.ndarray, arity: int,
            exact: bool) -> np.ndarray:  # fmt: skip
    """``bool[k]``: which modules at ``undecided`` a predecessor of ``arity`` parameters
    can rewrite (``nparams`` is None when the word has no parameters)."""
    k = undecided.size
    if nparams is None:
        return np.full(k, arity == 0, np.bool_)
    if exact:
        return nparams[undecided] == arity
    return nparams[undecided] >= arity if arity else np.ones(k, np.bool_)


def differs(axiom: Iterable, rules: Iterable) -> bool:
    """Whether exact matching can change a derivation of ``axiom`` under ``rules``: some
    pattern module (predecessor or context) of ``k`` parameters meets a module of its
    letter with more (every module of every word is the axiom's or a successor's)."""
    rules = tuple(rules)
    most: dict[str, int] = {}
    for m in (*axiom, *(m for r in rules for m in r.successor)):
        most[m.symbol] = max(most.get(m.symbol, 0), len(m.args))
    return any(len(p.params) < most.get(p.symbol, 0)
               for r in rules for p in (*r.left, r.predecessor, *r.right))  # fmt: skip
