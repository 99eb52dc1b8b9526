"""Render benchmark: a 1 M-triangle plant at 1920 × 1080 against a bare moderngl draw.

The plant (``--triangles``, 1 M by default: ¾ tapered branches with bark uvs, ¼ double-sided
leaf quads) is drawn on the shared context by

* ``bare``: a minimal moderngl program (position + normal, one Lambert light) into a
  single-sampled framebuffer, then the pixels are read back;
* ``sylva``: :meth:`sylva.render.Renderer.render` with the same single sampling, Phong lighting
  from the default sun and no extras (no shadows, textures or ground): the renderer's cost for
  the same work, which must stay within 1.5 × ``bare``;
* ``sylva full``: the default look (4× MSAA, shadow-casting sun, procedural bark, leaf and grass
  textures, ground plane), with and without MSAA, for later frames (shadow map reused, as in a
  turntable) and the first frame (with the shadow pass).

The candidates take turns (``--repeat`` rounds after a warm-up) in the same process and the
same context; ratios use the best time of each, the least disturbed by other load.  The script
exits with status 1 when ``sylva / bare`` exceeds 1.5.

Usage::

    .venv/bin/python benchmarks/render.py [--triangles 1000000] [--size 1920x1080] [--repeat 5]
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time

import moderngl
import numpy as np

from sylva.geometry.mesh import Material, Mesh, Scene
from sylva.render import Camera, Renderer, context_info, get_context

BARK = Material("bark", color=(0.36, 0.24, 0.13, 1.0), roughness=0.8, texture="bark")
LEAF = Material(
    "leaf", color=(0.14, 0.42, 0.08, 1.0), roughness=0.5, texture="leaf", double_sided=True
)

BARE_VERTEX = """
#version 330 core
uniform mat4 u_mvp;
in vec3 in_position;
in vec3 in_normal;
out vec3 v_normal;
void main() {
    v_normal = in_normal;
    gl_Position = u_mvp * vec4(in_position, 1.0);
}
"""
BARE_FRAGMENT = """
#version 330 core
in vec3 v_normal;
out vec4 f_color;
void main() {
    float d = max(dot(normalize(v_normal), normalize(vec3(0.4, 1.0, 0.3))), 0.0);
    f_color = vec4(vec3(0.2 + 0.8 * d) * vec3(0.4, 0.3, 0.2), 1.0);
}
"""


def _frame(axis: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Two unit vectors perpendicular to each row of ``axis`` (rows unit length)."""
    helper = np.where(np.abs(axis[:, :1]) < 0.9, [[1.0, 0, 0]], [[0, 0, 1.0]])
    e1 = np.cross(axis, helper)
    e1 /= np.linalg.norm(e1, axis=1, keepdims=True)
    return e1, np.cross(axis, e1)


def branches(n: int, rng: np.random.Generator) -> tuple[np.ndarray, ...]:
    """Start, end, start radius and end radius of ``n`` branches of a random binary tree."""
    starts = np.zeros((n, 3))
    ends = np.zeros((n, 3))
    r0 = np.zeros(n)
    ends[0] = (0, 3.0, 0)
    r0[0] = 0.25
    for i in range(1, n):
        parent = (i - 1) // 2
        t = rng.uniform(0.55, 1.0)
        starts[i] = starts[parent] + t * (ends[parent] - starts[parent])
        pdir = ends[parent] - starts[parent]
        plen = np.linalg.norm(pdir)
        d = pdir / plen + rng.normal(0, 0.6, 3) + (0, 0.25, 0)
        d /= np.linalg.norm(d)
        ends[i] = starts[i] + d * plen * rng.uniform(0.62, 0.8)
        r0[i] = r0[parent] * rng.uniform(0.55, 0.72)
    return starts, ends, r0, r0 * 0.7


def tapered_cylinders(starts, ends, r0, r1, sections: int, rings: int) -> Mesh:
    """Open tapered cylinders with uvs (u around, v along), all in one vectorised mesh."""
    n = len(starts)
    axis = ends - starts
    length = np.linalg.norm(axis, axis=1, keepdims=True)
    a = axis / length
    e1, e2 = _frame(a)
    u = np.arange(sections + 1) / sections
    v = np.arange(rings + 1) / rings
    ang = 2 * np.pi * u
    ring = np.cos(ang)[None, :, None] * e1[:, None] + np.sin(ang)[None, :, None] * e2[:, None]
    radius = r0[:, None] + (r1 - r0)[:, None] * v[None, :]  # (n, rings+1)
    centre = starts[:, None] + v[None, :, None] * axis[:, None]  # (n, rings+1, 3)
    pos = centre[:, :, None] + radius[:, :, None, None] * ring[:, None]  # (n, R, S, 3)
    nrm = np.broadcast_to(ring[:, None], pos.shape)
    uv = np.stack(np.meshgrid(u, v), axis=-1)  # (R, S, 2)
    per = (rings + 1) * (sections + 1)
    grid = np.arange(per).reshape(rings + 1, sections + 1)
    a0, a1 = grid[:-1, :-1].ravel(), grid[:-1, 1:].ravel()
    b0, b1 = grid[1:, :-1].ravel(), grid[1:, 1:].ravel()
    quad = np.concatenate([np.stack([a0, a1, b1], 1), np.stack([a0, b1, b0], 1)])
    idx = (quad[None] + per * np.arange(n)[:, None, None]).reshape(-1, 3)
    return Mesh(
        pos.reshape(-1, 3),
        idx,
        normals=nrm.reshape(-1, 3),
        uvs=np.broadcast_to(uv, (n, *uv.shape)).reshape(-1, 2),
        materials=[BARK],
        name="branches",
    )


def leaves(starts, ends, count: int, rng: np.random.Generator) -> Mesh:
    """``count`` leaf quads on the thinner half of the branches."""
    n = len(starts)
    pick = rng.integers(n // 2, n, count)
    at = starts[pick] + rng.uniform(0.3, 1.0, (count, 1)) * (ends[pick] - starts[pick])
    d = rng.normal(0, 1, (count, 3)) + (0, 0.8, 0)
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    side, normal = _frame(d)
    size = rng.uniform(0.05, 0.09, (count, 1))
    corners = np.stack(
        [
            at - side * size * 0.4,
            at + side * size * 0.4,
            at + side * size * 0.4 + d * size * 2,
            at - side * size * 0.4 + d * size * 2,
        ],
        1,
    )
    quad = np.array([[0, 1, 2], [0, 2, 3]])
    idx = (quad[None] + 4 * np.arange(count)[:, None, None]).reshape(-1, 3)
    uvs = np.tile(np.array([[0, 0], [1, 0], [1, 1], [0, 1]], float), (count, 1))
    nrm = np.repeat(normal, 4, axis=0)
    return Mesh(corners.reshape(-1, 3), idx, normals=nrm, uvs=uvs, materials=[LEAF], name="leaves")


def plant(triangles: int, seed: int = 7) -> Scene:
    """A plant of about ``triangles`` triangles: ¾ bark (16 × 16 per branch), ¼ leaves."""
    rng = np.random.default_rng(seed)
    per_branch = 2 * 16 * 16
    n_branches = max(1, int(0.75 * triangles) // per_branch)
    s, e, r0, r1 = branches(n_branches, rng)
    bark = tapered_cylinders(s, e, r0, r1, 16, 16)
    n_leaves = max(0, (triangles - bark.n_triangles) // 2)
    return Scene([bark, leaves(s, e, n_leaves, rng)], name="benchmark plant")


def interleaved(fns: dict, repeat: int) -> dict:
    """Best and median seconds of each function, run in turn ``repeat`` times after a warm-up.

    Taking turns spreads other load on the machine over all candidates alike; the best time
    is the least disturbed.
    """
    for fn in fns.values():
        fn()
    times: dict = {name: [] for name in fns}
    for _ in range(repeat):
        for name, fn in fns.items():
            t = time.perf_counter()
            fn()
            times[name].append(time.perf_counter() - t)
    return {name: (min(ts), statistics.median(ts)) for name, ts in times.items()}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--triangles", type=int, default=1_000_000)
    ap.add_argument("--size", default="1920x1080")
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--gallery", action="store_true",
                    help="also time the whole `sylva render` of every gallery example")
    args = ap.parse_args(argv)
    w, h = (int(x) for x in args.size.lower().split("x"))

    t = time.perf_counter()
    scene = plant(args.triangles)
    build = time.perf_counter() - t
    mesh = scene.merged()
    ctx = get_context()
    info = context_info(ctx)
    print(
        f"device: {info['renderer']} (GL {info['version']}), {mesh.n_triangles:,} triangles, "
        f"{mesh.n_vertices:,} vertices, {w}x{h}; plant built in {build:.2f} s"
    )

    renderer = Renderer.default()
    cam = Camera.auto(scene, "perspective", yaw=30, pitch=15, aspect=w / h)
    near, far = cam.clip_planes(mesh.bounds())
    mvp = cam.projection_matrix(w / h, near, far) @ cam.view_matrix()

    # --- bare moderngl: same triangles, same size, same context ---------------------------
    t = time.perf_counter()
    prog = ctx.program(vertex_shader=BARE_VERTEX, fragment_shader=BARE_FRAGMENT)
    vbo_p = ctx.buffer(mesh.vertices.tobytes())
    vbo_n = ctx.buffer(mesh.normals.tobytes())
    ibo = ctx.buffer(mesh.indices.tobytes())
    vao = ctx.vertex_array(
        prog,
        [(vbo_p, "3f", "in_position"), (vbo_n, "3f", "in_normal")],
        index_buffer=ibo,
        index_element_size=4,
    )
    fbo = ctx.framebuffer(
        color_attachments=[ctx.renderbuffer((w, h), 4)],
        depth_attachment=ctx.depth_renderbuffer((w, h)),
    )
    prog["u_mvp"].write(mvp.T.astype("f4").tobytes())
    ctx.finish()
    bare_upload = time.perf_counter() - t

    def bare():
        fbo.use()
        fbo.clear(1.0, 1.0, 1.0, 1.0, depth=1.0)
        ctx.enable(moderngl.DEPTH_TEST)
        vao.render(moderngl.TRIANGLES)
        data = fbo.read(components=4, alignment=1)
        return np.frombuffer(data, np.uint8).reshape(h, w, 4)[::-1, :, :3].copy()

    # --- sylva ------------------------------------------------------------------------------
    t = time.perf_counter()
    gpu = renderer.upload(scene)
    ctx.finish()
    sylva_upload = time.perf_counter() - t

    def sylva():
        return renderer.render(
            gpu, (w, h), cam, msaa=0, shadows=False, textures=False, ground=False
        )

    def sylva_full():
        return renderer.render(gpu, (w, h), cam)

    def sylva_full_no_msaa():
        return renderer.render(gpu, (w, h), cam, msaa=0)

    gpu.forget_shadows()
    t = time.perf_counter()
    sylva_full()  # first frame: includes the shadow pass
    t_first = time.perf_counter() - t
    res = interleaved({"bare": bare, "sylva": sylva}, args.repeat)
    full = interleaved(
        {"bare": bare, "full": sylva_full, "nomsaa": sylva_full_no_msaa}, max(1, args.repeat // 2)
    )
    (t_bare, m_bare), (t_sylva, m_sylva) = res["bare"], res["sylva"]
    ratio = t_sylva / t_bare
    print(f"upload: bare {bare_upload:.3f} s, sylva {sylva_upload:.3f} s")
    print(f"{'':32s}{'best':>10s}{'median':>10s}")
    print(f"{'bare moderngl draw + readback':32s}{t_bare * 1e3:8.0f}ms{m_bare * 1e3:8.0f}ms")
    print(
        f"{'sylva render, same settings':32s}{t_sylva * 1e3:8.0f}ms{m_sylva * 1e3:8.0f}ms"
        f"   {ratio:.2f}x bare"
    )
    fb, ff = full["bare"][0], full["full"][0]
    print(
        f"{'sylva full look (next frames)':32s}{ff * 1e3:8.0f}ms{full['full'][1] * 1e3:8.0f}ms"
        f"   {ff / fb:.2f}x bare"
    )
    fn = full["nomsaa"][0]
    print(
        f"{'  the same without MSAA':32s}{fn * 1e3:8.0f}ms{full['nomsaa'][1] * 1e3:8.0f}ms"
        f"   {fn / fb:.2f}x bare"
    )
    print(f"{'sylva full look, first frame':32s}{t_first * 1e3:8.0f}ms   (with the shadow pass)")
    ok = ratio <= 1.5
    print(f"target sylva/bare <= 1.5: {'met' if ok else 'MISSED'}")
    for obj in (vao, prog, vbo_p, vbo_n, ibo, fbo):
        obj.release()
    gpu.release()
    if args.gallery:
        gallery_times(args.size)
    return 0 if ok else 1


def gallery_times(size: str) -> None:
    """The whole ``sylva render`` (load, grow, mesh, render, save) of every example."""
    import contextlib
    import io
    import tempfile

    from sylva.cli import main as sylva_main
    from sylva.data import examples

    print(f"\nsylva render EXAMPLE --size {size}: whole command, in-process")
    with tempfile.TemporaryDirectory() as tmp:
        for ex in examples():
            out = f"{tmp}/{ex.name}.png"
            t = time.perf_counter()
            with contextlib.redirect_stderr(io.StringIO()):
                sylva_main(["render", str(ex.path), "-o", out, "--size", size])
            print(f"  {ex.name:40s} {time.perf_counter() - t:6.2f} s")


if __name__ == "__main__":
    sys.exit(main())
