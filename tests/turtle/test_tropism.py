"""ABOP §2.3 tropism and cpfg's ``@`` modules, checked against a turtle written out here.

The reference turtle below is independent of sylva's kernel: the frame is a 3×3 matrix of
columns H, L, U, every command a right-handed rotation about one of the turtle's own axes
(ABOP §1.5: ``+`` about U, ``&`` about L, ``\\`` about H, by +δ; ``-``, ``^``, ``/`` by −δ),
and tropism ABOP's rule: after every step the frame turns about ``H × T`` by
``α = e·|H × T|`` (ABOP §2.3, p. 58).  Fig. 2.8a–d are derived with the book's parameters
(shipped as examples 31, 37, 38, 39) and every segment end and the extents are compared.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from sylva.data import find
from sylva.errors import SylvaError, SylvaWarning
from sylva.lsystem import derive, load, loads
from sylva.lsystem.dialects.lsysvis import AT_FUNCTIONS
from sylva.turtle import _kernels as K
from sylva.turtle import interpret, interpreter, trace
from sylva.turtle.tables import AT_FUNCTIONS as TURTLE_AT
from sylva.turtle.tables import AT_SUBFUNCTIONS

from .test_parallel import _both, _same

# ABOP Fig. 2.8 (p. 60): d1, d2, a, lr, T, e, n (vr = 1.732 in all four)
FIG_2_8 = {
    "31-abop-2.8-ternary-tree": (94.74, 132.63, 18.95, 1.109, (0, -1, 0), 0.22, 6),
    "37-abop-2.8b-ternary-tree": (137.5, 137.5, 18.95, 1.109, (0, -1, 0), 0.14, 8),
    "38-abop-2.8c-ternary-tree": (112.5, 157.5, 22.5, 1.790, (-0.02, -1, 0), 0.27, 8),
    "39-abop-2.8d-ternary-tree": (180.0, 252.0, 36.0, 1.070, (-0.61, 0.77, -0.19), 0.40, 6),
}


def _rot(axis, angle):
    """Rodrigues: the matrix of the right-handed rotation by ``angle`` about unit ``axis``."""
    x, y, z = axis
    k = np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])
    return np.eye(3) + math.sin(angle) * k + (1.0 - math.cos(angle)) * (k @ k)


def reference_turtle(modules, tropism=(0.0, -1.0, 0.0), elasticity=0.0):
    """Segment ends of a word of ``F + - & ^ \\ / [ ]`` (other modules do nothing)."""
    t = np.asarray(tropism, float)
    pos = np.zeros(3)
    frame = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])  # cols H, L, U
    axis_of = {"+": 2, "-": 2, "&": 1, "^": 1, "\\": 0, "/": 0}
    sign = {"+": 1, "-": -1, "&": 1, "^": -1, "\\": 1, "/": -1}
    stack, ends = [], []
    for name, args in modules:
        if name == "F":
            pos = pos + args[0] * frame[:, 0]
            ends.append(pos)
            hxt = np.cross(frame[:, 0], t)
            m = np.linalg.norm(hxt)
            if elasticity and m > 1e-12:
                frame = _rot(hxt / m, elasticity * m) @ frame
        elif name in axis_of:
            ax = frame[:, axis_of[name]]
            frame = _rot(ax, sign[name] * math.radians(args[0])) @ frame
        elif name == "[":
            stack.append((pos, frame))
        elif name == "]":
            pos, frame = stack.pop()
    return np.array(ends)


def _modules(word):
    return list(word)


@pytest.mark.parametrize("name", list(FIG_2_8))
def test_fig_2_8_example_has_the_published_parameters(name):
    d1, d2, a, lr, t, e, n = FIG_2_8[name]
    p = load(find(name).path)
    assert p.steps == n
    assert dict(p.constants) == pytest.approx({"d1": d1, "d2": d2, "a": a, "lr": lr, "vr": 1.732})
    assert p.settings["tropism"] == pytest.approx(t)
    assert p.settings["elasticity"] == pytest.approx(e)


@pytest.mark.parametrize("name", list(FIG_2_8))
def test_fig_2_8_tips_and_extents_match_the_reference_turtle(name):
    d1, d2, a, lr, t, e, n = FIG_2_8[name]
    p = load(find(name).path)
    word = derive(p)
    g = interpret(word, p)
    ref = reference_turtle(_modules(word), t, e)
    assert g.n_segments == ref.shape[0] == 1 + 2 * (3**n - 1)
    scale = np.abs(ref).max()
    assert np.abs(g.seg_end - ref).max() < 1e-9 * scale
    # the tips: segments no other segment grows from
    tips = np.setdiff1d(np.arange(g.n_segments), g.seg_parent)
    assert tips.size == 3**n
    lo, hi = ref.min(axis=0), ref.max(axis=0)
    assert np.allclose(
        g.bounds(), [np.minimum(lo, 0), np.maximum(hi, 0)], rtol=0, atol=1e-9 * scale
    )
    # and tropism matters: without it the tree stands otherwise
    stiff = reference_turtle(_modules(word))
    assert np.abs(stiff - ref).max() > 0.05 * scale


def test_fig_2_8a_droops():
    # T = (0, -1, 0): the branches bend down; the tips of the stiff tree stand higher
    p = load(find("31-abop-2.8-ternary-tree").path)
    word = derive(p)
    bent = interpret(word, p)
    stiff = interpret(word, p, elasticity=0.0)
    tips = np.setdiff1d(np.arange(bent.n_segments), bent.seg_parent)
    assert bent.seg_end[tips, 1].mean() < stiff.seg_end[tips, 1].mean() - 50


def test_the_bending_angle_is_e_times_the_sine():
    # H = +Y at 90° to T = +X: after F the heading has turned by exactly e toward T;
    # at 30° to T by e·sin 30°
    t = trace("FF", dialect="abop", elasticity=0.2, tropism=(1, 0, 0))
    h = t.frames[0, 0]
    assert math.degrees(math.atan2(h[0], h[1])) == pytest.approx(math.degrees(0.2), abs=1e-9)
    t = trace("-(60)F", dialect="abop", elasticity=0.2, tropism=(1, 0, 0))
    h0, h1 = t.frames[0, 0], t.frames[1, 0]
    turned = math.acos(np.clip(h0 @ h1, -1, 1))
    assert turned == pytest.approx(0.2 * math.sin(math.radians(30)), abs=1e-12)
    assert h1[0] > h0[0]  # toward T


def test_a_heading_along_t_does_not_bend():
    g = interpret("FFF", dialect="abop", elasticity=0.5)  # up, T = gravity: antiparallel
    assert np.allclose(g.seg_end[:, 0], 0) and np.allclose(g.seg_end[:, 1], [1, 2, 3])


def test_ts_sets_the_elasticity_of_one_branch():
    g = interpret("+(90)F[@Ts(0.3)FF]FF", dialect="lsys")
    # the main axis does not bend; the branch does, toward gravity
    assert np.allclose(g.seg_end[[0, 3, 4], 1], 0.0, atol=1e-12)
    # after the branch's first step H = -X turns about H x T = +Z by 0.3, toward -Y
    assert np.allclose(g.seg_end[2], [-2 - math.cos(0.3), -math.sin(0.3), 0], atol=1e-12)


def test_ti_td_step_the_elasticity():
    a = interpret("+(90)@Ti@TiFF", dialect="lsys", elasticity_step=0.1)
    b = interpret("+(90)@Ts(0.2)FF", dialect="lsys")
    c = interpret("+(90)@Ts(0.5)@Td(0.3)FF", dialect="lsys")
    assert np.allclose(a.seg_end, b.seg_end) and np.allclose(c.seg_end, b.seg_end)


CPFG = """Lsystem: 1
derivation length: 1
tropism direction: 0,-2,0
initial elasticity: 0.0
Axiom: +(90)F[{ts}FF]
endlsystem
"""


def test_cpfg_ts_takes_the_tropism_index_first(tmp_path):
    # the anchors disagree: cpfg writes @Ts(index, e) and @Ts(index) sets e to 0, L-Py and
    # sylva's .lsys write @Ts(e).  Each dialect reads its own spelling.  cpfg's index names
    # a tropism: line of the view file, whose bend comes before each step (movements.c):
    # ABOP's bend after a step of length 0 and each F
    lsys = interpret("+(90)F[@Ts(0.3)f(0)FF]", dialect="abop")
    (tmp_path / "t.v").write_text("tropism: T: 0 -2 0\n")
    cp = load(CPFG.format(ts="@Ts(1, 0.3)"), dialect="cpfg", view=tmp_path / "t.v")
    assert cp.settings["tropisms"][0][1] == (0.0, -1.0, 0.0)  # normalised, as cpfg does
    g = interpret(derive(cp, 0), cp)
    assert np.allclose(g.seg_end, lsys.seg_end, atol=1e-12)
    off = load(CPFG.format(ts="@Ts(1, 0.3)@Ts(1)"), dialect="cpfg", view=tmp_path / "t.v")
    g = interpret(derive(off, 0), off)
    assert np.allclose(g.seg_end[:, 1], 0.0, atol=1e-12)  # @Ts(1): tropism 1 off
    two = load(CPFG.format(ts="@Ts(2, 0.3)"), dialect="cpfg", view=tmp_path / "t.v")
    with pytest.warns(SylvaWarning, match="names tropism 2, but the view file defines 1"):
        g = interpret(derive(two, 0), two)
    assert np.allclose(g.seg_end[:, 1], 0.0, atol=1e-12)  # ignored, as cpfg does


def test_cpfg_view_settings():
    p = load(
        CPFG.replace(
            "initial elasticity: 0.0", "initial elasticity: 0.22\nelasticity increment: 0.05"
        ).format(ts="F"),
        dialect="cpfg",
    )
    assert p.settings["elasticity"] == 0.22 and p.settings["elasticity_step"] == 0.05


def test_lsys_tropism_settings_read_and_write():
    p = loads("tropism = 0, -1, 0\nelasticity = 0.22\naxiom = F")
    assert p.settings["tropism"] == (0.0, -1.0, 0.0) and p.settings["elasticity"] == 0.22
    from sylva.lsystem.dialects import dumps

    assert loads(dumps(p)) == p
    with pytest.raises(SylvaError, match="'tropism' is a vector") as info:
        loads("tropism = 0, -1\naxiom = F")
    assert info.value.line == 1


def test_at_v_rolls_to_vertical_like_dollar():
    word = "+(30)&(40)/(25)@vF"
    a = trace(word, dialect="abop")
    b = trace(word.replace("@v", "$"), dialect="abop")
    assert np.allclose(a.frames[-1], b.frames[-1])
    assert abs(a.frames[-1, 1, 1]) < 1e-12  # L horizontal


def test_at_m_moves_without_drawing():
    g = interpret("F@M(3, 4, 5)F@M(1, 2)F", dialect="abop")
    assert np.allclose(g.seg_start, [[0, 0, 0], [3, 4, 5], [1, 2, 0]])
    assert g.seg_parent.tolist() == [-1, -1, -1]


def test_at_r_sets_the_heading():
    t = trace("/(30)@R(0, 0, 2)F", dialect="abop")
    h, left, u = t.frames[-1]
    assert np.allclose(h, [0, 0, 1]) and np.allclose(t.positions[-1], [0, 0, 1])
    assert np.allclose(np.cross(h, left), u) and abs(h @ left) < 1e-12
    t = trace("@R(1, 0, 0, 0, 0, 1)F", dialect="abop")
    assert np.allclose(t.frames[-1], [[1, 0, 0], [0, 1, 0], [0, 0, 1]])


def test_at_o_draws_a_sphere_of_diameter_d():
    g = interpret("F@O(3)", dialect="abop")
    assert g.n_polygons == K.SPHERE_NP
    centre = np.array([0.0, 1.0, 0.0])
    assert np.allclose(np.linalg.norm(g.poly_vertices - centre, axis=1), 1.5)
    for i in range(g.n_polygons):  # counter-clockwise seen from outside
        v = g.polygon(i)
        n = np.cross(v[1] - v[0], v[2] - v[0])
        assert n @ (v.mean(axis=0) - centre) > 0


def test_unknown_at_module_is_an_error_with_line_and_column():
    with pytest.raises(SylvaError, match="unknown @ module '@X'") as info:
        loads("axiom = F\nF -> F@X(1)")
    assert (info.value.line, info.value.column) == (2, 7)
    with pytest.raises(SylvaError, match="'@Tq'"):
        loads("axiom = F@Tq")
    with pytest.raises(SylvaError, match=r"module 1 of the word: '@' followed by 'X'"):
        interpret("F@XF", dialect="abop")
    # other turtles have no @ functions: @ is a plain module there
    assert loads("turtle = classic\naxiom = F@X").axiom[1].symbol == "@"


def test_the_at_tables_agree():
    assert set(AT_FUNCTIONS) == set(TURTLE_AT)
    assert AT_FUNCTIONS["T"] == set(AT_SUBFUNCTIONS)


def test_tropism_walks_in_parallel_as_serially(monkeypatch):
    p = load(find("31-abop-2.8-ternary-tree").path)
    word = derive(p, 4)
    par, ser, walked = _both(monkeypatch, interpret, word, p)
    assert walked > 0
    _same(par, ser)
    assert interpreter.GRAVITY == (0.0, -1.0, 0.0)


def test_at_modules_round_trip_through_lsys_text():
    from sylva.lsystem.dialects import dumps

    p = loads("axiom = A\nA -> F@Ts(0.2)[@O(1)@M(1, 2, 3)@R(0, 1, 0)@v@Ti@Td(0.1)]A")
    assert loads(dumps(p)) == p
