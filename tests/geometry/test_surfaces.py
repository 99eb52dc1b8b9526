"""Predefined surfaces (cpfg's ``~X`` from ``.s`` Bézier-patch files) and cpfg's colour maps
and material files: small files written here, checked against the formulas."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from sylva.errors import LSystemSyntaxError, SylvaError, SylvaWarning
from sylva.geometry.build import build_leaves, build_mesh
from sylva.geometry.colormaps import (
    CpfgMaterial,
    read_colormap,
    read_materials,
    srgb_to_linear,
    write_materials,
)
from sylva.geometry.surfaces import (
    BUILTIN,
    Patch,
    Surface,
    evaluate_patch,
    load_surface,
    read_surface,
    write_surface,
)
from sylva.lsystem import load
from sylva.turtle import interpret

RNG = np.random.default_rng(19)


def test_a_bicubic_patch_is_the_bernstein_sum():
    P = RNG.normal(size=(4, 4, 3))
    for u, v in [(0.0, 0.0), (1.0, 1.0), (0.3, 0.8), (0.5, 0.25), (0.91, 0.07)]:
        # B_i(t) = C(3, i) t^i (1 - t)^(3 - i), written out
        bu = [(1 - u) ** 3, 3 * u * (1 - u) ** 2, 3 * u**2 * (1 - u), u**3]
        bv = [(1 - v) ** 3, 3 * v * (1 - v) ** 2, 3 * v**2 * (1 - v), v**3]
        want = sum(bu[i] * bv[j] * P[i, j] for i in range(4) for j in range(4))
        assert np.allclose(evaluate_patch(P, u, v), want, atol=1e-12)
    # corners interpolate the corner control points; the grid broadcasts
    assert np.allclose(evaluate_patch(P, 0.0, 1.0), P[0, 3])
    grid = evaluate_patch(P, np.array([[0.0], [1.0]]), np.array([[0.0, 1.0]]))
    assert np.allclose(grid, [[P[0, 0], P[0, 3]], [P[3, 0], P[3, 3]]])


def _surface() -> Surface:
    pts = RNG.uniform(-1, 1, size=(4, 4, 3)).round(3)
    return Surface(
        (Patch(pts, "blade", (3, 0.5, 4, 0.25), ("~", "top", "~", "~", "~", "~", "~", "~")),
         Patch(pts + 1.0, "tip")),
        contact=(0.125, -1.5, 0.0), end=(0.0, 1.0, 0.0), heading=(0.0, 1.0, 0.0),
        up=(0.0, 0.0, -1.0), size=2.5, precision=(3, 2),
    )  # fmt: skip


def test_a_surface_file_round_trips(tmp_path):
    s = _surface()
    path = write_surface(s, tmp_path / "leaf.s")
    text = path.read_text()
    assert text.splitlines()[1] == "PRECISION S: 3 T: 2"
    assert "CONTACT POINT  X: 0.125 Y: -1.5 Z: 0.0" in text
    back = load_surface(path)
    assert back == s
    assert back.patches[0].neighbours[1] == "top" and back.patches[0].colors == (3, 0.5, 4, 0.25)
    every = np.concatenate([p.points.reshape(-1, 3) for p in s.patches])
    assert np.allclose(back.bounds, np.stack([every.min(0), every.max(0)], axis=1))
    assert [float(x) for x in text.split("\n")[0].split()] == back.bounds.ravel().tolist()


def test_a_bad_surface_file_names_its_line_and_column(tmp_path):
    good = write_surface(_surface(), tmp_path / "a.s").read_text().splitlines()
    text = list(good)
    text[3] = "END POINT  X: 0.0 Y: one Z: 0.0"
    with pytest.raises(LSystemSyntaxError) as e:
        read_surface("\n".join(text), "a.s")
    assert (e.value.filename, e.value.line, e.value.column) == ("a.s", 4, 22)
    assert "END POINT Y: expected a number" in e.value.message
    with pytest.raises(LSystemSyntaxError, match="unexpected end of the surface file"):
        read_surface("\n".join(good[:12]))
    with pytest.raises(SylvaError, match="cannot read the surface file"):
        load_surface(tmp_path / "missing.s")


def test_the_template_places_the_contact_point_at_the_origin_in_the_turtle_frame():
    s = _surface()
    v, uv, tris = s.template(3, 2, scale=2.0)
    assert v.shape == (2 * 4 * 3, 3) and tris.shape == (2 * 2 * 3 * 2, 3) and uv.shape[0] == 24
    # surface frame: h = +y, u = -z, l = h × u = -x; template x is -x' (x to the right, -L)
    p = evaluate_patch(s.patches[0].points, 0.0, 0.0)
    q = (p - s.contact) * 2.0 / 2.5
    assert np.allclose(v[0], [q[0], q[1], -q[2]])


def _cpfg(tmp_path, view: str, body: str = "F~l(2)") -> object:
    (tmp_path / "p.l").write_text(f"Lsystem: 1\nderivation length: 0\nAxiom: {body}\n"
                                  "endlsystem\n")  # fmt: skip
    (tmp_path / "p.v").write_text(view)
    return load(tmp_path / "p.l")


def test_a_view_file_surface_is_drawn_at_the_turtle(tmp_path):
    # one flat patch: the square [0, 2] x [0, 2] of z = 0 in the editor, contact (1, 0, 0),
    # heading +y, up +z: a leaf two units long and two wide at SIZE 2 -> 1 x 1 at scale 1
    pts = np.array([[(x, y, 0.0) for x in np.linspace(0, 2, 4)] for y in np.linspace(0, 2, 4)])
    write_surface(Surface((Patch(pts),), contact=(1.0, 0.0, 0.0), size=2.0),
                  tmp_path / "sq.s")  # fmt: skip
    program = _cpfg(tmp_path, "angle increment: 90\nsurface: l sq.s 3 2 2\n", "F&F~l(2)")
    assert program.settings["surfaces"] == {"l": (str(tmp_path / "sq.s"), 3.0, 2, 2)}
    g = interpret("F&F~l(2)", program)
    assert g.n_leaves == 1 and g.leaf_surface.tolist() == [0]
    m = build_leaves(g)
    assert m.n_triangles == 2 * 2 * 2 and m.n_vertices == 9
    # after F & F the turtle is at (0, 1, -1) with H = -Z, L = -X, U = +Y; a patch point
    # (x, y) of the editor is at pos + k·((x - 1)·L' + y·H) with k = 3/2 · 2 and the
    # surface's left l = h × u = +x, matched to the turtle's L
    pos = np.array([0.0, 1.0, -1.0])
    H, L = np.array([0.0, 0.0, -1.0]), np.array([-1.0, 0.0, 0.0])
    k = 3.0 / 2.0 * 2.0
    want = np.array([pos + k * ((x - 1) * L + y * H)
                     for y in (0.0, 1.0, 2.0) for x in (0.0, 1.0, 2.0)])  # fmt: skip
    got = m.vertices.astype(np.float64)
    assert np.allclose(np.sort(got, axis=0), np.sort(want, axis=0), atol=1e-5)
    assert {tuple(r) for r in got.round(4)} == {tuple(r) for r in want.round(4)}
    # the flat leaf faces U (+Y) or -U: its normals are ±U
    assert np.allclose(np.abs(m.normals[:, 1]), 1.0, atol=1e-5)


def test_three_parameters_scale_the_surface_axes_and_a_call_scales_all_three(tmp_path):
    # a flat square lifted to z = 0.5: ~l(sx, sy, sz) scales x' (along L) by sx, y' (H) by
    # sy and z' (U) by sz, as cpfg's ~id(sx, sy, sz) does
    pts = np.array([[(x, y, 0.5) for x in np.linspace(0, 2, 4)] for y in np.linspace(0, 2, 4)])
    write_surface(Surface((Patch(pts),), contact=(1.0, 0.0, 0.0), size=2.0),
                  tmp_path / "sq.s")  # fmt: skip
    program = _cpfg(tmp_path, "surface: l sq.s 3 1 1\n", "~l(1,2,4)")
    m = build_leaves(interpret("~l(1,2,4)", program))
    k = 3.0 / 2.0  # H = +Y, L = -X, U = +Z at the start
    want = {(round(-k * 1 * (x - 1), 4), round(k * 2 * y, 4), round(k * 4 * 0.5, 4))
            for x in (0.0, 2.0) for y in (0.0, 2.0)}  # fmt: skip
    got = {tuple(r) for r in m.vertices.astype(np.float64).round(4)}
    assert want <= got and len(got) == 4
    assert np.allclose(np.abs(m.normals[:, 2]), 1.0, atol=1e-5)  # still facing U
    # inside ?(1, 0.5) … $ all three halve (a word as the turtle reads it: $ silenced)
    half = build_leaves(interpret("?(1,0.5)~l(1,2,4)?", program))
    assert np.allclose(np.sort(half.vertices, axis=0), np.sort(m.vertices, axis=0) * 0.5,
                       atol=1e-5)  # fmt: skip


def test_view_surface_errors_and_a_missing_file(tmp_path):
    with pytest.raises(LSystemSyntaxError) as e:
        _cpfg(tmp_path, "surface: l leaf.s\n")
    assert (e.value.line, "expected an id, a file name and a scale" in e.value.message) == \
        (1, True)  # fmt: skip
    (tmp_path / "leaf.s").write_text("")  # only its existence is checked on reading
    with pytest.warns(SylvaWarning, match="surface .l.: .bark.rgb. is not a texture number"):
        _cpfg(tmp_path, "surface: l leaf.s 1 4 4 bark.rgb\n")
    # cpfg skips a surface line whose file does not exist (interpret.c checks access()):
    # so does sylva, with a warning naming the line and column, and ~l draws nothing
    with pytest.warns(SylvaWarning, match=r":1:12: surface 'l': no file .*nowhere\.s; as in cpfg"):
        p = _cpfg(tmp_path, "surface: l nowhere.s 1 4 4\n")
    assert "l" not in (p.settings.get("surfaces") or {})
    # a Surface setting naming a file that is gone is still an error at drawing time
    with pytest.raises(SylvaError, match=r"surface 'l': cannot read the surface file .*gone\.s"):
        interpret("F~l", p, surfaces={"l": str(tmp_path / "gone.s")})


def test_builtin_leaf_and_petal_surfaces_in_an_lsys_program():
    g = interpret('F[~"leaf"(2)]~"petal"~', dialect="abop")
    assert g.leaf_surface.tolist() == [0, 1, -1]
    assert [s[0] for s in g.surfaces] == ["leaf", "petal"]
    scene = build_mesh(g)
    leaves = next(m for m in scene.meshes if m.name == "leaves")
    n_leaf, n_petal = (len(BUILTIN[k].template()[2]) for k in ("leaf", "petal"))
    assert leaves.n_triangles == n_leaf + n_petal + 24  # 24: sylva's default leaf
    # all three start at the turtle (1 up the stem); the leaf of size 2 reaches 2 units
    # along H = +Y
    y = leaves.vertices[:, 1]
    assert np.isclose(y.min(), 1.0, atol=1e-6) and np.isclose(y.max(), 3.0, atol=1e-6)
    for s in BUILTIN.values():  # the built-ins are valid surfaces that read back
        assert read_surface(write_surface_text(s)) == s


def write_surface_text(s):
    from sylva.geometry.surfaces import format_surface

    return format_surface(s)


# ------------------------------------------------------------------------------ colours
def test_a_colour_map_colours_the_indices(tmp_path):
    data = bytearray(768)
    data[3 * 2 : 3 * 2 + 3] = bytes([255, 128, 0])  # index 2: orange
    data[3 * 255 : 768] = bytes([0, 0, 255])
    (tmp_path / "c.map").write_bytes(bytes(data))
    pal = read_colormap(tmp_path / "c.map")
    assert pal.shape == (256, 3)
    assert np.allclose(pal[2], [1.0, ((128 / 255 + 0.055) / 1.055) ** 2.4, 0.0])
    g = interpret(";(2)F;(255)F", dialect="abop", colormap=tmp_path / "c.map")
    assert np.allclose(g.seg_color, [pal[2], pal[255]], atol=1e-6)
    assert g.materials[g.seg_material[1]].color[:3] == pytest.approx((0.0, 0.0, 1.0))
    (tmp_path / "bad.map").write_bytes(bytes(700))
    with pytest.raises(SylvaError, match="bad.map: a cpfg colour map holds 768 bytes"):
        read_colormap(tmp_path / "bad.map")


def test_a_material_file_gives_colour_opacity_and_shininess(tmp_path):
    # index 7: transparency 51, ambient (10, 20, 30), diffuse (200, 100, 50), emissive 0,
    # specular (255, 255, 255), exponent 30
    rec = bytes([7, 51, 10, 20, 30, 200, 100, 50, 0, 0, 0, 255, 255, 255, 30])
    (tmp_path / "m.mat").write_bytes(rec)
    mats = read_materials(tmp_path / "m.mat")
    assert mats[7].defined and not mats[6].defined and mats[6].diffuse == (0.8, 0.8, 0.8)
    assert mats[7].shininess == 30 and mats[7].transparency == pytest.approx(0.2)
    g = interpret(";(7)F", dialect="abop", materials=tmp_path / "m.mat")
    m = g.materials[g.seg_material[0]]
    assert m.color == pytest.approx((*srgb_to_linear([200 / 255, 100 / 255, 50 / 255]), 0.8))
    assert m.roughness == pytest.approx(math.sqrt(2 / 32))
    back = write_materials({7: mats[7]}, tmp_path / "back.mat").read_bytes()
    assert back == rec
    (tmp_path / "bad.mat").write_bytes(rec[:-1])
    with pytest.raises(SylvaError, match="bad.mat: a cpfg material file is made of 15-byte"):
        read_materials(tmp_path / "bad.mat")
    assert CpfgMaterial().diffuse == (0.8, 0.8, 0.8)


def test_view_lines_name_the_colour_files_and_the_first_index(tmp_path):
    data = bytearray(768)
    data[9:12] = bytes([0, 255, 0])
    (tmp_path / "c.map").write_bytes(bytes(data))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        p = _cpfg(tmp_path, "color map: c.map\ninitial color: 3\n", "F")
    assert p.settings["colormap"] == str(tmp_path / "c.map") and p.settings["color_index"] == 3
    g = interpret("F", p)
    assert np.allclose(g.seg_color[0], [0.0, 1.0, 0.0])
