"""Memory: once its clients have gone idle, a Studio server gives their words and meshes
back, and its resident size returns to near a fresh server's (a real server in a child
process, measured in /proc; a modest load on 127.0.0.1, bounded in time)."""

from __future__ import annotations

import asyncio
import subprocess
import sys
import time
from pathlib import Path

import httpx
import pytest

from .conftest import page_token

SERVE = """
import sys
from sylva.studio import Limits, serve
serve(sys.argv[1], port=0, open_browser=False,
      limits=Limits(idle_timeout=float(sys.argv[2]), max_modules=400_000))
"""
HEAVY = "rot = 25.7\ndetail = 8\naxiom = F\nF -> F[+F]F[-F]F\n"


def rss(pid: int, field: str = "VmRSS") -> int:
    """Resident set size in bytes (``VmHWM``: its peak), from /proc/PID/status."""
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith(field + ":"):
            return int(line.split()[1]) * 1024
    raise AssertionError(f"no {field}")


def wait_for(pred, timeout: float, what: str):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        value = pred()
        if value:
            return value
        time.sleep(0.2)
    raise AssertionError(f"timed out waiting for {what}")


@pytest.fixture()
def server(tmp_path):
    if not Path("/proc/self/status").exists():
        pytest.skip("needs /proc")
    log = tmp_path / "server.log"
    with open(log, "w") as out:
        proc = subprocess.Popen([sys.executable, "-c", SERVE, str(tmp_path), "1.5"],
                                stdout=out, stderr=subprocess.STDOUT, text=True)
    try:
        line = wait_for(lambda: "http://127.0.0.1:" in log.read_text() and log.read_text(),
                        120, "the server to start")
        url = line.split(" at ", 1)[1].split()[0].rstrip("/")
        wait_for(lambda: httpx.get(url + "/api/info").json()["ready"], 300, "warm-up")
        yield url, proc.pid
    finally:
        proc.terminate()
        try:
            proc.wait(30)
        except subprocess.TimeoutExpired:  # pragma: no cover
            proc.kill()
            proc.wait()


async def client(url: str, token: str, text: str, steps: int) -> int:
    async with httpx.AsyncClient(base_url=url, timeout=120) as c:
        r = await c.post("/api/session", json={}, headers={"x-sylva-page": token})
        c.headers["x-sylva-session"] = r.json()["session"]
        r = await c.post("/api/load", json={"text": text, "steps": steps})
        assert r.status_code == 200, r.text
        m = await c.get("/api/mesh")
        assert m.status_code == 200, m.text
        return int(m.headers["x-sylva-triangles"])
        # and the client goes away without a word: its session idles out


def test_rss_returns_after_the_clients_leave(server):
    url, pid = server
    token = page_token(url)
    # a fresh server, once it has served one small request
    asyncio.run(client(url, token, HEAVY, 2))
    wait_for(lambda: httpx.get(url + "/api/info").json()["sessions"] == 0, 60, "idle-out")
    time.sleep(0.5)
    fresh = rss(pid)

    async def load():
        return await asyncio.wait_for(asyncio.gather(
            *(client(url, token, HEAVY.replace("25.7", str(20 + k)), 6) for k in range(4))),
            240)

    tris = asyncio.run(load())
    assert min(tris) > 100_000
    loaded = rss(pid, "VmHWM")
    assert loaded > 1.5 * fresh  # the load did hold memory
    wait_for(lambda: httpx.get(url + "/api/info").json()["sessions"] == 0, 60, "idle-out")
    after = wait_for(lambda: (r := rss(pid)) <= 1.5 * fresh and r, 30, "memory back")
    assert after <= 1.5 * fresh, (fresh, loaded, after)
