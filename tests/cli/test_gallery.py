"""The main job: every built-in example grows and renders; render/animate commands work."""

import numpy as np
from PIL import Image

from sylva.cli import main
from sylva.cli.gallery import make
from sylva.data import examples


def test_gallery_renders_every_example(tmp_path):
    assert make(tmp_path, size=(96, 96), animations=False) == 0
    page = (tmp_path / "index.html").read_text()
    for ex in examples():
        png = tmp_path / f"{ex.name}.png"
        assert png.exists(), ex.name
        a = np.asarray(Image.open(png).convert("L"), dtype=float)
        assert a.std() > 3, f"{ex.name} rendered a blank image"
        assert ex.name in page
    textures = sorted(tmp_path.glob("texture-*.png"))
    assert len(textures) >= 10 and all(t.name in page for t in textures)
    assert "<summary>graph</summary>" in page and "[nodes.out]" in page  # graph beside image


def test_render_command_frames_a_2d_plant(tmp_path):
    out = tmp_path / "plant.png"
    assert main(["render", "abop-1.24a-plant", "-n", "3", "-o", str(out), "--size", "120x160",
                 "--msaa", "0"]) == 0
    a = np.asarray(Image.open(out).convert("L"))
    assert a.shape == (160, 120)
    ink = np.argwhere(a < 200)
    # auto-framing: the drawing spans most of the height and is centred
    assert np.ptp(ink[:, 0]) > 0.7 * 160
    assert abs(ink[:, 1].mean() - 60) < 25


def test_animate_growth_has_a_frame_per_substep(tmp_path, capsys):
    out = tmp_path / "grow.gif"
    assert main(["animate", "abop-1.24d-plant", "-n", "3", "--substeps", "2", "-o", str(out),
                 "--size", "64x64", "--msaa", "0"]) == 0
    assert "(7 frames)" in capsys.readouterr().err  # 3 steps x 2 substeps + the axiom
    with Image.open(out) as im:
        # GIF merges identical frames (the empty axiom); the growth frames all differ
        assert 5 <= im.n_frames <= 7


def test_bad_output_suffix_is_a_clean_error(tmp_path, capsys):
    assert main(["render", "koch-snowflake", "-o", str(tmp_path / "x.bmpx")]) == 2
    assert "must end in" in capsys.readouterr().err
