"""The one-line API: sylva.grow / sylva.tree / sylva.world render, save, animate and report."""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
import types

import numpy as np
import pytest
import trimesh
from PIL import Image

import sylva
from sylva.errors import SylvaError

BUSH = "rot = 25.7\naxiom = F\nF -> F[+F]F[-F]F"


def _image(path) -> tuple[str, tuple[int, int]]:
    with Image.open(path) as im:
        return im.format, im.size


@pytest.fixture(scope="module")
def plant():
    return sylva.grow(BUSH, 2, seed=1)


def test_grow_takes_text_names_programs_and_paths(tmp_path, plant):
    # ABOP fig. 1.24a: F -> F[+F]F[-F]F has 5^n segments after n steps
    assert plant.stats["segments"] == 25 and plant.stats["steps"] == 2
    path = tmp_path / "bush.lsys"
    path.write_text(BUSH, encoding="utf-8")
    assert sylva.grow(path, 2).stats["segments"] == 25
    assert sylva.grow(str(path), 2).stats["segments"] == 25
    assert sylva.grow(sylva.loads(BUSH), 1).stats["segments"] == 5
    assert sylva.grow("koch-snowflake", 1).stats["modules"] > 4


def test_grow_takes_species_and_tree_files(tmp_path):
    t = sylva.grow("fan_palm", 1.0, leaves=False)
    assert isinstance(t, sylva.grown.TreePlant) and t.stats["name"] == "fan palm"
    from sylva.tree.species import species_text

    text, _ = species_text("fan_palm")
    (tmp_path / "palm.txt").write_text(text, encoding="utf-8")
    mine = sylva.grow(tmp_path / "palm.txt", 1.0, leaves=False)
    assert isinstance(mine, sylva.grown.TreePlant)
    assert mine.stats["height"] == pytest.approx(t.stats["height"])


def test_render_is_an_image_of_the_plant(plant):
    img = plant.render(size=(120, 90))
    assert isinstance(img, Image.Image) and img.size == (120, 90)
    a = np.asarray(img.convert("RGB"), np.int32)
    # a white background (the 2D camera) with dark branches drawn on it
    assert (a == 255).all(axis=2).mean() > 0.5
    assert (a.sum(axis=2) < 600).mean() > 0.01


def test_save_picks_the_format_from_the_extension(tmp_path, plant):
    for ext in ("glb", "obj", "ply", "stl"):
        out = plant.save(tmp_path / f"p.{ext}")
        loaded = trimesh.load(out, force="mesh")
        assert len(loaded.faces) == plant.stats["triangles"], ext
    assert "<svg" in plant.save(tmp_path / "p.svg").read_text(encoding="utf-8")
    assert _image(plant.save(tmp_path / "p.png", size=(64, 48))) == ("PNG", (64, 48))
    assert _image(plant.save(tmp_path / "p.jpg", size=(40, 30))) == ("JPEG", (40, 30))
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(  # no temp files left
        ["p.glb", "p.obj", "p.mtl", "p.ply", "p.stl", "p.svg", "p.png", "p.jpg"])


def test_repr_png_is_a_png(plant):
    data = plant._repr_png_()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    assert "modules=61" in repr(plant)


def test_animate_writes_one_frame_per_step(tmp_path, plant):
    out = plant.animate(tmp_path / "grow.gif", size=(48, 36))
    with Image.open(out) as gif:
        assert gif.n_frames == 3  # axiom, step 1, step 2


def test_tree_and_world(tmp_path):
    oak = sylva.tree("black_oak", age=2.0, seed=1, leaves=False)
    assert oak.stats["stems"][0] == 1 and oak.stats["triangles"] > 0
    assert oak.render(size=(48, 48)).size == (48, 48)
    assert len(trimesh.load(oak.save(tmp_path / "oak.glb"), force="mesh").faces) == \
        oak.stats["triangles"]
    w = sylva.world(seed=3, size=16, chunk=16, plants=False)
    assert w.stats["chunks"] == 1 and w.stats["quads"] > 0
    assert w.render(size=(64, 40), shadows=False).size == (64, 40)
    assert w.save(tmp_path / "w.glb").stat().st_size > 0
    assert w.biome_map().size == (16, 16)
    folder = w.store.directory
    w.close()
    assert not folder.exists()


def test_tree_and_world_stay_subpackages():
    import sylva.tree as tree_pkg
    import sylva.world as world_pkg

    assert sylva.tree is tree_pkg and sylva.world is world_pkg
    assert isinstance(sylva.tree, types.ModuleType) and callable(sylva.tree)
    assert sylva.tree.Tree is not None and sylva.world.WorldConfig is not None


@pytest.mark.parametrize("call, words", [
    (lambda: sylva.grow(BUSH, -1), "steps: expected a whole number >= 0"),
    (lambda: sylva.grow(BUSH, 2.5), "steps: expected a whole number"),
    (lambda: sylva.grow("no_such_thing_here"), "no built-in example"),
    (lambda: sylva.grow(BUSH, 1).render(size=(0, 10)), "positive whole pixel counts"),
    (lambda: sylva.grow(BUSH, 1).render(camera="fisheye"), "camera: expected"),
    (lambda: sylva.grow(BUSH, 1).save("/tmp/x.docx"), "cannot tell the export format"),
    (lambda: sylva.grow(BUSH, 1).animate("/tmp/x.png"), "must end in .gif or .mp4"),
    (lambda: sylva.tree("fan_palm", age=-1), "age: expected a positive"),
    (lambda: sylva.tree("no_such_species"), "unknown species"),
    (lambda: sylva.world(seed="x"), "seed: expected a whole number"),
    (lambda: sylva.world(size=0), "positive whole pixel counts"),
])  # fmt: skip
def test_bad_arguments_are_sylva_errors(call, words):
    with pytest.raises(SylvaError, match=words):
        call()


def test_render_needs_no_display(tmp_path):
    """The API in a process with no X or Wayland display: EGL renders offscreen."""
    env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY")}
    code = textwrap.dedent(f"""
        import os, sylva
        assert "DISPLAY" not in os.environ and "WAYLAND_DISPLAY" not in os.environ
        p = sylva.grow({BUSH!r}, 2)
        p.save({str(tmp_path / "h.png")!r}, size=(50, 40))
        print(p.render(size=(30, 20)).size)
    """)
    r = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True,
                       timeout=600)
    assert r.returncode == 0, r.stderr
    assert r.stdout.strip() == "(30, 20)"
    assert _image(tmp_path / "h.png") == ("PNG", (50, 40))


def test_cli_renders_without_a_display(tmp_path):
    env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY")}
    out = tmp_path / "c.png"
    r = subprocess.run([sys.executable, "-m", "sylva", "render", "koch-snowflake", "-n", "1",
                        "--size", "40x30", "-o", str(out)], env=env, capture_output=True,
                       text=True, timeout=600)  # fmt: skip
    assert r.returncode == 0, r.stderr
    assert _image(out) == ("PNG", (40, 30))


@pytest.mark.parametrize("module", ["sylva", "sylva.grown", "sylva.plant", "sylva._shown"])
def test_doctests(module):
    import doctest
    import importlib

    result = doctest.testmod(importlib.import_module(module), optionflags=doctest.ELLIPSIS)
    assert result.failed == 0 and (result.attempted > 0 or module == "sylva._shown")


def test_render_in_a_worker_thread():
    """As a Dask worker or a notebook's background thread runs it: not on the main thread."""
    from concurrent.futures import ThreadPoolExecutor

    with ThreadPoolExecutor(2) as pool:
        sizes = list(pool.map(lambda n: sylva.grow(BUSH, n).render(size=(40 + n, 30)).size,
                              [1, 2]))
    assert sizes == [(41, 30), (42, 30)]
