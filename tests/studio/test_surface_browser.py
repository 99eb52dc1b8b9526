"""The studio's bark and leaf are the texture graphs' GLSL (issue 22): the page fetches
``/api/surfaces.glsl`` and runs it in WebGL2 (Chromium's SwiftShader here) to the CPU
kernel's values, and the viewer shades a GLB's bark with it."""

from __future__ import annotations

import base64
import io

import numpy as np
import pytest

from sylva.geometry.exchange import write_glb
from sylva.geometry.mesh import Material, Mesh, Scene
from sylva.texture.graph.surface import bark_graph, evaluate_uv, leaf_graph
from sylva.tree.stem import Stem, stems_to_arrays

N = 24

# A WebGL2 float target drawing FN(q) at q = ((i + 0.5) / N, 2 (j + 0.5) / N, 0)
_RUN = """async ([fn, n]) => {
    const glsl = await (await fetch("/api/surfaces.glsl")).text();
    const canvas = document.createElement("canvas");
    canvas.width = n; canvas.height = n;
    const gl = canvas.getContext("webgl2");
    if (!gl.getExtension("EXT_color_buffer_float")) return "no float targets";
    const sh = (type, src) => {
        const s = gl.createShader(type);
        gl.shaderSource(s, src); gl.compileShader(s);
        if (!gl.getShaderParameter(s, gl.COMPILE_STATUS)) throw new Error(gl.getShaderInfoLog(s));
        return s;
    };
    const prog = gl.createProgram();
    gl.attachShader(prog, sh(gl.VERTEX_SHADER, "#version 300 es\\nin vec2 p;\\n" +
        "void main() { gl_Position = vec4(p, 0.0, 1.0); }"));
    gl.attachShader(prog, sh(gl.FRAGMENT_SHADER, "#version 300 es\\nprecision highp float;\\n" +
        "precision highp int;\\n" + glsl + "\\nout vec4 color;\\nvoid main() {\\n" +
        "  vec2 c = (floor(gl_FragCoord.xy) + 0.5) / float(" + n + ");\\n" +
        "  color = " + fn + "(vec3(c.x, 2.0 * c.y, 0.0));\\n}\\n"));
    gl.bindAttribLocation(prog, 0, "p");
    gl.linkProgram(prog);
    if (!gl.getProgramParameter(prog, gl.LINK_STATUS)) throw new Error(gl.getProgramInfoLog(prog));
    const tex = gl.createTexture();
    gl.bindTexture(gl.TEXTURE_2D, tex);
    gl.texStorage2D(gl.TEXTURE_2D, 1, gl.RGBA32F, n, n);
    const fbo = gl.createFramebuffer();
    gl.bindFramebuffer(gl.FRAMEBUFFER, fbo);
    gl.framebufferTexture2D(gl.FRAMEBUFFER, gl.COLOR_ATTACHMENT0, gl.TEXTURE_2D, tex, 0);
    gl.viewport(0, 0, n, n);
    gl.useProgram(prog);
    const buf = gl.createBuffer();
    gl.bindBuffer(gl.ARRAY_BUFFER, buf);
    gl.bufferData(gl.ARRAY_BUFFER, new Float32Array([-1, -1, 3, -1, -1, 3]), gl.STATIC_DRAW);
    gl.enableVertexAttribArray(0);
    gl.vertexAttribPointer(0, 2, gl.FLOAT, false, 0, 0);
    gl.drawArrays(gl.TRIANGLES, 0, 3);
    const out = new Float32Array(n * n * 4);
    gl.readPixels(0, 0, n, n, gl.RGBA, gl.FLOAT, out);
    return Array.from(out);
}"""


@pytest.fixture(scope="module")
def page(browser, live):
    ctx = browser.new_context(viewport={"width": 800, "height": 600}, bypass_csp=True)
    pg = ctx.new_page()
    pg.errors = []
    pg.on("pageerror", lambda e: pg.errors.append(str(e)))
    pg.on("console", lambda m: m.type == "error" and pg.errors.append(m.text))
    pg.goto(live.url + "/")
    pg.wait_for_selector("body[data-ready='1']", timeout=30_000)
    yield pg
    ctx.close()


# the leaf's veins are a sine of up to 2 pi 14, whose precision GLSL ES leaves to the driver
# (SwiftShader's is ~1e-5, times the vein's s-curve slope of ~10)
@pytest.mark.parametrize("fn,graph,tol", [("sylva_bark_graph", bark_graph, 1e-4),
                                          ("sylva_leaf_graph", leaf_graph, 1e-3)])
def test_webgl_runs_the_graphs_glsl_to_the_cpu_values(page, fn, graph, tol):
    got = page.evaluate(_RUN, [fn, N])
    if isinstance(got, str):
        pytest.skip(got)
    got = np.array(got, np.float64).reshape(N, N, 4)  # row j at v = 2 (j + 0.5) / N
    c = (np.arange(N) + 0.5) / N
    uu, vv = np.meshgrid(c, 2.0 * c)
    want = evaluate_uv(graph(), uu, vv).reshape(N, N, 4)
    assert want.std() > 0.05
    assert np.abs(got - want).max() < tol
    assert not page.errors, page.errors


def test_the_viewer_draws_a_glbs_bark_with_the_graph(page):
    bark = Material("bark", color=(0.8, 0.55, 0.35, 1.0), texture="bark")
    s = Stem(sides=32)
    y = np.linspace(0.0, 3.0, 17)
    s.add_points(np.c_[np.zeros_like(y), y, np.zeros_like(y)], None, np.full_like(y, 0.4))
    v, n, uv, tri, _, _ = stems_to_arrays([s])
    buf = io.BytesIO()
    write_glb(Scene([Mesh(v, tri, normals=n, uvs=uv, materials=[bark])]), buf)
    kinds = page.evaluate("""async (b64) => {
        const bytes = Uint8Array.from(atob(b64), (c) => c.charCodeAt(0));
        const v = window.studio.viewer;
        await v.showGlb(bytes.buffer, { fit: true });
        v._render();
        const kinds = [];
        v.plant.traverse((o) => { if (o.isMesh) kinds.push(o.material.userData.sylvaSurface); });
        return kinds;
    }""", base64.b64encode(buf.getvalue()).decode())
    assert kinds == ["bark"]
    from PIL import Image

    img = np.asarray(Image.open(io.BytesIO(page.locator("#view").screenshot())).convert("L"))
    h, w = img.shape
    face = img[h // 3: 2 * h // 3, w // 2 - 6: w // 2 + 6].astype(float)
    # down each column a plain cylinder under the viewer's lights is one flat tone; the bark
    # graph's cracks break it
    assert face.std(axis=0).mean() > 3, face.std(axis=0).mean()
    assert not page.errors, page.errors
