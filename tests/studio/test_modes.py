"""The Studio's debugger (breakpoints, profile), progress, Tree and World modes, image and
mesh exports, through its HTTP API (httpx against a live server)."""

from __future__ import annotations

import io

import numpy as np
import pytest

from sylva.lsystem import Derivation, loads

GROW = "axiom = A(1)\nA(x) -> A(x+1)B\nB -> BF\n"


@pytest.fixture()
def client(live):
    with live.client(timeout=120) as c:
        yield c


def load(client, text=GROW, **kw):
    r = client.post("/api/load", json={"text": text, **kw})
    assert r.status_code == 200, r.text
    return r.json()


def test_condition_breakpoint_stops_where_it_first_holds(client):
    s = load(client)
    assert [r["text"] for r in s["rule_list"]] == ["A(x) -> A(x + 1)B", "B -> BF"]
    r = client.post("/api/debug", json={"n": 10, "breakpoints": [
        {"kind": "condition", "text": "A(x) : x > 3"}]})
    assert r.status_code == 200, r.text
    hit = r.json()["hit"]
    # A(1) A(2) A(3) A(4): x > 3 first holds after step 3, on module 0
    assert r.json()["step"] == 3 and hit["step"] == 3 and hit["matched"] == [0]
    # a condition over two parameters, and one that never holds
    r = client.post("/api/debug", json={"n": 2, "breakpoints": [
        {"kind": "condition", "text": "A(x) : x > 100"}]}).json()
    assert r["hit"] is None and r["done"] == 2 and r["step"] == 5


def test_rule_and_module_breakpoints_match_the_trace(client):
    load(client)
    # B -> BF first fires in step 2 (A -> A B makes the first B in step 1)
    r = client.post("/api/debug", json={"n": 10, "breakpoints": [
        {"kind": "rule", "rule": 1}]}).json()
    ref = Derivation(loads(GROW), trace=True)
    ref.advance(2)
    made = np.flatnonzero((ref.origin_rules == 1) & (ref.origin_steps == 2))
    assert r["hit"]["step"] == 2 and r["hit"]["matched"] == made.tolist()
    assert r["hit"]["count"] == len(made) > 0
    # step on: the next hit is the next step (B -> BF fires in every step from here)
    r = client.post("/api/debug", json={"n": 10, "breakpoints": [
        {"kind": "rule", "rule": 1}]}).json()
    assert r["hit"]["step"] == 3
    # a module appears: F is first made in step 2; reset and stop there
    client.post("/api/reset", json={})
    r = client.post("/api/debug", json={"n": 10, "breakpoints": [
        {"kind": "module", "symbol": "F"}]}).json()
    assert r["hit"]["step"] == 2 and r["hit"]["matched"] == [3]
    assert r["modules"] == len(ref.word)


def test_profile_counts_instances_per_rule_and_step(client):
    load(client)
    client.delete("/api/profile")
    r = client.post("/api/debug", json={"n": 4, "profile": True}).json()
    assert r["hit"] is None and r["step"] == 4
    prof = client.get("/api/profile").json()
    assert [s["step"] for s in prof["steps"]] == [1, 2, 3, 4]
    d = Derivation(loads(GROW))
    for s in prof["steps"]:
        before = d.word
        d.advance(1)
        want = {0: before.count("A"), 1: before.count("B")}
        got = {x["rule"]: x["instances"] for x in s["rules"]}
        assert got == {k: v for k, v in want.items() if v}
        # A -> A B writes 2 modules per instance, B -> B F 2
        assert {x["rule"]: x["written"] for x in s["rules"]} == {k: 2 * v for k, v in
                                                                 got.items()}
        assert s["modules"] == len(d.word) and s["ms"] >= sum(x["ms"] for x in s["rules"]) \
            - 1e-9


def test_bad_breakpoints_are_refused(client):
    load(client)
    for bad, words in [
        ([{"kind": "rule", "rule": 7}], "[0, 1]"),
        ([{"kind": "rule", "rule": True}], "rule number"),
        ([{"kind": "condition", "text": "A(x) : x >"}], "expected an expression"),
        ([{"kind": "condition", "text": "A < B : 1"}], "no context"),
        ([{"kind": "module", "symbol": ""}], "module name"),
        ([{"kind": "sometimes"}], "rule, module or condition"),
        ("F", "list"),
    ]:
        r = client.post("/api/debug", json={"n": 1, "breakpoints": bad})
        assert r.status_code == 400 and words in r.json()["message"], (bad, r.text)
    # without rule tracing, the rule trace's breakpoints are a 409 that says so
    load(client, trace=False)
    r = client.post("/api/debug", json={"n": 1, "profile": True})
    assert r.status_code == 409 and "Rule tracing" in r.json()["message"]
    r = client.post("/api/debug", json={"n": 3, "breakpoints": [
        {"kind": "condition", "text": "A(x) : x >= 3"}]})
    assert r.status_code == 200 and r.json()["hit"]["step"] == 2


def test_the_hook_is_off_unless_asked():
    d = Derivation(loads(GROW), trace=True)
    seen = []
    d.on_rewrite = lambda step, src, rule: seen.append((step, len(src), rule.tolist()))
    d.advance(2)
    # step 2 of A(2) B -> A(3) B B F: A rewrote one module into two, B one into two
    assert seen[1] == (2, 4, [0, 0, 1, 1])
    d.on_rewrite = None
    d.advance(1)
    assert len(seen) == 2


def test_refused_step_keeps_the_last_word_that_fits_and_says_why(client, live):
    cap = live.app.state.studio.limits.max_modules
    load(client, "axiom = F\nF -> FF\n")
    r = client.post("/api/step", json={"n": 40})
    assert r.status_code == 422 and r.json()["error"] == "modules"
    s = r.json()["state"]
    assert s["modules"] <= cap < 2 * s["modules"]  # the last word under the cap
    assert "refused" in r.json()["message"] and f"the view shows step {s['step']}" in \
        r.json()["message"]
    assert client.get("/api/mesh").status_code == 200
    g = client.get("/api/progress").json()
    assert g["steps"] == s["step"] and g["modules"] == s["modules"] and not g["busy"]


def test_cpfg_is_in_the_dialect_picker(client):
    assert "cpfg" in client.get("/api/info").json()["dialects"]
    s = load(client, "#define N 3\nLsystem: 1\nderivation length: N\nAxiom: F\n"
             "F --> F[+F]F\nendlsystem\n", dialect="cpfg", steps=2)
    assert s["dialect"] == "cpfg" and s["modules"] == len(
        Derivation(loads("axiom = F\nF -> F[+F]F\n")).advance(2))


def test_tree_mode_grows_the_fields_and_refuses_a_bad_one(client):
    sp = client.get("/api/tree/species").json()
    assert any(s["species"] == "fan_palm" for s in sp["species"])
    keys = {f["key"] for g in sp["schema"]["global"] for f in g["keys"]}
    assert {"Shape", "BaseSize", "Scale", "Levels", "Leaves", "Age"} <= keys
    level = {f["key"]: f for f in sp["schema"]["level"]}
    assert level["Taper"]["lo"] == 0 and level["Taper"]["hi"] == 3 and level["Taper"]["doc"]
    f = client.get("/api/tree/fields", params={"species": "fan_palm"}).json()
    body = {"blocks": f["blocks"], "extra": f["extra"], "age": 2.0, "seed": 1, "wind": 0.5}
    r = client.post("/api/tree", json=body)
    assert r.status_code == 200, r.text
    import sylva

    ref = sylva.tree("fan_palm", age=2.0, seed=1, wind=0.5)
    assert r.json()["stats"] == ref.stats
    glb = client.get("/api/grown.glb")
    assert glb.status_code == 200 and glb.content[:4] == b"glTF"
    # a value out of its range comes back naming its field and the range
    bad = {**f["blocks"], "global": {**f["blocks"]["global"], "BaseSize": "2"}}
    r = client.post("/api/tree", json={**body, "blocks": bad})
    assert r.status_code == 400 and r.json()["field"] == ["global", "BaseSize"]
    assert "[0, 0.99]" in r.json()["message"]
    for k, v in (("age", 0), ("age", 1e9), ("wind", -1), ("seed", -1), ("seed", 1.5)):
        r = client.post("/api/tree", json={**body, k: v})
        assert r.status_code == 400 and k in r.json()["message"], (k, v, r.text)
    assert client.get("/api/tree/fields", params={"species": "baobab"}).status_code == 404
    # the tree's exports
    stl = client.get("/api/export.stl", params={"of": "tree"})
    assert stl.status_code == 200 and len(stl.content) == 84 + 50 * ref.stats["triangles"]
    assert client.get("/api/export.obj", params={"of": "world"}).status_code == 409


def test_world_mode_and_its_biome_map(client):
    from PIL import Image

    r = client.post("/api/world", json={"seed": 3, "size": 16, "plants": False})
    assert r.status_code == 200, r.text
    assert r.json()["stats"]["size"] == [16, 16]
    png = client.get("/api/world/biomes.png")
    with Image.open(io.BytesIO(png.content)) as im:
        assert im.size == (16, 16)
    assert client.get("/api/grown.glb").content[:4] == b"glTF"
    for body in ({"seed": 1, "size": 4}, {"seed": 1, "size": 10**6}, {"seed": -1},
                 {"seed": 1, "size": "big"}):
        r = client.post("/api/world", json=body)
        assert r.status_code == 400 and r.json()["message"], body


def test_jpg_and_png_of_any_size(client):
    pytest.importorskip("moderngl")
    from PIL import Image

    load(client, "axiom = F\nF -> F[+F]F\n", steps=2)
    for fmt, kind in (("jpg", "JPEG"), ("png", "PNG")):
        r = client.post("/api/export-png", json={"width": 97, "height": 41, "format": fmt,
                                                 "camera": {"distance": 5}})
        if r.status_code == 503:
            pytest.skip(r.json()["message"])
        assert r.status_code == 200 and r.headers["content-disposition"].endswith(
            f'.{fmt}"')
        with Image.open(io.BytesIO(r.content)) as im:
            assert im.format == kind and im.size == (97, 41)
    r = client.post("/api/export-png", json={"width": 9, "height": 9, "format": "gif"})
    assert r.status_code == 400 and "png or jpg" in r.json()["message"]


def test_a_plant_of_many_branches_comes_as_instanced_rows(client):
    from sylva.plant import grow_geometry

    text = "axiom = X\nX -> F[+X]F[-X]+X\nF -> FF\n"
    load(client, text, steps=8, seed=1)
    g = grow_geometry(loads(text), 8, seed=1)[-1]
    assert g.n_segments > 10_000 and not g.n_leaves
    r = client.get("/api/mesh", params={"instanced": "1"})
    assert r.status_code == 200 and r.headers["x-sylva-kind"] == "segments"
    rows = np.frombuffer(r.content, np.float32).reshape(-1, 11)
    # F -> FF's chains of branches are one row each: fewer rows, the same cylinders (every
    # row starts at a branch's start, and together they are as long as the branches)
    assert len(rows) < g.n_segments
    starts = {tuple(p) for p in np.round(g.seg_start, 3)}
    assert all(tuple(p) in starts for p in np.round(rows[:, 0:3].astype(float), 3))
    length = np.linalg.norm(rows[:, 3:6] - rows[:, 0:3], axis=1).sum()
    assert length == pytest.approx(np.linalg.norm(g.seg_end - g.seg_start, axis=1).sum(),
                                   rel=1e-5)
    np.testing.assert_allclose(rows[:, 6:8], g.seg_radius[0, 0])  # one width throughout
    # the exports and a plain mesh request still get the whole mesh, from the same turtle
    m = client.get("/api/mesh")
    assert m.headers["x-sylva-kind"] == "glb" and m.content[:4] == b"glTF"
    assert int(m.headers["x-sylva-triangles"]) > 16 * g.n_segments
    assert client.get("/api/export.glb").content == m.content
