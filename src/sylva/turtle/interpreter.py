"""Turn a derived word into geometry records with the 3D turtle.

The turtle keeps a position and an orthonormal frame of unit vectors H (heading), L (left)
and U (up) with ``H × L = U`` (ABOP §1.5).  It starts at the origin with H = +Y, L = −X and
U = +Z, so a planar system is drawn in the XY plane as ABOP's figures are, and "up" is
glTF's +Y.  Every rotation is the right-handed rotation of the frame about one of its own
axes, which gives the signs ABOP's text states: ``+`` turns left about U (H toward L),
``&`` pitches down about L (H toward −U), ``\\`` rolls about H (L toward U, as ABOP's
matrix R_H(δ) does).  (Read literally, with ``[H' L' U'] = [H L U]·R``, ABOP's printed R_U and
R_L turn the other way; the text and every figure in the book agree with the signs here.)

Seed 004's engine turtle keeps yaw and pitch instead and rebuilds Front, Right and Up from
them after every turn (no roll, ``WORLD_UP = +Y``, start yaw −90°).  Its H, L, U are Front,
−Right and Up.

Examples
--------
>>> from sylva.lsystem.lstring import ModuleString
>>> g = interpret(ModuleString.from_text("F+F+F+F"), dialect="abop", rot=90)
>>> g.n_segments, (g.seg_end[-1].round(12) + 0.0).tolist()
(4, [0.0, 0.0, 0.0])
>>> t = trace(ModuleString.from_text("+(90)F"), dialect="abop")
>>> t.positions[-1].round(12).tolist(), t.frames[0, 0].round(12).tolist()
([-1.0, 0.0, 0.0], [-1.0, 0.0, 0.0])
"""

from __future__ import annotations

import math
import threading
import warnings
from collections.abc import Mapping
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass

import numba
import numpy as np

from .. import _jit
from ..errors import SylvaError, SylvaWarning
from ..geometry.buffers import empty
from ..geometry.colormaps import (
    palette_materials,
    read_colormap,
    read_materials,
    srgb_to_linear,
)
from ..geometry.mesh import Material
from ..geometry.records import Geometry
from ..lsystem.ast import Program
from ..lsystem.lstring import ModuleString
from . import _gcylinder, _surfaces
from . import _movements as M
from . import tables as T
from ._subscale import scale_word
from .tables import ARGS, DEFAULTS, PALETTE, TABLES, compile_table

__all__ = ["DIALECTS", "Trace", "TurtleSettingsError", "interpret", "trace"]

DIALECTS = tuple(TABLES)

#: The kernels; while they are not compiled, words of at most :data:`SMALL` modules run
#: their Python source instead (:func:`sylva._jit.road`: about 20 µs a module against some
#: 14 s of compiling; tests compare the two roads on every built-in example).
K = _jit.road("sylva.turtle._kernels", ("sylva.turtle._state",))
SMALL = 100_000

#: Words of at least this many modules are walked by as many threads as numba uses, one
#: subtree at a time (the result does not depend on it: tests compare both walks).
PARALLEL_MIN = 20_000
#: The smallest bracket pair handed to a thread of its own.
SUBTREE_MIN = 256

_BUFFER_COLORS = (
    (0.40, 0.26, 0.13),  # 0 trunk and branches
    (0.20, 0.50, 0.15),  # 1 leaves
    (0.85, 0.55, 0.15),
    (0.60, 0.60, 0.60),
    (0.90, 0.85, 0.30),
)

#: ABOP §2.3 tropism: the vector T, the initial elasticity e and the step of @Ti / @Td.
_TROPISM = ("tropism", "elasticity", "elasticity_step")
#: The tropism vector when a program sets an elasticity but no vector: gravity (ABOP's
#: figures use T = (0, -1, 0); +Y is up).
GRAVITY = (0.0, -1.0, 0.0)

# Setting names each dialect understands (besides its DEFAULTS).
_EXTRA = {
    "lsys": {"ignore", "axiom", "turtle", *_TROPISM},
    "abop": {"palette", "color", "bg", "turtle", "angle", "delta", "width", "width_step",
             *_TROPISM, "tropisms", "surfaces", "colormap", "materials", "background_scene",
             "textures"},
    "classic": {"angle", "thickness", "radius", "turtle", "iteration"},
    "engine": {"turtle", "seed", "noise_seed", "salt"},
}


class TurtleSettingsError(SylvaError, ValueError):
    """A turtle setting that is unknown for the dialect or has an impossible value."""


@dataclass(frozen=True)
class Trace:
    """The pose of the turtle after every module.

    Attributes
    ----------
    positions : float64[n, 3]
        Position after module ``i``.
    frames : float64[n, 3, 3]
        Rows H, L, U after module ``i``.
    """

    positions: np.ndarray
    frames: np.ndarray


def _num(settings: Mapping, key: str) -> float:
    v = settings[key]
    try:
        return float(v)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        raise TurtleSettingsError(f"setting {key!r} must be a number, got {v!r}") from None


def _rgb(settings: Mapping, key: str) -> tuple[float, float, float]:
    v = settings[key]
    try:
        t = tuple(float(x) for x in v)  # type: ignore[union-attr]
    except (TypeError, ValueError):
        raise TurtleSettingsError(
            f"setting {key!r} must be 3 numbers (r, g, b), got {v!r}"
        ) from None
    if len(t) != 3:
        raise TurtleSettingsError(f"setting {key!r} must be 3 numbers (r, g, b), got {v!r}")
    return t  # type: ignore[return-value]


def _clamp01(c):
    return tuple(min(max(float(x), 0.0), 1.0) for x in c)


def _as_word(word, program: Program | None) -> ModuleString:
    if isinstance(word, ModuleString):
        return word
    if isinstance(word, str):
        return ModuleString.from_text(word)
    raise TypeError(f"expected a ModuleString or text, got {type(word).__name__}")


def _settings(program: Program | None, dialect: str | None, overrides: Mapping) -> tuple:
    if dialect is None:
        dialect = program.turtle if program is not None else "lsys"
    if dialect not in TABLES:
        raise TurtleSettingsError(
            f"unknown turtle dialect {dialect!r}: expected one of {', '.join(DIALECTS)}"
        )
    allowed = set(DEFAULTS[dialect]) | _EXTRA[dialect]
    if dialect == "lsys":
        allowed |= {"detail", "bg"}
    for key in overrides:
        if key not in allowed:
            raise TurtleSettingsError(
                f"unknown setting {key!r} for the {dialect!r} turtle: expected one of "
                + ", ".join(sorted(allowed))
            )
    s = dict(DEFAULTS[dialect])
    if program is not None:
        s.update({k: v for k, v in program.settings.items() if v is not None})
    s.update({k: v for k, v in overrides.items() if v is not None})
    return dialect, s


def _configure(dialect: str, s: dict, seed: int | None):
    cfg = np.zeros(K.NC)
    palette = np.array(PALETTE, np.float64)
    materials: list[Material]
    vertex_colors = False
    cfg[K.C_REDUCTION] = 1.0
    cfg[K.C_WSCALE] = 0.5
    cfg[K.C_RAD_F] = 1.0
    cfg[K.C_BASE] = 1.0
    cfg[K.C_MAT_POLY] = 0
    bg = None
    if dialect in ("lsys", "abop", "classic"):
        cfg[K.C_LEN] = _num(s, "len")
        rot_key = "rot"
        for alias in ("angle", "delta"):
            if alias in s and "rot" not in s:
                rot_key = alias
        if dialect == "classic" and "angle" in s:
            rot_key = "angle"
        cfg[K.C_ROT] = _num(s, rot_key) if rot_key in s else 90.0
    if dialect == "lsys":
        cfg[K.C_RAD] = _num(s, "thick") / 2.0
        cfg[K.C_RAD_D] = _num(s, "thick_delta") / 2.0
        cfg[K.C_LEN_D] = _num(s, "len_delta")
        cfg[K.C_ROT_D] = _num(s, "rot_delta")
        cfg[K.C_COL : K.C_COL + 3] = _clamp01(_rgb(s, "color"))
        cfg[K.C_COL_D : K.C_COL_D + 3] = _rgb(s, "color_delta")
        cfg[K.C_CLAMP] = 1.0
        cfg[K.C_MAT_LEAF] = 1
        cfg[K.C_MAT_POLY] = 2
        vertex_colors = True
        materials = [
            Material("lsys_stem", (1.0, 1.0, 1.0, 1.0), texture="bark"),
            Material("leaf", (1.0, 1.0, 1.0, 1.0), texture="leaf"),
            Material("lsys_polygon", (1.0, 1.0, 1.0, 1.0), roughness=0.6),
        ]
        bg = _clamp01(_rgb(s, "bg"))
    elif dialect == "abop":
        table = None
        if "palette" in s:
            palette = np.asarray(s["palette"], np.float64).reshape(-1, 3)
            if palette.shape[0] == 0:
                raise TurtleSettingsError("the palette needs at least one colour")
        elif s.get("materials") is not None:  # cpfg -M file.mat
            entries = read_materials(s["materials"])
            palette, table = palette_materials(entries)
            # cpfg clears its window to the emissive colour of material 0
            bg = tuple(float(c) for c in srgb_to_linear(entries[0].emissive))
        elif s.get("colormap") is not None:  # cpfg -m file.map
            palette = read_colormap(s["colormap"])
            bg = tuple(float(c) for c in palette[0])  # cpfg clears its window to entry 0
        width = s.get("width", s["thick"])
        cfg[K.C_RAD] = float(width) / 2.0  # type: ignore[arg-type]
        cfg[K.C_RAD_F] = _num(s, "thick_factor")
        if "width_step" in s:  # cpfg's line width increment: ! and # step by it
            cfg[K.C_WMODE] = 1.0
            cfg[K.C_RAD_D] = _num(s, "width_step") / 2.0
        cidx = int(_num(s, "color_index"))
        if cidx < 0:
            raise TurtleSettingsError(f"color_index must be >= 0, got {cidx}")
        cfg[K.C_CIDX] = cidx
        cfg[K.C_COL : K.C_COL + 3] = palette[cidx % palette.shape[0]]
        cfg[K.C_LEAF] = _num(s, "leaf_size")
        cfg[K.C_MAT_LEAF] = palette.shape[0]
        cfg[K.C_MAT_POLY] = -1  # polygons take the current colour index
        materials = table or [
            Material(f"color_{i}", (*map(float, c), 1.0), texture="bark" if i == 0 else None)
            for i, c in enumerate(palette)
        ]
        materials.append(Material("leaf", (0.16, 0.42, 0.10, 1.0), texture="leaf"))
        if "bg" in s:
            bg = _clamp01(_rgb(s, "bg"))
    elif dialect == "classic":
        red = _num(s, "reduction")
        if not red >= 0.0:
            raise TurtleSettingsError(f"reduction must be >= 0, got {red}")
        cfg[K.C_REDUCTION] = red
        if "radius" in s:
            cfg[K.C_RAD] = _num(s, "radius")
        elif "thickness" in s:  # a diameter relative to the segment length (Table 3.1)
            cfg[K.C_RAD] = _num(s, "thickness") * cfg[K.C_LEN] / 2.0
        else:
            cfg[K.C_RAD] = 0.1
        cfg[K.C_LEAF] = _num(s, "leaf_size")
        cfg[K.C_MAT_LEAF] = 1
        cfg[K.C_MAT_POLY] = 0
        cfg[K.C_COL : K.C_COL + 3] = (0.40, 0.26, 0.13)
        materials = [
            Material("bark", (0.40, 0.26, 0.13, 1.0), texture="bark"),
            Material("leaf", (0.16, 0.42, 0.10, 1.0), texture="leaf"),
        ]
    else:  # engine
        cfg[K.C_ENGINE] = 1.0
        cfg[K.C_YAW] = _num(s, "yaw")
        cfg[K.C_PITCH] = _num(s, "pitch")
        cfg[K.C_SHRINK] = _num(s, "shrink")
        if cfg[K.C_SHRINK] <= 0:
            raise TurtleSettingsError(f"shrink must be > 0, got {cfg[K.C_SHRINK]}")
        cfg[K.C_BASE] = _num(s, "scale")
        if cfg[K.C_BASE] <= 0:
            raise TurtleSettingsError(f"scale must be > 0, got {cfg[K.C_BASE]}")
        cfg[K.C_AVAR] = _num(s, "angle_var")
        salt = seed if seed is not None else s.get("salt", s.get("seed", 0))
        cfg[K.C_SALT] = int(salt or 0) & 0xFFFFFFFF
        cfg[K.C_NSEED] = int(s.get("noise_seed", 0)) & 0xFFFFFFFF
        materials = [
            Material(f"buffer_{b}", (*_BUFFER_COLORS[b % len(_BUFFER_COLORS)], 1.0),
                     texture="bark" if b == 0 else "leaf" if b == 1 else None)
            for b in range(10)
        ]  # fmt: skip
    return cfg, palette, materials, vertex_colors, bg


def _tropism(cfg, s: Mapping, program: Program | None, ops: np.ndarray) -> None:
    """The tropism settings into ``cfg``; the walk's tropism flag when anything can bend."""
    t = s.get("tropism", GRAVITY)
    try:
        vec = tuple(float(x) for x in t)  # type: ignore[union-attr]
    except (TypeError, ValueError):
        vec = ()
    if len(vec) != 3 or not all(np.isfinite(vec)):
        raise TurtleSettingsError(f"setting 'tropism' must be 3 numbers (x, y, z), got {t!r}")
    cfg[K.C_TROP : K.C_TROP + 3] = vec
    cfg[K.C_ELAST] = _num(s, "elasticity") if "elasticity" in s else 0.0
    cfg[K.C_ESTEP] = _num(s, "elasticity_step") if "elasticity_step" in s else 0.0
    cfg[K.C_TMODE] = 1.0 if program is not None and program.dialect == "cpfg" else 0.0
    moving = False
    if cfg[K.C_TMODE] != 0.0:
        moving = _movements(cfg, s.get("tropisms") or ())
    cfg[K.C_TON] = 1.0 if (cfg[K.C_ELAST] != 0.0 or moving or np.any(ops == T.AT)
                           or (cfg[K.C_TMODE] != 0.0 and np.any(ops == T.ELASTICITY))) else 0.0


def _movements(cfg, movements) -> bool:
    """cpfg's ``tropism:`` / ``torque:`` lines (the setting ``tropisms``: ``(kind, (x, y,
    z), angle, elasticity, step)`` each, as the view reader makes them) into ``cfg``;
    whether one bends from the start."""
    if len(movements) > M.MAX_MOVEMENTS:
        raise TurtleSettingsError(f"setting 'tropisms': {len(movements)} tropisms and "
                                  f"torques; sylva draws at most {M.MAX_MOVEMENTS}")
    for k, item in enumerate(movements):
        try:
            kind, vec, angle, e0, step = item
            vec = tuple(float(x) for x in vec)
            angle, e0, step = float(angle), float(e0), float(step)
        except (TypeError, ValueError):
            vec = ()
        if kind not in ("tropism", "torque") or len(vec) != 3:
            raise TurtleSettingsError(f"setting 'tropisms': entry {k + 1} must be (kind, "
                                      f"(x, y, z), angle, elasticity, step), got {item!r}")
        b = M.C_MOV + M.MOV_W * k
        g = math.radians(angle)
        cfg[b : b + M.MOV_W] = (float(kind == "torque"), *vec, math.cos(g), math.sin(g), e0,
                                step)  # fmt: skip
    cfg[M.C_NMOV] = len(movements)
    return any(item[3] != 0.0 for item in movements)


def _check_at(word: ModuleString, ops: np.ndarray, arg: np.ndarray, cpfg: bool,
              nmov: int = 0) -> None:
    """Every ``@`` of ``word`` followed by a function the turtle knows (``O v M R T``, and
    ``s i d`` after ``T``), else a :class:`TurtleSettingsError` naming the module."""
    syms = np.flatnonzero(ops == T.AT)  # the alphabet's '@' (no pass over a word without)
    if syms.size == 0:
        return
    at = np.flatnonzero(word.ids == syms[0])
    if at.size == 0:
        return
    names = word.alphabet.names
    n = len(word)
    code = np.zeros(at.size)
    inside = at + 1 < n
    code[inside] = arg[word.ids[at[inside] + 1]]
    fun = np.isin(code, list(T.AT_FUNCTIONS.values()))
    tee = code == T.AT_T
    sub_at = at + 2
    sub = np.zeros(at.size)
    ok2 = tee & (sub_at < n)
    sub[ok2] = arg[word.ids[sub_at[ok2]]]
    bad = ~fun | (tee & ~np.isin(sub, list(T.AT_SUBFUNCTIONS.values())))
    want = "@O @o @c @v @M @R @Ts @Ti @Td @Tx @Tf @G. @! @# @L"
    if bad.any():
        k = int(np.flatnonzero(bad)[0])
        p = int(at[k])
        nxt = names[word.ids[p + 1]] if p + 1 < n else None
        if nxt is not None and tee[k]:
            after = names[word.ids[p + 2]] if p + 2 < n else None
            got = f"'@T' followed by {after!r}" if after is not None else "'@T' at the end"
        else:
            got = f"'@' followed by {nxt!r}" if nxt is not None else "'@' at the end"
        raise TurtleSettingsError(
            f"unknown @ module at module {p} of the word: {got}; expected one of {want}"
        )
    if cpfg and word.values.size:  # cpfg's @T take the movement's index first
        settable = tee & np.isin(sub, [T.AT_TS, T.AT_TI, T.AT_TD])  # not @Tx, @Tf
        for p in at[settable].tolist():
            a, b = word.offsets[p + 2], word.offsets[p + 3]
            k = word.values[a] if b > a else None
            if k is not None and not (k == int(k) and 1 <= k <= nmov):
                defined = (f"the view file defines {nmov} (its tropism: and torque: lines)"
                           if nmov else "the view file has no tropism: or torque: line")
                warnings.warn(
                    f"module {p + 2} of the word: @T{names[word.ids[p + 2]]}({k:g}, ...) "
                    f"names tropism {k:g}, but {defined}; ignored, as cpfg does "
                    "('Movement index out of range')", SylvaWarning, stacklevel=5)
                return


def _run(word, program, dialect, seed, overrides, trace_on):
    word = _as_word(word, program)
    with _jit.small(len(word) <= SMALL):
        return _run_word(word, program, dialect, seed, overrides, trace_on)


def _run_word(word, program, dialect, seed, overrides, trace_on):
    dialect, s = _settings(program, dialect, overrides)
    cfg, palette, materials, vertex_colors, bg = _configure(dialect, s, seed)
    cylinders = None
    if dialect == "abop" and getattr(program, "dialect", None) == "cpfg":
        cfg[K.C_PMODE] = 1.0  # a cpfg file's { . } as cpfg builds polygons
        word, cylinders = _gcylinder.control_word(word)  # @Gs ... @Ge: Hermite curves
    ops, arg = compile_table(TABLES[dialect], word.alphabet.names, ARGS.get(dialect))
    if dialect == "abop":  # cpfg's ?(n, s): the sub-L-system drawn s times as large
        word = scale_word(word, ops, arg, cfg[K.C_LEN], cfg[K.C_LEAF])
    has_at = "@" in word.alphabet
    if dialect in ("lsys", "abop") and (has_at or s.get("elasticity") or s.get("tropisms")
                                        or "_" in word.alphabet):  # else nothing bends
        _tropism(cfg, s, program, ops)
        if has_at:
            _check_at(word, ops, arg, cfg[K.C_TMODE] != 0.0, int(cfg[M.C_NMOV]))
    n = len(word)
    threads = _threads()
    parallel = (threads > 1 and n >= PARALLEL_MIN and cfg[K.C_ENGINE] == 0.0
                and not _jit.interpreting(K, "walk", "walk_plain", "scan_range"))  # fmt: skip
    # subtrees of 1/64 to 1/16 of a thread's share, so that the threads can be kept even
    s_max = max(n // (16 * threads), 1) if parallel else -1
    counts, sel = _scan(word.ids, ops, max(s_max // 64, SUBTREE_MIN), s_max, threads, parallel)
    if counts[5] > 0 or sel.shape[0] < 2:  # polygons or %: one serial walk
        sel = sel[:0]
    empty = np.zeros(0, np.int64)
    match = word.match if np.any(ops == T.CUT) else empty
    offsets = word.offsets if word.values.size else empty  # no parameters: none to read
    walked_trace = trace_on or cylinders is not None  # the curves need the frames
    args = (word.ids, offsets, word.values, match, ops, arg, cfg, palette, walked_trace)
    out = _walk(args, 0, counts, sel, threads)
    if out[-1] > 0:  # blocks were counted, not written: run again with room for them
        out = _walk(args, out[-1], counts, sel, threads)
    if cylinders is not None:
        out = _gcylinder.splice(out, cylinders, trace_on, s.get("contours"),
                                s.get("contour_sides") or 8, bool(s.get("cylinder_twist")))
    return dialect, s, materials, vertex_colors, bg, out


def _scan(ids, ops, s_min, s_max, threads, parallel):
    """:func:`~sylva.turtle._kernels.scan_word`, on ``threads`` consecutive ranges at once
    when ``parallel`` (a pair that spans two ranges is not offered; pairs inside it are)."""
    if not parallel:
        return K.scan_word(ids, ops, s_min, s_max)
    n = ids.shape[0]
    bounds = [n * k // threads for k in range(threads + 1)]

    def part(k):
        return K.scan_range(ids, ops, bounds[k], bounds[k + 1], s_min, s_max)

    with ThreadPoolExecutor(threads, thread_name_prefix="sylva-turtle") as pool:
        return K.scan_merge(list(pool.map(part, range(threads))))


def _threads() -> int:
    return numba.get_num_threads()


def _walk(args, blk_cap, counts, sel, threads):
    # the records come from the buffer pool: a word interpreted again reuses touched pages
    word, segs, leaves, polys, blocks, tr, cnt, slots, depths, st, stack = K.walk_word(
        *args, blk_cap, counts, sel, K.segment_arrays(int(counts[0]), empty)
    )
    walk, flags = _walker(word, tr)
    n = int(word[0].shape[0])
    walk(0, n, st, stack, 0, 0, cnt, word, segs, leaves, polys, blocks, tr, sel, slots, depths,
         *flags)  # fmt: skip
    holes = int(cnt[K.K_HOLES])
    if sel.shape[0]:
        holes += _walk_subtrees(
            sel, slots, depths, int(counts[4]) + 1, (word, segs, leaves, polys, blocks, tr), threads
        )
    return K.finish_word(segs, leaves, polys, blocks, tr, cnt, holes)


def _walker(word, tr):
    """The compiled walk for ``word`` and its last arguments: :func:`K.walk_plain` in the
    common case (compiled without the flags' branches), else :func:`K.walk` and its flags.
    Only the one a word needs is compiled on a cold cache."""
    has_par = word[1].shape[0] > 0
    engine = bool(word[6][K.C_ENGINE] != 0.0)
    trace = tr[0].shape[0] > 0
    tropism = bool(word[6][K.C_TON] != 0.0)
    if has_par or engine or trace or tropism:
        return K.walk, (has_par, engine, trace, tropism)
    return K.walk_plain, ()


def _walk_subtrees(sel, slots, depths, rows, arrays, threads) -> int:
    """Walk the subtrees of ``sel`` from their stored states on ``threads`` threads.

    The compiled walk releases the GIL; each thread takes the largest subtree left, so the
    threads finish together however unequal the subtrees are.  Returns the hole count.
    """
    order = iter(np.argsort(sel[:, 0] - sel[:, 1], kind="stable").tolist())
    lock = threading.Lock()
    none = np.zeros((0, 6), np.int64)
    no_slots = np.zeros((0, K.NS))
    no_depth = np.zeros(0, np.int64)
    walk, flags = _walker(arrays[0], arrays[5])

    def worker(_) -> int:
        stack = np.empty((rows, K.NS))
        cnt = np.zeros(K.NK, np.int64)
        holes = 0
        while True:
            with lock:
                t = next(order, None)
            if t is None:
                return holes
            cnt[:] = 0
            cnt[K.K_NS] = sel[t, 2]
            cnt[K.K_NL] = sel[t, 3]
            d = int(depths[t])
            a, b = int(sel[t, 0]), int(sel[t, 1])
            args = (a, b + 1, slots[t].copy(), stack, d, d, cnt, *arrays, none, no_slots)
            walk(*args, no_depth, *flags)
            holes += int(cnt[K.K_HOLES])

    with ThreadPoolExecutor(threads, thread_name_prefix="sylva-turtle") as pool:
        return sum(pool.map(worker, range(threads)))


def interpret(
    word: ModuleString | str,
    program: Program | None = None,
    *,
    dialect: str | None = None,
    seed: int | None = None,
    **overrides,
) -> Geometry:
    """Interpret ``word`` with the command table of ``dialect``.

    Parameters
    ----------
    word : ModuleString or str
        The derived word (after render rules).  Text is read with
        :meth:`ModuleString.from_text`.
    program : Program, optional
        Supplies the dialect (:attr:`Program.turtle`) and the settings (``len``, ``rot`` …).
    dialect : {"lsys", "abop", "classic", "engine"}, optional
        Overrides the program's command table (default ``"lsys"`` without a program).
    seed : int, optional
        The salt of seed 004's random angle variation (``engine`` only).
    **overrides
        Settings that replace the program's: ``len``, ``rot``, ``thick``, ``color`` and the
        ``*_delta`` of ``lsys``; ``rot``, ``len``, ``thick``, ``thick_factor``,
        ``color_index``, ``palette``, ``leaf_size`` of ``abop``; ``rot`` (or ``angle``),
        ``reduction``, ``radius``, ``thickness`` of ``classic``; ``yaw``, ``pitch``,
        ``shrink``, ``scale``, ``angle_var`` of ``engine``.

    Returns
    -------
    Geometry
        Segments, leaves, polygons and blocks (see :class:`sylva.geometry.records.Geometry`).

    Raises
    ------
    TurtleSettingsError
        For an unknown dialect or setting, or an impossible value.

    Examples
    --------
    >>> from sylva.lsystem.lstring import ModuleString
    >>> g = interpret(ModuleString.from_text("F[+F]F"), dialect="abop", rot=90)
    >>> g.seg_end.round(12).tolist()
    [[0.0, 1.0, 0.0], [-1.0, 1.0, 0.0], [0.0, 2.0, 0.0]]
    >>> g.seg_parent.tolist(), g.seg_module.tolist()
    ([-1, 0, 0], [0, 3, 5])
    """
    word = _as_word(word, program)
    dialect, s, materials, vertex_colors, bg, out = _run(
        word, program, dialect, seed, overrides, False
    )
    detail = s.get("detail")
    if detail is not None:
        detail = int(np.floor(float(detail)))  # type: ignore[arg-type]
    geo = Geometry(
        *out[:24],
        materials=materials,
        dialect=dialect,
        background=bg,
        detail=detail,
        vertex_colors=vertex_colors,
    )
    if dialect == "abop" and geo.n_leaves:
        _surfaces.assign(geo, word, s.get("surfaces"), s.get("textures"))
    if dialect == "abop" and s.get("textures"):  # @Tx(n) on cylinders (cpfg)
        _surfaces.texture_segments(geo, word, s["textures"])
    if dialect == "abop" and s.get("background_scene"):  # cpfg's background scene
        from ..geometry.scenery import scenery_mesh

        geo.scenery = scenery_mesh(s["background_scene"], default_color=materials[0].color)
    return geo


def trace(
    word: ModuleString | str,
    program: Program | None = None,
    *,
    dialect: str | None = None,
    seed: int | None = None,
    **overrides,
) -> Trace:
    """The turtle's position and frame after every module of ``word``.

    Takes the arguments of :func:`interpret`.  Meant for checking a command table
    numerically and for showing the turtle's path in the studio.

    Examples
    --------
    >>> from sylva.lsystem.lstring import ModuleString
    >>> t = trace(ModuleString.from_text("&(90)"), dialect="abop")
    >>> t.frames[0].round(12).tolist()   # H now points down -U = -Z; U = +Y
    [[0.0, 0.0, -1.0], [-1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]
    """
    out = _run(word, program, dialect, seed, overrides, True)[-1]
    return Trace(out[24], out[25])
