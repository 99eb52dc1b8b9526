"""The one place where sylva creates OpenGL contexts.

Every renderer, test and benchmark gets its context from here.  Contexts are headless
(moderngl's standalone EGL backend): on a machine with a GPU and its EGL driver the GPU renders,
on a machine without one (continuous integration) Mesa's llvmpipe renders on the CPU.  Nothing
needs an X server.

The EGL device can be chosen with the environment variable ``SYLVA_EGL_DEVICE`` (an index into
the devices EGL enumerates, 0 by default) and the libraries with ``SYLVA_LIBEGL`` and
``SYLVA_LIBGL`` (``libEGL.so.1`` and ``libGL.so.1`` by default, which the runtime packages
``libegl1`` and ``libgl1`` provide, so the ``-dev`` packages are not needed).

Examples
--------
>>> ctx = get_context()
>>> ctx is get_context()
True
>>> context_info(ctx)["version"] >= 330
True
"""

from __future__ import annotations

import os
import threading
from typing import Any

import moderngl

from sylva.errors import SylvaError

__all__ = ["RenderError", "context_info", "create_context", "get_context", "max_render_size"]

#: The lowest OpenGL version the shaders need (GLSL 330 core).
REQUIRED_VERSION = 330

_local = threading.local()


class RenderError(SylvaError, RuntimeError):
    """No usable OpenGL context, a failed shader, or an image that cannot be made."""


def create_context() -> moderngl.Context:
    """Create a new headless OpenGL 3.3+ context through EGL.

    Most callers want :func:`get_context`, which shares one context per process; a new
    context is only needed to render from several threads at once.

    Returns
    -------
    moderngl.Context
        A standalone context (no default framebuffer: render into framebuffer objects).

    Raises
    ------
    RenderError
        When EGL or a driver is missing, or the context is older than OpenGL 3.3.  The message
        names the Debian packages that provide a software renderer.
    """
    device = int(os.environ.get("SYLVA_EGL_DEVICE", "0"))
    libegl = os.environ.get("SYLVA_LIBEGL", "libEGL.so.1")
    libgl = os.environ.get("SYLVA_LIBGL", "libGL.so.1")
    try:
        ctx = moderngl.create_context(
            standalone=True,
            backend="egl",
            require=REQUIRED_VERSION,
            libegl=libegl,
            libgl=libgl,
            device_index=device,
        )
    except Exception as exc:  # glcontext raises plain Exception subclasses
        raise RenderError(
            f"cannot create a headless OpenGL 3.3 context through EGL (device {device}): "
            f"{exc}. Without a GPU, install Mesa's "
            "software renderer: apt-get install libegl1 libegl-mesa0 libgl1 libgl1-mesa-dri libgbm1"
        ) from exc
    return ctx


def get_context() -> moderngl.Context:
    """The calling thread's shared context, created on first use.

    An EGL context is current in one thread at a time, so every thread that renders (the
    studio's workers, say) gets a context of its own; within a thread every call returns
    the same object.

    Returns
    -------
    moderngl.Context
    """
    ctx = getattr(_local, "ctx", None)
    if ctx is None:
        ctx = create_context()
        _local.ctx = ctx
    return ctx


def context_info(ctx: moderngl.Context | None = None) -> dict[str, Any]:
    """What the context is and what it can do.

    Parameters
    ----------
    ctx : moderngl.Context, optional
        Defaults to :func:`get_context`.

    Returns
    -------
    dict
        ``renderer``, ``vendor`` (str), ``version`` (int, e.g. 450), ``software`` (bool: llvmpipe
        or another CPU rasteriser), ``max_size`` (int, the largest square framebuffer side) and
        ``max_samples`` (int, MSAA).
    """
    ctx = ctx or get_context()
    renderer = str(ctx.info["GL_RENDERER"])
    return {
        "renderer": renderer,
        "vendor": str(ctx.info["GL_VENDOR"]),
        "version": int(ctx.version_code),
        "software": any(s in renderer.lower() for s in ("llvmpipe", "softpipe", "swrast")),
        "max_size": max_render_size(ctx),
        "max_samples": int(ctx.max_samples),
    }


def max_render_size(ctx: moderngl.Context | None = None) -> int:
    """The largest framebuffer side the context accepts (renderbuffer, texture and viewport)."""
    ctx = ctx or get_context()
    vp = ctx.info["GL_MAX_VIEWPORT_DIMS"]
    return int(
        min(
            ctx.info["GL_MAX_RENDERBUFFER_SIZE"],
            ctx.info["GL_MAX_TEXTURE_SIZE"],
            vp[0],
            vp[1],
        )
    )
