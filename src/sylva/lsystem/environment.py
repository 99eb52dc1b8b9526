"""The query protocol: modules whose parameters the turtle fills between steps.

cpfg's query modules (Prusinkiewicz, James & Měch 1994, "Synthetic topiary") ``?P(x,y,z)``,
``?H(x,y,z)``, ``?U(x,y,z)`` and ``?L(x,y,z)`` are set, after every derivation step and on
the axiom before the first, to the turtle's position, heading, up or left vector at the
module, so that the next step's productions can test them (``?P(x,y,z) < A : y > 5 -> …``
prunes against a shape).  The turtle draws nothing for them.

:mod:`sylva.lsystem` does not import the turtle: a :class:`~sylva.lsystem.Derivation` takes
a *query* callback, ``query(word, index) -> values``, that receives the word and the indices
of its query modules (``int64[m]``, in word order) and returns their new values as a
``float64[m, 3]`` array, all at once.  :func:`sylva.plant.turtle_query` is the callback that
interprets the word with the program's turtle; :func:`sylva.grow` and :func:`sylva.derive`
wire it in.

Examples
--------
>>> from sylva.lsystem import Derivation, loads
>>> p = loads("axiom = ?P(0,0,0)\\n?P(x,y,z) : x < 2 -> ?P(x,y,z)A")
>>> d = Derivation(p, query=lambda word, index: [[len(word), 0, 0]] * len(index))
>>> str(d.advance(2))
'"?P"(2,0,0)A'
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from ..errors import SylvaError
from .ast import Program
from .lstring import ModuleString

__all__ = ["QUERY_MODULES", "Query", "apply_query", "has_queries", "query_index"]

#: The query modules and what the turtle puts in them.
QUERY_MODULES = {"?P": "position", "?H": "heading", "?U": "up", "?L": "left"}

#: ``query(word, index) -> float64[len(index), 3]``
Query = Callable[[ModuleString, np.ndarray], np.ndarray]


def has_queries(program: Program) -> bool:
    """True when a query module appears in the axiom or in a successor of ``program``."""
    mods = list(program.axiom)
    for rule in program.rules:
        mods.extend(rule.successor)
    return any(m.symbol in QUERY_MODULES for m in mods)


def query_index(word: ModuleString) -> np.ndarray:
    """``int64[m]``: the positions of the query modules in ``word``."""
    ids = [word.alphabet.get(name) for name in QUERY_MODULES]
    ids = [i for i in ids if i >= 0]
    if not ids:
        return np.zeros(0, np.int64)
    return np.flatnonzero(np.isin(word.ids, ids)).astype(np.int64)


def apply_query(word: ModuleString, query: Query, step: int) -> ModuleString:
    """``word`` with the parameters of its query modules set by ``query``.

    A query module keeps as many parameters as it has (at most 3 are set).  A callback
    that raises, or returns the wrong shape or a value that is not finite, is a
    :class:`~sylva.errors.SylvaError` naming the step.
    """
    index = query_index(word)
    if index.size == 0:
        return word
    try:
        out = query(word, index)
    except SylvaError:
        raise
    except Exception as exc:  # the user's environment: say where it failed
        raise SylvaError(
            f"step {step}: the query callback raised {type(exc).__name__}: {exc}"
        ) from exc
    try:
        values = np.asarray(out, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise SylvaError(
            f"step {step}: the query callback returned {type(out).__name__}; expected "
            f"float values of shape ({index.size}, 3)"
        ) from exc
    if values.shape != (index.size, 3):
        raise SylvaError(
            f"step {step}: the query callback returned shape {values.shape}; expected "
            f"({index.size}, 3), one (x, y, z) per query module"
        )
    if not np.isfinite(values).all():
        raise SylvaError(f"step {step}: the query callback returned a value that is not finite")
    offsets = word.offsets
    start = offsets[index]
    count = np.minimum(offsets[index + 1] - start, 3)
    new = word.values.copy()
    for k in range(3):
        has = count > k
        new[start[has] + k] = values[has, k]
    return ModuleString(word.alphabet, word.ids, offsets, new)


def missing_query(program: Program) -> SylvaError:
    """The error for a program with query modules derived without a query callback."""
    where = ""
    span = None
    for rule in program.rules:
        if any(m.symbol in QUERY_MODULES for m in rule.successor):
            span = rule.span
            break
    if span is not None:
        name = span.filename or "<string>"
        where = f"{name}:{span.line}:{span.column}: "
    return SylvaError(
        f"{where}the program has query modules (?P ?H ?U ?L), whose values the turtle sets "
        "between steps; expected a query callback: derive it with sylva.derive or "
        "sylva.grow, or pass query=sylva.plant.turtle_query(program)"
    )
