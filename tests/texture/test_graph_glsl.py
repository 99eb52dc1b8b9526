"""GLSL from the graph: the shader the GPU (llvmpipe here) runs gives the CPU kernel's
values on a grid within float32 tolerance, for every node kind GLSL covers."""

import numpy as np
import pytest

from sylva.render.texgraph import render_graph
from sylva.texture import graph as tg
from sylva.texture.graph import GraphError
from sylva.texture.graph._compile import evaluate as _evaluate

SHAPE = (20, 28)


def _graphs():
    a = tg.improved(scale=5.0, octaves=4, seed=3)
    b = tg.fbm(kind="simplex", scale=3.0, octaves=3, seed=1)
    c = tg.value(scale=6.0, octaves=2, seed=4, interpolation="cubic")
    r = tg.ridged(scale=4.0, octaves=3, seed=2)
    sel = tg.select(a, b, c, lower=-0.1, upper=0.3, falloff=0.1)
    mods = tg.terrace(tg.curve(tg.rotate(sel, angle=30.0),
                               points=[[-1, -1], [-0.3, 0.2], [0.3, -0.2], [1, 1]]),
                      points=[-1, 0, 0.5, 1])
    mix = tg.blend(tg.clamp(abs(a) * 2.0, lower=0, upper=1), tg.scale_bias(c, scale=0.5,
                                                                           bias=0.5),
                   tg.smoothstep(tg.x() * 1.5)) + tg.exponent(r, exponent=1.5)
    warp = tg.warp(tg.translate(a, by=[0.1, 0.2]), dx=b, dy=c, amount=0.1) * tg.sin(tg.y())
    colour = tg.layer(tg.gradient(mods, colors="terrain", vmin=-1, vmax=1),
                      tg.gradient(r, colors="fire"), mode="overlay", opacity=0.5)
    screen = tg.layer(tg.rgb(tg.x(), c * 0.5 + 0.5, 0.3), tg.color(value="#3366cc", alpha=0.7),
                      mode="soft-light")
    perlin = tg.perlin(scale=5.0, octaves=3, seed=6)
    worleys = [
        ("worley f1", tg.worley(scale=6.0, seed=2), {}),
        ("worley f2-f1 manhattan", tg.worley(scale=5.0, seed=3, output="f2-f1",
                                             metric="manhattan", jitter=0.8), {}),
        ("worley f3 chebyshev", tg.worley(scale=4.0, seed=4, output="f3",
                                          metric="chebyshev"), {}),
        ("worley cell", tg.worley(scale=3.0, seed=5, output="cell"), {}),
        ("worley sqrt(f1*f2) squared", tg.worley(scale=4.0, seed=1, output="sqrt(f1*f2)",
                                                 metric="euclidean2"), {}),
        ("worley fbm tileable 3D", tg.fbm(kind="worley", scale=3.0, octaves=3, seed=7,
                                          output="1-f2"), {"tileable": True, "time": 0.4}),
        ("worley under warp", tg.warp(tg.worley(scale=5.0, seed=8, output="f1+f2"), dx=b,
                                      dy=c, amount=0.05), {}),
    ]
    return [
        ("perlin", tg.Graph(perlin), 5e-5),
        ("perlin 3D tileable", tg.Graph(tg.turbulence(kind="perlin", scale=4.0, octaves=3,
                                                      seed=2), tileable=True, time=1.3), 5e-5),
        ("perlin ridged", tg.Graph(tg.ridged(kind="perlin", scale=3.0, octaves=4)), 5e-5),
        *[(name, tg.Graph(n, **props), 1e-4) for name, n, props in worleys],
        *[(f"pattern {name}", tg.Graph(n, **props), 2e-4) for name, n, props in _patterns()],
        ("improved", tg.Graph(a), 5e-5),
        ("simplex", tg.Graph(b), 5e-5),
        ("value", tg.Graph(c), 5e-5),
        ("ridged", tg.Graph(r), 5e-5),
        ("tileable 3D (time)", tg.Graph(a, tileable=True, time=0.3), 5e-5),
        ("modifiers", tg.Graph(mods), 1e-4),
        ("combiners", tg.Graph(mix), 1e-4),
        ("transformers", tg.Graph(warp), 1e-4),
        ("colour layers", tg.Graph(colour), 1e-3),
        ("soft light", tg.Graph(screen), 1e-4),
    ]


def _patterns():
    """Every pattern node GLSL covers (as a graph of primitives), plain, tiled and animated."""
    return [
        ("marble", tg.marble(seed=3, turbulence=1.5), {}),
        ("marble tileable time", tg.marble(seed=4, stripes=3.4), {"tileable": True,
                                                                  "time": 0.7}),
        ("wood", tg.wood(seed=2), {}),
        ("wood tileable", tg.wood(seed=5, rings=6.6), {"tileable": True}),
        ("clouds", tg.clouds(seed=1, octaves=5, coverage=0.8), {}),
        ("granite", tg.granite(seed=6, scale=8.0), {}),
        ("granite tileable", tg.granite(seed=7, scale=6.0), {"tileable": True}),
        ("bark", tg.bark(seed=5), {}),
        ("bark unstretched", tg.bark(seed=2, stretch=0.0), {"time": 0.5}),
        ("bark tileable", tg.bark(seed=3), {"tileable": True}),
        ("leaf", tg.leaf(), {}),
        ("leaf with noise", tg.leaf(noise=0.1, seed=2), {"time": 0.2}),
        ("grass", tg.grass(seed=3), {}),
        ("grass tileable", tg.grass(seed=4, octaves=2), {"tileable": True}),
    ]


GRAPHS = _graphs()


@pytest.fixture(scope="module")
def cpu():
    """The CPU values of every graph, by few kernels (one per kind of output and tiling)."""
    out = {}
    groups = {}
    for name, g, _ in GRAPHS:
        groups.setdefault((g.output.spec.output, g.tileable, g.time), []).append((name, g))
    for items in groups.values():
        vals = _evaluate(items[0][1], SHAPE, np.float64, outputs=[g.output for _, g in items])
        out.update({name: v for (name, _), v in zip(items, vals)})
    return out


@pytest.mark.parametrize("name,graph,tol", GRAPHS, ids=[g[0] for g in GRAPHS])
def test_glsl_equals_cpu_within_float32_tolerance(cpu, name, graph, tol):
    cpu = cpu[name]
    gpu = render_graph(graph, SHAPE)
    assert gpu.shape == cpu.shape
    assert np.abs(cpu).max() > 0.05  # not a blank image
    assert np.abs(gpu - cpu).max() < tol, name


def test_nodes_without_glsl_are_errors():
    with pytest.raises(GraphError, match="no GLSL for worley orders above F3"):
        tg.Graph(tg.worley_fn(scale=3.0, output="f5")).glsl()
    with pytest.raises(GraphError, match="Poisson"):
        tg.Graph(tg.worley(scale=3.0, density=2.0)).glsl()
    with pytest.raises(GraphError, match="no GLSL for ifs"):
        tg.Graph(tg.ifs()).glsl()
    # escape-time fractals and formula nodes have GLSL now: tests/texture/test_formula_glsl.py
