"""GLSL of the formula language (issue 22): escape-time fractals and formula nodes run on the
GPU (llvmpipe here) to the CPU kernel's values on a grid.

The CPU computes in float64, the shader in float32.  Near the boundary of a fractal's set the
orbit is chaotic and the two iteration counts part at once, so the escape-time graphs are
sampled in regions away from it, where every orbit leaves within a few iterations (or,
inside the set, converges to an attracting cycle): there the orbit's rounding error stays
near float32's 6e-8 relative times the few doublings of z -> z^2 + c, and the smooth
colouring index (n + 1 - log2(log|z| / log B)) moves by about that error over log|z|.
Measured on llvmpipe: at most 5e-7 for the four built-in fractals, 4e-6 for the custom
node (exp, log, sin of values up to ~10), 2e-5 for the orbit trap (up to 17 iterations, the
error doubling with each).  The index is continuous where the iteration count steps (at
|z| = B both sides give n + 1), so a pixel whose count differs by one between float32 and
float64 moves the index by that small amount, not by one.  The tolerances are those
figures with a margin of 20-200x for other drivers' log and exp (GLSL leaves their
precision to the driver).  Without smoothing the counts themselves are compared: equal.

Not covered, on purpose: regions on the boundary of the set (there float32 and float64
orbits part after a few dozen iterations, as any two precisions do), and barnsley-j1's
plain variant (zz = 0), whose set fills most of the plane with chaotic orbits.
"""

import numpy as np
import pytest

from sylva.texture import graph as tg

pytest.importorskip("moderngl")
from sylva.render.texgraph import render_graph  # noqa: E402

SHAPE = (20, 28)

CUSTOM = """custom {
default:
  k = (0.5, -0.25)
init:
  z = #pixel
final:
  w = exp(z * @k) * sqrt(z) + z^3 / (z + (2, 1)) - log(z + 3) + sin(z) * cos(conj(z))
  v = z ^ (0.5, 0.5)
  if real(w) > imag(w)
    #index = cabs(w) + atan2(v) + #in1
  else
    #index = |w| * 0.1 - floor(real(z) * 3) + abs(imag(w))
  endif
}
"""

ORBIT = """orbit {
default:
  maxiter = 60
  bailout = 16.0
init:
  z = 0
  c = #pixel
  trap = 100
loop:
  z = z * z + c
  trap = min(trap, cabs(z - (0.5, 0.5)))
bailout:
  |z| < @bailout
final:
  #index = #numiter + trap
inside:
  #index = -trap
}
"""


def _gpu_or_skip(graph):
    try:
        return render_graph(graph, SHAPE)
    except Exception as exc:  # no GL context on this machine
        if "GraphError" in type(exc).__name__:
            raise
        pytest.skip(f"no OpenGL context: {exc}")


@pytest.mark.parametrize("name,node,tol", [
    # every orbit leaves within a few iterations in these regions (|c| > 1.2, far from M)
    ("mandelbrot", tg.mandelbrot(center=[1.4, 1.0], width=1.0), 1e-5),
    ("mandelbrot, no smoothing", tg.mandelbrot(center=[-2.6, 0.4], width=0.8,
                                               params={"smooth": 0}), 0.0),
    ("julia", tg.julia(center=[1.9, 0.9], width=0.8, params={"c": [-0.8, 0.156]}), 1e-5),
    ("burning ship", tg.burning_ship(center=[1.6, 1.4], width=0.8), 1e-5),
    ("barnsley-j1 zz", tg.barnsley_j1(center=[1.0, 1.4], width=0.6,
                                      params={"zz": 1, "start": [0.6, 1.1]}), 1e-5),
    # no iteration: the complex library (exp, log, sqrt, sin, cos, powers, division)
    ("custom node", tg.formula(tg.x(), source=CUSTOM, center=[0.6, 0.4], width=2.0), 1e-4),
    # an orbit trap outside the set (final:) and inside it (the inside: section)
    ("orbit trap", tg.formula(source=ORBIT, center=[-1.4, 0.6], width=0.5), 5e-4),
    ("orbit trap inside", tg.formula(source=ORBIT, center=[-0.15, 0.1], width=0.2), 1e-5),
])
def test_formula_glsl_equals_the_cpu_away_from_the_set_boundary(name, node, tol):
    g = tg.Graph(node)
    cpu = g.evaluate(SHAPE, dtype=np.float64)
    gpu = _gpu_or_skip(g)
    assert gpu.shape == cpu.shape
    assert np.ptp(cpu) > 0.15, name  # not a flat image: the index varies over the grid
    assert np.abs(gpu - cpu).max() <= tol, (name, np.abs(gpu - cpu).max())


def test_formula_nodes_feed_the_rest_of_the_graph():
    # an index coloured by a gradient: the colour graph of a fractal runs on the GPU
    idx = tg.mandelbrot(center=[1.4, 1.0], width=1.0)
    g = tg.Graph(tg.gradient(idx, colors="fire", vmin=0.0, vmax=6.0))
    cpu = g.evaluate(SHAPE, dtype=np.float64)
    gpu = _gpu_or_skip(g)
    assert cpu[..., :3].std() > 0.05
    assert np.abs(gpu - cpu).max() < 1e-4


def test_a_formulas_own_names_are_valid_glsl():
    # x_ would be u_x__r in the numba lines: GLSL reserves names with "__"
    src = """names {
init:
  x_ = #pixel * 2
  a__b = real(x_) + 1
final:
  #index = a__b + imag(x_)
}
"""
    g = tg.Graph(tg.formula(source=src, center=[0.3, -0.2], width=2.0))
    assert "__" not in g.glsl().split("sylva_formula1(float")[1]
    cpu = g.evaluate(SHAPE, dtype=np.float64)
    assert np.abs(_gpu_or_skip(g) - cpu).max() < 1e-5
