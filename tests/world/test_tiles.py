"""3D Tiles output: the tileset's structure, the Khronos validator on every tile, and a load
of the whole tileset in headless Chromium with three.js' GLTFLoader (the loader 3D Tiles
renderers for three.js use for glTF content), walking the tree as a tiles loader does.
The coarse tile holds coarser terrain and the larger plants as instanced impostors."""

import json
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

from sylva._impostor import world_impostor
from sylva.cli import main
from sylva.world import World, WorldConfig
from sylva.world.plants import PlantLibrary
from sylva.world.tiles import plan_tiles, write_tileset

NODE_DIR = Path(__file__).parents[1] / "geometry" / "_node"
THREE = Path(__file__).parents[2] / "src" / "sylva" / "studio" / "static" / "vendor" / "three.js"
CHROMIUM = "/usr/bin/chromium"


@pytest.fixture(scope="module")
def tileset(tmp_path_factory):
    root = tmp_path_factory.mktemp("tiles")
    store = World(WorldConfig(seed=21, chunk_size=16), size=(64, 48)).generate(
        root / "w.zarr", workers=1)
    info = write_tileset(store, root / "out", leaf_columns=32, workers=1,
                         impostor=world_impostor(size=32))
    doc = json.loads((root / "out" / "tileset.json").read_text())
    return store, root / "out", doc, info


def _tiles(tile, depth=0):
    yield tile, depth
    for c in tile.get("children", []):
        yield from _tiles(c, depth + 1)


def _glb(path: Path) -> tuple[dict, bytes]:
    data = path.read_bytes()
    n = int.from_bytes(data[12:16], "little")
    return json.loads(data[20 : 20 + n]), data[20 + n + 8 :]


def _floats(doc: dict, binary: bytes, i: int) -> np.ndarray:
    acc = doc["accessors"][i]
    view = doc["bufferViews"][acc["bufferView"]]
    start = view.get("byteOffset", 0) + acc.get("byteOffset", 0)
    a = np.frombuffer(binary, np.float32, acc["count"] * 3, start)
    return a.reshape(-1, 3)


def test_quadtree_plan(tileset):
    store = tileset[0]
    levels, tiles = plan_tiles(store, 32)
    assert levels == 2 and len(tiles) == 1 + 4
    leaves = [t for t in tiles if t["level"] == 1]
    assert sorted((t["x0"], t["z0"], t["x1"], t["z1"]) for t in leaves) == [
        (0, 0, 32, 32), (0, 32, 32, 48), (32, 0, 64, 32), (32, 32, 64, 48)]
    with pytest.raises(Exception, match="multiple of the chunk size"):
        plan_tiles(store, 24)


def test_tileset_structure(tileset):
    store, out, doc, info = tileset
    assert doc["asset"]["version"] == "1.1"
    assert doc["geometricError"] > doc["root"]["geometricError"] > 0
    nodes = list(_tiles(doc["root"]))
    assert len(nodes) == 5 and info["levels"] == 2
    for tile, depth in nodes:
        box = tile["boundingVolume"]["box"]
        assert len(box) == 12
        kids = tile.get("children", [])
        for k in kids:
            assert k["geometricError"] < tile["geometricError"]
        if not kids:
            assert tile["geometricError"] == 0 and depth == 1
        uri = tile["content"]["uri"]
        glb = out / uri
        assert glb.read_bytes()[:4] == b"glTF"
        # the content lies in the box: glTF (x, y, z) is the tileset's (x, -z, y)
        doc_glb, binary = _glb(glb)
        c, h = np.array(box[:3]), np.array([box[3], box[7], box[11]])
        checked = 0
        for i in _world_space_accessors(doc_glb):
            p = _floats(doc_glb, binary, i)
            t = np.stack([p[:, 0], -p[:, 2], p[:, 1]], 1)
            assert np.all(np.abs(t - c) <= h + 1e-3), (uri, box)
            checked += len(p)
        assert checked
        assert "EXT_mesh_gpu_instancing" in doc_glb.get("extensionsUsed", [])


def _instanced(doc) -> dict[str, int]:
    return {n["name"]: doc["accessors"][
        n["extensions"]["EXT_mesh_gpu_instancing"]["attributes"]["TRANSLATION"]]["count"]
        for n in doc["nodes"] if "EXT_mesh_gpu_instancing" in n.get("extensions", {})}


def test_coarse_tile_has_coarser_terrain_and_impostors(tileset):
    """The root (2 columns a sample, geometric error 2): its terrain has fewer triangles
    than the leaves' together, and every plant of at least 2 blocks is one instance of its
    model's impostor (textured, alpha-tested crossed quads); grass and smaller plants are
    left out, the leaves keep every plant."""
    store, out, doc, info = tileset
    root = doc["root"]
    assert root["geometricError"] == 2.0
    coarse, binary = _glb(out / root["content"]["uri"])
    leaves = [_glb(out / k["content"]["uri"])[0] for k in root["children"]]

    def terrain_triangles(d):
        return sum(d["accessors"][p["indices"]]["count"] // 3 for n in d["nodes"]
                   if "mesh" in n and "extensions" not in n
                   for p in d["meshes"][n["mesh"]]["primitives"])  # fmt: skip

    assert 0 < 2 * terrain_triangles(coarse) < sum(terrain_triangles(d) for d in leaves)
    lib = PlantLibrary.for_config(store.config)
    plants = store.plants().column("model").to_pylist()
    sizes = {k: float(np.max(np.ptp(lib.model(k).bounds(), axis=0))) for k in set(plants)}
    want: dict[str, int] = {}
    for k in plants:
        if not k.startswith("grass#") and sizes[k] >= 2.0:
            want[f"{k}#impostor"] = want.get(f"{k}#impostor", 0) + 1
    got = _instanced(coarse)
    assert got == want and sum(want.values()) == info["impostors"] > 10
    assert len(want) == len({k for k in plants if not k.startswith("grass#")
                             and sizes[k] >= 2.0}) < len(set(plants))  # fmt: skip
    for n in coarse["nodes"]:
        if n["name"].endswith("#impostor"):
            (prim,) = coarse["meshes"][n["mesh"]]["primitives"]
            mat = coarse["materials"][prim["material"]]
            assert mat["alphaMode"] == "MASK" and mat["doubleSided"]
            assert "baseColorTexture" in mat["pbrMetallicRoughness"]
            assert coarse["accessors"][prim["indices"]]["count"] == 3 * 4  # two quads
    # the leaves: every plant at full detail, no impostor
    assert sum(sum(_instanced(d).values()) for d in leaves) == store.n_plants
    assert not any(k.endswith("#impostor") for d in leaves for k in _instanced(d))


def _world_space_accessors(doc) -> list[int]:
    """Terrain POSITION accessors and instance TRANSLATION accessors (plant meshes are in
    model space: their instances place them)."""
    out = []
    for n in doc["nodes"]:
        ext = n.get("extensions", {}).get("EXT_mesh_gpu_instancing")
        if ext:
            out.append(ext["attributes"]["TRANSLATION"])
        elif "mesh" in n:
            out += [p["attributes"]["POSITION"] for p in doc["meshes"][n["mesh"]]["primitives"]]
    return out


def test_every_tile_passes_the_khronos_validator(tileset):
    node = shutil.which("node")
    if node is None or not (NODE_DIR / "node_modules" / "gltf-validator").is_dir():
        pytest.skip("the Khronos glTF validator (node, npm ci in tests/geometry/_node)")
    out = tileset[1]
    paths = sorted(out.glob("tiles/*/*.glb"))
    assert len(paths) == 5
    run = subprocess.run([node, str(NODE_DIR / "validate.js"), *map(str, paths)],
                         capture_output=True, text=True, timeout=120, check=False)
    assert run.returncode == 0, run.stderr
    for report in json.loads(run.stdout):
        issues = report["issues"]
        assert issues["numErrors"] == 0 and issues["numWarnings"] == 0, report["file"]
        assert report["info"]["totalTriangleCount"] > 0


_PAGE = """<!doctype html><script type="module">
import * as THREE from "./three.js";
const loader = new THREE.GLTFLoader();
async function walk(tile, depth, out) {
  if (tile.content) {
    const gltf = await loader.loadAsync(tile.content.uri);
    const counts = {};
    let meshes = 0;
    gltf.scene.traverse((o) => {
      if (o.isInstancedMesh) {
        // a node of several primitives is a group of instanced meshes with one count
        const p = o.parent;
        counts[p && p.isGroup && p !== gltf.scene ? p.uuid : o.uuid] = o.count;
      } else if (o.isMesh) meshes += 1;
    });
    out.push({uri: tile.content.uri, depth, meshes,
              instances: Object.values(counts).reduce((a, b) => a + b, 0)});
  }
  for (const c of tile.children || []) await walk(c, depth + 1, out);
}
const ts = await (await fetch("tileset.json")).json();
const out = [];
walk(ts.root, 0, out).then(() => { window.result = out; },
                           (e) => { window.result = String(e); });
</script>"""


def _browse(out: Path, files: dict):
    """Serve ``files`` and the tileset folder at http://tiles.test/, open index.html in
    headless Chromium, and return its ``window.result``."""
    sync_api = pytest.importorskip("playwright.sync_api")
    if not Path(CHROMIUM).exists():
        pytest.skip(f"{CHROMIUM} is not installed")

    def serve(route):
        name = route.request.url.split("://tiles.test/", 1)[1].lstrip("/")
        body = files.get(name)
        if body is None and (out / name).is_file():
            body = (out / name).read_bytes()
        if body is None:
            route.fulfill(status=404, body=b"")
            return
        kind = {"html": "text/html", "js": "text/javascript", "json": "application/json",
                "glb": "model/gltf-binary"}[name.rsplit(".", 1)[1]]
        route.fulfill(status=200, body=body, content_type=kind)

    with sync_api.sync_playwright() as pw:
        browser = pw.chromium.launch(executable_path=CHROMIUM, headless=True,
                                     args=["--no-sandbox", "--disable-gpu"])
        try:
            page = browser.new_page()
            page.route("http://tiles.test/**", serve)
            page.goto("http://tiles.test/index.html")
            page.wait_for_function("window.result !== undefined", timeout=60_000)
            return page.evaluate("window.result")
        finally:
            browser.close()


def test_tileset_loads_in_chromium(tileset):
    store, out, doc, info = tileset
    result = _browse(out, {"index.html": _PAGE.encode(), "three.js": THREE.read_bytes()})
    assert isinstance(result, list), result
    assert len(result) == info["tiles"] == 5
    # the leaves hold every plant of the world, drawn as GPU instances, the root the
    # impostors of the larger ones
    leaves = [r for r in result if r["depth"] == 1]
    assert sum(r["instances"] for r in leaves) == store.n_plants
    (root,) = [r for r in result if r["depth"] == 0]
    assert root["instances"] == info["impostors"] > 0
    assert store.n_plants + info["impostors"] == info["instances"]
    assert all(r["meshes"] >= 1 for r in result)
    assert {r["depth"] for r in result} == {0, 1}


RENDERER = Path(__file__).parent / "_3dtiles"  # 3DTilesRendererJS, see VENDORED.txt

_STREAM = """<!doctype html>
<script type="importmap">{"imports": {"three": "./three.js",
  "three/addons/loaders/GLTFLoader.js": "./gltf-shim.js",
  "three/addons/utils/BufferGeometryUtils.js": "./bgu-shim.js"}}</script>
<script type="module">
import * as THREE from "three";
import { TilesRenderer } from "./3dtr/index.three.js";
const sleep = (ms) => new Promise((r) => setTimeout(r, ms));
const errors = [];
async function view(position, target) {
  const tiles = new TilesRenderer(new URL("tileset.json", location.href).href);
  const camera = new THREE.PerspectiveCamera(60, 4 / 3, 0.1, 100000);
  camera.up.set(0, 0, 1);  // the tileset's frame is Z up
  camera.position.set(...position);
  camera.lookAt(new THREE.Vector3(...target));
  camera.updateMatrixWorld();
  tiles.setCamera(camera);
  tiles.setResolution(camera, 800, 600);
  const instances = {};
  tiles.addEventListener("load-model", ({ scene, tile }) => {
    const counts = {};  // a node of several primitives: one count for its group
    scene.traverse((o) => {
      if (o.isInstancedMesh) {
        const p = o.parent;
        counts[p && p.isGroup && p !== scene ? p.uuid : o.uuid] = o.count;
      }
    });
    instances[tile.content.uri] = Object.values(counts).reduce((a, b) => a + b, 0);
  });
  tiles.addEventListener("load-error", (e) => errors.push(String(e.error) + " " + e.url));
  let rooted = 0;
  for (let i = 0; i < 600; i++) {
    tiles.update();
    await sleep(25);
    const s = tiles.stats;
    // idle only counts a few updates after tileset.json is in (loaded: 4, failed: -1): on
    // a busy machine its fetch can outlast the first ten frames, with nothing queued yet
    if (tiles.rootLoadingState === 4 || tiles.rootLoadingState === -1) rooted++;
    if (i > 10 && rooted > 2 && s.downloading === 0 && s.parsing === 0 && s.queued === 0) break;
  }
  tiles.update();
  const visible = [...tiles.visibleTiles].map((t) => t.content && t.content.uri).sort();
  const out = { visible, instances, failed: tiles.stats.failed };
  tiles.dispose();
  return out;
}
try {
  const [cx, cy] = FRAME;
  const far = await view([cx, cy, 4000], [cx, cy, 0]);
  const near = await view([cx, cy, 70], [cx, cy, 40]);
  window.result = { far, near, errors };
} catch (e) { window.result = String(e.stack || e); }
</script>"""


def test_tileset_streams_in_a_3d_tiles_renderer(tileset):
    """NASA-AMMOS' 3DTilesRendererJS (a three.js 3D Tiles 1.1 loader, vendored) streams the
    tileset in headless Chromium by screen-space error: from 4 km up it shows the root
    alone (coarse terrain and impostors), from 70 m it replaces it by the four leaves."""
    store, out, doc, info = tileset
    box = doc["root"]["boundingVolume"]["box"]
    page = _STREAM.replace("FRAME", json.dumps(box[:2]))
    files = {"index.html": page.encode(), "three.js": THREE.read_bytes(),
             "gltf-shim.js": b'export { GLTFLoader } from "three";',
             "bgu-shim.js": b"export function estimateBytesUsed(g) { let n = 0; "
                            b"for (const k in g.attributes) n += g.attributes[k].array"
                            b".byteLength; return n + (g.index ? g.index.array.byteLength "
                            b": 0); }"}  # fmt: skip
    files |= {f"3dtr/{p.name}": p.read_bytes() for p in RENDERER.glob("*.js")}
    result = _browse(out, files)
    assert isinstance(result, dict), result
    assert result["errors"] == [] and result["far"]["failed"] == result["near"]["failed"] == 0
    root = doc["root"]["content"]["uri"]
    leaves = sorted(k["content"]["uri"] for k in doc["root"]["children"])
    assert result["far"]["visible"] == [root]
    assert result["far"]["instances"] == {root: info["impostors"]}
    assert result["near"]["visible"] == leaves
    assert sum(result["near"]["instances"][u] for u in leaves) == store.n_plants


def test_cli_3dtiles(tmp_path):
    out = tmp_path / "tiles"
    rc = main(["world", "--seed", "3", "--size", "32x32", "--chunk", "16", "-o", str(out),
               "--format", "3dtiles", "--workers", "1", "--quiet"])
    assert rc == 0
    doc = json.loads((out / "tileset.json").read_text())
    assert doc["asset"]["version"] == "1.1" and (out / doc["root"]["content"]["uri"]).is_file()
