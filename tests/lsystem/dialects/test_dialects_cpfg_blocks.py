"""cpfg's production statement blocks, its functions and the constructs vlab's models use:
small models of our own, each derived by hand from what the cpfg manual says they mean."""

from __future__ import annotations

import numpy as np
import pytest

from sylva.errors import SylvaError, SylvaWarning
from sylva.lsystem import Derivation, derive, loads
from sylva.lsystem.dialects import cpfg, dumps


def _word(text, steps=None, **kw):
    p = loads(text, filename="plant.l", view=False, **kw)
    return str(derive(p, p.steps if steps is None else steps))


def test_a_pre_condition_block_may_change_a_parameter_the_condition_then_reads():
    # A(0): t=1 < 3 -> B(1)A(1); t=2 -> B(2)A(2); t=3: the condition fails, A(2) stays
    text = ("Lsystem: 1\nderivation length: 3\nAxiom: A(0)\n"
            "A(t) : {t=t+1;} t<3 --> B(t)A(t)\nendlsystem\n")  # fmt: skip
    assert _word(text) == "B(1)B(2)A(2)"


def test_blocks_run_if_else_and_while_for_each_application():
    # A(3): s = 3+2+1 = 6 > 5 so c = 1; then A(2): s = 3, c = 0; A(1) would be next
    text = """Lsystem: 1
derivation length: 2
Axiom: A(3)
A(n) : n > 0 {s = 0; k = n; while (k > 0) {s = s + k; k = k - 1;}
    if (s > 5) c = 1; else c = 0;} --> B(s,c)A(n-1)
endlsystem
"""
    assert _word(text) == "B(6,1)B(3,0)A(1)"


def test_a_post_condition_block_runs_only_where_the_condition_holds():
    # both A's are tested; only A(2) passes and gets y = 20
    text = ("Lsystem: 1\nderivation length: 1\nAxiom: A(1)A(2)\n"
            "A(x) : x > 1 {y = x*10;} --> B(y)\nendlsystem\n")  # fmt: skip
    assert _word(text) == "A(1)B(20)"


def test_rows_of_one_rule_loop_different_numbers_of_times():
    # a for loop under masks: 2^n for n = 0, 3, 5 in one step
    text = ("Lsystem: 1\nderivation length: 1\nAxiom: A(0)A(3)A(5)\n"
            "A(n) : 1 {p = 1; for (i = 0; i < n; i++) p = p*2;} --> P(p)\nendlsystem\n")
    assert _word(text) == "P(1)P(8)P(32)"


def test_a_block_that_never_ends_stops_at_the_step_budget():
    text = ("Lsystem: 1\nderivation length: 1\nAxiom: A\n"
            "A : 1 {x = 0; while (1) {x = x + 1;}} --> B\nendlsystem\n")  # fmt: skip
    p = loads(text, filename="plant.l", view=False)
    with pytest.raises(SylvaError, match=r"plant\.l:4 \(production block\).*ran past"):
        derive(p, 1)


def test_a_block_variable_named_like_a_sylva_setting_is_its_own():
    # 'len' is a sylva setting (the step length); in a cpfg block it is a variable
    text = ("Lsystem: 1\nderivation length: 1\nAxiom: L(2)\n"
            "L(t) : 1 {len = t*3;} --> F(len)\nendlsystem\n")  # fmt: skip
    assert _word(text) == "F(6)"


def test_c_conditional_operator_in_a_successor():
    text = ("Lsystem: 1\nderivation length: 1\nAxiom: A(2)A(0)\n"
            "A(x) --> B(x > 1 ? 10 : 20, x)\nendlsystem\n")  # fmt: skip
    assert _word(text) == "B(10,2)B(20,0)"


def test_random_functions_are_per_application_and_reproducible():
    text = ("Lsystem: 1\nseed: 7\nderivation length: 1\nAxiom: A A A A A A A A\n"
            "A --> B(ran(2), nran(5, 0.1))\nendlsystem\n")  # fmt: skip
    p = loads(text, filename="plant.l", view=False)
    w1, w2 = derive(p, 1), derive(p, 1)
    assert str(w1) == str(w2)  # the same seed, the same word
    v = w1.values.reshape(-1, 2)
    assert ((v[:, 0] >= 0) & (v[:, 0] < 2)).all()
    assert len(set(v[:, 0].tolist())) == 8  # one draw per module, not one per rule
    assert np.abs(v[:, 1] - 5).max() < 1.0


def test_func_reads_the_view_files_function(tmp_path):
    # four collinear control points: the clamped B-spline is the line y = 2x
    (tmp_path / "line.func").write_text("fver 1 1\nname: line\nsamples: 10\nflip: off\n"
                                        "points: 4\n0 0\n0.333333 0.666667\n"
                                        "0.666667 1.333333\n1 2\n")  # fmt: skip
    (tmp_path / "plant.v").write_text("function: line.func 100\n")
    (tmp_path / "plant.l").write_text(
        "Lsystem: 1\nderivation length: 1\nAxiom: A(0.25) F(func(1, 0.5))\n"
        "A(x) --> B(func(1, x))\nendlsystem\n")  # fmt: skip
    p = cpfg.parse((tmp_path / "plant.l").read_text(), str(tmp_path / "plant.l"))
    assert p.axiom[1].args[0].value == pytest.approx(1.0, abs=1e-4)  # read once, in the axiom
    w = derive(p, 1)
    assert w.values[0] == pytest.approx(0.500977, abs=1e-6)  # cpfg's -str: its bisection


def test_func_values_are_cpfgs_own(tmp_path):
    # cpfg tabulates a function at its samples (the file's 'samples: 5' for fver 1 1, the
    # view's number for a 'range:' file, none here) by bisecting the spline's parameter to
    # 0.001 in x, and interpolates linearly; the numbers are cpfg's -str output for this
    # model (a cpfg built from vlab's source, benchmarks/cpfg_reference.py)
    (tmp_path / "bend.func").write_text("fver 1 1\nname: bend\nsamples: 5\nflip: off\n"
                                        "points: 4\n0 0.2 1\n0.3 0.9 1\n0.5 0.1 1\n1 0.6 1\n")
    (tmp_path / "old.func").write_text("range: 0.0 1.0\npoints: 4\n0 0\n0.2 1\n0.6 0.2\n1 1\n")
    (tmp_path / "plant.v").write_text("function: bend.func 100\nfunction: old.func\n")
    (tmp_path / "plant.l").write_text(
        "Lsystem: 1\nderivation length: 1\nAxiom: A\nA --> B(func(1,0))B(func(1,0.1))"
        "B(func(1,0.37))B(func(1,1))C(func(2,0))C(func(2,0.37))C(func(2,0.8))\nendlsystem\n")
    p = cpfg.parse((tmp_path / "plant.l").read_text(), str(tmp_path / "plant.l"))
    cpfg_str = [0.202046, 0.32113, 0.476109, 0.599269, 0.00292454, 0.565757, 0.716187]
    assert derive(p, 1).values.tolist() == pytest.approx(cpfg_str, rel=1e-5)


def test_trigonometry_is_in_degrees_as_in_cpfg():
    # cpfg's sin/cos/tan take degrees and asin/acos/atan(2) give degrees, in conditions,
    # successors and blocks alike; the word is cpfg's -str output for this model
    text = ("Lsystem: 1\nStart: {x = cos(60)+atan(1);}\nderivation length: 1\nAxiom: A(30)\n"
            "A(t) : sin(t) > 0.4 --> B(sin(t),tan(45),asin(0.5),acos(0.5),atan(1),x)\n"
            "endlsystem\n")  # fmt: skip
    p = loads(text, filename="plant.l", view=False)
    assert derive(p, 1).to_text(float32=True) == "B(0.5,1,30,60,45,45.5)"


def test_curve_functions_read_the_view_files_curve(tmp_path):
    # a straight curve from (0,0) to (3,4): length 5, halfway at (1.5, 2)
    (tmp_path / "c.con").write_text("version: 1.4\npoints: 2\nrange: 0.0 1.0\ndimension: 4\n"
                                    "type: bspline\n0 0 0 1\n3 4 0 1\n")  # fmt: skip
    (tmp_path / "plant.v").write_text("curve: c.con\n")
    (tmp_path / "plant.l").write_text(
        "Lsystem: 1\nStart: {L = curveGAL(1);}\nderivation length: 1\nAxiom: A(0.5)\n"
        "A(t) --> P(curveX(1, t), curveY(1, t), L)\nendlsystem\n")  # fmt: skip
    p = cpfg.parse((tmp_path / "plant.l").read_text(), str(tmp_path / "plant.l"))
    assert derive(p, 1).values.tolist() == pytest.approx([1.5, 2.0, 5.0], abs=1e-6)


def test_a_curves_point_is_cpfgs_table_lookup(tmp_path):
    # cpfg's CCurveXYZ: a table of the curve: line's sample count (here 3) of spline points
    # at u = 0, 0.5, 1, chord lengths normalised; the fraction t of the length is found in
    # the table, the parameter interpolated linearly, the spline evaluated there.  A curved
    # spline (control points (0,0) (0,2) (2,2) (2,0), a cubic Bezier) makes the table's
    # chords differ from the true arc, so the point is not the true arc-length point.
    (tmp_path / "c.con").write_text("version: 1.4\npoints: 4\nrange: 0.0 1.0\ndimension: 4\n"
                                    "type: bspline\n0 0 0 1\n0 2 0 1\n2 2 0 1\n2 0 0 1\n")
    (tmp_path / "plant.v").write_text("curve: c.con 3\n")
    (tmp_path / "plant.l").write_text(
        "Lsystem: 1\nStart: {L = curveGAL(1);}\nderivation length: 1\nAxiom: A(0.25)\n"
        "A(t) --> P(curveX(1, t), curveY(1, t), L)\nendlsystem\n")  # fmt: skip
    p = cpfg.parse((tmp_path / "plant.l").read_text(), str(tmp_path / "plant.l"))

    def bezier(u):  # the four-point clamped cubic B-spline is this Bezier curve
        b = np.array([(1 - u) ** 3, 3 * u * (1 - u) ** 2, 3 * u * u * (1 - u), u**3])
        return b @ np.array([[0.0, 0.0], [0.0, 2.0], [2.0, 2.0], [2.0, 0.0]])

    mid = bezier(0.5)  # (1, 1.5): the table's chords are (0,0)-(1,1.5)-(2,0), equal
    chord = float(np.hypot(*mid))
    # t = 0.25 is halfway along the first chord: u = (0 + 0.5) / 2 = 0.25
    want = [*bezier(0.25), 2 * chord]
    assert derive(p, 1).values.tolist() == pytest.approx(want, abs=1e-6)


def test_a_strict_predecessor_of_several_modules_rewrites_them_together():
    # XF --> G: the X and the F after it become one G; a lone F stays
    text = "Lsystem: 1\nderivation length: 1\nAxiom: XFYF\nXF --> G\nendlsystem\n"
    assert _word(text) == "GYF"
    text = ("Lsystem: 1\nderivation length: 1\nAxiom: A(1)B(2)B(3)\n"
            "A(x)B(y) --> C(x+y)\nendlsystem\n")  # fmt: skip
    assert _word(text) == "C(3)B(3)"


def test_multi_line_axiom_and_a_production_head_before_its_arrow():
    text = """Lsystem: 1
derivation length: 1
Axiom: A(1)
    B
A(x) : {y = x + 1;}
    y > 1 -->
    C(y)
endlsystem
"""
    assert _word(text) == "C(2)B"


def test_width_lines_equals_modules_and_brackets_in_consider():
    text = """Lsystem: 1
derivation length: 1
Consider: AB[]
Axiom: A
A --> F
    #(2) B=C
endlsystem
"""
    p = loads(text, view=False)
    assert [m.symbol for m in p.rules[0].successor] == ["F", "#", "B", "=", "C"]
    assert p.consider == frozenset("AB")


def test_cpfg_at_functions_read_and_drawn():
    from sylva.turtle import interpret

    text = ("Lsystem: 1\nderivation length: 0\n"
            "Axiom: @Gs F @Gc(1) @o(1) f @c(0.5) @Tx(1) @!(6) @#(1) @Ge(1) @Tf\n"
            "endlsystem\n")  # fmt: skip
    p = loads(text, view=False)
    with pytest.warns(SylvaWarning, match="contour 1, which the view file does not define"):
        g = interpret(derive(p, 0), p)  # @#(1) without a contour: 1 line, the circle
    assert g.n_polygons > 0  # @o and @c drew their spheres
    plain = loads(text.replace("@o(1)", "").replace("@c(0.5)", "").replace("@#(1)", ""),
                  view=False)  # fmt: skip
    assert interpret(derive(plain, 0), plain).n_polygons == 0


def test_a_block_that_assigns_a_global_carries_it_to_the_next_application():
    # cpfg applies productions module by module, left to right: each A sees the count so
    # far, the B after them the total, the homomorphism the value the step left
    text = ("Lsystem: 1\nStart: {n = 0;}\nderivation length: 1\nAxiom: AAAB\n"
            "A : 1 {n = n + 1;} --> A(n)\nB : n >= 3 --> C(n)\nhomomorphism\n"
            "C(x) --> F(n)\nendlsystem\n")  # fmt: skip
    p = loads(text, filename="plant.l", view=False)
    d = Derivation(p)
    assert str(d.advance(1)) == "A(1)A(2)A(3)C(3)"
    assert str(d.render_word()) == "A(1)A(2)A(3)F(3)"
    assert str(Derivation(p).advance(1)) == "A(1)A(2)A(3)C(3)"  # each derivation afresh
    # a condition reads the running value: only the first I sees go == 1
    q = loads("Lsystem: 1\nStart: {go = 1;}\nderivation length: 1\nAxiom: IIII\n"
              "I : go == 1 {go = 0;} --> J\nendlsystem\n", view=False)  # fmt: skip
    assert str(Derivation(q).advance(1)) == "JIII"


def test_programs_with_blocks_have_no_lsys_spelling():
    p = loads("Lsystem: 1\nAxiom: A(1)\nA(t) : {t=t+1;} --> B(t)\nendlsystem\n", view=False)
    with pytest.raises(ValueError, match="statement blocks"):
        dumps(p)


def test_array_elements_and_labels_in_successors_and_a_head_ending_in_a_colon():
    # len[s] reads the Define: array; @L("%.f", c) keeps its number, not its text;
    # the second production's head ends with ':' and its condition is on the next line
    text = """Lsystem: 1
Define: { array len[2] = {1.5, 2.5}; }
derivation length: 1
Axiom: A(1) B(0)
A(s) --> F(len[s]) @L("%.f", s)
B(x) :
    x == 0 --> C
endlsystem
"""
    assert _word(text) == "F(2.5)@L(1)C"


def test_arrays_of_two_dimensions_row_major():
    # m[2][3] = {1..6}: m[1][0] is the 4th value, m[0][2] the 3rd
    text = """Lsystem: 1
Define: { array m[2][3] = {1, 2, 3, 4, 5, 6}; }
Start: { s = m[1][0] + 10 * m[0][2]; }
derivation length: 1
Axiom: A(1, 2)
A(i, j) --> B(m[i][j], s)
endlsystem
"""
    assert _word(text) == "B(6,34)"


def test_a_head_whose_condition_has_a_minus_after_a_less_than():
    # x<-1 is a comparison, not an arrow: the head runs on to the next line's arrow
    text = """Lsystem: 1
derivation length: 1
Axiom: A(-2) B A(0)
A(x) B : x<-1
    --> C
endlsystem
"""
    assert _word(text) == "CA(0)"
