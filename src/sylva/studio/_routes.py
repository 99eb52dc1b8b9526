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
=======================  =============================================================
"""

from __future__ import annotations

import math

from starlette.requests import Request
from starlette.responses import JSONResponse, Response
from starlette.routing import Route

from ..errors import SylvaError
from . import _debug, _grown, _work
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
    ]
