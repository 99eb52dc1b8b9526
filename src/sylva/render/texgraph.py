"""Texture graphs on the GPU: a graph's GLSL (:mod:`sylva.texture.graph.glsl`) drawn into a
float framebuffer on the shared context, for previews and for comparing with the CPU kernel.

Examples
--------
>>> from sylva.texture import graph as tg
>>> img = render_graph(tg.Graph(tg.improved(scale=4.0, seed=1)), (8, 16))
>>> img.shape, img.dtype.name
((8, 16), 'float32')
"""

from __future__ import annotations

import numpy as np

from ..texture.graph.glsl import compile_glsl
from .context import get_context

__all__ = ["render_graph"]

_VERTEX = """#version 330
in vec2 pos;
void main() { gl_Position = vec4(pos, 0.0, 1.0); }
"""


def render_graph(graph, shape=None) -> np.ndarray:
    """Evaluate ``graph`` on the GPU at every pixel of ``shape`` ((H, W); default: the
    graph's size): float32 ``(H, W)`` for a scalar graph, ``(H, W, 4)`` RGBA for a colour one.
    Row ``j``, column ``i`` is the point ``(i / W, j / W)``, as :meth:`Graph.evaluate`."""
    h, w = graph._shape(shape)
    colour = graph.output.spec.output == "colour"
    src = compile_glsl(graph, shape=(h, w))
    store = "color = sylva_texture(q);" if colour else \
        "color = vec4(sylva_texture(q), 0.0, 0.0, 1.0);"
    frag = ("#version 330\n" + src + "\nout vec4 color;\nvoid main() {\n"
            "    vec3 q = vec3(floor(gl_FragCoord.x), floor(gl_FragCoord.y), 0.0) / "
            f"{float(w)!r};\n"
            f"    {store}\n}}\n")
    ctx = get_context()
    prog = ctx.program(vertex_shader=_VERTEX, fragment_shader=frag)
    vbo = ctx.buffer(np.array([-1, -1, 3, -1, -1, 3], dtype="f4").tobytes())
    vao = ctx.vertex_array(prog, [(vbo, "2f", "pos")])
    tex = ctx.texture((w, h), 4, dtype="f4")
    fbo = ctx.framebuffer(color_attachments=[tex])
    try:
        fbo.use()
        ctx.viewport = (0, 0, w, h)
        vao.render()
        out = np.frombuffer(fbo.read(components=4, dtype="f4"), dtype="f4").reshape(h, w, 4)
    finally:
        for obj in (fbo, tex, vao, vbo, prog):
            obj.release()
    return out.copy() if colour else out[..., 0].copy()
