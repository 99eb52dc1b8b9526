"""Shader sources shipped as package data (``shaders/*.glsl``) and their compilation.

Sources may contain ``#include "name.glsl"`` lines, which are replaced by that file (once per
program, recursively).  ``surfaces.glsl`` is not a file: it is the GLSL of the plant-surface
texture graphs (:func:`sylva.texture.graph.surface.surface_glsl`), the functions the exports
bake on the CPU.
"""

from __future__ import annotations

import re
from functools import cache
from importlib import resources

import moderngl

from sylva.render.context import RenderError

__all__ = ["compile_program", "shader_source"]

_INCLUDE = re.compile(r'^\s*#include\s+"([\w.\-]+)"\s*$', re.MULTILINE)


@cache
def _raw(name: str) -> str:
    if name == "surfaces.glsl":
        from sylva.texture.graph.surface import surface_glsl

        return surface_glsl()
    path = resources.files("sylva.render").joinpath("shaders", name)
    try:
        return path.read_text(encoding="utf-8")
    except FileNotFoundError as exc:
        raise RenderError(f"shader {name!r} is missing from sylva/render/shaders") from exc


def shader_source(name: str, skip=()) -> str:
    """The text of ``shaders/<name>`` with its ``#include`` lines expanded (the names in
    ``skip`` expand to nothing)."""
    seen: set[str] = set(skip)

    def expand(n: str) -> str:
        if n in seen:
            return ""
        seen.add(n)
        return _INCLUDE.sub(lambda m: expand(m.group(1)), _raw(n))

    return expand(name)


def _with_defines(source: str, defines) -> str:
    if not defines:
        return source
    first, _, rest = source.partition("\n")
    if not first.startswith("#version"):
        raise RenderError("a shader must start with its #version line")
    lines = "".join(f"#define {d}\n" for d in sorted(defines))
    return f"{first}\n{lines}{rest}"


def compile_program(
    ctx: moderngl.Context, vertex: str, fragment: str, defines=()
) -> moderngl.Program:
    """Compile and link ``shaders/<vertex>`` and ``shaders/<fragment>``.

    ``defines`` are names ``#define``-d right after the ``#version`` line of both stages
    (shader variants).

    Raises
    ------
    RenderError
        With the driver's log when compilation or linking fails.
    """
    # the surface graphs' GLSL only where a variant draws bark or leaf (generating it imports
    # the graph compiler; llvmpipe compiles its tables in about a second)
    skip = () if {"TEXTURE_KIND 2", "TEXTURE_KIND 3"} & set(defines) else ("surfaces.glsl",)
    try:
        return ctx.program(
            vertex_shader=_with_defines(shader_source(vertex, skip), defines),
            fragment_shader=_with_defines(shader_source(fragment, skip), defines),
        )
    except moderngl.Error as exc:
        raise RenderError(
            f"cannot build shaders {vertex} + {fragment} {sorted(defines)}: {exc}"
        ) from exc
