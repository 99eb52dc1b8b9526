"""Branch tubes, prisms, cones, leaves, polygons and blocks."""

from __future__ import annotations

import math

import numpy as np
import pytest
import trimesh

from sylva.geometry import _kernels as K
from sylva.geometry import build as B
from sylva.geometry.build import (
    BuildError,
    build_blocks,
    build_branches,
    build_leaves,
    build_mesh,
    build_polygons,
    leaf_template,
)
from sylva.turtle import interpret

from .words import expand

PLANT = expand("X", {"X": "F[+X][-X]FX", "F": "FF"}, 4)
BUSH = expand(
    "A", {"A": "[&FL!A]/////[&FL!A]///////[&FL!A]", "F": "S/////F", "S": "FL", "L": ""}, 4
)


def as_trimesh(mesh):
    # merge by position only: seams duplicate vertices for their texture coordinates
    return trimesh.Trimesh(mesh.vertices.astype(np.float64), mesh.indices, process=True)


def tubes_of(g, detail):
    """The triangles of each tube (an axis followed through its continuations)."""
    plan = B._tube_plan(g, g.seg_radius, 140.0, False, detail)
    cont, prev, toff = plan[0], plan[1], plan[5]
    for s in np.flatnonzero(~prev):
        tris = []
        while s >= 0:
            tris.extend(range(toff[s], toff[s + 1]))
            s = cont[s]
        yield np.array(tris)


@pytest.mark.parametrize("word, rot", [(PLANT, 25.7), (BUSH, 22.5), ("F&F+F&F&F", 90.0)])
def test_tubes_are_closed_consistently_wound_manifolds(word, rot):
    g = interpret(word, dialect="abop", rot=rot, thick=0.2, thick_factor=0.8)
    m = build_branches(g, detail=8)
    seen = 0
    for tris in tubes_of(g, 8):
        body = trimesh.Trimesh(m.vertices.astype(np.float64), m.indices[tris], process=True)
        assert body.is_watertight and body.is_winding_consistent
        assert body.euler_number == 2  # each tube is a sphere topologically
        assert body.volume > 0  # normals point outward
        seen += len(tris)
    assert seen == m.n_triangles


@pytest.mark.parametrize("d", [3, 5, 15, 16, 17, 40])
def test_tubes_at_any_detail_are_round_closed_and_unit_normal(d):
    # the fill writes rings 16 vertices and indices 16 at a time: sides below, at and
    # above a block's width must all give round rings, unit normals and closed tubes
    g = interpret("F[+(40)F&(30)F]F/(45)F", dialect="abop", thick=0.3)
    m = build_branches(g, detail=d)
    r = d + 1
    ring = m.vertices[:r].astype(np.float64)  # the trunk's start ring
    np.testing.assert_allclose(np.linalg.norm(ring[:, [0, 2]], axis=1), 0.15, rtol=1e-6)
    np.testing.assert_allclose(ring[:, 1], 0.0, atol=1e-7)
    np.testing.assert_allclose(ring[-1], ring[0], atol=1e-7)  # the seam closes
    np.testing.assert_allclose(m.uvs[:r, 0], np.arange(r) / d, atol=1e-7)
    np.testing.assert_allclose(np.linalg.norm(m.normals, axis=1), 1.0, atol=1e-6)
    assert m.indices.max() == m.n_vertices - 1
    seen = 0
    for tris in tubes_of(g, d):
        body = trimesh.Trimesh(m.vertices.astype(np.float64), m.indices[tris], process=True)
        assert body.is_watertight and body.is_winding_consistent and body.volume > 0
        seen += len(tris)
    assert seen == m.n_triangles


def test_tube_counts_share_rings_along_axes():
    g = interpret("FFF[+F]F", dialect="abop", rot=30)
    d = 7
    m = build_branches(g, detail=d)
    # main axis of 4 segments: 1 start ring + 4 end rings + 2 caps; branch: 2 rings + 2 caps
    assert m.n_vertices == (5 * (d + 1) + 2) + (2 * (d + 1) + 2)
    assert m.n_triangles == 4 * 2 * d + 2 * d + 2 * d + 2 * d


def test_colour_changes_keep_one_closed_tube():
    # abop ; switches the material: the axis stays one tube, each segment in its own
    # material, with a copy of the previous end ring where the material changes
    g = interpret("F;+(20)F;-(35)F", dialect="abop", thick=0.3)
    assert len(set(g.seg_material.tolist())) == 3
    d = 9
    r = d + 1
    m = build_branches(g, detail=d)
    assert m.n_triangles == 3 * 2 * d + 2 * d  # two caps only
    assert m.n_vertices == 6 * r + 2
    ids = m.triangle_materials()
    assert [len(set(ids[k : k + 2 * d].tolist())) for k in (d, 3 * d, 5 * d)] == [1, 1, 1]
    # the copies lie exactly on the rings they copy
    ring = [m.vertices[k * r + 1 : (k + 1) * r + 1] for k in range(5)]  # after start cap
    np.testing.assert_array_equal(ring[2], ring[1])
    np.testing.assert_array_equal(ring[4], ring[3])
    body = as_trimesh(m)
    assert body.is_watertight and body.is_winding_consistent and body.volume > 0
    assert body.euler_number == 2


def test_mitred_joint_has_no_gap_and_keeps_the_radius():
    g = interpret("F+(60)F", dialect="abop", thick=0.4)
    m = build_branches(g, detail=16)
    # the shared ring lies in the bisecting plane of the two axes through the joint
    a = np.array([0.0, 1.0, 0.0])
    b = np.array([-math.sin(math.radians(60)), math.cos(math.radians(60)), 0.0])
    n = (a + b) / np.linalg.norm(a + b)
    joint = np.array([0.0, 1.0, 0.0])
    ring = m.vertices[17 + 1 : 17 + 1 + 17].astype(np.float64)  # after start ring + cap
    np.testing.assert_allclose((ring - joint) @ n, 0.0, atol=1e-6)
    # every ring point is at the tube radius from both axes (both cylinders meet there)
    for axis, point in ((a, joint), (b, joint)):
        rel = ring - point
        dist = np.linalg.norm(rel - np.outer(rel @ axis, axis), axis=1)
        np.testing.assert_allclose(dist, 0.2, rtol=1e-5)


def test_parallel_transport_does_not_twist_a_straight_axis():
    g = interpret("F\\(50)F/(20)F", dialect="abop")
    m = build_branches(g, detail=6)
    rings = m.vertices[:7], m.vertices[8:15], m.vertices[15:22]
    np.testing.assert_allclose(rings[0][:, [0, 2]], rings[1][:, [0, 2]], atol=1e-6)
    np.testing.assert_allclose(rings[1][:, [0, 2]], rings[2][:, [0, 2]], atol=1e-6)


def test_uvs_run_around_and_along():
    g = interpret("FFF", dialect="abop", thick=1 / math.pi)  # circumference 1
    m = build_branches(g, detail=8)
    u, v = m.uvs[:, 0], m.uvs[:, 1]
    assert u.min() == 0 and u.max() == 1
    np.testing.assert_allclose(sorted(set(np.round(v, 5))), [0, 1, 2, 3], atol=1e-5)


def test_normals_are_unit_and_point_away_from_the_axis():
    g = interpret("F", dialect="abop", thick=0.5)
    m = build_branches(g, detail=12)
    np.testing.assert_allclose(np.linalg.norm(m.normals, axis=1), 1.0, atol=1e-6)
    side = np.abs(m.vertices[:, 1] - 0.5) < 0.51
    radial = m.vertices[:, [0, 2]]
    ring = np.linalg.norm(radial, axis=1) > 0.2
    sel = side & ring
    dots = (m.normals[sel][:, [0, 2]] * radial[sel]).sum(axis=1)
    assert np.all(dots > 0)


def test_leonardo_taper_keeps_cross_section_area():
    g = interpret(PLANT, dialect="abop", rot=25.7, thick=0.02)
    m = build_branches(g, detail=6, taper="leonardo")
    assert m.n_triangles > 0
    r = K.leonardo(g.seg_parent, g.seg_radius, 2.0)
    for s in np.unique(g.seg_parent[g.seg_parent >= 0])[:200]:
        kids = np.flatnonzero(g.seg_parent == s)
        assert r[s, 0] ** 2 == pytest.approx((r[kids, 0] ** 2).sum(), rel=1e-5)
    tips = np.setdiff1d(np.arange(g.n_segments), g.seg_parent)
    np.testing.assert_allclose(r[tips, 0], 0.01, rtol=1e-6)
    assert r[0, 0] == pytest.approx(0.01 * math.sqrt(len(tips)), rel=1e-5)


def test_prism_mode_is_seed_001s_mantle():
    g = interpret("FF", dialect="lsys")
    m = build_branches(g, mode="prism", detail=5)
    assert m.n_triangles == 2 * 2 * 5 and m.n_vertices == 2 * 5 * 4
    flat = build_branches(g, mode="prism", detail=2)  # detail < 3: one rectangle
    assert flat.n_triangles == 2 * 2 * 2
    np.testing.assert_allclose(np.ptp(flat.vertices, axis=0)[[0, 2]].max(), 0.2, atol=1e-6)
    assert build_mesh(g, mode="prism").meshes[0].n_triangles == 2 * 2 * 25  # detail 25


def test_cone_mode_is_seed_000s_frustum_with_bottom_hemisphere():
    g = interpret("F", dialect="classic", radius=0.5, reduction=0.5)
    m = build_branches(g, mode="cone", detail=8)
    t = as_trimesh(m)
    assert t.is_watertight and t.volume > 0
    lo, hi = m.bounds()
    assert lo[1] == pytest.approx(-0.5, abs=1e-6)  # hemisphere below the base
    assert hi[1] == pytest.approx(1.0, abs=1e-6)
    top = m.vertices[np.isclose(m.vertices[:, 1], 1.0)]
    assert np.linalg.norm(top[:, [0, 2]], axis=1).max() == pytest.approx(0.25, abs=1e-6)
    # frustum + hemisphere volume, approximated by 8 sides
    exact = math.pi / 3 * (0.25 + 0.125 + 0.0625) + 2 / 3 * math.pi * 0.125
    assert t.volume == pytest.approx(exact, rel=0.15)


def test_bad_options_raise_build_errors():
    g = interpret("F", dialect="abop")
    with pytest.raises(BuildError, match="unknown branch mode"):
        build_branches(g, mode="spline")
    with pytest.raises(BuildError, match="at least 3 sides"):
        build_branches(g, detail=2)
    with pytest.raises(BuildError, match="unknown taper"):
        build_branches(g, taper="murray")


def test_leaves_are_one_face_with_a_double_sided_material_and_visible_edge_on():
    g = interpret("[&L]", dialect="classic", rot=90)
    m = build_leaves(g)
    tv, _, tt = leaf_template()
    # one face per template triangle (two coincident opposite faces are dropped as
    # duplicates by Blender and make STL non-manifold); the material says double-sided
    assert m.n_triangles == len(tt) * g.n_leaves and m.n_vertices == len(tv) * g.n_leaves
    assert all(mat.double_sided for mat in (m.materials[i] for i in np.unique(m.material_ids)))
    tri = m.vertices[m.indices].astype(np.float64)
    key = np.sort(m.indices, axis=1)
    assert len(np.unique(key, axis=0)) == m.n_triangles
    # the leaf lies along -Z (pitched down) in the XZ plane; seen edge-on (from +X) it
    # still shows an area thanks to its fold and droop
    e1 = tri[:, 1, 1:] - tri[:, 0, 1:]
    e2 = tri[:, 2, 1:] - tri[:, 0, 1:]
    area = 0.5 * np.abs(e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]).sum()
    assert area > 0.01
    assert m.uvs.min() >= 0 and m.uvs.max() <= 1
    # the scene agrees: the leaf material is double-sided wherever it appears
    s = build_mesh(interpret("F[&L]", dialect="classic", rot=90))
    leaf = {mat.name for mat in s.meshes[1].materials}
    assert all(mat.double_sided for mesh in s.meshes for mat in mesh.materials if mat.name in leaf)


def test_concave_polygon_triangulation_preserves_area():
    # an L-shaped (concave) hexagon drawn by the turtle, area 3
    word = "{.F(2).-(90)F.-(90)F.+(90)F.-(90)F(1).-(90)F(2).}"
    g = interpret(word, dialect="abop")
    assert g.n_polygons == 1 and len(g.polygon(0)) == 6
    m = build_polygons(g)
    tri = m.vertices[m.indices].astype(np.float64)
    area = 0.5 * np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]), axis=1)
    assert m.n_triangles == 4  # a hexagon: 4 triangles, one face (double-sided material)
    assert m.materials[int(m.material_ids[0])].double_sided
    assert area.sum() == pytest.approx(3.0)
    assert (area > 1e-9).all()


def test_blocks_are_cubes_with_a_material_per_buffer():
    g = interpret("U1U2xU", dialect="engine", shrink=0.5)
    m = build_blocks(g)
    assert m.n_triangles == 12 * g.n_blocks
    assert sorted(np.unique(m.material_ids).tolist()) == [0, 1, 2]
    t = as_trimesh(m)
    assert t.volume == pytest.approx(1 + 1 + 0.125 + 0.125)
    s = build_mesh(g)
    assert [mat.name for mat in s.meshes[0].materials] == ["buffer_0", "buffer_1", "buffer_2"]


def test_build_mesh_scene_parts_and_material_pruning():
    word = "F[&F~l][{.-f.+f.+f.}]"
    g = interpret(word, dialect="abop", rot=30)
    s = build_mesh(g, detail=6)
    assert [m.name for m in s.meshes] == ["branches", "leaves", "polygons"]
    assert [mat.name for mat in s.meshes[0].materials] == ["color_0"]
    assert [mat.name for mat in s.meshes[1].materials] == ["leaf"]


def test_program_detail_below_three_is_flat_for_prisms_and_minimal_for_tubes():
    g = interpret("F", dialect="lsys", detail=2.9)  # seed 001: floor 2 < 3 -> a rectangle
    assert g.detail == 2
    assert build_branches(g, mode="prism").n_triangles == 4  # one rectangle, both sides
    assert build_branches(g).n_triangles == 4 * 3  # tube: 3 sides and two caps
    assert (
        build_branches(interpret("F", dialect="lsys", detail=7.8), mode="prism").n_triangles == 14
    )


@pytest.mark.parametrize("road", ["always", "never"])
def test_segments_too_short_to_frame_are_left_out_of_the_tubes(monkeypatch, road):
    # cpfg's F(func(...)) draws segments 1e-19 long (vlab's sympodial models): the compiled
    # tube fill divided by their zero length inside its parallel loop (a SystemError)
    from sylva.turtle import interpret

    monkeypatch.setenv("SYLVA_JIT", road)
    g = interpret("F(1)F(1e-19)F(1e-19)[+F(1)]F(-1e-19)F(1)", dialect="abop", rot=30)
    clean = interpret("F(1)[+F(1)]F(1)", dialect="abop", rot=30)
    assert g.n_segments == 6 and clean.n_segments == 3
    a, b = build_branches(g, detail=6), build_branches(clean, detail=6)
    assert a.n_triangles == b.n_triangles  # the same three tubes, joined the same way
    np.testing.assert_allclose(a.vertices, b.vertices, atol=1e-6)
    assert np.isfinite(a.normals).all()
