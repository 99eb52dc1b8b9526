"""Vector code for the tube fill: whole rings and runs of triangle indices at once.

Written as scalar numba loops, a ring costs per vertex eight float64 → float32 conversions
and eight scalar stores, and LLVM does not vectorise it (the stores interleave x, y, z).
Here a block of up to :data:`LANES` ring vertices is computed in float32 vector registers,
its coordinates interleaved by shuffles and written with masked stores (with AVX-512, eight
for the positions, normals and texture coordinates of 16 vertices), so a ring of 9 vertices
is one block.  Index runs (a tube's mantle, its caps) are ``base + offset`` from per-``d``
patterns, 16 at once.

The intrinsics below emit LLVM vector IR through numba's :func:`~numba.extending.intrinsic`;
LLVM lowers it for the CPU it compiles on (AVX-512 masked stores, AVX2 masked moves, or
scalar code).  A masked store touches no memory outside its mask, so a block never writes
past the vertices it owns.
"""

from __future__ import annotations

import math

import llvmlite.ir as ir
import numpy as np
from numba import njit, types, uint64
from numba.core import cgutils
from numba.extending import intrinsic

LANES = 16
"""Vertices (or indices) per vector block."""

_F32 = ir.FloatType()
_I32 = ir.IntType(32)
_I1 = ir.IntType(1)
_CONTRACT = ("contract",)  # multiply-adds may fuse


def _splat(b, x, n):
    vt = ir.VectorType(x.type, n)
    v = b.insert_element(ir.Constant(vt, ir.Undefined), x, ir.Constant(_I32, 0))
    zeros = ir.Constant(ir.VectorType(_I32, n), [0] * n)
    return b.shuffle_vector(v, ir.Constant(vt, ir.Undefined), zeros)


def _masked_store(b, vec, addr, count):
    """Store the first ``count`` elements of ``vec`` at the integer address ``addr``."""
    n = vec.type.count
    kind = "f32" if vec.type.element == _F32 else "i32"
    mty = ir.VectorType(_I1, n)
    fnty = ir.FunctionType(ir.VoidType(), [vec.type, vec.type.as_pointer(), _I32, mty])
    fn = cgutils.get_or_insert_function(b.module, fnty, f"llvm.masked.store.v{n}{kind}.p0")
    lane = ir.Constant(ir.VectorType(_I32, n), list(range(n)))
    mask = b.icmp_unsigned("<", lane, _splat(b, b.trunc(count, _I32), n))
    b.call(fn, [vec, b.inttoptr(addr, vec.type.as_pointer()), ir.Constant(_I32, 4), mask])


def _interleave(b, vecs):
    """``[a0 b0 (c0) a1 b1 (c1) …]`` of two or three vectors of LANES elements."""
    n = LANES
    if len(vecs) == 2:
        m = [j // 2 + (j % 2) * n for j in range(2 * n)]
        return b.shuffle_vector(vecs[0], vecs[1], ir.Constant(ir.VectorType(_I32, 2 * n), m))
    ab = b.shuffle_vector(
        vecs[0], vecs[1], ir.Constant(ir.VectorType(_I32, 2 * n), list(range(2 * n)))
    )
    cc = b.shuffle_vector(
        vecs[2],
        ir.Constant(vecs[2].type, ir.Undefined),
        ir.Constant(ir.VectorType(_I32, 2 * n), list(range(n)) + [0] * n),
    )
    m = []
    for j in range(3 * n):
        lane, comp = divmod(j, 3)
        m.append(lane + comp * n if comp < 2 else 2 * n + lane)
    return b.shuffle_vector(ab, cc, ir.Constant(ir.VectorType(_I32, 3 * n), m))


@intrinsic
def ring_block(typingctx, v_addr, n_addr, uv_addr, lanes, bases, tv, table):
    """Write ``lanes`` (1 … LANES) ring vertices: positions and normals (float32 xyz at
    ``v_addr`` and ``n_addr``) and texture coordinates (float32 uv at ``uv_addr``).

    ``bases`` are the 20 floats of :func:`sylva.geometry._kernels._end_basis`: vertex j is
    ``centre + cos_j·P + sin_j·Q``, its normal ``(G + cos_j·A + sin_j·B)·k_j`` with
    ``k_j = 1/sqrt(1 - (cos_j·alpha + sin_j·beta)²)``; its texture coordinates are
    ``(u_j, tv)``.  ``table`` is the address of the block's float32[3, LANES] rows of
    cos_j, sin_j and u_j (:func:`ring_table`)."""
    if not (isinstance(bases, types.UniTuple) and bases.count == 20):
        return None  # a typing error: the bases are 20 floats
    sig = types.void(
        types.uintp, types.uintp, types.uintp, types.int64, bases, types.float64, types.uintp
    )

    def codegen(context, b, signature, args):
        va, na, ua, count, bs, v, tab = args
        vt = ir.VectorType(_F32, LANES)

        def row(k):
            a = b.add(tab, ir.Constant(tab.type, 4 * LANES * k))
            return b.load(b.inttoptr(a, vt.as_pointer()), align=4)

        cs, sn, uu = row(0), row(1), row(2)
        f = [_splat(b, b.fptrunc(b.extract_value(bs, k), _F32), LANES) for k in range(20)]
        cx, cy, cz, px, py, pz, qx, qy, qz, ax, ay, az, bx, by, bz, gx, gy, gz, al, be = f

        def comb(c0, p, q):
            cp = b.fmul(cs, p, flags=_CONTRACT)
            sq = b.fmul(sn, q, flags=_CONTRACT)
            return b.fadd(b.fadd(c0, cp, flags=_CONTRACT), sq, flags=_CONTRACT)

        one = ir.Constant(vt, [1.0] * LANES)
        w = b.fadd(b.fmul(cs, al, flags=_CONTRACT), b.fmul(sn, be, flags=_CONTRACT),
                   flags=_CONTRACT)  # fmt: skip
        sqrt = cgutils.get_or_insert_function(
            b.module, ir.FunctionType(vt, [vt]), f"llvm.sqrt.v{LANES}f32"
        )
        k = b.fdiv(one, b.call(sqrt, [b.fsub(one, b.fmul(w, w, flags=_CONTRACT),
                                             flags=_CONTRACT)]))  # fmt: skip
        xyz = [comb(cx, px, qx), comb(cy, py, qy), comb(cz, pz, qz)]
        nrm = [b.fmul(comb(gx, ax, bx), k), b.fmul(comb(gy, ay, by), k),
               b.fmul(comb(gz, az, bz), k)]  # fmt: skip
        three = b.mul(count, ir.Constant(count.type, 3))
        _masked_store(b, _interleave(b, xyz), va, three)
        _masked_store(b, _interleave(b, nrm), na, three)
        tv32 = _splat(b, b.fptrunc(v, _F32), LANES)
        _masked_store(b, _interleave(b, [uu, tv32]), ua, b.mul(count, ir.Constant(count.type, 2)))
        return context.get_dummy_value()

    return sig, codegen


@intrinsic
def index_block(typingctx, i_addr, count, a, e, pattern):
    """Write ``count`` (1 … LANES) uint32 indices at ``i_addr``: index m is
    ``(a if sel_m else e) + off_m`` from the pattern at address ``pattern`` (uint32[2,
    LANES]: sel, off; :func:`index_patterns`)."""
    sig = types.void(types.uintp, types.int64, types.uint64, types.uint64, types.uintp)

    def codegen(context, b, signature, args):
        ia, n, av, ev, pat = args
        vt = ir.VectorType(_I32, LANES)
        sel = b.load(b.inttoptr(pat, vt.as_pointer()), align=4)
        off_addr = b.add(pat, ir.Constant(pat.type, 4 * LANES))
        off = b.load(b.inttoptr(off_addr, vt.as_pointer()), align=4)
        pick = b.icmp_unsigned("!=", sel, ir.Constant(vt, [0] * LANES))
        base = b.select(pick, _splat(b, b.trunc(av, _I32), LANES),
                        _splat(b, b.trunc(ev, _I32), LANES))  # fmt: skip
        _masked_store(b, b.add(base, off), ia, n)
        return context.get_dummy_value()

    return sig, codegen


@njit(cache=True)
def ring_table(d):  # pragma: no cover - compiled
    """float32[blocks, 3, LANES]: cos, sin and u of the d + 1 vertices of a ring (the last
    one closes the seam: cos 1, sin 0, u 1), zero past them."""
    r = d + 1
    t = np.zeros(((r + LANES - 1) // LANES, 3, LANES), np.float32)
    for j in range(r):
        k, lane = j // LANES, j % LANES
        if j < d:
            t[k, 0, lane] = math.cos(2.0 * math.pi * j / d)
            t[k, 1, lane] = math.sin(2.0 * math.pi * j / d)
        else:
            t[k, 0, lane] = 1.0
        t[k, 2, lane] = j / d
    return t


@njit(cache=True)
def _pattern(sel, off):  # pragma: no cover - compiled
    n = sel.shape[0]
    p = np.zeros(((n + LANES - 1) // LANES, 2, LANES), np.uint32)
    for m in range(n):
        p[m // LANES, 0, m % LANES] = sel[m]
        p[m // LANES, 1, m % LANES] = off[m]
    return p


@njit(cache=True)
def index_patterns(d):  # pragma: no cover - compiled
    """The index patterns of a tube at ``d`` sides, for :func:`index_block`:

    * mantle (a = the ring below, e = the ring above): ``(a+j, a+j+1, e+j+1),
      (a+j, e+j+1, e+j)`` for j < d;
    * start cap (a = e = its ring, whose centre follows it): ``(a+d+1, a+j+1, a+j)``;
    * end cap (a = e = its ring): ``(e+d+1, e+j, e+j+1)``."""
    r = d + 1
    ms = np.empty(6 * d, np.uint32)
    mo = np.empty(6 * d, np.uint32)
    cs = np.ones(3 * d, np.uint32)
    so = np.empty(3 * d, np.uint32)
    eo = np.empty(3 * d, np.uint32)
    for j in range(d):
        for k in range(6):
            ms[6 * j + k] = 1 if k == 0 or k == 1 or k == 3 else 0
        mo[6 * j] = j
        mo[6 * j + 1] = j + 1
        mo[6 * j + 2] = j + 1
        mo[6 * j + 3] = j
        mo[6 * j + 4] = j + 1
        mo[6 * j + 5] = j
        so[3 * j] = r
        so[3 * j + 1] = j + 1
        so[3 * j + 2] = j
        eo[3 * j] = r
        eo[3 * j + 1] = j
        eo[3 * j + 2] = j + 1
    return _pattern(ms, mo), _pattern(cs, so), _pattern(cs, eo)


@njit(cache=True)
def write_ring(e, bases, tv, r, table, V, N, UV):  # pragma: no cover - compiled
    """Ring vertices ``e`` … ``e + r - 1`` of the C-contiguous float32 arrays V, N (n×3) and
    UV (n×2): the blocks write through raw addresses, rows of 12 and 8 bytes."""
    for k in range(table.shape[0]):
        j = e + uint64(k * LANES)
        ring_block(
            V.ctypes.data + j * uint64(12), N.ctypes.data + j * uint64(12),
            UV.ctypes.data + j * uint64(8), min(LANES, r - k * LANES), bases, tv,
            table.ctypes.data + uint64(k * 12 * LANES),
        )  # fmt: skip


@njit(cache=True)
def write_indices(t, n, a, e, pattern, I):  # pragma: no cover - compiled
    """``n`` indices from triangle ``t`` of the C-contiguous uint32 array I (m×3), from
    ``pattern``."""
    for k in range(pattern.shape[0]):
        index_block(
            I.ctypes.data + (t * uint64(3) + uint64(k * LANES)) * uint64(4),
            min(LANES, n - k * LANES), a, e, pattern.ctypes.data + uint64(k * 8 * LANES),
        )  # fmt: skip


# ------------------------------------------------- stand-ins for the interpreted road
def _py_write_ring(e, bases, tv, r, table, V, N, UV):
    """:func:`write_ring` in NumPy, for :func:`sylva._jit.interpreted` (the intrinsics do
    not run as Python): the same float32 formulas, without the fused multiply-adds, so
    equal to the compiled ring within a float32 rounding."""
    e, r = int(e), int(r)
    rows = table.transpose(1, 0, 2).reshape(3, -1)[:, :r]
    cs, sn, uu = rows[0][:, None], rows[1][:, None], rows[2]
    f = np.asarray(bases, np.float64).astype(np.float32)
    c, p, q, a, b, g = f[0:3], f[3:6], f[6:9], f[9:12], f[12:15], f[15:18]
    V[e : e + r] = c + cs * p + sn * q
    w = cs[:, 0] * f[18] + sn[:, 0] * f[19]
    k = np.float32(1.0) / np.sqrt(np.float32(1.0) - w * w)
    N[e : e + r] = (g + cs * a + sn * b) * k[:, None]
    UV[e : e + r, 0] = uu
    UV[e : e + r, 1] = np.float32(tv)


def _py_write_indices(t, n, a, e, pattern, I):
    """:func:`write_indices` in NumPy, for :func:`sylva._jit.interpreted`."""
    t, n = int(t), int(n)
    sel = pattern[:, 0, :].reshape(-1)[:n]
    off = pattern[:, 1, :].reshape(-1)[:n]
    base = np.where(sel != 0, np.uint32(int(a) & 0xFFFFFFFF), np.uint32(int(e) & 0xFFFFFFFF))
    I.reshape(-1)[3 * t : 3 * t + n] = base + off


#: What :func:`sylva._jit.interpreted` runs instead of the kernels built on intrinsics.
_INTERPRETED = {"write_ring": "_py_write_ring", "write_indices": "_py_write_indices"}
