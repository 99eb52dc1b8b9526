"""The Studio's Texture mode through its HTTP API (issue 22): a preset's graph renders to
the image ``sylva texture --graph`` writes, a bad text comes back with its line and column
(never a 500), and a save writes the TOML and the PNG together inside the workspace."""

from __future__ import annotations

import base64
import io

import numpy as np
import pytest
from PIL import Image

from sylva.cli import main
from sylva.texture import graph as tg


@pytest.fixture()
def client(live):
    with live.client(timeout=120) as c:
        yield c


def pixels(data: bytes) -> np.ndarray:
    with Image.open(io.BytesIO(data)) as im:
        assert im.format == "PNG"
        return np.asarray(im.convert("RGB"))


def test_a_preset_renders_as_sylva_texture_draws_its_graph(client, tmp_path):
    names = [p["name"] for p in client.get("/api/texture/presets").json()["presets"]]
    assert {"arabescato-marble", "seahorse-valley", "fern"} <= set(names)
    text = client.get("/api/texture/preset", params={"name": "arabescato-marble"}).json()[
        "text"]
    assert text == tg.from_recipe("arabescato-marble").dumps()
    r = client.post("/api/texture", json={"text": text, "side": 0})
    assert r.status_code == 200, r.text
    got = r.json()
    assert (got["width"], got["height"]) == (512, 512) and got["output"] == "scalar"
    # the same graph through the command line, as a user would render it
    (tmp_path / "marble.toml").write_text(text, encoding="utf-8")
    assert main(["texture", "--graph", str(tmp_path / "marble.toml"), "-o",
                 str(tmp_path / "marble.png")]) == 0
    want = pixels((tmp_path / "marble.png").read_bytes())
    img = pixels(base64.b64decode(got["png"]))
    assert img.std() > 10 and np.array_equal(img, want)
    # while editing: a small image of the same graph (the longer side 64)
    small = client.post("/api/texture", json={"text": text, "side": 64}).json()
    assert (small["width"], small["height"]) == (64, 64) and small["size"] == [512, 512]
    assert np.array_equal(pixels(base64.b64decode(small["png"])),
                          tg.loads(text).image((64, 64)))
    assert client.get("/api/texture/preset", params={"name": "nope"}).status_code == 404


def test_the_node_list_is_the_graphs_tree(client):
    from sylva.texture.graph.library import marble_graph

    g = marble_graph(seed=1)
    r = client.post("/api/texture", json={"text": g.dumps(), "side": 32}).json()
    nodes = {n["name"]: n for n in r["nodes"]}
    assert list(nodes) == list(g.to_dict()["nodes"]) and r["nodes"][-1]["name"] == "out"
    assert nodes["out"]["type"] == "clamp" and nodes["out"]["inputs"] == {"source": "add8"}
    assert nodes["out"]["params"] == {"lower": 0.0, "upper": 1.0}
    assert nodes["multiply7"]["inputs"] == {"a": 0.5, "b": "sin6"}
    assert nodes["multiply7"]["links"] == ["b"]
    assert nodes["turbulence2"]["category"] == "generator"
    assert nodes["out"]["category"] == "modifier"


@pytest.mark.parametrize("text,line,column,words", [
    # not TOML at all: tomllib's position
    ('[graph]\noutput = "out"\n\n[nodes.out]\ntype = = "perlin"\n', 5, 8, "not valid TOML"),
    # an unknown node type: the position of its type
    ('[graph]\noutput = "out"\n\n[nodes.out]\ntype = "perlinn"\n', 5, 8, "perlinn"),
    # a missing input: the node's table
    ('[graph]\noutput = "out"\n\n[nodes.out]\ntype = "clamp"\nlower = 0\n', 4, 1, "source"),
])
def test_a_bad_graph_comes_back_with_its_line_and_column(client, text, line, column, words):
    r = client.post("/api/texture", json={"text": text})
    assert r.status_code == 400, r.text
    e = r.json()
    assert (e["line"], e["column"]) == (line, column), e
    assert words in e["message"] and f":{line}:{column}:" in e["message"]
    with pytest.raises(tg.GraphError) as want:
        tg.loads(text)
    assert (want.value.line, want.value.column) == (line, column)
    for body in ({"text": 3}, {"text": "x", "side": -1}, {"text": "x", "side": 10**6}):
        assert client.post("/api/texture", json=body).status_code == 400, body


def test_save_writes_the_toml_and_its_png_together(client, workspace):
    g = tg.from_recipe({"kind": "worley", "output": "f1", "scale": 6.0, "size": [48, 32],
                        "seed": 2})
    text = g.dumps()
    r = client.put("/api/texture/file", json={"path": "tex/cells.toml", "text": text})
    assert r.status_code == 200, r.text
    assert r.json()["image"] == "tex/cells.png"
    assert (workspace / "tex" / "cells.toml").read_text(encoding="utf-8") == text
    img = pixels((workspace / "tex" / "cells.png").read_bytes())
    assert img.shape == (32, 48, 3) and np.array_equal(img, g.image())
    # not over an existing file unless asked; never outside the workspace or as another kind
    again = client.put("/api/texture/file", json={"path": "tex/cells.toml", "text": text})
    assert again.status_code == 409
    assert client.put("/api/texture/file", json={"path": "tex/cells.toml", "text": text,
                                                 "overwrite": True}).status_code == 200
    assert client.put("/api/texture/file", json={"path": "../x.toml",
                                                 "text": text}).status_code == 403
    assert client.put("/api/texture/file", json={"path": "x.lsys",
                                                 "text": text}).status_code == 400
    # a text that does not read is not saved, and says where it is wrong
    bad = client.put("/api/texture/file", json={"path": "bad.toml", "text": "[graph\n"})
    assert bad.status_code == 400 and bad.json()["line"] == 1
    assert not (workspace / "bad.toml").exists() and not (workspace / "bad.png").exists()
    # the workspace's graphs, and one's text back
    listed = [f["path"] for f in client.get("/api/texture/files").json()["files"]]
    assert listed == ["tex/cells.toml"]
    assert client.get("/api/texture/file", params={"path": "tex/cells.toml"}).json()[
        "text"] == text


def test_a_huge_graph_previews_small_but_is_not_rendered_whole(client, workspace):
    g = tg.from_recipe({"kind": "marble", "size": [4096, 2048], "seed": 3})
    r = client.post("/api/texture", json={"text": g.dumps(), "side": 64})
    assert r.status_code == 200 and (r.json()["width"], r.json()["height"]) == (64, 32)
    for call in (lambda: client.post("/api/texture", json={"text": g.dumps(), "side": 0}),
                 lambda: client.put("/api/texture/file", json={"path": "huge.toml",
                                                               "text": g.dumps()})):
        r = call()
        assert r.status_code == 400 and "2048 pixels a side" in r.json()["message"]
    assert not (workspace / "huge.toml").exists()
