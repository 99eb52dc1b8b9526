"""The command tables of seed 001 (LSysVis), seed 000 (classic) and ABOP's extras."""

from __future__ import annotations

import math

import numpy as np
import pytest

from sylva.lsystem.ast import Program
from sylva.lsystem.lstring import ModuleString
from sylva.turtle import interpret, trace

BROWN = (0.4, 0.2, 0.1)


# ----------------------------------------------------------------------------- seed 001
def t14_program():
    return Program(axiom=(), settings={"rot": 35, "color": BROWN, "bg": (1, 1, 1)})


def test_lsysvis_t14_render_word_step_1():
    # seed 001 §8.3 (T14): the step-1 render word draws 5 segments; ';(0,0.7,0)' inside a
    # branch is undone by ']'; '+(20)' turns 20 degrees, '+' turns 35.
    word = ModuleString.from_text("F[+;(0,0.7,0)F]F[-;(0,0.7,0)F]+(20);(0,0.7,0)F")
    g = interpret(word, t14_program())
    assert g.n_segments == 5
    green = (0.0, 0.7, 0.0)
    np.testing.assert_allclose(g.seg_color, [BROWN, green, BROWN, green, green], atol=1e-6)
    d = g.seg_end - g.seg_start
    ang = np.degrees(np.arctan2(-d[:, 0], d[:, 1]))  # counter-clockwise from +Y
    np.testing.assert_allclose(ang, [0, 35, 0, -35, 20], atol=1e-9)
    np.testing.assert_allclose(g.seg_radius, 0.1)  # thick 0.2 is the width
    assert g.background == (1.0, 1.0, 1.0) and g.vertex_colors


def test_lsysvis_defaults_follow_table_1():
    g = interpret("F", dialect="lsys")
    np.testing.assert_allclose(g.seg_end, [[0, 1, 0]])  # len 1, facing +Y
    np.testing.assert_allclose(g.seg_color, [[0, 0, 0]])  # color 0,0,0
    np.testing.assert_allclose(g.seg_radius, [[0.1, 0.1]])  # thick 0.2
    assert g.detail == 25
    t = trace("+", dialect="lsys")  # rot 90
    np.testing.assert_allclose(t.frames[0, 0], [-1, 0, 0], atol=1e-12)


def test_lsysvis_change_commands_add_deltas_or_set_values():
    g = interpret("F_F_(3)F!F!(0.5)F;F;(0.2,0.3,0.4)F", dialect="lsys", color=(0.5, 0.5, 0.5))
    np.testing.assert_allclose(
        np.linalg.norm(g.seg_end - g.seg_start, axis=1), [1, 0.9, 3, 3, 3, 3, 3]
    )
    np.testing.assert_allclose(
        g.seg_radius[:, 0], [0.1, 0.1, 0.1, 0.05, 0.25, 0.25, 0.25], atol=1e-7
    )
    np.testing.assert_allclose(g.seg_color[-2], [0.4, 0.4, 0.4], atol=1e-6)
    np.testing.assert_allclose(g.seg_color[-1], [0.2, 0.3, 0.4], atol=1e-6)
    t = trace("~+~(45)+", dialect="lsys")  # rot 90 + rot_delta 10 = 100, then 45
    heading = [math.degrees(math.atan2(-h[0], h[1])) for h in t.frames[:, 0]]
    np.testing.assert_allclose(heading, [0, 100, 100, 145], atol=1e-9)


def test_lsysvis_colour_is_clamped_to_unit_range():
    g = interpret(";;;F", dialect="lsys", color=(0.15, 0.5, 1.0), color_delta=(-0.1, 0.1, 0.2))
    np.testing.assert_allclose(g.seg_color[0], [0.0, 0.8, 1.0], atol=1e-6)


def test_lsysvis_render_rule_leaf_draws_six_segments_and_restores_pose():
    # seed 001 T11: l ->> [-F+F+F-|-F+F+F]
    word = ModuleString.from_text("F" + "[-F+F+F-|-F+F+F]" + "F")
    g = interpret(word, dialect="lsys", rot=30)
    assert g.n_segments == 8
    np.testing.assert_allclose(g.seg_start[-1], [0, 1, 0], atol=1e-12)


def test_lsysvis_t15_segment_counts():
    word = "F"
    counts = []
    for _ in range(5):
        counts.append(interpret(word, dialect="lsys", rot=30).n_segments)
        word = word.replace("F", "F[+F][-F]F")
    assert counts == [1, 4, 16, 64, 256]


# ----------------------------------------------------------------------------- seed 000
def test_classic_leaf_neither_moves_nor_tapers():
    g = interpret("FFL[+L]F", dialect="classic", rot=45, radius=0.3, reduction=0.5)
    np.testing.assert_allclose(g.seg_radius, [[0.3, 0.15], [0.15, 0.075], [0.075, 0.0375]])
    np.testing.assert_allclose(g.leaf_pos, [[0, 2, 0], [0, 2, 0]], atol=1e-12)
    np.testing.assert_allclose(g.leaf_size, [1.0, 1.0])
    np.testing.assert_allclose(g.seg_start[2], [0, 2, 0], atol=1e-12)
    np.testing.assert_allclose(g.leaf_frame[1, 0], [-math.sqrt(0.5), math.sqrt(0.5), 0], atol=1e-12)


def test_classic_thickness_is_a_diameter_relative_to_length():
    g = interpret("F", dialect="classic", thickness=2)
    np.testing.assert_allclose(g.seg_radius, [[1.0, 1.0]])  # "diameter equals double the height"


def test_classic_taper_is_restored_by_brackets():
    g = interpret("F[F]F", dialect="classic", radius=1.0, reduction=0.5)
    np.testing.assert_allclose(g.seg_radius[:, 0], [1.0, 0.5, 0.5])


# ----------------------------------------------------------------------------- ABOP extras
def test_abop_width_and_colour_index():
    mods = ["F", "!", "F", ("!", [0.5]), "F", ";", "F", (";", [3]), "F", ",", "F"]
    word = ModuleString.from_modules(mods)  # ',' cannot be written in word text
    g = interpret(word, dialect="abop", thick=0.2, thick_factor=0.5)
    np.testing.assert_allclose(g.seg_radius[:, 0], [0.1, 0.05, 0.25, 0.25, 0.25, 0.25], atol=1e-7)
    assert g.seg_material.tolist() == [0, 0, 0, 1, 3, 2]
    assert g.materials[g.seg_material[4]].name == "color_3"


def test_abop_surface_draws_a_leaf_at_the_turtle():
    g = interpret("F~l(2)F~", dialect="abop", leaf_size=0.5)
    assert g.n_leaves == 2 and g.n_segments == 2
    np.testing.assert_allclose(g.leaf_pos, [[0, 1, 0], [0, 2, 0]], atol=1e-12)
    np.testing.assert_allclose(g.leaf_size, [2.0, 0.5])
    assert g.materials[g.leaf_material[0]].name == "leaf"


@pytest.mark.parametrize(
    "word",
    [
        "{.-f.+f.+f.-|-f.+f.+f.}",  # ABOP ch. 5: vertices recorded by '.'
        "{-f+f+f-|-f+f+f}",  # ABOP ch. 1 (Fig. 1.26): vertices are the f moves
    ],
)
def test_polygon_vertex_conventions_agree(word):
    g = interpret(word, dialect="abop", rot=30)
    assert g.n_polygons == 1 and g.n_segments == 0
    p = g.polygon(0)
    assert len(p) == 6
    # a hexagonal leaf: unit sides, symmetric about the y axis
    np.testing.assert_allclose(np.linalg.norm(np.roll(p, -1, axis=0) - p, axis=1), 1.0, atol=1e-12)
    np.testing.assert_allclose(sorted(p[:, 0]), [-0.5, -0.5, 0, 0, 0.5, 0.5], atol=1e-12)


def test_nested_polygons_are_separate():
    g = interpret("{.f.+(90)f.[{.f.-(90)f.}]+(90)f.}", dialect="abop")
    assert g.n_polygons == 2
    assert sorted(np.diff(g.poly_offsets).tolist()) == [3, 4]


def test_lsysvis_t14_with_the_derivation_engine():
    # seed 001 §8.3 (T14): render-word lengths and drawn segments for steps 0-5
    lsystem = pytest.importorskip("sylva.lsystem")
    text = "bg = 1, 1, 1\nrot = 35\ncolor = 0.4, 0.2, 0.1\naxiom = X\n"
    text += "X -> F[+X]F[-X]+(20)X\nF -> FF\nX ->> ; (0,0.7,0)F\n"
    program = lsystem.loads(text)
    got = []
    for n in range(6):
        word = lsystem.render_word(program, lsystem.derive(program, n))
        got.append((len(word), interpret(word, program).n_segments))
    assert got == [(2, 1), (15, 5), (56, 19), (183, 65), (572, 211), (1755, 665)]


def test_colour_indices_wrap_around_the_palette():
    mods = [(";", [9]), "F", "~", "{", "f", "+", "f", "+", "f", "}"]
    g = interpret(ModuleString.from_modules(mods), dialect="abop", rot=120)
    assert g.seg_material.tolist() == [1] and g.leaf_material.tolist() == [1]
    assert g.poly_material.tolist() == [1]
    assert g.materials[1].name == "color_1"
