"""Reference images, one per camera mode: a guard against unnoticed changes in the look.

The analytic checks (silhouettes, shading, shadows) live in the other test modules; these
compare whole images with a tolerance.  To regenerate after an intended change, run
``SYLVA_REGENERATE_REFERENCES=1 python -m pytest tests/render/test_render_reference.py`` and
look at the images before committing them.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from sylva.geometry.mesh import Material, Scene
from sylva.render import Camera, render_array

REFERENCE = Path(__file__).parent / "reference"
SIZE = (96, 72)
VIEWS = {
    "perspective": Camera(mode="perspective", yaw=30, pitch=25),
    "orthographic": Camera(mode="orthographic", yaw=-40, pitch=30),
    "2d": Camera(mode="2d"),
}


def reference_scene(geo) -> Scene:
    bark = Material("bark", color=(0.40, 0.26, 0.14, 1.0), texture="bark", roughness=0.7)
    paint = Material("paint", color=(0.70, 0.15, 0.10, 1.0), roughness=0.4)
    return Scene(
        [
            geo.frustum((0, 0, 0), (0, 2.5, 0), 0.35, 0.25, sections=32, material=bark),
            geo.box((0.6, 0.0, -0.4), (1.4, 0.8, 0.4), paint),
        ]
    )


@pytest.mark.parametrize("mode", list(VIEWS))
def test_matches_reference(geo, mode):
    view = VIEWS[mode]
    scene = reference_scene(geo)
    cam = Camera.auto(scene, mode, yaw=view.yaw, pitch=view.pitch, aspect=SIZE[0] / SIZE[1])
    got = render_array(scene, SIZE, cam, msaa=4, shadow_size=1024)
    path = REFERENCE / f"{mode}.png"
    if os.environ.get("SYLVA_REGENERATE_REFERENCES"):
        REFERENCE.mkdir(exist_ok=True)
        Image.fromarray(got).save(path)
    want = np.asarray(Image.open(path).convert("RGB"))
    assert got.shape == want.shape
    diff = np.abs(got.astype(int) - want.astype(int)).max(axis=-1)
    assert diff.mean() < 2.0
    assert (diff > 32).mean() < 0.01
