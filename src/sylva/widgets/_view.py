"""The interactive three.js view of plants, trees, scenes and worlds (an anywidget widget)."""

from __future__ import annotations

import contextlib
import io
import json
import threading
import time
from collections.abc import Callable
from functools import cache
from importlib.resources import files

import anywidget
import traitlets

from ..errors import SylvaError

__all__ = ["PlantView", "esm", "glb_bytes", "view"]

#: The triangle budget of one view (a browser holds this comfortably).
MAX_TRIANGLES = 3_000_000


@cache
def esm() -> str:
    """The widget's ES module: ``widget.js`` with the studio's three.js bundle and Viewer
    inlined (so the notebook needs no network and no server of sylva's)."""
    static = files("sylva") / "studio" / "static"  # read, not imported (no server)
    three = (static / "vendor" / "three.js").read_text(encoding="utf-8")
    viewer = (static / "viewer.js").read_text(encoding="utf-8")
    if '"./vendor/three.js"' not in viewer:  # pragma: no cover - a guard for the studio's edits
        raise SylvaError("sylva.studio's viewer.js no longer imports \"./vendor/three.js\"")
    src = (files("sylva") / "widgets" / "widget.js").read_text(encoding="utf-8")
    return src.replace("__THREE_SOURCE__", json.dumps(three)).replace(
        "__VIEWER_SOURCE__", json.dumps(viewer))


def glb_bytes(scene) -> bytes:
    """A scene as binary glTF bytes (what the view sends)."""
    from ..geometry.exchange import write_glb

    buf = io.BytesIO()
    write_glb(scene, buf)
    return buf.getvalue()


class _Latest:
    """Runs ``work(request)`` in a background thread, always on the newest request.

    Requests that arrive while one is being worked on replace each other, so a slider
    dragged through fifty values costs two derivations, not fifty, and the kernel is never
    blocked.  ``done(request, result, error)`` is called in the thread: ``error`` is the
    message of a :class:`SylvaError` (or of any other failure), never a traceback.
    """

    def __init__(self, work: Callable, done: Callable) -> None:
        self._work, self._done = work, done
        self._lock = threading.Lock()
        self._pending = None
        self._has_pending = False
        self._thread: threading.Thread | None = None
        self._idle = threading.Event()
        self._idle.set()

    def submit(self, request) -> None:
        with self._lock:
            self._pending, self._has_pending = request, True
            self._idle.clear()
            if self._thread is None:
                self._thread = threading.Thread(target=self._run, name="sylva-widget",
                                                daemon=True)  # fmt: skip
                self._thread.start()

    def _run(self) -> None:
        while True:
            with self._lock:
                if not self._has_pending:
                    self._thread = None
                    self._idle.set()
                    return
                req, self._pending, self._has_pending = self._pending, None, False
            try:
                result, error = self._work(req), None
            except SylvaError as exc:
                result, error = None, str(exc)
            except Exception as exc:  # noqa: BLE001 - shown in place, never a traceback
                result, error = None, f"{type(exc).__name__}: {exc}"
            with contextlib.suppress(Exception):  # a closed comm must not kill the worker
                self._done(req, result, error)

    def wait(self, timeout: float | None = None) -> bool:
        """Wait until every request is done; False on timeout."""
        return self._idle.wait(timeout)


class PlantView(anywidget.AnyWidget):
    """A three.js view of a mesh that Python can replace (a derivation step, a slider).

    Parameters
    ----------
    build : callable, optional
        ``build(step) -> Scene``: the scene at a derivation step; the step slider is shown
        when ``max_steps > 0``.  Called in a background thread.
    scene : Scene, optional
        A fixed scene (no slider).
    step, max_steps : int
        The step shown and the slider's end.
    camera : {"perspective", "orthographic", "2d"}
    height : int
        Pixels.

    The traits ``status`` (counts and timings of the mesh shown), ``error`` (why the last
    request failed; the mesh before it stays) and ``busy`` are shown under the view.
    """

    _esm = esm()
    glb = traitlets.Bytes(b"").tag(sync=True)
    segments = traitlets.Bytes(b"").tag(sync=True)
    #: The preview while a slider is dragged: the branches as lines (:mod:`sylva._lines`).
    lines = traitlets.Bytes(b"").tag(sync=True)
    step = traitlets.Int(0).tag(sync=True)
    max_steps = traitlets.Int(0).tag(sync=True)
    camera = traitlets.Unicode("perspective").tag(sync=True)
    height = traitlets.Int(420).tag(sync=True)
    status = traitlets.Unicode("").tag(sync=True)
    error = traitlets.Unicode("").tag(sync=True)
    busy = traitlets.Bool(False).tag(sync=True)
    #: Filled by the front end: milliseconds from receiving a mesh to its frame, and frames.
    draw_ms = traitlets.Float(0.0).tag(sync=True)
    frames = traitlets.Int(0).tag(sync=True)
    #: Filled by the front end: what the last frame drew ("glb", "segments", "preview").
    shown = traitlets.Unicode("").tag(sync=True)
    #: Seconds a preview rests before the full frame replaces it.
    settle = 0.3

    def __init__(self, build: Callable | None = None, *, scene=None, step: int = 0,
                 max_steps: int = 0, camera: str = "perspective", height: int = 420,
                 animated: Callable | None = None, mesh: Callable | None = None,
                 instanced: bool | None = None, request_now: bool = True) -> None:  # fmt: skip
        _check_camera(camera)
        if isinstance(height, bool) or not isinstance(height, int) or not 60 <= height <= 4000:
            raise SylvaError(f"height: expected a whole number of pixels in 60..4000, "
                             f"got {height!r}")  # fmt: skip
        super().__init__(step=step, max_steps=max_steps, camera=camera, height=height)
        self._build = build
        self._mesh = mesh or _default_mesh
        self.instanced = instanced
        self._params: dict = {}
        self._worker = _Latest(self._work, self._finish)
        # the previews: the newest request's number, the geometry the last preview drew (for
        # its full frame) and whether no full frame is still to come
        self._token = 0
        self._previewed = None
        self._settled = threading.Event()
        self._settled.set()
        self._tlock = threading.Lock()
        self.timings: dict[str, float] = {}
        self._shown_step = step
        if scene is not None:
            self._set_scene(scene, glb_bytes(scene) if animated is None else animated())
        elif build is not None and request_now:
            self.request(step)
        self.observe(self._on_step, names="step")

    # ------------------------------------------------------------------ requests
    def _on_step(self, change) -> None:
        new = change["new"]
        if not 0 <= new <= self.max_steps:
            self.error = f"step: expected 0..{self.max_steps}, got {new}"
            self.step = self._shown_step
            return
        if self._build is not None and new != self._shown_step:
            self.request(new)

    def request(self, step: int | None = None, **params) -> None:
        """Ask for the scene at ``step`` (and ``params``, for :func:`explore`; they are kept
        for later requests) without waiting: the mesh changes when it is ready."""
        self._submit(step, params, "full")

    def request_preview(self, step: int | None = None, **params) -> None:
        """As :meth:`request`, for a slider being dragged: a plant drawn as instanced
        branches is sent first as its lines (the ``lines`` trait, drawn in a fraction of
        the time), and its full frame follows when no newer request came for
        :attr:`settle` seconds; anything else is sent as :meth:`request` sends it."""
        self._submit(step, params, "preview")

    def _submit(self, step, params, mode) -> None:
        self._params.update(params)
        self.busy = True
        self._settled.clear()
        with self._tlock:
            self._token += 1
            self._worker.submit((self.step if step is None else step, dict(self._params),
                                 mode, self._token))

    def _settle_later(self, req) -> None:
        def final():
            with self._tlock:
                if req[3] != self._token:
                    return  # a newer request came: it brings its own full frame
                self._worker.submit((req[0], req[1], "final", req[3]))

        t = threading.Timer(self.settle, final)
        t.daemon = True
        t.start()

    def wait(self, timeout: float | None = 60.0) -> bool:
        """Wait for the requests in flight and the full frame after a preview (for scripts
        and tests)."""
        t0 = time.monotonic()
        while True:
            left = None if timeout is None else max(0.0, timeout - (time.monotonic() - t0))
            if not self._worker.wait(left):
                return False
            left = None if timeout is None else max(0.0, timeout - (time.monotonic() - t0))
            if not self._settled.wait(left):
                return False
            if self._worker.wait(0):  # nothing submitted meanwhile
                return True

    def _work(self, req):
        from .._lines import line_bytes
        from ..geometry.mesh import Scene

        step, params, mode, _token = req
        t0 = time.perf_counter()
        done = self._previewed
        if mode == "final" and done is not None and done[0] == (step, params):
            built = done[1]  # what the preview drew: no derivation again
        else:
            built = self._build(step, **params)
        self._previewed = None
        t1 = time.perf_counter()
        timings = {"derive_ms": (t1 - t0) * 1e3}
        if not isinstance(built, Scene):  # a Geometry: instanced when big, else meshed
            if mode == "preview" and _instanced(built, self.instanced):
                data = line_bytes(built)
                t2 = time.perf_counter()
                self._previewed = ((step, params), built)
                timings.update(mesh_ms=0.0, serialise_ms=(t2 - t1) * 1e3)
                return step, built, ("lines", data), timings
            if _instanced(built, self.instanced):
                data = segment_bytes(built)
                t2 = time.perf_counter()
                timings.update(mesh_ms=0.0, serialise_ms=(t2 - t1) * 1e3)
                return step, built, ("segments", data), timings
            built = self._mesh(built)
        t2 = time.perf_counter()
        if built.n_triangles > MAX_TRIANGLES:
            raise SylvaError(f"{built.n_triangles:,} triangles are more than the view's "
                             f"{MAX_TRIANGLES:,}: fewer steps, or save() it to a file")
        data = glb_bytes(built)
        t3 = time.perf_counter()
        timings.update(mesh_ms=(t2 - t1) * 1e3, serialise_ms=(t3 - t2) * 1e3)
        return step, built, ("glb", data), timings

    def _finish(self, req, result, error) -> None:
        previewed = error is None and result[2][0] == "lines"
        if error is not None:
            self.error = error
            self.step = self._shown_step
        else:
            step, scene, data, timings = result
            self.timings = timings
            self._shown_step = step
            self.step = step
            self.error = ""
            self._set_scene(scene, data)
        if previewed:
            self._settle_later(req)  # busy until the full frame is sent
        else:
            self.busy = False
            with self._tlock:
                if req[3] == self._token:
                    self._settled.set()

    def _set_scene(self, scene, data) -> None:
        kind, data = data if isinstance(data, tuple) else ("glb", data)
        what = {"glb": lambda: f"{scene.n_triangles:,} triangles",
                "segments": lambda: f"{scene.n_segments:,} branches (instanced)",
                "lines": lambda: f"{scene.n_segments:,} branches as lines (preview)"}[kind]()
        self.status = what + (f", step {self.step}" if self.max_steps else "")
        # the new data first: the front end draws a trait that changes to non-empty (and
        # draws nothing for the others emptied after it)
        setattr(self, kind, data)
        for other in ("glb", "segments", "lines"):
            if other != kind:
                setattr(self, other, b"")


#: Plants with more branches than this (and nothing but branches) are drawn instanced.
INSTANCE_FROM = 10_000


def _instanced(geometry, instanced) -> bool:
    plain = not (geometry.n_leaves or geometry.n_polygons or geometry.n_blocks)
    if instanced is None:
        return plain and geometry.n_segments > INSTANCE_FROM
    return bool(instanced) and plain


def segment_bytes(geometry) -> bytes:
    """The branches as float32 rows ``start xyz, end xyz, r0, r1, linear rgb`` (11 floats
    each): what the front end draws as instanced cylinders (seed 001 §6.7's shared prism
    with per-segment instance data), a fraction of the bytes of their mesh; a chain of
    branches of one width is one row (:func:`sylva._lines.branch_rows`)."""
    from .._lines import branch_rows

    return branch_rows(geometry)


def _check_camera(camera) -> None:
    if camera not in ("perspective", "orthographic", "2d"):
        raise SylvaError(f"camera: expected 'perspective', 'orthographic' or '2d', "
                         f"got {camera!r}")  # fmt: skip


def _default_mesh(geometry):
    from ..geometry.build import build_mesh

    return build_mesh(geometry)


def _plant_builder(plant):
    """``build(step)`` for a :class:`sylva.plant.Plant`: the turtle's geometry of its
    program grown to ``step``, and how to mesh it as the plant was."""
    from ..geometry.build import build_mesh
    from ..plant import grow_geometry

    def build(step: int, **_):
        return grow_geometry(plant.program, step, seed=plant.seed)[-1]

    def mesh(geometry):
        return build_mesh(geometry, detail=plant._detail, mode=plant._mode, taper=plant._taper)

    return build, mesh


def view(obj, *, height: int = 420, camera: str | None = None, wind: bool = True,
         instanced: bool | None = None) -> PlantView:
    """An interactive view of a plant, tree, world, scene or mesh.

    A :class:`sylva.plant.Plant` gets a step slider (its derivation from the axiom to its
    step; with more than :data:`INSTANCE_FROM` branches, or ``instanced=True``, the branches
    go as instanced cylinders, else as its mesh); a tree plays in the wind (``wind=False``
    for a still one); anything else with a ``scene`` (or a
    :class:`~sylva.geometry.mesh.Scene` or ``Mesh``) is shown as it is.

    Examples
    --------
    >>> import sylva
    >>> from sylva.widgets import view
    >>> v = view(sylva.grow("axiom = F\\nF -> F[+F]F[-F]F", 2))
    >>> v.wait() and (v.step, v.max_steps, v.glb[:4])
    (2, 2, b'glTF')
    """
    from ..geometry.mesh import Mesh, Scene
    from ..grown import TreePlant
    from ..plant import Plant

    if isinstance(obj, Plant):
        plant = obj
        cam = camera or ("2d" if plant.is_2d else "perspective")
        build, mesh = _plant_builder(plant)
        v = PlantView(build, step=plant.steps, max_steps=plant.steps, camera=cam,
                      height=height, mesh=mesh, instanced=instanced,
                      request_now=False)  # fmt: skip
        if not _instanced(plant.geometry, instanced):  # the mesh it has already
            v._set_scene(plant.scene, glb_bytes(plant.scene))
        else:
            v._set_scene(plant.geometry, ("segments", segment_bytes(plant.geometry)))
        return v
    if isinstance(obj, TreePlant) and wind:
        from ..tree import Wind
        from ..tree.animation import wind_animation

        def animated() -> bytes:
            from ..geometry.exchange.gltf_animation import write_animated_glb

            anim = wind_animation(obj.mesh, Wind(obj.wind or 1.0, seed=obj.seed), 4.0, 12.0)
            buf = io.BytesIO()
            write_animated_glb(anim, buf)
            return buf.getvalue()

        return PlantView(scene=obj.scene, camera=camera or "perspective", height=height,
                         animated=animated)  # fmt: skip
    if isinstance(obj, Mesh):
        obj = Scene([obj])
    scene = obj if isinstance(obj, Scene) else getattr(obj, "scene", None)
    if not isinstance(scene, Scene):
        raise SylvaError(f"view: expected a plant, tree, world, Scene or Mesh, got "
                         f"{type(obj).__name__}")  # fmt: skip
    return PlantView(scene=scene, camera=camera or "perspective", height=height)
