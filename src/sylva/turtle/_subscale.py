"""The scale of cpfg's sub-L-system calls ``?(n, s)``: what the sub-L-system draws is ``s``
times as large.

cpfg (its manual §6 and ``interpret.c``) keeps a scale factor per call: ``?(n, s)``
multiplies the one in effect by ``s`` (``?(n)``: by 1) until the matching ``$``, and the
factor multiplies every length (``F f G g`` with or without a parameter), every width set by
a parameter (``!(w)``), the size of a surface (``~X(k)``, ``~X``) and of a sphere or circle
(``@O(d)``, ``@o(d)``, ``@c(r)``); the width at the call is multiplied by ``s`` and divided
back at the end.  The turtle reads the word after :func:`sylva.lsystem._sublsystems.silence`,
where each end ``$`` is a ``?`` without parameters: :func:`scale_word` gives each module the
parameters it draws with under its factor (a length where it had none, ``F`` → ``F(l·k)``),
and each end the parameters ``(0, 1/s)`` that the turtle's ``?`` (``SUBCALL``) applies to the
width, so the word keeps its length and module indices.
"""

from __future__ import annotations

import numpy as np

from ..lsystem.lstring import ModuleString
from . import tables as T

__all__ = ["scale_word"]

_LENGTH = (T.DRAW, T.MOVE, T.DRAW_NOREC, T.MOVE_NOREC)


def scale_word(word: ModuleString, ops: np.ndarray, arg: np.ndarray, length: float,
               leaf: float) -> ModuleString:  # fmt: skip
    """``word`` with the scale of its sub-L-system calls applied (see the module docstring);
    ``word`` itself when no call scales (``length``, ``leaf``: the defaults of ``F`` and
    ``~``)."""
    sub = np.flatnonzero(ops == T.SUBCALL)
    if sub.size == 0 or not word.has_params:
        return word
    ids, offsets, values = word.ids, word.offsets, word.values
    marks = np.flatnonzero(ids == sub[0])
    if marks.size == 0:
        return word
    cnt = np.diff(offsets)
    mcnt = cnt[marks]
    calls = marks[mcnt >= 2]
    if calls.size == 0 or np.all(values[offsets[calls] + 1] == 1.0):
        return word
    n = ids.shape[0]
    k = np.ones(n)
    stack = [1.0]
    last = 0
    ends: list[int] = []
    factors: list[float] = []
    for p, c in zip(marks.tolist(), mcnt.tolist()):
        if c >= 1:  # a call: it belongs to the caller
            k[last : p + 1] = stack[-1]
            stack.append(stack[-1] * (float(values[offsets[p] + 1]) if c >= 2 else 1.0))
            last = p + 1
        elif len(stack) > 1:  # an end: it belongs to the callee
            k[last : p + 1] = stack[-1]
            inner = stack.pop()
            ends.append(p)
            factors.append(stack[-1] / inner if inner != 0.0 else 1.0)
            last = p + 1
    k[last:] = stack[-1]
    op = ops[ids]
    scaled = k != 1.0
    new_cnt = cnt.copy()
    first: list[np.ndarray] = []  # modules whose first parameter is multiplied by k
    second: list[np.ndarray] = []  # modules whose 2nd, then 3rd parameter is too
    added: list[tuple[np.ndarray, np.ndarray]] = []  # (modules, their one new parameter)
    lengths = scaled & np.isin(op, _LENGTH)
    first.append(np.flatnonzero(lengths & (cnt > 0)))
    bare = np.flatnonzero(lengths & (cnt == 0))
    added.append((bare, length * k[bare]))
    first.append(np.flatnonzero(scaled & (op == T.WIDTH_MUL) & (cnt > 0)))
    surf = np.flatnonzero(scaled & (op == T.SURFACE))
    if surf.size:
        nxt = np.minimum(surf + 1, n - 1)
        named = (surf + 1 < n) & (op[nxt] == T.NOP) & (cnt[surf] == 0)
        target = np.where(named, nxt, surf)  # ~X(k): the name's parameter scales
        first.append(target[cnt[target] > 0])
        three = target[cnt[target] >= 3]  # ~X(sx, sy, sz): all three
        second.extend([three, three])
        bare = target[cnt[target] == 0]
        added.append((bare, leaf * k[bare]))
    at = np.flatnonzero(scaled & (op == T.AT) & (np.arange(n) + 1 < n))
    if at.size:
        code = arg[ids[at + 1]]
        ball = at[np.isin(code, [T.AT_SPHERE, T.AT_CIRCLE])] + 1
        first.append(ball[cnt[ball] > 0])
    for mods, _ in added:
        new_cnt[mods] = 1
    ends_a = np.array(ends, np.int64)
    new_cnt[ends_a] = 2
    new_off = np.zeros(n + 1, np.int64)
    np.cumsum(new_cnt, out=new_off[1:])
    out = np.zeros(int(new_off[-1]))
    owner = np.repeat(np.arange(n), cnt)
    out[new_off[owner] + (np.arange(values.size) - offsets[owner])] = values
    for mods in first:
        out[new_off[mods]] *= k[mods]
    for j, mods in enumerate(second):
        out[new_off[mods] + 1 + j % 2] *= k[mods]
    for mods, v in added:
        out[new_off[mods]] = v
    out[new_off[ends_a]] = 0.0
    out[new_off[ends_a] + 1] = np.array(factors)
    return ModuleString(word.alphabet, ids, new_off, out)
