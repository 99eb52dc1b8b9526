"""Numba kernels behind the engine: bracket matching, context matching, rewriting, cutting.

Every kernel works on the arrays of a :class:`~sylva.lsystem.lstring.ModuleString`
(``ids`` uint16, ``offsets`` int64, ``values`` float64).  Ids 0 and 1 are ``[`` and ``]``.
The public, documented layer is :mod:`sylva.lsystem.matching` and
:mod:`sylva.lsystem.engine`; these functions check nothing.
"""

from __future__ import annotations

import numpy as np
from numba import njit, prange

OPEN = 0
CLOSE = 1

# splitmix64 constants
_GOLDEN = np.uint64(0x9E3779B97F4A7C15)
_M1 = np.uint64(0xBF58476D1CE4E5B9)
_M2 = np.uint64(0x94D049BB133111EB)


@njit(cache=True)
def match_brackets(ids):  # pragma: no cover - compiled
    """Matching bracket index for every ``[``/``]`` (-1 elsewhere or when unbalanced)."""
    n = ids.shape[0]
    m = np.full(n, -1, np.int64)
    stack = np.empty(n + 1, np.int64)
    top = 0
    for i in range(n):
        s = ids[i]
        if s == OPEN:
            stack[top] = i
            top += 1
        elif s == CLOSE and top > 0:
            top -= 1
            j = stack[top]
            m[i] = j
            m[j] = i
    return m


@njit(cache=True, inline="always")
def _mix(z):  # pragma: no cover - compiled
    z = (z ^ (z >> np.uint64(30))) * _M1
    z = (z ^ (z >> np.uint64(27))) * _M2
    return z ^ (z >> np.uint64(31))


@njit(cache=True)
def uniform(key, positions):  # pragma: no cover - compiled
    """Counter-based uniform numbers in [0, 1): one per position, from a 64-bit key."""
    out = np.empty(positions.shape[0], np.float64)
    for k in range(positions.shape[0]):
        z = key + (np.uint64(positions[k]) + np.uint64(1)) * _GOLDEN
        out[k] = np.float64(_mix(z) >> np.uint64(11)) * (1.0 / 9007199254740992.0)
    return out


@njit(cache=True, inline="always")
def _arity_ok(have, want):  # pragma: no cover - compiled
    """A module of ``have`` parameters against a pattern's arity: ``want >= 0`` at least
    that many, ``-(a + 1)`` exactly ``a`` (cpfg's, :mod:`sylva.lsystem._arity`)."""
    return have >= want if want >= 0 else have == -want - 1


@njit(cache=True)
def _left_one(ids, match, offsets, ignored, p, pat, arity, pos, row):  # pragma: no cover
    """Match a left context at position ``p``; write the positions into ``pos[row]``."""
    m = pat.shape[0]
    i = p - 1
    j = m - 1
    check = offsets.shape[0] > 0
    while j >= 0:
        found = False
        while i >= 0:
            s = ids[i]
            if s == CLOSE:
                mi = match[i]
                if mi < 0:
                    break
                i = mi - 1
                continue
            if s == OPEN:
                i -= 1
                continue
            if s == pat[j]:
                found = True
                break
            if ignored[s]:
                i -= 1
                continue
            break
        if not found:
            return False
        if check and not _arity_ok(offsets[i + 1] - offsets[i], arity[j]):
            return False
        pos[row, j] = i
        j -= 1
        i -= 1
    return True


@njit(cache=True)
def _right_one(ids, match, offsets, ignored, p, pat, arity, pos, row, fj, fi):  # pragma: no cover
    """Match a right context at position ``p`` (see :func:`match_right`)."""
    n = ids.shape[0]
    m = pat.shape[0]
    check = offsets.shape[0] > 0
    i = p + 1
    j = 0
    top = 0
    while j < m:
        r = pat[j]
        fail = False
        if r == OPEN:
            while i < n and ids[i] > CLOSE and ignored[ids[i]]:
                i += 1
            if i < n and ids[i] == OPEN:
                fj[top] = j
                fi[top] = i
                top += 1
                j += 1
                i += 1
                continue
            fail = True
        elif r == CLOSE:
            top -= 1
            i = match[fi[top]] + 1
            j += 1
            continue
        else:
            found = False
            while i < n:
                s = ids[i]
                if s == OPEN:
                    mi = match[i]
                    if mi < 0:
                        break
                    i = mi + 1
                    continue
                if s == CLOSE:
                    break
                if s == r:
                    found = True
                    break
                if ignored[s]:
                    i += 1
                    continue
                break
            if found and (not check or _arity_ok(offsets[i + 1] - offsets[i], arity[j])):
                pos[row, j] = i
                i += 1
                j += 1
                continue
            fail = True
        if fail:
            # retry the innermost open frame with its next sibling branch
            retried = False
            while top > 0:
                t = top - 1
                nxt = match[fi[t]]
                if nxt < 0:
                    return False
                nxt += 1
                while nxt < n and ids[nxt] > CLOSE and ignored[ids[nxt]]:
                    nxt += 1
                if nxt < n and ids[nxt] == OPEN:
                    fi[t] = nxt
                    j = fj[t] + 1
                    i = nxt + 1
                    retried = True
                    break
                top -= 1
            if not retried:
                return False
    return True


@njit(cache=True)
def match_left(ids, match, offsets, ignored, cand, pat, arity):  # pragma: no cover
    """Left context on the axial tree for every candidate position.

    Walking left from a candidate, a ``]`` skips its whole bracketed subtree, a ``[`` is
    passed (it leads to the parent), an ignored symbol is skipped unless it is the one the
    pattern wants next.  Returns ``ok bool[k]`` and the matched positions ``int64[k, m]``.
    An empty ``offsets`` array skips the parameter-count check.
    """
    k = cand.shape[0]
    ok = np.zeros(k, np.bool_)
    pos = np.full((k, pat.shape[0]), -1, np.int64)
    for c in range(k):
        ok[c] = _left_one(ids, match, offsets, ignored, cand[c], pat, arity, pos, c)
    return ok, pos


@njit(cache=True)
def match_right(ids, match, offsets, ignored, cand, pat, pmatch, arity):  # pragma: no cover
    """Right context on the axial tree for every candidate position.

    ``pat`` may hold ``[``/``]`` (ids 0/1) delimiting lateral subtrees; ``pmatch`` gives
    their partners within the pattern.  A lateral subtree of the pattern must match some
    later lateral subtree of the word (ordered, distinct); lateral subtrees of the word that
    the pattern does not mention are skipped; the pattern may end before the word's axis;
    the word's ``]`` ends the current branch.  Greedy earliest matching with retry of the
    next sibling branch is complete for ordered matching (an earlier sibling never leaves
    less to match than a later one).
    """
    k = cand.shape[0]
    m = pat.shape[0]
    ok = np.zeros(k, np.bool_)
    pos = np.full((k, m), -1, np.int64)
    fj = np.empty(m + 1, np.int64)
    fi = np.empty(m + 1, np.int64)
    for c in range(k):
        ok[c] = _right_one(ids, match, offsets, ignored, cand[c], pat, arity, pos, c, fj, fi)
    return ok, pos


@njit(cache=True)
def rewrite_context(ids, match, ignored, key, sym_start, sym_count, r_tier, r_weight,
                    r_lstart, r_llen, r_rstart, r_rlen, pats, r_len, r_ids_start, r_ids):
    """One step of a parameter-free system with contexts, in two compiled passes.

    The rules of symbol ``s`` are ``sym_start[s] … + sym_count[s]``, sorted by tier
    (context before context-free).  Rule ``r`` has its left and right context in
    ``pats[r_lstart[r]:…+r_llen[r]]`` / ``pats[r_rstart[r]:…]``, a positive weight and a
    successor ``r_ids[r_ids_start[r]:…+r_len[r]]``.  Within the first tier that has an
    applicable rule one is drawn by weight with the hash of ``(key, position)``, as the
    general road does.  Returns the new ids.
    """  # pragma: no cover - compiled
    n = ids.shape[0]
    choice = np.full(n, -1, np.int64)
    noff = np.zeros(0, np.int64)
    maxm = 1
    for r in range(r_llen.shape[0]):
        maxm = max(maxm, r_llen[r], r_rlen[r])
    pos = np.empty((1, maxm), np.int64)
    fj = np.empty(maxm + 1, np.int64)
    fi = np.empty(maxm + 1, np.int64)
    app = np.empty(max(1, r_tier.shape[0]), np.int64)
    total = 0
    for i in range(n):
        s = ids[i]
        cnt = sym_count[s]
        if cnt == 0:
            total += 1
            continue
        st = sym_start[s]
        q = st
        chosen = -1
        while q < st + cnt and chosen < 0:
            tier = r_tier[q]
            na = 0
            wsum = 0.0
            while q < st + cnt and r_tier[q] == tier:
                good = True
                if r_llen[q] > 0:
                    good = _left_one(ids, match, noff, ignored, i,
                                     pats[r_lstart[q]:r_lstart[q] + r_llen[q]], pats, pos, 0)
                if good and r_rlen[q] > 0:
                    good = _right_one(ids, match, noff, ignored, i,
                                      pats[r_rstart[q]:r_rstart[q] + r_rlen[q]], pats, pos, 0,
                                      fj, fi)
                if good:
                    app[na] = q
                    na += 1
                    wsum += r_weight[q]
                q += 1
            if na == 1:
                chosen = app[0]
            elif na > 1:
                z = key + (np.uint64(i) + np.uint64(1)) * _GOLDEN
                u = np.float64(_mix(z) >> np.uint64(11)) * (1.0 / 9007199254740992.0)
                t = u * wsum
                acc = 0.0
                chosen = app[na - 1]
                for a in range(na):
                    acc += r_weight[app[a]]
                    if acc > t:
                        chosen = app[a]
                        break
        choice[i] = chosen
        total += 1 if chosen < 0 else r_len[chosen]
    out = np.empty(total, ids.dtype)
    o = 0
    for i in range(n):
        r = choice[i]
        if r < 0:
            out[o] = ids[i]
            o += 1
        else:
            b = r_ids_start[r]
            for k in range(r_len[r]):
                out[o + k] = r_ids[b + k]
            o += r_len[r]
    return out


@njit(cache=True, inline="always")
def _pick(i, s, key, stochastic, nalt, alt_start, cum_w):  # pragma: no cover - compiled
    a0 = alt_start[s]
    na = nalt[s]
    a = a0
    if na > 1 and stochastic:
        z = key + (np.uint64(i) + np.uint64(1)) * _GOLDEN
        u = np.float64(_mix(z) >> np.uint64(11)) * (1.0 / 9007199254740992.0)
        t = u * cum_w[a0 + na - 1]
        while a < a0 + na - 1 and cum_w[a] <= t:
            a += 1
    return a


@njit(cache=True, parallel=True)
def rewrite_table(ids, key, stochastic, nalt, alt_start, cum_w, succ_start, succ_len, succ_ids):
    """One context-free, parameter-free step: choose and count, then copy, in parallel chunks.

    Per symbol ``s``: ``nalt[s]`` alternatives starting at ``alt_start[s]``; alternative
    ``a`` has cumulative weight ``cum_w[a]`` (within its symbol) and successor
    ``succ_ids[succ_start[a]:succ_start[a] + succ_len[a]]``.  ``nalt == 0`` is identity.
    Random draws use :func:`uniform`'s hash of ``(key, position)``, so the result does not
    depend on the number of threads.
    """
    n = ids.shape[0]
    nchunks = 64 if n >= 50_000 else 1  # small words: one chunk, no thread hand-off
    bounds = np.linspace(0, n, nchunks + 1).astype(np.int64)
    pick = np.empty(n, np.int32)
    sizes = np.zeros(nchunks + 1, np.int64)
    for c in prange(nchunks):
        tot = 0
        for i in range(bounds[c], bounds[c + 1]):
            s = ids[i]
            if nalt[s] == 0:
                pick[i] = -1
                tot += 1
            else:
                a = _pick(i, s, key, stochastic, nalt, alt_start, cum_w)
                pick[i] = a
                tot += succ_len[a]
        sizes[c + 1] = tot
    starts = np.cumsum(sizes)
    out = np.empty(starts[nchunks], ids.dtype)
    for c in prange(nchunks):
        o = starts[c]
        for i in range(bounds[c], bounds[c + 1]):
            a = pick[i]
            if a < 0:
                out[o] = ids[i]
                o += 1
                continue
            st = succ_start[a]
            ln = succ_len[a]
            if ln == 1:
                out[o] = succ_ids[st]
                o += 1
            else:
                for q in range(ln):
                    out[o + q] = succ_ids[st + q]
                o += ln
    return out


@njit(cache=True)
def count_table(ids, key, stochastic, nalt, alt_start, cum_w, succ_len):  # pragma: no cover
    """The length :func:`rewrite_table` would produce (for the growth limit)."""
    total = 0
    for i in range(ids.shape[0]):
        s = ids[i]
        if nalt[s] == 0:
            total += 1
        else:
            total += succ_len[_pick(i, s, key, stochastic, nalt, alt_start, cum_w)]
    return total


@njit(cache=True)
def assemble(ids, offsets, values, choice, rule_len, rule_nvals, rule_ids_start, rule_ids,
             rule_nparams):  # pragma: no cover - compiled
    """Build the next word's ids and parameter layout from a rule choice per module.

    ``choice[i]`` is -1 (identity: the module and its parameters are copied) or a rule
    index whose successor ids are ``rule_ids[rule_ids_start[r]:...+rule_len[r]]`` with
    ``rule_nparams`` parameters per successor module (flattened the same way).  Returns
    the new ``ids``, ``offsets``, ``values`` (rule-made parameters left to fill), and for
    every old module the index of its first new module and of its first new value.
    """
    n = ids.shape[0]
    out_start = np.empty(n + 1, np.int64)
    val_start = np.empty(n + 1, np.int64)
    tot = 0
    totv = 0
    for i in range(n):
        out_start[i] = tot
        val_start[i] = totv
        r = choice[i]
        if r < 0:
            tot += 1
            totv += offsets[i + 1] - offsets[i]
        else:
            tot += rule_len[r]
            totv += rule_nvals[r]
    out_start[n] = tot
    val_start[n] = totv
    new_ids = np.empty(tot, ids.dtype)
    new_off = np.empty(tot + 1, np.int64)
    new_vals = np.zeros(totv, np.float64)
    for i in range(n):
        o = out_start[i]
        v = val_start[i]
        r = choice[i]
        if r < 0:
            new_ids[o] = ids[i]
            new_off[o] = v
            a = offsets[i]
            b = offsets[i + 1]
            for q in range(b - a):
                new_vals[v + q] = values[a + q]
        else:
            st = rule_ids_start[r]
            for q in range(rule_len[r]):
                new_ids[o + q] = rule_ids[st + q]
                new_off[o + q] = v
                v += rule_nparams[st + q]
    new_off[tot] = totv
    return new_ids, new_off, new_vals, out_start, val_start


@njit(cache=True)
def assemble_ids(ids, choice, rule_len, rule_ids_start, rule_ids):  # pragma: no cover
    """:func:`assemble` for words and rules without parameters: the new ids only."""
    n = ids.shape[0]
    tot = 0
    for i in range(n):
        r = choice[i]
        tot += 1 if r < 0 else rule_len[r]
    out = np.empty(tot, ids.dtype)
    o = 0
    for i in range(n):
        r = choice[i]
        if r < 0:
            out[o] = ids[i]
            o += 1
        else:
            st = rule_ids_start[r]
            ln = rule_len[r]
            for q in range(ln):
                out[o + q] = rule_ids[st + q]
            o += ln
    return out


@njit(cache=True)
def cut_mask(ids, cut_id):  # pragma: no cover - compiled
    """Keep-mask after ABOP's cut: ``%`` removes itself and the rest of its branch."""
    n = ids.shape[0]
    keep = np.ones(n, np.bool_)
    i = 0
    while i < n:
        if ids[i] == cut_id:
            depth = 0
            while i < n:
                s = ids[i]
                if s == OPEN:
                    depth += 1
                elif s == CLOSE:
                    if depth == 0:
                        break
                    depth -= 1
                keep[i] = False
                i += 1
        else:
            i += 1
    return keep


@njit(cache=True)
def parents(ids, match):  # pragma: no cover - compiled
    """Parent module on the axial tree (-1 at a root) and bracket depth of every module."""
    n = ids.shape[0]
    parent = np.full(n, -1, np.int64)
    depth = np.zeros(n, np.int32)
    # stack[d] = last module on the axis at depth d (-1 when none yet)
    stack = np.full(n + 2, -1, np.int64)
    d = 0
    for i in range(n):
        s = ids[i]
        if s == 0:  # [
            depth[i] = d
            d += 1
            stack[d] = stack[d - 1]
        elif s == 1:  # ]
            d -= 1
            if d < 0:
                d = 0
            depth[i] = d
        else:
            depth[i] = d
            parent[i] = stack[d]
            stack[d] = i
    return parent, depth
