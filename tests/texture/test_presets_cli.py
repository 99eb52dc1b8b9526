"""Recipes, presets (TOML round trip), patterns and the ``sylva texture`` command."""

import ast
import tomllib
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

import sylva.texture as tx
from sylva.cli import main
from sylva.texture import PRESETS, TEXTURE_KINDS, PresetError, load_preset, render, save_preset
from sylva.texture.presets import dumps_toml, resolve


def _small(name):
    r = resolve(name)
    r["size"] = [24, 16]
    if r["kind"] == "ifs":
        r["points"] = 20000
    if r["kind"] == "lsystem":
        r["iterations"] = min(int(r["iterations"]), 3)
    return r


@pytest.mark.parametrize("name", list(PRESETS))
def test_every_preset_renders_and_round_trips(name, tmp_path):
    r = _small(name)
    img = render(r)
    assert img.shape == (16, 24, 3) and img.dtype == np.uint8
    path = save_preset(r, tmp_path / "p.toml")
    assert load_preset(path) == resolve(r)
    np.testing.assert_array_equal(render(load_preset(path)), img)


@pytest.mark.parametrize("kind", list(TEXTURE_KINDS))
def test_every_kind_renders_with_defaults(kind):
    r = {"kind": kind, "size": [20, 12]}
    if kind == "lsystem":
        r.update(axiom="F", rules={"F": "F[+F]F"}, iterations=2, angle=30)
    if kind == "ifs":
        r["points"] = 5000
    assert render(r).shape == (12, 20, 3)


def test_recipes_are_checked():
    with pytest.raises(PresetError, match="unknown parameter"):
        resolve({"kind": "marble", "octavs": 3})
    with pytest.raises(PresetError, match="unknown texture kind"):
        resolve({"kind": "plasma"})
    with pytest.raises(PresetError, match="size"):
        resolve({"kind": "marble", "size": "big"})
    with pytest.raises(PresetError, match="axiom"):
        resolve({"kind": "lsystem", "rules": {}, "iterations": 1, "angle": 3})


def test_toml_writer_is_valid_toml():
    r = {"kind": "lsystem", "axiom": 'F"\\', "angle": -22.5, "tileable": False,
         "palette": ["#000000", "#ffffff"], "size": [3, 4],
         "rules": {"F": [[0.3, "F[+F]"], [0.7, "F[-F]"]], "+": "-"}}
    assert tomllib.loads(dumps_toml(r)) == r


def test_animation_frames_differ():
    frames = tx.render_frames({"kind": "simplex", "size": [16, 16], "speed": 0.3}, 3)
    assert len(frames) == 3 and not np.array_equal(frames[0], frames[2])
    grow = tx.render_frames({"kind": "lsystem", "example": "bush", "size": [16, 16]}, 3)
    assert grow[0].sum() < grow[2].sum()


def test_normal_map_output():
    img = render({"kind": "improved", "size": [16, 16], "octaves": 3, "normal_map": 2.0})
    assert img[..., 2].min() > 128  # normals point out of the surface


@pytest.mark.parametrize("fn", [tx.marble, tx.wood, tx.clouds, tx.granite, tx.bark, tx.grass])
def test_patterns_range_determinism_and_tiling(fn):
    a = fn((40, 56), seed=3, tileable=True)
    assert a.dtype == np.float32 and a.min() >= 0 and a.max() <= 1 and a.std() > 0.01
    np.testing.assert_array_equal(a, fn((40, 56), seed=3, tileable=True))
    d = np.abs(np.diff(a.astype(float), axis=1)).mean()
    assert np.abs(a[:, 0].astype(float) - a[:, -1]).mean() < 2.5 * d + 1e-6


def test_marble_without_turbulence_is_stripes_and_leaf_is_symmetric():
    m = tx.marble((8, 64), turbulence=0.0, stripes=2)
    np.testing.assert_allclose(m[0], m[-1])
    x = np.linspace(0, 1, 64)
    np.testing.assert_allclose(m[0], 0.5 + 0.5 * np.sin(2 * np.pi * 2 * x), atol=1e-6)
    leaf = tx.leaf((64, 33))
    np.testing.assert_allclose(leaf, leaf[:, ::-1], atol=1e-6)
    assert leaf[32, 16] > leaf[32, 10] > 0 and leaf[2, 0] == 0


def test_bark_cracks_run_along_the_branch():
    b = tx.bark((128, 64), stretch=0.0, seed=1).astype(float)
    assert np.abs(np.diff(b, axis=0)).mean() < 0.5 * np.abs(np.diff(b, axis=1)).mean()


def test_cli_png_list_preset_and_errors(tmp_path, capsys):
    out = tmp_path / "m.png"
    assert main(["texture", "marble", "-o", str(out), "--size", "32x20", "--seed", "4",
                 "--tileable", "--octaves", "3", "--save-preset", str(tmp_path / "m.toml")]) == 0
    with Image.open(out) as im:
        assert im.size == (32, 20)
        first = np.asarray(im)
    again = tmp_path / "again.png"
    assert main(["texture", "--preset", str(tmp_path / "m.toml"), "-o", str(again)]) == 0
    with Image.open(again) as im:
        np.testing.assert_array_equal(first, np.asarray(im))
    assert main(["texture", "--list"]) == 0
    listing = capsys.readouterr().out
    assert all(k in listing for k in TEXTURE_KINDS) and "seahorse-valley" in listing
    assert main(["texture", "plasma", "-o", str(out)]) == 2
    assert main(["texture", "marble", "-o", str(out), "--octaves", "0"]) == 2
    assert main(["texture", "--preset", str(tmp_path / "missing.toml"), "-o", str(out)]) == 2
    bad = tmp_path / "bad.toml"
    bad.write_text("kind = \n")
    assert main(["texture", "--preset", str(bad), "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert "not valid TOML" in err and "Traceback" not in err


def test_cli_animation(tmp_path):
    gif = tmp_path / "a.gif"
    assert main(["texture", "simplex", "-o", str(gif), "--size", "16x16", "--frames", "3",
                 "--tileable"]) == 0
    with Image.open(gif) as im:
        assert im.n_frames == 3
    mp4 = tmp_path / "a.mp4"
    assert main(["texture", "julia", "-o", str(mp4), "--size", "17x16", "--frames", "2"]) == 0
    assert mp4.stat().st_size > 0
    assert main(["texture", "simplex", "-o", str(tmp_path / "a.png"), "--frames", "2"]) == 2


def test_public_api_is_curated():
    assert tx.__all__ == sorted(tx.__all__)
    assert all(hasattr(tx, n) for n in tx.__all__)
    src = Path(tx.__file__).parent
    for path in src.glob("*.py"):
        tree = ast.parse(path.read_text())
        for node in ast.walk(tree):
            if isinstance(node, ast.ImportFrom) and node.module:
                assert node.module.split(".")[-1] != "lsystem" or node.level == 0, path
                assert not node.module.startswith("sylva.lsystem"), path
