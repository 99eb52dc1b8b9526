"""Running the Studio: uvicorn on the loopback, and opening the browser."""

from __future__ import annotations

import socket
import threading
import webbrowser
from pathlib import Path

from ._limits import Limits
from .app import create_app

__all__ = ["serve"]

HOST = "127.0.0.1"


def _bind(port: int) -> socket.socket:
    sock = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
    sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
    try:
        sock.bind((HOST, port))
    except OSError:
        sock.close()
        raise
    sock.set_inheritable(True)
    return sock


def serve(
    workspace: str | Path = ".",
    *,
    port: int = 8765,
    start_file: str | None = None,
    limits: Limits | None = None,
    open_browser: bool = True,
    log_level: str = "warning",
) -> None:
    """Serve the Studio on ``http://127.0.0.1:port`` until interrupted (``port=0``: any
    free port), opening it in the default browser."""
    import uvicorn

    from ..errors import SylvaError

    try:
        sock = _bind(port)
    except OSError as exc:
        raise SylvaError(f"cannot listen on {HOST}:{port}: {exc.strerror}; "
                         "choose another --port") from None
    port = sock.getsockname()[1]
    app = create_app(workspace, limits=limits, start_file=start_file)
    config = uvicorn.Config(app, log_level=log_level, lifespan="on",
                            h11_max_incomplete_event_size=64 * 1024, timeout_keep_alive=30)
    server = uvicorn.Server(config)
    url = f"http://{HOST}:{port}/"
    print(f"sylva studio: serving {Path(workspace).resolve()} at {url} (Ctrl+C stops)",
          flush=True)
    if open_browser:
        threading.Timer(0.8, webbrowser.open, args=(url,)).start()
    try:
        server.run(sockets=[sock])
    finally:
        sock.close()
