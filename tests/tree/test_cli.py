"""``sylva tree``."""

import json

import numpy as np
import pytest
from PIL import Image

from sylva.cli import main


def test_list(capsys):
    assert main(["tree", "--list"]) == 0
    out = capsys.readouterr().out
    for name in ("quaking_aspen", "black_oak", "weeping_willow", "fan_palm", "scots_pine",
                 "hazel_shrub"):
        assert name in out
    assert "Weber & Penn 1995" in out and "palm" in out and "user species folders" in out


def test_contact_sheet(tmp_path, capsys):
    png = tmp_path / "sheet.png"
    assert main(["tree", "--sheet", "-o", str(png), "--only", "sphere_tree"]) == 0
    with Image.open(png) as im:
        w, h = im.size
        assert w >= 4 * 150 * 3 - 1 and h > 200
        px = np.asarray(im.convert("RGB"))
    # trees were drawn: green foliage in the first cell, white elsewhere
    green = (px[..., 1].astype(int) - px[..., 0] > 20) & (px[..., 1] < 200)
    assert green[:, : 3 * 150].sum() > 100 and green[:, 3 * 150:].sum() == 0
    assert "sphere_tree" in capsys.readouterr().out


def test_mesh_and_pov_outputs(tmp_path, capsys):
    glb = tmp_path / "palm.glb"
    assert main(["tree", "fan_palm", "-o", str(glb), "--age", "20", "--seed", "3"]) == 0
    data = glb.read_bytes()
    assert data[:4] == b"glTF"
    n = int(np.frombuffer(data[12:16], np.uint32)[0])
    doc = json.loads(data[20:20 + n])
    assert {m["name"] for m in doc["materials"]} == {"bark.palm", "leaf.palm"}
    assert "height" in capsys.readouterr().out
    pov = tmp_path / "palm.pov"
    assert main(["tree", "fan_palm", "-o", str(pov), "--age", "20", "--no-leaves"]) == 0
    text = pov.read_text()
    assert "mesh2" in text and "camera" in text and "light_source" in text


def test_wind_animation_glb_and_growth_gif(tmp_path):
    glb = tmp_path / "wind.glb"
    assert main(["tree", "fan_palm", "-o", str(glb), "--animate", "wind", "--wind", "2",
                 "--seconds", "0.5", "--fps", "8", "--age", "20"]) == 0
    n = int(np.frombuffer(glb.read_bytes()[12:16], np.uint32)[0])
    doc = json.loads(glb.read_bytes()[20:20 + n])
    times = doc["accessors"][doc["animations"][0]["samplers"][0]["input"]]
    assert times["count"] == 5 and times["max"] == [0.5]
    gif = tmp_path / "grow.gif"
    assert main(["tree", "fan_palm", "-o", str(gif), "--animate", "growth", "--seconds", "0.25",
                 "--fps", "8", "--size", "64x64", "--age", "10"]) == 0
    with Image.open(gif) as im:
        assert im.size == (64, 64) and im.n_frames == 2


@pytest.mark.parametrize(
    ("argv", "words"),
    [
        (["tree", "no_such_tree", "-o", "x.glb"], "unknown species"),
        (["tree", "fan_palm"], "-o OUT"),
        (["tree"], "species name"),
        (["tree", "fan_palm", "-o", "x.gif"], "--animate"),
        (["tree", "fan_palm", "-o", "x.obj", "--animate", "wind"], ".glb, .gif or .mp4"),
        (["tree", "fan_palm", "-o", "x.glb", "--age", "-1"], "positive age"),
    ],
)
def test_errors_exit_2_with_a_message(tmp_path, monkeypatch, capsys, argv, words):
    monkeypatch.chdir(tmp_path)
    assert main(argv) == 2
    assert words in capsys.readouterr().err
