"""A texture graph's two roads give the same values: its fused kernel compiled by numba, and
the same generated source run as Python (the road a graph takes while its kernel is neither
compiled nor cached and the image is small: issue 25, the suite compiled a kernel per
graph a test builds, about 1.3 CPU s each).  Bit for bit, float64 and float32: the Python
road calls the same compiled row and point kernels and does the per-sample arithmetic in
IEEE float64 as the kernel does."""

import numpy as np

from sylva.texture import graph as tg
from sylva.texture.graph import Node, _compile
from sylva.texture.graph._compile import evaluate as _evaluate

SHAPE = (6, 10)


def _both(nodes, shape=SHAPE, dtype=np.float64, **props):
    g = tg.Graph(nodes[0], **props)
    py = _evaluate(g, shape, dtype, outputs=nodes, road="python")
    jit = _evaluate(g, shape, dtype, outputs=nodes, road="compiled")
    return py, jit


def test_scalar_graph_roads_are_equal_bit_for_bit():
    # every kind of per-sample code once (more blocks of rows than one), in one kernel
    a = tg.improved(scale=3.0, seed=1)
    b = tg.value(scale=2.0, seed=2, octaves=2)
    x = tg.x()
    base = tg.gradient(a, colors="terrain", vmin=-1.0, vmax=1.0)
    top = tg.gradient(tg.y(), colors=["#ff0000", "#0000ff"], vmin=0.0, vmax=0.6)
    nodes = [
        a, tg.exponent(a, exponent=2.0),
        tg.sin(b * 3.0), tg.fract(b * 4.0), tg.smoothstep(a + 0.5), abs(a) ** (b + 1.5),
        a ** b, tg.select(a, b, x, lower=0.2, upper=0.6, falloff=0.1),
        tg.curve(a, points=[[-1.0, -0.5], [-0.2, 0.1], [0.3, -0.1], [0.8, 0.9]]),
        tg.terrace(a, points=[-1.0, 0.0, 1.0], invert=True),
        tg.rotate(a, angle=30.0, center=[0.5, 0.25]), tg.warp(a, dx=b, dy=x, amount=0.3),
        tg.x(closed=True), (abs(a) + 1.0) / 0.0,
        Node("fbm", params=dict(scale=3.0, octaves=3, seed=6, warp=1.5)),
        tg.luminance(tg.layer(base, top, mode="overlay", opacity=0.75)),
        tg.mandelbrot(), tg.wood(),
    ]
    py, jit = _both(nodes, shape=(20, 6))
    assert np.isinf(py[13]).all() and np.isnan(py[6]).any()  # a ** b of a < 0: NaN
    assert np.array_equal(py, jit, equal_nan=True)


def test_float32_roads_are_equal_bit_for_bit():
    gens = [tg.fbm(kind=k, scale=4.0, octaves=2, seed=3) for k in ("perlin", "simplex")]
    py, jit = _both([*gens, gens[0] * gens[1] + 0.5], shape=(19, 5), dtype=np.float32)
    assert py.dtype == np.float32 and np.isfinite(py).all() and np.array_equal(py, jit)


def test_small_work_on_a_cold_kernel_takes_the_python_road(monkeypatch):
    roads = []
    python = _compile._python
    monkeypatch.setattr(_compile, "_python", lambda *a: roads.append("python") or python(*a))
    monkeypatch.setattr(_compile, "_run", lambda *a: roads.append("compiled"))  # no compile
    g = tg.Graph(tg.value(scale=2.0, seed=11) * 0.25 + tg.sin(tg.x() * 7.0))
    monkeypatch.setenv("SYLVA_JIT", "never")
    g.evaluate((4, 6), dtype=np.float64)
    monkeypatch.setenv("SYLVA_JIT", "always")
    g.evaluate((4, 6), dtype=np.float64)
    monkeypatch.delenv("SYLVA_JIT")
    g.evaluate((4, 6), dtype=np.float64)  # a cold kernel (not evaluated yet, not cached)
    g.evaluate((1024, 1024), dtype=np.float64)  # large work: compiling pays
    assert roads == ["python", "compiled", "python", "compiled"]
