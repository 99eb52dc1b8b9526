"""cpfg's generalised cylinders drawn along their path: ``@Gs … @Gc … @Ge``.

cpfg (``blackbox.c``, ``interpret.c``) starts a generalised cylinder at ``@Gs``, adds a
control point at each ``@Gc`` and ends it at ``@Ge``; the surface sweeps the turtle's
width along the path through those points.  Models that draw with it move the turtle with
``f`` between the points (vlab's GeneralizedCylinder, LilyLeaf, Horneophyton), so without
the cylinder they draw nothing.  sylva draws the path as its tubes: every ``f`` taken while
a cylinder is open (in the branch that opened it and the branches that grow from it, as
cpfg's turtle state carries the flag through ``[`` and ``]``) becomes an ``F`` of the same
length, so the tube follows the same points with the same widths (a polyline through the
moves, not cpfg's spline through the control points).
"""

from __future__ import annotations

import numpy as np

from ..lsystem.lstring import ModuleString


def cylinder_word(word: ModuleString) -> ModuleString:
    """``word`` with each ``f`` inside an open ``@Gs … @Ge`` cylinder made an ``F``
    (``word`` itself when it opens none)."""
    alpha = word.alphabet
    at, g, f = alpha.get("@"), alpha.get("G"), alpha.get("f")
    s, e = alpha.get("s"), alpha.get("e")
    if min(at, g, f, s) < 0:
        return word
    ids = word.ids
    n = ids.shape[0]
    marks = np.flatnonzero((ids[: max(n - 2, 0)] == at) & (ids[1 : max(n - 1, 1)] == g))
    if marks.size == 0 or not np.any(ids[marks + 2] == s):
        return word
    interesting = np.flatnonzero((ids == 0) | (ids == 1) | (ids == f))
    events = np.union1d(interesting, marks)
    starts = set((marks[ids[marks + 2] == s]).tolist())
    ends = set((marks[ids[marks + 2] == e]).tolist()) if e >= 0 else set()
    new = ids.copy()
    big_f = alpha.id("F")
    open_ = False
    stack: list[bool] = []
    for p in events.tolist():
        c = ids[p]
        if p in starts:
            open_ = True
        elif p in ends:
            open_ = False
        elif c == 0:  # [
            stack.append(open_)
        elif c == 1:  # ]
            if stack:
                open_ = stack.pop()
        elif c == f and open_:
            new[p] = big_f
    if np.array_equal(new, ids):
        return word
    return ModuleString(alpha, new, word.offsets, word.values)
