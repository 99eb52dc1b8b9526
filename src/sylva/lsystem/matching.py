"""Context matching on the axial tree (ABOP §1.6–1.7, seed 001 §2.3 and §2.5).

* The **left context** of a module is the path of its ancestors: looking left, a whole
  bracketed subtree ``[..]`` is skipped and the ``[`` of the enclosing branch is passed.
* A **right context** may contain lateral subtrees ``[..]``; each must match some later
  lateral subtree of the word (ordered, distinct), unmentioned lateral subtrees are skipped,
  the word's axis may be longer than the pattern's, and the ``]`` closing the current branch
  ends it.
* Symbols in the **ignore** set (or outside the **consider** set) are skipped, unless they
  are the symbol the pattern wants next (the ABOP / L-Py rule, seed 001 §2.3).

:func:`match_left` and :func:`match_right` run the compiled kernels over many candidates at
once; :func:`left_context` and :func:`right_context` are the plain-Python reference for one
module, kept to test the kernels against.

Examples
--------
>>> from sylva.lsystem.lstring import ModuleString
>>> w = ModuleString.from_text("a[bc]d[e[f][g]h]i")
>>> [w.symbols()[i] for i in left_context(w, 14, ["a", "d", "e"])]
['a', 'd', 'e']
>>> right_context(w, 0, list("[b]d[e]i")) is not None
True
"""

from __future__ import annotations

from collections.abc import Collection, Sequence

import numpy as np

from .._jit import road
from .lstring import CLOSE, OPEN, SMALL_WORD, ModuleString

_kernels = road("sylva.lsystem._kernels", size=SMALL_WORD)  # one road, lstring's

__all__ = [
    "ignored_table",
    "left_context",
    "match_left",
    "match_right",
    "pattern_match",
    "right_context",
]


def ignored_table(
    word_or_size: ModuleString | int,
    ignore: Collection[int] = (),
    consider: Collection[int] | None = None,
) -> np.ndarray:
    """``bool[len(alphabet)]``: which symbol ids context matching skips."""
    size = word_or_size if isinstance(word_or_size, int) else len(word_or_size.alphabet)
    if consider is not None:
        t = np.ones(size, np.bool_)
        t[list(consider)] = False
    else:
        t = np.zeros(size, np.bool_)
        if ignore:
            t[list(ignore)] = True
    t[OPEN] = t[CLOSE] = False
    return t


def pattern_match(pattern: Sequence[int]) -> np.ndarray:
    """Partner index of every bracket in a right-context pattern (-1 elsewhere)."""
    m = np.full(len(pattern), -1, np.int64)
    stack = []
    for j, s in enumerate(pattern):
        if s == OPEN:
            stack.append(j)
        elif s == CLOSE:
            if not stack:
                raise ValueError("unbalanced brackets in a right context")
            o = stack.pop()
            m[o], m[j] = j, o
    if stack:
        raise ValueError("unbalanced brackets in a right context")
    return m


def match_left(
    word: ModuleString,
    candidates: np.ndarray,
    pattern: Sequence[int],
    arity: Sequence[int],
    ignored: np.ndarray,
) -> tuple[np.ndarray, np.ndarray]:
    """Match a left context at many positions.

    Returns ``ok bool[k]`` and ``positions int64[k, len(pattern)]``: the word module matched
    by each pattern module (valid where ``ok``).  ``arity[j]`` is the number of parameters
    the pattern's module ``j`` binds; a word module with fewer does not match.
    """
    return _kernels.match_left(
        word.ids,
        word.match,
        word.offsets,
        ignored,
        np.ascontiguousarray(candidates, np.int64),
        np.asarray(pattern, word.ids.dtype),
        np.asarray(arity, np.int64),
    )


def match_right(
    word: ModuleString,
    candidates: np.ndarray,
    pattern: Sequence[int],
    arity: Sequence[int],
    ignored: np.ndarray,
) -> tuple[np.ndarray, np.ndarray]:
    """Match a right context (which may contain ``[``/``]``) at many positions.

    Returns ``ok bool[k]`` and ``positions int64[k, len(pattern)]`` (-1 for brackets).
    """
    pat = np.asarray(pattern, word.ids.dtype)
    return _kernels.match_right(
        word.ids,
        word.match,
        word.offsets,
        ignored,
        np.ascontiguousarray(candidates, np.int64),
        pat,
        pattern_match(pat),
        np.asarray(arity, np.int64),
    )


# ----------------------------------------------------------------------------- reference
def _ids(word: ModuleString, pattern: Sequence[int | str]) -> list[int]:
    out = []
    for p in pattern:
        if isinstance(p, str):
            out.append(word.alphabet.get(p, -2))
        else:
            out.append(int(p))
    return out


def left_context(
    word: ModuleString,
    index: int,
    pattern: Sequence[int | str],
    ignore: Collection[str] = (),
) -> list[int] | None:
    """Reference: the positions matching ``pattern`` as left context of ``index``, or None."""
    ids = word.ids.tolist()
    match = word.match.tolist()
    pat = _ids(word, pattern)
    ign = {word.alphabet.get(s) for s in ignore}
    out: list[int] = []
    i = index - 1
    for want in reversed(pat):
        while True:
            if i < 0:
                return None
            s = ids[i]
            if s == CLOSE:
                if match[i] < 0:
                    return None
                i = match[i] - 1
            elif s == OPEN:
                i -= 1
            elif s == want:
                break
            elif s in ign:
                i -= 1
            else:
                return None
        out.append(i)
        i -= 1
    return out[::-1]


def right_context(
    word: ModuleString,
    index: int,
    pattern: Sequence[int | str],
    ignore: Collection[str] = (),
) -> list[int] | None:
    """Reference: positions matching ``pattern`` as right context of ``index``, or None.

    A recursive implementation with full backtracking over the choice of lateral subtree,
    written for clarity; the kernel must agree with it.
    """
    ids = word.ids.tolist()
    match = word.match.tolist()
    pat = _ids(word, pattern)
    pm = pattern_match(pat).tolist() if pat else []
    ign = {word.alphabet.get(s) for s in ignore}
    n = len(ids)

    def skip_ignored(i: int) -> int:
        while i < n and ids[i] > CLOSE and ids[i] in ign:
            i += 1
        return i

    def seq(i: int, j: int, end: int, acc: list[int]) -> list[int] | None:
        # match pattern[j:end] starting at word position i; returns the positions or None
        if j == end:
            return acc
        r = pat[j]
        if r == OPEN:
            jc = pm[j]
            b = skip_ignored(i)
            while b < n and ids[b] == OPEN and match[b] >= 0:
                inner = seq(b + 1, j + 1, jc, [])
                if inner is not None:
                    rest = seq(match[b] + 1, jc + 1, end, acc + [-1] + inner + [-1])
                    if rest is not None:
                        return rest
                b = skip_ignored(match[b] + 1)
            return None
        while i < n:
            s = ids[i]
            if s == OPEN:
                if match[i] < 0:
                    return None
                i = match[i] + 1
            elif s == CLOSE:
                return None
            elif s == r:
                return seq(i + 1, j + 1, end, acc + [i])
            elif s in ign:
                i += 1
            else:
                return None
        return None

    return seq(index + 1, 0, len(pat), [])
