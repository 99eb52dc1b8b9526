"""The texture graph: every node against its definition, one-node graphs equal to
``noise_grid`` bit for bit, seamless tiling, TOML/JSON round trips of every preset, and the
errors a bad graph file gets.

Many nodes go through one kernel (``outputs=``), so the suite compiles few kernels."""

import math

import numpy as np
import pytest

from sylva import _jit
from sylva.texture import Colormap, fbm, get_colormap, noise_grid, presets
from sylva.texture import graph as tg
from sylva.texture.graph import GraphError, Node
from sylva.texture.graph._compile import evaluate as _evaluate
from sylva.texture.graph.library import marble_graph

SHAPE = (12, 20)
H, W = SHAPE
X = np.arange(W)[None, :] / W + np.zeros(SHAPE)
Y = np.arange(H)[:, None] / W + np.zeros(SHAPE)


def many(nodes, shape=SHAPE, **props):
    g = tg.Graph(nodes[0], **props)
    return _evaluate(g, shape, np.float64, outputs=nodes)


# ----------------------------------------------------------------------------- single nodes
def test_one_node_graphs_equal_noise_grid_bit_for_bit():
    kinds = [
        ("value", dict(octaves=3, interpolation="cosine")),
        ("perlin", dict(octaves=2)),
        ("improved", dict(octaves=4, fractal="turbulence")),
        ("simplex", dict(octaves=2, fractal="ridged")),
        ("worley", dict(output="f2-f1", metric="manhattan")),
    ]
    nodes = [Node(k, params=dict(scale=5.3, seed=7, **kw)) for k, kw in kinds]
    nodes.append(Node("fbm", params=dict(scale=3.0, octaves=5, seed=6, warp=1.5)))
    got = many(nodes)
    for (kind, kw), g in zip(kinds, got):
        want = noise_grid(SHAPE, kind=kind, scale=5.3, seed=7, dtype=np.float64, **kw)
        assert np.array_equal(g, want), kind
    warped = noise_grid(SHAPE, kind="improved", scale=3.0, octaves=5, seed=6, warp=1.5,
                        dtype=np.float64)
    assert np.array_equal(got[-1], warped)
    # float32 output: the generators take noise_grid's float32 road (float32 SIMD row
    # routines), within its documented tolerance of the float64 road
    from sylva.texture._gridkernels32 import TOLERANCE

    for (kind, kw), node in zip(kinds, nodes):
        g32 = tg.Graph(node).evaluate(SHAPE)
        assert g32.dtype == np.float32
        want = noise_grid(SHAPE, kind=kind, scale=5.3, seed=7, dtype=np.float64, **kw)
        assert np.abs(g32 - want).max() <= TOLERANCE, kind
        # the graph's row routines are noise_grid's compiled float32 kernels (on a cold
        # numba cache small grids take the interpreted float64 road and round instead)
        with _jit.compiled():
            same = noise_grid(SHAPE, kind=kind, scale=5.3, seed=7, **kw)
        assert np.abs(g32 - same).max() < 1e-6, kind
        assert not np.array_equal(g32, want.astype(np.float32)), kind  # float32 arithmetic


def test_tileable_and_animated_graphs_equal_noise_grid():
    nodes = [Node("improved", params=dict(scale=4.6, octaves=3, seed=2)),
             Node("worley", params=dict(scale=5.0, seed=3, output="f1"))]
    got = many(nodes, tileable=True, time=0.7)
    for n, g in zip(nodes, got):
        kw = {k: v for k, v in n.params.items()}
        want = noise_grid(SHAPE, kind=n.type, tileable=True, time=0.7, dtype=np.float64, **kw)
        assert np.array_equal(g, want), n.type
    vol = tg.Graph(nodes[0]).evaluate((3, 6, 10), dtype=np.float64)
    assert np.array_equal(vol, noise_grid((3, 6, 10), kind="improved", scale=4.6, octaves=3,
                                          seed=2, dtype=np.float64))


def test_modifiers_combiners_selector_transformers_against_their_formulas():
    a = tg.improved(scale=3.0, seed=1)
    b = tg.value(scale=2.0, seed=2)
    x = tg.x()
    curve_pts = [[-1.0, -0.5], [-0.2, 0.1], [0.3, -0.1], [0.8, 0.9], [1.2, 1.0]]
    nodes = [
        a, b, x, abs(a), tg.clamp(a, lower=-0.2, upper=0.3), -a,
        tg.scale_bias(a, scale=2.5, bias=-0.5), tg.exponent(a, exponent=2.0), tg.sin(b * 3.0),
        tg.cos(b), tg.fract(b * 4.0), tg.smoothstep(a + 0.5), a + b, a - b, a * b, a / (b + 3.0),
        tg.min_(a, b), tg.max_(a, b), abs(a) ** (b + 1.5), tg.blend(a, b, x),
        tg.select(a, b, x, lower=0.2, upper=0.6, falloff=0.1),
        tg.curve(a, points=curve_pts), tg.terrace(a, points=[-1.0, -0.2, 0.4, 1.0]),
        tg.terrace(a, points=[-1.0, 0.0, 1.0], invert=True),
        tg.translate(a, by=[0.25, -0.125]), tg.rotate(a, angle=30.0, center=[0.5, 0.25]),
        tg.scale(a, by=[2.0, 0.5]), tg.warp(a, dx=b, dy=x, amount=0.3), tg.constant(value=0.7),
        tg.y(), tg.x(closed=True), (abs(a) + 1.0) / 0.0,
    ]
    got = dict(zip(range(len(nodes)), many(nodes)))
    A, B, C = got[0], got[1], got[2]
    assert np.allclose(C, X, rtol=0, atol=0)
    # the generators at moved coordinates (image units; improved scale 3 = 3 cells per unit)

    def imp(px, py):
        return fbm(px * 3.0, py * 3.0, kind="improved", octaves=1, seed=1, dtype=np.float64)

    assert np.allclose(A, imp(X, Y), atol=1e-12)
    ref = {
        3: abs(A), 4: np.clip(A, -0.2, 0.3), 5: -A, 6: A * 2.5 - 0.5,
        7: np.abs((A + 1) / 2) ** 2.0 * 2 - 1, 8: np.sin(B * 3.0), 9: np.cos(B),
        10: B * 4.0 - np.floor(B * 4.0), 12: A + B, 13: A - B, 14: A * B, 15: A / (B + 3.0),
        16: np.minimum(A, B), 17: np.maximum(A, B), 18: np.abs(A) ** (B + 1.5),
        19: A + C * (B - A), 28: np.full(SHAPE, 0.7), 29: Y,
        30: np.linspace(0, 1, W)[None, :] + np.zeros(SHAPE),
        31: np.full(SHAPE, np.inf),  # division by zero: inf as in NumPy, not an exception
    }
    s = np.clip(A + 0.5, 0, 1)
    ref[11] = s * s * (3 - 2 * s)
    for k, v in ref.items():
        assert np.allclose(got[k], v, rtol=0, atol=1e-12), k
    # select: b inside [0.2, 0.6], a outside, s-curve blends of half-width 0.1 at both edges
    sel = np.where((C >= 0.3) & (C < 0.5), B, A)
    inner = (C < 0.1) | ((C >= 0.3) & (C < 0.5)) | (C >= 0.7)
    assert np.allclose(got[20][inner], sel[inner], atol=1e-12)
    lo = (C >= 0.1) & (C < 0.3)
    t = (C[lo] - 0.1) / 0.2
    t = t * t * (3 - 2 * t)
    assert np.allclose(got[20][lo], A[lo] + t * (B[lo] - A[lo]), atol=1e-12)
    # libnoise Curve: cubic through the four nearest control points
    pts = np.array(curve_pts)

    def curve(v):
        pos = int(np.searchsorted(pts[:, 0], v, side="right"))
        i = [min(max(pos + d, 0), len(pts) - 1) for d in (-2, -1, 0, 1)]
        if i[1] == i[2]:
            return pts[i[1], 1]
        a_ = (v - pts[i[1], 0]) / (pts[i[2], 0] - pts[i[1], 0])
        n0, n1, n2, n3 = pts[i, 1]
        p = (n3 - n2) - (n0 - n1)
        q = (n0 - n1) - p
        return p * a_**3 + q * a_**2 + (n2 - n0) * a_ + n1

    assert np.allclose(got[21], np.vectorize(curve)(A), atol=1e-12)

    def terrace(v, tp, inv):
        pos = int(np.searchsorted(tp, v, side="right"))
        i0, i1 = min(max(pos - 1, 0), len(tp) - 1), min(max(pos, 0), len(tp) - 1)
        if i0 == i1:
            return tp[i1]
        a0, a1 = tp[i0], tp[i1]
        s_ = (v - a0) / (a1 - a0)
        if inv:
            s_, a0, a1 = 1 - s_, a1, a0
        return a0 * (1 - s_ * s_) + a1 * s_ * s_

    assert np.allclose(got[22], [[terrace(v, [-1, -0.2, 0.4, 1], False) for v in r] for r in A])
    assert np.allclose(got[23], [[terrace(v, [-1, 0, 1], True) for v in r] for r in A])
    # transformers: the source at p - by, R(-30 deg)(p - c) + c, p / by, p + 0.3 (b, x)
    assert np.allclose(got[24], imp(X - 0.25, Y + 0.125), atol=1e-12)
    ang = math.radians(30.0)
    rx = math.cos(ang) * (X - 0.5) + math.sin(ang) * (Y - 0.25) + 0.5
    ry = -math.sin(ang) * (X - 0.5) + math.cos(ang) * (Y - 0.25) + 0.25
    assert np.allclose(got[25], imp(rx, ry), atol=1e-12)
    assert np.allclose(got[26], imp(X / 2.0, Y / 0.5), atol=1e-12)
    assert np.allclose(got[27], imp(X + 0.3 * B, Y + 0.3 * C), atol=1e-12)


def test_colour_nodes_against_colormap_and_blend_formulas():
    v = tg.x()
    base = tg.gradient(v, colors="terrain", vmin=0.0, vmax=1.0)
    top = tg.gradient(tg.y(), colors=["#ff0000", "#0000ff"], vmin=0.0, vmax=0.6)
    modes = list(tg.BLEND_MODES)
    nodes = [base, top, tg.rgb(v, tg.y(), 0.25), tg.color(value="#336699", alpha=0.5)]
    nodes += [tg.layer(base, top, mode=m, opacity=0.75) for m in modes]
    got = many(nodes)
    a = get_colormap("terrain")(X)
    b = Colormap(np.array([0.0, 1.0]), np.array([[1.0, 0, 0], [0, 0, 1.0]]))(Y / 0.6)
    assert np.allclose(got[0][..., :3], a, atol=1e-12) and (got[0][..., 3] == 1).all()
    assert np.allclose(got[1][..., :3], b, atol=1e-12)
    assert np.allclose(got[2], np.stack([X, Y, np.full(SHAPE, 0.25), np.ones(SHAPE)], -1))
    assert np.allclose(got[3], np.broadcast_to([0.2, 0.4, 0.6, 0.5], SHAPE + (4,)))
    f = {
        "normal": b, "multiply": a * b, "screen": 1 - (1 - a) * (1 - b),
        "overlay": np.where(a < 0.5, 2 * a * b, 1 - 2 * (1 - a) * (1 - b)),
        "difference": np.abs(a - b), "add": np.minimum(a + b, 1), "subtract":
            np.maximum(a - b, 0), "darken": np.minimum(a, b), "lighten": np.maximum(a, b),
        "hard-light": np.where(b < 0.5, 2 * a * b, 1 - 2 * (1 - a) * (1 - b)),
        "soft-light": (1 - 2 * b) * a * a + 2 * b * a,
    }
    for m, g in zip(modes, got[4:]):
        assert np.allclose(g[..., :3], a + 0.75 * (f[m] - a), atol=1e-12), m
        assert np.allclose(g[..., 3], 1.0)
    lum = tg.Graph(tg.luminance(base)).evaluate(SHAPE, dtype=np.float64)
    assert np.allclose(lum, a @ [0.2126, 0.7152, 0.0722], atol=1e-12)


def test_python_expression_tree():
    a = tg.improved(scale=2.0)
    e = (a + 1) * 0.5 - abs(a) / 2 ** a
    assert e.type == "sub" and e.inputs["a"].type == "multiply"
    assert e.inputs["b"].inputs["b"].type == "power"
    assert tg.node.scale_bias(a, bias=1.0).type == "scale-bias"
    assert isinstance(tg.node.burning_ship(), Node)


# ----------------------------------------------------------------------------- tiling
def _seam(img):
    """Mean jump across the wrap seams over the mean jump between neighbours (1: seamless)."""
    inner = (np.abs(np.diff(img, axis=1)).mean() + np.abs(np.diff(img, axis=0)).mean()) / 2
    seam = (np.abs(img[:, 0] - img[:, -1]).mean() + np.abs(img[0] - img[-1]).mean()) / 2
    return seam / inner


def test_tiled_graphs_have_matching_opposite_edges():
    a = tg.improved(scale=4.0, octaves=4, seed=1)
    b = tg.worley(scale=6.0, seed=2, output="f1")
    w = tg.fbm(kind="value", scale=3.0, octaves=3, seed=3)
    nodes = [a, b, w, tg.blend(a, b, w * 0.5 + 0.5), tg.warp(a, dx=w, dy=b, amount=0.2),
             tg.translate(a + b, by=[0.31, 0.17])]
    tiled = many(nodes, (48, 64), tileable=True)
    plain = many(nodes, (48, 64))
    for k, (t, p) in enumerate(zip(tiled, plain)):
        assert _seam(t) < 1.6, k
        assert _seam(p) > 2.0 * _seam(t), k  # the statistic does see an untiled seam
    m = marble_graph(seed=4, tileable=True).evaluate((48, 64), dtype=np.float64)
    assert _seam(m) < 1.6


def test_marble_graph_equals_the_pattern():
    from sylva.texture import marble

    for tile in (False, True):
        g = marble_graph(scale=3.0, stripes=3.0, turbulence=2.5, seed=11, tileable=tile)
        want = marble((20, 28), scale=3.0, stripes=3.0, turbulence=2.5, seed=11,
                      tileable=tile, dtype=np.float64)
        assert np.allclose(g.evaluate((20, 28), dtype=np.float64), want, rtol=0, atol=1e-14)


# ----------------------------------------------------------------------------- files
@pytest.mark.parametrize("name", sorted(presets.PRESETS))
def test_every_preset_round_trips_through_toml_and_renders_as_before(name):
    recipe = dict(presets.PRESETS[name], size=[24, 16])
    if recipe.get("points"):
        recipe["points"] = 20000
    g = tg.from_recipe(recipe)
    text = g.dumps()
    back = tg.loads(text)
    assert back.dumps() == text
    assert tg.loads(g.dumps("json"), fmt="json").dumps() == text
    assert np.array_equal(back.image(), presets.render(recipe)), name


def test_graph_file_save_and_load(tmp_path):
    g = marble_graph(seed=3)
    p = g.save(tmp_path / "marble.toml")
    again = tg.load(p)
    assert again.dumps() == g.dumps()
    j = tg.load(g.save(tmp_path / "marble.json"))
    assert np.array_equal(j.evaluate((8, 8)), g.evaluate((8, 8)))


# ----------------------------------------------------------------------------- bad input
def _bad(text, fmt="toml"):
    with pytest.raises(GraphError) as e:
        tg.loads(text, fmt=fmt, filename="bad.toml").evaluate((4, 4))
    return e.value


def test_cycle_is_an_error_at_the_input_that_closes_it():
    e = _bad('[graph]\noutput = "a"\n\n[nodes.a]\ntype = "abs"\nsource = "b"\n\n'
             '[nodes.b]\ntype = "invert"\nsource = "a"\n')
    assert "cycle" in e.message and (e.filename, e.line, e.column) == ("bad.toml", 10, 10)


def test_unknown_node_type_and_unknown_reference():
    e = _bad('[nodes.a]\ntype = "perlinn"\n')
    assert "unknown node type 'perlinn'" in e.message and "improved" in e.message
    assert (e.line, e.column) == (2, 8)
    e = _bad('[nodes.a]\ntype = "abs"\nsource = "nowhere"\n')
    assert "unknown node 'nowhere'" in e.message and (e.line, e.column) == (3, 10)


def test_missing_input_names_the_node_and_what_is_expected():
    e = _bad('[graph]\noutput = "s"\n\n[nodes.s]\ntype = "add"\na = 1.0\n')
    assert "needs its input 'b'" in e.message and "a node or a number" in e.message
    assert (e.line, e.column) == (4, 1)


def test_colour_into_scalar_input():
    e = _bad('[graph]\noutput = "c"\n[nodes.g]\ntype = "gradient"\nsource = 0.5\n'
             '[nodes.c]\ntype = "clamp"\nsource = "g"\n')
    assert "takes a scalar" in e.message and "gives a colour" in e.message
    assert (e.line, e.column) == (8, 10)


def test_bad_toml_json_parameter_and_property():
    e = _bad('[nodes.a]\ntype = "abs"\nsource = \n')
    assert "not valid TOML" in e.message and e.line == 3
    e = _bad('{"nodes": {"a": {"type": "abs", "source": }}}', fmt="json")
    assert "not valid JSON" in e.message and (e.line, e.column) == (1, 43)
    e = _bad('{"nodes": {\n  "a": {"type": "abss"}}}', fmt="json")
    assert "unknown node type 'abss'" in e.message and e.line == 2
    e = _bad('[nodes.a]\ntype = "improved"\nscael = 3\n')
    assert "no parameter 'scael'" in e.message and (e.line, e.column) == (3, 9)
    e = _bad('[graph]\ntileable = "yes"\n[nodes.a]\ntype = "improved"\n')
    assert "tileable" in e.message and (e.line, e.column) == (2, 12)
    e = _bad('[nodes.a]\ntype = "improved"\noctaves = 0\n')
    assert "octaves" in e.message and e.line == 2
    e = _bad('[nodes.a]\ntype = "layer"\nbase = 1.0\ntop = 2.0\n')
    assert "must be a node name" in e.message and e.line == 3


def test_threaded_run_equals_the_serial_one():
    import numba

    g = tg.Graph(tg.improved(scale=9.0, octaves=2, seed=5))
    shape = (260, 300)  # enough work for the threaded path
    want = noise_grid(shape, kind="improved", scale=9.0, octaves=2, seed=5,
                      dtype=np.float64)
    got = g.evaluate(shape)
    assert np.abs(got - want).max() < 2e-4  # the float32 road's tolerance
    want = got
    before = numba.get_num_threads()
    numba.set_num_threads(1)
    try:
        assert np.array_equal(g.evaluate(shape), want)
    finally:
        numba.set_num_threads(before)


def test_every_node_type_is_in_the_reference():
    from pathlib import Path

    page = (Path(__file__).parents[2] / "docs" / "reference" / "texture-graph.rst").read_text()
    for name in tg.NODE_TYPES:
        assert f"``{name}``" in page, name
    for mode in tg.BLEND_MODES:
        assert mode in page


def test_parameter_types_are_checked_where_they_are_written():
    e = _bad('[nodes.a]\ntype = "marble"\nstripes = "x"\n')
    assert "'stripes' of a marble node must be a number" in e.message
    assert (e.line, e.column) == (3, 11)
    e = _bad('[nodes.a]\ntype = "terrace"\nsource = 0.0\ninvert = 1\n')
    assert "true or false" in e.message and e.line == 4
    e = _bad('[nodes.a]\ntype = "translate"\nsource = "b"\n[nodes.b]\ntype = "wood"\n')
    assert "cannot sit under a transformer" in e.message and e.line == 5
