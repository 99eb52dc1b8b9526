"""The Studio server under load: a bystander beside heavy meshes, and many clients at once.

    python benchmarks/studio_load.py [--heavy 4] [--seconds 20] [--clients 200]

A real server runs in a child process on 127.0.0.1 (nothing else is contacted); the
clients run here.  Two rows:

* **bystander** — ``--heavy`` clients ask again and again for a heavy mesh (a plant of
  ~200 k modules, ~1 M triangles); meanwhile a small client loads a 2-step derivation and
  meshes it, once a second.  Printed: the small client's answer times (median, max).
* **crowd** — ``--clients`` clients start at once; each opens a session (retrying after
  ``Retry-After`` when the store is full), loads, derives 4 steps, meshes and leaves.
  Printed: how many finished, the longest any single request waited for its answer and
  for its result (after the 503s it retried), the 503s (all with ``Retry-After``) and any
  409s.

Everything is bounded: a fixed number of clients, a fixed duration, and a timeout on every
request; the child server is stopped at the end.
"""

from __future__ import annotations

import argparse
import asyncio
import re
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import httpx

SERVE = """
import sys
from sylva.studio import Limits, serve
serve(sys.argv[1], port=0, open_browser=False, limits=Limits(max_sessions=int(sys.argv[2])))
"""
HEAVY = "rot = 25.7\naxiom = F\nF -> F[+F]F[-F]F\n"
SMALL = "rot = 30\naxiom = X\nX -> F[+X]F[-X]\nF -> FF\n"


class Server:
    def __init__(self, sessions: int) -> None:
        self.dir = tempfile.TemporaryDirectory()
        self.log = Path(self.dir.name) / "server.log"
        with open(self.log, "w") as out:
            self.proc = subprocess.Popen([sys.executable, "-c", SERVE, self.dir.name,
                                          str(sessions)], stdout=out, stderr=subprocess.STDOUT)
        deadline = time.monotonic() + 300
        while "http://127.0.0.1:" not in self.log.read_text():
            if time.monotonic() > deadline or self.proc.poll() is not None:
                raise RuntimeError("the server did not start:\n" + self.log.read_text())
            time.sleep(0.1)
        self.url = self.log.read_text().split(" at ", 1)[1].split()[0].rstrip("/")
        while not httpx.get(self.url + "/api/info").json()["ready"]:
            if time.monotonic() > deadline:
                raise RuntimeError("the server did not warm up")
            time.sleep(0.2)
        html = httpx.get(self.url + "/").text
        self.token = re.search(r'name="sylva-page" content="([^"]+)"', html).group(1)

    def close(self) -> None:
        self.proc.terminate()
        try:
            self.proc.wait(30)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait()
        self.dir.cleanup()


class Client:
    """One page's worth of API calls, counting the answers."""

    def __init__(self, srv: Server, stats: dict) -> None:
        self.srv, self.stats = srv, stats
        # plain HTTP on the loopback: no TLS context to build (60 ms a client otherwise)
        self.http = httpx.AsyncClient(base_url=srv.url, timeout=120, verify=False)

    async def request(self, method: str, path: str, **kw) -> httpx.Response:
        first = time.monotonic()
        try:
            return await self._request(method, path, **kw)
        finally:
            total = time.monotonic() - first
            self.stats["starved"] = max(self.stats.get("starved", 0.0), total)

    async def _request(self, method: str, path: str, **kw) -> httpx.Response:
        while True:
            t0 = time.monotonic()
            r = await self.http.request(method, path, **kw)
            waited = time.monotonic() - t0
            if waited > self.stats.get("longest", 0.0):
                self.stats["longest"] = waited
                self.stats["longest_what"] = f"{method} {path} -> {r.status_code}"
            self.stats[r.status_code] = self.stats.get(r.status_code, 0) + 1
            if r.status_code != 503:
                return r
            retry = r.headers.get("retry-after")
            if retry is None:
                self.stats["503 without Retry-After"] = \
                    self.stats.get("503 without Retry-After", 0) + 1
                return r
            await asyncio.sleep(float(retry))

    async def open(self) -> None:
        r = await self.request("POST", "/api/session", json={},
                               headers={"x-sylva-page": self.srv.token})
        self.http.headers["x-sylva-session"] = r.json()["session"]

    async def close(self) -> None:
        await self.http.delete("/api/session")
        await self.http.aclose()


async def hog(url: str, token: str, k: int, seconds: float) -> None:
    """A heavy client: a fresh ~1 M-triangle mesh again and again (run in its own process,
    so that reading its large answers does not slow the bystander's own event loop)."""
    srv = argparse.Namespace(url=url, token=token)
    c = Client(srv, {})
    await c.open()
    stop = time.monotonic() + seconds
    try:
        while time.monotonic() < stop:
            await c.request("POST", "/api/load", json={
                "text": HEAVY.replace("25.7", f"{20 + k}.{int(time.monotonic()) % 10}"),
                "steps": 7})
            await c.request("GET", "/api/mesh")
    finally:
        await c.close()


async def bystander(srv: Server, heavy: int, seconds: float) -> list[tuple[float, float]]:
    hogs = [subprocess.Popen([sys.executable, __file__, "--hog", srv.url, srv.token, str(k),
                              str(seconds)]) for k in range(heavy)]
    c = Client(srv, {})
    await c.open()
    times = []
    try:
        await asyncio.sleep(3.0)  # the heavy ones are at work
        stop = time.monotonic() + seconds - 3.0
        while time.monotonic() < stop:
            t0 = time.monotonic()
            r = await c.request("POST", "/api/load", json={"text": SMALL, "steps": 2})
            t1 = time.monotonic()
            m = await c.request("GET", "/api/mesh")
            assert r.status_code == 200 and m.status_code == 200, (r.text, m.text)
            times.append((t1 - t0, time.monotonic() - t1))
            if sum(times[-1]) > 1.0:
                t = r.json()["timings"]
                print(f"  slow: load {t1 - t0:.2f} s (server: queued {t['queue_ms']:.0f} ms, "
                      f"worked {t['work_ms']:.0f} ms, answered after "
                      f"{t['request_ms']:.0f} ms), mesh {times[-1][1]:.2f} s")
            await asyncio.sleep(1.0)
    finally:
        await c.close()
        for p in hogs:
            try:
                p.wait(180)
            except subprocess.TimeoutExpired:
                p.kill()
    return times


async def crowd(srv: Server, n: int) -> tuple[int, dict]:
    stats: dict = {}

    async def one(k: int) -> bool:
        c = Client(srv, stats)
        try:
            await c.open()
            text = SMALL.replace("30", str(10 + k % 50))
            r = await c.request("POST", "/api/load", json={"text": text})
            r = await c.request("POST", "/api/step", json={"n": 4})
            m = await c.request("GET", "/api/mesh")
            return r.status_code == 200 and m.status_code == 200
        finally:
            await c.close()

    done = await asyncio.wait_for(asyncio.gather(*(one(k) for k in range(n))), 600)
    return sum(done), stats


def main() -> None:
    if sys.argv[1:2] == ["--hog"]:
        url, token, k, seconds = sys.argv[2:6]
        asyncio.run(hog(url, token, int(k), float(seconds)))
        return
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--heavy", type=int, default=4)
    ap.add_argument("--seconds", type=float, default=20.0)
    ap.add_argument("--clients", type=int, default=200)
    ap.add_argument("--sessions", type=int, default=64, help="the server's max_sessions")
    args = ap.parse_args()
    srv = Server(args.sessions)
    try:
        if args.heavy:
            pairs = asyncio.run(bystander(srv, args.heavy, args.seconds))
            times = [a + b for a, b in pairs]
            print(f"bystander: 2-step load + mesh beside {args.heavy} heavy mesh clients: "
                  f"{len(times)} answers, median {statistics.median(times):.2f} s, "
                  f"max {max(times):.2f} s (load, mesh: "
                  + " ".join(f"{a:.2f}+{b:.2f}" for a, b in pairs) + ")")
        if args.clients:
            t0 = time.monotonic()
            ok, stats = asyncio.run(crowd(srv, args.clients))
            codes = ", ".join(f"{k}: {v}" for k, v in sorted(stats.items(), key=str)
                              if k not in ("longest", "starved", "longest_what"))
            print(f"crowd: {ok} of {args.clients} clients finished in "
                  f"{time.monotonic() - t0:.1f} s; longest wait for one answer "
                  f"{stats.get('longest', 0):.1f} s ({stats.get('longest_what')}), "
                  "for a result (503s retried) "
                  f"{stats.get('starved', 0):.1f} s; answers {codes}")
    finally:
        srv.close()


if __name__ == "__main__":
    main()
