"""The widget's Python side: meshes as binary glTF, newest-first re-derivation, errors in
place (no kernel needed: ipywidgets works without one)."""

from __future__ import annotations

import threading

import pytest
import trimesh

pytest.importorskip("anywidget")

import sylva  # noqa: E402
from sylva.errors import SylvaError  # noqa: E402
from sylva.geometry.mesh import Scene  # noqa: E402
from sylva.widgets import PlantView, explore, glb_bytes, slider_range, view  # noqa: E402

BUSH = "rot = 25.7\naxiom = F\nF -> F[+F]F[-F]F"


def _faces(data: bytes) -> int:
    import io

    return len(trimesh.load(io.BytesIO(data), file_type="glb", force="mesh").faces)


def test_a_plant_view_sends_its_mesh_and_steps_back():
    plant = sylva.grow(BUSH, 2)
    v = plant.show()
    assert (v.step, v.max_steps, v.camera) == (2, 2, "2d")
    assert _faces(v.glb) == plant.stats["triangles"]
    v.step = 1  # what the front end's slider does
    assert v.wait()
    assert v.error == "" and _faces(v.glb) == sylva.grow(BUSH, 1).stats["triangles"]
    v.step = 7
    assert v.error == "step: expected 0..2, got 7" and v.step == 1


def test_changes_are_coalesced_newest_first():
    gate, started = threading.Event(), threading.Event()
    built = []

    def build(step, **params):
        built.append((step, params.get("k")))
        started.set()
        gate.wait(10)
        return sylva.grow(BUSH, step).scene

    v = PlantView(build, step=0, max_steps=3)  # asks for step 0 at once
    assert started.wait(10)  # ... which is now being built
    for k in range(20):
        v.request(k % 4, k=k)
    gate.set()
    assert v.wait()
    # the first request (in flight) and the newest one; the 18 between were skipped
    assert built == [(0, None), (3, 19)]
    assert v.step == 3 and _faces(v.glb) == sylva.grow(BUSH, 3).stats["triangles"]


def test_explore_sliders_follow_the_globals():
    ex = explore("angle = 30\nn = 2\naxiom = F\nF -> F[+(angle)F]F", 2)
    assert ex.wait()
    assert sorted(ex.sliders) == ["angle", "n", "steps"]
    assert (ex.sliders["angle"].min, ex.sliders["angle"].max) == (0.0, 60.0)
    first = ex.view.glb
    ex.set(angle=45.0)
    assert ex.wait() and ex.view.error == "" and ex.view.glb != first
    assert ex.program_with(ex.values()).constants["angle"] == 45.0
    ex.set(steps=3)
    assert ex.wait() and ex.view.step == 3
    assert _faces(ex.view.glb) == sylva.grow(ex.program_with(ex.values()), 3).stats["triangles"]


def test_a_refused_change_keeps_the_mesh_and_says_why():
    ex = explore("axiom = F\nF -> FFFFFFFFFF", 2, max_steps=12, limit=50_000)
    assert ex.wait()
    shown = ex.view.glb
    ex.set(steps=9)
    assert ex.wait()
    assert "50,000 modules (the module limit)" in ex.view.error
    assert "50,000 modules (the module limit)" in ex.message.value
    assert ex.view.glb == shown and ex.view.step == 2
    ex.set(steps=3)
    assert ex.wait() and ex.view.error == "" and ex.message.value == ""


@pytest.mark.parametrize("call, words", [
    (lambda ex: ex.set(angle=1000), r"angle: expected a value in 0\.\.60, got 1000"),
    (lambda ex: ex.set(angle="wide"), "angle: expected a number"),
    (lambda ex: ex.set(angle=float("nan")), "angle: expected a number"),
    (lambda ex: ex.set(steps=2.5), "steps: expected a whole number"),
    (lambda ex: ex.set(size=3), "no slider 'size'"),
])  # fmt: skip
def test_bad_slider_values_are_refused(call, words):
    ex = explore("angle = 30\naxiom = F\nF -> F[+(angle)F]F", 1)
    with pytest.raises(SylvaError, match=words):
        call(ex)


@pytest.mark.parametrize("call, words", [
    (lambda: explore(BUSH, -1), "steps: expected a whole number >= 0"),
    (lambda: explore(BUSH, 4, max_steps=2), "max_steps: expected at least steps"),
    (lambda: explore(42), "explore: expected a Program"),
    (lambda: view(object()), "view: expected a plant"),
    (lambda: view(sylva.grow(BUSH, 1), camera="fisheye"), "camera: expected"),
    (lambda: view(sylva.grow(BUSH, 1), height=5), "height: expected"),
])  # fmt: skip
def test_bad_arguments_are_sylva_errors(call, words):
    with pytest.raises(SylvaError, match=words):
        call()


def test_trees_worlds_and_scenes_are_shown():
    tree = sylva.tree("fan_palm", age=3.0, leaves=False)
    tv = tree.show()
    assert tv.glb[:4] == b"glTF" and tv.max_steps == 0
    assert len(trimesh.load(__import__("io").BytesIO(tv.glb), file_type="glb").geometry) >= 1
    still = view(tree, wind=False)
    assert _faces(still.glb) == tree.stats["triangles"]
    plant = sylva.grow(BUSH, 1)
    assert _faces(view(plant.scene).glb) == _faces(glb_bytes(Scene(plant.scene.meshes)))


def test_slider_ranges_are_round():
    assert slider_range(30) == (0.0, 60.0, 0.5)
    assert slider_range(-2) == (-4.0, 4.0, 0.05)
    assert slider_range(0) == (-1.0, 1.0, 0.01)


def test_big_plants_go_as_instanced_branches():
    import numpy as np

    plant = sylva.grow(BUSH, 2)
    v = view(plant, instanced=True)
    assert v.glb == b"" and len(v.segments) == 11 * 4 * plant.stats["segments"]
    rows = np.frombuffer(v.segments, np.float32).reshape(-1, 11)
    assert np.allclose(rows[:, 0:3], plant.geometry.seg_start, atol=1e-5)
    assert np.allclose(rows[:, 3:6], plant.geometry.seg_end, atol=1e-5)
    v.step = 1
    assert v.wait() and len(v.segments) == 11 * 4 * 5 and v.glb == b""
    assert "5 branches (instanced)" in v.status
    assert view(plant).segments == b""  # 25 branches: the mesh, as the studio draws it


def test_a_dragged_slider_sends_lines_then_the_full_frame():
    import numpy as np

    program = "angle = 30\naxiom = F\nF -> F[+(angle)F]F[-(angle)F]F"
    ex = explore(program, 2, max_steps=3)
    assert ex.wait()
    ex.view.instanced = True  # a big plant's way, on a small one
    ex.view.request(2)
    assert ex.wait()
    assert ex.view.segments and not ex.view.lines
    sent = []
    ex.view.observe(lambda ch: sent.append((ch["name"], len(ch["new"]))),
                    names=["lines", "segments"])
    ex.view.settle = 0.2
    ex.set(angle=40)  # a global's slider moved: the preview, then the full frame
    assert ex.wait() and ex.view.error == ""
    n = 25
    assert [k for k, size in sent if size] == ["lines", "segments"]
    assert ("lines", 32 * n) in sent and ("segments", 44 * n) in sent
    assert ex.view.lines == b"" and len(ex.view.segments) == 44 * n
    assert "(instanced)" in ex.view.status and not ex.view.busy
    # the full frame is the preview's plant at the new angle
    rows = np.frombuffer(ex.view.segments, np.float32).reshape(-1, 11)
    want = sylva.grow(program.replace("30", "40"), 2).geometry
    assert np.allclose(rows[:, 3:6], want.seg_end, atol=1e-5)
    # the steps slider asks for the full frame at once
    sent.clear()
    ex.set(steps=3)
    assert ex.wait() and [k for k, size in sent if size] == ["segments"]


@pytest.mark.parametrize("module", ["sylva.widgets._view", "sylva.widgets._explore"])
def test_doctests(module):
    import doctest
    import importlib

    result = doctest.testmod(importlib.import_module(module))
    assert result.failed == 0 and result.attempted > 0
