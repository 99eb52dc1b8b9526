"""cpfg's context matching, module by module: literal brackets, ``=``, ring L-systems.

sylva's compiled matcher (:mod:`.matching`) reads a right context as a tree pattern
(balanced brackets, lateral subtrees matched in order).  cpfg (``generate.c``,
Prusinkiewicz & Hanan's) walks the word instead, and two of its constructs need that walk:

* a right context whose brackets do not balance: each ``[`` and ``]`` of the pattern is the
  next bracket of the word (a ``[`` the pattern does not name starts a branch that is
  skipped whole), so ``A > [B`` is "a branch that begins with ``B`` follows" and ``F > G]H``
  "``G`` ends this branch and ``H`` follows it";
* ``=`` in a right context (cpfg only): skip the rest of the current branch, up to its
  ``]`` (``N > [I=][I=]``: two branches that begin with ``I``);
* a *ring* L-system (``ring lsystem``): the word's last module is followed by its first,
  for both contexts.

These walks run in Python, one candidate at a time (cpfg's own cost), only for the rules
and programs that need them; every other rule keeps the compiled road.

Examples
--------
>>> from sylva.lsystem.lstring import ModuleString
>>> w = ModuleString.from_text("A[BC]D")
>>> ids = lambda s: np.array([w.alphabet.get(c) for c in s], w.ids.dtype)
>>> ign = np.zeros(len(w.alphabet), np.bool_)
>>> ok, pos = match_right(w, np.array([0]), ids("[B"), np.zeros(2, np.int64), ign)
>>> bool(ok[0]), pos[0].tolist()
(True, [-1, 2])
>>> ok, _ = match_right(w, np.array([2]), ids("C]D"), np.zeros(3, np.int64), ign)
>>> bool(ok[0])
True
"""

from __future__ import annotations

import numpy as np

from ._arity import arity_ok, need
from .lstring import CLOSE, OPEN, ModuleString

__all__ = ["contexts", "match_left", "match_right", "needs_walk"]


def contexts(word: ModuleString, cr, candidates: np.ndarray, ignored, ok: np.ndarray,
             kernels, ring: bool = False, skip: int = -1, exact: bool = False):  # fmt: skip
    """Match the left and right context of the engine's compiled rule ``cr`` at
    ``candidates``: ``ok`` is cleared where one fails; returns the matched positions
    ``(lpos, rpos)`` (None for a context the rule lacks).  The compiled kernels
    (``kernels.match_left`` / ``match_right``) do it, except for the walks of this module:
    ring L-systems and right contexts that need cpfg's walk (``cr.walk_right``).  ``exact``:
    a context module matches only a module of as many parameters (cpfg's, :mod:`._arity`)."""
    lpos = rpos = None
    left_arity, right_arity = need(cr.left_arity, exact), need(cr.right_arity, exact)
    if cr.left.size:
        if ring:
            okl, lpos = match_left(word, candidates, cr.left, left_arity, ignored)
        else:
            okl, lpos = kernels.match_left(word.ids, word.match, word.offsets, ignored,
                                           candidates, cr.left, left_arity)  # fmt: skip
        ok &= okl
    if cr.right.size:
        if cr.walk_right or ring:
            okr, rpos = match_right(word, candidates, cr.right, right_arity, ignored, skip,
                                    ring)  # fmt: skip
        else:
            okr, rpos = kernels.match_right(word.ids, word.match, word.offsets, ignored,
                                            candidates, cr.right, cr.right_match,
                                            right_arity)  # fmt: skip
        ok &= okr
    return lpos, rpos


def needs_walk(pattern: np.ndarray, skip: int) -> bool:
    """Whether a right-context pattern (symbol ids) needs the walk: unbalanced brackets, or
    cpfg's ``=`` (id ``skip``; -1 for none)."""
    depth = 0
    for s in pattern.tolist():
        if s == skip:
            return True
        if s == OPEN:
            depth += 1
        elif s == CLOSE:
            depth -= 1
            if depth < 0:
                return True
    return depth != 0


def _branch_end(ids: list, p: int, n: int) -> int:
    """The position of the ``]`` that closes the branch ``p`` is in (or ``n``)."""
    level = 0
    while p < n:
        s = ids[p]
        if s == OPEN:
            level += 1
        elif s == CLOSE:
            if level == 0:
                return p
            level -= 1
        p += 1
    return n


def _prepare(word, candidates, pattern, arity, ignored):
    """The word and the pattern as Python lists (the walks below index them one module at
    a time, where lists beat arrays) and the empty results: ``ok`` and ``pos``."""
    off = word.offsets
    pat = pattern.tolist()
    ok = np.zeros(len(candidates), np.bool_)
    pos = np.full((len(candidates), len(pat)), -1, np.int64)
    return (word.ids.tolist(), word.match.tolist(), (off[1:] - off[:-1]).tolist(),
            ignored.tolist(), pat, arity.tolist(), ok, pos)  # fmt: skip


def match_right(word: ModuleString, candidates: np.ndarray, pattern: np.ndarray,
                arity: np.ndarray, ignored: np.ndarray, skip: int = -1,
                ring: bool = False) -> tuple[np.ndarray, np.ndarray]:  # fmt: skip
    """cpfg's right context at each candidate: ``ok bool[k]`` and the word position of
    each pattern module ``int64[k, len(pattern)]`` (-1 for brackets and ``=``)."""
    ids, match, nparams, ign, pat, ar, ok, pos = _prepare(
        word, candidates, pattern, arity, ignored
    )
    n = len(ids)
    for c, i in enumerate(candidates.tolist()):
        p, j, wrapped, good = i + 1, 0, False, True
        row = pos[c]
        while j < len(pat):
            want = pat[j]
            if p >= n:
                if ring and not wrapped and want != CLOSE:
                    p, wrapped = 0, True
                    continue
                good = False
                break
            if ring and wrapped and p == i + 1:  # around the whole ring
                good = False
                break
            if want == skip:
                p = _branch_end(ids, p, n)
                j += 1
                continue
            s = ids[p]
            if s > CLOSE and ign[s] and s != want:
                p += 1
            elif want != OPEN and s == OPEN:
                m = match[p]
                if m < 0:
                    good = False
                    break
                p = m + 1
            elif s != want or (s > CLOSE and not arity_ok(nparams[p], ar[j])):
                good = False
                break
            else:
                if s > CLOSE:
                    row[j] = p
                p += 1
                j += 1
        ok[c] = good
    return ok, pos


def match_left(
    word: ModuleString, candidates: np.ndarray, pattern: np.ndarray, arity: np.ndarray,
    ignored: np.ndarray,
) -> tuple[np.ndarray, np.ndarray]:
    """A left context in a ring L-system (the word's first module is preceded by its
    last): ``ok bool[k]`` and ``positions int64[k, len(pattern)]``."""
    ids, match, nparams, ign, pat, ar, ok, pos = _prepare(
        word, candidates, pattern, arity, ignored
    )
    n = len(ids)
    for c, i in enumerate(candidates.tolist()):
        p, j, seen, good = i - 1, len(pat) - 1, 0, True
        while j >= 0:
            if p < 0:
                p = n - 1
            seen += 1
            if seen > n:  # around the whole ring
                good = False
                break
            s = ids[p]
            if s == CLOSE:
                m = match[p]
                if m < 0:
                    good = False
                    break
                seen += p - m
                p = m - 1
            elif s == OPEN:
                p -= 1
            elif s == pat[j] and arity_ok(nparams[p], ar[j]):
                pos[c, j] = p
                p -= 1
                j -= 1
            elif ign[s]:
                p -= 1
            else:
                good = False
                break
        ok[c] = good
    return ok, pos
