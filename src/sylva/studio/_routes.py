"""The Studio's later endpoints: the debugger, the progress figures, Tree and World modes.

=======================  =============================================================
``POST debug``           ``{n, breakpoints, profile}``: derive up to ``n`` steps, stopping
                         after the first step where a breakpoint holds (``hit``: which,
                         at which step, the modules that matched); see :mod:`._debug`
``GET  profile``         the per-rule profile of the steps derived with ``profile``
``DELETE profile``       forget it
``GET  progress``        seed 001's two figures of the running job: steps derived and
                         modules interpreted (answered at once, beside the job)
``GET  tree/species``    the species and the schema of every species parameter
``GET  tree/fields``     ``?species=``: the values a species sets
``POST tree``            ``{blocks, extra, age, seed, wind, leaves}``: grow that tree
``POST world``           ``{seed, size, plants}``: generate a world
``GET  grown.glb``       the last tree or world as binary glTF
``GET  world/biomes.png``  the last world's biome map
``GET  surfaces.glsl``   the GLSL of the bark and leaf texture graphs, which the viewer
                         calls on plant surfaces (the functions the exports bake)
``GET  texture/presets`` Texture mode: the shipped presets (each one a graph)
``GET  texture/preset``  ``?name=``: a preset's graph as TOML
``POST texture``         ``{text, side?}``: read and render a graph's TOML (the CPU
                         kernel; ``side``: the image's longer side, 256 by default, 0 for
                         the graph's size): ``{png (base64), width, height, nodes, ...}``;
                         a bad text: ``400`` with ``line`` and ``column``
``PUT  texture/file``    ``{path, text, overwrite}``: save the graph (``.toml``) and its
                         image at its size (the same name, ``.png``) together, atomically
``GET  texture/files``   the workspace's graph files; ``GET texture/file?path=`` one's text
=======================  =============================================================
"""

from __future__ import annotations

import math

from starlette.requests import Request
from starlette.responses import JSONResponse, Response
from starlette.routing import Route

from ..errors import SylvaError
from . import _debug, _grown, _texture, _work
from ._workspace import WorkspaceError
from .app import ApiError, _body, _derive, _int, _json, _need, _once, _studio

__all__ = ["routes"]


def _number(value, name: str, lo: float, hi: float, *, open_lo: bool = False) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(
            value) or not ((value > lo) if open_lo else (value >= lo)) or value > hi:
        raise ApiError(400, "bad_request", f"{name} must be a number in "
                       f"{'(' if open_lo else '['}{lo:g}, {hi:g}]", field=name)
    return float(value)


async def debug(request: Request) -> JSONResponse:
    studio = _studio(request)
    data = await _json(request)
    n = _int(data.get("n", 1), "n", 0, studio.limits.max_steps)
    session = studio.session(request)
    _need(session)
    try:
        bps = _debug.check_breakpoints(data.get("breakpoints"), session.program)
    except SylvaError as exc:
        raise ApiError(400, "bad_request", str(exc)) from None
    profile = bool(data.get("profile"))
    if (profile or any(b["kind"] != "condition" for b in bps)) \
            and not session.derivation.trace:
        raise ApiError(409, "trace", "rule and module breakpoints and the profile need rule "
                       "tracing: turn on Rule tracing and reset")
    result: dict = {}

    def make(job):
        out = yield from _debug.debugging(session, n, bps, profile, studio.limits, job.used)
        result.update(out)
        return out

    response = await _derive(studio, session, make)
    if response.status_code != 200:
        return response
    return JSONResponse({**_work.state(session), "hit": result.get("hit"),
                         "done": result.get("done", 0),
                         "profile": session.profile[-1:] if profile else []})


async def profile_get(request: Request) -> JSONResponse:
    studio = _studio(request)
    session = studio.session(request)
    _need(session)
    return JSONResponse({"rules": _debug.rules(session.program), "steps": session.profile})


async def profile_delete(request: Request) -> JSONResponse:
    studio = _studio(request)
    session = studio.session(request)
    session.profile = []
    return JSONResponse({"steps": []})


async def progress(request: Request) -> JSONResponse:
    studio = _studio(request)
    session = studio.session(request)
    d = session.derivation
    return JSONResponse({**session.progress, "busy": session.busy,
                         "step": d.step if d is not None else None})


async def tree_species(request: Request) -> JSONResponse:
    studio = _studio(request)
    species, schema = await studio.light(lambda: (_grown.species_list(), _grown.tree_schema()))
    return JSONResponse({"species": species, "schema": schema,
                         "limits": {"age": _grown.MAX_AGE, "wind": _grown.MAX_WIND}})


async def tree_fields(request: Request) -> JSONResponse:
    studio = _studio(request)
    name = request.query_params.get("species", "")
    try:
        out = await studio.light(_grown.species_fields, name)
    except SylvaError as exc:
        raise ApiError(404, "not_found", str(exc)) from None
    return JSONResponse(out)


def _grown_state(g) -> dict:
    out = {"kind": g.kind, "name": g.name, "stats": g.stats, "timings": g.timings,
           "triangles": int(g.stats.get("triangles", 0)), "background": list(g.background)}
    return out


async def tree(request: Request) -> JSONResponse:
    studio = _studio(request)
    data = await _json(request)
    age = _number(data.get("age", 10.0), "age", 0, _grown.MAX_AGE, open_lo=True)
    wind = _number(data.get("wind", 0.0), "wind", 0, _grown.MAX_WIND)
    seed = _int(data.get("seed", 0), "seed", 0, 2**31 - 1)
    blocks, extra = data.get("blocks"), data.get("extra") or {}
    if not isinstance(blocks, dict) or not isinstance(extra, dict):
        raise ApiError(400, "bad_request", "blocks must map block names to {key: value}")
    session = studio.session(request)

    def grow():
        session.grown = _grown.grow_tree(session, blocks=blocks, extra=extra, age=age,
                                         seed=seed, wind=wind,
                                         leaves=bool(data.get("leaves", True)))
        return session.grown

    try:
        g = await studio.run(session, _once(grow))
    except _grown.FieldError as exc:
        raise ApiError(400, "invalid", str(exc),
                       field=list(exc.field) if exc.field else None) from None
    except SylvaError as exc:
        raise ApiError(400, "invalid", str(exc)) from None
    return JSONResponse(_grown_state(g))


async def world(request: Request) -> JSONResponse:
    studio = _studio(request)
    data = await _json(request)
    seed = _int(data.get("seed", 0), "seed", 0, 2**31 - 1)
    size = _int(data.get("size", 32), "size", 8, _grown.MAX_WORLD)
    session = studio.session(request)

    def grow():
        session.grown = _grown.grow_world(session, seed=seed, size=size,
                                          plants=bool(data.get("plants", True)))
        return session.grown

    try:
        g = await studio.run(session, _once(grow))
    except SylvaError as exc:
        raise ApiError(400, "invalid", str(exc)) from None
    return JSONResponse(_grown_state(g))


def _last_grown(request: Request, kind: str | None = None):
    studio = _studio(request)
    session = studio.session(request)
    g = session.grown
    if g is None or (kind is not None and g.kind != kind):
        raise ApiError(409, "no_program", f"no {kind or 'tree or world'} is grown yet")
    return g


async def grown_glb(request: Request) -> Response:
    g = _last_grown(request)
    return _body(g.glb, "model/gltf-binary", {"cache-control": "no-store",
                                              "x-sylva-triangles": str(g.stats.get(
                                                  "triangles", 0))})


async def biomes(request: Request) -> Response:
    g = _last_grown(request, "world")
    return Response(g.extra["biomes"], media_type="image/png",
                    headers={"cache-control": "no-store"})


async def surfaces_glsl(request: Request) -> Response:
    from ..texture.graph.surface import surface_glsl

    return Response(surface_glsl(), media_type="text/plain; charset=utf-8",
                    headers={"cache-control": "no-cache"})


def _graph_error(exc: SylvaError) -> ApiError:
    """A graph text that does not read: the message, and the line and column the
    loader found (``None`` when it names none)."""
    return ApiError(400, "invalid", str(exc), line=getattr(exc, "line", None),
                    column=getattr(exc, "column", None),
                    detail=getattr(exc, "message", str(exc)))


def _graph_text(studio, data) -> str:
    text = data.get("text")
    if not isinstance(text, str):
        raise ApiError(400, "bad_request", "text must be the graph's TOML, a string")
    if len(text) > studio.limits.max_text:
        raise ApiError(413, "too_large",
                       f"the graph is longer than {studio.limits.max_text:,} characters")
    return text


async def texture_presets(request: Request) -> JSONResponse:
    studio = _studio(request)
    presets = await studio.light(_texture.preset_list)
    return JSONResponse({"presets": presets, "preview_side": _texture.PREVIEW_SIDE})


async def texture_preset(request: Request) -> JSONResponse:
    studio = _studio(request)
    name = request.query_params.get("name", "")
    try:
        text = await studio.light(_texture.preset_text, name)
    except SylvaError as exc:
        raise ApiError(404, "not_found", str(exc)) from None
    return JSONResponse({"name": name, "text": text})


async def texture(request: Request) -> JSONResponse:
    import base64

    studio = _studio(request)
    data = await _json(request)
    text = _graph_text(studio, data)
    side = _int(data.get("side", _texture.PREVIEW_SIDE), "side", 0, _texture.MAX_SIDE)
    filename = data.get("filename") if isinstance(data.get("filename"), str) else None
    session = studio.session(request)
    try:
        out = await studio.run(session, _once(_texture.render, text, side=side or None,
                                              filename=filename))
    except SylvaError as exc:
        raise _graph_error(exc) from None
    return JSONResponse({**out, "png": base64.b64encode(out["png"]).decode("ascii")})


async def texture_save(request: Request) -> JSONResponse:
    studio = _studio(request)
    data = await _json(request)
    text = _graph_text(studio, data)
    session = studio.session(request)
    path, overwrite = data.get("path"), bool(data.get("overwrite"))
    try:
        return JSONResponse(await studio.run(session, _once(
            _texture.save, studio.workspace, path, text, overwrite=overwrite)))
    except SylvaError as exc:
        if isinstance(exc, WorkspaceError):
            raise  # answered with its own status (409 exists, 403 outside, ...)
        raise _graph_error(exc) from None


async def texture_files(request: Request) -> JSONResponse:
    studio = _studio(request)
    studio.session(request)
    listing = await studio.light(lambda: studio.workspace.list(
        suffixes=_texture.GRAPH_SUFFIXES))
    return JSONResponse({"root": studio.workspace.root.name, "files": listing})


async def texture_file(request: Request) -> JSONResponse:
    studio = _studio(request)
    studio.session(request)
    path = request.query_params.get("path")
    text = await studio.light(lambda: studio.workspace.read(
        path, studio.limits.max_text * 4, suffixes=_texture.GRAPH_SUFFIXES))
    return JSONResponse({"path": path, "text": text})


def routes() -> list[Route]:
    """The routes of this module, mounted under ``/api`` by :func:`~.app.create_app`."""
    return [
        Route("/debug", debug, methods=["POST"]),
        Route("/profile", profile_get),
        Route("/profile", profile_delete, methods=["DELETE"]),
        Route("/progress", progress),
        Route("/tree/species", tree_species),
        Route("/tree/fields", tree_fields),
        Route("/tree", tree, methods=["POST"]),
        Route("/world", world, methods=["POST"]),
        Route("/grown.glb", grown_glb),
        Route("/world/biomes.png", biomes),
        Route("/surfaces.glsl", surfaces_glsl),
        Route("/texture/presets", texture_presets),
        Route("/texture/preset", texture_preset),
        Route("/texture", texture, methods=["POST"]),
        Route("/texture/file", texture_save, methods=["PUT"]),
        Route("/texture/file", texture_file, methods=["GET"]),
        Route("/texture/files", texture_files),
    ]
