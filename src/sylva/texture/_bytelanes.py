"""Permutation-table lookups 64 at a time, in byte lanes (private; for the float32 roads).

Gradient noise hashes a lattice point by chained lookups in a permutation of 0..255,
``perm[i + perm[j + perm[k]]]``.  With the table doubled (as Perlin's and Gustavson's are)
every index is taken modulo 256, which byte arithmetic does for free: a lookup is a byte
permutation.  AVX-512 VBMI's ``vpermi2b`` permutes 64 bytes out of a 128-byte table in
one instruction, so two of them and a blend by the index's top bit read a 256-entry table
for 64 indices at once: 12 lookups hash the four corners of 64 3D simplices (6 the three
of 2D ones), 12 the eight corners of 64 samples of 3D improved noise, up to 30 the sixteen
of a 4D lattice point, the chain's intermediate bytes staying in registers.  The
intrinsics below emit that (LLVM's ``llvm.x86.avx512.vpermi2var.qi.512``) when the CPU
numba compiles for has VBMI, and 64 scalar loads a lookup otherwise (the same results: the
tests run both where they can); :data:`USE` tells the kernels which road to take on this
machine (the other one loads the tables with scalar loads, simplex one packed word of
corner hashes a sample, :func:`._simplex32.simplex_table`).

Numba caches compiled kernels per CPU name and feature set, so a cache made on a VBMI
machine is never loaded on one without.  Its cache keys on each kernel module's own source
file, not on this one: after editing an intrinsic here, touch the modules that call it
(``_gridkernels32``, ``_simplex32``, ``_points32``), or their cached kernels keep the old
code (a wheel install rewrites every file).

:class:`Wide` is the compiler the float32 kernels are built with: it lets LLVM vectorise
their loops to 512-bit registers on every AVX-512 CPU (LLVM's Intel models prefer 256).
"""

from __future__ import annotations

import os

import llvmlite.binding as llvm
import llvmlite.ir as ir
from numba import types
from numba.core.compiler import Compiler
from numba.extending import intrinsic

#: bytes an intrinsic reads and writes per row (one zmm register)
LANES = 64

_I8 = ir.IntType(8)
_I32 = ir.IntType(32)
_V = ir.VectorType(_I8, LANES)


def _host_has(*features: str) -> bool:
    """Whether the CPU that numba compiles for has ``features``: the host's, or those of
    ``NUMBA_CPU_FEATURES`` where it is set (a cache built for other CPUs, or an AVX2
    build measured on an AVX-512 machine): the intrinsics must not emit instructions that
    the target lacks."""
    env = os.environ.get("NUMBA_CPU_FEATURES")
    if env:
        on = {f[1:] for f in env.split(",") if f.startswith("+")}
        return all(f in on for f in features)
    try:
        feats = llvm.get_host_cpu_features()
    except RuntimeError:  # no feature list from this host
        return False
    return all(feats.get(f) for f in features)


def _host_has_vbmi() -> bool:
    return _host_has("avx512vbmi", "avx512bw")


#: the CPU has AVX-512 VBMI (byte permutes): the byte-lane roads are the fast ones here.
#: ``SYLVA_BYTELANES=0`` / ``1`` chooses the road for a process (both compile everywhere).
VBMI = _host_has_vbmi()
#: AVX-512F (16-lane float permutes, :func:`cell_lerp16`): every VBMI CPU has it
AVX512 = VBMI or _host_has("avx512f")
#: AVX2 (8-lane float permutes, ``vpermps``: :func:`cell_lerp8`)
AVX2 = AVX512 or _host_has("avx2")
_env = os.environ.get("SYLVA_BYTELANES", "")
USE = VBMI if _env not in ("0", "1") else _env == "1"


#: the function attribute that sets LLVM's vector width for one function (clang's
#: ``-mprefer-vector-width``); llvmlite's attribute set takes only enum attributes
_PREFER_512 = '"prefer-vector-width"="512"'


class Wide(Compiler):
    """numba's compiler, but every function it lowers (and the outlined bodies of its
    ``prange`` loops, which inherit the target context) carries the LLVM attribute
    ``"prefer-vector-width"="512"``. LLVM's models of Intel's AVX-512 CPUs (Skylake-SP to
    Sapphire Rapids) prefer 256-bit vectors, a tuning against the clock drop of early
    AVX-512 parts, so the loop vectoriser gave the float32 kernels 8 lanes where they are
    written for 16 (2D simplex, fBm and 3D Worley ran 1.1-1.3x slower on an Intel Xeon VM
    that LLVM takes for ``rocketlake``); AMD's models already prefer 512, and CPUs without
    AVX-512 cap the width at their registers. Per kernel, not numba's process-wide
    ``NUMBA_CPU_FEATURES``: loops of a few iterations (the float64 Worley road's runs of
    four samples a cell) are faster at 256 bits, and the user's own numba code keeps its
    tuning. Use it as ``@njit(pipeline_class=Wide, ...)``; ``SYLVA_VECTOR_WIDTH=256`` leaves
    LLVM's width (for comparison; it takes effect when the kernels compile, not on a warm
    cache)."""

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        if os.environ.get("SYLVA_VECTOR_WIDTH") == "256":
            return
        ctx = self.state.targetctx  # this compile's own copy (numba's subtarget)
        real = ctx.post_lowering

        def post_lowering(mod, library):
            for fn in mod.functions:
                if not fn.is_declaration:
                    set.add(fn.attributes, _PREFER_512)  # past llvmlite's list of names
            real(mod, library)

        ctx.post_lowering = post_lowering


def _load(b, addr):
    return b.load(b.inttoptr(addr, _V.as_pointer()), align=1)


def _lut(b, t, idx):
    """IR: ``tab[idx]`` for 64 byte indices (``t``: the address of the 256-byte table)."""
    if VBMI:
        rows = [_load(b, b.add(t, ir.Constant(t.type, LANES * r))) for r in range(4)]
        fn = b.module.declare_intrinsic(
            "llvm.x86.avx512.vpermi2var.qi.512", fnty=ir.FunctionType(_V, [_V, _V, _V])
        )
        lo = b.call(fn, [rows[0], idx, rows[1]])  # index bit 6 picks the row, 0..5 the byte
        hi = b.call(fn, [rows[2], idx, rows[3]])
        return b.select(b.icmp_signed("<", idx, ir.Constant(_V, None)), hi, lo)  # bit 7
    base = b.inttoptr(t, _I8.as_pointer())
    res = ir.Constant(_V, ir.Undefined)
    for q in range(LANES):
        i = b.zext(b.extract_element(idx, ir.Constant(_I32, q)), ir.IntType(64))
        res = b.insert_element(res, b.load(b.gep(base, [i]), align=1), ir.Constant(_I32, q))
    return res


def _row(b, rows, stride, r):
    return b.add(rows, b.mul(stride, ir.Constant(stride.type, r)))


@intrinsic
def simplex3_hash(typingctx, tab, rows, stride):
    """Gustavson's 3D corner hashes for 64 samples: from byte rows 0..3 at the address
    ``rows`` (``stride`` bytes apart) — the cell's ``i, j, k & 255`` and the code
    ``i1 | j1 << 1 | k1 << 2 | i2 << 3 | j2 << 4 | k2 << 5`` of corners 1 and 2 — the four
    corners' gradient indices ``perm12[i + di + perm[j + dj + perm[k + dk]]]`` into rows
    4..7 (corners 0 .. 3).  ``tab``: the address of perm (256 bytes) then perm12."""
    sig = types.void(types.uintp, types.uintp, types.uintp)

    def codegen(context, b, signature, args):
        t, r0, st = args
        t12 = b.add(t, ir.Constant(t.type, 256))
        vi, vj, vk, code = (_load(b, _row(b, r0, st, r)) for r in range(4))
        one = ir.Constant(_V, [1] * LANES)
        zero = ir.Constant(_V, None)

        def bit(n):
            return b.and_(b.lshr(code, ir.Constant(_V, [n] * LANES)), one)

        offs = [(zero, zero, zero), (bit(0), bit(1), bit(2)), (bit(3), bit(4), bit(5)),
                (one, one, one)]
        for c, (di, dj, dk) in enumerate(offs):
            a = _lut(b, t, b.add(vk, dk))
            h = _lut(b, t, b.add(b.add(vj, dj), a))
            g = _lut(b, t12, b.add(b.add(vi, di), h))
            b.store(g, b.inttoptr(_row(b, r0, st, 4 + c), _V.as_pointer()), align=1)
        return context.get_dummy_value()

    return sig, codegen


@intrinsic
def simplex2_hash(typingctx, tab, rows, stride):
    """Gustavson's 2D corner hashes for 64 samples: from byte rows 0, 1 and 3 at the
    address ``rows`` (``stride`` bytes apart) — the cell's ``i, j & 255`` and 1 where the
    middle corner is (1, 0), 0 where it is (0, 1) — the three corners' gradient indices
    ``perm12[i + di + perm[j + dj]]`` into rows 4..6.  ``tab`` as for
    :func:`simplex3_hash`."""
    sig = types.void(types.uintp, types.uintp, types.uintp)

    def codegen(context, b, signature, args):
        t, r0, st = args
        t12 = b.add(t, ir.Constant(t.type, 256))
        vi, vj, c = (_load(b, _row(b, r0, st, r)) for r in (0, 1, 3))
        one = ir.Constant(_V, [1] * LANES)
        zero = ir.Constant(_V, None)
        offs = [(zero, zero), (c, b.xor(c, one)), (one, one)]
        for k, (di, dj) in enumerate(offs):
            h = _lut(b, t, b.add(vj, dj))
            g = _lut(b, t12, b.add(b.add(vi, di), h))
            b.store(g, b.inttoptr(_row(b, r0, st, 4 + k), _V.as_pointer()), align=1)
        return context.get_dummy_value()

    return sig, codegen


@intrinsic
def lattice3_hash(typingctx, tab, rows, stride, y0, y1, z0, z1):
    """Perlin's 3D corner hashes for 64 samples: from byte rows 0 and 1 at the address
    ``rows`` (``stride`` bytes apart) — each sample's ``perm[x0]`` and ``perm[x1]`` — and
    the row's lattice indices ``y0, y1, z0, z1`` (0..255), the eight corners'
    ``perm[perm[perm[x] + y] + z]`` into rows 2..9 (corner ``c``: x1 if ``c & 1``, y1 if
    ``c & 2``, z1 if ``c & 4``).  ``tab``: the address of perm (256 bytes)."""
    sig = types.void(types.uintp, types.uintp, types.uintp, types.uint64, types.uint64,
                     types.uint64, types.uint64)  # fmt: skip

    def codegen(context, b, signature, args):
        t, r0, st, *yz = args
        a0, a1 = (_load(b, _row(b, r0, st, r)) for r in range(2))
        sy0, sy1, sz0, sz1 = (_splat8(b, v) for v in yz)
        hy = [_lut(b, t, b.add(a, y)) for y in (sy0, sy1) for a in (a0, a1)]
        for c in range(8):
            g = _lut(b, t, b.add(hy[c & 3], sz1 if c & 4 else sz0))
            b.store(g, b.inttoptr(_row(b, r0, st, 2 + c), _V.as_pointer()), align=1)
        return context.get_dummy_value()

    return sig, codegen


@intrinsic
def lattice2_hash(typingctx, tab, rows, stride, y0, y1):
    """Improved noise's 2D corner gradient indices for 64 samples, packed as
    :func:`._gridkernels32._lat_hash` packs them: from byte rows 0 and 1 at ``rows`` (each
    sample's ``perm[x0]``, ``perm[x1]``) and the row's ``y0, y1`` (0..255), the corners'
    ``perm[perm[perm[x] + y]] & 15`` — into row 2 corners (x0, y0) and (x1, y0) in the
    low and high nibble, into row 3 (x0, y1) and (x1, y1).  ``tab``: perm (256 bytes)."""
    sig = types.void(types.uintp, types.uintp, types.uintp, types.uint64, types.uint64)

    def codegen(context, b, signature, args):
        t, r0, st, y0, y1 = args
        a0, a1 = (_load(b, _row(b, r0, st, r)) for r in range(2))
        low = ir.Constant(_V, [15] * LANES)
        four = ir.Constant(_V, [4] * LANES)
        for r, y in enumerate((y0, y1)):
            sy = _splat8(b, y)
            g0, g1 = (b.and_(_lut(b, t, _lut(b, t, b.add(a, sy))), low) for a in (a0, a1))
            word = b.or_(g0, b.shl(g1, four))
            b.store(word, b.inttoptr(_row(b, r0, st, 2 + r), _V.as_pointer()), align=1)
        return context.get_dummy_value()

    return sig, codegen


_F32 = ir.FloatType()
_CONTRACT = ("contract",)


def _cell_lerp_codegen(lanes, permute, name):
    """IR of :func:`cell_lerp16` / :func:`cell_lerp8`: ``lanes`` samples, the cells'
    coefficients by ``permute`` (whether the target has the instruction ``name``) or by
    lane-by-lane extracts (they compile everywhere; the kernels do not call them there)."""
    vf = ir.VectorType(_F32, lanes)
    vi = ir.VectorType(_I32, lanes)

    def codegen(context, b, signature, args):
        c0a, st, pcid, cf, pxf, pxu, pout = args

        def ld(addr, ty):
            return b.load(b.inttoptr(addr, ty.as_pointer()), align=4)

        cfv = b.trunc(cf, _I32)
        vcf = b.shuffle_vector(
            b.insert_element(ir.Constant(vi, ir.Undefined), cfv, ir.Constant(_I32, 0)),
            ir.Constant(vi, ir.Undefined), ir.Constant(vi, [0] * lanes))
        idx = b.sub(ld(pcid, vi), vcf)
        rows = [ld(b.add(c0a, b.mul(st, ir.Constant(st.type, r))), vf) for r in range(4)]
        if permute:
            fn = b.module.declare_intrinsic(name, fnty=ir.FunctionType(vf, [vf, vi]))
            c = [b.call(fn, [row, idx]) for row in rows]
        else:
            c = []
            for row in rows:
                res = ir.Constant(vf, ir.Undefined)
                for q in range(lanes):
                    e = b.extract_element(idx, ir.Constant(_I32, q))
                    res = b.insert_element(res, b.extract_element(row, e), ir.Constant(_I32, q))
                c.append(res)
        x = ld(pxf, vf)
        u = ld(pxu, vf)
        one = ir.Constant(vf, [1.0] * lanes)
        a = b.fadd(b.fmul(c[0], x, flags=_CONTRACT), c[1], flags=_CONTRACT)
        x1 = b.fsub(x, one, flags=_CONTRACT)
        e = b.fadd(b.fmul(c[2], x1, flags=_CONTRACT), c[3], flags=_CONTRACT)
        r = b.fadd(a, b.fmul(u, b.fsub(e, a, flags=_CONTRACT), flags=_CONTRACT),
                   flags=_CONTRACT)
        b.store(r, b.inttoptr(pout, vf.as_pointer()), align=4)
        return context.get_dummy_value()

    return codegen


_CELL_SIG = types.void(types.uintp, types.uintp, types.uintp, types.int64, types.uintp,
                       types.uintp, types.uintp)


@intrinsic
def cell_lerp16(typingctx, cc, stride, cid, cf, xf, xu, out):
    """The cell road's 16 samples at once (:func:`._gridkernels32._cell_eval16`): lane ``q``
    takes cell ``cid[q] - cf`` of the 16 cells whose four coefficient rows start at the
    address ``cc`` (``stride`` bytes apart; ``p0, q0, p1, q1``) by one ``vpermps`` a row
    (AVX-512F) instead of select chains, and writes ``lerp(u, p0 x + q0, p1 (x - 1) +
    q1)`` (``x = xf[q]``, ``u = xu[q]``) to ``out``.  ``cid``, ``xf``, ``xu``, ``out``:
    addresses of 16 int32 / float32; every ``cid[q] - cf`` must lie in 0..15."""
    return _CELL_SIG, _cell_lerp_codegen(16, AVX512, "llvm.x86.avx512.permvar.sf.512")


@intrinsic
def cell_lerp8(typingctx, cc, stride, cid, cf, xf, xu, out):
    """:func:`cell_lerp16` for 8 samples by AVX2's ``vpermps`` (8-lane float permutes):
    every ``cid[q] - cf`` must lie in 0..7 (so it does for any 8 samples of a row, whose
    cell grows by at most one a sample)."""
    return _CELL_SIG, _cell_lerp_codegen(8, AVX2, "llvm.x86.avx2.permps")


def _chain_codegen(order, extra):
    """IR of :func:`lattice_chain2` .. ``4``: the chain over the axes ``order``."""

    def codegen(context, b, signature, args):
        t, r0, st = args
        lo = {a: _load(b, _row(b, r0, st, a)) for a in order}
        hi = {a: _load(b, _row(b, r0, st, 4 + a)) for a in order}
        vals = {0: None}
        for n, a in enumerate(order):  # corner keys: bit a set where axis a takes index 1
            nxt = {}
            for key, v in vals.items():
                for bit, idx in ((0, lo[a]), (1 << a, hi[a])):
                    nxt[key | bit] = _lut(b, t, idx if n == 0 else b.add(v, idx))
            vals = nxt
        for c, v in vals.items():
            if extra:
                v = _lut(b, t, v)
            b.store(v, b.inttoptr(_row(b, r0, st, 8 + c), _V.as_pointer()), align=1)
        return context.get_dummy_value()

    return codegen


def _chain(order, extra, doc):
    @intrinsic
    def chain(typingctx, tab, rows, stride):
        return types.void(types.uintp, types.uintp, types.uintp), _chain_codegen(order, extra)

    chain.__doc__ = doc
    return chain


_CHAIN_DOC = """The lattice corners' hashes of 64 points, the float64 road's chain ({}): from
byte rows ``a`` (index 0) and ``4 + a`` (index 1) of axis ``a`` (x = 0 .. w = 3) at
``rows`` (``stride`` bytes apart) into rows ``8 + c`` (corner ``c``: bit ``a`` set where
axis ``a`` takes index 1).  ``tab``: perm (256 bytes)."""
lattice_chain2 = _chain((0, 1), False, _CHAIN_DOC.format("perm[perm[x] + y]"))
lattice_chain2i = _chain((0, 1), True, _CHAIN_DOC.format(
    "perm[perm[perm[x] + y]], 2D improved noise's z = 0"))
lattice_chain3 = _chain((0, 1, 2), False, _CHAIN_DOC.format("perm[perm[perm[x] + y] + z]"))
lattice_chain4 = _chain((3, 0, 1, 2), False, _CHAIN_DOC.format(
    "perm[perm[perm[perm[w] + x] + y] + z]"))


def _simplex_chain_codegen(nd):
    def codegen(context, b, signature, args):
        t, r0, st = args
        t12 = b.add(t, ir.Constant(t.type, 256))
        mask = ir.Constant(_V, [31] * LANES)
        for c in range(nd + 1):
            idx = [_load(b, _row(b, r0, st, 4 * c + a)) for a in range(nd)]
            h = _lut(b, t, idx[-1])
            for a in range(nd - 2, 0, -1):
                h = _lut(b, t, b.add(idx[a], h))
            if nd == 4:  # Gustavson's 4D: perm[...] & 31
                h = b.and_(_lut(b, t, b.add(idx[0], h)), mask)
            else:
                h = _lut(b, t12, b.add(idx[0], h))
            b.store(h, b.inttoptr(_row(b, r0, st, 20 + c), _V.as_pointer()), align=1)
        return context.get_dummy_value()

    return codegen


def _simplex_chain(nd, doc):
    @intrinsic
    def chain(typingctx, tab, rows, stride):
        return types.void(types.uintp, types.uintp, types.uintp), _simplex_chain_codegen(nd)

    chain.__doc__ = doc
    return chain


_SCHAIN_DOC = """Gustavson's {nd}D corner gradient indices of 64 points ({f}): corner ``c``'s
lattice indices ``i, j, ...`` (& 255) in byte rows ``4 c ..`` at ``rows`` (``stride``
bytes apart), its index into row ``20 + c`` (corners 0 .. {nd}).  ``tab``: perm then
perm12 (256 bytes each)."""
simplex_chain2 = _simplex_chain(2, _SCHAIN_DOC.format(nd=2, f="perm12[i + perm[j]]"))
simplex_chain3 = _simplex_chain(3, _SCHAIN_DOC.format(nd=3, f="perm12[i + perm[j + perm[k]]]"))
simplex_chain4 = _simplex_chain(4, _SCHAIN_DOC.format(
    nd=4, f="perm[i + perm[j + perm[k + perm[l]]]] & 31"))


def _splat8(b, v):
    x = b.trunc(v, _I8)
    vec = b.insert_element(ir.Constant(_V, ir.Undefined), x, ir.Constant(_I32, 0))
    return b.shuffle_vector(vec, ir.Constant(_V, ir.Undefined),
                            ir.Constant(ir.VectorType(_I32, LANES), [0] * LANES))


# -- bit helpers for float32 lanes ---------------------------------------------------------
# Scalar intrinsics that LLVM's loop vectoriser widens to one instruction a lane vector:
# numba has no bit casts between float32 and int32, and it types int32 shifts as int64
# (half the lanes), so a sign flip cost a negation and a select, a variable shift a
# select chain.


def _i32_binop(op):
    def binop(typingctx, a, n):
        sig = types.int32(types.int32, types.int32)

        def codegen(context, b, signature, args):
            return op(b, args[0], b.and_(args[1], ir.Constant(_I32, 31)))

        return sig, codegen

    return binop


_F32 = ir.FloatType()

#: ``a >> n`` (logical, int32, n taken mod 32): ``vpsrlvd`` / ``vpsrld``
srl32 = intrinsic(_i32_binop(lambda b, a, n: b.lshr(a, n)))
#: ``a >> n`` (arithmetic, int32, n mod 32)
sar32 = intrinsic(_i32_binop(lambda b, a, n: b.ashr(a, n)))
#: ``a << n`` (int32, n mod 32)
shl32 = intrinsic(_i32_binop(lambda b, a, n: b.shl(a, n)))


@intrinsic
def xorf(typingctx, x, bits):
    """float32 ``x`` with its bits xor ``bits``: ``-x`` where ``bits`` is the sign bit,
    ``x`` where 0 (one ``vxorps``)."""
    sig = types.float32(types.float32, types.int32)

    def codegen(context, b, signature, args):
        return b.bitcast(b.xor(b.bitcast(args[0], _I32), args[1]), _F32)

    return sig, codegen


@intrinsic
def andf(typingctx, x, mask):
    """float32 ``x`` where ``mask`` is -1, 0.0 where 0 (one ``vandps``)."""
    sig = types.float32(types.float32, types.int32)

    def codegen(context, b, signature, args):
        return b.bitcast(b.and_(b.bitcast(args[0], _I32), args[1]), _F32)

    return sig, codegen


@intrinsic
def signm(typingctx, x):
    """-1 where float32 ``x`` has its sign bit set (negative numbers and ``-0.0``), else 0
    (int32; one ``vpsrad``)."""
    sig = types.int32(types.float32)

    def codegen(context, b, signature, args):
        return b.ashr(b.bitcast(args[0], _I32), ir.Constant(_I32, 31))

    return sig, codegen
