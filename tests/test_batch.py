"""``sylva batch``: a plan expanded into items, run on the Dask road, with its manifest."""

import numpy as np
import pyarrow.parquet as pq
import pytest
from PIL import Image

from sylva.batch import parse_plan
from sylva.cli import main
from sylva.errors import SylvaError

PLAN = """
[output]
formats = ["glb"]
size = [64, 48]

[[plant]]
source = "30-abop-2.6-monopodial-tree"
seeds = [1, 2]
steps = [3, 4]
cameras = [{yaw = 30, pitch = 20}]
[plant.sweep]
a0 = [30.0, 45.0]

[[plant]]
source = "koch-snowflake"
seeds = [1]
steps = [1, 2, 3, 4]
"""


def test_plan_expands_into_the_product():
    plan = parse_plan(PLAN)
    assert len(plan.items) == 2 * 2 * 2 + 4 == 12
    first = plan.items[0]
    assert (first.seed, first.steps, first.params, first.cameras) == (1, 3, (("a0", 30.0),),
                                                                       ((30.0, 20.0),))
    assert [i.index for i in plan.items] == list(range(12))


@pytest.mark.parametrize("text, match", [
    ("[[plant]]\nsource = = 'x'", "<plan>:2:10"),
    ("[output]\nsize = [1, 2]\n[[plant]]\nsource = 'x'", "size"),
    ("[[plant]]\nsource = 'x'\nseeds = ['a']", "whole number"),
    ("[[plant]]\nsource = 'x'\ncolour = 1", "unknown key"),
    ("[output]\nformats = ['docx']\n[[plant]]\nsource = 'x'", "unknown format"),
    ("", "at least one"),
])
def test_bad_plans(text, match):
    with pytest.raises(SylvaError, match=match):
        parse_plan(text)


def test_batch_of_12_items(tmp_path, capsys):
    plan = tmp_path / "plan.toml"
    plan.write_text(PLAN)
    out = tmp_path / "out"
    assert main(["batch", str(plan), "-o", str(out), "--workers", "1", "--quiet"]) == 0
    t = pq.read_table(out / "manifest.parquet").to_pylist()
    assert len(t) == 12 + 8  # a GLB per item, a render per camera
    assert sorted({r["item"] for r in t}) == list(range(12))
    for r in t:
        data = (out / r["path"]).read_bytes()
        assert data[:4] == (b"glTF" if r["kind"] == "asset" else b"\x89PNG")
        assert r["modules"] > 0 and r["seconds"] > 0
    glbs = {(r["seed"], r["steps"], r["params"]): (out / r["path"]).read_bytes()
            for r in t if r["format"] == "glb" and r["source"].startswith("30-")}
    # the sweep changes the plant, the seed of a deterministic program does not
    assert glbs[(1, 3, '{"a0": 30.0}')] != glbs[(1, 3, '{"a0": 45.0}')]
    assert glbs[(1, 3, '{"a0": 30.0}')] == glbs[(2, 3, '{"a0": 30.0}')]
    koch = sorted((r["steps"], r["segments"]) for r in t if r["source"] == "koch-snowflake")
    assert [s for _, s in koch] == [3 * 4**k for k in (1, 2, 3, 4)]  # Koch: 3·4^n edges
    img = np.asarray(Image.open(out / next(r["path"] for r in t if r["kind"] == "render")))
    assert img.shape[:2] == (48, 64) and img.std() > 1


LABELS = """
[output]
formats = []
size = [240, 180]

[[plant]]
source = "34-sylva-flowering-herb"
seeds = [7]
cameras = [{yaw = 30, pitch = 20}, {yaw = 120, pitch = 60}]
"""


def test_labels_masks_and_coco(tmp_path):
    import json
    import warnings

    from pycocotools.coco import COCO

    import sylva

    plan = tmp_path / "plan.toml"
    plan.write_text(LABELS)
    out = tmp_path / "out"
    assert main(["batch", str(plan), "-o", str(out), "--workers", "1", "--quiet",
                 "--labels"]) == 0
    rows = pq.read_table(out / "manifest.parquet").to_pylist()
    assert sorted(r["kind"] for r in rows) == ["depth"] * 4 + ["labels", "labels", "mask",
                                                             "mask", "render", "render"]
    leaves = sylva.grow("34-sylva-flowering-herb", seed=7).stats["leaves"]
    assert leaves == 39 and {r["leaves"] for r in rows} == {leaves}
    seen = set()
    for r in (r for r in rows if r["kind"] == "labels"):
        path = out / r["path"]
        mask = np.asarray(Image.open(str(path).replace(".coco.json", ".mask.png")))
        doc = json.loads(path.read_text())
        coco = COCO(str(path))  # the reference reader accepts the file
        assert {c["name"] for c in coco.loadCats(coco.getCatIds())} == {"branch", "leaf",
                                                                         "flower"}
        anns = coco.loadAnns(coco.getAnnIds())
        assert len(anns) == len(np.unique(mask)) - 1 > 20
        for a in anns:
            with warnings.catch_warnings():  # pycocotools' decode and NumPy 2's __array__
                warnings.simplefilter("ignore", DeprecationWarning)
                decoded = coco.annToMask(a)
            np.testing.assert_array_equal(decoded, mask == a["organ"])
        seen |= {a["organ"] for a in doc["annotations"] if a["category_id"] == 2}
    # from the side and from above, every leaf the turtle drew has its own id in a mask
    assert len(seen) == leaves
    _check_depth(out, rows, sylva.grow("34-sylva-flowering-herb", seed=7))


def _check_depth(out, rows, plant):
    """Depth of each render: 0 exactly on the mask's background; elsewhere a view-axis
    distance inside the plant's box as the camera sees it; the 16-bit PNG decodes to the
    float image within half a step of its near..far scale."""
    from sylva.render import Camera
    from sylva.render.camera import box_corners

    for r in (r for r in rows if r["kind"] == "depth" and r["format"] == "npy"):
        z = np.load(out / r["path"])
        png = np.asarray(Image.open(out / r["path"].replace(".npy", ".png"))).astype(float)
        mask = np.asarray(Image.open(out / r["path"].replace(".depth.npy", ".mask.png")))
        assert z.dtype == np.float32 and z.shape == mask.shape == png.shape
        np.testing.assert_array_equal(z > 0, mask > 0)
        np.testing.assert_array_equal(png > 0, mask > 0)
        near, far = r["near"], r["far"]
        cam = Camera.auto(plant.scene.bounds(), "perspective", yaw=r["yaw"], pitch=r["pitch"],
                          aspect=240 / 180)  # the batch's camera
        box = (box_corners(plant.scene.bounds()) - cam.eye) @ -cam.basis()[2]
        drawn = z[z > 0]
        assert near <= box.min() - 1e-6 and box.max() <= far
        assert box.min() - 1e-4 <= drawn.min() and drawn.max() <= box.max() + 1e-4
        assert drawn.max() - drawn.min() > 0.2 * (box.max() - box.min())
        back = near + (png[z > 0] - 1) / 65534 * (far - near)
        np.testing.assert_allclose(back, drawn, atol=0.51 * (far - near) / 65534 + 1e-6)


def test_tree_species_items(tmp_path):
    """A Weber–Penn species in a plan: steps are its age in years, seeds its individuals;
    a sweep (L-system constants) and --labels (organ masks) are refused for it."""
    import sylva
    from sylva.batch import run_batch

    plan = parse_plan('[output]\nformats = ["glb"]\n[[plant]]\nsource = "quaking_aspen"\n'
                      "seeds = [1, 2]\nsteps = [2, 4]\n")
    out = tmp_path / "out"
    assert run_batch(plan, out, workers=1)["items"] == 4
    rows = pq.read_table(out / "manifest.parquet").to_pylist()
    glb = {(r["seed"], r["steps"]): (out / r["path"]).read_bytes() for r in rows}
    assert len(set(glb.values())) == 4 and all(v[:4] == b"glTF" for v in glb.values())
    leaves = {(r["seed"], r["steps"]): r["leaves"] for r in rows}
    assert leaves[(1, 4)] == sylva.tree("quaking_aspen", age=4, seed=1).stats["leaves"]
    assert leaves[(1, 4)] > leaves[(1, 2)] > 0
    bad = parse_plan('[[plant]]\nsource = "quaking_aspen"\n[plant.sweep]\nx = [1.0]\n')
    with pytest.raises(SylvaError, match="tree species has none"):
        run_batch(bad, tmp_path / "bad", workers=1)

