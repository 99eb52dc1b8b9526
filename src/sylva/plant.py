"""From an L-system to a mesh in one call: derive, apply render rules, interpret, build.

This is the pipeline every front end shares (the command line, the gallery, the studio,
and :func:`sylva.grow`).  A :class:`Plant` renders, saves and shows itself:

>>> from sylva.plant import grow
>>> plant = grow("rot = 25.7\\naxiom = F\\nF -> F[+F]F", steps=2, seed=1)
>>> plant.geometry.n_segments, plant.scene.n_triangles > 0
(9, True)
>>> plant.is_2d
True
>>> plant.stats["modules"], plant.stats["steps"]
(21, 2)
"""

from __future__ import annotations

import os
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ._shown import Shown, check_size
from .errors import SylvaError
from .geometry.build import build_mesh
from .geometry.mesh import Scene
from .geometry.records import Geometry
from .lsystem import DEFAULT_MODULE_LIMIT, Derivation, ModuleString, Program, load
from .lsystem.engine import check_steps
from .lsystem.environment import has_communication, has_queries
from .turtle import interpret, trace

__all__ = [
    "Plant", "derive", "environment_for", "grow", "grow_geometry", "growth_scenes", "is_2d",
    "plant_texture", "query_for", "resolve", "texture_segments", "turtle_locate",
    "turtle_query",
]  # fmt: skip

#: Symbols that leave the plane (seed 001 §5.3: the camera is 2D when none is used).
_3D_SYMBOLS = frozenset("^&\\/$")


def resolve(source: Program | str | os.PathLike, *, dialect: str | None = None) -> Program:
    """A program from a Program, a path, a built-in example's name, or L-system text."""
    if isinstance(source, Program):
        return source
    if isinstance(source, os.PathLike) or (
        isinstance(source, str) and "\n" not in source and Path(source).exists()
    ):
        return load(Path(source), dialect=dialect)
    if isinstance(source, str) and "\n" not in source and "=" not in source:
        from .data import find

        try:
            return load(find(source).path, dialect=dialect)
        except SylvaError:
            raise SylvaError(
                f"{source}: no such file, and no built-in example of that name "
                "(`sylva examples` lists them)"
            ) from None
    return load(str(source), dialect=dialect)


def is_2d(program: Program) -> bool:
    """True when no rule, axiom or render rule uses a symbol that leaves the plane."""
    if program.turtle == "engine":
        return False
    symbols = {m.symbol for m in program.axiom}
    for r in program.rules:
        symbols.update(m.symbol for m in r.successor)
    return not (symbols & _3D_SYMBOLS)


@dataclass(repr=False)
class Plant(Shown):
    """A grown plant: the program, its word, what the turtle drew and the meshes.

    Besides its parts it has the methods of the one-line API (see :class:`sylva._shown.Shown`):
    :meth:`render` (a PIL image), :meth:`save` (an image or any export format, by
    extension), :meth:`animate` (a GIF or MP4 of its growth or a turntable), :meth:`show`
    (the notebook's three.js view), :attr:`stats`; in a notebook it displays as an image.
    """

    program: Program
    seed: int
    steps: int
    word: ModuleString
    render_word: ModuleString
    geometry: Geometry
    scene: Scene
    _detail: int | None = None
    _mode: str = "tube"
    _taper: str | None = None

    @property
    def is_2d(self) -> bool:
        return is_2d(self.program)

    def with_min_radius(self, radius: float) -> Plant:
        """The same plant with every branch at least ``radius`` thick (for line drawings
        of 2D systems, whose unit-thin branches vanish at image scale)."""
        import dataclasses

        g = dataclasses.replace(self.geometry)
        g.seg_radius = np.maximum(self.geometry.seg_radius, np.float32(radius))
        scene = build_mesh(g, detail=self._detail, mode=self._mode, taper=self._taper)
        return dataclasses.replace(self, geometry=g, scene=scene)

    def line_radius(self, pixels: float, size: tuple[int, int]) -> float:
        """The radius that is ``pixels`` wide when the plant fills an image of ``size``."""
        lo, hi = (self.scene.bounds(skip=("background",)) if self.scene.meshes
                  else self.geometry.bounds())  # fmt: skip
        extent = float(np.max(np.asarray(hi) - np.asarray(lo)))
        return 0.5 * pixels * extent / max(1, min(size))

    @property
    def background(self) -> tuple[float, float, float]:
        """The program's ``bg`` (seed 001), else white."""
        bg = self.program.settings.get("bg")
        return tuple(float(c) for c in bg) if bg is not None else (1.0, 1.0, 1.0)

    # ------------------------------------------------------------------ the one-line API
    @property
    def stats(self) -> dict:
        """Counts and extent: ``name``, ``steps``, ``seed``, ``modules``, ``segments``,
        ``leaves``, ``triangles``, ``size`` (the extent along x, y, z)."""
        if self.scene.meshes:
            lo, hi = self.scene.bounds()
            extent = [round(float(b - a), 6) for a, b in zip(lo, hi, strict=True)]
        else:
            extent = [0.0, 0.0, 0.0]
        return {
            "name": self.program.name, "steps": self.steps, "seed": self.seed,
            "modules": len(self.word), "segments": int(self.geometry.n_segments),
            "leaves": int(getattr(self.geometry, "n_leaves", 0)),
            "triangles": int(self.scene.n_triangles), "size": extent,
        }  # fmt: skip

    def _camera_mode(self) -> str:
        return "2d" if self.is_2d else "perspective"

    def _render_options(self, size: tuple[int, int]) -> dict:
        return {"bg": self.background}

    def _render_scene(self, mode: str, size: tuple[int, int]):
        if mode == "2d" and self.geometry.n_segments:
            # unit-thin branches of 2D systems vanish at image scale: 2 pixels at least
            return self.with_min_radius(self.line_radius(2.0, size)).scene
        return self.scene

    def _write(self, path, fmt: str, options: dict) -> None:
        from .geometry.exchange import write

        write(self.geometry if fmt == "svg" else self.scene, path, format=fmt, **options)

    def animate(self, path, *, kind: str = "growth", size=(640, 480), fps: float = 12.0,
                substeps: int = 1, frames: int = 48, camera=None, **options) -> Path:
        """Write a GIF or MP4 of the plant growing (one frame per step, or ``substeps``
        smooth frames per step) or, with ``kind="turntable"``, of the camera orbiting it.

        ``options`` go to :func:`sylva.render.render`.  Returns the path written.
        """
        from .render import growth_frames, turntable_frames, write_animation

        path = Path(path)
        if path.suffix.lower() not in (".gif", ".mp4", ".m4v", ".mov"):
            raise SylvaError(f"{path}: an animation must end in .gif or .mp4")
        if kind not in ("growth", "turntable"):
            raise SylvaError(f"kind: expected 'growth' or 'turntable', got {kind!r}")
        if isinstance(substeps, bool) or not isinstance(substeps, int) or substeps < 1:
            raise SylvaError(f"substeps: expected a whole number >= 1, got {substeps!r}")
        if not fps > 0:
            raise SylvaError(f"fps: expected a positive number, got {fps!r}")
        size = check_size(size)
        mode = camera or self._camera_mode()
        opts = {**self._render_options(size), **options}
        if kind == "turntable":
            if isinstance(frames, bool) or not isinstance(frames, int) or frames < 2:
                raise SylvaError(f"frames: expected a whole number >= 2, got {frames!r}")
            out = turntable_frames(self.scene, frames, size,
                                   "perspective" if mode == "2d" else mode, **opts)
        else:
            scenes = list(growth_scenes(self.program, self.steps, seed=self.seed,
                                        substeps=substeps, detail=self._detail,
                                        mode=self._mode))
            out = growth_frames(scenes, size, mode, **opts)
        write_animation(out, path, fps=fps, progress=False)
        return path


def turtle_query(program: Program, *, seed: int | None = None):
    """The query callback of :class:`~sylva.lsystem.Derivation` that asks the turtle.

    It interprets the word as derived (render and interpretation rules are not applied)
    with ``program``'s turtle, and gives each query module the turtle's state at it:
    ``?P`` its position, ``?H`` / ``?U`` / ``?L`` its heading, up and left vectors
    (:func:`sylva.turtle.trace`; the turtle draws nothing for a query module).

    Examples
    --------
    >>> from sylva.lsystem import Derivation, loads
    >>> p = loads("axiom = F(1)+(90)F(2)?P(0,0,0)?H(0,0,0)")
    >>> d = Derivation(p, query=turtle_query(p))
    >>> (d.word.values[-6:].round(9) + 0.0).tolist()   # ?P: (-2, 1, 0); ?H: -X
    [-2.0, 1.0, 0.0, -1.0, 0.0, 0.0]
    """
    rows = {"?H": 0, "?L": 1, "?U": 2}

    def query(word: ModuleString, index: np.ndarray) -> np.ndarray:
        t = trace(_drawn(word, program), program, seed=seed)
        out = np.empty((index.size, 3))
        names = word.alphabet.names
        kind = np.array([names[i] for i in word.ids[index]])
        pos = kind == "?P"
        out[pos] = t.positions[index[pos]]
        for name, row in rows.items():
            sel = kind == name
            out[sel] = t.frames[index[sel], row]
        return out + 0.0  # no negative zeros

    return query


def _drawn(word: ModuleString, program: Program) -> ModuleString:
    """The word as the turtle reads it: a sub-L-system's end ``$`` draws nothing."""
    if any(r.lsystem for r in program.rules):
        from .lsystem._sublsystems import silence

        return silence(word)
    return word


def _has_leaves(word: ModuleString, program: Program) -> bool:
    """Whether the turtle draws a leaf or surface anywhere in ``word``."""
    from .turtle import TABLES
    from .turtle import tables as T

    table = TABLES.get(program.turtle, {})
    ids = [word.alphabet.get(sym) for sym, op in table.items() if op in (T.SURFACE, T.LEAF)]
    ids = [i for i in ids if i >= 0]
    return bool(ids) and bool(np.isin(word.ids, ids).any())


def turtle_locate(program: Program, *, seed: int | None = None, organs: bool | str = False):
    """The ``locate`` callback of :class:`~sylva.lsystem.Derivation`: the turtle's
    position and frame (rows H, L, U) at the communication modules ``?E`` of a word, for
    an open L-system's environment (the word as derived, like :func:`turtle_query`).
    With ``organs``, also the plant's organs that cast shadow in the light environment:
    each leaf's centre (half its size along its heading) and each segment's midpoint
    (:attr:`~sylva.lsystem.environment.Communication.organs`); ``organs="leaves"`` skips
    the drawing when the word has no leaf (its segments are then not wanted).

    Examples
    --------
    >>> from sylva.lsystem import loads
    >>> from sylva.lsystem.lstring import ModuleString
    >>> p = loads("axiom = F")
    >>> pos, frames = turtle_locate(p)(ModuleString.from_text("F(2)?E(0)"), np.array([1]))
    >>> pos.round(9).tolist(), frames[0, 0].round(9).tolist()
    ([[0.0, 2.0, 0.0]], [0.0, 1.0, 0.0])
    """

    def locate(word: ModuleString, index: np.ndarray) -> tuple[np.ndarray, ...]:
        drawn = _drawn(word, program)
        t = trace(drawn, program, seed=seed)
        if not organs:
            return t.positions[index] + 0.0, t.frames[index] + 0.0
        if organs == "leaves" and not _has_leaves(drawn, program):  # nothing to cast
            return (t.positions[index] + 0.0, t.frames[index] + 0.0, np.zeros((0, 3)),
                    np.zeros(0, np.int8))  # fmt: skip
        g = interpret(drawn, program, seed=seed)
        leaf = g.leaf_pos + g.leaf_frame[:, 0] * (0.5 * g.leaf_size.astype(np.float64))[:, None]
        seg = 0.5 * (g.seg_start + g.seg_end)
        kinds = np.concatenate([np.zeros(len(leaf), np.int8), np.ones(len(seg), np.int8)])
        return (t.positions[index] + 0.0, t.frames[index] + 0.0,
                np.concatenate([leaf, seg]), kinds)  # fmt: skip

    return locate


def environment_for(program: Program, seed: int | None = None, environment=None):
    """``(environment, locate)`` for :class:`~sylva.lsystem.Derivation`: ``environment``
    (a name such as ``"light"``, a function, or None for the program's own ``environment
    = …``, :func:`sylva.environments.resolve_environment`) and the turtle's
    :func:`turtle_locate`; ``(None, None)`` for a program without ``?E`` modules."""
    from .environments import resolve_environment

    if not has_communication(program):
        if environment is not None:  # a misspelt name is an error even where none is used
            resolve_environment(environment, program)
        return None, None

    env = resolve_environment(environment, program)
    if env is None:
        return None, None
    organs: bool | str = False
    if getattr(env, "wants_organs", False):
        organs = True if getattr(env, "segments", 0.0) > 0.0 else "leaves"
    return env, turtle_locate(program, seed=seed, organs=organs)


def _derivation(program: Program, seed, environment=None, **kw) -> Derivation:
    env, locate = environment_for(program, seed, environment)
    return Derivation(program, seed=seed, query=query_for(program, seed), environment=env,
                      locate=locate, **kw)  # fmt: skip


def query_for(program: Program, seed: int | None = None):
    """:func:`turtle_query` for a program with query modules, else None (the ``query``
    argument of :class:`~sylva.lsystem.Derivation` every front end passes)."""
    return turtle_query(program, seed=seed) if has_queries(program) else None


def derive(
    program: Program,
    steps: int | None = None,
    *,
    seed: int | None = None,
    limit: int = DEFAULT_MODULE_LIMIT,
    lineage: bool = False,
    environment=None,
) -> ModuleString:
    """:func:`sylva.lsystem.derive`, with the turtle answering the query modules and the
    environment the communication modules.

    A program with ``?P`` / ``?H`` / ``?U`` / ``?L`` modules is derived with
    :func:`turtle_query` (the word is interpreted after every step), one with ``?E``
    modules with ``environment`` (default: the program's ``environment = …``, see
    :func:`environment_for`); any other program exactly as :func:`sylva.lsystem.derive`
    derives it.
    """
    from .lsystem.engine import derive as _derive

    s = seed if seed is not None else program.seed
    q = query_for(program, s)
    env, locate = environment_for(program, s, environment)
    return _derive(program, steps, seed=seed, limit=limit, lineage=lineage, query=q,
                   environment=env, locate=locate)  # fmt: skip


def grow(
    source: Program | str | os.PathLike,
    steps: int | None = None,
    *,
    seed: int | None = None,
    detail: int | None = None,
    mode: str = "tube",
    taper: str | None = None,
    limit: int = DEFAULT_MODULE_LIMIT,
    environment=None,
) -> Plant:
    """Derive ``source`` and build its meshes.

    Parameters
    ----------
    source : Program, path, example name or text
    steps : int, optional
        Derivation steps (default: the program's own count, else 0).
    seed : int, optional
        Seed of the stochastic rules and of the engine turtle's angle variation (default:
        the program's ``seed``, else 1, so that a plant is reproducible unless asked).
    detail, mode, taper
        Passed to :func:`sylva.geometry.build.build_mesh`.
    limit : int
        The module limit of the derivation.
    environment : str or callable, optional
        The environment of an open L-system's ``?E`` modules: a built-in's name with
        options (``"light"``, ``"obstacle(shape = box)"``, ``"world"``;
        :mod:`sylva.environments`) or a function of a
        :class:`~sylva.lsystem.environment.Communication`.  Default: the program's
        ``environment = …``.
    """
    program, seed, n, word, rw, geometry = grow_geometry(source, steps, seed=seed, limit=limit,
                                                         environment=environment)  # fmt: skip
    dd = _detail(program, detail)
    scene = build_mesh(geometry, detail=dd, mode=mode, taper=taper)
    return Plant(program, seed, n, word, rw, geometry, scene, dd, mode, taper)


def grow_geometry(source, steps: int | None = None, *, seed: int | None = None,
                  limit: int = DEFAULT_MODULE_LIMIT, environment=None):
    """:func:`grow` up to the turtle, without the meshes.

    Returns
    -------
    (Program, seed, steps, word, render word, Geometry)
    """
    program = resolve(source)
    if seed is None:
        seed = program.seed if program.seed is not None else 1
    n = steps if steps is not None else (program.steps or 0)
    _check_count(n, "steps")
    _check_count(seed, "seed", signed=True)
    n = check_steps(program, steps, limit=limit)
    d = _derivation(program, seed, environment, limit=limit)
    d.advance(n)
    rw = d.render_word()
    return program, seed, n, d.word, rw, interpret(rw, program, seed=seed)


def _check_count(value, what: str, *, signed: bool = False) -> None:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or (
        not signed and value < 0
    ):
        kind = "a whole number" if signed else "a whole number >= 0"
        raise SylvaError(f"{what}: expected {kind}, got {value!r}")


def _detail(program: Program, detail: int | None) -> int | None:
    if detail is not None:
        return int(detail)
    return None


def growth_scenes(
    source: Program | str | os.PathLike,
    steps: int | None = None,
    *,
    seed: int | None = None,
    substeps: int = 1,
    detail: int | None = None,
    mode: str = "tube",
    limit: int = DEFAULT_MODULE_LIMIT,
    environment=None,
) -> Iterator[Scene]:
    """Scenes of a plant growing: one per derivation step, or ``substeps`` per step.

    With ``substeps > 1`` the growth is smooth: the segments drawn by modules that a step
    made (known from the derivation's trace) grow from nothing to their full length, so
    new branches extend out of the old ones instead of popping into place.  This works for
    every system whose drawing module takes its length as first parameter (``F(l)``).
    """
    program = resolve(source)
    if seed is None:
        seed = program.seed if program.seed is not None else 1
    n = check_steps(program, steps, limit=limit)
    smooth = substeps > 1 and program.turtle != "engine"
    d = _derivation(program, seed, environment, trace=smooth, limit=limit)
    dd = _detail(program, detail)

    def scene_of(word: ModuleString) -> Scene:
        return build_mesh(interpret(word, program, seed=seed), detail=dd, mode=mode)

    yield scene_of(d.render_word())
    for _ in range(n):
        d.advance(1)
        if not smooth:
            yield scene_of(d.render_word())
            continue
        rw, src = d.render_word_sources()
        fresh = d.origin_steps[src] == d.step
        for k in range(1, substeps + 1):
            t = k / substeps
            yield scene_of(_scale_fresh(rw, fresh, t, program) if t < 1 else rw)


def _scale_fresh(
    word: ModuleString, fresh: np.ndarray, t: float, program: Program
) -> ModuleString:
    """The word with the step length of fresh drawing modules scaled by ``t``."""
    draw = {"F", "G", "f", "g"}
    ids = [word.alphabet.get(s) for s in draw if s in word.alphabet]
    if not ids:
        return word
    is_draw = np.isin(word.ids, ids) & fresh
    if not is_draw.any():
        return word
    default = float(program.settings.get("len", 1.0))
    counts = word.nparams.copy()
    add = is_draw & (counts == 0)
    counts[add] = 1
    offsets = np.zeros(len(word) + 1, np.int64)
    np.cumsum(counts, out=offsets[1:])
    values = np.empty(offsets[-1], np.float64)
    old = word.offsets
    # every existing parameter moves to its module's new start plus its rank
    owner = np.repeat(np.arange(len(word)), word.nparams)
    rank = np.arange(word.values.shape[0]) - old[owner]
    values[offsets[owner] + rank] = word.values
    values[offsets[:-1][add]] = default
    first = offsets[:-1][is_draw]
    values[first] *= t
    return ModuleString(word.alphabet, word.ids, offsets, values)


# --------------------------------------------------------------------------- textures
#: Bark to leaf, one colour per colour index of the abop turtle (L-Studio's colour increment)
TEXTURE_PALETTE = ("#3b2414", "#4a2f1b", "#5b3a1f", "#4f5a24", "#2f5d1e", "#3f7a25", "#5d9b35",
                   "#8cc152")  # fmt: skip

def texture_segments(geometry: Geometry, *, width: float = 4.0):
    """The turtle's segments as a 2D line drawing for :mod:`sylva.texture` (seed 003 §4.8).

    Segments are projected onto the XY plane (where 2D systems are drawn); a segment's
    line is ``width`` pixels at the radius of the first segment and scales with its own
    radius (``!`` thins it); its palette index is its colour index (``;`` advances it), and
    its generation is its bracket depth.
    """
    from .texture.lsystem_texture import Segments

    n = geometry.n_segments
    r0 = float(geometry.seg_radius[0, 0]) if n else 1.0
    rad = geometry.seg_radius.mean(axis=1).astype(np.float64)
    return Segments(
        np.ascontiguousarray(geometry.seg_start[:, :2], np.float64),
        np.ascontiguousarray(geometry.seg_end[:, :2], np.float64),
        width * rad / (r0 if r0 > 0 else 1.0),
        geometry.seg_material.astype(np.int32),
        np.minimum(geometry.seg_depth, np.iinfo(np.int16).max).astype(np.int16),
    )


def plant_texture(
    source: Program | str | os.PathLike,
    shape: tuple[int, int] = (512, 512),
    *,
    steps: int | None = None,
    seed: int | None = None,
    width: float = 4.0,
    palette=None,
    background="#000000",
    tileable: bool = False,
    count: int = 1,
    size: float = 0.9,
    limit: int = DEFAULT_MODULE_LIMIT,
) -> np.ndarray:
    """An L-system texture from any sylva program (parametric, stochastic, any dialect).

    Seed 003's L-system textures with sylva's engine and turtle: the program is derived
    (``steps``, ``seed`` as in :func:`grow`), interpreted, and its segments drawn by
    :func:`sylva.texture.lsystem_texture.draw_segments` (see :func:`texture_segments`) in
    ``palette`` (indexed by the colour index that ``;`` advances; the default runs from
    bark to leaf over the 8 indices of the abop turtle); ``tileable`` scatters
    ``count`` copies over a seamless tile.  Leaves and polygons are not drawn.

    Returns
    -------
    ndarray, uint8, shape (H, W, 3)

    Examples
    --------
    >>> img = plant_texture("axiom = F\\nF -> F[+F]F[-F]F", (32, 48), steps=2)
    >>> img.shape
    (32, 48, 3)
    """
    from .texture.lsystem_texture import draw_segments

    program = resolve(source)
    if seed is None:
        seed = program.seed if program.seed is not None else 1
    d = _derivation(program, seed, None, limit=limit)
    d.advance(check_steps(program, steps, limit=limit))
    geometry = interpret(d.render_word(), program, seed=seed)
    return draw_segments(
        shape, texture_segments(geometry, width=width),
        palette=TEXTURE_PALETTE if palette is None else palette, background=background,
        tileable=tileable, count=count, size=size, seed=seed,
    )  # fmt: skip
