"""cpfg constructs of vlab's models, each on a small model of our own: ring L-systems,
right contexts with open brackets and ``=``, late ``#define``, condition heads over two
lines, and environment files served by sylva's built-in environments."""

from __future__ import annotations

import numpy as np
import pytest

import sylva
from sylva.environments import Density, Light
from sylva.errors import SylvaWarning
from sylva.lsystem import Derivation
from sylva.lsystem.dialects import cpfg
from sylva.lsystem.dialects._cpfg_env import EnvironmentProgramError, environment_spec
from sylva.plant import environment_for


def _derive(text: str, steps: int | None = None) -> str:
    p = cpfg.parse(text, view=False)
    return str(sylva.derive(p, p.steps if steps is None else steps))


@pytest.mark.parametrize(
    ("ring", "rule", "axiom", "want"),
    [
        ("ring lsystem\n", "B > A --> A", "ABBB", "ABBA"),  # the last B sees the first A
        ("", "B > A --> A", "ABBB", "ABBB"),
        ("ring lsystem\n", "A < B --> C", "BBBA", "CBBA"),  # the first B sees the last A
        ("", "A < B --> C", "BBBA", "BBBA"),
    ],
)
def test_a_ring_lsystem_wraps_its_contexts(ring, rule, axiom, want):
    text = f"Lsystem: 0\n{ring}derivation length: 1\nAxiom: {axiom}\n{rule}\nendlsystem\n"
    assert _derive(text) == want


def test_a_ring_signal_goes_round():
    # a signal that moves right, around the ring: after 4 steps it is back where it began
    text = ("Lsystem: 0\nring lsystem\nderivation length: 4\nAxiom: SBBB\n"
            "S < B --> S\nS --> B\nendlsystem\n")  # fmt: skip
    words = [_derive(text, k) for k in range(5)]
    assert words == ["SBBB", "BSBB", "BBSB", "BBBS", "SBBB"]


def test_right_contexts_with_open_brackets():
    # [E: a branch that begins with E follows; ]D: the branch ends, D follows it
    text = ("Lsystem: 0\nderivation length: 1\nAxiom: A[BC]DX[E]F\nX > [E --> Y\n"
            "A > [B --> Z\nC > ]D --> W\nB > C]DX[E --> V\nD > X]F --> Q\nendlsystem\n")
    assert _derive(text) == "Z[VW]DY[E]F"  # D > X]F: X is followed by [, not ]


def test_equals_skips_the_rest_of_a_branch():
    # cpfg's = in a right context: the rest of the branch, up to its ]
    text = ("Lsystem: 0\nderivation length: 1\nAxiom: N[IXX][IY]A F[GH]K\n"
            "N > [I=][I=]A --> M\nF > [G=]K --> P\nF > [H=]K --> R\nendlsystem\n")
    assert _derive(text) == "M[IXX][IY]AP[GH]K"


def test_a_define_after_the_rules_is_a_constant():
    text = ("Lsystem: 0\nderivation length: 1\nAxiom: A(1)\nA(x) --> A(x+K)\n"
            "#define K 0.25\nendlsystem\n")
    assert _derive(text) == "A(1.25)"


def test_a_condition_head_over_two_lines_is_not_a_successor():
    text = ("Lsystem: 0\nderivation length: 1\nAxiom: M(1)M(-1)\n"
            "M(x) : (x<=5)&&(x>0)\n\t--> M(x+2)\nM(x) : (x<=5)&&(x<0)\n\t--> M(x-2)\n"
            "endlsystem\n")
    assert _derive(text) == "M(3)M(-3)"


# ------------------------------------------------------------------ environment programs
def test_density_crowds_out_the_weaker_of_two_close_buds():
    env = Density(radius=1.0)
    p = np.array([[0, 0, 0], [0.5, 0, 0], [3, 0, 0], [3.2, 0, 0]], float)
    # equal vigour: both crowded (honda81's <=); another group does not count
    assert env.free(p, np.array([1, 2, 1, 1.0])).tolist() == [0, 1, 0, 0]
    assert env.free(p, np.ones(4), np.array([0, 1, 0, 1.0])).tolist() == [1, 1, 1, 1]
    # planar: the distance in x-z, so buds above each other collide
    q = np.array([[0, 0, 0], [0, 5, 0]], float)
    assert Density(radius=1, planar=1).free(q, np.array([1, 2.0])).tolist() == [0, 1]
    assert Density(radius=1).free(q, np.array([1, 2.0])).tolist() == [1, 1]


def _files(tmp_path, executable, spec):
    (tmp_path / "the.spec").write_text(spec)
    e = tmp_path / "plant.e"
    e.write_text(f"executable: {executable} -e plant.e the.spec\ncommunication type: files\n"
                 "turtle position:P:%.4f %.4f %.4f\n")  # fmt: skip
    return e


def test_a_honda81_model_grows_until_its_tips_collide(tmp_path):
    e = _files(tmp_path, "honda81", "verbose: off\nradius: 0.9\n3d case: on\n")
    assert environment_spec(e) == "density(radius = 0.9, planar = 0)"
    # two tips grow towards each other along x; they stop when they are within 0.9
    text = ("Lsystem: 0\nderivation length: 6\n"
            "Axiom: [+(90)f(2)-(90)-(90)A(1)?E(1)][-(90)f(2)+(90)+(90)A(2)?E(2)]\n"
            "A(v) > ?E(x) : x > 0 --> f(0.5)A(v)\nA(v) < ?E(x) --> ?E(v)\n"
            "endlsystem\n")  # fmt: skip
    p = cpfg.parse(text, view=False, environment=e)
    env, locate = environment_for(p)
    assert isinstance(env, Density)
    d = Derivation(p, environment=env, locate=locate)
    weak, strong = str(d.advance(6)).split("][")
    # they meet after 4 steps: the weaker tip (vigour 1) stops there, the stronger grows on
    assert weak.count("f(0.5)") == 4
    assert strong.count("f(0.5)") == 6


def test_a_chiba_model_gets_the_light_of_its_position(tmp_path):
    e = _files(tmp_path, "chiba", "grid size: 32x32x32\ntransmittance: 0.25\n")
    assert environment_spec(e) == "light(shadow = 0.75)"
    # three leaf balls one above the other: the top one gets the most light
    text = ("Lsystem: 1\nderivation length: 1\nAxiom: ?E(1)f(1)?E(1)f(1)?E(1)\n"
            "?E(r) --> ?E(r)\nendlsystem\n")  # fmt: skip
    p = cpfg.parse(text, view=False, environment=e)
    env, locate = environment_for(p)
    assert isinstance(env, Light)
    d = Derivation(p, environment=env, locate=locate)
    w = d.advance(1)
    light = [float(w.values[w.offsets[i]]) for i in range(len(w)) if w.symbols()[i] == "?E"]
    assert light[0] < light[1] < light[2] == 1.0


def test_an_environment_program_sylva_lacks_is_named(tmp_path):
    e = _files(tmp_path, "clover", "verbose: off\n")
    with pytest.raises(EnvironmentProgramError, match="needs environment program clover") as ex:
        cpfg.parse("Lsystem: 0\nAxiom: A\nendlsystem\n", view=False, environment=e)
    assert ex.value.program == "clover"


def test_file_output_calls_run_as_nothing(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    text = ('Lsystem: 1\nStart: {n = 0; fp = fopen("out.txt", "w");}\n'
            'EndEach: {n = n + 1; fprintf(fp, "n = %.0f\\n", n); fflush(fp);}\n'
            "End: {fclose(fp);}\nderivation length: 2\nAxiom: A\nA --> AB\nendlsystem\n")
    assert _derive(text) == "ABB"
    assert list(tmp_path.iterdir()) == []  # sylva writes no file


def test_width_modules_step_by_the_line_width_increment(tmp_path):
    from sylva.turtle import interpret

    view = tmp_path / "w.v"
    view.write_text("line style: cylinder\ninitial line width: 1\nline width increment: 0.25\n")
    text = "Lsystem: 0\nAxiom: F!F#F#F#(0.1)F!(2)F!F\nendlsystem\n"
    p = cpfg.parse(text, view=view)
    widths = 2 * interpret(sylva.derive(p, 0), p).seg_radius[:, 0]
    # cpfg: ! subtracts the increment, # adds it, a parameter sets the width
    assert np.allclose(widths, [1, 0.75, 1, 1.25, 0.1, 2, 1.75])
    # without an increment (cpfg's default 0) a plain ! or # keeps the width
    q = cpfg.parse(text, view=False)
    w0 = 2 * interpret(sylva.derive(q, 0), q).seg_radius[:, 0]
    assert np.allclose(w0[:4], w0[0]) and np.isclose(w0[4], 0.1)


def test_a_concave_polygon_covers_its_own_area_only():
    from sylva.geometry.build import build_polygons, triangulate_polygons
    from sylva.turtle import interpret

    def area(v, t):
        e = np.cross(v[t[:, 1]] - v[t[:, 0]], v[t[:, 2]] - v[t[:, 0]])
        return 0.5 * np.linalg.norm(e, axis=1).sum()

    # a square with a notch, from the vertex beside the notch: a fan from there covers
    # the notch and more (5); the outline's area is 3
    v = np.array([[-2, 2, 0], [-1, 1, 0], [-2, 0, 0], [0, 0, 0], [0, 2, 0]], float)
    tris, owner, normals = triangulate_polygons(v, np.array([0, 5]))
    assert area(v, tris) == pytest.approx(3.0)
    assert owner.tolist() == [0] * len(tris) and normals[0].tolist() == [0.0, 0.0, 1.0]
    # the same outline drawn by cpfg's turtle, { . }
    text = ("Lsystem: 0\nAxiom: f(2)-(90)f(2)-(90){.-(45)f(1.4142135623730951).+(90)"
            "f(1.4142135623730951).-(135)f(2).-(90)f(2).-(90)f(2).}\nendlsystem\n")
    p = cpfg.parse(text, view=False)
    mesh = build_polygons(interpret(sylva.derive(p, 0), p))
    assert area(mesh.vertices.astype(float), mesh.indices.reshape(-1, 3)) == pytest.approx(3.0)


def test_the_view_files_camera_places_the_render(tmp_path):
    from argparse import Namespace

    from sylva.cli._common import view_camera

    (tmp_path / "plant.l").write_text("Lsystem: 0\nAxiom: F(4)[+(90)F(1)]\nendlsystem\n")
    (tmp_path / "plant.v").write_text("viewpoint: 10, 0, 0\nview reference point: 0,0,0\n"
                                      "twist: 900\nprojection: perspective\n"
                                      "scale factor: 0.5\n")  # fmt: skip
    plant = sylva.grow(str(tmp_path / "plant.l"))
    args = Namespace(camera="auto", yaw=None, pitch=None, view=None)
    cam = view_camera(args, plant, 1.0)
    right, up, back = cam.basis()
    assert cam.mode == "perspective"
    assert np.allclose(back, [1, 0, 0])  # from the viewpoint on +x towards the origin
    assert np.allclose(up, [0, 0, -1], atol=1e-9)  # world +y turned as cpfg turns it
    wide = view_camera(args, plant, 1.0)
    (tmp_path / "plant.v").write_text("viewpoint: 10, 0, 0\nprojection: perspective\n")
    full = view_camera(args, sylva.grow(str(tmp_path / "plant.l")), 1.0)
    assert wide.distance > 1.5 * full.distance  # scale factor 0.5: the plant half as big
    assert view_camera(Namespace(camera="auto", yaw=30.0, pitch=None, view=None), plant,
                       1.0) is None  # the command line's view wins


def test_pixel_lines_keep_their_width_in_pixels(tmp_path):
    from argparse import Namespace

    from sylva.cli._common import view_line_pixels

    (tmp_path / "plant.l").write_text("Lsystem: 0\nAxiom: F(4)[+(90)F(1)]\nendlsystem\n")
    args = Namespace(view=None, line_width=2.0)
    (tmp_path / "plant.v").write_text("initial line width: 5 pixels\n")  # cpfg's pixel style
    with pytest.warns(SylvaWarning):
        plant = sylva.grow(str(tmp_path / "plant.l"))
    assert view_line_pixels(args, plant) == 5.0
    (tmp_path / "plant.v").write_text("line style: cylinder\ninitial line width: 0.3\n")
    assert view_line_pixels(args, sylva.grow(str(tmp_path / "plant.l"))) is None  # units


def test_command_line_colour_map_colours_the_lines_and_clears_the_window(tmp_path):
    # cpfg -m plant.map plant.l: the map named on the command line gives index n its
    # colour and entry 0 is the window's background (vlab's 01-Introduction leaves: black
    # background, yellow lines of index 1)
    from sylva.geometry.colormaps import read_colormap, write_colormap
    from sylva.turtle import interpret

    write_colormap([(0.0, 0.0, 0.0), (1.0, 1.0, 0.0), (0.0, 0.5, 0.0)], tmp_path / "p.map")
    (tmp_path / "p.v").write_text("initial color: 1\ncolor map: other.map\n")
    write_colormap([(1.0, 1.0, 1.0), (0.0, 0.0, 1.0)], tmp_path / "other.map")
    text = "Lsystem: 0\nAxiom: F;F\nendlsystem\n"
    p = cpfg.parse(text, str(tmp_path / "p.l"), view=tmp_path / "p.v",
                   colormap=tmp_path / "p.map")  # fmt: skip
    assert p.settings["colormap"] == str(tmp_path / "p.map")  # -m wins over the view's
    g = interpret(Derivation(p).word, p)
    want = read_colormap(tmp_path / "p.map")
    assert np.allclose(g.seg_color, want[[1, 2]], atol=1e-6)  # ; steps to index 2
    assert np.allclose(g.background, want[0])
    plain = cpfg.parse(text, str(tmp_path / "p.l"), view=tmp_path / "p.v")
    assert plain.settings["colormap"] == str(tmp_path / "other.map")  # the view's map


def test_polygons_gather_vertices_as_cpfg_does():
    # cpfg's interpret.c: { adds no vertex, '.' and each F (and f) add one, and F still
    # draws its line (vlab's ConcavePolygons: {.,L--S--...} with S --> F@c, one filled
    # gasket outlined by its edges; sylva's own rule kept only the '.' vertex: nothing)
    from sylva.turtle import interpret

    p = cpfg.parse("Lsystem: 0\nAxiom: {.F(1)+(90)F(1)+(90)F(1)}\nendlsystem\n", view=False)
    g = interpret(Derivation(p).word, p)
    assert g.n_polygons == 1 and g.n_segments == 3
    v = np.asarray(g.poly_vertices)
    assert np.allclose(v[:, :2], [[0, 0], [0, 1], [-1, 1], [-1, 0]], atol=1e-9)
    p = cpfg.parse("Lsystem: 0\nAxiom: f(5){F(1)+(90)f(1)+(90)F(1)}\nendlsystem\n", view=False)
    g = interpret(Derivation(p).word, p)
    v = np.asarray(g.poly_vertices)  # no vertex where { stands (0, 5): a triangle
    assert np.allclose(v[:, :2], [[0, 6], [-1, 6], [-1, 5]], atol=1e-9)
    assert g.n_segments == 2  # the F edges drawn, the f edge not


def test_generalised_cylinder_draws_its_curve_through_the_control_points():
    # vlab's Horneophyton: #(w) @Gs f(l) @Gc [ ... f @Gc ... ] @Ge: the stems are the
    # cylinder's Hermite curves between the control points (tests/turtle/test_gcylinder.py
    # checks the curve); the branch continues the open cylinder from its last point, the
    # f after @Ge stays a move and the F draws itself
    from sylva.turtle import interpret

    text = ("Lsystem: 0\nAxiom: #(0.5)@Gsf(2)@Gc(4)[+(90)f(1)@Gc(4)]f(1)@Ge(4)f(3)F(1)\n"
            "endlsystem\n")  # fmt: skip
    p = cpfg.parse(text, view=False)
    g = interpret(Derivation(p).word, p)
    assert g.n_segments == 1 + 3 * 4  # the F, then 4 strips from each @Gc / @Ge
    ends = np.asarray(g.seg_end)[:, :2]
    assert np.allclose(ends[[0, 4, 8, 12]], [[0, 7], [0, 2], [-1, 2], [0, 3]], atol=1e-9)
    assert np.allclose(np.asarray(g.seg_radius), 0.25)  # the width at the points
    assert g.n_polygons == 0  # nothing else drawn


def test_a_second_tropism_is_the_view_files_second_tropism_line(tmp_path):
    # vlab's 11-CPFG/Tropisms: N --> @Ts(1,0)@Ts(2,0)@Ts(3,0) with every strength 0, its
    # view file two tropism: lines and a torque: line (tests/turtle/test_cpfg_movements.py
    # checks the bends against the manual's formula)
    from sylva.turtle import interpret

    (tmp_path / "v.v").write_text("tropism: T: 1 0 0\ntropism: T: 0 0 1\ntorque: T: 0 1 0\n")

    def ends(axiom):
        p = cpfg.parse(f"Lsystem: 0\nAxiom: {axiom}\nendlsystem\n", view=tmp_path / "v.v")
        return np.asarray(interpret(Derivation(p).word, p).seg_end)

    bent = ends("@Ts(1,0.5)FF")
    assert not np.allclose(bent[:, 0], 0.0)  # the tropism bends toward +x
    assert np.allclose(bent[:, 2], 0.0)
    assert np.allclose(ends("@Ts(1,0.5)@Ts(2,0)@Ts(3,0)FF"), bent)
    both = ends("@Ts(1,0.5)@Ts(2,0.3)FF")
    assert both[1, 2] > 0.1  # the second bends toward +z
    assert np.allclose(ends("@Ts(1,0)@Ts(2,0)@Ts(3,0)FF"), [[0, 1, 0], [0, 2, 0]])



def test_parameters_are_32_bit_floats_as_cpfg_keeps_them():
    # vlab's 01-Introduction/08-continuous-time: t grows by dt = 0.02 until t >= 2.  cpfg
    # stores module parameters as C floats: after 100 steps t is 1.9999989 (as a double it
    # is 2.0000000000000013), so the apex crosses the threshold one step later, and every
    # later metamer with it: the leaflets that cpfg's icon shows longer than sylva drew them
    text = ("#define dt 0.02\nLsystem: 1\nderivation length: 101\nAxiom: A(0)\n"
            "A(t) : t < 2 --> A(t+dt)\nA(t) : t >= 2 --> B\nendlsystem\n")  # fmt: skip
    program = cpfg.parse(text, view=False)
    word = Derivation(program, seed=1).advance(101)
    assert len(word) == 1 and word.alphabet.names[int(word.ids[0])] == "A"
    t = np.float32(0.0)
    for _ in range(101):
        t = np.float32(np.float64(t) + 0.02)
    assert word.values.tolist() == [float(t)] and 2.0 < float(t) < 2.021
    assert str(Derivation(program, seed=1).advance(102)) == "B"
    # in a double the same rules cross at step 101
    lsys = sylva.lsystem.loads("axiom = A(0)\nA(t) : t < 2 -> A(t+0.02)\nA(t) : t >= 2 -> B\n")
    assert str(Derivation(lsys, seed=1).advance(101)) == "B"
