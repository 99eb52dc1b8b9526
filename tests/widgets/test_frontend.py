"""The widget's front end draws in headless Chromium: its ES module (three.js and the
studio's Viewer inlined) mounted on a static page with a fake anywidget model."""

from __future__ import annotations

import functools
import http.server
import threading
from pathlib import Path

import pytest

pytest.importorskip("anywidget")
sync_api = pytest.importorskip("playwright.sync_api")

import sylva  # noqa: E402
from sylva._lines import line_bytes  # noqa: E402
from sylva.widgets import esm, glb_bytes  # noqa: E402
from sylva.widgets._view import segment_bytes  # noqa: E402

CHROMIUM = Path("/usr/bin/chromium")
ARGS = ["--no-sandbox", "--disable-gpu", "--disable-background-networking",
        "--disable-component-update", "--disable-sync", "--no-first-run", "--disable-quic",
        "--use-angle=swiftshader", "--enable-unsafe-swiftshader"]  # WebGL on the CPU

# A fake anywidget model: get/set/on/save_changes/send, as the real one (Backbone) behaves.
PAGE = """<!doctype html><meta charset="utf-8">
<div id="host" style="width: 400px"></div>
<script type="module">
const buffers = {};
for (const name of ["step2", "step1", "tree", "segments", "lines"]) {
  buffers[name] = new DataView(await (await fetch(name + ".glb")).arrayBuffer());
}
const state = { glb: buffers.step2, step: 2, max_steps: 2, camera: "2d", height: 300,
  status: "", error: "", busy: false, draw_ms: 0, frames: 0 };
const handlers = {}, sent = [], saved = [];
const model = {
  get: (k) => state[k],
  set: (k, v) => { state[k] = v; for (const f of handlers["change:" + k] || []) f(); },
  on: (ev, f) => { (handlers[ev] ||= []).push(f); },
  off: () => {},
  save_changes: () => { saved.push({ ...state, glb: null }); },
  send: (m) => { sent.push(m); },
};
window.sylva = { state, buffers, model, sent, saved,
  probe: () => { for (const f of handlers["msg:custom"]) f({ type: "pixels" });
                 return sent[sent.length - 1].value; } };
try {
  const { default: widget } = await import("./widget.mjs");
  window.sylva.cleanup = await widget.render({ model, el: document.getElementById("host") });
  window.ready = true;
} catch (e) { window.ready = String(e.stack || e); }
</script>"""


@pytest.fixture
def page(tmp_path):
    if not CHROMIUM.exists():
        pytest.skip(f"{CHROMIUM} is not installed (apt-get install chromium)")
    (tmp_path / "widget.mjs").write_text(esm(), encoding="utf-8")
    bush = "rot = 25.7\naxiom = F\nF -> F[+F]F[-F]F"
    (tmp_path / "step2.glb").write_bytes(glb_bytes(sylva.grow(bush, 2).scene))
    (tmp_path / "step1.glb").write_bytes(glb_bytes(sylva.grow(bush, 1).scene))
    tree = sylva.tree("fan_palm", age=3.0, leaves=False)
    (tmp_path / "tree.glb").write_bytes(sylva.widgets.view(tree).glb)
    (tmp_path / "segments.glb").write_bytes(segment_bytes(sylva.grow(bush, 2).geometry))
    (tmp_path / "lines.glb").write_bytes(line_bytes(sylva.grow(bush, 2).geometry))
    (tmp_path / "index.html").write_text(PAGE, encoding="utf-8")

    class Quiet(http.server.SimpleHTTPRequestHandler):
        extensions_map = {**http.server.SimpleHTTPRequestHandler.extensions_map,
                          ".mjs": "text/javascript"}

        def log_message(self, *args):
            pass

    server = http.server.ThreadingHTTPServer(
        ("127.0.0.1", 0), functools.partial(Quiet, directory=str(tmp_path)))
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    errors: list[str] = []
    with sync_api.sync_playwright() as pw:
        browser = pw.chromium.launch(executable_path=str(CHROMIUM), args=ARGS, headless=True)
        try:
            pg = browser.new_page(viewport={"width": 480, "height": 420})
            pg.on("pageerror", lambda e: errors.append(str(e)))
            pg.goto(f"http://127.0.0.1:{server.server_address[1]}/index.html")
            pg.wait_for_function("window.ready !== undefined", timeout=120_000)
            assert pg.evaluate("window.ready") is True, pg.evaluate("window.ready")
            yield pg
        finally:
            browser.close()
            server.shutdown()
            server.server_close()
            thread.join(5)
    assert not errors, errors


def test_the_view_draws_the_plant(page):
    page.wait_for_function("window.sylva.state.frames >= 1", timeout=60_000)
    drawn = page.evaluate("window.sylva.probe()")
    # the bush covers part of the canvas, not none of it and not all of it
    assert 0.005 < drawn < 0.6, drawn
    assert page.evaluate("document.querySelector('.sylva-view .bar input').max") == "2"


def test_the_step_slider_asks_python_and_the_new_mesh_is_drawn(page):
    page.wait_for_function("window.sylva.state.frames >= 1", timeout=60_000)
    before = page.evaluate("window.sylva.probe()")
    page.evaluate("""() => { const s = document.querySelector('.sylva-view .bar input');
                             s.value = '1'; s.dispatchEvent(new Event('change')); }""")
    assert page.evaluate("window.sylva.state.step") == 1  # what Python would receive
    assert page.evaluate("window.sylva.saved.some((s) => s.step === 1)")
    # Python answers with the mesh of step 1: fewer branches, fewer drawn pixels
    page.evaluate("window.sylva.model.set('glb', window.sylva.buffers.step1)")
    page.wait_for_function("window.sylva.state.frames >= 2", timeout=60_000)
    after = page.evaluate("window.sylva.probe()")
    assert 0 < after < before, (before, after)


def test_zoom_and_errors_in_place(page):
    page.wait_for_function("window.sylva.state.frames >= 1", timeout=60_000)
    before = page.evaluate("window.sylva.probe()")
    box = page.locator(".sylva-view canvas").bounding_box()
    page.mouse.move(box["x"] + box["width"] / 2, box["y"] + box["height"] / 2)
    page.mouse.wheel(0, -600)  # zoom in: the plant covers more of the canvas
    page.wait_for_timeout(200)
    assert page.evaluate("window.sylva.probe()") > before * 1.3
    page.evaluate("window.sylva.model.set('error', 'angle: expected a value in 0..60')")
    status = page.locator(".sylva-view .status")
    assert status.text_content() == "angle: expected a value in 0..60"
    assert "error" in status.get_attribute("class")


def test_a_tree_plays_in_the_wind(page):
    page.evaluate("window.sylva.model.set('camera', 'perspective')")
    page.evaluate("window.sylva.model.set('glb', window.sylva.buffers.tree)")
    page.wait_for_function("window.sylva.state.frames >= 2", timeout=60_000)
    assert page.locator(".sylva-view .bar button", has_text="wind").is_visible()
    a = page.evaluate("window.sylva.probe()")
    assert a > 0.001
    shots = {page.locator(".sylva-view canvas").screenshot() for _ in range(3)
             if page.wait_for_timeout(300) is None}
    assert len(shots) > 1  # the wind moves the tree between frames


def test_instanced_branches_draw_like_the_mesh(page):
    page.wait_for_function("window.sylva.state.frames >= 1", timeout=60_000)
    meshed = page.evaluate("window.sylva.probe()")
    page.evaluate("window.sylva.model.set('segments', window.sylva.buffers.segments)")
    page.evaluate("window.sylva.model.set('glb', new DataView(new ArrayBuffer(0)))")
    page.wait_for_function("window.sylva.state.frames >= 2", timeout=60_000)
    instanced = page.evaluate("window.sylva.probe()")
    # the same 25 branches from the same camera: about the same pixels (tubes vs cylinders)
    assert instanced == pytest.approx(meshed, rel=0.35), (meshed, instanced)
    assert page.evaluate("window.sylva.state.frames") == 2  # the emptied glb drew nothing


def test_a_preview_draws_lines_and_the_full_frame_replaces_it(page):
    page.wait_for_function("window.sylva.state.frames >= 1", timeout=60_000)
    meshed = page.evaluate("window.sylva.probe()")
    # Python's order: the new trait first, then the others emptied
    page.evaluate("window.sylva.model.set('lines', window.sylva.buffers.lines)")
    page.evaluate("window.sylva.model.set('glb', new DataView(new ArrayBuffer(0)))")
    page.wait_for_function("window.sylva.state.frames >= 2", timeout=60_000)
    assert page.evaluate("window.sylva.state.shown") == "preview"
    lines = page.evaluate("window.sylva.probe()")
    assert 0 < lines < meshed, (meshed, lines)  # one-pixel lines: fewer pixels than tubes
    # the full frame: instanced branches again where the lines were
    page.evaluate("window.sylva.model.set('segments', window.sylva.buffers.segments)")
    page.evaluate("window.sylva.model.set('lines', new DataView(new ArrayBuffer(0)))")
    page.wait_for_function("window.sylva.state.frames >= 3", timeout=60_000)
    assert page.evaluate("window.sylva.state.shown") == "segments"
    assert page.evaluate("window.sylva.probe()") == pytest.approx(meshed, rel=0.35)
    assert page.evaluate("window.sylva.state.frames") == 3  # the emptied lines drew nothing
