"""Baking procedural materials to images (sylva.assets) and the CLI's --textures."""

from __future__ import annotations

import json
import struct

import numpy as np
import pytest

from sylva.assets import bake_material, bake_scene, check_texture_size, leaf_coverage
from sylva.cli import main
from sylva.errors import SylvaError
from sylva.geometry.mesh import Material, MaterialImages, Mesh, Scene, with_images

BARK = Material("bark", (0.30, 0.22, 0.15, 1.0), roughness=0.95, texture="bark")
LEAF = Material("leaf", (0.16, 0.38, 0.08, 1.0), roughness=0.6, texture="leaf",
                double_sided=True)  # fmt: skip


@pytest.mark.parametrize("bad", [0, 7, 300, 8192, "big", "-64", 2.5])
def test_a_bad_texture_size_is_an_error_naming_the_option(bad):
    with pytest.raises(SylvaError, match="--textures: expected a power of two from 8 to 4096"):
        check_texture_size(bad, "--textures")


def test_images_of_the_wrong_shape_are_refused():
    with pytest.raises(SylvaError, match="base_color"):
        MaterialImages(np.zeros((4, 4, 3), np.uint8))
    with pytest.raises(SylvaError, match="normal"):
        MaterialImages(np.zeros((4, 4, 4), np.uint8), normal=np.zeros((8, 8, 3), np.uint8))


def test_with_images_is_the_door_for_impostors():
    rgba = np.zeros((8, 8, 4), np.uint8)
    rgba[2:6, 2:6] = (40, 120, 30, 255)
    normal = np.full((8, 8, 3), (128, 128, 255), np.uint8)
    m = with_images(Material("impostor", (0.2, 0.5, 0.1, 1.0)), rgba, normal)
    assert m.images.has_alpha and m.alpha_cutoff == 0.5 and m.double_sided
    assert m.images.normal is normal or np.array_equal(m.images.normal, normal)
    assert m == Material("impostor", (0.2, 0.5, 0.1, 1.0), alpha_cutoff=0.5, double_sided=True)
    hash(m)  # images are not compared or hashed: materials stay usable as keys


def _seam(img: np.ndarray, axis: int) -> float:
    """Mean step across the wrap-around seam over the largest mean step between other
    neighbouring rows (axis 0) or columns (axis 1): below 1 where the image tiles; an image
    that does not tile joins unrelated pixels there, several times any neighbours' step."""
    a = img.astype(float)
    inner = np.abs(np.diff(a, axis=axis)).mean(axis=1 - axis).max()
    first = np.take(a, 0, axis=axis)
    last = np.take(a, -1, axis=axis)
    return float(np.abs(first - last).mean() / inner)


def test_baked_bark_tiles_around_and_along_the_stem():
    img = bake_material(BARK, 128).images
    grey = img.base_color[:, :, :3].mean(axis=2)
    assert grey.std() > 8  # cracks, not a flat colour
    # the seam is no larger a step than any other pair of neighbouring pixels
    assert _seam(grey, 0) < 1.0 and _seam(grey, 1) < 1.0
    assert _seam(img.normal[:, :, 0], 1) < 1.0 and _seam(img.normal[:, :, 1], 0) < 1.0
    # cracks run along the stem (v, the rows): small steps down a column, large across
    assert np.abs(np.diff(grey, axis=1)).mean() > 2 * np.abs(np.diff(grey, axis=0)).mean()
    # rougher in the cracks than the material's 0.95 (the spec map is 0 there), never smoother
    # than 1 - (1 - 0.95) * 0.25
    r = img.roughness / 255.0
    assert r.min() >= 1 - 0.05 * 0.25 - 0.01 and r.max() <= 1.0


def test_baked_colours_are_the_renderers_colours():
    """The baked leaf is the renderer's sylva_leaf: main vein bright, edges darker."""
    img = bake_material(LEAF, 64).images.base_color[:, :, :3].astype(float).mean(axis=2)
    cols = img.mean(axis=0)
    assert cols[31:33].mean() > 1.2 * np.median(cols[8:24])
    assert cols[2] < cols[20]


def test_the_leaf_alpha_is_the_blade_outline_from_the_meshes():
    from sylva.tree import Tree

    t = Tree("hazel_shrub", seed=0)
    t.grow(2.0)
    mesh = t.mesh().mesh
    leaf = next(m for m in mesh.materials if m.texture == "leaf")
    cov = leaf_coverage([mesh], leaf.name, 64)
    assert cov[0, 0] == cov[0, -1] == cov[-1, 0] == False  # noqa: E712  corners: outside
    assert cov[32, 32]  # the blade's middle
    baked = bake_scene(Scene([mesh]), 64).meshes[0]
    bl = next(m for m in baked.materials if m.name == leaf.name)
    assert np.array_equal(bl.images.base_color[:, :, 3] == 255, cov)
    # every leaf vertex's uv lies inside the outline (the blade is never cut)
    ids = [k for k, m in enumerate(mesh.materials) if m.name == leaf.name]
    tri = np.isin(mesh.triangle_materials(), ids)
    uv = mesh.uvs[np.unique(mesh.indices[tri])]
    px = np.clip((uv * 64).astype(int), 0, 63)
    assert cov[px[:, 1], px[:, 0]].all()


def test_bake_scene_bakes_a_shared_material_once_and_keeps_the_arrays():
    a = Mesh(np.eye(3), np.array([[0, 1, 2]]), uvs=np.zeros((3, 2)), materials=[BARK])
    b = Mesh(np.eye(3) + 1, np.array([[0, 1, 2]]), uvs=np.zeros((3, 2)), materials=[BARK])
    out = bake_scene(Scene([a, b], name="two"), 16)
    assert out.name == "two"
    assert out.meshes[0].materials[0] is out.meshes[1].materials[0]
    assert np.shares_memory(out.meshes[0].vertices, a.vertices)  # not copied
    assert a.materials[0].images is None  # the input is left alone


def _glb_json(path) -> dict:
    data = path.read_bytes()
    n = struct.unpack_from("<I", data, 12)[0]
    return json.loads(data[20:20 + n])


def test_cli_tree_textures(tmp_path, capsys):
    out = tmp_path / "hazel.glb"
    assert main(["tree", "hazel_shrub", "--age", "1.5", "-o", str(out), "--textures", "32"]) == 0
    doc = _glb_json(out)
    assert len(doc["images"]) == 6 and all("bufferView" in i for i in doc["images"])
    leaf = next(m for m in doc["materials"] if m["name"].startswith("leaf"))
    assert leaf["alphaMode"] == "MASK" and leaf["doubleSided"]
    assert leaf["pbrMetallicRoughness"]["baseColorTexture"] == {"index": 3}
    assert "normalTexture" in leaf


def test_cli_export_textures_writes_pngs_beside_a_gltf(tmp_path):
    out = tmp_path / "plant.obj"
    assert main(["export", "24-seed000-bush-leaves", "-n", "2", "-o", str(out),
                 "--textures", "16"]) == 0  # fmt: skip
    names = sorted(p.name for p in tmp_path.iterdir())
    assert "plant.bark.color.png" in names and "plant.leaf.alpha.png" in names
    assert "map_Kd plant.leaf.color.png" in (tmp_path / "plant.mtl").read_text()


@pytest.mark.parametrize(("size", "out", "message"), [
    ("100", "x.glb", "--textures: expected a power of two from 8 to 4096, got 100"),
    ("64", "x.stl", "--textures: STL files carry no images"),
])  # fmt: skip
def test_cli_bad_textures_option(tmp_path, capsys, size, out, message):
    argv = ["export", "24-seed000-bush-leaves", "-n", "1", "-o", str(tmp_path / out),
            "--textures", size]  # fmt: skip
    assert main(argv) != 0
    assert message in capsys.readouterr().err
    assert list(tmp_path.iterdir()) == []  # refused before anything is written


@pytest.mark.parametrize("ext", ["gltf", "obj", "usda", "pov"])
def test_a_failed_textured_export_leaves_no_image_behind(tmp_path, ext):
    from sylva.geometry.exchange import write

    if ext == "usda":
        pytest.importorskip("pxr")
    m = Mesh(np.eye(3), np.array([[0, 1, 2]]), uvs=np.eye(3)[:, :2], materials=[BARK])
    scene = bake_scene(Scene([m]), 8)
    target = tmp_path / f"plant.{ext}"
    target.mkdir()  # a folder where the file should go: the write fails
    with pytest.raises(OSError):
        write(scene, target)
    assert [p.name for p in tmp_path.iterdir()] == [target.name]  # no PNG, no temporary


def test_the_one_line_api_saves_textured(tmp_path):
    import sylva

    plant = sylva.grow("24-seed000-bush-leaves", 2)
    out = plant.save(tmp_path / "bush.glb", textures=16)
    doc = _glb_json(out)
    assert len(doc["images"]) == 6
    with pytest.raises(SylvaError, match="textures: PLY files carry no images"):
        plant.save(tmp_path / "bush.ply", textures=16)


def test_compiled_tangents_equal_the_numpy_reference():
    # the GLB writer's TANGENT comes from a compiled loop; the NumPy formulation is the
    # reference (uv gradients summed at the vertices, Gram-Schmidt, handedness)
    from sylva.geometry.build import build_mesh
    from sylva.geometry.exchange._textures import tangents, tangents_numpy
    from sylva.turtle import interpret

    g = interpret("F[+F[&F]L]F[-FL]/F", dialect="abop", rot=30, thick=0.1)
    for mesh in build_mesh(g, detail=6).meshes:
        a, b = tangents(mesh), tangents_numpy(mesh)
        assert a.shape == b.shape == (mesh.n_vertices, 4)
        np.testing.assert_allclose(a[:, :3], b[:, :3], atol=1e-5)
        assert np.array_equal(a[:, 3], b[:, 3])
    # a triangle without a uv gradient gets a unit tangent orthogonal to its normal
    flat = Mesh(np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], np.float32), np.array([[0, 1, 2]]),
                normals=np.array([[0, 0, 1]] * 3, np.float32), uvs=np.zeros((3, 2), np.float32))
    t = tangents(flat)
    np.testing.assert_allclose(t, tangents_numpy(flat), atol=1e-6)
    np.testing.assert_allclose(np.linalg.norm(t[:, :3], axis=1), 1.0, atol=1e-6)
