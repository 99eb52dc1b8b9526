"""Levels of detail, impostors, billboards and wind vertex data, checked in real clients.

Budgets (LOD1 <= 25 %, LOD2 <= 5 % of LOD0's triangles) on a tree and on L-system plants;
the Khronos validator (0 errors, 0 warnings) on LOD GLBs; Blender (one process for the
module) sees every level as a named node with its triangles; usd-core sees the variant
set; the impostor's alpha matches the plant's silhouette seen from the same side.
"""

from __future__ import annotations

import json
import shutil
import subprocess
import sys

import numpy as np
import pytest

from sylva._impostor import add_impostor, textured_scene
from sylva.errors import SylvaError
from sylva.geometry.exchange.gltf_lod import lod_document, write_lod_glb
from sylva.geometry.lod import check_lods, plant_lods, simplify_segments
from sylva.geometry.mesh import Material, Mesh, Scene
from sylva.plant import grow_geometry
from sylva.turtle import interpret

from .test_clients import NODE_DIR, _have_module, _need


@pytest.fixture(scope="module")
def tree():
    from sylva.tree import Tree

    return Tree("hazel_shrub", seed=0).grow(2.5)


@pytest.fixture(scope="module")
def tree_chain(tree):
    from sylva.tree.lod import tree_lods

    return add_impostor(tree_lods(tree), size=64)


@pytest.fixture(scope="module")
def herb_chain():
    geometry = grow_geometry("34-sylva-flowering-herb")[-1]
    chain = add_impostor(plant_lods(geometry), size=64)
    chain.name = "herb"
    return chain


def _assert_budgets(chain):
    r = chain.ratios()
    assert r[0] == 1.0 and r[1] <= 0.25 and r[2] <= 0.05, r
    # still the plant: the coarse levels keep its height and its leaves (as cards)
    h0 = np.ptp(chain.levels[0].scene.bounds()[:, 1])
    for lv in chain.levels[1:3]:
        assert np.ptp(lv.scene.bounds()[:, 1]) == pytest.approx(h0, rel=0.15)
        assert any("cards" in m.name for m in lv.scene.meshes)


def test_tree_lod_budgets(tree_chain):
    assert [lv.name for lv in tree_chain.levels] == ["LOD0", "LOD1", "LOD2", "LOD3"]
    _assert_budgets(tree_chain)
    assert tree_chain.levels[3].kind == "impostor" and tree_chain.levels[3].n_triangles == 4


@pytest.mark.parametrize("name", ["34-sylva-flowering-herb", "35-sylva-birch"])
def test_lsystem_plant_lod_budgets(name):
    geometry = grow_geometry(name)[-1]
    assert geometry.n_leaves > 0
    _assert_budgets(plant_lods(geometry))


def test_joining_segments_keeps_the_axis_ends():
    g = interpret("FFFFFFFF[+F]", dialect="classic", radius=0.1)
    s = simplify_segments(g, join=2)
    assert s.n_segments == 5  # 8 along the axis → 4, the branch stays
    assert np.allclose(s.seg_start[0], g.seg_start[0]) and np.allclose(s.seg_end[3], g.seg_end[7])
    # the branch still grows from the end of the axis's last segment
    assert s.seg_parent[4] == 3


def test_thin_twigs_are_dropped_with_what_grows_on_them():
    # a thin twig (0.1) carrying thicker shoots (0.4): the shoots go with it
    g = interpret("F(4)[!(0.2)+F!(0.8)[-F]F]F", dialect="abop", thick=1.0)
    assert g.n_segments == 5 and sorted(g.seg_radius[:, 0].round(2)) == [0.1, 0.4, 0.4, 0.5, 0.5]
    s = simplify_segments(g, drop=0.2)
    assert s.n_segments == 2 and np.allclose(s.seg_radius, 0.5)
    assert s.seg_parent.tolist() == [-1, 0]


def test_wind_vertex_data_layout():
    g = interpret("FFF[+FF[-F]]F", dialect="classic", radius=0.1)
    chain = plant_lods(g, levels=1)
    (mesh,) = chain.levels[0].scene.meshes
    w = mesh.attributes["WIND"]
    assert w.shape == (mesh.n_vertices, 4) and w.dtype == np.float32
    base = mesh.vertices[:, 1] < 1e-6
    assert np.all(w[base, 0] == 0) and w[base, 2].max() < 0.3  # the trunk's foot hardly moves
    assert w[:, 2].max() == pytest.approx(1.0, abs=1e-6)  # the farthest tip moves fully
    assert set(np.unique(w[:, 0])) == {0.0, 1.0, 2.0}  # bracket depth = branch level
    assert np.all((w[:, 1] >= 0) & (w[:, 1] < 1)) and np.all(w[:, 3] == 0)
    # one phase per axis: all trunk vertices share it, the branches differ
    assert np.unique(w[w[:, 0] == 0, 1]).size == 1
    assert np.unique(w[:, 1]).size == 3


def test_tree_meshes_carry_wind_for_leaves(tree):
    w = tree.mesh().mesh.attributes["WIND"]
    tm = tree.mesh()
    leaf = tm.vertex_leaf >= 0
    assert w[leaf, 3].max() == pytest.approx(1.0) and np.all(w[~leaf, 3] == 0)
    assert w[leaf, 0].min() >= 1  # a leaf's level is its branch's + 1


def test_bad_lod_settings_name_the_option():
    for bad in (0, 5, "x", 2.5):
        with pytest.raises(SylvaError, match="--lod"):
            check_lods(bad, "--lod")
    g = interpret("F", dialect="classic")
    with pytest.raises(SylvaError, match="coverage"):
        plant_lods(g, coverage=(0.1, 0.5, 0.01))


def test_cli_lod_errors(tmp_path, capsys):
    from sylva.cli import main

    assert main(["export", "34-sylva-flowering-herb", "-o", str(tmp_path / "x.obj"),
                 "--lod", "3"]) != 0  # fmt: skip
    assert "--lod" in capsys.readouterr().err
    assert main(["tree", "hazel_shrub", "--age", "1", "-o", str(tmp_path / "x.glb"),
                 "--lod", "9"]) != 0  # fmt: skip
    assert "--lod" in capsys.readouterr().err
    assert not list(tmp_path.iterdir())


def test_msft_lod_document(herb_chain):
    doc, _ = lod_document(herb_chain)
    names = [n["name"] for n in doc["nodes"]]
    assert names == ["herb_LOD0", "herb_LOD1", "herb_LOD2", "herb_LOD3", "herb"]
    lod0 = doc["nodes"][0]
    assert lod0["extensions"]["MSFT_lod"]["ids"] == [1, 2, 3]
    cov = lod0["extras"]["MSFT_screencoverage"]
    assert len(cov) == 4 and cov == sorted(cov, reverse=True)
    assert doc["extensionsUsed"] == ["MSFT_lod"] and "extensionsRequired" not in doc
    imp = next(m for m in doc["materials"] if m["name"] == "impostor")
    assert imp["alphaMode"] == "MASK" and "normalTexture" in imp
    assert "_WIND" in doc["meshes"][0]["primitives"][0]["attributes"]


# --------------------------------------------------------------------------- impostor
def test_impostor_alpha_matches_the_silhouette(tree_chain, tmp_path):
    from sylva.render import Camera, render_array

    scene = tree_chain.levels[0].scene
    imp = tree_chain.levels[-1]
    alpha = imp.images["impostor"]["color"][..., 3]
    assert 0.05 < (alpha > 127).mean() < 0.95
    b = scene.bounds()
    centre = 0.5 * (b[0] + b[1])
    opts = {"transparent": True, "ground": False, "lit": False, "shadows": False, "msaa": 0}
    for yaw in (0.0, 90.0):  # the two views of the cross
        cam = Camera(mode="orthographic", target=centre, yaw=yaw, pitch=0, distance=50,
                     height=1.3 * float(b[1, 1] - b[0, 1]))
        plant = render_array(scene, (96, 128), cam, **opts)[..., 3] > 127
        quads = render_array(textured_scene(imp, tmp_path), (96, 128), cam, **opts)[..., 3] > 127
        iou = (plant & quads).sum() / (plant | quads).sum()
        assert iou > 0.8, (yaw, iou)


def test_billboard_leaves_face_the_camera():
    from sylva.render import Camera, render_array

    quad = np.array([[-1, 0, -1], [1, 0, -1], [1, 0, 1], [-1, 0, 1]], float)  # flat, normal +Y
    cam = Camera(mode="orthographic", target=np.zeros(3), yaw=30, pitch=0, distance=10, height=4)
    seen = []
    for flag in (False, True):
        mat = Material("leaf", color=(0.2, 0.6, 0.1, 1), double_sided=True, billboard=flag)
        mesh = Mesh(quad, np.array([[0, 2, 1], [0, 3, 2]]), materials=[mat])
        a = render_array(Scene([mesh]), (64, 64), cam, transparent=True, ground=False, msaa=0)
        seen.append((a[..., 3] > 0).mean())
    # edge-on it is invisible; as a billboard it turns to the camera: 2 × 2 of a 4 × 4 view
    assert seen[0] == 0.0 and seen[1] == pytest.approx(0.25, abs=0.02)


# --------------------------------------------------------------------------- clients
@pytest.fixture(scope="module")
def lod_files(tree_chain, herb_chain, tmp_path_factory):
    folder = tmp_path_factory.mktemp("lod")
    out = {"tree": folder / "tree.glb", "herb": folder / "herb.glb",
           "tree_all": folder / "tree_all.glb"}
    write_lod_glb(tree_chain, out["tree"])
    write_lod_glb(herb_chain, out["herb"])
    write_lod_glb(tree_chain, out["tree_all"], nodes="all")
    from sylva.cli import main

    out["bush_textured"] = folder / "bush_textured.glb"  # --lod with --textures
    assert main(["export", "24-seed000-bush-leaves", "-n", "2", "--lod", "3", "--textures",
                 "32", "-o", str(out["bush_textured"])]) == 0  # fmt: skip
    out["world"] = folder / "world.glb"
    _world_info.update(_world_with_impostors(out["world"], folder / "tiles"))
    return out


_world_info: dict = {}


def _world_with_impostors(path, tiles):
    from sylva._impostor import world_impostor
    from sylva.world import World, WorldConfig
    from sylva.world.export import write_world_glb

    tiles.mkdir()
    with World(WorldConfig(seed=11, chunk_size=16), size=(16, 16)).generate(workers=1) as st:
        plants = sum(len(g) for k, g in st.instances().items() if not k.startswith("grass#"))
        info = write_world_glb(st, path, tiles=tiles, impostor=world_impostor(size=32), near=0.0)
    return {**info, "plants": plants}


def test_every_level_of_a_textured_lod_glb_references_its_baked_images(lod_files, tmp_path,
                                                                       capsys):
    data = lod_files["bush_textured"].read_bytes()
    n = int.from_bytes(data[12:16], "little")
    doc = json.loads(data[20:20 + n])
    by_name = {nd["name"]: nd for nd in doc["nodes"]}
    for level in ("LOD0", "LOD1", "LOD2"):
        node = next(nd for name, nd in by_name.items() if name.endswith("_" + level))
        mats = [doc["materials"][p["material"]] for p in doc["meshes"][node["mesh"]]["primitives"]]
        textured = [m for m in mats if "baseColorTexture" in m.get("pbrMetallicRoughness", {})]
        # the bark and the leaves of every level carry their baked images
        assert len(textured) == len(mats) == 2, level
    from sylva.cli import main

    code = main(["export", "34-sylva-flowering-herb", "--lod", "3", "--textures", "32",
                 "-o", str(tmp_path / "h.gltf")])  # fmt: skip
    err = capsys.readouterr().err
    assert code == 2 and "--lod with --textures" in err and ".glb" in err
    assert not (tmp_path / "h.gltf").exists()


def test_world_glb_draws_far_plants_as_impostors(lod_files):
    info = _world_info
    assert info["plants"] > 0 and info["impostor_instances"] == info["plants"]  # near=0: all
    data = lod_files["world"].read_bytes()
    n = int.from_bytes(data[12:16], "little")
    doc = json.loads(data[20:20 + n])
    quads = [m for m in doc["meshes"] if m["name"].endswith("#impostor")]
    assert quads and any(im["name"].startswith("impostor_") for im in doc["images"])


def test_khronos_validator_passes_lod_glbs(lod_files):
    node = shutil.which("node")
    _need(node is not None and (NODE_DIR / "node_modules" / "gltf-validator").is_dir(),
          "the Khronos glTF validator (node, npm ci in tests/geometry/_node)")
    run = subprocess.run([node, str(NODE_DIR / "validate.js"), *map(str, lod_files.values())],
                         capture_output=True, text=True, timeout=180, check=False)
    assert run.returncode == 0, run.stderr
    for report in json.loads(run.stdout):
        issues = report["issues"]
        bad = [m for m in issues["messages"] if m["severity"] <= 1][:5]
        assert issues["numErrors"] == 0 and issues["numWarnings"] == 0, (report["file"], bad)


_BLENDER = r"""
import json, sys
import bpy

out = {}
for path in sys.argv[1:]:
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.import_scene.gltf(filepath=path)
    nodes = {}
    for ob in bpy.data.objects:
        tris = 0
        if ob.type == "MESH":
            ob.data.calc_loop_triangles()
            tris = len(ob.data.loop_triangles)
        nodes[ob.name] = {"triangles": tris, "images": sorted(i.name for i in bpy.data.images)}
    out[path] = nodes
sys.stdout.write("\nJSON:" + json.dumps(out))
"""


def test_blender_sees_every_level_as_a_named_node(lod_files, tree_chain, herb_chain):
    _need(_have_module("bpy"), "Blender as a Python module (pip install 'bpy==4.2.*')")
    paths = [str(lod_files["tree"]), str(lod_files["herb"])]
    run = subprocess.run([sys.executable, "-c", _BLENDER, *paths], capture_output=True,
                         text=True, timeout=600, check=False)  # fmt: skip
    assert run.returncode == 0, run.stderr[-3000:]
    got = json.loads(run.stdout.rsplit("\nJSON:", 1)[1])
    for path, chain in zip(paths, (tree_chain, herb_chain)):
        nodes = got[path]
        name = chain.name
        for i, lv in enumerate(chain.levels):
            assert nodes[f"{name}_LOD{i}"]["triangles"] == lv.n_triangles
        assert {"impostor_color", "impostor_normal"} <= set(nodes[f"{name}_LOD0"]["images"])


def test_usd_core_sees_the_lod_variant_set(tree_chain, tmp_path):
    _need(_have_module("pxr"), "usd-core")
    from pxr import Usd, UsdGeom

    from sylva.geometry.exchange.usd_lod import write_usd_lod

    path = tmp_path / "tree.usda"
    write_usd_lod(tree_chain, path)
    assert (tmp_path / "tree_impostor_color.png").is_file()
    stage = Usd.Stage.Open(str(path))
    vs = stage.GetDefaultPrim().GetVariantSets().GetVariantSet("lod")
    assert vs.GetVariantNames() == ["LOD0", "LOD1", "LOD2", "LOD3"]
    assert vs.GetVariantSelection() == "LOD0"
    for name, lv in zip(vs.GetVariantNames(), tree_chain.levels):
        vs.SetVariantSelection(name)
        meshes = [UsdGeom.Mesh(p) for p in stage.Traverse() if p.IsA(UsdGeom.Mesh)]
        assert sum(len(m.GetFaceVertexCountsAttr().Get()) for m in meshes) == lv.n_triangles
    try:
        from pxr import UsdValidation
    except ImportError:
        return
    reg = UsdValidation.ValidationRegistry()
    errors = UsdValidation.ValidationContext(reg.GetOrLoadAllValidators()).Validate(
        Usd.Stage.Open(str(path)))
    assert [(e.GetName(), e.GetMessage()[:200]) for e in errors] == []


def test_cli_writes_lod_glb_and_tree_glb_carries_wind(tmp_path, tree):
    from sylva.cli import main
    from sylva.geometry.exchange.gltf import gltf_document

    out = tmp_path / "herb.glb"
    assert main(["export", "34-sylva-flowering-herb", "-o", str(out), "--lod", "3"]) == 0
    data = out.read_bytes()
    n = int.from_bytes(data[12:16], "little")
    doc = json.loads(data[20:20 + n])
    assert [nd["name"].rsplit("_", 1)[-1] for nd in doc["nodes"][:3]] == ["LOD0", "LOD1", "LOD2"]
    # a plain tree export carries the wind data too, beside the skinned animation
    tdoc, _ = gltf_document(tree.scene())
    acc = tdoc["meshes"][0]["primitives"][0]["attributes"]["_WIND"]
    assert tdoc["accessors"][acc]["type"] == "VEC4"
