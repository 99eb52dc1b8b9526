"""The formula language: the four fractals re-expressed in it give today's images bit for
bit, orbit traps colour by the orbit, and bad formulas are errors at their file, line and
column."""

import numpy as np
import pytest

from sylva.texture import barnsley_j1, burning_ship, julia, mandelbrot
from sylva.texture import graph as tg
from sylva.texture.graph import GraphError, Node
from sylva.texture.graph._compile import evaluate as _evaluate

SHAPE = (18, 26)


def test_builtin_formulas_equal_todays_fractals():
    nodes = [
        Node("mandelbrot", params={"params": {"maxiter": 60}}),
        Node("mandelbrot", params={"center": [-0.745, 0.105], "width": 0.03,
                                   "params": {"maxiter": 200, "smooth": 0}}),
        Node("julia", params={"params": {"c": [0.0, 1.0], "maxiter": 80}}),
        Node("burning-ship", params={"center": [-1.762, -0.028], "width": 0.08,
                                     "params": {"maxiter": 90}}),
        Node("barnsley-j1", params={}),
        Node("barnsley-j1", params={"params": {"start": [1.6, 1.1], "zz": 1, "bailout": 3.0}}),
    ]
    got = _evaluate(tg.Graph(nodes[0]), SHAPE, np.float64, outputs=nodes)
    want = [
        mandelbrot(SHAPE, maxiter=60, dtype=np.float64),
        mandelbrot(SHAPE, center=(-0.745, 0.105), width=0.03, maxiter=200, smooth=False,
                   dtype=np.float64),
        julia(SHAPE, (0.0, 1.0), maxiter=80, dtype=np.float64),
        burning_ship(SHAPE, center=(-1.762, -0.028), width=0.08, maxiter=90, dtype=np.float64),
        barnsley_j1(SHAPE, dtype=np.float64),
        barnsley_j1(SHAPE, (1.6, 1.1), variant="zz", uf_bailout=3.0, dtype=np.float64),
    ]
    for k, (g, w) in enumerate(zip(got, want)):
        assert np.array_equal(g, w), k
    assert (want[0] == -1).any() and (want[0] > 0).any()  # both inside and escaped points


ORBIT = """orbit_trap {
default:
  maxiter = 30
  point = (0.25, 0.0)
init:
  c = #pixel
  trap = 1e9
loop:
  z = z^2 + c
  trap = min(trap, cabs(z - @point))   ; distance of the orbit to the trap point
bailout:
  |z| < 4
final:
  #index = trap
inside:
  #index = -trap
}
"""


def test_orbit_trap_colouring_follows_the_orbit():
    g = tg.Graph(Node("formula", params={"source": ORBIT, "center": [-0.5, 0.0],
                                         "width": 3.0}))
    got = g.evaluate((7, 9), dtype=np.float64)
    h, w = 7, 9
    px = 3.0 / w
    want = np.empty((h, w))
    for j in range(h):
        for i in range(w):
            c = complex(-0.5 + (i - (w - 1) / 2) * px, ((h - 1) / 2 - j) * px)
            z, trap, n = 0j, 1e9, 0
            while abs(z) ** 2 < 4 and n < 30:
                z = z * z + c
                trap = min(trap, abs(z - 0.25))
                n += 1
            want[j, i] = trap if abs(z) ** 2 >= 4 else -trap
    assert np.allclose(got, want, rtol=1e-12, atol=1e-12)
    assert (want < 0).any() and (want > 0).any()


def _err(src, filename="f.toml"):
    text = f'[nodes.f]\ntype = "formula"\nsource = """\n{src}"""\n'
    with pytest.raises(GraphError) as e:
        tg.loads(text, filename=filename).evaluate((4, 4))
    return e.value


def test_syntax_error_at_file_line_and_column():
    e = _err("f {\ninit:\n  z = (1, \nbailout:\n  |z| < 4\n}\n")
    # the formula starts on line 4 of the file; "(1, " breaks on line 3 of the formula
    assert e.filename == "f.toml" and e.line == 6
    assert "expected" in e.message
    e = _err("f {\nloop:\n  z = z $ 2\nbailout:\n  |z| < 4\n}\n")
    assert (e.line, e.column) == (6, 9) and "'$'" in e.message
    assert e.source_line == "  z = z $ 2"


def test_semantic_errors_name_what_was_expected():
    e = _err("f {\nloop:\n  z = w + 1\nbailout:\n  |z| < 4\n}\n")
    assert "unknown variable 'w'" in e.message and (e.line, e.column) == (6, 7)
    e = _err("f {\ninit:\n  r = 1\n  r = #pixel\nbailout:\n  |z| < 4\n}\n")
    assert "is real" in e.message and e.line == 7
    e = _err("f {\nbailout:\n  z < 4\n}\n")
    assert "expected a real number" in e.message and e.line == 6
    e = _err("f {\nloop:\n  z = foo(z)\nbailout:\n  |z| < 4\n}\n")
    assert "unknown function 'foo'" in e.message and e.line == 6
    e = _err("f {\nloop:\n  z = z * @k\nbailout:\n  |z| < 4\n}\n")
    assert "unknown parameter @k" in e.message
    e = _err("f {\nloop:\n  z = z\n}\n")
    assert "bailout" in e.message
    with pytest.raises(GraphError, match="no parameter"):
        tg.Graph(Node("mandelbrot", params={"params": {"maxiterr": 3}})).evaluate((4, 4))


def test_single_line_formula_position():
    text = ('[nodes.f]\ntype = "formula"\n'
            'source = "f {\\ninit:\\n z = 1\\nbailout:\\n |z| < 4\\n}"\n')
    g = tg.loads(text)  # parses; a bad one points into the line of the file
    assert g.output.type == "formula"
    text = '[nodes.f]\ntype = "formula"\nsource = "f { ! }"\n'
    with pytest.raises(GraphError) as e:
        tg.loads(text, filename="g.toml").evaluate((4, 4))
    assert (e.value.line, e.value.column) == (3, 15)  # the "!" after "f {"


def test_a_formula_without_a_loop_is_a_custom_node_of_its_inputs():
    src = """shade {
final:
  #index = sin(#in1 * 3) + #in2 * real(#pixel)
}"""
    a = tg.improved(scale=4.0, seed=1)
    g = tg.Graph(tg.formula(a, 0.5, source=src, center=[0.0, 0.0], width=2.0))
    got = g.evaluate((6, 10), dtype=np.float64)
    A = tg.Graph(a).evaluate((6, 10), dtype=np.float64)
    re = (np.arange(10) - 4.5) * 0.2
    assert np.allclose(got, np.sin(A * 3) + 0.5 * re[None, :], atol=1e-12)
    e = _err("f {\nloop:\n  z = z\n}\n")
    assert "needs a bailout" in e.message and e.line == 5
