"""Compiled turtle: one numba loop over a word's arrays, shared by every dialect.

The public layer (:mod:`sylva.turtle.interpret`) checks inputs and builds the arrays; nothing
here validates anything.  State is a ``float64`` vector (layout ``S_*``), pushed and popped as
rows of a stack array; settings come in as a ``float64`` vector (layout ``C_*``).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, uint64

from . import tables as T
from ._movements import (
    C_MOV,
    C_NMOV,
    MOV_SLOTS,
    MOV_W,
    NC_MOV,
    movement_adjust,
    old_bend,
    turn_frame,
)
from ._movements import S_H as M_H
from ._movements import S_L as M_L
from ._movements import S_OLD as M_OLD
from ._movements import S_U as M_U
from ._state import COPIED, SPHERE_NP, SPHERE_NV, SPHERE_OFF, SPHERE_V
from ._state import copy_state as _copy_state
from .tables import (
    AT_CIRCLE,
    AT_G,
    AT_HEADING,
    AT_MOVE,
    AT_SPHERE,
    AT_T,
    AT_TD,
    AT_TI,
    AT_TS,  # fmt: skip
    AT_VERTICAL,
)

# --------------------------------------------------------------------------- state layout
S_POS = 0
S_H = 3
S_L = 6
S_U = 9
S_LEN = 12
S_ROT = 13
S_RAD = 14
S_COL = 15
S_CIDX = 18
S_LAST = 19
S_YAW = 20
S_PITCH = 21
S_SCALE = 22
S_BUF = 23
S_LASTMOVE = 24
S_OPEN = 25
S_DIR = 26  # unit direction of the last segment (valid while S_LAST >= 0)
S_REF = 29  # its ring reference vector
S_NROT = 32  # rotations since the frame was last made orthonormal
# elasticity of the branch (ABOP §2.3 tropism; @Ts sets it per branch): the slot of seed
# 004's pitch, which only the engine turtle uses, and it has no tropism (a 34th element
# would make every push and pop of every word copy more)
S_ELAST = S_PITCH
NS = 33

# --------------------------------------------------------------------------- settings layout
C_LEN = 0
C_ROT = 1
C_RAD = 2
C_COL = 3
C_LEN_D = 6
C_RAD_D = 7
C_ROT_D = 8
C_COL_D = 9
C_RAD_F = 12
C_REDUCTION = 13
C_LEAF = 14
C_YAW = 15
C_PITCH = 16
C_SHRINK = 17
C_BASE = 18
C_AVAR = 19
C_SALT = 20
C_NSEED = 21
C_WSCALE = 22
C_MAT_LEAF = 23
C_MAT_POLY = 24
C_CIDX = 25
C_ENGINE = 26
C_CLAMP = 27
C_TROP = 28  # tropism vector T (3)
C_ELAST = 31  # initial elasticity e
C_ESTEP = 32  # elasticity increment of @Ti / @Td
C_TMODE = 33  # 1: cpfg's @T modules (tropism index first), 0: sylva's / L-Py's
C_TON = 34  # 1 when tropism may bend the word (an elasticity or an @ module): walk's flag
C_WMODE = 35  # 1: cpfg's widths (``!`` subtracts width_step, ``#`` adds it), 0: ABOP's
C_PMODE = 36  # 1: cpfg's polygons (interpret.c: ``{`` adds no vertex; ``.``, F and f each add
#   one; F still draws its line), 0: sylva's (``{`` and every move add one, dropped if ``.``)
# cpfg's tropism: and torque: lines (_movements: C_NMOV, then MOV_W numbers each)
NC = NC_MOV


MASK32 = 0xFFFFFFFF
UINT_MAX = 4294967295.0


@njit(cache=True)
def squirrel1d(x, seed):  # pragma: no cover - compiled
    """Squirrel Eiserloh's "Squirrel3" integer noise (seed 004 A.2), ``uint32`` result."""
    m = ((np.int64(x) & MASK32) * 0x68E31DA4) & MASK32
    m = (m + (np.int64(seed) & MASK32)) & MASK32
    m ^= m >> 8
    m = (m + 0xB5297A4D) & MASK32
    m ^= (m << 8) & MASK32
    m = (m * 0x1B56C4E9) & MASK32
    m ^= m >> 8
    return m


@njit(cache=True)
def hash01(x, seed):  # pragma: no cover - compiled
    return squirrel1d(x, seed) / UINT_MAX


@njit(cache=True)
def _engine_frame(st):  # pragma: no cover - compiled
    # seed 004 §4.4, with the singularity guard
    if abs(math.cos(math.radians(st[S_PITCH]))) < 0.001:
        st[S_PITCH] -= 0.01
    yaw = math.radians(st[S_YAW])
    pitch = math.radians(st[S_PITCH])
    fx = math.cos(yaw) * math.cos(pitch)
    fy = math.sin(pitch)
    fz = math.sin(yaw) * math.cos(pitch)
    n = math.sqrt(fx * fx + fy * fy + fz * fz)
    fx /= n
    fy /= n
    fz /= n
    # right = normalize(front x (0, 1, 0))
    rx = -fz
    ry = 0.0
    rz = fx
    n = math.sqrt(rx * rx + rz * rz)
    rx /= n
    rz /= n
    # up = normalize(right x front)
    ux = ry * fz - rz * fy
    uy = rz * fx - rx * fz
    uz = rx * fy - ry * fx
    n = math.sqrt(ux * ux + uy * uy + uz * uz)
    st[S_H] = fx
    st[S_H + 1] = fy
    st[S_H + 2] = fz
    st[S_L] = -rx
    st[S_L + 1] = -ry
    st[S_L + 2] = -rz
    st[S_U] = ux / n
    st[S_U + 1] = uy / n
    st[S_U + 2] = uz / n


@njit(cache=True)
def _rotate(st, a, b, c, s):  # pragma: no cover - compiled
    """Right-handed rotation of the frame by the angle of cosine ``c`` and sine ``s`` about
    the axis (a x b).

    ``a`` and ``b`` are the state offsets of the two vectors that turn: for a rotation about
    U they are H and L (H turns toward L), about L they are U and H, about H they are L and U.
    """
    for k in range(3):
        x = st[a + k]
        y = st[b + k]
        st[a + k] = x * c + y * s
        st[b + k] = -x * s + y * c


if (S_H, S_L, S_U, S_ELAST) != (M_H, M_L, M_U, M_OLD):  # pragma: no cover
    raise ImportError("_movements' state slots differ from the kernel's")
if NS != COPIED:  # pragma: no cover - a layout change must update _copy_state
    raise ImportError(f"_copy_state copies {COPIED} state elements, the state has {NS}")


@njit(cache=True)
def _normalize_frame(st):  # pragma: no cover - compiled
    # Gram-Schmidt keeps H, L, U orthonormal over millions of rotations
    n = math.sqrt(st[S_H] ** 2 + st[S_H + 1] ** 2 + st[S_H + 2] ** 2)
    for k in range(3):
        st[S_H + k] /= n
    d = st[S_L] * st[S_H] + st[S_L + 1] * st[S_H + 1] + st[S_L + 2] * st[S_H + 2]
    for k in range(3):
        st[S_L + k] -= d * st[S_H + k]
    n = math.sqrt(st[S_L] ** 2 + st[S_L + 1] ** 2 + st[S_L + 2] ** 2)
    for k in range(3):
        st[S_L + k] /= n
    st[S_U] = st[S_H + 1] * st[S_L + 2] - st[S_H + 2] * st[S_L + 1]
    st[S_U + 1] = st[S_H + 2] * st[S_L] - st[S_H] * st[S_L + 2]
    st[S_U + 2] = st[S_H] * st[S_L + 1] - st[S_H + 1] * st[S_L]


@njit(cache=True)
def _level(st):  # pragma: no cover - compiled
    # ABOP $: L = V x H / |V x H| with V = +Y, U = H x L
    hx = st[S_H]
    hy = st[S_H + 1]
    hz = st[S_H + 2]
    lx = hz  # (0,1,0) x (hx,hy,hz) = (hz, 0, -hx)
    lz = -hx
    n = math.sqrt(lx * lx + lz * lz)
    if n < 1e-12:
        return
    lx /= n
    lz /= n
    st[S_L] = lx
    st[S_L + 1] = 0.0
    st[S_L + 2] = lz
    st[S_U] = hy * lz - hz * 0.0
    st[S_U + 1] = hz * lx - hx * lz
    st[S_U + 2] = hx * 0.0 - hy * lx


@njit(cache=True)
def _bend(st, tx, ty, tz):  # pragma: no cover - compiled
    """ABOP §2.3 tropism: rotate the frame about H x T by e|H x T| (H turns toward T)."""
    hx = st[S_H]
    hy = st[S_H + 1]
    hz = st[S_H + 2]
    ax = hy * tz - hz * ty
    ay = hz * tx - hx * tz
    az = hx * ty - hy * tx
    m = math.sqrt(ax * ax + ay * ay + az * az)
    if m < 1e-12:
        return
    ang = st[S_ELAST] * m
    kx = ax / m
    ky = ay / m
    kz = az / m
    turn_frame(st, kx, ky, kz, ang, S_H)  # H, L and U alike (Rodrigues)
    st[S_NROT] += 1.0
    if st[S_NROT] >= 64.0:
        _normalize_frame(st)
        st[S_NROT] = 0.0


@njit(cache=True)
def _transport(rx, ry, rz, ax, ay, az, bx, by, bz, fx, fy, fz):  # pragma: no cover - compiled
    """Parallel transport of unit ``r`` (normal to ``a``) to a unit vector normal to ``b``;
    ``f`` is the fallback (the turtle's L) for a reversal.  Scalars in and out (no heap)."""
    c = ax * bx + ay * by + az * bz
    if c > -0.9999:
        kx = ay * bz - az * by
        ky = az * bx - ax * bz
        kz = ax * by - ay * bx
        f = (kx * rx + ky * ry + kz * rz) / (1.0 + c)
        ox = rx * c + (ky * rz - kz * ry) + kx * f
        oy = ry * c + (kz * rx - kx * rz) + ky * f
        oz = rz * c + (kx * ry - ky * rx) + kz * f
    else:
        ox, oy, oz = fx, fy, fz
    d = ox * bx + oy * by + oz * bz
    ox -= d * bx
    oy -= d * by
    oz -= d * bz
    n = math.sqrt(ox * ox + oy * oy + oz * oz)
    if n < 1e-9:
        d = fx * bx + fy * by + fz * bz
        ox = fx - d * bx
        oy = fy - d * by
        oz = fz - d * bz
        n = math.sqrt(ox * ox + oy * oy + oz * oz)
    return ox / n, oy / n, oz / n


# --------------------------------------------------------------------------- counters
# ``cnt`` (int64) carries the walker's counters between calls and threads
K_NS = 0  # next segment slot: the ordinal of the next F/G (a slot stays a hole when unused)
K_NL = 1  # leaves written
K_NTMP = 2  # open-polygon vertices
K_NPSTACK = 3  # open polygons
K_NOPENED = 4  # polygons opened
K_NV = 5  # polygon vertices kept
K_NPOLY = 6  # polygons kept
K_NB = 7  # blocks (counted beyond the room)
K_HOLES = 8  # segment slots left unused (zero length, inside a polygon)
K_STOP = 9  # where the walk ended (a top-level % ends it early)
K_SALT = 10  # seed 004's salt chain
K_SEL = 11  # next subtree to hand to the parallel walkers
NK = 12

# the bits and fields of scan_range's per-symbol table
F_DRAW = 1
F_SERIAL = 8
F_LEAF = 16
F_PUSH = 32
F_POP = 64
F_PV = 1 << 8  # bits 8-15: polygon-vertex room
F_POLY = 1 << 16  # bits 16-23: polygon room


PUSH_CAP = 1 << 16  # brackets deeper than this are never split off (the walk still works)


@njit(cache=True, nogil=True)
def scan_range(ids, ops, lo, hi, s_min, s_max):  # pragma: no cover - compiled
    """One pass over modules ``lo`` … ``hi - 1``: counts, bracket depths, and the subtrees
    the turtle may walk in parallel.

    A subtree is a bracket pair ``[ … ]`` of ``s_min`` to ``s_max`` modules, wholly in the
    range, that lies in no other chosen pair of the range.  Returns ``(stats, sel)``:
    ``stats`` = (F/G draws, leaves, polygon-vertex room, polygons, serial-only commands,
    net depth change, lowest depth, highest depth), depths relative to the range's start
    and unclamped; ``sel`` an ``int64[k, 6]`` of (start, end, draws before, leaves before,
    draws after, leaves after), the ordinals counted from the range's start.  Ranges scanned
    apart (on threads) combine with :func:`scan_merge`.
    """
    n_draw = 0
    n_leaf = 0
    n_pv = 0
    n_poly = 0
    serial = 0
    d = 0  # depth relative to lo, unclamped: a ] may close a [ before the range
    lowest = 0
    highest = 0
    ld = 0  # open brackets of the range itself
    b_pos = np.empty(PUSH_CAP, np.int64)
    b_ns = np.empty(PUSH_CAP, np.int64)
    b_nl = np.empty(PUSH_CAP, np.int64)
    cap = (hi - lo) // max(s_min, 1) + 2
    sel = np.empty((cap, 6), np.int64)
    nc = 0
    # what each symbol counts toward, as bits: the loop adds them without branching and
    # branches only on brackets (a few per cent faster than a chain of tests on the opcode;
    # the brackets' bookkeeping is most of the scan's time)
    fl = np.empty(ops.shape[0], np.int64)
    for k in range(ops.shape[0]):
        op = ops[k]
        fl[k] = (
            (op == T.DRAW or op == T.DRAW_NOREC) * F_DRAW
            + (op == T.DRAW or op == T.MOVE or op == T.POLY_VERTEX or op == T.POLY_BEGIN) * F_PV
            + (op == T.POLY_BEGIN) * F_POLY
            + (op == T.AT) * (SPHERE_NV * F_PV + SPHERE_NP * F_POLY)  # room for an @O
            + (
                op == T.POLY_BEGIN
                or op == T.POLY_END
                or op == T.POLY_VERTEX
                or op == T.CUT
                or op == T.AT
            )
            * F_SERIAL
            + (op == T.LEAF or op == T.SURFACE) * F_LEAF
            + (op == T.PUSH) * F_PUSH
            + (op == T.POP) * F_POP
        )
    for i in range(lo, hi):
        f = fl[uint64(ids[i])]
        n_draw += f & F_DRAW
        n_pv += (f >> 8) & 0xFF
        n_poly += (f >> 16) & 0xFF
        serial += (f >> 3) & 1
        n_leaf += (f >> 4) & 1
        if (f & (F_PUSH | F_POP)) == 0:
            continue
        if f & F_PUSH:
            if ld < PUSH_CAP:
                b_pos[ld] = i
                b_ns[ld] = n_draw
                b_nl[ld] = n_leaf
            ld += 1
            d += 1
            if d > highest:
                highest = d
        else:
            d -= 1
            if d < lowest:
                lowest = d
            if ld > 0:
                ld -= 1
                if ld < PUSH_CAP:
                    a = b_pos[ld]
                    size = i - a + 1
                    if size >= s_min and size <= s_max:
                        while nc > 0 and sel[nc - 1, 0] > a:  # pairs inside this one
                            nc -= 1
                        sel[nc, 0] = a
                        sel[nc, 1] = i
                        sel[nc, 2] = b_ns[ld]
                        sel[nc, 3] = b_nl[ld]
                        sel[nc, 4] = n_draw
                        sel[nc, 5] = n_leaf
                        nc += 1
    stats = np.array([n_draw, n_leaf, n_pv, n_poly, serial, d, lowest, highest], np.int64)
    return stats, sel[:nc].copy()


def scan_merge(parts):
    """``(counts, sel)`` of a word from the :func:`scan_range` results of its consecutive
    ranges: ``counts`` = (F/G draws, leaves, polygon-vertex room, polygons, deepest bracket,
    serial-only commands).

    A ``]`` with no ``[`` before it is ignored, as the turtle ignores it: a range entered
    at depth D ends at ``max(D, -lowest) + net`` and reaches at most
    ``max(D, -lowest) + highest`` (exact for balanced words, an upper bound otherwise: the
    depth sizes the turtle's stack).
    """
    total = np.zeros(5, np.int64)
    depth = 0
    deepest = 0
    sels = []
    for stats, sel in parts:
        if sel.shape[0]:
            sel = sel.copy()
            sel[:, 2] += total[0]
            sel[:, 4] += total[0]
            sel[:, 3] += total[1]
            sel[:, 5] += total[1]
            sels.append(sel)
        total += stats[:5]
        entry = max(depth, -int(stats[6]))
        deepest = max(deepest, entry + int(stats[7]))
        depth = entry + int(stats[5])
    counts = np.array([total[0], total[1], total[2], total[3], deepest, total[4]], np.int64)
    sel = np.concatenate(sels) if sels else np.zeros((0, 6), np.int64)
    return counts, sel


def scan_word(ids, ops, s_min, s_max):
    """:func:`scan_range` over the whole word, in one piece (see :func:`scan_merge`)."""
    return scan_merge([scan_range(ids, ops, 0, ids.shape[0], s_min, s_max)])


@njit(cache=True, inline="always")
def _trace_pose(tr_pos, tr_frame, i, st):  # pragma: no cover - compiled
    for k in range(3):
        tr_pos[i, k] = st[S_POS + k]
        tr_frame[i, 0, k] = st[S_H + k]
        tr_frame[i, 1, k] = st[S_L + k]
        tr_frame[i, 2, k] = st[S_U + k]


@njit(cache=True)
def _set_heading(st, values, a, npar):  # pragma: no cover - compiled
    """cpfg's @R: H from the first 2 or 3 parameters (a zero vector is +Y); U from the next
    three when they make a vector that is not along H, else the frame turns the least."""
    hx = values[a]
    hy = values[a + 1]
    hz = values[a + 2] if npar >= 3 else 0.0
    m = math.sqrt(hx * hx + hy * hy + hz * hz)
    if m == 0.0:
        hx, hy, hz, m = 0.0, 1.0, 0.0, 1.0
    hx /= m
    hy /= m
    hz /= m
    ux = 0.0
    uy = 0.0
    uz = 0.0
    um = 0.0
    if npar >= 6:
        ux = values[a + 3]
        uy = values[a + 4]
        uz = values[a + 5]
        d = ux * hx + uy * hy + uz * hz
        ux -= d * hx
        uy -= d * hy
        uz -= d * hz
        um = math.sqrt(ux * ux + uy * uy + uz * uz)
    if um > 1e-9:
        ux /= um
        uy /= um
        uz /= um
        lx = uy * hz - uz * hy  # L = U x H
        ly = uz * hx - ux * hz
        lz = ux * hy - uy * hx
    else:  # the rotation that takes the old H to the new one carries L along
        lx, ly, lz = _transport(
            st[S_L],
            st[S_L + 1],
            st[S_L + 2],
            st[S_H],
            st[S_H + 1],
            st[S_H + 2],
            hx,
            hy,
            hz,
            st[S_U],
            st[S_U + 1],
            st[S_U + 2],
        )
    st[S_H] = hx
    st[S_H + 1] = hy
    st[S_H + 2] = hz
    st[S_L] = lx
    st[S_L + 1] = ly
    st[S_L + 2] = lz
    st[S_U] = hy * lz - hz * ly  # U = H x L
    st[S_U + 1] = hz * lx - hx * lz
    st[S_U + 2] = hx * ly - hy * lx
    st[S_NROT] = 0.0


@njit(cache=True, nogil=True)
def walk(i, stop, st, stack, depth, base, cnt, word, segs, leaves, polys, blocks, tr, sel,
         slot_state, slot_depth, has_par, engine,
         trace, tropism):  # fmt: skip  # pragma: no cover - compiled
    """Interpret modules ``i`` … ``stop - 1`` from state ``st`` at bracket ``depth``.

    ``stack`` holds the states pushed above bracket level ``base``.  Segment slot ``s`` is
    the ordinal of the F/G that draws it, so walkers of disjoint subtrees write disjoint
    rows; a slot that records nothing is marked by ``seg_mod = -1`` and counted as a hole.
    When ``sel`` lists subtrees, the walk stops at each one's ``[``, stores the state there
    in ``slot_state`` and jumps past its ``]`` (the state after a bracket pair is the state
    before it).

    ``has_par`` (the word has parameters), ``engine`` (seed 004's executor), ``trace``
    (record every pose) and ``tropism`` (an elasticity or an ``@`` module may bend the
    turtle) must agree with ``word``, ``tr`` and ``cfg``; :func:`walk_plain` passes them as
    constants, so that numba drops their code from the loop.
    """
    ids, offsets, values, match, ops, oparg, cfg, palette = word
    seg_start, seg_end, seg_rad, seg_col, seg_mat, seg_mod, seg_par, seg_dep, seg_ref = segs
    leaf_pos, leaf_frame, leaf_size, leaf_col, leaf_mat, leaf_mod = leaves
    (tmp_pos, tmp_owner, tmp_implicit, pinfo_first, pinfo_dot, pinfo_col, pinfo_mat,
     pinfo_mod, pstack, poly_v, poly_off, poly_col, poly_mat, poly_mod) = polys  # fmt: skip
    blk_c, blk_s, blk_b, blk_m = blocks
    tr_pos, tr_frame = tr
    n = ids.shape[0]
    blk_cap = blk_c.shape[0]
    nsel = sel.shape[0]
    npal = palette.shape[0]
    reduction = cfg[C_REDUCTION]
    nseed = np.int64(cfg[C_NSEED])
    avar = cfg[C_AVAR]
    clamp = cfg[C_CLAMP] != 0.0
    ns = cnt[K_NS]
    nl = cnt[K_NL]
    ntmp = cnt[K_NTMP]
    npstack = cnt[K_NPSTACK]
    nopened = cnt[K_NOPENED]
    nv = cnt[K_NV]
    npoly = cnt[K_NPOLY]
    nb = cnt[K_NB]
    holes = cnt[K_HOLES]
    salt = cnt[K_SALT]
    k_sel = cnt[K_SEL]
    last_ang = np.nan
    cs = 1.0
    sn = 0.0
    while i < stop:
        sym = ids[uint64(i)]
        op = ops[sym]
        a = 0
        npar = 0
        if has_par:
            a = offsets[uint64(i)]
            npar = offsets[uint64(i + 1)] - a
        delta = 0.0
        if engine:
            delta = (hash01(salt, nseed) - 0.5) * 2.0 * avar
        if op == T.NOP:
            pass
        elif op == T.DRAW or op == T.DRAW_NOREC or op == T.MOVE or op == T.MOVE_NOREC:
            if tropism and cfg[C_NMOV] != 0.0:  # cpfg's tropism: and torque: lines, before
                movement_adjust(st, cfg)
            length = values[a] if npar > 0 else st[S_LEN]
            x0 = st[S_POS]
            y0 = st[S_POS + 1]
            z0 = st[S_POS + 2]
            st[S_POS] += st[S_H] * length
            st[S_POS + 1] += st[S_H + 1] * length
            st[S_POS + 2] += st[S_H + 2] * length
            if op == T.DRAW or op == T.DRAW_NOREC:
                s = uint64(ns)  # unsigned: no negative-index checks on the ~30 stores below
                ns += 1
                if (npstack == 0 or cfg[C_PMODE] != 0.0) and length != 0.0:
                    seg_start[s, 0] = x0
                    seg_start[s, 1] = y0
                    seg_start[s, 2] = z0
                    seg_end[s, 0] = st[S_POS]
                    seg_end[s, 1] = st[S_POS + 1]
                    seg_end[s, 2] = st[S_POS + 2]
                    r0 = st[S_RAD]
                    r1 = r0 * reduction
                    st[S_RAD] = r1
                    seg_rad[s, 0] = r0
                    seg_rad[s, 1] = r1
                    seg_col[s, 0] = st[S_COL]
                    seg_col[s, 1] = st[S_COL + 1]
                    seg_col[s, 2] = st[S_COL + 2]
                    mi = np.int64(st[S_CIDX])  # a division only outside the palette
                    seg_mat[s] = np.int32(mi if mi >= 0 and mi < npal else mi % npal)
                    seg_mod[s] = i
                    p = np.int64(st[S_LAST])
                    seg_par[s] = p
                    seg_dep[s] = depth
                    sg = 1.0 if length > 0.0 else -1.0
                    bx = st[S_H] * sg
                    by = st[S_H + 1] * sg
                    bz = st[S_H + 2] * sg
                    if p >= 0 and bx == st[S_DIR] and by == st[S_DIR + 1] and bz == st[S_DIR + 2]:
                        r0x, r0y, r0z = st[S_REF], st[S_REF + 1], st[S_REF + 2]  # straight on
                    elif p >= 0:  # the parent's direction and reference travel in the state
                        r0x, r0y, r0z = _transport(
                            st[S_REF], st[S_REF + 1], st[S_REF + 2],
                            st[S_DIR], st[S_DIR + 1], st[S_DIR + 2], bx, by, bz,
                            st[S_L], st[S_L + 1], st[S_L + 2],
                        )  # fmt: skip
                    else:
                        r0x, r0y, r0z = st[S_L], st[S_L + 1], st[S_L + 2]
                    seg_ref[s, 0] = r0x
                    seg_ref[s, 1] = r0y
                    seg_ref[s, 2] = r0z
                    st[S_REF] = r0x
                    st[S_REF + 1] = r0y
                    st[S_REF + 2] = r0z
                    st[S_DIR] = bx
                    st[S_DIR + 1] = by
                    st[S_DIR + 2] = bz
                    st[S_LAST] = ns - 1
                else:
                    seg_mod[s] = -1
                    holes += 1
            else:
                st[S_LAST] = -1.0
            if npstack > 0 and (op == T.DRAW or op == T.MOVE):
                tmp_pos[ntmp, 0] = st[S_POS]
                tmp_pos[ntmp, 1] = st[S_POS + 1]
                tmp_pos[ntmp, 2] = st[S_POS + 2]
                tmp_owner[ntmp] = pstack[npstack - 1]
                tmp_implicit[ntmp] = cfg[C_PMODE] == 0.0  # cpfg: kept beside the dots
                ntmp += 1
            if tropism and st[S_ELAST] != 0.0:  # after each step (ABOP §2.3)
                if cfg[C_TMODE] != 0.0:  # cpfg's old tropism (_movements)
                    old_bend(st, cfg[C_TROP], cfg[C_TROP + 1], cfg[C_TROP + 2])
                else:
                    _bend(st, cfg[C_TROP], cfg[C_TROP + 1], cfg[C_TROP + 2])
        elif op >= T.TURN_LEFT and op <= T.TURN_AROUND:
            if op == T.TURN_AROUND:
                ang = 180.0
            else:
                ang = values[a] if npar > 0 else st[S_ROT]
            if ang != last_ang:
                last_ang = ang
                cs = math.cos(math.radians(ang))
                sn = math.sin(math.radians(ang))
            # signed turns: +, &, \ turn by +angle; -, ^, / by -angle
            sg = -1.0 if (op == T.TURN_RIGHT or op == T.PITCH_UP or op == T.ROLL_RIGHT) else 1.0
            if op == T.TURN_LEFT or op == T.TURN_RIGHT or op == T.TURN_AROUND:
                _rotate(st, S_H, S_L, cs, sg * sn)  # about U: H turns toward L
            elif op == T.PITCH_DOWN or op == T.PITCH_UP:
                _rotate(st, S_U, S_H, cs, sg * sn)  # about L: H turns toward -U (down)
            else:
                _rotate(st, S_L, S_U, cs, sg * sn)  # about H: L turns toward U
            # the count of rotations since the frame was last made orthonormal travels in
            # the state, so every path from the root is normalised alike, however it is walked
            st[S_NROT] += 1.0
            if st[S_NROT] >= 64.0:  # rotations keep the frame orthonormal to ~1e-16 each
                _normalize_frame(st)
                st[S_NROT] = 0.0
        elif op == T.LEVEL:
            _level(st)
        elif op == T.PUSH:
            if k_sel < nsel and sel[k_sel, 0] == i:  # a subtree for a parallel walker
                _copy_state(st, slot_state[k_sel])
                slot_depth[k_sel] = depth
                ns = sel[k_sel, 4]
                nl = sel[k_sel, 5]
                i = sel[k_sel, 1] + 1
                k_sel += 1
                continue
            _copy_state(st, stack[depth - base])
            depth += 1
            st[S_OPEN] = i
        elif op == T.POP:
            if depth > base:
                depth -= 1
                _copy_state(stack[depth - base], st)
        elif op == T.CUT:
            if depth == 0:
                break
            j = match[np.int64(st[S_OPEN])]
            if j < 0:
                break
            if trace:
                for jj in range(i, j):
                    for k in range(3):
                        tr_pos[jj, k] = st[S_POS + k]
                        tr_frame[jj, 0, k] = st[S_H + k]
                        tr_frame[jj, 1, k] = st[S_L + k]
                        tr_frame[jj, 2, k] = st[S_U + k]
            i = j
            depth -= 1
            _copy_state(stack[depth - base], st)
        elif op == T.POLY_BEGIN:
            pid = nopened
            nopened += 1
            pstack[npstack] = pid
            npstack += 1
            pinfo_first[pid] = ntmp
            pinfo_col[pid, 0] = st[S_COL]
            pinfo_col[pid, 1] = st[S_COL + 1]
            pinfo_col[pid, 2] = st[S_COL + 2]
            if cfg[C_MAT_POLY] >= 0:
                pinfo_mat[pid] = np.int32(cfg[C_MAT_POLY])
            else:
                pinfo_mat[pid] = np.int32(np.int64(st[S_CIDX]) % npal)
            pinfo_mod[pid] = i
            if cfg[C_PMODE] == 0.0:  # cpfg's { adds no vertex of its own
                tmp_pos[ntmp, 0] = st[S_POS]
                tmp_pos[ntmp, 1] = st[S_POS + 1]
                tmp_pos[ntmp, 2] = st[S_POS + 2]
                tmp_owner[ntmp] = pid
                tmp_implicit[ntmp] = True
                ntmp += 1
        elif op == T.POLY_VERTEX:
            if npstack > 0:
                pid = pstack[npstack - 1]
                pinfo_dot[pid] = True
                tmp_pos[ntmp, 0] = st[S_POS]
                tmp_pos[ntmp, 1] = st[S_POS + 1]
                tmp_pos[ntmp, 2] = st[S_POS + 2]
                tmp_owner[ntmp] = pid
                tmp_implicit[ntmp] = False
                ntmp += 1
        elif op == T.POLY_END:
            if npstack > 0:
                npstack -= 1
                pid = pstack[npstack]
                start = nv
                for t in range(pinfo_first[pid], ntmp):
                    if tmp_owner[t] != pid:
                        continue
                    if pinfo_dot[pid] and tmp_implicit[t]:
                        continue
                    if nv > start:
                        dd = 0.0
                        for k in range(3):
                            dd += (tmp_pos[t, k] - poly_v[nv - 1, k]) ** 2
                        if dd < 1e-20:
                            continue
                    poly_v[nv] = tmp_pos[t]
                    nv += 1
                if nv - start > 1:
                    dd = 0.0
                    for k in range(3):
                        dd += (poly_v[start, k] - poly_v[nv - 1, k]) ** 2
                    if dd < 1e-20:
                        nv -= 1
                if nv - start >= 3:
                    poly_col[npoly] = pinfo_col[pid]
                    poly_mat[npoly] = pinfo_mat[pid]
                    poly_mod[npoly] = pinfo_mod[pid]
                    npoly += 1
                    poly_off[npoly] = nv
                else:
                    nv = start
        elif op == T.WIDTH_ADD:
            if npar > 0:
                st[S_RAD] = values[a] * cfg[C_WSCALE]
            else:
                st[S_RAD] = max(st[S_RAD] + cfg[C_RAD_D], 0.0)
        elif op == T.WIDTH_MUL:
            if npar > 0:
                st[S_RAD] = values[a] * cfg[C_WSCALE]
            elif cfg[C_WMODE] != 0.0:  # cpfg: less the line width increment
                st[S_RAD] = max(st[S_RAD] - cfg[C_RAD_D], 0.0)
            else:
                st[S_RAD] *= cfg[C_RAD_F]
        elif op == T.SUBCALL:  # ?(n, s) of a sub-L-system, or its end ?(0, 1/s): width × s
            if npar >= 2:
                st[S_RAD] *= values[a + 1]
        elif op == T.WIDTH_INC:
            if npar > 0:
                st[S_RAD] = values[a] * cfg[C_WSCALE]
            else:
                st[S_RAD] = max(st[S_RAD] + cfg[C_RAD_D], 0.0)
        elif op == T.COLOR_ADD:
            for k in range(3):
                if npar >= 3:
                    v = values[a + k]
                else:
                    v = st[S_COL + k] + cfg[C_COL_D + k]
                if clamp:
                    v = min(max(v, 0.0), 1.0)
                st[S_COL + k] = v
        elif op == T.COLOR_NEXT or op == T.COLOR_PREV:
            if npar > 0:
                c = values[a]
            elif op == T.COLOR_NEXT:
                c = st[S_CIDX] + 1.0
            else:
                c = st[S_CIDX] - 1.0
            c = max(math.floor(c), 0.0)
            st[S_CIDX] = c
            ci = np.int64(c) % npal
            for k in range(3):
                st[S_COL + k] = palette[ci, k]
        elif op == T.ANGLE_ADD:
            st[S_ROT] = values[a] if npar > 0 else st[S_ROT] + cfg[C_ROT_D]
        elif op == T.LENGTH_ADD:
            st[S_LEN] = values[a] if npar > 0 else st[S_LEN] + cfg[C_LEN_D]
        elif op == T.LEAF or op == T.SURFACE:
            size = cfg[C_LEAF]
            if npar > 0:
                size = values[a]
            elif op == T.SURFACE and i + 1 < n and ops[ids[i + 1]] == T.NOP:
                # cpfg: ~l(s) names a surface; the name's first parameter scales it
                i += 1
                if has_par and offsets[i + 1] > offsets[i]:
                    size = values[offsets[i]]
                if trace:  # the name keeps the pose of the ~ before it
                    for k in range(3):
                        tr_pos[i - 1, k] = st[S_POS + k]
                        tr_frame[i - 1, 0, k] = st[S_H + k]
                        tr_frame[i - 1, 1, k] = st[S_L + k]
                        tr_frame[i - 1, 2, k] = st[S_U + k]
            leaf_pos[nl, 0] = st[S_POS]
            leaf_pos[nl, 1] = st[S_POS + 1]
            leaf_pos[nl, 2] = st[S_POS + 2]
            for k in range(3):
                leaf_frame[nl, 0, k] = st[S_H + k]
                leaf_frame[nl, 1, k] = st[S_L + k]
                leaf_frame[nl, 2, k] = st[S_U + k]
            leaf_size[nl] = size
            if op == T.SURFACE and st[S_CIDX] > 0.0:
                leaf_mat[nl] = np.int32(np.int64(st[S_CIDX]) % npal)
                for k in range(3):
                    leaf_col[nl, k] = st[S_COL + k]
            else:
                leaf_mat[nl] = np.int32(cfg[C_MAT_LEAF])
                leaf_col[nl, 0] = 0.16
                leaf_col[nl, 1] = 0.42
                leaf_col[nl, 2] = 0.10
            leaf_mod[nl] = i
            nl += 1
        elif tropism and op == T.ELASTICITY:  # cpfg's _: the old tropism's elasticity
            if cfg[C_TMODE] != 0.0:
                st[S_ELAST] = values[a] if npar > 0 else st[S_ELAST] + cfg[C_ESTEP]
        elif tropism and op == T.AT:  # cpfg's @: the function is the next module (or two)
            j = i + 1
            code = oparg[ids[j]] if j < n else 0.0
            fa = 0
            fn = 0
            if has_par and j < n:
                fa = offsets[j]
                fn = offsets[j + 1] - fa
            if trace:
                _trace_pose(tr_pos, tr_frame, i, st)
            if code == AT_SPHERE or code == AT_CIRCLE:  # noqa: SIM109 - numba
                if code == AT_CIRCLE:  # @c(r): a radius
                    r = values[fa] if fn > 0 else st[S_RAD]
                else:
                    r = (values[fa] if fn > 0 else 2.0 * st[S_RAD]) * 0.5  # @O(d), @o(d)
                if cfg[C_MAT_POLY] >= 0:
                    mat = np.int32(cfg[C_MAT_POLY])
                else:
                    mat = np.int32(np.int64(st[S_CIDX]) % npal)
                for q in range(SPHERE_NP):
                    for t in range(SPHERE_OFF[q], SPHERE_OFF[q + 1]):
                        for k in range(3):
                            poly_v[nv, k] = st[S_POS + k] + r * SPHERE_V[t, k]
                        nv += 1
                    for k in range(3):
                        poly_col[npoly, k] = st[S_COL + k]
                    poly_mat[npoly] = mat
                    poly_mod[npoly] = i
                    npoly += 1
                    poly_off[npoly] = nv
            elif code == AT_G:  # the letter after @G names the cylinder's function
                if trace:  # the G keeps the pose too
                    _trace_pose(tr_pos, tr_frame, j, st)
                j += 1
            elif code == AT_VERTICAL:
                _level(st)
            elif code == AT_MOVE:
                if fn >= 2:
                    st[S_POS] = values[fa]
                    st[S_POS + 1] = values[fa + 1]
                    st[S_POS + 2] = values[fa + 2] if fn >= 3 else 0.0
                    st[S_LAST] = -1.0  # the next segment does not grow from the last
            elif code == AT_HEADING:
                if fn >= 2:
                    _set_heading(st, values, fa, fn)
            elif code == AT_T:
                j += 1
                sub = oparg[ids[j]] if j < n else 0.0
                if trace:
                    _trace_pose(tr_pos, tr_frame, j - 1, st)
                ka = 0
                kn = 0
                if has_par and j < n:
                    ka = offsets[j]
                    kn = offsets[j + 1] - ka
                slot = S_ELAST
                step = cfg[C_ESTEP]
                if cfg[C_TMODE] != 0.0:  # cpfg: the movement's index, then the value
                    k = np.int64(values[ka]) - 1 if kn > 0 else -1
                    if kn > 0 and k >= 0 and k < cfg[C_NMOV] and values[ka] == k + 1:
                        slot = MOV_SLOTS[k]
                        step = cfg[C_MOV + MOV_W * k + 7]
                    else:  # no index, or one of no tropism: line: nothing (cpfg's message)
                        slot = -1
                    ka += 1
                    kn -= 1
                if slot >= 0:
                    e = st[slot]
                    if sub == AT_TS:
                        e = values[ka] if kn > 0 else 0.0
                    elif sub == AT_TI:
                        e += values[ka] if kn > 0 else step
                    elif sub == AT_TD:
                        e -= values[ka] if kn > 0 else step
                    st[slot] = e
            i = j
        elif engine:
            if op == T.YAW_LEFT:
                st[S_YAW] += (-1.0 + delta) * cfg[C_YAW]
                _engine_frame(st)
            elif op == T.YAW_RIGHT:
                st[S_YAW] += (1.0 + delta) * cfg[C_YAW]
                _engine_frame(st)
            elif op == T.E_PITCH_UP:
                st[S_PITCH] += (1.0 + delta) * cfg[C_PITCH]
                _engine_frame(st)
            elif op == T.E_PITCH_DOWN:
                st[S_PITCH] += (-1.0 + delta) * cfg[C_PITCH]
                _engine_frame(st)
            elif op == T.BLOCK_FORWARD or op == T.BLOCK_UP:
                off = S_H if op == T.BLOCK_FORWARD else S_U
                sc = st[S_SCALE]
                base_scale = cfg[C_BASE]
                x = sc
                first = True
                while first or x <= base_scale * (1.0 + 1e-9):
                    if nb < blk_cap:
                        blk_c[nb, 0] = st[S_POS]
                        blk_c[nb, 1] = st[S_POS + 1]
                        blk_c[nb, 2] = st[S_POS + 2]
                        blk_s[nb] = sc
                        blk_b[nb] = np.int32(st[S_BUF])
                        blk_m[nb] = i
                    nb += 1
                    for k in range(3):
                        st[S_POS + k] += st[off + k] * sc
                    first = False
                    x += sc
                    if sc <= 0.0:
                        break
                st[S_LASTMOVE] = 1.0 if op == T.BLOCK_FORWARD else 2.0
            elif op == T.SHRINK or op == T.GROW or op == T.RESET_SCALE:
                old = st[S_SCALE]
                if op == T.SHRINK:
                    new = old * cfg[C_SHRINK]
                elif op == T.GROW:
                    new = old / cfg[C_SHRINK]
                else:
                    new = cfg[C_BASE]
                if st[S_LASTMOVE] != 0.0:
                    off = S_H if st[S_LASTMOVE] == 1.0 else S_U
                    for k in range(3):
                        st[S_POS + k] -= st[off + k] * (old - new) / 2.0
                st[S_SCALE] = new
            elif op == T.BUFFER:
                st[S_BUF] = oparg[sym]
        if trace:
            for k in range(3):
                tr_pos[i, k] = st[S_POS + k]
                tr_frame[i, 0, k] = st[S_H + k]
                tr_frame[i, 1, k] = st[S_L + k]
                tr_frame[i, 2, k] = st[S_U + k]
        if engine:
            salt = squirrel1d(salt, nseed)
        i += 1
    if trace and i < stop:  # a top-level cut ended the walk: later modules keep the last pose
        for j in range(i, stop):
            for k in range(3):
                tr_pos[j, k] = st[S_POS + k]
                tr_frame[j, 0, k] = st[S_H + k]
                tr_frame[j, 1, k] = st[S_L + k]
                tr_frame[j, 2, k] = st[S_U + k]
    cnt[K_NS] = ns
    cnt[K_NL] = nl
    cnt[K_NTMP] = ntmp
    cnt[K_NPSTACK] = npstack
    cnt[K_NOPENED] = nopened
    cnt[K_NV] = nv
    cnt[K_NPOLY] = npoly
    cnt[K_NB] = nb
    cnt[K_HOLES] = holes
    cnt[K_STOP] = i
    cnt[K_SALT] = salt
    cnt[K_SEL] = k_sel


@njit(cache=True, nogil=True)
def walk_plain(i, stop, st, stack, depth, base, cnt, word, segs, leaves, polys, blocks, tr, sel,
               slot_state, slot_depth):  # fmt: skip  # pragma: no cover - compiled
    """:func:`walk` of a word without parameters, outside seed 004's executor, untraced.

    The flags are literal ``False``: numba prunes their branches, and the loop of a
    bracketed plant runs about 20 % faster than with the flags tested on every module."""
    walk(i, stop, st, stack, depth, base, cnt, word, segs, leaves, polys, blocks, tr, sel,
         slot_state, slot_depth, False, False, False, False)  # fmt: skip


@njit(cache=True)
def _compact(segs, n):  # pragma: no cover - compiled
    """Drop the hole slots (``seg_mod < 0``) of the first ``n`` and renumber the parents."""
    seg_start, seg_end, seg_rad, seg_col, seg_mat, seg_mod, seg_par, seg_dep, seg_ref = segs
    remap = np.empty(n, np.int64)
    j = 0
    for s in range(n):
        if seg_mod[s] < 0:
            remap[s] = -1
            continue
        remap[s] = j
        if j != s:
            seg_start[j] = seg_start[s]
            seg_end[j] = seg_end[s]
            seg_rad[j] = seg_rad[s]
            seg_col[j] = seg_col[s]
            seg_mat[j] = seg_mat[s]
            seg_mod[j] = seg_mod[s]
            seg_dep[j] = seg_dep[s]
            seg_ref[j] = seg_ref[s]
        p = seg_par[s]
        seg_par[j] = remap[p] if p >= 0 else -1
        j += 1
    return j


def segment_arrays(n, empty=np.empty):
    """Room for ``n`` segments: start, end (float64[n, 3]), radii (float32[n, 2]), colour
    (float32[n, 3]), material (int32), module (int64), parent (int64), bracket depth (int32),
    ring reference (float32[n, 3]); ``empty`` makes each array."""
    return (
        empty((n, 3), np.float64), empty((n, 3), np.float64), empty((n, 2), np.float32),
        empty((n, 3), np.float32), empty(n, np.int32), empty(n, np.int64), empty(n, np.int64),
        empty(n, np.int32), empty((n, 3), np.float32),
    )  # fmt: skip


def walk_word(ids, offsets, values, match, ops, oparg, cfg, palette, trace, blk_cap, counts, sel,
              segs):  # fmt: skip
    """Allocate a word's outputs (but its segments, passed in) and the turtle's initial
    state and stack, for :func:`walk` or :func:`walk_plain`.

    See :func:`sylva.turtle.interpret` for the meaning of the outputs.  The interpreter
    walks the word up to the subtrees of ``sel``, then the subtrees (on threads), and
    :func:`finish_word` cuts the arrays.  Plain Python (some thirty allocations, tens of
    microseconds), and the walk is not called from here: compiled, this function took
    seconds to compile on a cold cache, and calling both :func:`walk` and
    :func:`walk_plain` compiled both (each ~10 s) where a word needs one.

    Parameters
    ----------
    ids : int[n]; offsets : int64[n+1] or int64[0]; values : float64[m]
        The word (:class:`~sylva.lsystem.lstring.ModuleString` arrays); empty ``offsets``
        when no module has parameters.
    match : int64[n] or int64[0]
        Matching bracket of each bracket (read by ``%`` only).
    ops : int32[a]; oparg : float64[a]
        Opcode and argument per symbol id.
    cfg : float64[NC]
        Settings (``C_*`` layout).
    palette : float64[p, 3]
        Colour of each colour index (p >= 1).
    trace : bool
        Record the position and frame after every module.
    blk_cap : int
        Room for blocks; the returned block count may exceed it (then nothing past the
        room was written: call again with the count).
    counts : int64[6]; sel : int64[k, 6]
        From :func:`scan_word`.  The subtrees of ``sel`` are walked in parallel after the
        rest of the word (the result is the same as one walk: every path from the root
        meets the same operations in the same order); pass none for one serial walk (the
        only way for polygons, ``%`` and seed 004's salt chain).
    segs : tuple
        Room for ``counts[0]`` segments, as :func:`segment_arrays` lays it out.
    """
    n = ids.shape[0]
    n_leaf, n_pv, n_poly, max_d = (int(c) for c in counts[1:5])
    leaves = (
        np.empty((n_leaf, 3)), np.empty((n_leaf, 3, 3)), np.empty(n_leaf, np.float32),
        np.empty((n_leaf, 3), np.float32), np.empty(n_leaf, np.int32),
        np.empty(n_leaf, np.int64),
    )  # fmt: skip
    poly_off = np.zeros(n_poly + 1, np.int64)
    polys = (
        np.empty((n_pv, 3)), np.empty(n_pv, np.int64), np.empty(n_pv, np.bool_),
        np.empty(n_poly, np.int64), np.zeros(n_poly, np.bool_),
        np.empty((n_poly, 3), np.float32), np.empty(n_poly, np.int32),
        np.empty(n_poly, np.int64), np.empty(n_poly + 1, np.int64), np.empty((n_pv, 3)),
        poly_off, np.empty((n_poly, 3), np.float32), np.empty(n_poly, np.int32),
        np.empty(n_poly, np.int64),
    )  # fmt: skip
    blocks = (
        np.empty((blk_cap, 3)), np.empty(blk_cap, np.float32), np.empty(blk_cap, np.int32),
        np.empty(blk_cap, np.int64),
    )  # fmt: skip
    tr = (np.empty((n if trace else 0, 3)), np.empty((n if trace else 0, 3, 3)))
    word = (ids, offsets, values, match, ops, oparg, cfg, palette)

    # ---------------------------------------------------------------- initial state
    engine = cfg[C_ENGINE] != 0.0
    st = np.zeros(NS)
    st[S_H + 1] = 1.0  # H = +Y (up)
    st[S_L] = -1.0  # L = -X
    st[S_U + 2] = 1.0  # U = +Z
    st[S_LEN] = cfg[C_LEN]
    st[S_ROT] = cfg[C_ROT]
    st[S_RAD] = cfg[C_RAD]
    st[S_COL] = cfg[C_COL]
    st[S_COL + 1] = cfg[C_COL + 1]
    st[S_COL + 2] = cfg[C_COL + 2]
    st[S_CIDX] = cfg[C_CIDX]
    st[S_LAST] = -1.0
    st[S_OPEN] = -1.0
    st[S_SCALE] = cfg[C_BASE]
    if not engine:
        st[S_ELAST] = cfg[C_ELAST]
        for k in range(np.int64(cfg[C_NMOV])):  # cpfg's movements: their initial E:
            st[MOV_SLOTS[k]] = cfg[C_MOV + MOV_W * k + 6]
    if engine:
        st[S_YAW] = -90.0
        st[S_PITCH] = 0.0
        _engine_frame(st)
        st[S_POS + 1] = -(1.0 - cfg[C_BASE]) / 2.0
    stack = np.empty((max_d + 1, NS))
    cnt = np.zeros(NK, np.int64)
    cnt[K_SALT] = np.int64(cfg[C_SALT])
    k = sel.shape[0]
    slot_state = np.empty((k, NS))
    slot_depth = np.empty(k, np.int64)
    return word, segs, leaves, polys, blocks, tr, cnt, slot_state, slot_depth, st, stack


def finish_word(segs, leaves, polys, blocks, tr, cnt, holes):
    """The output tuple of a walked word: holes dropped, arrays cut to their counts (views;
    plain Python, for the reason given in :func:`walk_word`)."""
    ns = int(cnt[K_NS])  # below the F/G count when a cut ended the walk early
    if holes > 0:
        ns = int(_compact(segs, ns))
    nl = int(cnt[K_NL])
    nv = int(cnt[K_NV])
    npoly = int(cnt[K_NPOLY])
    nb = int(cnt[K_NB])
    seg_start, seg_end, seg_rad, seg_col, seg_mat, seg_mod, seg_par, seg_dep, seg_ref = segs
    leaf_pos, leaf_frame, leaf_size, leaf_col, leaf_mat, leaf_mod = leaves
    poly_v = polys[9]
    poly_off = polys[10]
    poly_col, poly_mat, poly_mod = polys[11], polys[12], polys[13]
    blk_c, blk_s, blk_b, blk_m = blocks
    nbw = min(nb, blk_c.shape[0])
    return (
        seg_start[:ns], seg_end[:ns], seg_rad[:ns], seg_col[:ns], seg_mat[:ns], seg_mod[:ns],
        seg_par[:ns], seg_dep[:ns], seg_ref[:ns],
        leaf_pos[:nl], leaf_frame[:nl], leaf_size[:nl], leaf_col[:nl], leaf_mat[:nl],
        leaf_mod[:nl],
        poly_v[:nv], poly_off[: npoly + 1], poly_col[:npoly], poly_mat[:npoly], poly_mod[:npoly],
        blk_c[:nbw], blk_s[:nbw], blk_b[:nbw], blk_m[:nbw], tr[0], tr[1], int(cnt[K_SALT]), nb,
    )  # fmt: skip
