"""Every export format, read back by an independent reader (trimesh, meshio, the Khronos
glTF validator, OpenSCAD/POV-Ray text parsed here, the XML parser, pxr)."""

from __future__ import annotations

import io
import json
import re
import shutil
import subprocess
import xml.etree.ElementTree as ET
from pathlib import Path

import meshio
import numpy as np
import pytest
import trimesh

from sylva.errors import SylvaError
from sylva.geometry.build import build_mesh
from sylva.geometry.exchange import WRITERS, ExportError, format_of, usd_available, write
from sylva.geometry.mesh import Material, Mesh, Scene
from sylva.turtle import interpret

from .words import expand

NODE_DIR = Path(__file__).parent / "_node"


@pytest.fixture(scope="module")
def plant_scene() -> Scene:
    word = expand("X", {"X": "F[+X~l][-X]FX", "F": "FF"}, 3) + "[{.-f.+f.+f.-|-f.+f.+f.}]"
    g = interpret(word, dialect="abop", rot=25.7, thick=0.15)
    scene = build_mesh(g, detail=6)
    assert [m.name for m in scene.meshes] == ["branches", "leaves", "polygons"]
    return scene


@pytest.fixture(scope="module")
def coloured_scene() -> Scene:
    word = "F[+;(0,0.7,0)F]F[-;(0,0.7,0)F]+(20);(0,0.7,0)F"
    g = interpret(word, dialect="lsys", rot=35, color=(0.4, 0.2, 0.1))
    return build_mesh(g, detail=5)


@pytest.mark.parametrize("ext", ["glb", "gltf", "obj", "ply", "stl"])
def test_trimesh_reads_back_the_same_triangles(plant_scene, tmp_path, ext):
    path = tmp_path / f"plant.{ext}"
    write(plant_scene, path)
    back = trimesh.load(path, force="mesh", process=False)
    assert len(back.faces) == plant_scene.n_triangles
    # STL and PLY follow the 3D-printing / scanning convention, Z up
    v = np.concatenate([m.vertices for m in plant_scene.meshes]).astype(np.float64)
    if ext in ("ply", "stl"):
        v = np.stack([v[:, 0], -v[:, 2], v[:, 1]], axis=1)
    np.testing.assert_allclose(back.bounds, [v.min(axis=0), v.max(axis=0)], atol=1e-4)
    assert back.bounds[1, 2 if ext in ("ply", "stl") else 1] > 10  # the plant stands up


@pytest.mark.parametrize("ext", ["glb", "obj", "ply", "stl"])
def test_up_option_turns_the_frame(plant_scene, tmp_path, ext):
    height = float(plant_scene.bounds()[1, 1])
    for up, axis in (("y", 1), ("z", 2)):
        path = tmp_path / f"plant-{up}.{ext}"
        write(plant_scene, path, up=up)
        back = trimesh.load(path, force="mesh", process=False)
        assert back.bounds[1, axis] == pytest.approx(height, abs=1e-4)
    with pytest.raises(SylvaError, match="up: expected 'y' or 'z'"):
        write(plant_scene, tmp_path / f"bad.{ext}", up="x")


@pytest.mark.parametrize("ext", ["obj", "ply", "stl"])
def test_meshio_reads_back_the_same_triangles(plant_scene, tmp_path, ext):
    path = tmp_path / f"plant.{ext}"
    write(plant_scene, path)
    back = meshio.read(path)
    assert sum(len(c.data) for c in back.cells if c.type == "triangle") == plant_scene.n_triangles


def test_glb_keeps_materials_normals_uvs_and_colours(coloured_scene, tmp_path):
    path = tmp_path / "t14.glb"
    write(coloured_scene, path)
    back = trimesh.load(path, force="scene", process=False)
    (geom,) = back.geometry.values()
    mesh = coloured_scene.meshes[0]
    assert len(geom.faces) == mesh.n_triangles
    attrs = geom.visual.vertex_attributes
    assert attrs["uv"].shape == (len(geom.vertices), 2)
    cols = np.unique(np.round(attrs["color"][:, :3], 3), axis=0)
    np.testing.assert_allclose(cols, [[0.0, 0.7, 0.0], [0.4, 0.2, 0.1]], atol=1e-6)
    np.testing.assert_allclose(np.linalg.norm(geom.vertex_normals, axis=1), 1.0, atol=1e-5)
    assert geom.visual.material.name == "lsys_stem"


def test_obj_writes_its_material_library(plant_scene, tmp_path):
    path = tmp_path / "plant.obj"
    write(plant_scene, path)
    mtl = (tmp_path / "plant.mtl").read_text()
    assert "newmtl color_0" in mtl and "newmtl leaf" in mtl
    text = path.read_text()
    assert "mtllib plant.mtl" in text and text.count("usemtl") >= 3


def test_ply_carries_colours(coloured_scene, tmp_path):
    path = tmp_path / "t14.ply"
    write(coloured_scene, path)
    back = meshio.read(path)
    # (meshio reads PLY uchar as int8: undo the wrap)
    rgb = np.stack([back.point_data[k] for k in ("red", "green", "blue")], axis=1).astype(int) % 256
    assert {tuple(c) for c in rgb.tolist()} == {(102, 51, 26), (0, 178, 0)}


def _gltf_validator_reports(paths):
    node = shutil.which("node")
    if node is None:
        pytest.skip("node is not installed: the Khronos glTF validator runs in node")
    if not (NODE_DIR / "node_modules" / "gltf-validator").is_dir():
        pytest.fail(f"gltf-validator is not installed: run `npm ci` in {NODE_DIR}")
    run = subprocess.run(
        [node, str(NODE_DIR / "validate.js"), *map(str, paths)],
        capture_output=True, text=True, timeout=120, check=False,
    )  # fmt: skip
    assert run.returncode == 0, run.stderr
    return json.loads(run.stdout)


def test_gltf_validator_finds_no_errors_or_warnings(plant_scene, coloured_scene, tmp_path):
    blocks = build_mesh(interpret("U1U[+xF]", dialect="engine", shrink=0.5))
    files = []
    for name, scene in (("plant", plant_scene), ("t14", coloured_scene), ("blocks", blocks)):
        for ext in ("glb", "gltf"):
            files.append(tmp_path / f"{name}.{ext}")
            write(scene, files[-1])
    for report in _gltf_validator_reports(files):
        issues = report["issues"]
        bad = [m for m in issues["messages"] if m["severity"] <= 1]
        assert issues["numErrors"] == 0 and issues["numWarnings"] == 0, (report["file"], bad)
        assert report["info"]["totalTriangleCount"] > 0


def test_leaves_are_one_face_and_double_sided_in_the_files(plant_scene, tmp_path):
    # no triangle written twice (front and back on the same three points): Blender drops
    # such duplicates and they make STL non-manifold; glTF says doubleSided instead
    write(plant_scene, tmp_path / "plant.stl")
    stl = trimesh.load(tmp_path / "plant.stl", force="mesh")  # merges equal points
    key = np.sort(stl.faces, axis=1)
    assert len(np.unique(key, axis=0)) == len(key) == plant_scene.n_triangles
    write(plant_scene, tmp_path / "plant.gltf")
    doc = json.loads((tmp_path / "plant.gltf").read_text())
    leaf_mats = {p["material"] for m in doc["meshes"] if m["name"] in ("leaves", "polygons")
                 for p in m["primitives"]}  # fmt: skip
    assert leaf_mats and all(doc["materials"][i].get("doubleSided") for i in leaf_mats)


def test_gltf_validator_big_index_buffer(tmp_path):
    # more than 65535 vertices: 32-bit indices
    g = interpret("F" * 3000, dialect="abop", thick=0.1)
    scene = build_mesh(g, detail=24)
    assert scene.meshes[0].n_vertices > 65535
    write(scene, tmp_path / "long.glb")
    (report,) = _gltf_validator_reports([tmp_path / "long.glb"])
    assert report["issues"]["numErrors"] == 0 and report["issues"]["numWarnings"] == 0
    assert report["info"]["totalTriangleCount"] == scene.n_triangles


def _numbers(text):
    return [float(x) for x in re.findall(r"-?\d+(?:\.\d*)?(?:e[-+]?\d+)?", text)]


def test_openscad_polyhedra_are_closed_solids_one_per_colour(plant_scene, tmp_path):
    path = tmp_path / "plant.scad"
    write(plant_scene, path)
    text = path.read_text()
    faces = re.findall(r"faces=\[(.*?)\],\s*convexity", text, re.S)
    points = re.findall(r"points=\[(.*?)\],\s*faces", text, re.S)
    colors = re.findall(r"color\(\[([^\]]*)\]\) polyhedron", text)
    assert len(faces) == len(points) == len(colors) == text.count("polyhedron(") >= 2
    assert len(set(colors)) == len(colors)  # one solid per colour
    for f, p in zip(faces, points):
        idx = np.array(_numbers(f), int).reshape(-1, 3)
        pts = np.array(_numbers(p)).reshape(-1, 3)
        assert idx.min() == 0 and idx.max() == len(pts) - 1
        # closed and oriented: every directed edge once, and its reverse once
        e = np.concatenate([idx[:, [0, 1]], idx[:, [1, 2]], idx[:, [2, 0]]])
        code = e[:, 0] * len(pts) + e[:, 1]
        assert len(np.unique(code)) == len(code)
        assert np.isin(e[:, 1] * len(pts) + e[:, 0], code).all()
        # OpenSCAD's faces run clockwise seen from outside: the volume comes out negative
        t = pts[idx]
        assert np.einsum("ij,ij->i", t[:, 0], np.cross(t[:, 1], t[:, 2])).sum() < 0
    # Z-up: the plant's height (sylva's +Y) is OpenSCAD's +Z
    pts = np.array(_numbers(",".join(points))).reshape(-1, 3)
    # in millimetres: sylva's unit is the metre
    assert pts[:, 2].max() == pytest.approx(1000 * plant_scene.bounds()[1, 1], rel=0.01)


def test_povray_scene_has_a_mesh2_per_material(plant_scene, tmp_path):
    path = tmp_path / "plant.pov"
    write(plant_scene, path)
    text = path.read_text()
    assert text.count("mesh2 {") == sum(len(np.unique(m.material_ids)) for m in plant_scene.meshes)
    counts = [int(c) for c in re.findall(r"face_indices \{ (\d+),", text)]
    assert sum(counts) == plant_scene.n_triangles
    assert "camera" in text and "light_source" in text
    assert text.count("{") == text.count("}")


def test_svg_of_a_2d_system_is_valid_xml_with_every_segment(tmp_path):
    g = interpret(expand("F-F-F-F", {"F": "F-F+F+FF-F-F+F"}, 2), dialect="abop", rot=90)
    path = tmp_path / "koch.svg"
    write(g, path)
    root = ET.parse(path).getroot()
    ns = {"s": "http://www.w3.org/2000/svg"}
    (p,) = root.findall("s:path", ns)
    d = p.get("d")
    assert d.count("L") == g.n_segments and d.count("M") == 1
    vb = [float(x) for x in root.get("viewBox").split()]
    assert vb[2] == pytest.approx(26 * 1.04)  # the island's box plus margins


def test_svg_of_a_scene_paints_every_triangle(coloured_scene, tmp_path):
    path = tmp_path / "t14.svg"
    write(coloured_scene, path)
    root = ET.parse(path).getroot()
    assert len(root.findall("{http://www.w3.org/2000/svg}path")) == coloured_scene.n_triangles


@pytest.mark.skipif(not usd_available(), reason="usd-core is not installed")
@pytest.mark.parametrize("ext", ["usda", "usdc"])
def test_usd_stage_holds_every_triangle(plant_scene, tmp_path, ext):
    from pxr import Usd, UsdGeom

    path = tmp_path / f"plant.{ext}"
    write(plant_scene, path)
    stage = Usd.Stage.Open(str(path))
    assert UsdGeom.GetStageUpAxis(stage) == UsdGeom.Tokens.y
    n = 0
    for prim in stage.Traverse():
        if prim.IsA(UsdGeom.Mesh):
            counts = UsdGeom.Mesh(prim).GetFaceVertexCountsAttr().Get()
            assert set(counts) == {3}
            n += len(counts)
    assert n == plant_scene.n_triangles


def test_writers_accept_file_objects():
    m = Mesh(np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]]), np.array([[0, 1, 2]]),
             materials=[Material("a", (1, 0, 0, 1))])  # fmt: skip
    for fmt in ("glb", "ply", "stl"):
        buf = io.BytesIO()
        write(m, buf, format=fmt)
        back = trimesh.load(io.BytesIO(buf.getvalue()), file_type=fmt, force="mesh")
        assert len(back.faces) == 1
    for fmt in ("gltf", "obj", "scad", "pov", "svg"):
        buf = io.StringIO()
        write(m, buf, format=fmt)
        assert buf.getvalue()


def test_format_comes_from_the_extension():
    assert format_of("a/b/plant.GLB") == "glb"
    assert set(WRITERS) >= {"glb", "gltf", "obj", "ply", "stl", "scad", "pov", "svg", "usd"}
    with pytest.raises(ExportError, match="cannot tell the export format"):
        format_of("plant.fbx")
    with pytest.raises(ExportError, match="needs format="):
        write(Scene(), io.BytesIO())


def test_gltf_colour_is_the_tint_times_the_material_within_range():
    """Tints above one (tree leaves, up to 1.6) fold into baseColorFactor: COLOR_0 stays in
    [0, 1] (ACCESSOR_NON_CLAMPED otherwise) and COLOR_0 x baseColorFactor is unchanged."""
    from sylva.geometry.exchange.gltf import gltf_document

    rng = np.random.default_rng(1)
    v = rng.uniform(-1, 1, (30, 3))
    tint = np.concatenate([rng.uniform(0.3, 1.6, (30, 3)), np.ones((30, 1))], axis=1)
    mats = [Material("bark", (0.4, 0.26, 0.13, 1.0)), Material("leaf", (0.16, 0.42, 0.1, 1.0))]
    mesh = Mesh(v, np.arange(30).reshape(10, 3), colors=tint,
                material_ids=np.repeat([0, 1], 5), materials=mats)  # fmt: skip
    doc, blob = gltf_document(mesh)
    (prim0, prim1) = doc["meshes"][0]["primitives"]
    acc = doc["accessors"][prim0["attributes"]["COLOR_0"]]
    view = doc["bufferViews"][acc["bufferView"]]
    col = np.frombuffer(blob, np.float32, 4 * acc["count"], view["byteOffset"]).reshape(-1, 4)
    assert col.min() >= 0.0 and col.max() <= 1.0 and tint.max() > 1.5
    for prim, rows in ((prim0, slice(0, 15)), (prim1, slice(15, 30))):
        base = np.array(doc["materials"][prim["material"]]["pbrMetallicRoughness"][
            "baseColorFactor"])
        mat = mats[0 if rows.start == 0 else 1]
        np.testing.assert_allclose(col[rows, :3] * base[:3],
                                   np.clip(tint[rows, :3] * mat.color[:3], 0, 1), atol=1e-6)
