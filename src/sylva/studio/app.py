"""The Studio's ASGI application (Starlette): the JSON/GLB API and the static front end.

API (all under ``/api``; JSON unless said otherwise; errors are ``{"error": kind,
"message": text, ...}`` with a 4xx/5xx status):

=======================  =============================================================
``GET  info``            dialects, limits, the built-in examples, the start-up file
``GET  help?turtle=``    the symbol table and the special variables of a command table
``POST load``            ``{text, dialect?, seed?, filename?, overrides?, steps?, trace?}``:
                         parse, make the session's derivation (and derive ``steps``)
``POST step``            ``{n}``: derive ``n`` more steps under the caps
``POST back``            one step back
``POST reset``           back to the axiom
``POST stop``            stop the running derivation of this session
``GET  state``           step, module count, globals, settings, camera hint, timings
``GET  word?start=&count=``  a page of the current word, one text per module
``GET  mesh``            the current (render) word as binary glTF (``model/gltf-binary``)
``POST pick``            ``{point}``: the module drawn there and the rule/step that made it
``GET  module?index=``   module ``index`` of the word: what it drew and its rule and step
``GET  export.glb`` / ``export.obj``   downloads of the mesh
``POST export.png``      ``{width, height, camera, focus}``: a PNG rendered by the server
``GET  files``           the workspace's definition files
``GET  file?path=``      a file's text;  ``PUT file`` ``{path, text, overwrite}`` saves it
``GET  example?name=``   a built-in example's text
=======================  =============================================================

Every derivation, mesh and render runs in a worker thread, never on the event loop; each
request is capped in time and modules, bodies and URLs are capped in size, each client has
its own session, and user text is only ever parsed.
"""

from __future__ import annotations

import asyncio
import contextlib
import json
import math
from concurrent.futures import ThreadPoolExecutor
from importlib import resources
from pathlib import Path

from starlette.applications import Starlette
from starlette.middleware import Middleware
from starlette.middleware.trustedhost import TrustedHostMiddleware
from starlette.requests import Request
from starlette.responses import FileResponse, JSONResponse, Response
from starlette.routing import Mount, Route
from starlette.staticfiles import StaticFiles

from ..errors import LSystemSyntaxError, SylvaError
from . import _work
from ._help import help_tables
from ._limits import Limits
from ._sessions import COOKIE, HEADER, Session, SessionStore, TooManySessions
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
    """Size limits on URLs and bodies, a same-origin check on writes, and the session id.

    The body is read here (at most ``max_body`` bytes) and replayed to the app, so no
    handler ever sees more.  A client without a valid session id gets a new one in a
    cookie.
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
        if not SessionStore.valid_id(sid):
            sid = None
            for part in headers.get("cookie", "").split(";"):
                k, _, v = part.strip().partition("=")
                if k == COOKIE and SessionStore.valid_id(v):
                    sid = v
        fresh = sid is None
        if fresh:
            sid = SessionStore.new_id()
        scope.setdefault("state", {})["sid"] = sid

        async def send_with_cookie(message):
            if fresh and message["type"] == "http.response.start":
                cookie = f"{COOKIE}={sid}; Path=/; HttpOnly; SameSite=Strict"
                message.setdefault("headers", []).append(
                    (b"set-cookie", cookie.encode("latin-1")))
            await send(message)

        return await self.app(scope, replay, send_with_cookie)


# --------------------------------------------------------------------------- the app
class Studio:
    """The state of one server: sessions, workspace, limits and the worker pools."""

    def __init__(self, workspace: Workspace, limits: Limits, start_file: str | None) -> None:
        self.workspace = workspace
        self.limits = limits
        self.start_file = start_file
        self.sessions = SessionStore(limits.max_sessions, limits.idle_timeout)
        self.pool = ThreadPoolExecutor(limits.workers, thread_name_prefix="sylva-studio")
        # one thread owns the GL context of the offscreen renderer
        self.gl = ThreadPoolExecutor(1, thread_name_prefix="sylva-studio-gl")
        self.slots = asyncio.Semaphore(limits.workers)
        self.ready = asyncio.Event()  # set once the kernels are compiled (warm-up)

    def close(self) -> None:
        self.sessions.close()
        self.pool.shutdown(wait=True, cancel_futures=True)
        self.gl.shutdown(wait=True, cancel_futures=True)

    def session(self, request: Request) -> Session:
        try:
            return self.sessions.get(request.scope["state"]["sid"])
        except TooManySessions as exc:
            raise ApiError(503, "busy", str(exc)) from None

    async def run(self, session: Session, fn, *args, pool=None, **kw):
        """Run ``fn`` in a worker thread holding the session's lock, under the time cap.

        The work goes on in its thread when the cap passes (Python cannot kill a thread),
        but the client is answered, and the session stays locked until it ends.
        """
        cap = self.limits.time_cap
        if not self.ready.is_set():
            # the first requests wait for the one-off compilation instead of paying for it
            # inside their time cap
            with contextlib.suppress(TimeoutError):
                await asyncio.wait_for(self.ready.wait(), timeout=600)
        try:
            await asyncio.wait_for(session.lock.acquire(), timeout=cap)
        except TimeoutError:
            raise ApiError(409, "busy", "this session is still working on an earlier "
                           "request; press Stop or wait") from None
        loop = asyncio.get_running_loop()

        async def work():
            try:
                async with self.slots:
                    return await loop.run_in_executor(pool or self.pool, lambda: fn(*args, **kw))
            finally:
                session.lock.release()
                session.touch()

        session.cancel.clear()
        task = asyncio.ensure_future(work())
        # a task that outlives its request still has its outcome collected
        task.add_done_callback(lambda t: t.cancelled() or t.exception())
        try:
            return await asyncio.wait_for(asyncio.shield(task), timeout=cap * 1.5 + 2.0)
        except TimeoutError:
            session.cancel.set()
            raise ApiError(503, "time", f"the request passed the time cap of {cap:g} s; it "
                           "is being stopped") from None


def _studio(request: Request) -> Studio:
    return request.app.state.studio


async def _json(request: Request) -> dict:
    try:
        data = json.loads(await request.body() or b"{}")
    except (ValueError, UnicodeDecodeError):
        raise ApiError(400, "bad_request", "the body is not JSON") from None
    if not isinstance(data, dict):
        raise ApiError(400, "bad_request", "the body must be a JSON object")
    return data


def _int(value, name: str, lo: int, hi: int) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, float, str)):
        raise ApiError(400, "bad_request", f"{name} must be an integer")
    try:
        v = int(value)
    except ValueError:
        raise ApiError(400, "bad_request", f"{name} must be an integer") from None
    if not lo <= v <= hi:
        raise ApiError(400, "bad_request", f"{name} must be in [{lo}, {hi}]")
    return v


def _need(session: Session) -> None:
    if session.derivation is None:
        raise ApiError(409, "no_program", "no L-system is loaded: load a definition first")


async def _state_response(studio: Studio, session: Session, status: int = 200, **extra):
    return JSONResponse({**_work.state(session), **extra}, status_code=status)


async def _derive(studio: Studio, session: Session, n: int) -> JSONResponse:
    try:
        await studio.run(session, _work.advance, session, n, studio.limits)
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
        "examples": [{"name": e.name, "title": e.title, "file": e.path.name}
                     for e in examples()],
        "start_file": studio.start_file,
        "limits": {"modules": lim.max_modules, "time_cap": lim.time_cap,
                   "steps": lim.max_steps, "text": lim.max_text, "body": lim.max_body,
                   "image_side": lim.max_image_side, "page": lim.page_size},
    })


async def help_(request: Request) -> JSONResponse:
    return JSONResponse(help_tables(request.query_params.get("turtle", "lsys")))


async def load(request: Request) -> JSONResponse:
    studio = _studio(request)
    data = await _json(request)
    text = data.get("text")
    if not isinstance(text, str):
        raise ApiError(400, "bad_request", "text must be the definition, a string")
    if len(text) > studio.limits.max_text:
        raise ApiError(413, "too_large",
                       f"the definition is longer than {studio.limits.max_text:,} characters")
    dialect = data.get("dialect") or None
    seed = data.get("seed")
    seed = None if seed in (None, "") else _int(seed, "seed", 0, 2**63 - 1)
    steps = _int(data.get("steps", 0), "steps", 0, studio.limits.max_steps)
    filename = data.get("filename") if isinstance(data.get("filename"), str) else None
    overrides = data.get("overrides") or {}
    if not isinstance(overrides, dict):
        raise ApiError(400, "bad_request", "overrides must map global names to numbers")
    trace = bool(data.get("trace", True))
    session = studio.session(request)

    def parse():
        program = _work.load_program(text, dialect=dialect, filename=filename,
                                     overrides=overrides)
        d = _work.new_derivation(program, seed=seed, limits=studio.limits, trace=trace)
        session.program, session.derivation = program, d
        session.text, session.filename = text, filename
        session.overrides = {k: v for k, v in overrides.items() if k in program.constants}
        session.drawn, session.last_step = None, None
        session.timings = {}

    try:
        await studio.run(session, parse)
    except LSystemSyntaxError as exc:
        return JSONResponse(_work.syntax_error_payload(exc), status_code=400)
    except SylvaError as exc:
        return _error(400, "invalid", str(exc))
    if steps:
        return await _derive(studio, session, steps)
    return await _state_response(studio, session)


async def step(request: Request) -> JSONResponse:
    studio = _studio(request)
    data = await _json(request)
    n = _int(data.get("n", 1), "n", 0, studio.limits.max_steps)
    session = studio.session(request)
    _need(session)
    return await _derive(studio, session, n)


async def back(request: Request) -> JSONResponse:
    studio = _studio(request)
    session = studio.session(request)
    _need(session)
    await studio.run(session, _work.back, session)
    return await _state_response(studio, session)


async def reset(request: Request) -> JSONResponse:
    studio = _studio(request)
    session = studio.session(request)
    _need(session)

    def do():
        session.derivation.reset()
        session.last_step = None

    await studio.run(session, do)
    return await _state_response(studio, session)


async def stop(request: Request) -> JSONResponse:
    session = _studio(request).session(request)
    session.cancel.set()
    return JSONResponse({"stopping": session.busy})


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
    page = await studio.run(session, _work.word_page, session, start, count, studio.limits)
    return JSONResponse(page)


async def _mesh(studio: Studio, session: Session) -> _work.Drawn:
    try:
        return await studio.run(session, _work.mesh, session, studio.limits)
    except _work.CapError as exc:
        raise ApiError(422, exc.kind, str(exc)) from None


async def mesh(request: Request) -> Response:
    studio = _studio(request)
    session = studio.session(request)
    _need(session)
    drawn = await _mesh(studio, session)
    return Response(drawn.glb, media_type="model/gltf-binary", headers={
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
    try:
        return JSONResponse(await studio.run(session, _work.pick, session, point,
                                             studio.limits))
    except _work.CapError as exc:
        raise ApiError(422, exc.kind, str(exc)) from None


async def module(request: Request) -> JSONResponse:
    studio = _studio(request)
    index = _int(request.query_params.get("index", ""), "index", 0, 2**62)
    session = studio.session(request)
    _need(session)
    try:
        return JSONResponse(await studio.run(session, _work.trace_module, session, index,
                                             studio.limits))
    except _work.CapError as exc:
        raise ApiError(422, exc.kind, str(exc)) from None


def _download_name(session: Session, ext: str) -> str:
    stem = Path(session.filename or "plant").stem or "plant"
    stem = "".join(c if c.isalnum() or c in "-_." else "_" for c in stem)[:80]
    return f"{stem}-step{session.derivation.step}.{ext}"


async def export(request: Request) -> Response:
    studio = _studio(request)
    fmt = request.path_params["fmt"]
    session = studio.session(request)
    _need(session)
    try:
        data = await studio.run(session, _work.export_mesh, session, fmt, studio.limits)
    except _work.CapError as exc:
        raise ApiError(422, exc.kind, str(exc)) from None
    media = "model/gltf-binary" if fmt == "glb" else "text/plain; charset=utf-8"
    name = _download_name(session, fmt)
    return Response(data, media_type=media,
                    headers={"content-disposition": f'attachment; filename="{name}"'})


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
    session = studio.session(request)
    _need(session)
    await _mesh(studio, session)
    bg = _work.state(session).get("background")
    try:
        png = await studio.run(session, _work.render_png, session, studio.limits, width=width,
                               height=height, camera=clean, focus=bool(data.get("focus")),
                               background=bg, pool=studio.gl)
    except _work.CapError as exc:
        raise ApiError(422, exc.kind, str(exc)) from None
    except SylvaError as exc:
        raise ApiError(503, "render", f"the server cannot render images: {exc}") from None
    name = _download_name(session, "png")
    return Response(png, media_type="image/png",
                    headers={"content-disposition": f'attachment; filename="{name}"'})


async def files(request: Request) -> JSONResponse:
    studio = _studio(request)
    listing = await asyncio.get_running_loop().run_in_executor(studio.pool, studio.workspace.list)
    return JSONResponse({"root": studio.workspace.root.name, "files": listing})


async def file_get(request: Request) -> JSONResponse:
    studio = _studio(request)
    path = request.query_params.get("path")
    text = await asyncio.get_running_loop().run_in_executor(
        studio.pool, studio.workspace.read, path, studio.limits.max_text * 4)
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
    ws = studio.workspace
    rel = await asyncio.get_running_loop().run_in_executor(
        studio.pool, lambda: ws.write(data.get("path"), text,
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


async def index(request: Request) -> Response:
    return FileResponse(static_dir() / "index.html", headers={
        "cache-control": "no-cache",
        "content-security-policy": _CSP,
        "x-content-type-options": "nosniff",
        "referrer-policy": "no-referrer",
    })


# --------------------------------------------------------------------------- errors
async def _api_error(request: Request, exc: ApiError) -> JSONResponse:
    return _error(exc.status, exc.kind, exc.message, **exc.extra)


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
    limits = limits or Limits()
    studio = Studio(Workspace(workspace), limits, start_file)
    api = [
        Route("/info", info),
        Route("/help", help_),
        Route("/load", load, methods=["POST"]),
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
                await asyncio.sleep(min(60.0, limits.idle_timeout / 2))
                studio.sessions.evict_idle()

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

