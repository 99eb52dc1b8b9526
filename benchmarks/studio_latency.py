"""Studio latency: from a globals slider change to the new frame, a ~100 k-module plant.

    python benchmarks/studio_latency.py [--changes 20] [--steps 9]

A Studio server runs in this process (uvicorn on 127.0.0.1, a thread); the page runs in
headless Chromium (Debian's ``/usr/bin/chromium``, driven by Playwright; WebGL on the CPU
through SwiftShader, as in the tests).  The program is the widget benchmark's (ABOP fig.
1.24d with its angle a global), derived to ``--steps`` (9: 126,912 modules, 38,342
branches).  Each of ``--changes`` changes moves the ``angle`` slider (an ``input`` event,
as while it is dragged), waits for the preview, then lets it go (a ``change`` event) and
waits for the full frame; after one warm-up change, the medians of two sets of figures.

PREVIEW — what the page shows while the slider is dragged: the server derives and runs the
turtle and answers ``POST /api/preview`` with the branches as one-pixel lines
(:mod:`sylva._lines`, no mesh), drawn on a canvas without multisampling:

* total — the input event to the lines on the canvas (a pixel is read back, so the frame
  is really drawn);
* derive — the server's parse and derivation to the step;
* mesh — the server's render word, turtle and lines;
* transfer — the page's round trip of the request less ``derive`` and ``mesh``;
* draw — the lines taken into three.js (upload) and the frame rendered (frame);
* other — total less the rest (the page's own work: the number set in the text).

FULL FRAME — what replaces the preview when the slider is let go, the studio's
full-quality view: 8-sided cylinders, instanced, lit, multisampled.  The page loads the
same request again (the server keeps the derivation and the turtle's geometry) and asks
for the instanced rows (``GET /api/mesh?instanced=1``):

* total — the change event to the full frame on the canvas; input — the same from the
  drag's input event (the preview's time included);
* derive — the preview's derivation (not done again); load — the page's round trip of
  the load; mesh — the server's instanced rows (``x-sylva-mesh-ms``); transfer — the
  mesh request's round trip less ``mesh``;
* draw — upload (the rows into three.js) and frame (from then until the pixel is read);
* other — total less the rest (the word page, the globals).

Nothing leaves the machine; the server, the browser and the page are stopped at the end.
"""

from __future__ import annotations

import argparse
import socket
import statistics
import tempfile
import threading
import time

PROGRAM = "angle = 20\naxiom = X\nX -> F[+(angle)X]F[-(angle)X]+(angle)X\nF -> FF\n"
CHROMIUM = "/usr/bin/chromium"
ARGS = ["--no-sandbox", "--disable-gpu", "--use-angle=swiftshader",
        "--enable-unsafe-swiftshader", "--no-first-run", "--disable-background-networking"]

# waits for the preview drawn after the input event at ``since`` and returns its figures
PREVIEW = """async (since) => {
  const s = window.studio;
  for (;;) {
    const shown = s.previewShownAt > since && s.viewer.renderedAt > s.previewShownAt;
    if (shown && !s.previewing && !s.previewPending) break;
    await new Promise((ok) => setTimeout(ok, 2));
  }
  const gl = s.viewer.activeRenderer.getContext();
  gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, new Uint8Array(4));
  const now = performance.now(), p = s.timing.preview;
  return { total: now - since, derive: p.derive_ms, mesh: p.turtle_ms + p.lines_ms,
           roundtrip: p.roundtrip_ms, upload: p.upload_ms, frame: now - s.previewShownAt,
           bytes: p.bytes, modules: p.modules, lines: s.viewer.lines,
           kind: s.viewer.kind };
}"""

# waits for the full frame after the change at ``since`` and returns the page's figures
FRAME = """async (since) => {
  const s = window.studio;
  for (;;) {
    const shown = s.meshShownAt > since && s.viewer.renderedAt > s.meshShownAt;
    if (shown && !s.busy && !s.rerunPending) break;
    await new Promise((ok) => setTimeout(ok, 2));
  }
  const gl = s.viewer.renderer.getContext();
  gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, new Uint8Array(4));
  const now = performance.now();
  return { total: now - since, derive: s.state.timings.derive_ms, load: s.timing.load_ms,
           mesh: s.timing.mesh_ms, roundtrip: s.timing.roundtrip_ms, draw: s.timing.draw_ms,
           frame: now - s.meshShownAt, bytes: s.timing.mesh_bytes, modules: s.state.modules,
           triangles: s.viewer.triangles, kind: s.viewer.kind };
}"""

# the slider moved (an input event, as while it is dragged)
INPUT = """(value) => {
  const el = document.querySelector('input[data-global=angle]');
  el.value = value;
  const at = performance.now();
  el.dispatchEvent(new Event('input'));
  return at;
}"""

# the slider let go (a change event, as when the pointer is released)
RELEASE = """() => {
  const el = document.querySelector('input[data-global=angle]');
  const at = performance.now();
  el.dispatchEvent(new Event('change'));
  return at;
}"""


def serve(workspace: str):
    import uvicorn

    from sylva.studio import Limits, create_app

    app = create_app(workspace, limits=Limits(time_cap=120.0, max_triangles=10_000_000))
    sock = socket.socket()
    sock.bind(("127.0.0.1", 0))
    server = uvicorn.Server(uvicorn.Config(app, log_level="error", timeout_keep_alive=60))
    thread = threading.Thread(target=server.run, kwargs={"sockets": [sock]}, daemon=True)
    thread.start()
    while not server.started:
        time.sleep(0.05)
    return server, thread, f"http://127.0.0.1:{sock.getsockname()[1]}"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--changes", type=int, default=20)
    ap.add_argument("--steps", type=int, default=9)
    args = ap.parse_args()
    from playwright.sync_api import sync_playwright

    with tempfile.TemporaryDirectory() as ws:
        server, thread, url = serve(ws)
        try:
            with sync_playwright() as pw:
                browser = pw.chromium.launch(executable_path=CHROMIUM, args=ARGS)
                # the benchmark's functions are evaluated as strings: the page's CSP forbids it
                page = browser.new_page(viewport={"width": 1280, "height": 800},
                                        bypass_csp=True)
                page.goto(url + "/")
                page.wait_for_selector("body[data-ready='1']", timeout=600_000)
                page.evaluate("(t) => window.studio.editor.setText(t)", PROGRAM)
                page.fill("#steps", str(args.steps))
                page.click("#btn-derive")
                page.wait_for_function(
                    f"window.studio.meshStep === {args.steps} && !window.studio.busy",
                    timeout=600_000, polling=100)
                pre, fin = [], []
                for i in range(args.changes + 1):
                    at = page.evaluate(INPUT, 20.0 + 0.5 * (i + 1))
                    p = page.evaluate(PREVIEW, at)
                    let_go = page.evaluate(RELEASE)
                    r = page.evaluate(FRAME, let_go)
                    p["transfer"] = p["roundtrip"] - p["derive"] - p["mesh"]
                    p["draw"] = p["upload"] + p["frame"]
                    p["other"] = p["total"] - p["roundtrip"] - p["draw"]
                    r["upload"] = r["draw"]
                    r["transfer"] = r["roundtrip"] - r["mesh"]
                    r["draw"] = r["draw"] + r["frame"]
                    r["other"] = r["total"] - r["load"] - r["roundtrip"] - r["frame"]
                    r["input"] = r["total"] + (let_go - at)
                    if i:  # the first change is the warm-up
                        pre.append(p)
                        fin.append(r)
                browser.close()
        finally:
            server.should_exit = True
            thread.join(30)
    _report(pre, fin)


def _table(rows: list[dict], keys) -> None:
    for k in keys:
        v = [r[k] for r in rows]
        print(f"  {k:9s} {statistics.median(v):9.1f} ms   (min {min(v):.1f}, "
              f"max {max(v):.1f})")


def _report(pre: list[dict], fin: list[dict]) -> None:
    p, f = pre[-1], fin[-1]
    assert all(r["kind"] == "preview" for r in pre), "the drag did not preview"
    print(f"studio slider -> frame, {p['modules']:,} modules; median of {len(pre)} changes")
    print(f"PREVIEW (while the slider is dragged): {p['lines']:,} branches as one-pixel "
          f"lines, {p['bytes'] / 1e6:.2f} MB; from the input event to the lines on the canvas")
    _table(pre, ("total", "derive", "mesh", "transfer", "draw", "upload", "frame", "other"))
    med = statistics.median(r["total"] for r in pre)
    print(f"  preview target <= 150 ms: {'met' if med <= 150 else 'not met'}")
    print(f"FULL FRAME (the slider let go): {f['triangles']:,} triangles of instanced "
          f"cylinders, {f['bytes'] / 1e6:.1f} MB; from the release to the frame on the "
          "canvas (the derivation is the preview's, kept)")
    _table(fin, ("total", "derive", "load", "mesh", "transfer", "draw", "upload", "frame",
                 "other", "input"))
    med = statistics.median(r["total"] for r in fin)
    print(f"  full-frame target <= 150 ms: {'met' if med <= 150 else 'not met'}")


if __name__ == "__main__":
    main()
