"""Issue 22 item 4, the gaps closed: custom colour maps and palette files on the CLI, marble
turbulence, Worley F1..Fn of any order with a point count, wood that tiles, a normalised
F1 + F2 and grass as even as the renderer's shader."""

import numpy as np
import pytest
from PIL import Image

import sylva.texture as tx
from sylva.cli import main
from sylva.texture import noise, presets
from sylva.texture._cellkernels import INV32, _cell_hash, hash32, poisson_cell_points
from sylva.texture.colormap import (
    ColormapError,
    apply_colormap,
    get_colormap,
    load_palette,
    parse_colors,
)


# ----------------------------------------------------------------------------- tiling
def edge_ratio(img):
    """The worst, over both axes, of mean |jump| across the wrap edge / mean |jump| between
    neighbouring rows (columns): about 1 when the opposite edges continue each other."""
    a = np.asarray(img, dtype=np.float64)
    if a.ndim == 3:
        a = a.mean(axis=2)
    out = []
    for axis in (0, 1):
        b = np.moveaxis(a, axis, 0)
        out.append(np.abs(b[0] - b[-1]).mean() / np.abs(np.diff(b, axis=0)).mean())
    return max(out)


SHAPE = (96, 128)


@pytest.fixture(scope="module")
def noise_edges():
    """The edge statistic of the tileable noises: the bar every tileable pattern must meet."""
    return max(edge_ratio(noise.noise_grid(SHAPE, kind=k, scale=5.3, octaves=3, seed=s,
                                           tileable=True))
               for k in ("value", "improved", "simplex", "worley") for s in (3, 4))


@pytest.mark.parametrize("fn", [tx.marble, tx.wood, tx.clouds, tx.granite, tx.bark, tx.grass])
def test_every_tileable_pattern_matches_at_its_edges_as_the_noises_do(fn, noise_edges):
    for seed in (3, 4):
        assert edge_ratio(fn(SHAPE, seed=seed, tileable=True)) <= 1.25 * noise_edges


@pytest.mark.parametrize("kw", [{}, {"turbulence": 0.0, "grain": 1.0},  # the grain alone
                                {"turbulence": 0.0, "grain": 0.0}, {"rings": 14.0}])
def test_tileable_wood_continues_across_its_joins(kw, noise_edges):
    w = tx.wood(SHAPE, seed=5, tileable=True, dtype=np.float64, **kw)
    assert edge_ratio(w) <= 1.25 * noise_edges
    # not a mirror: the left edge does not repeat the column beside the right edge
    assert np.abs(w[:, 0] - w[:, -2]).mean() > 0.5 * np.abs(np.diff(w, axis=1)).mean()
    # the beech preset, tiled (it was 6.2 across the width before)
    img = presets.render({**presets.PRESETS["beech-wood"], "tileable": True, "size": [128, 96]})
    assert edge_ratio(img) <= 1.25 * noise_edges


def test_tileable_wood_rings_are_whole_and_run_along_the_board():
    # without turbulence and grain, a row holds exactly `rings` periods of the ring profile
    w = tx.wood((8, 256), rings=7.0, turbulence=0.0, grain=0.0, tileable=True,
                dtype=np.float64)
    row = w[0] - w[0].mean()
    spectrum = np.abs(np.fft.rfft(row))
    assert int(np.argmax(spectrum[1:])) + 1 == 7


# ----------------------------------------------------------------------------- Worley Fn
def _brute_force(xs, ys, n, metric, *, density=None, jitter=1.0, seed=0, period=None):
    """The n nearest distances by listing every feature point of a wide window of cells
    (points written out from the hashes: cell + 0.5 + jitter (u - 0.5), or Poisson)."""
    px = py = 0 if period is None else period
    pts = []
    for ix in range(-12, 16):
        for iy in range(-12, 16):
            if density is None:
                h = _cell_hash(hash32(seed), 2, ix, iy, 0, 0, px, py, 0, 0)
                pts.append((ix + 0.5 + jitter * (hash32(h ^ 0x68E31DA4) * INV32 - 0.5),
                            iy + 0.5 + jitter * (hash32(h ^ 0xB5297A4D) * INV32 - 0.5)))
            else:
                p, _ = poisson_cell_points(2, ix, iy, 0, 0, px, py, 0, 0, density, seed)
                pts.extend(map(tuple, p))
    p = np.array(pts)
    dx = p[None, :, 0] - xs[:, None]
    dy = p[None, :, 1] - ys[:, None]
    d = {"euclidean": np.hypot(dx, dy), "manhattan": np.abs(dx) + np.abs(dy),
         "chebyshev": np.maximum(np.abs(dx), np.abs(dy)), "euclidean2": dx * dx + dy * dy}
    return np.sort(d[metric], axis=1)[:, :n]


@pytest.mark.parametrize("metric", ["euclidean", "manhattan", "chebyshev", "euclidean2"])
@pytest.mark.parametrize("case", [{}, {"jitter": 0.3}, {"density": 0.7}, {"density": 3.0},
                                  {"period": 3}])
def test_worley_fn_equals_a_brute_force_search(metric, case):
    g = np.linspace(0.0, 4.0, 9)[:-1] + 0.013
    xs, ys = (a.ravel() for a in np.meshgrid(g, g))
    ref = _brute_force(xs, ys, 6, metric, seed=7, **case)
    fs = noise.worley_features(xs, ys, seed=7, metric=metric, order=6, dtype=np.float64, **case)
    assert len(fs) == 7
    for k in range(6):
        np.testing.assert_allclose(fs[k], ref[:, k], rtol=1e-12, atol=1e-12)
        # and output "fN" of worley() is the same column
        np.testing.assert_allclose(noise.worley(xs, ys, seed=7, metric=metric, output=f"f{k + 1}",
                                                dtype=np.float64, **case), ref[:, k],
                                   rtol=1e-12, atol=1e-12)
    # orders 1..3 are those of the F1..F3 kernel, and a high order stays exact
    f1, f2, f3, _ = noise.worley_features(xs, ys, seed=7, metric=metric, dtype=np.float64,
                                          **case)
    np.testing.assert_array_equal(fs[0], f1)
    np.testing.assert_array_equal(fs[2], f3)


def test_worley_high_order_and_bad_orders():
    x = np.array([0.3, 2.7])
    y = np.array([1.1, 0.2])
    ref = _brute_force(x, y, 40, "euclidean", seed=2)
    f40 = noise.worley(x, y, seed=2, output="f40", dtype=np.float64)
    np.testing.assert_allclose(f40, ref[:, 39], rtol=1e-12)
    for bad in (0, 1.5, True, noise.MAX_ORDER + 1):
        with pytest.raises(noise.NoiseError, match="order"):
            noise.worley_features(x, y, order=bad)
    with pytest.raises(noise.NoiseError, match="f1"):
        noise.worley(x, y, output="f0")


def test_worley_fn_grid_and_cli(tmp_path, capsys):
    g = noise.noise_grid((12, 16), kind="worley", output="f5", scale=4, seed=1, tileable=True,
                         dtype=np.float64)
    # 4 cells across the width, 4 * 12 / 16 = 3 down: quarter-cell steps, periods (4, 3)
    X, Y = np.meshgrid(np.arange(16) * 0.25, np.arange(12) * 0.25)
    ref = noise.worley(X, Y, output="f5", seed=1, period=(4, 3), dtype=np.float64)
    np.testing.assert_allclose(g, ref, rtol=1e-12)
    out = tmp_path / "f5.png"
    assert main(["texture", "worley", "--cell", "f5", "--density", "2", "--size", "24x16",
                 "-o", str(out), "--seed", "3"]) == 0
    with Image.open(out) as im:
        assert np.asarray(im).std() > 1
    assert main(["texture", "worley", "--cell", "f0", "-o", str(out)]) == 2
    assert main(["texture", "worley", "--density", "100", "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert "order starts at f1" in err and "density" in err and "Traceback" not in err


# ----------------------------------------------------------------------------- F1 + F2
@pytest.mark.parametrize("metric", ["euclidean", "manhattan", "chebyshev"])
@pytest.mark.parametrize("output", ["f1+f2", "f2", "f3", "f6"])
def test_spread_worley_outputs_are_not_washed_out(metric, output):
    img = presets.render({"kind": "worley", "output": output, "metric": metric, "scale": 12.0,
                          "size": [160, 120], "seed": 5, "colormap": "gray"})
    v = img[..., 0]
    assert (v == 255).mean() < 0.01  # was 58 % (F1 + F2, Euclidean) on the [0, 1] range
    assert v.max() > 200 and np.percentile(v, 50) < 200  # the range is used, not squeezed


def test_worley_range_follows_the_dimension_and_density():
    _, hi2 = noise.worley_range("f1+f2")
    _, hi3 = noise.worley_range("f1+f2", ndim=3)
    _, dense = noise.worley_range("f1+f2", density=4.0)
    assert 1.9 < hi2 < 2.2 and hi3 > hi2 and dense < 0.8 * hi2
    assert noise.worley_range("f1+f2") == (0.0, hi2)  # deterministic


# ----------------------------------------------------------------------------- colours
def test_colour_lists():
    cm = parse_colors("#223344,#88aa55, white")
    np.testing.assert_allclose(cm.positions, [0.0, 0.5, 1.0])
    np.testing.assert_allclose(cm.colors[0], [0x22 / 255, 0x33 / 255, 0x44 / 255])
    np.testing.assert_allclose(cm.colors[2], [1.0, 1.0, 1.0])
    cm = parse_colors("0.0:#223344, 0.8:#8a5, 1:darkolivegreen")
    np.testing.assert_allclose(cm.positions, [0.0, 0.8, 1.0])
    np.testing.assert_allclose(cm.colors[1], [0x88 / 255, 0xAA / 255, 0x55 / 255])
    np.testing.assert_allclose(cm.colors[2] * 255, [85, 107, 47])
    np.testing.assert_allclose(cm(0.4), (cm.colors[0] + cm.colors[1]) / 2)


@pytest.mark.parametrize(("text", "match"), [
    ("#223344", "at least two colours"),
    ("#223344,#12345", r"--colors column 9: colour '#12345'"),
    ("#223344,notacolour", "column 9.*not #rrggbb, #rgb or a colour name"),
    ("0:#000000,#ffffff", "to every colour or to none"),
    ("0:#000000,0.7:#ffffff,0.5:#ff0000,1:#000000", "must not decrease"),
    ("0.1:#000000,1:#ffffff", "run from 0 to 1"),
    ("0:#000000,x:#ffffff", "column 11: stop position 'x' is not a number"),
    ("0:#000000,,1:#ffffff", "column 11: empty colour"),
    ("0:#000000,1.5:#ffffff", "outside"),
])
def test_bad_colour_lists(text, match):
    with pytest.raises(ColormapError, match=match):
        parse_colors(text)


def test_palette_files(tmp_path):
    gpl = tmp_path / "sunset.gpl"
    gpl.write_text("GIMP Palette\nName: sunset\nColumns: 3\n# a comment\n"
                   " 34  51  68\tnight\n255 128 0 orange\n255 255 255\n")
    cm = load_palette(gpl)
    assert cm.name == "sunset"
    np.testing.assert_allclose(cm.colors * 255, [[34, 51, 68], [255, 128, 0], [255, 255, 255]])
    np.testing.assert_allclose(cm.positions, [0.0, 0.5, 1.0])
    toml = tmp_path / "p.toml"
    toml.write_text('stops = [[0.0, "#000000"], [0.25, "red"], [1.0, "#fff"]]\n')
    np.testing.assert_allclose(load_palette(toml).positions, [0.0, 0.25, 1.0])
    toml.write_text('colors = ["#000000", "blue"]\n')
    np.testing.assert_allclose(load_palette(toml).colors[1], [0.0, 0.0, 1.0])
    txt = tmp_path / "p.txt"
    txt.write_text("# position colour\n0 #000000\n0.3: #ff0000\n\n1 white\n")
    np.testing.assert_allclose(load_palette(txt).positions, [0.0, 0.3, 1.0])


@pytest.mark.parametrize(("name", "text", "match"), [
    ("a.gpl", "JASC-PAL\n", r"a.gpl:1:1: a .gpl file starts with"),
    ("a.gpl", "GIMP Palette\n0 0 0\n  12 300 4 x\n", r"a.gpl:3:3: expected 'R G B \[name\]'"),
    ("a.gpl", "GIMP Palette\n0 0 0\n", "at least two colours"),
    ("a.toml", "colors = [\n", "not valid TOML"),
    ("a.toml", "colours = ['#000', '#fff']\n", "holds 'colors"),
    ("a.toml", "stops = [[0.0, '#000'], [1.0, 'nocolour']]\n", r"stops\[1\].*colour name"),
    ("a.txt", "#000000\n  0.5 #ffffff extra\n", r"a.txt:2:3: expected '\[position\] colour'"),
    ("a.txt", "#000000\n#zzzzzz\n", r"a.txt:2:1: colour '#zzzzzz' is not hexadecimal"),
])
def test_bad_palette_files(tmp_path, name, text, match):
    path = tmp_path / name
    path.write_text(text)
    with pytest.raises(ColormapError, match=match):
        load_palette(path)


def test_cli_colors_for_every_kind_with_a_colour_map(tmp_path, capsys):
    out = tmp_path / "c.png"
    for kind in ("simplex", "worley", "marble", "clouds", "julia", "ifs"):
        assert main(["texture", kind, "-o", str(out), "--size", "24x16",
                     "--colors", "0:#000000,1:#ff0000"]) == 0
        with Image.open(out) as im:
            rgb = np.asarray(im).astype(int)
        assert (rgb[..., 1] == 0).all() and (rgb[..., 2] == 0).all() and rgb[..., 0].max() > 0
    # a palette file, saved into the preset and read back
    gpl = tmp_path / "p.gpl"
    gpl.write_text("GIMP Palette\n0 0 255\n255 255 0\n")
    preset = tmp_path / "p.toml"
    assert main(["texture", "marble", "-o", str(out), "--size", "24x16", "--colors", str(gpl),
                 "--save-preset", str(preset)]) == 0
    with Image.open(out) as im:
        first = np.asarray(im)
    assert presets.load_preset(preset)["colormap"] == [[0.0, "#0000ff"], [1.0, "#ffff00"]]
    again = tmp_path / "again.png"
    assert main(["texture", "--preset", str(preset), "-o", str(again)]) == 0
    with Image.open(again) as im:
        np.testing.assert_array_equal(first, np.asarray(im))
    capsys.readouterr()
    for args, match in [
        (["marble", "--colors", "#000,#12"], "--colors column 6"),
        (["marble", "--colors", "#000,#fff", "--colormap", "gray"], "not both"),
        (["marble", "--colors", str(tmp_path / "missing.gpl")], "cannot read palette"),
        (["bush", "--colors", "#000,#fff"], "take no colour map"),
    ]:
        assert main(["texture", *args, "-o", str(out)]) == 2
        err = capsys.readouterr().err
        assert match in err and "Traceback" not in err
    with pytest.raises(presets.PresetError, match="colormap"):
        presets.resolve({"kind": "marble", "colormap": ["#000000"]})
    np.testing.assert_allclose(get_colormap([[0.0, "#000000"], [1.0, "#ffffff"]])(0.5), 0.5)


# ----------------------------------------------------------------------------- marble
def test_marble_turbulence_zero_is_pure_bands(tmp_path):
    w, h, k = 64, 8, 3
    out = tmp_path / "m.png"
    assert main(["texture", "marble", "--turbulence", "0", "--stripes", str(k), "--size",
                 f"{w}x{h}", "-o", str(out), "--seed", "2"]) == 0
    with Image.open(out) as im:
        img = np.asarray(im)
    x = np.linspace(0.0, 1.0, w)
    bands = 0.5 + 0.5 * np.sin(2.0 * np.pi * k * x)  # the reference formula
    ref = apply_colormap(np.broadcast_to(bands, (h, w)), "marble", vmin=0.0, vmax=1.0)
    assert np.abs(img.astype(int) - ref).max() <= 1
    # with turbulence the bands bend
    assert main(["texture", "marble", "--turbulence", "3", "--stripes", str(k), "--size",
                 f"{w}x{h}", "-o", str(out), "--seed", "2"]) == 0
    with Image.open(out) as im:
        assert np.abs(np.asarray(im).astype(int) - ref).max() > 40
    assert main(["texture", "simplex", "--turbulence", "1", "-o", str(out)]) == 2


# ----------------------------------------------------------------------------- grass
def _shader_grass(n, scale):
    """The renderer's grass shader (sylva_grass in render/shaders/textures.glsl), written out
    with improved Perlin noise on the plane, over `scale` units: the luminance."""
    u = np.arange(n) / n * scale
    x, y = np.meshgrid(u, u)

    def p(px, py, z):
        return noise.improved_perlin(px, py, np.full_like(px, z), dtype=np.float64)

    a = p(x * 1.3, y * 1.3, 0.37)
    b = p(x * 5.1 + 17.31, y * 5.1 + 41.73, 0.37)
    blades = p(x * 40.0 + 3.1, y * 43.0 + 7.9, 0.61)
    g = 0.78 + 0.3 * a + 0.18 * b + 0.1 * blades
    c = np.array([0.20, 0.42, 0.10]) * g[..., None]
    c = c + (c * np.array([1.25, 1.1, 0.55]) - c) * np.clip(0.8 * a, 0.0, 1.0)[..., None]
    return c @ [0.2126, 0.7152, 0.0722]


def _evenness(lum, block=32):
    h, w = lum.shape
    blocks = lum[: h // block * block, : w // block * block].reshape(
        h // block, block, w // block, block).mean(axis=(1, 3))
    return lum.std() / lum.mean(), blocks.std() / lum.mean()


def _anisotropy(a):
    """Mean |step| along x over mean |step| along y (7.5 for the old streaky grass)."""
    return np.abs(np.diff(a, axis=1)).mean() / np.abs(np.diff(a, axis=0)).mean()


def test_cpu_grass_is_as_even_as_the_shader():
    n = 256
    shader = _shader_grass(n, 4.0)
    cv_gpu, block_gpu = _evenness(shader)
    for seed in (1, 2):
        img = presets.render({"kind": "grass", "size": [n, n], "seed": seed, "scale": 4.0})
        lum = (img / 255.0) @ [0.2126, 0.7152, 0.0722]
        cv, block = _evenness(lum)
        assert cv < 1.25 * cv_gpu and block < 1.5 * block_gpu
        g = tx.grass((n, n), seed=seed, scale=4.0, dtype=np.float64)
        assert ((g <= 0.0) | (g >= 1.0)).mean() < 1e-3  # (almost) nothing saturates
        # no streaks: as isotropic as the shader (the old grass was 7x finer across than along)
        assert abs(_anisotropy(lum) / _anisotropy(shader) - 1.0) < 0.3
