"""Load test: 50 concurrent clients derive and mesh different systems on one real server.

Every answer is checked: module and symbol counts against an independent count (the
Lindenmayer growth matrix, not the engine), and every GLB is parsed by trimesh.  The test
sends a bounded number of requests to 127.0.0.1 only, and stops by itself.
"""

from __future__ import annotations

import asyncio
import io
import random

import numpy as np
import pytest

trimesh = pytest.importorskip("trimesh")

CLIENTS = 50
SYMBOLS = ["F", "X", "+", "-", "[", "]"]


def make_system(rng: random.Random) -> tuple[str, dict[str, str], int]:
    """A random D0L plant: F and X rewritten, brackets balanced."""

    def successor(letters: str) -> str:
        parts = []
        for _ in range(rng.randint(2, 4)):
            piece = "".join(rng.choice(letters) for _ in range(rng.randint(1, 3)))
            if rng.random() < 0.5:
                piece = "[" + rng.choice("+-") + piece + "]"
            parts.append(piece)
        return "".join(parts)

    rules = {"F": "F" + successor("FF+-"), "X": successor("FX+-") + "X"}
    steps = rng.randint(2, 4)
    return "F X", rules, steps


def text_of(rules: dict[str, str], rot: int) -> str:
    lines = [f"rot = {rot}", "axiom = FX"]
    lines += [f"{k} -> {v}" for k, v in rules.items()]
    return "\n".join(lines) + "\n"


def expected_counts(rules: dict[str, str], steps: int) -> dict[str, int]:
    """Symbol counts after ``steps`` steps, by powers of the growth matrix."""
    index = {s: i for i, s in enumerate(SYMBOLS)}
    m = np.zeros((len(SYMBOLS), len(SYMBOLS)), dtype=np.int64)
    for s in SYMBOLS:
        succ = rules.get(s, s)
        for c in succ:
            m[index[c], index[s]] += 1
    v = np.zeros(len(SYMBOLS), dtype=np.int64)
    v[index["F"]] = v[index["X"]] = 1
    for _ in range(steps):
        v = m @ v
    return {s: int(v[index[s]]) for s in SYMBOLS if v[index[s]]}


async def one_client(live, k: int) -> dict:
    rng = random.Random(1000 + k)
    _axiom, rules, steps = make_system(rng)
    text = text_of(rules, rot=15 + k)
    want = expected_counts(rules, steps)
    async with live.async_client(timeout=60) as c:
        r = await c.post("/api/load", json={"text": text, "seed": k, "trace": k % 2 == 0})
        assert r.status_code == 200, r.text
        r = await c.post("/api/step", json={"n": steps})
        assert r.status_code == 200, r.text
        s = r.json()
        assert s["step"] == steps and s["seed"] == k
        assert s["modules"] == sum(want.values()), (k, text)
        assert s["symbols"] == want, (k, text)
        g = await c.get("/api/mesh")
        assert g.status_code == 200 and g.headers["content-type"] == "model/gltf-binary"
        scene = trimesh.load(io.BytesIO(g.content), file_type="glb", force="scene")
        tris = sum(len(geo.faces) for geo in scene.geometry.values())
        assert tris == int(g.headers["x-sylva-triangles"]) > 0
        # the session still holds this client's own word (no cross-talk)
        page = (await c.get("/api/word", params={"count": 5000})).json()
        assert page["total"] == s["modules"]
        got = {}
        for m in page["modules"][:5000]:
            got[m] = got.get(m, 0) + 1
        if s["modules"] <= 5000:
            assert got == want
        return {"k": k, "modules": s["modules"], "triangles": tris}


def test_fifty_concurrent_clients(live):
    async def main():
        return await asyncio.wait_for(
            asyncio.gather(*(one_client(live, k) for k in range(CLIENTS))), timeout=120)

    results = asyncio.run(main())  # bounded: wait_for gives up after 120 s
    assert len(results) == CLIENTS
    assert len({r["modules"] for r in results}) > 10  # different systems really
