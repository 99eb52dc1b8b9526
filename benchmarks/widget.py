"""Notebook latency: from a slider change to the new mesh in the widget, ~100k modules.

    python benchmarks/widget.py [--changes 20] [--steps 9] [--browser]

A program with a global ``angle`` (ABOP fig. 1.24d with the angle as a variable) is
derived to ``--steps`` (9: 126,912 modules, 38,342 branches, 2.2 M triangles); each of
``--changes`` slider changes moves the angle and the figures are medians over them, after
one warm-up change (compilation excluded):

* derive — the derivation, its render word and the turtle (in the widget's worker);
* serialise (lines) — the preview's bytes: the branches as lines (:mod:`sylva._lines`,
  32 bytes a branch), what the widget sends while a slider is dragged;
* serialise — the full frame's bytes: the branches as instanced rows (what it sends
  for a plant this big once the slider rests), and for comparison the studio's way, a
  mesh (``mesh``) as a binary glTF (``glb``);
* widget (preview) — ``Explorer.set(angle=…)`` until the preview's lines are in the
  widget's trait, end to end through its background worker (the kernel is free
  meanwhile); widget (full) — until the instanced rows replace them (after the
  :attr:`PlantView.settle` rest of 0.3 s with no newer change);
* with ``--browser``: draw (preview) and draw (full) — the front end in headless Chromium
  (Debian's, SwiftShader WebGL on the CPU) from receiving the bytes to the new frame on
  the canvas (a pixel is read back, so the frame is really drawn, not just queued).

The transfer between kernel and browser is a binary comm buffer of the size printed; on a
local Jupyter server it costs about that many bytes of memory copies.
"""

from __future__ import annotations

import argparse
import statistics
import threading
import time

PROGRAM = "angle = 20\naxiom = X\nX -> F[+(angle)X]F[-(angle)X]+(angle)X\nF -> FF"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--changes", type=int, default=20)
    ap.add_argument("--steps", type=int, default=9)
    ap.add_argument("--browser", action="store_true", help="also time the draw in Chromium")
    args = ap.parse_args()

    from sylva.geometry.build import build_mesh
    from sylva.plant import grow_geometry
    from sylva.widgets import explore, glb_bytes

    ex = explore(PROGRAM, args.steps, max_steps=args.steps)
    ex.wait(600)
    previewed, seen = threading.Event(), {}

    def on_lines(change):
        if change["new"]:
            seen.update(ex.view.timings, at=time.perf_counter(), lines=change["new"])
            previewed.set()

    ex.view.observe(on_lines, names="lines")
    angles = [20.5 + 0.5 * k for k in range(args.changes + 1)]  # 20 is the start
    rows = {"derive": [], "serialise (lines)": [], "serialise": [], "widget (preview)": [],
            "widget (full)": [], "mesh (glb)": [], "serialise (glb)": []}
    for i, a in enumerate(angles):
        previewed.clear()
        t0 = time.perf_counter()
        ex.set(angle=a)
        if not previewed.wait(600):
            raise SystemExit("no preview came")
        ex.wait(600)
        t1 = time.perf_counter()
        if ex.view.error:
            raise SystemExit(ex.view.error)
        tm = ex.view.timings
        geometry = grow_geometry(ex.program_with(ex.values()), args.steps, seed=1)[-1]
        t2 = time.perf_counter()
        scene = build_mesh(geometry)
        t3 = time.perf_counter()
        glb = glb_bytes(scene)
        t4 = time.perf_counter()
        if i == 0:
            continue  # warm-up
        for k, v in zip(rows, (seen["derive_ms"], seen["serialise_ms"], tm["serialise_ms"],
                               (seen["at"] - t0) * 1e3, (t1 - t0) * 1e3, (t3 - t2) * 1e3,
                               (t4 - t3) * 1e3), strict=True):
            rows[k].append(v)
    segs = ex.view.segments
    lines = seen["lines"]
    print(f"widget latency, {len(segs) // 44:,} instanced rows (chains of branches) after "
          f"{args.steps} steps; "
          f"sent {len(segs) / 1e6:.1f} MB "
          f"instanced (the glTF: {len(glb) / 1e6:.1f} MB, {scene.n_triangles:,} triangles); "
          f"median of {args.changes} slider changes")
    for k, v in rows.items():
        print(f"  {k:16s} {statistics.median(v):8.1f} ms")
    print(f"  the preview: {len(lines) / 1e6:.2f} MB of lines; the widget's full frame "
          "comes 0.3 s (PlantView.settle) after the last change")
    if args.browser:
        pre = _draw_ms(lines, "lines", args.changes)
        print(f"  {'draw (preview)':16s} {pre:8.1f} ms  (headless Chromium, one-pixel lines)")
        print(f"  {'draw (full)':16s} {_draw_ms(segs, 'segments', 5):8.1f} ms  "
              "(headless Chromium, instanced cylinders)")
        print(f"  {'draw (glb)':16s} {_draw_ms(glb, 'glb', 3):8.1f} ms  "
              "(headless Chromium)")
        total = statistics.median(rows["widget (preview)"]) + pre
        print(f"  preview: slider change to lines on the canvas {total:.1f} ms (widget "
              "(preview) + draw (preview); the comm's copy of the bytes not counted); "
              f"target <= 150 ms: {'met' if total <= 150 else 'not met'}")


def _draw_ms(data: bytes, kind: str, repeat: int) -> float:
    """Median ms from the glTF arriving in the front end to its frame drawn."""
    import functools
    import http.server
    import tempfile
    import threading
    from pathlib import Path

    from playwright.sync_api import sync_playwright

    from sylva.widgets import esm

    page_html = """<!doctype html><meta charset="utf-8"><div id="host" style="width:800px"></div>
<script type="module">
const buf = new DataView(await (await fetch("plant.glb")).arrayBuffer());
const state = { glb: null, segments: null, lines: null, shown: "", step: 0, max_steps: 0,
  camera: "perspective", height: 600, status: "", error: "", busy: false, draw_ms: 0, frames: 0 };
const handlers = {};
const model = { get: (k) => state[k], on: (e, f) => { (handlers[e] ||= []).push(f); },
  set: (k, v) => { state[k] = v; for (const f of handlers["change:" + k] || []) f(); },
  off: () => {}, save_changes: () => {}, send: () => {} };
const { default: widget } = await import("./widget.mjs");
await widget.render({ model, el: document.getElementById("host") });
window.times = [];
for (let i = 0; i < REPEAT; i++) {
  const n = state.frames;
  const t0 = performance.now();
  model.set("KIND", new DataView(buf.buffer.slice(0)));
  while (state.frames === n) await new Promise((r) => setTimeout(r, 5));
  // the frame on the canvas, not just queued: read a pixel back
  const canvas = document.querySelector(state.shown === "preview" ? "canvas.sylva-preview"
    : ".sylva-view canvas");
  const gl = canvas.getContext("webgl2");
  gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, new Uint8Array(4));
  window.times.push(performance.now() - t0);
}
window.done = true;
</script>""".replace("REPEAT", str(repeat)).replace("KIND", kind)
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        (folder / "widget.mjs").write_text(esm(), encoding="utf-8")
        (folder / "plant.glb").write_bytes(data)
        (folder / "index.html").write_text(page_html, encoding="utf-8")
        class Quiet(http.server.SimpleHTTPRequestHandler):
            extensions_map = {".mjs": "text/javascript", ".js": "text/javascript",
                              ".html": "text/html", ".glb": "model/gltf-binary"}

            def log_message(self, *args):
                pass

        handler = functools.partial(Quiet, directory=tmp)
        server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), handler)
        threading.Thread(target=server.serve_forever, daemon=True).start()
        try:
            with sync_playwright() as pw:
                browser = pw.chromium.launch(
                    executable_path="/usr/bin/chromium", headless=True,
                    args=["--no-sandbox", "--use-angle=swiftshader",
                          "--enable-unsafe-swiftshader"])  # fmt: skip
                page = browser.new_page(viewport={"width": 820, "height": 700})
                page.goto(f"http://127.0.0.1:{server.server_address[1]}/index.html")
                page.wait_for_function("window.done === true", timeout=600_000)
                times = page.evaluate("window.times")
                browser.close()
        finally:
            server.shutdown()
    return statistics.median(times[1:] or times)


if __name__ == "__main__":
    main()
