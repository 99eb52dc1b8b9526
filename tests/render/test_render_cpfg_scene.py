"""cpfg's background scenes and surface textures (the cpfg manual §8.3 and §8.1.7): small
files written here, read by the view file, checked in the mesh and at known pixels."""

from __future__ import annotations

import numpy as np
import pytest
from PIL import Image

from sylva.errors import LSystemSyntaxError, SylvaWarning
from sylva.geometry.build import build_mesh
from sylva.geometry.colormaps import srgb_to_linear
from sylva.geometry.mesh import Scene
from sylva.geometry.scenery import scenery_mesh
from sylva.geometry.surfaces import Patch, Surface, write_surface
from sylva.lsystem import load
from sylva.lsystem.dialects._cpfg_scene import read_scene
from sylva.render import Camera, render_array
from sylva.turtle import interpret

SCENE = """#define ALPHA 1   /* a constant, as cpfg's preprocessor reads it */
material
0 0 0 ALPHA
1 0 0 ALPHA
0 0 0 ALPHA
0 0 0 ALPHA
0
pushmatrix
 translate 2 0 0
 box 1 1 1
popmatrix
material 0 0 0 1  0 0 1 1  0 0 0 1  0 0 0 1  10
polygon -3 0 0  -2 0 0  -2 1 0  -3 1 0
"""


def _model(tmp_path, view: str, axiom: str = "F") -> object:
    (tmp_path / "p.l").write_text(f"Lsystem: 1\nderivation length: 0\nAxiom: {axiom}\n"
                                  "endlsystem\n")  # fmt: skip
    (tmp_path / "p.v").write_text(view)
    return load(tmp_path / "p.l")


def test_a_scene_file_reads_its_objects_with_their_matrices_and_materials():
    box, poly = read_scene(SCENE, "bg.dat")
    assert (box.kind, box.params, poly.kind, len(poly.params)) == ("box", (1, 1, 1), "polygon", 12)
    m = np.array(box.matrix).reshape(4, 4)
    assert np.allclose(m[:3, 3], (2, 0, 0)) and np.allclose(poly.matrix, np.eye(4).ravel())
    assert box.material[4:8] == (1.0, 0.0, 0.0, 1.0)  # the #define'd alpha substituted
    assert poly.material[4:8] == (0.0, 0.0, 1.0, 1.0) and poly.material[16] == 10
    # transformations compose as OpenGL's: rotate then translate moves along the turned x
    (s,) = read_scene("rotate 90 0 0 1\ntranslate 1 0 0\nscale 2 2 2\nsphere 1\n")
    m = np.array(s.matrix).reshape(4, 4)
    assert np.allclose(m[:3, 3], (0, 1, 0)) and np.allclose(m[:3, :3] @ (1, 0, 0), (0, 2, 0))
    # multmatrix takes its 16 numbers column by column (the last four: the translation)
    (c,) = read_scene("multmatrix 0 1 0 0  -1 0 0 0  0 0 1 0  5 6 7 1\ncylinder 1 2\n")
    m = np.array(c.matrix).reshape(4, 4)
    assert np.allclose(m[:3, 3], (5, 6, 7)) and np.allclose(m[:3, :3] @ (1, 0, 0), (0, 1, 0))


def test_the_view_file_draws_the_scene_around_the_plant_in_its_colours(tmp_path):
    (tmp_path / "bg.dat").write_text(SCENE)
    program = _model(tmp_path, "background scene: bg.dat\nline style: cylinder\n")
    scene = build_mesh(interpret("F", program))
    bg = next(m for m in scene.meshes if m.name == "background")
    assert bg.n_triangles == 12 + 2  # the box's six faces, the quad fanned
    ids = bg.triangle_materials()
    red, blue = (bg.materials[k] for k in np.unique(ids))
    assert np.allclose(red.color, (1, 0, 0, 1)) and np.allclose(blue.color, (0, 0, 1, 1))
    box = bg.vertices[bg.indices[ids == ids[0]].ravel()]
    assert np.allclose(box.min(0), (2, 0, 0)) and np.allclose(box.max(0), (3, 1, 1))
    # the plant's box leaves the background out (cpfg fits its view to the plant)
    lo, hi = scene.bounds(skip=("background",))
    assert hi[0] < 1 and lo[0] > -1
    # at known pixels: the red box right of the plant, the blue square left of it
    cam = Camera(mode="2d", target=(0.0, 0.5, 0.0), height=4.0, distance=10.0)
    img = render_array(Scene([bg]), (64, 32), cam, lit=False, msaa=0, bg="black")
    px = 64 / 8  # 8 units across
    red_px = img[16, int((2.5 + 4) * px)]
    blue_px = img[16, int((-2.5 + 4) * px)]
    assert red_px[0] > 200 and red_px[1] < 40 and red_px[2] < 40
    assert blue_px[2] > 200 and blue_px[0] < 40 and blue_px[1] < 40
    assert img[16, 32].max() < 40  # nothing between (the plant is not in this scene)


@pytest.mark.parametrize("text, line, column, what", [
    ("sphere 1\nteapot 2\n", 2, 1, "unknown background scene command 'teapot'"),
    ("box 1 2\n", 1, 1, "box needs at least 3 numbers, got 2"),
    ("pushmatrix\npopmatrix\n  popmatrix\n", 3, 3, "popmatrix without a pushmatrix"),
    ("translate 1 2\n", 1, 1, "translate needs 3 numbers, got 2"),
    ("1 2 3\n", 1, 1, "the number '1' follows no command"),
])  # fmt: skip
def test_bad_scene_files_name_the_file_line_and_column(text, line, column, what):
    with pytest.raises(LSystemSyntaxError) as e:
        read_scene(text, "bg.dat")
    assert (e.value.filename, e.value.line, e.value.column) == ("bg.dat", line, column)
    assert what in e.value.message


def test_a_missing_scene_file_names_the_view_line(tmp_path):
    with pytest.raises(LSystemSyntaxError) as e:
        _model(tmp_path, "angle increment: 30\nbackground scene: nowhere.dat\n")
    assert e.value.filename.endswith("p.v") and e.value.line == 2 and e.value.column == 19
    assert "cannot read" in e.value.message and "nowhere.dat" in e.value.message
    with pytest.warns(SylvaWarning, match="'light' .* is skipped"):
        assert read_scene("light 0 0 1 1\nsphere 1\n")[0].kind == "sphere"


def test_scenery_transforms_normals_and_keeps_spheres_round():
    ident = tuple(np.eye(4).ravel())
    scale = (2.0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1)
    m = scenery_mesh([("sphere", (1.0,), scale, None)])
    assert np.allclose(m.bounds(), [[-2, -1, -1], [2, 1, 1]], atol=1e-6)
    v = m.vertices.astype(float)
    n = m.normals.astype(float)  # an ellipsoid's normal is (x/4, y, z), normalised
    want = v / np.array([4.0, 1.0, 1.0])
    want /= np.linalg.norm(want, axis=1, keepdims=True)
    assert np.allclose(n, want, atol=1e-5)
    cone = scenery_mesh([("cone", (1.0, 0.0, 2.0), ident, (0, 0, 0, 1, 0.5, 0.5, 0.5, 1))])
    assert np.allclose(cone.bounds()[:, 1], (0, 2)) and cone.materials[0].double_sided
    assert np.allclose(cone.materials[0].color[:3], srgb_to_linear([0.5] * 3))


# --------------------------------------------------------------------------- textures
def _square_patch(tmp_path) -> None:
    # one flat patch, the square [0, 2]² of z = 0, contact (1, 0, 0), SIZE 2: at the
    # turtle's start (H = +Y, L = -X, U = +Z) a leaf over x ∈ [-0.5, 0.5], y ∈ [0, 1]
    pts = np.array([[(x, y, 0.0) for x in np.linspace(0, 2, 4)] for y in np.linspace(0, 2, 4)])
    write_surface(Surface((Patch(pts),), contact=(1.0, 0.0, 0.0), size=2.0),
                  tmp_path / "sq.s")  # fmt: skip


def _two_by_two(path) -> None:
    # top row: red, green; bottom row: blue, black (Pillow: the first row is the top)
    rgb = np.array([[[255, 0, 0], [0, 255, 0]], [[0, 0, 255], [0, 0, 0]]], np.uint8)
    Image.fromarray(rgb).save(path)


def test_texture_coordinates_per_patch_and_per_surface(tmp_path):
    _square_patch(tmp_path)
    from sylva.geometry.surfaces import load_surface

    surf = load_surface(tmp_path / "sq.s")
    verts = surf.template(2, 2)[0]
    per_patch = surf.texture_uvs(2, 2)
    # (i / s, j / t): along the rows' index (y in the file) and along a row (x)
    assert np.allclose(per_patch[:3], [[0, 0], [0, 0.5], [0, 1]])
    assert np.allclose(per_patch[-1], [1, 1])
    whole = surf.texture_uvs(2, 2, per_surface=True)
    # along the turtle's left (the template's -x) and its heading, each over [0, 1]
    assert np.allclose(whole[:, 0], (verts[:, 0].max() - verts[:, 0]) / np.ptp(verts[:, 0]))
    assert np.allclose(whole[:, 1], (verts[:, 1] - verts[:, 1].min()) / np.ptp(verts[:, 1]))


def test_a_texture_line_maps_its_image_onto_the_surface(tmp_path):
    _square_patch(tmp_path)
    _two_by_two(tmp_path / "tex.png")
    view = ("surface: l sq.s 1 4 4\n"
            "texture: F: tex.png E: m S: H: n L: n\n")  # fmt: skip
    program = _model(tmp_path, view, "@Tx(1)~l(1)")
    scene = build_mesh(interpret("@Tx(1)~l(1)", program))
    (leaves,) = [m for m in scene.meshes if m.name == "leaves"]
    (mat,) = leaves.materials
    # an opaque image: no alpha test (one with transparent pixels gets a cut-off of 0.5)
    assert mat.texture == str(tmp_path / "tex.png") and mat.alpha_cutoff is None
    # the pixels travel with the material for the formats that embed images, bottom row
    # first (the mesh's v = 0 is the image's bottom, as in OpenGL)
    assert mat.images.base_color[0, 0, :3].tolist() == [0, 0, 255]
    mat = type(mat)(mat.name, (1.0, 1.0, 1.0, 1.0), texture=mat.texture, double_sided=True)
    leaves.materials = [mat]
    cam = Camera(mode="2d", target=(0.0, 0.5, 0.0), height=1.0, distance=10.0)
    img = render_array(Scene([leaves]), (32, 32), cam, lit=False, msaa=0, bg="white")
    # seen from +Z: u grows along L = -X (to the left), v up the heading
    quads = {"top left": img[8, 8], "top right": img[8, 24], "bottom left": img[24, 8],
             "bottom right": img[24, 24]}  # fmt: skip
    assert np.argmax(quads["top right"]) == 0 and quads["top right"][0] > 200  # red
    assert np.argmax(quads["top left"]) == 1 and quads["top left"][1] > 200  # green
    assert np.argmax(quads["bottom right"]) == 2 and quads["bottom right"][2] > 200  # blue
    assert quads["bottom left"].max() < 30  # black
    # without @Tx the same leaf has no texture; the surface line's own number fixes it
    plain = build_mesh(interpret("~l(1)", program))
    assert all(m.texture != str(tmp_path / "tex.png") for m in plain.meshes[0].materials)
    fixed = _model(tmp_path, "surface: l sq.s 1 4 4 1\ntexture: F: tex.png\n", "~l(1)")
    got = build_mesh(interpret("~l(1)", fixed)).meshes[0].materials[0]
    assert got.texture == str(tmp_path / "tex.png")


def test_a_texture_that_cpfg_drops_takes_no_number(tmp_path):
    _square_patch(tmp_path)
    _two_by_two(tmp_path / "tex.png")
    with pytest.warns(SylvaWarning, match="cannot be read; cpfg drops it"):
        p = _model(tmp_path, "surface: l sq.s 1\ntexture: F: gone.png\ntexture: F: tex.png\n")
    assert [t["file"] for t in p.settings["textures"]] == [str(tmp_path / "tex.png")]
    with pytest.warns(SylvaWarning, match=r"p\.v:1:10: texture: unknown subcommand 'tex"):
        _model(tmp_path, "texture: tex.png\n")


def test_at_tx_textures_the_cylinders_drawn_after_it_in_its_branch(tmp_path):
    _two_by_two(tmp_path / "tex.png")
    axiom = "F[@Tx(1)F]F@Tx(1)F"
    program = _model(tmp_path, "texture: F: tex.png\nline style: cylinder\n", axiom)
    g = interpret(axiom, program)
    textured = [g.materials[k].texture for k in g.seg_material.tolist()]
    want = str(tmp_path / "tex.png")
    # the first F, the one after the branch (the branch gave the texture back), not;
    # the one inside the branch and the last one, textured
    assert textured[0] != want and textured[2] != want
    assert textured[1] == want and textured[3] == want
    (branches,) = [m for m in build_mesh(g).meshes if m.name == "branches"]
    assert branches.uvs is not None  # u around, v along: the image's coordinates
    assert any(m.texture == want and m.images is not None for m in branches.materials)


def test_sgi_rgb_textures_read_as_cpfg_writes_them(tmp_path):
    # vlab's textures are often SGI images (.rgb); Pillow reads and writes them
    _square_patch(tmp_path)
    rgb = np.array([[[255, 0, 0], [0, 255, 0]], [[0, 0, 255], [0, 0, 0]]], np.uint8)
    Image.fromarray(rgb).save(tmp_path / "tex.rgb", format="SGI")
    program = _model(tmp_path, "surface: l sq.s 1 2 2 1\ntexture: F: tex.rgb\n", "~l(1)")
    (leaves,) = build_mesh(interpret("~l(1)", program)).meshes
    (mat,) = leaves.materials
    assert mat.texture.endswith("tex.rgb")
    assert mat.images.base_color[:, :, :3].tolist() == rgb[::-1].tolist()  # bottom row first
    cam = Camera(mode="2d", target=(0.0, 0.5, 0.0), height=1.0, distance=10.0)
    white = type(mat)(mat.name, (1.0, 1.0, 1.0, 1.0), texture=mat.texture, double_sided=True)
    leaves.materials = [white]
    img = render_array(Scene([leaves]), (32, 32), cam, lit=False, msaa=0, bg="white")
    # per patch: u = i / s along the rows' index (the file's y: up the heading, up the
    # screen), v = j / t along a row (the file's x, drawn at -x: v = 0 on the right)
    assert np.argmax(img[24, 24]) == 2 and img[24, 24][2] > 200  # u < .5, v < .5: blue
    assert img[8, 24].max() < 30  # u > .5, v < .5: black
    assert np.argmax(img[24, 8]) == 0 and img[24, 8][0] > 200  # u < .5, v > .5: red
    assert np.argmax(img[8, 8]) == 1 and img[8, 8][1] > 200  # u > .5, v > .5: green


def test_the_viewing_angle_is_the_perspective_field_of_view(tmp_path):
    import warnings

    from sylva.lsystem.dialects._cpfg_view import read_camera

    view = "projection: perspective\nviewing angle: 30\nviewpoint: 0,3,7\n"
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # a camera line: no warning
        _model(tmp_path, view)
    cam = read_camera(tmp_path / "p.v")
    assert cam["viewing angle"] == 30.0 and cam["projection"] == "perspective"
