"""The Studio's ASGI application (Starlette): the JSON/GLB API and the static front end.

API (all under ``/api``; JSON unless said otherwise; errors are ``{"error": kind,
"message": text, ...}`` with a 4xx/5xx status):

=======================  =============================================================
``POST session``         with the page's token in ``X-Sylva-Page``: a new session,
                         ``{session}``, sent back in ``X-Sylva-Session`` by every call
                         below but ``info``, ``help`` and ``example``
``DELETE session``       the page is closed: its work stops, its memory is released
``GET  info``            dialects, limits, the built-in examples, the start-up file
``GET  help?turtle=``    the symbol table and the special variables of a command table
``POST load``            ``{text, dialect?, seed?, filename?, overrides?, steps?, trace?}``:
                         parse, make the session's derivation (and derive ``steps``)
``POST preview``         the body of ``load``, answered with the last step's branches as
                         lines (:mod:`sylva._lines`): the preview while a slider moves
``POST step``            ``{n}``: derive ``n`` more steps under the caps
``POST back``            one step back
``POST reset``           back to the axiom
``POST stop``            stop the running derivation of this session
``GET  state``           step, module count, globals, settings, camera hint, timings
``GET  word?start=&count=``  a page of the current word, one text per module
``GET  mesh``            the current (render) word as binary glTF (``model/gltf-binary``);
                         ``?instanced=1``: a plant of many branches as instanced rows
``POST pick``            ``{point}``: the module drawn there and the rule/step that made it
``GET  module?index=``   module ``index`` of the word: what it drew and its rule and step
``GET  export.FMT``      downloads of the mesh: ``glb``, ``obj``, ``scad`` (solids)
``POST export.png``      ``{width, height, camera, focus}``: a PNG rendered by the server
``GET  files``           the workspace's definition files
``GET  file?path=``      a file's text;  ``PUT file`` ``{path, text, overwrite}`` saves it
``GET  example?name=``   a built-in example's text
=======================  =============================================================

Every derivation, mesh and render runs in a worker thread of the fair scheduler
(:mod:`._scheduler`), never on the event loop: each session has one job at a time (a newer
request supersedes it, ``409 superseded``), the sessions take turns step by step, and a
request that cannot get a turn soon is answered ``503`` with ``Retry-After``.  Each job is
capped in worker time, modules and triangles; bodies and URLs are capped in size; a bad
body (not JSON, too deep, numbers out of range) is a ``400``; each client has its own
session, made only by the page, never evicted while active; and user text is only ever
parsed.
"""

from __future__ import annotations

import asyncio
import contextlib
import gc
import json
import math
import secrets
import sys
import time
from concurrent.futures import ThreadPoolExecutor
from importlib import resources
from pathlib import Path

from starlette.applications import Starlette
from starlette.middleware import Middleware
from starlette.middleware.trustedhost import TrustedHostMiddleware
from starlette.requests import Request
from starlette.responses import HTMLResponse, JSONResponse, Response, StreamingResponse
from starlette.routing import Mount, Route
from starlette.staticfiles import StaticFiles

from ..errors import LSystemSyntaxError, SylvaError
from . import _work
from ._help import help_tables
from ._limits import Limits
from ._scheduler import Busy, Scheduler, Superseded
from ._sessions import (
    HEADER,
    PAGE_HEADER,
    Session,
    SessionStore,
    TooManySessions,
    release_memory,
)
from ._workspace import Workspace, WorkspaceError

__all__ = ["create_app", "static_dir"]


def static_dir() -> Path:
    """The folder of the front end shipped in the package."""
    return Path(str(resources.files("sylva.studio") / "static"))


class ApiError(Exception):
    def __init__(self, status: int, kind: str, message: str, **extra) -> None:
        self.status, self.kind, self.message, self.extra = status, kind, message, extra
        super().__init__(message)


def _error(status: int, kind: str, message: str, **extra) -> JSONResponse:
    return JSONResponse({"error": kind, "message": message, **extra}, status_code=status)


# --------------------------------------------------------------------------- middleware
class _Guard:
    """Size limits on URLs and bodies, a same-origin check on writes, and the session token.

    The body is read here (at most ``max_body`` bytes) and replayed to the app, so no
    handler ever sees more.  The session token comes from the ``X-Sylva-Session`` header
    only: no session is made here (see ``POST /api/session``).
    """

    def __init__(self, app, limits: Limits) -> None:
        self.app = app
        self.limits = limits

    async def __call__(self, scope, receive, send):
        if scope["type"] != "http":
            return await self.app(scope, receive, send)
        limits = self.limits
        if len(scope.get("raw_path") or b"") + len(scope.get("query_string", b"")) \
                > limits.max_url:
            return await _error(414, "too_large", "the URL is too long")(scope, receive, send)
        headers = {k.decode("latin-1"): v.decode("latin-1") for k, v in scope["headers"]}
        method = scope["method"]
        if method not in ("GET", "HEAD", "OPTIONS"):
            origin = headers.get("origin")
            host = headers.get("host", "")
            if origin and origin.split("://", 1)[-1] != host:
                return await _error(403, "origin", "cross-origin writes are refused")(
                    scope, receive, send)
        try:
            declared = int(headers.get("content-length", "0") or 0)
        except ValueError:
            declared = 0
        if declared > limits.max_body:
            return await _error(413, "too_large",
                                f"the request body is larger than {limits.max_body:,} bytes")(
                scope, receive, send)
        body = bytearray()
        if method not in ("GET", "HEAD"):
            more = True
            while more:
                msg = await receive()
                if msg["type"] == "http.disconnect":
                    return None
                body += msg.get("body", b"")
                more = msg.get("more_body", False)
                if len(body) > limits.max_body:
                    return await _error(
                        413, "too_large",
                        f"the request body is larger than {limits.max_body:,} bytes")(
                        scope, receive, send)
        sent = False

        async def replay():
            nonlocal sent
            if not sent:
                sent = True
                return {"type": "http.request", "body": bytes(body), "more_body": False}
            return await receive()

        sid = headers.get(HEADER)
        scope.setdefault("state", {})["sid"] = sid if SessionStore.valid_id(sid) else None
        return await self.app(scope, replay, send)


# --------------------------------------------------------------------------- the app
_SUPERSEDED = "a newer request of this session replaced this one"
# a job on a word of more modules is expected to be long: it waits for a heavy lane
_HEAVY_WORD = 50_000


def _once(fn, *args, **kw):
    """A job of one piece: ``fn(*args, **kw)``."""

    def make(job):
        def gen():
            return fn(*args, **kw)
            yield  # pragma: no cover - makes this a generator

        return gen()

    return make


class Studio:
    """The state of one server: sessions, workspace, limits, the scheduler and pools."""

    def __init__(self, workspace: Workspace, limits: Limits, start_file: str | None) -> None:
        self.workspace = workspace
        self.limits = limits
        self.start_file = start_file
        self.sessions = SessionStore(limits.max_sessions, limits.idle_timeout)
        self.scheduler = Scheduler(limits.workers, max_wait=limits.max_wait)
        # small, quick work beside the jobs: file listings, reads and saves, word pages
        self.pool = ThreadPoolExecutor(2, thread_name_prefix="sylva-studio-io")
        # one thread owns the GL context of the offscreen renderer
        self.gl = ThreadPoolExecutor(1, thread_name_prefix="sylva-studio-gl")
        self.ready = asyncio.Event()  # set once the kernels are compiled (warm-up)
        # written into the page: only a client that read the page can open a session
        self.page_token = secrets.token_urlsafe(24)

    def close(self) -> None:
        self.sessions.close()
        self.scheduler.close()
        self.pool.shutdown(wait=True, cancel_futures=True)
        self.gl.shutdown(wait=True, cancel_futures=True)

    def session(self, request: Request) -> Session:
        s = self.sessions.get(request.scope["state"].get("sid"))
        if s is None:
            raise ApiError(401, "session", "this page has no session on the server (it "
                           "ended after being idle, or the server restarted); the page "
                           "opens a new one with POST /api/session")
        return s

    async def run(self, session: Session, make):
        """Run the job ``make(job)`` (a generator) for ``session`` through the fair
        scheduler and return its value; a newer request of the session supersedes it."""
        if not self.ready.is_set():
            # the first requests wait for the one-off compilation instead of paying for it
            # inside their time cap
            with contextlib.suppress(TimeoutError):
                await asyncio.wait_for(self.ready.wait(), timeout=600)
        d = session.derivation
        heavy = d is not None and len(d.word) > _HEAVY_WORD
        try:
            job = self.scheduler.submit(session, make, heavy=heavy)
        except Busy as exc:
            raise ApiError(503, "busy", str(exc), retry_after=exc.retry_after) from None
        try:
            value = await self.scheduler.result(job)
            # what the request spent waiting for its turns and working (state.timings)
            done = time.monotonic()
            session.timings["queue_ms"] = ((job.started or done) - job.submitted) * 1e3
            session.timings["work_ms"] = job.spent * 1e3
            session.timings["request_ms"] = (done - job.submitted) * 1e3
            return value
        except Superseded:
            raise ApiError(409, "superseded", _SUPERSEDED) from None
        except Busy as exc:
            raise ApiError(503, "busy", str(exc), retry_after=exc.retry_after) from None
        except _work.CapError as exc:
            if job.reason == "superseded":
                raise ApiError(409, "superseded", f"{_SUPERSEDED} ({exc})") from None
            raise

    async def light(self, fn, *args):
        """Quick work (files, a word page) in the small pool, off the event loop."""
        return await asyncio.get_running_loop().run_in_executor(self.pool, fn, *args)


def _release() -> None:
    gc.collect()
    release_memory()


def _studio(request: Request) -> Studio:
    return request.app.state.studio


def _finite(text: str) -> float:
    v = float(text)
    if not math.isfinite(v):
        raise ValueError(f"the number {text[:40]} is out of range")
    return v


def _integer(text: str) -> int:
    # an integer past the largest float (1 followed by 400 zeros) is as out of range as
    # 1e400: every handler that takes a number may turn it into a float
    v = int(text)
    if abs(v) > sys.float_info.max:
        raise ValueError(f"the number {text[:40]}... is out of range")
    return v


def _constant(name: str):
    raise ValueError(f"{name} is not a JSON number")


async def _json(request: Request) -> dict:
    body = await request.body()
    try:
        data = json.loads(body or b"{}", parse_float=_finite, parse_int=_integer,
                          parse_constant=_constant)
    except RecursionError:
        raise ApiError(400, "bad_request", "the JSON body is nested too deeply") from None
    except (ValueError, UnicodeDecodeError) as exc:
        detail = str(exc) if "range" in str(exc) or "JSON number" in str(exc) else ""
        raise ApiError(400, "bad_request", "the body is not valid JSON"
                       + (f": {detail}" if detail else "")) from None
    if not isinstance(data, dict):
        raise ApiError(400, "bad_request", "the body must be a JSON object")
    try:
        # a lone surrogate (\ud800) is no text: it could be neither parsed, saved nor
        # echoed back in an error message
        json.dumps(data, ensure_ascii=False).encode("utf-8")
    except UnicodeEncodeError:
        raise ApiError(400, "bad_request", "the body holds a lone UTF-16 surrogate "
                       "(such as \\ud800), which is not text") from None
    return data


def _int(value, name: str, lo: int, hi: int) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, float, str)):
        raise ApiError(400, "bad_request", f"{name} must be an integer")
    if isinstance(value, float) and not (math.isfinite(value) and value.is_integer()):
        raise ApiError(400, "bad_request", f"{name} must be an integer, not {value!r}")
    try:
        v = int(value)
    except (ValueError, OverflowError):
        raise ApiError(400, "bad_request", f"{name} must be an integer") from None
    if not lo <= v <= hi:
        raise ApiError(400, "bad_request", f"{name} must be in [{lo}, {hi}]")
    return v


def _need(session: Session) -> None:
    if session.derivation is None:
        raise ApiError(409, "no_program", "no L-system is loaded: load a definition first")


async def _state_response(studio: Studio, session: Session, status: int = 200, **extra):
    return JSONResponse({**_work.state(session), **extra}, status_code=status)


async def _derive(studio: Studio, session: Session, make) -> JSONResponse:
    try:
        await studio.run(session, make)
    except _work.CapError as exc:
        return JSONResponse({"error": exc.kind, "message": str(exc),
                             "state": _work.state(session)}, status_code=422)
    return await _state_response(studio, session)


# --------------------------------------------------------------------------- handlers
async def info(request: Request) -> JSONResponse:
    from ..data import examples

    studio = _studio(request)
    lim = studio.limits
    return JSONResponse({
        "dialects": list(_work.DIALECTS),
        "export_formats": _work.export_formats(),
        "examples": [{"name": e.name, "title": e.title, "file": e.path.name}
                     for e in examples()],
        "start_file": studio.start_file,
        "ready": studio.ready.is_set(),
        "sessions": len(studio.sessions),
        "limits": {"modules": lim.max_modules, "time_cap": lim.time_cap,
                   "steps": lim.max_steps, "text": lim.max_text, "body": lim.max_body,
                   "image_side": lim.max_image_side, "page": lim.page_size},
    })


async def help_(request: Request) -> JSONResponse:
    return JSONResponse(help_tables(request.query_params.get("turtle", "lsys")))


async def new_session(request: Request) -> JSONResponse:
    """``POST /api/session``: a session for a client that read this server's page."""
    studio = _studio(request)
    token = request.headers.get(PAGE_HEADER, "")
    if not secrets.compare_digest(token.encode("latin-1", "replace"),
                                  studio.page_token.encode("ascii")):
        raise ApiError(403, "page", "a session is opened by the Studio's own page: send the "
                       f"token of its <meta name=\"sylva-page\"> in the {PAGE_HEADER} header")
    try:
        s = studio.sessions.create()
    except TooManySessions as exc:
        raise ApiError(503, "busy", str(exc), retry_after=exc.retry_after) from None
    return JSONResponse({"session": s.id, "header": HEADER,
                         "idle_timeout": studio.limits.idle_timeout})


async def end_session(request: Request) -> JSONResponse:
    """``DELETE /api/session``: the page is closed; its work stops and its memory goes."""
    studio = _studio(request)
    sid = request.scope["state"].get("sid")
    s = studio.sessions.get(sid)
    if s is not None:
        studio.scheduler.stop(s)
        studio.sessions.drop(sid)
    return JSONResponse({"ended": s is not None})


async def _load_params(request: Request, studio: Studio) -> dict:
    """The checked body of a load (or preview) request."""
    data = await _json(request)
    text = data.get("text")
    if not isinstance(text, str):
        raise ApiError(400, "bad_request", "text must be the definition, a string")
    if len(text) > studio.limits.max_text:
        raise ApiError(413, "too_large",
                       f"the definition is longer than {studio.limits.max_text:,} characters")
    dialect = data.get("dialect") or None
    if dialect is not None and not isinstance(dialect, str):
        raise ApiError(400, "bad_request", "dialect must be a string")
    seed = data.get("seed")
    seed = None if seed in (None, "") else _int(seed, "seed", 0, 2**63 - 1)
    steps = _int(data.get("steps", 0), "steps", 0, studio.limits.max_steps)
    filename = data.get("filename") if isinstance(data.get("filename"), str) else None
    overrides = data.get("overrides") or {}
    if not isinstance(overrides, dict):
        raise ApiError(400, "bad_request", "overrides must map global names to numbers")
    trace = bool(data.get("trace", True))
    return {"text": text, "dialect": dialect, "seed": seed, "steps": steps,
            "filename": filename, "overrides": overrides, "trace": trace}


def _loading(session: Session, q: dict, limits: Limits, job):
    """Parse, load and derive ``q`` (a :func:`_load_params`) into the session; a job's
    generator.  The same request again, with the derivation still at its step (the full
    frame after a slider's preview), keeps what is there: derivation and turtle."""
    key = repr(sorted(q.items()))
    d = session.derivation
    if session.loaded == key and d is not None and d.step == q["steps"] \
            and session.text == q["text"]:
        return
    overrides = q["overrides"]
    program = _work.load_program(q["text"], dialect=q["dialect"], filename=q["filename"],
                                 overrides=overrides)
    d = _work.new_derivation(program, seed=q["seed"], limits=limits, trace=q["trace"])
    session.program, session.derivation = program, d
    session.text, session.filename = q["text"], q["filename"]
    session.overrides = {k: v for k, v in overrides.items() if k in program.constants}
    session.drawn, session.last_step, session.loaded = None, None, None
    session.timings = {}
    if q["steps"]:
        yield
        yield from _work.advancing(session, q["steps"], limits, job.used)
    session.loaded = key


async def load(request: Request) -> JSONResponse:
    studio = _studio(request)
    q = await _load_params(request, studio)
    session = studio.session(request)

    def make(job):
        yield from _loading(session, q, studio.limits, job)

    try:
        return await _derive(studio, session, make)
    except LSystemSyntaxError as exc:
        return JSONResponse(_work.syntax_error_payload(exc), status_code=400)
    except SylvaError as exc:
        return _error(400, "invalid", str(exc))


async def preview(request: Request) -> Response:
    """A load (the same body) answered with the preview of its last step: the branches as
    lines (:mod:`sylva._lines`, ``application/octet-stream``) in one round trip, with the
    step, modules and timings in ``x-sylva-*`` headers.  What the page draws while a
    slider is dragged; the full frame follows with ``load`` (kept, not derived again) and
    ``mesh``.  Errors are answered as ``load`` answers them (JSON)."""
    studio = _studio(request)
    q = await _load_params(request, studio)
    session = studio.session(request)
    limits = studio.limits

    def make(job):
        yield from _loading(session, q, limits, job)
        return (yield from _work.previewing(session, limits, job.used))

    try:
        data, turtle_ms, lines_ms = await studio.run(session, make)
    except _work.CapError as exc:
        return JSONResponse({"error": exc.kind, "message": str(exc),
                             "state": _work.state(session)}, status_code=422)
    except LSystemSyntaxError as exc:
        return JSONResponse(_work.syntax_error_payload(exc), status_code=400)
    except SylvaError as exc:
        return _error(400, "invalid", str(exc))
    d = session.derivation
    return _body(data, "application/octet-stream", {
        "x-sylva-kind": "lines",
        "x-sylva-step": str(d.step),
        "x-sylva-modules": str(len(d.word)),
        "x-sylva-derive-ms": f"{session.timings.get('derive_ms', 0.0):.1f}",
        "x-sylva-turtle-ms": f"{turtle_ms:.1f}",
        "x-sylva-lines-ms": f"{lines_ms:.1f}",
    })


async def step(request: Request) -> JSONResponse:
    studio = _studio(request)
    data = await _json(request)
    n = _int(data.get("n", 1), "n", 0, studio.limits.max_steps)
    session = studio.session(request)
    _need(session)
    return await _derive(studio, session, lambda job: _work.advancing(
        session, n, studio.limits, job.used))


async def back(request: Request) -> JSONResponse:
    studio = _studio(request)
    session = studio.session(request)
    _need(session)
    await studio.run(session, _once(_work.back, session))
    return await _state_response(studio, session)


async def reset(request: Request) -> JSONResponse:
    studio = _studio(request)
    session = studio.session(request)
    _need(session)

    def do():
        session.derivation.reset()
        session.last_step = None

    await studio.run(session, _once(do))
    return await _state_response(studio, session)


async def stop(request: Request) -> JSONResponse:
    studio = _studio(request)
    session = studio.session(request)
    return JSONResponse({"stopping": studio.scheduler.stop(session)})


async def state(request: Request) -> JSONResponse:
    studio = _studio(request)
    session = studio.session(request)
    _need(session)
    return await _state_response(studio, session)


async def word(request: Request) -> JSONResponse:
    studio = _studio(request)
    session = studio.session(request)
    _need(session)
    q = request.query_params
    start = _int(q.get("start", 0), "start", 0, 2**62)
    count = _int(q.get("count", 500), "count", 1, studio.limits.page_size)
    # a page is quick and reads an immutable word: it does not wait for the session's job
    page = await studio.light(_work.word_page, session, start, count, studio.limits)
    return JSONResponse(page)


def _after_mesh(session: Session, limits: Limits, fn=None, *args, full: bool = True, **kw):
    """A job that builds the mesh (in turns) and then does ``fn(*args, **kw)``."""

    def make(job):
        drawn = yield from _work.meshing(session, limits, job.used, full=full)
        return drawn if fn is None else fn(*args, **kw)

    return make


async def _with_mesh(studio: Studio, session: Session, fn=None, *args, full: bool = True,
                     **kw):
    try:
        return await studio.run(session, _after_mesh(session, studio.limits, fn, *args,
                                                     full=full, **kw))
    except _work.CapError as exc:
        raise ApiError(422, exc.kind, str(exc)) from None


_CHUNK = 1 << 20


def _body(data: bytes, media_type: str, headers: dict) -> Response:
    """``data`` as the answer; a large one is sent a megabyte at a time, so that the event
    loop never copies a whole mesh into the socket's buffer at once (holding the GIL while
    every other client waits)."""
    if len(data) <= _CHUNK:
        return Response(data, media_type=media_type, headers=headers)
    view = memoryview(data)

    async def chunks():
        for i in range(0, len(view), _CHUNK):
            yield view[i:i + _CHUNK]

    return StreamingResponse(chunks(), media_type=media_type,
                             headers={**headers, "content-length": str(len(data))})


async def mesh(request: Request) -> Response:
    studio = _studio(request)
    session = studio.session(request)
    _need(session)
    # the page takes a large plant of branches as instanced rows (?instanced=1)
    full = request.query_params.get("instanced") not in ("1", "true")
    drawn = await _with_mesh(studio, session, full=full)
    if drawn.segments is not None and not full:
        return _body(drawn.segments, "application/octet-stream", {
            "x-sylva-kind": "segments",
            "x-sylva-step": str(drawn.step),
            "x-sylva-triangles": str(drawn.triangles),
            "x-sylva-mesh-ms": f"{drawn.mesh_ms:.1f}",
            "cache-control": "no-store",
        })
    return _body(drawn.glb, "model/gltf-binary", {
        "x-sylva-kind": "glb",
        "x-sylva-step": str(drawn.step),
        "x-sylva-triangles": str(drawn.triangles),
        "x-sylva-mesh-ms": f"{drawn.mesh_ms:.1f}",
        "x-sylva-sides": str(drawn.sides or ""),
        "cache-control": "no-store",
    })


async def pick(request: Request) -> JSONResponse:
    studio = _studio(request)
    data = await _json(request)
    point = data.get("point")
    if not (isinstance(point, list) and len(point) == 3
            and all(isinstance(x, (int, float)) and not isinstance(x, bool) for x in point)):
        raise ApiError(400, "bad_request", "point must be [x, y, z]")
    session = studio.session(request)
    _need(session)
    return JSONResponse(await _with_mesh(studio, session, _work.pick, session, point,
                                         studio.limits))


async def module(request: Request) -> JSONResponse:
    studio = _studio(request)
    index = _int(request.query_params.get("index", ""), "index", 0, 2**62)
    session = studio.session(request)
    _need(session)
    return JSONResponse(await _with_mesh(studio, session, _work.trace_module, session, index,
                                         studio.limits))


def _download_name(session: Session, ext: str) -> str:
    stem = Path(session.filename or "plant").stem or "plant"
    stem = "".join(c if c.isalnum() or c in "-_." else "_" for c in stem)[:80]
    return f"{stem}-step{session.derivation.step}.{ext}"


def _grown_of(request: Request, session: Session, of) -> object | None:
    """The tree or world of the Tree and World modes an export asks for (``of``), or
    ``None`` for the L-system."""
    if of in (None, "", "lsystem"):
        _need(session)
        return None
    if of not in ("tree", "world"):
        raise ApiError(400, "bad_request", "of must be lsystem, tree or world")
    g = session.grown
    if g is None or g.kind != of:
        raise ApiError(409, "no_program", f"no {of} is grown: grow one in {of.title()} mode "
                       "first")
    return g


async def export(request: Request) -> Response:
    studio = _studio(request)
    fmt = request.path_params["fmt"]
    session = studio.session(request)
    formats = _work.export_formats()
    if fmt not in formats:
        raise ApiError(400, "invalid", f"unknown export format {fmt!r}; expected one of "
                       + ", ".join(formats))
    grown = _grown_of(request, session, request.query_params.get("of"))
    media = "model/gltf-binary" if fmt == "glb" else (
        "application/octet-stream" if fmt in ("ply", "stl", "usd", "usdc")
        else "text/plain; charset=utf-8")
    if grown is not None:
        data = await studio.run(session, _once(grown.export, fmt))
        name = f"{grown.name}.{fmt}"
    else:
        data = await _with_mesh(studio, session, _work.export_mesh, session, fmt,
                                studio.limits)
        name = _download_name(session, fmt)
    return _body(data, media, {"content-disposition": f'attachment; filename="{name}"'})


async def export_png(request: Request) -> Response:
    studio = _studio(request)
    data = await _json(request)
    side = studio.limits.max_image_side
    width = _int(data.get("width", 1024), "width", 1, side)
    height = _int(data.get("height", 768), "height", 1, side)
    camera = data.get("camera") or {}
    if not isinstance(camera, dict):
        raise ApiError(400, "bad_request", "camera must be an object")
    clean: dict = {}
    for k in ("yaw", "pitch", "distance", "fov", "height", "axis"):
        if k in camera:
            v = camera[k]
            if not isinstance(v, (int, float)) or isinstance(v, bool) or not math.isfinite(v):
                raise ApiError(400, "bad_request", f"camera.{k} must be a finite number")
            clean[k] = float(v)
    mode = camera.get("mode", "perspective")
    if mode not in ("perspective", "orthographic", "2d"):
        raise ApiError(400, "bad_request", "camera.mode must be perspective, orthographic or 2d")
    clean["mode"] = mode
    t = camera.get("target", [0, 0, 0])
    if not (isinstance(t, list) and len(t) == 3 and all(
            isinstance(x, (int, float)) and math.isfinite(x) for x in t)):
        raise ApiError(400, "bad_request", "camera.target must be [x, y, z]")
    clean["target"] = [float(x) for x in t]
    fmt = data.get("format", "png")
    if fmt not in ("png", "jpg"):
        raise ApiError(400, "bad_request", "format must be png or jpg")
    session = studio.session(request)
    grown = _grown_of(request, session, data.get("of"))
    limits = studio.limits

    def render():
        if grown is not None:
            bg, scene = grown.background, grown.scene
        else:
            bg, scene = _work.state(session).get("background"), None
        # the GL context lives in its own thread: the job waits there for the picture
        return studio.gl.submit(
            _work.render_png, session, limits, width=width, height=height, camera=clean,
            focus=bool(data.get("focus")), background=bg, fmt=fmt, scene=scene).result()

    try:
        if grown is not None:
            image = await studio.run(session, _once(render))
        else:
            image = await _with_mesh(studio, session, render)
    except SylvaError as exc:
        if isinstance(exc, _work.CapError):
            raise ApiError(422, exc.kind, str(exc)) from None
        raise ApiError(503, "render", f"the server cannot render images: {exc}") from None
    name = f"{grown.name}.{fmt}" if grown is not None else _download_name(session, fmt)
    return Response(image, media_type="image/jpeg" if fmt == "jpg" else "image/png",
                    headers={"content-disposition": f'attachment; filename="{name}"'})


async def files(request: Request) -> JSONResponse:
    studio = _studio(request)
    studio.session(request)
    listing = await studio.light(studio.workspace.list)
    return JSONResponse({"root": studio.workspace.root.name, "files": listing})


async def file_get(request: Request) -> JSONResponse:
    studio = _studio(request)
    studio.session(request)
    path = request.query_params.get("path")
    text = await studio.light(studio.workspace.read, path, studio.limits.max_text * 4)
    return JSONResponse({"path": path, "text": text})


async def file_put(request: Request) -> JSONResponse:
    studio = _studio(request)
    data = await _json(request)
    text = data.get("text")
    if not isinstance(text, str):
        raise ApiError(400, "bad_request", "text must be a string")
    if len(text) > studio.limits.max_text:
        raise ApiError(413, "too_large",
                       f"the definition is longer than {studio.limits.max_text:,} characters")
    studio.session(request)
    ws = studio.workspace
    rel = await studio.light(lambda: ws.write(data.get("path"), text,
                                              overwrite=bool(data.get("overwrite"))))
    return JSONResponse({"path": rel, "saved": len(text)})


async def example(request: Request) -> JSONResponse:
    from ..data import examples

    name = request.query_params.get("name", "")
    for e in examples():
        if e.name == name:
            return JSONResponse({"name": e.name, "file": e.path.name,
                                 "text": e.path.read_text(encoding="utf-8")})
    raise ApiError(404, "not_found", f"no built-in example named {name!r}")


# Everything the page loads comes from this server: a CDN script would be refused.
_CSP = ("default-src 'self'; script-src 'self'; style-src 'self' 'unsafe-inline'; "
        "img-src 'self' data: blob:; connect-src 'self'; object-src 'none'; "
        "base-uri 'none'; frame-ancestors 'none'")


def _page(token: str) -> str:
    html = (static_dir() / "index.html").read_text(encoding="utf-8")
    meta = f'<meta name="sylva-page" content="{token}">'
    return html.replace('<meta charset="utf-8">', '<meta charset="utf-8">\n' + meta, 1)


async def index(request: Request) -> Response:
    studio = _studio(request)
    return HTMLResponse(_page(studio.page_token), headers={
        "cache-control": "no-store",
        "content-security-policy": _CSP,
        "x-content-type-options": "nosniff",
        "referrer-policy": "no-referrer",
    })


# --------------------------------------------------------------------------- errors
async def _api_error(request: Request, exc: ApiError) -> JSONResponse:
    response = _error(exc.status, exc.kind, exc.message, **exc.extra)
    if "retry_after" in exc.extra:
        response.headers["retry-after"] = str(exc.extra["retry_after"])
    return response


async def _workspace_error(request: Request, exc: WorkspaceError) -> JSONResponse:
    return _error(exc.status, "workspace", str(exc))


async def _sylva_error(request: Request, exc: SylvaError) -> JSONResponse:
    return _error(400, "invalid", str(exc))


async def _internal(request: Request, exc: Exception) -> JSONResponse:
    return _error(500, "internal", f"internal error ({type(exc).__name__}: {exc}); "
                  "please report it with the definition that caused it")


async def _not_found(request: Request, exc) -> JSONResponse:
    return _error(getattr(exc, "status_code", 404), "not_found",
                  getattr(exc, "detail", "not found"))


def create_app(
    workspace: str | Path = ".",
    *,
    limits: Limits | None = None,
    start_file: str | None = None,
    allowed_hosts: tuple[str, ...] = ("127.0.0.1", "localhost", "[::1]", "::1"),
    warm_up: bool = True,
) -> Starlette:
    """The Studio application serving ``workspace``.

    Parameters
    ----------
    workspace : path
        The only folder clients may open and save in.
    limits : Limits, optional
        The caps (defaults: :class:`~sylva.studio.Limits`).
    start_file : str, optional
        A workspace path or a built-in example name the front end opens first.
    allowed_hosts : tuple of str
        Host headers accepted (the server only listens on the loopback; this stops DNS
        rebinding).
    warm_up : bool
        Compile the derivation and meshing kernels in the background at start-up.
    """
    from . import _routes  # the debugger, progress, Tree and World modes

    limits = limits or Limits()
    studio = Studio(Workspace(workspace), limits, start_file)
    api = [
        Route("/session", new_session, methods=["POST"]),
        Route("/session", end_session, methods=["DELETE"]),
        Route("/info", info),
        Route("/help", help_),
        Route("/load", load, methods=["POST"]),
        Route("/preview", preview, methods=["POST"]),
        Route("/step", step, methods=["POST"]),
        Route("/back", back, methods=["POST"]),
        Route("/reset", reset, methods=["POST"]),
        Route("/stop", stop, methods=["POST"]),
        Route("/state", state),
        Route("/word", word),
        Route("/mesh", mesh),
        Route("/pick", pick, methods=["POST"]),
        Route("/module", module),
        Route("/export.{fmt:str}", export, methods=["GET"]),
        Route("/export-png", export_png, methods=["POST"]),
        Route("/files", files),
        Route("/file", file_get, methods=["GET"]),
        Route("/file", file_put, methods=["PUT"]),
        Route("/example", example),
        *_routes.routes(),
    ]

    @contextlib.asynccontextmanager
    async def lifespan(app):
        loop = asyncio.get_running_loop()
        if warm_up:
            # in the background: the server answers at once, the kernels compile meanwhile
            fut = loop.run_in_executor(studio.pool, _work.warm_up)
            fut.add_done_callback(lambda f: studio.ready.set())
        else:
            studio.ready.set()

        async def evict():
            while True:
                await asyncio.sleep(min(30.0, max(limits.idle_timeout / 4, 0.05)))
                if studio.sessions.evict_idle():
                    # the words and meshes of the sessions that went: back to the system
                    await studio.light(_release)

        janitor = asyncio.ensure_future(evict())
        try:
            yield
        finally:
            janitor.cancel()
            with contextlib.suppress(asyncio.CancelledError):
                await janitor
        await asyncio.get_running_loop().run_in_executor(None, studio.close)

    app = Starlette(
        routes=[
            Route("/", index),
            Mount("/api", routes=api),
            Mount("/static", StaticFiles(directory=static_dir()), name="static"),
        ],
        middleware=[
            Middleware(TrustedHostMiddleware, allowed_hosts=list(allowed_hosts)),
            Middleware(_Guard, limits=limits),
        ],
        exception_handlers={
            ApiError: _api_error,
            WorkspaceError: _workspace_error,
            SylvaError: _sylva_error,
            404: _not_found,
            405: _not_found,
            Exception: _internal,
        },
        lifespan=lifespan,
    )
    app.state.studio = studio
    return app

