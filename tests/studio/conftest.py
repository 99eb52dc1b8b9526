"""Fixtures of the Studio tests: a real server on a free loopback port, one per module."""

from __future__ import annotations

import re
import socket
import threading
import time
from pathlib import Path

import httpx
import pytest

pytest.importorskip("starlette")
uvicorn = pytest.importorskip("uvicorn")

from sylva.studio import Limits, create_app  # noqa: E402


def page_token(url: str) -> str:
    """The token the Studio writes into its page (what the page opens its session with)."""
    html = httpx.get(url + "/", timeout=30, verify=False).text
    return re.search(r'<meta name="sylva-page" content="([^"]+)">', html).group(1)


def open_session(url: str, token: str | None = None) -> httpx.Response:
    """``POST /api/session`` as the page does it."""
    return httpx.post(url + "/api/session", json={}, timeout=30, verify=False,
                      headers={"x-sylva-page": token or page_token(url)})


def session_headers(url: str) -> dict:
    r = open_session(url)
    assert r.status_code == 200, r.text
    return {"x-sylva-session": r.json()["session"]}


class LiveServer:
    """uvicorn serving a Studio app in a background thread."""

    def client(self, **kw) -> httpx.Client:
        """An API client with a session of its own, opened the way the page opens one."""
        # plain HTTP on the loopback: no TLS context to build (60 ms a client otherwise)
        return httpx.Client(base_url=self.url, headers=session_headers(self.url),
                            verify=False, **kw)

    def async_client(self, **kw) -> httpx.AsyncClient:
        return httpx.AsyncClient(base_url=self.url, headers=session_headers(self.url),
                                 verify=False, **kw)

    def __init__(self, workspace: Path, limits: Limits | None = None) -> None:
        self.workspace = workspace
        self.app = create_app(workspace, limits=limits)
        self.sock = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
        self.sock.bind(("127.0.0.1", 0))
        self.port = self.sock.getsockname()[1]
        self.url = f"http://127.0.0.1:{self.port}"
        # keep-alive as long as the real server's: with 5 s, a client that waited longer on
        # a loaded machine could send on a connection the server was closing
        config = uvicorn.Config(self.app, log_level="error", lifespan="on",
                                timeout_keep_alive=30)
        self.server = uvicorn.Server(config)
        self.thread = threading.Thread(target=self.server.run,
                                       kwargs={"sockets": [self.sock]}, daemon=True)

    def __enter__(self) -> LiveServer:
        self.thread.start()
        deadline = time.monotonic() + 20
        while not self.server.started:
            if time.monotonic() > deadline or not self.thread.is_alive():
                raise RuntimeError("the Studio server did not start")
            time.sleep(0.02)
        return self

    def __exit__(self, *exc) -> None:
        self.server.should_exit = True
        self.thread.join(30)
        self.sock.close()


@pytest.fixture(scope="module")
def workspace(tmp_path_factory) -> Path:
    ws = tmp_path_factory.mktemp("workspace")
    (ws / "plant.lsys").write_text("rot = 25.7\naxiom = F\nF -> F[+F]F[-F]F\n",
                                   encoding="utf-8")
    (ws / "sub").mkdir()
    (ws / "sub" / "koch.lsys").write_text("rot = 60\naxiom = F\nF -> F+F--F+F\n",
                                          encoding="utf-8")
    (ws / "notes.md").write_text("not a definition", encoding="utf-8")
    return ws


@pytest.fixture(scope="module")
def live(workspace) -> LiveServer:
    limits = Limits(max_modules=200_000, time_cap=8.0, max_sessions=80)
    with LiveServer(workspace, limits) as srv:
        yield srv


CHROMIUM = "/usr/bin/chromium"
CHROMIUM_ARGS = [
    "--no-sandbox", "--disable-gpu", "--disable-background-networking",
    "--disable-component-update", "--disable-sync", "--no-first-run", "--disable-quic",
    # WebGL without a GPU: ANGLE on SwiftShader
    "--use-angle=swiftshader", "--enable-unsafe-swiftshader",
]


@pytest.fixture(scope="module")
def browser():
    """One headless Debian Chromium for the browser tests (which live in one module, so it
    is started once); Playwright downloads no browser of its own."""
    sync_api = pytest.importorskip("playwright.sync_api")
    if not Path(CHROMIUM).exists():
        pytest.skip(f"{CHROMIUM} is not installed (apt-get install chromium)")
    with sync_api.sync_playwright() as pw:
        b = pw.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS, headless=True)
        try:
            yield b
        finally:
            b.close()
