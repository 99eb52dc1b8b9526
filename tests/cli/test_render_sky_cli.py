"""``sylva render --sky``: a sky behind the plant instead of the plain background."""

import numpy as np
from PIL import Image

from sylva.cli import main


def _render(tmp_path, name, *extra):
    out = tmp_path / name
    args = ["render", "abop-1.25-bush", "-n", "2", "-o", str(out), "--size", "96x64",
            "--msaa", "0", "--pitch", "0", *extra]  # fmt: skip
    assert main(args) == 0
    return Image.open(out)


def test_render_sky_flag(tmp_path):
    plain = np.asarray(_render(tmp_path, "plain.png").convert("RGB")).astype(int)
    sky = np.asarray(_render(tmp_path, "sky.png", "--sky").convert("RGB")).astype(int)
    assert plain.shape == sky.shape == (64, 96, 3)
    assert tuple(plain[0, 0]) == (255, 255, 255)
    r, g, b = sky[0, 0]
    assert b > r + 30 and b > 150  # sky blue at the top
    # the plant is drawn over it: the images differ in the middle as well as at the edges
    assert np.abs(sky - plain).max(axis=-1).mean() > 10


def test_render_sky_flag_is_off_in_transparent_images(tmp_path):
    img = _render(tmp_path, "t.png", "--sky", "--transparent")
    assert img.mode == "RGBA" and img.getpixel((0, 0))[3] == 0
