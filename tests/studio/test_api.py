"""The Studio's HTTP API against a real server on the loopback."""

from __future__ import annotations

import io
import os
import shutil
import subprocess

import httpx
import numpy as np
import pytest

from sylva.data import examples
from sylva.lsystem import derive, loads

trimesh = pytest.importorskip("trimesh")

PLANT = "rot = 25.7\naxiom = F\nF -> F[+F]F[-F]F\n"
PARAMETRIC = """\
# a parametric plant with globals
size = 2
angle = 30
axiom = A(size)
A(s) : s > 0.1 -> F(s)[+(angle)A(s*0.6)][-(angle)A(s*0.6)]
"""


@pytest.fixture()
def client(live):
    with live.client(timeout=30) as c:
        yield c


def load(c, text=PLANT, **kw):
    r = c.post("/api/load", json={"text": text, **kw})
    return r


def glb_scene(data: bytes):
    return trimesh.load(io.BytesIO(data), file_type="glb", force="scene")


def test_index_and_vendored_front_end(client):
    r = client.get("/")
    assert r.status_code == 200 and "sylva Studio" in r.text
    assert "/static/app.js" in r.text
    assert "script-src 'self'" in r.headers["content-security-policy"]
    # nothing is fetched from another host: every script and style is local
    assert "http://" not in r.text.replace("http://www.w3.org", "")
    assert "https://" not in r.text
    for path in ("/static/vendor/three.js", "/static/vendor/codemirror.js",
                 "/static/app.js", "/static/viewer.js", "/static/editor.js",
                 "/static/vendor/licenses/three.LICENSE"):
        assert client.get(path).status_code == 200, path
    assert "MIT" in client.get("/static/vendor/VENDORED.txt").text


def test_load_step_back_reset(client):
    r = load(client)
    assert r.status_code == 200, r.text
    s = r.json()
    assert (s["step"], s["modules"], s["camera"]) == (0, 1, "2d")
    r = client.post("/api/step", json={"n": 3})
    assert r.status_code == 200
    expected = len(derive(loads(PLANT), 3))
    assert r.json()["step"] == 3 and r.json()["modules"] == expected == 311
    r = client.post("/api/back")
    assert (r.json()["step"], r.json()["modules"]) == (2, len(derive(loads(PLANT), 2)))
    r = client.post("/api/reset")
    assert (r.json()["step"], r.json()["modules"]) == (0, 1)
    # load can derive at once
    r = load(client, steps=2)
    assert (r.json()["step"], r.json()["modules"]) == (2, 61)


def test_word_paging(client):
    load(client, steps=4)
    full = derive(loads(PLANT), 4)
    total = len(full)
    pages, start = [], 0
    while start < total:
        page = client.get("/api/word", params={"start": start, "count": 1000}).json()
        assert page["total"] == total and page["start"] == start
        pages.extend(page["modules"])
        start += len(page["modules"])
    assert len(pages) == total
    assert "".join(pages) == full.to_text()
    assert client.get("/api/word", params={"count": 10**9}).status_code == 400


def test_mesh_is_a_glb_of_the_plant(client):
    load(client, steps=3)
    r = client.get("/api/mesh")
    assert r.status_code == 200
    assert r.headers["content-type"] == "model/gltf-binary"
    assert r.content[:4] == b"glTF"
    scene = glb_scene(r.content)
    tris = sum(len(g.faces) for g in scene.geometry.values())
    assert tris == int(r.headers["x-sylva-triangles"]) > 0
    lo, hi = scene.bounds
    assert hi[1] - lo[1] == pytest.approx(27.0, rel=0.02)  # 3**3 unit segments tall
    assert int(r.headers["x-sylva-step"]) == 3
    assert client.get("/api/state").json()["triangles"] == tris


def test_pick_traces_module_rule_and_step(client):
    text = "rot = 30\naxiom = X\nX -> F[+X]F[-X]\nF -> FF\n"
    load(client, text, steps=3)
    # the first segment of the trunk: the first F, made by F -> FF in step 3
    r = client.post("/api/pick", json={"point": [0.0, 0.5, 0.0]})
    assert r.status_code == 200, r.text
    p = r.json()
    assert p["module"] == "F" and p["index"] == 0 and p["kind"] == "segment"
    assert p["rule"]["text"] == "F -> FF"
    assert (p["rule"]["line"], p["rule"]["column"]) == (4, 1)
    assert p["made_at_step"] == 3
    assert p["segment"]["start"] == pytest.approx([0, 0, 0])
    # a module right at the tip of a branch made in the last step by X -> …
    word = client.get("/api/word", params={"count": 5000}).json()["modules"]
    tip = client.post("/api/pick", json={"point": [0.0, 0.0, 0.0]}).json()
    assert word[tip["index"]] == tip["module"]
    bad = client.post("/api/pick", json={"point": [0, "x", 0]})
    assert bad.status_code == 400
    # the other way round: from a module of the word to what it drew
    m = client.get("/api/module", params={"index": 0}).json()
    assert m["segment"] == p["segment"] and m["rule"] == p["rule"]
    bracket = word.index("[")
    m = client.get("/api/module", params={"index": bracket}).json()
    assert m["module"] == "[" and m["kind"] is None and m["rule"]["text"].startswith("X ->")
    assert client.get("/api/module", params={"index": len(word)}).status_code == 400


def test_pick_through_render_rules(client):
    src = next(e for e in examples() if e.name.endswith("source-code-2"))
    load(client, src.path.read_text(), steps=2, filename=src.path.name)
    mesh = client.get("/api/mesh")
    assert mesh.status_code == 200
    # the green tips come from the render rule X ->> ;(0,0.7,0)F: the drawn F is a
    # render-word module, traced back to the word's X
    scene = glb_scene(mesh.content)
    lo, hi = scene.bounds
    top = [0.0, float(hi[1]) - 0.01, 0.0]
    p = client.post("/api/pick", json={"point": top}).json()
    assert p["render_index"] != p["index"] or p["module"] in ("F", "X")
    assert p["rule"] is None or p["rule"]["line"] >= 8


def test_syntax_error_has_line_and_column(client):
    r = load(client, "axiom = F\nF -> F[+F\n")
    assert r.status_code == 400
    e = r.json()
    assert e["error"] == "syntax"
    assert (e["line"], e["column"]) == (2, 7)
    assert "^" in e["detail"] and "expected" in e["message"]
    r = load(client, "axiom = F(\n")
    assert r.status_code == 400 and r.json()["line"] == 1


def test_all_three_dialects_open(client):
    seen = set()
    for ex in examples():
        text = ex.path.read_text(encoding="utf-8")
        r = load(client, text, filename=ex.path.name, steps=2)
        assert r.status_code == 200, (ex.name, r.text)
        seen.add(r.json()["dialect"])
        assert r.json()["step"] == 2
        m = client.get("/api/mesh")
        assert m.status_code == 200 and m.content[:4] == b"glTF", ex.name
    assert seen == {"lsys", "classic", "engine"}


def test_camera_hint_follows_pitch_and_roll(client):
    assert load(client, PLANT).json()["camera"] == "2d"
    assert load(client, "axiom = F\nF -> F[&F][/F]\n").json()["camera"] == "perspective"
    assert load(client, "axiom = F\nF -> F[^F]\n").json()["camera"] == "perspective"


def test_globals_and_overrides(client):
    s = load(client, PARAMETRIC, steps=3).json()
    assert s["constants"] == {"size": 2.0, "angle": 30.0}
    first = client.get("/api/word", params={"count": 3}).json()["modules"]
    assert first[0] == "F(2)"
    s = load(client, PARAMETRIC, steps=3, overrides={"size": 1.0}).json()
    assert s["overrides"] == {"size": 1.0}
    assert client.get("/api/word", params={"count": 1}).json()["modules"] == ["F(1)"]
    s = load(client, PARAMETRIC, steps=1, overrides={"angle": 45}).json()
    assert client.get("/api/word", params={"count": 3}).json()["modules"] == \
        ["F(2)", "[", "+(45)"]
    r = load(client, PARAMETRIC, overrides={"nope": 1, "angle": 40})
    assert r.status_code == 200 and r.json()["overrides"] == {"angle": 40}
    r = load(client, PARAMETRIC, overrides={"size": "1; import os"})
    assert r.status_code == 400


def test_seeds_repeat(client):
    text = "axiom = F\nF ->(1) F[+F]F\nF ->(1) F[-F]F\nF ->(1) FF\n"
    words = []
    for _ in range(2):
        load(client, text, seed=42, steps=4)
        words.append(client.get("/api/word", params={"count": 5000}).json()["modules"])
    assert words[0] == words[1]
    assert load(client, text, seed=-1).status_code == 400


def test_module_cap_refuses_a_step(live, client):
    cap = 200_000  # the fixture's Limits(max_modules=...)
    r = load(client, "axiom = F\nF -> FFFFFFFFFF\n", steps=8)
    assert r.status_code == 422
    e = r.json()
    assert e["error"] == "modules" and f"{cap:,}" in e["message"]
    assert e["state"]["step"] == 5 and e["state"]["modules"] == 100_000


def test_step_count_cap(client):
    load(client)
    r = client.post("/api/step", json={"n": 10**6})
    assert r.status_code == 400
    r = client.post("/api/step", json={"n": "many"})
    assert r.status_code == 400


def test_no_program_yet(live):
    with live.client() as fresh:
        r = fresh.post("/api/step", json={"n": 1})
        assert r.status_code == 409 and r.json()["error"] == "no_program"


def test_sessions_are_isolated(live):
    with live.client() as a, live.client() as b:
        load(a, steps=3)
        load(b, "axiom = X\nX -> XX\n", steps=5)
        assert a.get("/api/state").json()["modules"] == 311
        assert b.get("/api/state").json()["modules"] == 32
        assert a.headers["x-sylva-session"] != b.headers["x-sylva-session"]
        # the header names the session, whatever the connection
        sid = b.headers["x-sylva-session"]
        with httpx.Client(base_url=live.url) as c:
            r = c.get("/api/state", headers={"x-sylva-session": sid})
            assert r.json()["modules"] == 32


def test_body_and_url_limits(live, client):
    big = "x" * (2 << 20)
    r = client.post("/api/load", content=big, headers={"content-type": "application/json"})
    assert r.status_code == 413
    r = client.get("/api/word", params={"start": "1" * 5000})
    assert r.status_code == 414
    r = client.post("/api/load", content=b"not json")
    assert r.status_code == 400
    r = client.post("/api/load", json={"text": "axiom = F\n" + "#" * 300_000})
    assert r.status_code == 413


def test_host_and_origin_checks(live, client):
    r = client.get("/api/info", headers={"host": "evil.example"})
    assert r.status_code == 400
    r = client.post("/api/load", json={"text": PLANT},
                    headers={"origin": "http://evil.example"})
    assert r.status_code == 403
    ok = client.post("/api/load", json={"text": PLANT},
                     headers={"origin": live.url})
    assert ok.status_code == 200


def test_workspace_open_save_and_confinement(client, workspace):
    files = client.get("/api/files").json()["files"]
    paths = [f["path"] for f in files]
    assert "plant.lsys" in paths and "sub/koch.lsys" in paths and "notes.md" not in paths
    r = client.get("/api/file", params={"path": "sub/koch.lsys"})
    assert r.json()["text"].startswith("rot = 60")
    r = client.put("/api/file", json={"path": "new/tree.lsys", "text": PLANT})
    assert r.status_code == 200 and r.json()["path"] == "new/tree.lsys"
    assert (workspace / "new" / "tree.lsys").read_text(encoding="utf-8") == PLANT
    assert client.put("/api/file", json={"path": "new/tree.lsys", "text": "x"}).status_code \
        == 409
    r = client.put("/api/file", json={"path": "new/tree.lsys", "text": "axiom = G\n",
                                      "overwrite": True})
    assert r.status_code == 200
    assert client.get("/api/file", params={"path": "new/tree.lsys"}).json()["text"] \
        == "axiom = G\n"
    outside = workspace.parent / "outside.lsys"
    for bad in ("../outside.lsys", "/etc/passwd.lsys", "sub/../../outside.lsys",
                "..\\outside.lsys", "C:/x.lsys", ".hidden.lsys", "plant.py", ""):
        r = client.put("/api/file", json={"path": bad, "text": "axiom = F\n"})
        assert r.status_code in (400, 403), bad
        r = client.get("/api/file", params={"path": bad})
        assert r.status_code in (400, 403), bad
    assert not outside.exists()
    assert client.get("/api/file", params={"path": "missing.lsys"}).status_code == 404


def test_symlink_out_of_workspace_is_refused(client, workspace, tmp_path):
    secret = tmp_path / "secret.lsys"
    secret.write_text("axiom = S\n")
    link = workspace / "link.lsys"
    link.symlink_to(secret)
    try:
        assert client.get("/api/file", params={"path": "link.lsys"}).status_code == 403
        assert "link.lsys" not in [f["path"] for f in client.get("/api/files").json()["files"]]
    finally:
        link.unlink()


def test_examples_and_help(client):
    info = client.get("/api/info").json()
    names = [e["name"] for e in info["examples"]]
    assert len(names) == len(examples())
    assert info["dialects"] == ["lsys", "classic", "engine", "cpfg"]
    ex = client.get("/api/example", params={"name": names[0]}).json()
    assert "axiom" in ex["text"]
    assert client.get("/api/example", params={"name": "../../etc"}).status_code == 404
    h = client.get("/api/help", params={"turtle": "lsys"}).json()
    syms = {s["symbol"]: s["meaning"] for s in h["symbols"]}
    assert {"F", "f", "+", "-", "^", "&", "\\", "/", "|", "$", "!", "~", ";", "_", "[", "]"} \
        <= set(syms)
    assert "pitch" in syms["^"].lower() and "roll" in syms["/"].lower()
    defaults = {v["name"]: v["default"] for v in h["variables"]}
    assert defaults["rot"] == "90.0" and defaults["detail"] == "25"
    assert defaults["bg"] == "0.9, 0.9, 0.9" and defaults["len_delta"] == "-0.1"
    assert "axiom" in defaults and "ignore" in defaults
    classic = client.get("/api/help", params={"turtle": "classic"}).json()
    assert "L" in {s["symbol"] for s in classic["symbols"]}


def test_export_glb_and_obj(client):
    load(client, steps=2, filename="plant.lsys")
    g = client.get("/api/export.glb")
    assert g.status_code == 200 and 'filename="plant-step2.glb"' in \
        g.headers["content-disposition"]
    assert sum(len(x.faces) for x in glb_scene(g.content).geometry.values()) > 0
    o = client.get("/api/export.obj")
    assert o.status_code == 200
    mesh = trimesh.load(io.BytesIO(o.content), file_type="obj", force="mesh")
    assert len(mesh.faces) == sum(len(x.faces) for x in glb_scene(g.content).geometry.values())
    stl = client.get("/api/export.stl")  # every mesh format of the File menu
    assert stl.status_code == 200
    assert len(trimesh.load(io.BytesIO(stl.content), file_type="stl").faces) == len(mesh.faces)
    assert client.get("/api/export.xyz").status_code == 400


def test_export_scad_is_solids_openscad_renders(client, tmp_path):
    load(client, steps=2, filename="plant.lsys")
    r = client.get("/api/export.scad")
    assert r.status_code == 200 and 'filename="plant-step2.scad"' in \
        r.headers["content-disposition"]
    text = r.content.decode()
    assert "color([" in text and "polyhedron(" in text
    openscad = shutil.which("openscad")
    if openscad is None:
        if os.environ.get("SYLVA_REQUIRE_CLIENTS"):
            pytest.fail("OpenSCAD is not installed (bash .ci/run installs it)")
        return
    src, out = tmp_path / "plant.scad", tmp_path / "plant.stl"
    src.write_text(text)
    run = subprocess.run([openscad, "-o", str(out), str(src)], capture_output=True, text=True,
                         timeout=300, check=False)
    assert run.returncode == 0 and "ERROR" not in run.stderr, run.stderr[-2000:]
    assert len(trimesh.load(out, force="mesh").faces) > 0


def test_export_png_at_any_size(client):
    pytest.importorskip("moderngl")
    from PIL import Image

    load(client, steps=3)
    cam = {"mode": "2d", "target": [0, 13.5, 0], "distance": 40, "fov": 45}
    r = client.post("/api/export-png", json={"width": 333, "height": 517, "camera": cam})
    if r.status_code == 503:
        pytest.skip(r.json()["message"])
    assert r.status_code == 200 and r.headers["content-type"] == "image/png"
    img = np.asarray(Image.open(io.BytesIO(r.content)).convert("RGB"))
    assert img.shape == (517, 333, 3)
    dark = (img.sum(axis=2) < 200).mean()
    assert 0.002 < dark < 0.5  # the plant is there, in black on the light background
    r = client.post("/api/export-png", json={"width": 10**6, "height": 5, "camera": cam})
    assert r.status_code == 400
    r = client.post("/api/export-png", json={"width": 10, "height": 10,
                                             "camera": {"mode": "fisheye"}})
    assert r.status_code == 400


def test_long_derivation_blocks_nobody_and_stops(live):
    """A client deriving for seconds does not hold up another; Stop ends it between steps."""
    import threading
    import time

    # a traced step over 40,000 modules takes milliseconds: 1000 of them take seconds
    slow = "axiom = " + "F" * 40_000 + "\nF -> F\n"
    with live.client(timeout=60) as a, live.client(timeout=60) as b:
        assert load(a, slow).status_code == 200
        assert load(b, PLANT).status_code == 200
        result = {}
        worker = threading.Thread(
            target=lambda: result.update(r=a.post("/api/step", json={"n": 1000})))
        worker.start()
        try:
            time.sleep(0.3)
            assert b.post("/api/step", json={"n": 2}).json()["step"] == 2
            assert b.get("/api/info").status_code == 200
            # b got its answers while a is still deriving: nobody waited for a's steps
            assert worker.is_alive()
            # Stop, from a's session (a second connection with its id)
            sid = a.headers["x-sylva-session"]
            stop = b.post("/api/stop", headers={"x-sylva-session": sid})
            assert stop.json() == {"stopping": True}
        finally:
            worker.join(60)
        r = result["r"]
        assert r.status_code == 422 and r.json()["error"] == "stopped"
        assert 0 < r.json()["state"]["step"] < 1000
        # b's session was untouched by a's stop
        assert b.get("/api/state").json()["step"] == 2


def test_preview_is_the_branches_as_lines(client):
    import sylva
    from sylva._lines import line_count

    r = client.post("/api/preview", json={"text": PARAMETRIC, "steps": 3,
                                          "overrides": {"angle": 40}})
    assert r.status_code == 200, r.text
    assert r.headers["content-type"] == "application/octet-stream"
    assert r.headers["x-sylva-kind"] == "lines" and r.headers["x-sylva-step"] == "3"
    # the same branches as sylva's own turtle, at the slider's value
    g = sylva.grow(PARAMETRIC.replace("angle = 30", "angle = 40"), 3).geometry
    n = line_count(r.content)
    assert n == g.n_segments > 4
    ends = np.frombuffer(r.content[:24 * n], np.float32).reshape(n, 2, 3)
    assert np.allclose(ends[:, 0], g.seg_start, atol=1e-5)
    assert np.allclose(ends[:, 1], g.seg_end, atol=1e-5)
    rgba = np.frombuffer(r.content[24 * n:], np.uint8).reshape(n, 2, 4)
    assert np.allclose(rgba[:, 0, :3] / 255, g.seg_color, atol=0.5 / 255 + 1e-6)
    assert (rgba[..., 3] == 255).all()
    # the session holds what was derived: the full frame's load keeps it, and its mesh is
    # of the same step and value
    derive_ms = float(r.headers["x-sylva-derive-ms"])
    s = load(client, PARAMETRIC, steps=3, overrides={"angle": 40}).json()
    assert s["step"] == 3 and s["constants"]["angle"] == 40
    assert s["timings"]["derive_ms"] == pytest.approx(derive_ms, abs=0.051)  # not again
    m = client.get("/api/mesh")
    assert m.status_code == 200 and m.headers["x-sylva-step"] == "3"
    assert len(glb_scene(m.content).geometry) >= 1
    # another value is derived again
    r = client.post("/api/preview", json={"text": PARAMETRIC, "steps": 3,
                                          "overrides": {"angle": 10}})
    ends10 = np.frombuffer(r.content[:24 * n], np.float32).reshape(n, 2, 3)
    assert not np.allclose(ends10, ends, atol=1e-3)


def test_preview_errors_are_load_errors(client):
    r = client.post("/api/preview", json={"text": "axiom = F\nF -> F[+F\n"})
    assert r.status_code == 400 and r.json()["error"] == "syntax"
    assert r.json()["line"] == 2
    r = client.post("/api/preview", json={"text": PLANT, "steps": "x"})
    assert r.status_code == 400
