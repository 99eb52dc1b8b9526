"""The animated glTF of a tree plays in three.js (the studio's own bundle, in Chromium)."""

import functools
import http.server
import shutil
import threading
from pathlib import Path

import pytest

from sylva.cli import main

CHROMIUM = Path("/usr/bin/chromium")
VENDOR = Path(__file__).parents[2] / "src" / "sylva" / "studio" / "static" / "vendor"

PAGE = """<!doctype html><meta charset="utf-8"><script type="module">
import * as THREE from "./three.js";
const data = await (await fetch("tree.glb")).arrayBuffer();
new THREE.GLTFLoader().parse(data, "", (gltf) => {
  const clip = gltf.animations[0];
  let skinned = 0, bones = [];
  gltf.scene.traverse((o) => { if (o.isSkinnedMesh) skinned++; if (o.isBone) bones.push(o); });
  const mixer = new THREE.AnimationMixer(gltf.scene);
  mixer.clipAction(clip).play();
  mixer.update(0);
  const tip = bones[bones.length - 1];
  const q0 = tip.quaternion.clone();
  mixer.update(clip.duration * 0.37);
  window.result = {
    clips: gltf.animations.length, duration: clip.duration, tracks: clip.tracks.length,
    skinned, bones: bones.length, moved: 1 - Math.abs(q0.dot(tip.quaternion)),
  };
}, (err) => { window.result = { error: String(err) }; });
</script>"""


@pytest.fixture
def served(tmp_path):
    class Quiet(http.server.SimpleHTTPRequestHandler):
        def log_message(self, *args):  # keep the test output clean
            pass

    handler = functools.partial(Quiet, directory=str(tmp_path))
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), handler)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    yield tmp_path, f"http://127.0.0.1:{server.server_address[1]}"
    server.shutdown()
    server.server_close()
    thread.join(5)


@pytest.mark.skipif(not CHROMIUM.exists(), reason="Debian's chromium is not installed")
def test_wind_animation_plays_in_threejs(served):
    playwright = pytest.importorskip("playwright.sync_api")
    folder, url = served
    assert main(["tree", "quaking_aspen", "--age", "10", "--animate", "wind", "--wind", "2",
                 "--seconds", "1", "--fps", "8", "-o", str(folder / "tree.glb")]) == 0
    shutil.copy(VENDOR / "three.js", folder / "three.js")
    (folder / "index.html").write_text(PAGE)
    with playwright.sync_playwright() as p:
        browser = p.chromium.launch(
            executable_path=str(CHROMIUM),
            args=["--no-sandbox", "--disable-gpu", "--disable-background-networking",
                  "--disable-component-update", "--no-first-run", "--disable-sync"],
        )
        try:
            page = browser.new_page()
            page.goto(f"{url}/index.html")
            page.wait_for_function("window.result !== undefined", timeout=60_000)
            result = page.evaluate("window.result")
        finally:
            browser.close()
    assert "error" not in result, result
    assert result["clips"] == 1 and result["skinned"] >= 1 and result["bones"] > 10
    assert result["tracks"] > 10 and abs(result["duration"] - 1.0) < 0.2
    assert result["moved"] > 1e-6  # the wind really turns the bones in three.js
