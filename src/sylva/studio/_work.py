"""The work behind the Studio's requests: parse, derive under caps, mesh, page, trace, render.

Everything here is plain, blocking Python that the server runs in worker threads.  It uses
only the public API of :mod:`sylva.lsystem`, :mod:`sylva.turtle`, :mod:`sylva.geometry` and
:mod:`sylva.render`.  User text is parsed by the dialects' parsers; nothing is evaluated as
Python.
"""

from __future__ import annotations

import contextlib
import io
import math
import re
import time
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from ..errors import GrowthLimitError, LSystemSyntaxError, SylvaError
from ..lsystem import Derivation, detect, loads
from ..lsystem.dialects import format_rule
from ..lsystem.lstring import format_number, format_symbol
from ._limits import Limits
from ._scheduler import run_through
from ._sessions import Session

__all__ = [
    "DIALECTS",
    "CapError",
    "Drawn",
    "advance",
    "advancing",
    "back",
    "camera_hint",
    "export_formats",
    "export_mesh",
    "load_program",
    "mesh",
    "meshing",
    "pick",
    "previewing",
    "render_png",
    "trace_module",
    "state",
    "word_page",
]

DIALECTS = ("lsys", "classic", "engine", "cpfg")
# turtle commands that leave the plane: their presence makes the automatic camera 3D
_OUT_OF_PLANE = {"PITCH_DOWN", "PITCH_UP", "ROLL_LEFT", "ROLL_RIGHT", "E_PITCH_UP",
                 "E_PITCH_DOWN", "LEVEL"}


class CapError(SylvaError):
    """A request ran into a cap of the server (``kind``: ``"time"``, ``"modules"``,
    ``"steps"``, ``"stopped"``)."""

    def __init__(self, kind: str, message: str) -> None:
        self.kind = kind
        super().__init__(message)


@dataclass
class Drawn:
    """What the last mesh of a session was built from."""

    step: int
    geometry: Any
    sources: np.ndarray | None  # render-word module -> word module
    scene: Any  # None while only the instanced branches were asked for
    glb: bytes | None
    triangles: int
    sides: int | None
    mesh_ms: float
    segments: bytes | None = None  # the branches as instanced rows (segment_rows)


#: Plants of more branches than this (and nothing but branches) are sent to the page as
#: instanced branches, not as a mesh (as the notebook widget does): a tenth of the bytes,
#: no mesh to build, and the page draws one shared cylinder per branch.
INSTANCE_FROM = 10_000


def instanced(geometry) -> bool:
    """Whether the page draws ``geometry`` as instanced branches."""
    g = geometry
    return g.n_segments > INSTANCE_FROM and not (g.n_leaves or g.n_polygons or g.n_blocks)


def segment_rows(geometry) -> bytes:
    """The branches as float32 rows ``start xyz, end xyz, r0, r1, linear rgb`` (11 floats
    each), the rows the notebook widget sends too (:func:`sylva._lines.branch_rows`: a
    chain of branches of one width is one row): the page turns one shared cylinder per
    row (seed 001 §6.7's prism with per-segment instance data)."""
    from .._lines import branch_rows

    return branch_rows(geometry)


# --------------------------------------------------------------------------- loading
def load_program(text: str, *, dialect: str | None, filename: str | None,
                 overrides: dict[str, float] | None = None):
    """Parse ``text`` (in ``dialect``, detected when ``None``) and apply numeric overrides
    of its globals (the Studio's sliders); overrides of names it does not assign are
    dropped."""
    if dialect is not None and dialect not in DIALECTS:
        raise SylvaError(f"unknown dialect {dialect!r}; expected one of {', '.join(DIALECTS)}")
    name = filename or "<editor>"
    if dialect is None:
        dialect = detect(text, filename if filename else None)
    program = loads(text, filename=name, dialect=dialect)
    if not overrides:
        return program
    consts = dict(program.constants)
    # a slider of a global the text no longer has is dropped
    overrides = {k: v for k, v in overrides.items() if k in consts}
    if not overrides:
        return program
    for k, v in overrides.items():
        if not isinstance(v, (int, float)) or isinstance(v, bool) or not math.isfinite(v):
            raise SylvaError(f"the value of {k} must be a finite number")
    if dialect == "lsys":
        # set the assignment in the text, so that the axiom and the globals computed from
        # this one (both evaluated when the text is parsed) follow it
        for k, v in overrides.items():
            pattern = re.compile(rf"^([ \t]*{re.escape(k)}[ \t]*=[ \t]*)[^#\r\n]*", re.M)
            text = pattern.sub(lambda m, v=v: m.group(1) + format_number(float(v)) + " ",
                               text, count=1)
        program = loads(text, filename=name, dialect=dialect)
        consts = dict(program.constants)
    for k, v in overrides.items():
        consts[k] = float(v)
    return replace(program, constants=consts)


def new_derivation(program, *, seed: int | None, limits: Limits, trace: bool) -> Derivation:
    if seed is not None and not (0 <= int(seed) < 2**63):
        raise SylvaError("the seed must be an integer in [0, 2**63)")
    from ..plant import environment_for, query_for  # the turtle answers ?P ?H ?U ?L, the
    # program's environment its ?E modules

    s = seed if seed is not None else program.seed
    env, locate = environment_for(program, s)
    return Derivation(program, seed=seed, limit=limits.max_modules, trace=trace,
                      query=query_for(program, s), environment=env, locate=locate)


def turtle_table(program) -> str:
    t = program.settings.get("turtle")
    if isinstance(t, str):
        return t
    return {"classic": "classic", "engine": "engine"}.get(program.dialect, "lsys")


def camera_hint(program) -> str:
    """Seed 001 §5.3: ``"2d"`` when nothing in the system leaves the plane (no pitch or roll
    symbol), else ``"perspective"``."""
    from ..turtle import TABLES
    from ..turtle.tables import OPCODE_NAMES

    table = TABLES.get(turtle_table(program), {})
    symbols = {m.symbol for m in program.axiom}
    for r in program.rules:
        symbols.update(m.symbol for m in r.successor)
    for s in symbols:
        op = table.get(s)
        if op is not None and OPCODE_NAMES.get(op) in _OUT_OF_PLANE:
            return "perspective"
    return "2d"


# --------------------------------------------------------------------------- deriving
def _estimate(session: Session, n_now: int) -> float:
    """Seconds the next step is expected to take, from the last one scaled by size."""
    if session.last_step is None or n_now < 20_000:
        return 0.0  # small steps cost their fixed overhead (and a first JIT compile) only
    dt, before, _after = session.last_step
    if before < 5_000:
        return 0.0
    return dt * n_now / before


def _clock():
    """Seconds since now, for work run outside the scheduler."""
    t0 = time.perf_counter()
    return lambda: time.perf_counter() - t0


def advancing(session: Session, n: int, limits: Limits, clock=None):
    """Derive ``n`` steps of the session's derivation, one at a time, under the time cap;
    a generator that yields after each step (the scheduler's turns).

    ``clock()`` gives the seconds of work spent so far (the scheduler's count of worker
    time; by default the time since the start).  Raises :class:`CapError` (with the steps
    done so far kept) when the cap is hit, the client pressed Stop or sent a newer
    request, or the module cap refuses a step.
    """
    d = session.derivation
    if n < 0 or n > limits.max_steps:
        raise CapError("steps", f"ask for 0 to {limits.max_steps} steps at a time, not {n}")
    clock = clock or _clock()
    t0 = time.perf_counter()
    done = 0
    session.progress = {"steps": 0, "of": n, "modules": len(d.word), "interpreted": 0}
    for _ in range(n):
        check_turn(session, limits, clock, done, n)
        before = len(d.word)
        ts = time.perf_counter()
        try:
            d.advance(1)
        except GrowthLimitError as exc:
            raise CapError("modules", refused(d, exc, limits, done, n)) from None
        session.last_step = (time.perf_counter() - ts, before, len(d.word))
        done += 1
        session.progress.update(steps=done, modules=len(d.word))
        session.timings["derive_ms"] = (time.perf_counter() - t0) * 1e3
        yield
    session.timings["derive_ms"] = (time.perf_counter() - t0) * 1e3
    return {"done": done}


def check_turn(session: Session, limits: Limits, clock, done: int, n: int) -> None:
    """Before a step of a request: :class:`CapError` when the client pressed Stop, the
    time cap is spent, or the next step is estimated to pass it."""
    d = session.derivation
    if session.cancel.is_set():
        raise CapError("stopped", f"stopped after {done} of {n} steps (step {d.step})")
    elapsed = clock()
    est = _estimate(session, len(d.word))
    if done and elapsed >= limits.time_cap:
        raise CapError("time", f"the time cap of {limits.time_cap:g} s per request was "
                       f"reached after {done} of {n} steps (step {d.step})")
    if elapsed + est > limits.time_cap:
        raise CapError("time", f"step {d.step + 1} was refused: it is estimated to take "
                       f"{est:.1f} s, past the cap of {limits.time_cap:g} s per request "
                       f"({done} of {n} steps done)")


def refused(d, exc: GrowthLimitError, limits: Limits, done: int, n: int) -> str:
    """Why a step was refused by the module cap (the word before it is kept)."""
    return (f"step {d.step + 1} was refused: {exc} (the module cap is "
            f"{limits.max_modules:,}; {done} of {n} steps done, the view shows step "
            f"{d.step}, the last word that fits)")


def advance(session: Session, n: int, limits: Limits) -> dict:
    """:func:`advancing` run through in the calling thread."""
    return run_through(advancing(session, n, limits))


def back(session: Session) -> None:
    t0 = time.perf_counter()
    session.derivation.back()
    session.last_step = None
    session.timings["derive_ms"] = (time.perf_counter() - t0) * 1e3


def state(session: Session) -> dict:
    """What the client shows: step, counts, globals, settings and the camera hint."""
    p, d = session.program, session.derivation
    word = d.word
    settings = {}
    for k, v in p.settings.items():
        if isinstance(v, (int, float, str)) and not isinstance(v, bool):
            settings[k] = v
        elif isinstance(v, (tuple, list)) and all(isinstance(x, (int, float)) for x in v):
            settings[k] = [float(x) for x in v]
    from ..turtle import DEFAULTS

    # seed 001's default background (0.9 grey) where the program and its dialect set none
    bg = settings.get("bg") or DEFAULTS.get(turtle_table(p), {}).get("bg") or (0.9, 0.9, 0.9)
    drawn = session.drawn if session.drawn is not None and session.drawn.step == d.step else None
    return {
        "step": d.step,
        "modules": len(word),
        "seed": d.seed,
        "dialect": p.dialect,
        "turtle": turtle_table(p),
        "filename": session.filename,
        "steps_hint": p.steps,
        "constants": {k: float(v) for k, v in p.constants.items()},
        "overrides": dict(session.overrides),
        "settings": settings,
        "background": [min(max(float(x), 0.0), 1.0) for x in bg],
        "camera": camera_hint(p),
        "trace": d.trace,
        "symbols": dict(sorted(word.counts().items(), key=lambda kv: (-kv[1], kv[0]))[:64]),
        "rules": len(p.rules),
        "rule_list": _rule_list(p),
        "timings": dict(session.timings),
        "triangles": drawn.triangles if drawn and drawn.triangles else None,
        "limits": {"modules": d.limit},
    }


def _rule_list(program) -> list[dict]:
    from ._debug import rules

    return rules(program)


# --------------------------------------------------------------------------- word view
def _short(v: float) -> str:
    v = float(v)
    return format_number(float(f"{v:.6g}")) if math.isfinite(v) else str(v)


def module_text(symbol: str, params) -> str:
    text = format_symbol(symbol)
    if len(params):
        # shown to 6 significant digits: 0.0353393 rather than 0.0353393242999999
        text += "(" + ",".join(_short(v) for v in params) + ")"
    return text


def word_page(session: Session, start: int, count: int, limits: Limits) -> dict:
    """Modules ``start … start + count`` of the current word, one text per module."""
    word = session.derivation.word
    n = len(word)
    count = max(1, min(int(count), limits.page_size))
    start = max(0, min(int(start), max(n - 1, 0)))
    stop = min(n, start + count)
    part = word[start:stop]
    return {
        "step": session.derivation.step,
        "total": n,
        "start": start,
        "modules": [module_text(s, p) for s, p in part],
    }


# --------------------------------------------------------------------------- meshing
class _Pieces:
    """A binary file that keeps what is written and joins it once at the end: a large
    mesh's buffer is not copied into a BytesIO holding the GIL (``bytes.join`` lets the
    other threads run while it copies)."""

    def __init__(self) -> None:
        self.parts: list = []

    def write(self, data) -> int:
        self.parts.append(data)
        return len(data)

    def getvalue(self) -> bytes:
        return b"".join(self.parts)


def _tube_triangles(n: int, sides: int) -> int:
    """Triangles of ``n`` tubes of ``sides`` sides: the wall (2 a side) and the joint to
    the next segment (1 a side), as the mesh builder makes them, and the end caps."""
    return 3 * n * sides + 2 * sides


def _sides(geometry, limits: Limits) -> int | None:
    """The program's ``detail``, lowered when the mesh would pass the triangle cap."""
    wanted = geometry.detail
    n = geometry.n_segments
    if not n:
        return None
    sides = wanted if wanted is not None else 8
    sides = max(sides, 1)
    while sides > 3 and _tube_triangles(n, sides) > limits.max_triangles:
        sides -= 1
    if _tube_triangles(n, sides) > limits.max_triangles:
        raise CapError("modules", f"{n:,} branches need more than the cap of "
                       f"{limits.max_triangles:,} triangles")
    return sides if sides != wanted else wanted


def _meshing_turn(session: Session, limits: Limits, clock, step: int):
    """The check between two phases of meshing: stopped, superseded or past the time cap."""

    def turn(done: str):
        if session.cancel.is_set():
            raise CapError("stopped", f"meshing step {step} was stopped after {done}")
        if clock() > limits.time_cap:
            raise CapError("time", f"meshing step {step} passed the time cap of "
                           f"{limits.time_cap:g} s per request after {done}; lower the "
                           "detail or derive fewer steps")

    return turn


def _interpreting(session: Session, limits: Limits, clock, *, sources: bool = True):
    """The render word and the turtle's geometry of the current word (a generator that
    yields between the two); returns ``(geometry, sources)`` (``sources`` ``None``
    without rule tracing, or when not asked for)."""
    from ..turtle import interpret

    d, p = session.derivation, session.program
    turn = _meshing_turn(session, limits, clock, d.step)
    try:
        if d.trace and sources:
            rw, sources = d.render_word_sources()
        else:
            rw, sources = d.render_word(), None
    except GrowthLimitError as exc:
        raise CapError("modules", f"the render rules would pass the module cap: {exc}") from None
    yield
    turn(f"the render word ({len(rw):,} modules)")
    session.progress = {**session.progress, "interpreting": len(rw), "interpreted": 0}
    geometry = interpret(rw, p, seed=d.seed)
    session.progress["interpreted"] = len(rw)
    yield
    turn(f"the turtle ({geometry.n_segments:,} branches)")
    return geometry, sources


def meshing(session: Session, limits: Limits, clock=None, *, full: bool = True):
    """Interpret the current (render) word and build its mesh as GLB bytes (cached); a
    generator that yields between the phases (render word, turtle, mesh, GLB).

    With ``full=False`` a plant of many branches (:func:`instanced`) gets only its
    instanced rows (``Drawn.segments``, no scene): what the page draws.  Exports, renders
    and a later ``full`` call build the mesh from the same turtle geometry.

    Between two phases it stops with :class:`CapError` when the client pressed Stop or
    sent a newer request, or when ``clock()`` (seconds of work so far) passed the time cap.
    """
    d = session.derivation
    old = session.drawn
    if old is not None and old.step == d.step and d.trace and old.sources is None:
        old = None  # a preview's turtle, without the trace of its modules: again
    if old is not None and old.step == d.step and (
            old.scene is not None or (not full and old.segments is not None)):
        return old
    clock = clock or _clock()
    t0 = time.perf_counter()
    if old is not None and old.step == d.step:  # the turtle ran already: the mesh now
        if not full and instanced(old.geometry):
            drawn = _instanced_drawn(session, old.geometry, old.sources, t0)
            drawn.mesh_ms += old.mesh_ms  # the turtle's share, spent by the preview
            session.timings["mesh_ms"] = drawn.mesh_ms
            return drawn
        return (yield from _build(session, limits, clock, old.geometry, old.sources, t0))
    session.drawn = None  # the old mesh goes before the new one is built
    geometry, sources = yield from _interpreting(session, limits, clock)
    if not full and instanced(geometry):
        return _instanced_drawn(session, geometry, sources, t0)
    return (yield from _build(session, limits, clock, geometry, sources, t0))


def _instanced_drawn(session: Session, geometry, sources, t0) -> Drawn:
    rows = segment_rows(geometry)
    ms = (time.perf_counter() - t0) * 1e3
    # the triangles the page draws: 8-sided open cylinders, 16 a row
    drawn = Drawn(session.derivation.step, geometry, sources, None, None,
                  16 * (len(rows) // 44), 8, ms, segments=rows)
    session.drawn = drawn
    session.timings["mesh_ms"] = ms
    return drawn


def previewing(session: Session, limits: Limits, clock=None):
    """The preview of the current word: its branches as lines (:func:`sylva._lines.line_bytes`,
    no mesh built); a generator as :func:`meshing`.  The turtle's geometry is kept
    (``session.drawn``, without a mesh), so that the full frame asked for next, the
    rule trace and exports start from it (without the modules' sources: the full frame
    traces them when rule tracing is on).  Returns ``(bytes, turtle ms, lines ms)``."""
    from .._lines import line_bytes

    d = session.derivation
    clock = clock or _clock()
    t0 = time.perf_counter()
    old = session.drawn
    if old is not None and old.step == d.step:
        geometry = old.geometry
    else:
        session.drawn = None
        geometry, sources = yield from _interpreting(session, limits, clock, sources=False)
        ms = (time.perf_counter() - t0) * 1e3
        session.drawn = Drawn(d.step, geometry, sources, None, None, 0, None, ms)
        session.timings["mesh_ms"] = ms
    t1 = time.perf_counter()
    data = line_bytes(geometry)
    t2 = time.perf_counter()
    return data, (t1 - t0) * 1e3, (t2 - t1) * 1e3


def _build(session: Session, limits: Limits, clock, geometry, sources, t0):
    """The mesh and GLB of the turtle's ``geometry`` (the last phases of :func:`meshing`)."""
    from ..geometry.build import build_mesh
    from ..geometry.exchange import write_glb

    step = session.derivation.step
    turn = _meshing_turn(session, limits, clock, step)
    sides = _sides(geometry, limits)
    scene = build_mesh(geometry, detail=sides)
    triangles = int(sum(m.n_triangles for m in scene.meshes))
    yield
    turn(f"building {triangles:,} triangles")
    buf = _Pieces()
    write_glb(scene, buf)
    ms = (time.perf_counter() - t0) * 1e3
    drawn = Drawn(step, geometry, sources, scene, buf.getvalue(), triangles, sides, ms)
    session.drawn = drawn
    session.timings["mesh_ms"] = ms
    return drawn


def mesh(session: Session, limits: Limits) -> Drawn:
    """:func:`meshing` run through in the calling thread."""
    return run_through(meshing(session, limits))


def export_formats() -> list[str]:
    """The mesh formats the File menu offers: every writer of
    :mod:`sylva.geometry.exchange` (USD when ``usd-core`` is installed)."""
    from ..geometry.exchange import WRITERS, usd_available

    return [f for f in WRITERS if not f.startswith("usd") or usd_available()]


def scene_bytes(scene, fmt: str, geometry=None) -> bytes:
    """``scene`` written in the export format ``fmt`` (``svg`` from the turtle's
    ``geometry`` when given), as bytes."""
    import tempfile
    from pathlib import Path

    from ..geometry.exchange import BINARY, write

    if fmt not in export_formats():
        raise SylvaError(f"unknown export format {fmt!r}; expected one of "
                         + ", ".join(export_formats()))
    obj = geometry if fmt == "svg" and geometry is not None else scene
    if fmt.startswith("usd"):  # the USD library writes files, not streams
        with tempfile.TemporaryDirectory(prefix="sylva-studio-") as tmp:
            path = Path(tmp) / f"plant.{fmt}"
            write(obj, path, format=fmt)
            return path.read_bytes()
    if fmt in BINARY:
        buf = _Pieces() if fmt == "glb" else io.BytesIO()
        write(obj, buf, format=fmt)
        return buf.getvalue()
    text = io.StringIO()
    write(obj, text, format=fmt)
    return text.getvalue().encode("utf-8")


def export_mesh(session: Session, fmt: str, limits: Limits) -> bytes:
    """The current mesh in the export format ``fmt`` (:func:`export_formats`)."""
    drawn = mesh(session, limits)
    if fmt == "glb":
        return drawn.glb
    return scene_bytes(drawn.scene, fmt, drawn.geometry)


# --------------------------------------------------------------------------- rule trace
_F32_MAX = float(np.finfo(np.float32).max)


def _seg_distance(p: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    ab = b - a
    L2 = np.einsum("ij,ij->i", ab, ab)
    t = np.clip(np.einsum("ij,ij->i", p - a, ab) / np.where(L2 > 0, L2, 1.0), 0.0, 1.0)
    q = a + t[:, None] * ab
    return np.linalg.norm(p - q, axis=1)


def pick(session: Session, point, limits: Limits) -> dict:
    """The module that drew what lies at ``point`` (a hit on the mesh, model space), and the
    rule and step that made it."""
    p = np.asarray(point, dtype=np.float64).reshape(3)
    # the mesh is float32: a point past its range is no hit on it, and its squared
    # distances would overflow (1e300 was a 500, "overflow encountered in multiply")
    if not (np.isfinite(p).all() and np.abs(p).max() <= _F32_MAX):
        raise SylvaError("the picked point must be three finite numbers of the model's "
                         f"space (within ±{_F32_MAX:.3g})")
    drawn = mesh(session, limits)
    g = drawn.geometry
    best = (math.inf, None, None)  # distance, kind, record index
    if g.n_segments:
        dist = _seg_distance(p[None, :], g.seg_start, g.seg_end)
        dist = dist - g.seg_radius.max(axis=1)
        i = int(np.argmin(dist))
        best = min(best, (float(dist[i]), "segment", i), key=lambda x: x[0])
    if g.n_leaves:
        dist = np.linalg.norm(g.leaf_pos - p, axis=1) - g.leaf_size
        i = int(np.argmin(dist))
        best = min(best, (float(dist[i]), "leaf", i), key=lambda x: x[0])
    if g.n_polygons:
        off = g.poly_offsets
        counts = np.diff(off)
        ids = np.repeat(np.arange(len(counts)), counts)
        dv = np.linalg.norm(g.poly_vertices - p, axis=1)
        j = int(np.argmin(dv))
        best = min(best, (float(dv[j]), "polygon", int(ids[j])), key=lambda x: x[0])
    if g.n_blocks:
        dist = np.abs(g.block_center - p).max(axis=1) - g.block_size / 2
        i = int(np.argmin(dist))
        best = min(best, (float(dist[i]), "block", i), key=lambda x: x[0])
    dist, kind, i = best
    if kind is None:
        raise SylvaError("nothing is drawn to pick")
    module_of = {"segment": g.seg_module, "leaf": g.leaf_module, "polygon": g.poly_module,
                 "block": g.block_module}[kind]
    render_index = int(module_of[i])
    word_index = int(drawn.sources[render_index]) if drawn.sources is not None else render_index
    return _describe(session, drawn, word_index, render_index, kind, i, dist)


def trace_module(session: Session, index: int, limits: Limits) -> dict:
    """Module ``index`` of the current word: what it drew (its first segment, if any) and
    the rule and step that made it — the word view's side of the rule-trace debugger."""
    d = session.derivation
    if not 0 <= index < len(d.word):
        raise SylvaError(f"the word has {len(d.word):,} modules; there is no module {index}")
    drawn = mesh(session, limits)
    g = drawn.geometry
    if drawn.sources is not None:
        rendered = np.flatnonzero(drawn.sources == index)
    else:
        rendered = np.array([index]) if index < len(d.word) else np.array([], np.int64)
    hits = np.flatnonzero(np.isin(g.seg_module, rendered)) if g.n_segments else []
    if len(hits):
        i = int(hits[0])
        return _describe(session, drawn, index, int(g.seg_module[i]), "segment", i, 0.0)
    render_index = int(rendered[0]) if len(rendered) else -1
    return _describe(session, drawn, index, render_index, None, None, None)


def _describe(session, drawn, word_index, render_index, kind, i, dist) -> dict:
    g = drawn.geometry
    d = session.derivation
    word = d.word
    sym, params = next(iter(word[word_index:word_index + 1]))
    out: dict = {
        "kind": kind,
        "distance": dist,
        "render_index": render_index,
        "index": word_index,
        "module": module_text(sym, params),
        "step": d.step,
    }
    if kind == "segment":
        out["segment"] = {
            "start": g.seg_start[i].tolist(),
            "end": g.seg_end[i].tolist(),
            "radius": float(g.seg_radius[i].max()),
        }
    if d.trace:
        rule, made = d.origin(word_index)
        out["made_at_step"] = made
        if rule is None:
            out["rule"] = None
        else:
            span = rule.span
            out["rule"] = {
                "text": format_rule(rule),
                "line": span.line if span is not None else None,
                "column": span.column if span is not None else None,
            }
    return out


# --------------------------------------------------------------------------- PNG export
def _axis_cross(length: float = 1.0, width: float = 0.04):
    """Seed 001's focus point: +X red, +Y blue, +Z green, each ``length`` long."""
    from ..geometry.mesh import Mesh

    verts, idx, cols = [], [], []
    cube = np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)], float)
    faces = np.array([[0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5], [0, 4, 5], [0, 5, 1],
                      [2, 3, 7], [2, 7, 6], [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3]])
    for axis, rgb in ((0, (1, 0, 0)), (1, (0, 0, 1)), (2, (0, 1, 0))):
        size = np.full(3, width)
        size[axis] = length
        lo = np.full(3, -width / 2)
        lo[axis] = 0.0
        v = lo + cube * size
        idx.append(faces + sum(len(x) for x in verts))
        verts.append(v)
        cols.append(np.tile(rgb, (8, 1)))
    return Mesh(np.concatenate(verts), np.concatenate(idx), colors=np.concatenate(cols),
                name="focus")


def render_png(session: Session, limits: Limits, *, width: int, height: int, camera: dict,
               focus: bool, background, fmt: str = "png", scene=None) -> bytes:
    """Render the current mesh (or ``scene``, a tree's or a world's) offscreen at ``width``
    × ``height`` with the client's camera, as a PNG or (``fmt="jpg"``) a JPEG."""
    from ..geometry.mesh import Scene
    from ..render import Camera, render

    if not (1 <= width <= limits.max_image_side and 1 <= height <= limits.max_image_side):
        raise CapError("size", f"image sides must be 1 to {limits.max_image_side} pixels")
    if width * height > limits.max_image_pixels:
        raise CapError("size", f"at most {limits.max_image_pixels:,} pixels per image")
    meshes = list((scene if scene is not None else mesh(session, limits).scene).meshes)
    target = np.asarray(camera.get("target", (0, 0, 0)), dtype=np.float64).reshape(3)
    if focus:
        cross = _axis_cross(float(camera.get("axis", 1.0)))
        cross.vertices += target.astype(np.float32)
        meshes.append(cross)
    scene = Scene(meshes, name="studio")
    mode = camera.get("mode", "perspective")
    distance = float(camera.get("distance", 10.0))
    fov = float(camera.get("fov", 45.0))
    cam = Camera(
        mode=mode,
        target=target,
        yaw=float(camera.get("yaw", 0.0)),
        pitch=float(camera.get("pitch", 0.0)),
        distance=distance,
        fov=fov,
        height=float(camera.get("height", 2 * distance * math.tan(math.radians(fov) / 2))),
    )
    img = render(scene, size=(int(width), int(height)), camera=cam,
                 bg=tuple(background) if background else "white",
                 ground=False, shadows=mode != "2d")
    buf = io.BytesIO()
    if fmt == "jpg":
        img.convert("RGB").save(buf, format="JPEG", quality=92)
    else:
        img.save(buf, format="PNG")
    return buf.getvalue()


def warm_up() -> None:
    """Compile the numba kernels of tracing, interpreting and meshing once, so that the
    first client does not pay for it inside its time cap."""
    from .._jit import compiled

    # a warm-up must never take the server down; small work would otherwise run
    # interpreted on a cold cache and compile nothing
    with contextlib.suppress(Exception), compiled():
        _warm_up()


def _warm_up() -> None:
    from ..data import examples

    s = Session("warm-up")
    text = "axiom = F\nF -> F[+F][&F]F\n"
    for ex in examples():
        if ex.name.endswith("source-code-2"):
            text = ex.path.read_text(encoding="utf-8")
    s.program = load_program(text, dialect=None, filename="warm-up.lsys")
    for trace in (True, False):
        s.derivation = new_derivation(s.program, seed=1, limits=Limits(), trace=trace)
        s.drawn = None
        advance(s, 2, Limits(time_cap=600.0))
        mesh(s, Limits())


def syntax_error_payload(exc: LSystemSyntaxError) -> dict:
    return {
        "error": "syntax",
        "message": exc.message,
        "line": exc.line,
        "column": exc.column,
        "detail": str(exc),
    }
