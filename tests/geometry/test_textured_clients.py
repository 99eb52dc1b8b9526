"""Baked textures in real clients: a textured tree and a textured L-system plant, written with
their images to every format that carries them, opened by the programs people use.

* the Khronos glTF validator: 0 errors and 0 warnings for the textured GLB and ``.gltf``;
* Blender (the ``bpy`` 4.2 wheel, one process for the module): GLB, glTF, OBJ and USD
  imported with image textures connected to the Principled BSDF's colour (and normal and
  roughness, and the leaf's alpha), the images loaded; and the "done when" check: the GLB,
  rendered by Cycles as its diffuse-colour pass (albedo: no light), looks like
  ``sylva render``'s unlit image of the same scene through the same orthographic camera;
* POV-Ray renders the textured ``.pov`` in the textures' colours;
* usd-core's ``UsdValidation`` reports no error on the textured stage.

A missing client skips its test, except under ``SYLVA_REQUIRE_CLIENTS=1`` (``.ci/run``).
"""

from __future__ import annotations

import json
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

from sylva.assets import bake_scene
from sylva.geometry.exchange import write
from sylva.geometry.mesh import Scene

from .test_clients import NODE_DIR, _have_module, _need

TEX = 64  # baked image size: small scenes, small images (the suite's time budget)
VIEW = 96  # rendered image size, both renderers
FORMATS = ("glb", "gltf", "obj", "usda", "pov")


def _lsystem_plant() -> Scene:
    from sylva.cli.derive import load_program
    from sylva.geometry.build import build_mesh
    from sylva.lsystem import derive, render_word
    from sylva.turtle import interpret

    program = load_program("24-seed000-bush-leaves")
    scene = build_mesh(interpret(render_word(program, derive(program, 3)), program))
    scene.name = "bush"
    return scene


def _tree() -> Scene:
    from sylva.tree import Tree

    t = Tree("hazel_shrub", seed=0)
    t.grow(2.0)
    return Scene([t.mesh().mesh], name="hazel")


@pytest.fixture(scope="module")
def scenes() -> dict[str, Scene]:
    return {"plant": _lsystem_plant(), "tree": _tree()}


@pytest.fixture(scope="module")
def baked(scenes) -> dict[str, Scene]:
    return {name: bake_scene(scene, TEX) for name, scene in scenes.items()}


@pytest.fixture(scope="module")
def files(baked, tmp_path_factory) -> dict[tuple[str, str], Path]:
    folder = tmp_path_factory.mktemp("textured")
    out = {}
    for name, scene in baked.items():
        for ext in FORMATS:
            out[name, ext] = folder / f"{name}.{ext}"
            write(scene, out[name, ext])
    return out


def _camera(scene: Scene):
    """An orthographic front view (looking down sylva's -Z) framing ``scene``, as
    ``(sylva Camera, Blender camera location, ortho scale)``."""
    from sylva.render import Camera

    lo, hi = scene.bounds().astype(float)
    c = (lo + hi) / 2.0
    height = float(max(hi[0] - lo[0], hi[1] - lo[1])) * 1.1
    dist = float(hi[2] - lo[2]) + 10.0
    cam = Camera(mode="orthographic", target=tuple(c), yaw=0.0, pitch=0.0, distance=dist,
                 height=height)  # fmt: skip
    # glTF's Y-up becomes Blender's Z-up: (x, y, z) -> (x, -z, y); the eye sits on +Z
    return cam, (c[0], -(c[2] + dist), c[1]), height


def _textured(scene: Scene) -> dict:
    return {m.name: m for mesh in scene.meshes for m in mesh.materials if m.images is not None}


def test_every_writer_writes_the_images_beside_or_inside(files, baked):
    textured = _textured(baked["tree"])
    bark = next(n for n, m in textured.items() if m.texture == "bark")
    leaf = next(n for n, m in textured.items() if m.texture == "leaf")
    folder = files["tree", "obj"].parent
    names = sorted(p.name for p in folder.glob("tree.*.png"))
    assert f"tree.{bark}.color.png" in names and f"tree.{leaf}.alpha.png" in names
    assert f"tree.{leaf}.metallic_roughness.png" in names  # the .gltf's, beside it
    mtl = files["tree", "obj"].with_suffix(".mtl").read_text()
    assert f"map_Kd tree.{bark}.color.png" in mtl and f"map_d tree.{leaf}.alpha.png" in mtl
    assert f"norm tree.{bark}.normal.png" in mtl
    pov = files["tree", "pov"].read_text()
    assert f'image_map {{ png "tree.{leaf}.color.png"' in pov
    glb = files["tree", "glb"].read_bytes()
    # colour, normal and roughness of each textured material, embedded
    assert glb.count(b"\x89PNG\r\n\x1a\n") == 3 * len(textured)


# --------------------------------------------------------------------------- glTF validator
def test_khronos_validator_passes_the_textured_gltf_and_glb(files, baked):
    node = shutil.which("node")
    _need(node is not None and (NODE_DIR / "node_modules" / "gltf-validator").is_dir(),
          "the Khronos glTF validator (node, npm ci in tests/geometry/_node)")
    paths = [str(p) for (_, ext), p in files.items() if ext in ("glb", "gltf")]
    run = subprocess.run([node, str(NODE_DIR / "validate.js"), *paths], capture_output=True,
                         text=True, timeout=180, check=False)  # fmt: skip
    assert run.returncode == 0, run.stderr
    reports = json.loads(run.stdout)
    assert len(reports) == 4
    for report in reports:
        issues = report["issues"]
        bad = [m for m in issues["messages"] if m["severity"] <= 1][:5]
        assert issues["numErrors"] == 0 and issues["numWarnings"] == 0, (report["file"], bad)
        info = report["info"]
        assert info["materialCount"] >= 2 and info["hasTextures"]
        # every image is read and decoded by the validator (embedded or beside)
        resources = [r for r in info["resources"] if r["pointer"].startswith("/images/")]
        name = Path(report["file"]).stem
        assert len(resources) == 3 * len(_textured(baked[name]))
        assert all(r["mimeType"] == "image/png" and r["image"]["width"] == TEX
                   for r in resources)  # fmt: skip


# --------------------------------------------------------------------------- Blender
_BLENDER = r"""
import json, sys
import bpy

def upstream_images(socket, seen=None):
    # the image texture nodes that feed a node socket, through any chain of nodes
    out = []
    for link in socket.links:
        node = link.from_node
        if node.type == "TEX_IMAGE" and node.image is not None:
            img = node.image
            out.append({"name": img.name, "size": list(img.size),
                        "output": link.from_socket.name})
        for inp in node.inputs:
            out += upstream_images(inp)
    return out

def materials():
    found = {}
    for ob in bpy.context.scene.objects:
        if ob.type != "MESH":
            continue
        for mat in ob.data.materials:
            if mat is None or not mat.use_nodes:
                continue
            bsdf = next((n for n in mat.node_tree.nodes if n.type == "BSDF_PRINCIPLED"), None)
            if bsdf is None:
                continue
            found[mat.name] = {s: upstream_images(bsdf.inputs[s])
                               for s in ("Base Color", "Alpha", "Normal", "Roughness")}
    return found

args = json.loads(sys.argv[-1])
report = {}
for path in args["imports"]:
    bpy.ops.wm.read_factory_settings(use_empty=True)
    ext = path.rsplit(".", 1)[1]
    if ext in ("glb", "gltf"):
        bpy.ops.import_scene.gltf(filepath=path)
    elif ext == "obj":
        bpy.ops.wm.obj_import(filepath=path)
    else:
        bpy.ops.wm.usd_import(filepath=path)
    report[path] = materials()

for job in args["renders"]:
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.import_scene.gltf(filepath=job["file"])
    sc = bpy.context.scene
    sc.render.engine = "CYCLES"
    sc.cycles.device = "CPU"
    sc.cycles.samples = 16
    sc.cycles.use_denoising = False
    sc.render.resolution_x = sc.render.resolution_y = job["size"]
    sc.render.film_transparent = True
    sc.view_settings.view_transform = "Standard"
    sc.render.image_settings.color_mode = "RGBA"
    cam = bpy.data.cameras.new("view")
    cam.type = "ORTHO"
    cam.ortho_scale = job["scale"]
    cam.clip_end = 1e4
    ob = bpy.data.objects.new("view", cam)
    sc.collection.objects.link(ob)
    sc.camera = ob
    ob.location = job["eye"]
    ob.rotation_euler = (1.5707963267948966, 0.0, 0.0)  # looking down Blender's +Y
    # the diffuse-colour pass (albedo, as sylva's unlit render) into the composite
    sc.view_layers[0].use_pass_diffuse_color = True
    sc.use_nodes = True
    tree = sc.node_tree
    tree.nodes.clear()
    rl = tree.nodes.new("CompositorNodeRLayers")
    comp = tree.nodes.new("CompositorNodeComposite")
    comp.use_alpha = True
    tree.links.new(rl.outputs["DiffCol"], comp.inputs["Image"])
    tree.links.new(rl.outputs["Alpha"], comp.inputs["Alpha"])
    sc.render.filepath = job["out"]
    bpy.ops.render.render(write_still=True)
sys.stdout.write("\nJSON:" + json.dumps(report))
"""


@pytest.fixture(scope="module")
def blender(files, baked, tmp_path_factory):
    _need(_have_module("bpy"), "Blender as a Python module (pip install 'bpy==4.2.*')")
    folder = tmp_path_factory.mktemp("blender")
    renders = []
    for name, scene in baked.items():
        _, eye, scale = _camera(scene)
        renders.append({"file": str(files[name, "glb"]), "out": str(folder / f"{name}.png"),
                        "eye": list(eye), "scale": scale, "size": VIEW})  # fmt: skip
    job = {"imports": [str(files[n, e]) for n in baked for e in ("glb", "gltf", "obj", "usda")],
           "renders": renders}  # fmt: skip
    run = subprocess.run([sys.executable, "-c", _BLENDER, json.dumps(job)], capture_output=True,
                         text=True, timeout=600, check=False)  # fmt: skip
    assert run.returncode == 0, run.stderr[-3000:]
    report = json.loads(run.stdout.rsplit("\nJSON:", 1)[1])
    images = {r["file"]: np.asarray(Image.open(r["out"]).convert("RGBA")) for r in renders}
    return report, {name: images[str(files[name, "glb"])] for name in baked}


@pytest.mark.parametrize("ext", ("glb", "gltf", "obj", "usda"))
@pytest.mark.parametrize("name", ("plant", "tree"))
def test_blender_connects_the_images_to_the_materials(blender, files, baked, name, ext):
    report, _ = blender
    found = report[str(files[name, ext])]
    textured = _textured(baked[name])
    assert {m.texture for m in textured.values()} == {"bark", "leaf"}
    for mat_name, mat in textured.items():
        # importers may rename a material (OBJ/USD sanitise the dots): match by stem
        key = next(k for k in found if k.replace("_", ".").startswith(mat_name.replace("_", ".")))
        slots = found[key]
        colour = [i for i in slots["Base Color"] if i["output"] == "Color"]
        assert colour, (key, slots)
        assert all(i["size"] == [TEX, TEX] for i in colour)  # loaded, not a missing file
        assert slots["Normal"], (ext, key, "normal map not connected")
        assert slots["Roughness"], (ext, key, "roughness map not connected")
        if mat.images.has_alpha:  # the leaf's outline reaches the alpha
            assert slots["Alpha"], (ext, key, "alpha not connected")


def _sylva_view(scene: Scene) -> np.ndarray:
    from sylva.render import render_array

    cam, _, _ = _camera(scene)
    return render_array(scene, (VIEW, VIEW), cam, lit=False, transparent=True, ground=False,
                        sky=False, msaa=4)  # fmt: skip


@pytest.mark.parametrize("name", ("plant", "tree"))
def test_blender_render_looks_like_sylva_render(blender, scenes, name):
    """The done-when check.  Both images are albedo (sylva unlit, Cycles' diffuse-colour
    pass) through the same orthographic camera, so lighting plays no part.  Tolerances:
    the silhouettes' IoU >= 0.8 (thin twigs of a pixel or two land on either side of a
    pixel edge, Cycles filters them over 1.5 px, and leaves are cut by the alpha test in
    Blender and drawn whole by sylva); the mean colour of the plant's pixels within
    0.05 per channel (sRGB in [0, 1]: measured 0.0003 for the plant, 0.019 for the tree,
    whose per-leaf tints above 1 ``COLOR_0`` clamps), which Blender's white default of an
    unconnected image misses by far; and the mean per-pixel difference at most 0.05 and
    below 0.9 x that of the plain material colours, the untextured export (measured 0.036
    against 0.087 for the plant, 0.035 against 0.045 for the tree: the 64-pixel images,
    mipmapped, blur the finest cracks and veins that sylva draws per pixel)."""
    _, images = blender
    got = images[name].astype(float) / 255.0
    want = _sylva_view(scenes[name]).astype(float) / 255.0
    assert got.shape == want.shape == (VIEW, VIEW, 4)
    a, b = got[:, :, 3] > 0.5, want[:, :, 3] > 0.5
    iou = (a & b).sum() / max((a | b).sum(), 1)
    assert b.sum() > 300 and iou >= 0.8, iou
    both = a & b
    mean_got = got[both][:, :3].mean(axis=0)
    mean_want = want[both][:, :3].mean(axis=0)
    assert np.abs(mean_got - mean_want).max() <= 0.05, (mean_got, mean_want)
    # pixel by pixel: the bark's cracks and the leaves' veins are where sylva draws them,
    # closer than the plain material colours (an export without textures) come
    mad = np.abs(got[both][:, :3] - want[both][:, :3]).mean()
    flat = _flat_view(scenes[name])[both][:, :3]
    mad_flat = np.abs(flat - want[both][:, :3]).mean()
    assert mad <= 0.05 and mad < 0.9 * mad_flat, (mad, mad_flat)


def _flat_view(scene: Scene) -> np.ndarray:
    from sylva.render import render_array

    cam, _, _ = _camera(scene)
    return render_array(scene, (VIEW, VIEW), cam, lit=False, transparent=True, ground=False,
                        sky=False, msaa=4, textures=False).astype(float) / 255.0  # fmt: skip


# --------------------------------------------------------------------------- POV-Ray
def test_povray_renders_the_textured_tree_in_the_textures_colours(files, tmp_path):
    povray = shutil.which("povray")
    _need(povray is not None, "POV-Ray (apt-get install povray)")
    src = files["tree", "pov"]
    run = subprocess.run([povray, f"+I{src.name}", f"+O{tmp_path / 'tree.png'}", "+W120",
                          "+H120", "-A", "-D"], cwd=src.parent, capture_output=True,
                         text=True, timeout=300, check=False)  # fmt: skip
    assert run.returncode == 0, run.stderr[-2000:]
    img = np.asarray(Image.open(tmp_path / "tree.png").convert("RGB")).astype(int)
    plant = np.abs(img - 255).sum(axis=2) > 30  # not the white background
    assert plant.sum() > 200
    r, g, b = (img[plant][:, k].mean() for k in range(3))
    assert g > r + 10 and g > b + 10  # the leaf image's green, not grey or white
    assert np.ptp(img[plant].mean(axis=1)) > 60  # shading and texture, not one flat tone


# --------------------------------------------------------------------------- usd-core
@pytest.mark.parametrize("name", ("plant", "tree"))
def test_usd_validation_passes_the_textured_stage(files, baked, name):
    _need(_have_module("pxr"), "usd-core")
    from pxr import Usd, UsdShade, UsdValidation

    stage = Usd.Stage.Open(str(files[name, "usda"]))
    reg = UsdValidation.ValidationRegistry()
    errors = UsdValidation.ValidationContext(reg.GetOrLoadAllValidators()).Validate(stage)
    assert [(e.GetName(), e.GetMessage()[:200]) for e in errors] == []
    textures = [p for p in stage.Traverse() if p.IsA(UsdShade.Shader)
                and UsdShade.Shader(p).GetIdAttr().Get() == "UsdUVTexture"]  # fmt: skip
    assert len(textures) == 3 * len(_textured(baked[name]))  # colour, normal, roughness
    for p in textures:
        asset = UsdShade.Shader(p).GetInput("file").Get()
        assert (files[name, "usda"].parent / asset.path).is_file()
