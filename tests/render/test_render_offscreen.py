"""The offscreen renderer: silhouettes, tiling, backgrounds, MSAA and image files."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from sylva.geometry.mesh import Material, Scene
from sylva.render import Camera, Renderer, context_info, render, render_array, save_image
from sylva.render.context import RenderError, get_context

SIZE = (160, 120)


def mask(arr: np.ndarray) -> np.ndarray:
    """Pixels darker than the white background (the scene is black and unlit)."""
    return arr[..., :3].astype(int).sum(axis=-1) < 3 * 128


def test_one_shared_context(ctx):
    assert get_context() is ctx
    info = context_info(ctx)
    assert info["version"] >= 330
    assert info["max_size"] >= 2048


def test_contexts_are_only_made_in_context_py():
    root = Path(__import__("sylva").__file__).parent
    pattern = re.compile(r"create_(standalone_)?context\s*\(")
    offenders = [
        p.relative_to(root).as_posix()
        for p in root.rglob("*.py")
        if pattern.search(p.read_text(encoding="utf-8"))
        and p.relative_to(root).as_posix() != "render/context.py"
    ]
    assert offenders == []


@pytest.mark.parametrize(
    "camera",
    [
        Camera(mode="perspective", yaw=35, pitch=20),
        Camera(mode="orthographic", yaw=-60, pitch=35),
        Camera(mode="2d"),
        Camera(mode="perspective", yaw=200, pitch=-15, fov=60),
    ],
    ids=["perspective", "orthographic", "2d", "perspective-below"],
)
def test_silhouette_matches_the_projected_mesh(plant, camera, geo):
    w, h = SIZE
    cam = Camera.auto(
        plant, camera.mode, yaw=camera.yaw, pitch=camera.pitch, fov=camera.fov, aspect=w / h
    )
    got = mask(render_array(plant, SIZE, cam, lit=False, msaa=0, ground=False))
    want = geo.silhouette(plant, cam, SIZE)
    assert want.sum() > 0.05 * w * h  # the plant fills a fair part of the frame
    assert geo.iou(got, want) >= 0.99  # the brief asks 0.97; the rasteriser is exact


def test_silhouette_of_a_cube_is_a_square_in_2d(geo):
    cube = Scene([geo.box((-1, -1, -1), (1, 1, 1))])
    cam = Camera(mode="2d", height=4.0, distance=10)
    got = mask(render_array(cube, (80, 80), cam, lit=False, msaa=0))
    ys, xs = np.nonzero(got)
    assert (xs.min(), xs.max(), ys.min(), ys.max()) == (20, 59, 20, 59)
    assert got.sum() == 40 * 40


@pytest.mark.parametrize("mode", ["perspective", "2d"])
def test_tiled_render_equals_the_untiled_one(plant, mode, geo):
    scene = Scene(
        [
            geo.frustum(
                (0, 0, 0),
                (0, 2, 0),
                0.3,
                0.2,
                material=Material("bark", color=(0.4, 0.25, 0.1, 1), texture="bark"),
            )
        ]
        + plant.meshes[1:]
    )
    size = (97, 61)  # odd sizes: tiles of unequal width at the edges
    whole = render_array(scene, size, mode, msaa=0)
    tiled = render_array(scene, size, mode, msaa=0, tile_size=32)
    diff = np.abs(whole.astype(int) - tiled.astype(int))
    assert diff.mean() < 0.5
    assert (diff.max(axis=-1) > 8).mean() < 0.002


def test_tiling_beyond_the_limit_is_automatic(plant, monkeypatch):
    r = Renderer.default()
    monkeypatch.setattr(r, "max_size", 40)
    big = r.render(plant, (90, 50), "2d", lit=False, msaa=0, tile_size=4096)
    monkeypatch.undo()
    ref = r.render(plant, (90, 50), "2d", lit=False, msaa=0)
    assert np.abs(big.astype(int) - ref.astype(int)).max(axis=-1).mean() < 0.01


def test_background_colour_and_transparency(plant):
    rgb = render_array(plant, (64, 48), "2d", bg="#336699", lit=False, msaa=0)
    assert rgb.shape == (48, 64, 3)
    assert tuple(rgb[0, 0]) == (0x33, 0x66, 0x99)
    rgba = render_array(plant, (64, 48), "2d", transparent=True, lit=False, msaa=4)
    assert rgba.shape == (48, 64, 4)
    m = mask(render_array(plant, (64, 48), "2d", lit=False, msaa=0))
    assert rgba[0, 0, 3] == 0
    alpha = rgba[..., 3]
    assert np.all(alpha[m] > 0)
    inside = m & np.roll(m, 1, 0) & np.roll(m, -1, 0) & np.roll(m, 1, 1) & np.roll(m, -1, 1)
    assert np.all(alpha[inside] == 255)
    # straight alpha: edge pixels keep the object's colour (black), not a blend with the clear
    edge = (alpha > 0) & (alpha < 255)
    assert edge.any() and rgba[edge][:, :3].max() <= 2


def test_msaa_smooths_edges(plant):
    hard = render_array(plant, (64, 48), "2d", lit=False, msaa=0)
    soft = render_array(plant, (64, 48), "2d", lit=False, msaa=4)
    grey = lambda a: ((a[..., 0] > 10) & (a[..., 0] < 245)).sum()  # noqa: E731
    assert grey(hard) == 0
    assert grey(soft) > 20


def test_ground_defaults_on_for_3d_and_off_for_2d(plant):
    with_ground = render_array(plant, (64, 48), "orthographic", msaa=0)
    flat = render_array(plant, (64, 48), "2d", msaa=0)
    assert tuple(flat[0, 0]) == (255, 255, 255)
    corner = with_ground[-1, 0].astype(int)
    assert corner[1] > corner[0] and corner[1] > corner[2]  # grass green


def test_lights_off_gives_black_and_unlit_gives_albedo(geo):
    red = Scene([geo.box((-1, -1, -1), (1, 1, 1), Material("red", color=(1, 0, 0, 1)))])
    dark = render_array(red, (32, 32), "2d", lights=[], msaa=0)
    assert tuple(dark[16, 16]) == (0, 0, 0)
    flat = render_array(red, (32, 32), "2d", lit=False, msaa=0)
    assert tuple(flat[16, 16]) == (255, 0, 0)


def test_image_types_and_files(plant, tmp_path):
    img = render(plant, (40, 30), "2d", msaa=0)
    assert isinstance(img, Image.Image) and img.mode == "RGB" and img.size == (40, 30)
    png = save_image(img, tmp_path / "p.png")
    assert np.array_equal(np.asarray(Image.open(png)), np.asarray(img))
    rgba = render(plant, (40, 30), "2d", transparent=True, msaa=0)
    assert rgba.mode == "RGBA"
    jpg = save_image(rgba, tmp_path / "p.jpg", bg="black")
    back = Image.open(jpg)
    assert back.format == "JPEG" and back.mode == "RGB" and back.size == (40, 30)
    assert max(back.getpixel((0, 0))) < 20  # flattened onto black
    save_image(np.zeros((4, 5, 3), np.uint8), tmp_path / "a.png")
    with pytest.raises(ValueError, match="png"):
        save_image(img, tmp_path / "p.bmp")


def test_empty_scene_renders_background():
    arr = render_array(Scene(), (16, 8), ground=False)
    assert np.all(arr == 255)


@pytest.mark.parametrize(
    ("kwargs", "error"),
    [
        ({"size": (0, 10)}, ValueError),
        ({"size": "big"}, ValueError),
        ({"bg": "no-such-colour"}, ValueError),
        ({"camera": 3}, TypeError),
        ({"camera": "fisheye"}, ValueError),
        ({"ground": "yes"}, TypeError),
        ({"lights": ["sun"]}, TypeError),
    ],
)
def test_bad_arguments(plant, kwargs, error):
    args = {"size": (16, 16), "msaa": 0} | kwargs
    with pytest.raises(error):
        render(plant, **args)


def test_missing_texture_image_is_an_error(tmp_path, geo):
    m = geo.box((0, 0, 0), (1, 1, 1), Material("img", texture=str(tmp_path / "none.png")))
    with pytest.raises(RenderError, match="does not exist"):
        render(Scene([m]), (16, 16), msaa=0)


def test_vertex_colours_multiply_the_material_colour(geo):
    cube = geo.box((-1, -1, -1), (1, 1, 1), Material("white", color=(1, 1, 1, 1)))
    cube.colors = np.tile([[0.0, 1.0, 0.0, 1.0]], (cube.n_vertices, 1)).astype(np.float32)
    img = render_array(Scene([cube]), (16, 16), "2d", lit=False, msaa=0)
    assert tuple(img[8, 8]) == (0, 255, 0)
    mixed = Scene([cube, geo.box((2, -1, -1), (4, 1, 1), Material("red", color=(1, 0, 0, 1)))])
    img = render_array(mixed, (32, 16), "2d", lit=False, msaa=0)  # merged: white where absent
    assert tuple(img[8, 6]) == (0, 255, 0) and tuple(img[8, 26]) == (255, 0, 0)


def test_a_missing_egl_library_is_a_clear_error(monkeypatch):
    from sylva.render import create_context

    monkeypatch.setenv("SYLVA_LIBEGL", "libEGL-that-does-not-exist.so")
    with pytest.raises(RenderError, match="libegl-mesa0"):
        create_context()


def test_shadow_map_is_reused_while_the_sun_stays(plant):
    from sylva.render import Sun

    r = Renderer.default()
    with r.upload(plant) as gpu:
        r.render(gpu, (24, 24), "orthographic", msaa=0)
        first = gpu._shadow_cache["sun"]
        r.render(gpu, (24, 24), Camera.auto(gpu, yaw=120), msaa=0)
        assert gpu._shadow_cache["sun"] is first
        r.render(gpu, (24, 24), "orthographic", msaa=0, lights=[Sun(direction=(1, -1, 0))])
        assert gpu._shadow_cache["sun"] is not first
        gpu.forget_shadows()
        assert not gpu._shadow_cache


def test_transparency_blends_and_alpha_cutoff_discards(geo):
    glass = Material("glass", color=(1.0, 0.0, 0.0, 0.5))
    blue = Material("blue", color=(0.0, 0.0, 1.0, 1.0))
    # the glass is listed first and is nearer the camera: opaque materials are drawn first
    front = geo.box((-1, -1, 1.5), (1, 1, 2), glass)
    back = geo.box((0, -1, -1), (2, 1, 0), blue)
    img = render_array(
        Scene([front, back]),
        (40, 20),
        Camera(mode="2d", height=2.0, target=(0.5, 0, 0), distance=10),
        lit=False,
        msaa=0,
        bg="white",
    )
    over_white, over_blue = img[10, 8].astype(int), img[10, 24].astype(int)
    assert over_white == pytest.approx([255, 128, 128], abs=2)
    assert over_blue == pytest.approx([128, 0, 128], abs=2)
    cut = Material("cut", color=(1.0, 0.0, 0.0, 0.3), alpha_cutoff=0.5)
    img = render_array(
        Scene([geo.box((-1, -1, -1), (1, 1, 1), cut)]), (16, 16), "2d", lit=False, msaa=0
    )
    assert np.all(img == 255)
