"""The caps a Studio server puts on every client and request."""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["Limits"]


@dataclass(frozen=True)
class Limits:
    """Per-server limits.

    Attributes
    ----------
    max_modules : int
        The module cap of every derivation (``Derivation(limit=...)``): a step that would
        pass it is refused and the word before it is kept.
    time_cap : float
        Seconds of derivation or meshing one request may take.  A step that is estimated to
        pass it is refused; a request whose work overruns it is answered with an error.
    max_steps : int
        The most steps one request may ask for.
    max_body : int
        Bytes in a request body.
    max_text : int
        Characters in an L-system definition.
    max_url : int
        Bytes in the path and query string of a request.
    max_sessions : int
        Clients held at once.  An active one is never evicted for a new one: when all
        are active, a new client is refused (``503`` with ``Retry-After``).
    idle_timeout : float
        Seconds without a request after which a session is released, with its words and
        meshes (the page opens a new one and loads its text again when it comes back).
    max_image_side, max_image_pixels : int
        Size of exported PNG images.
    max_triangles : int
        Triangles in a mesh: a larger one is built with fewer sides per branch.
    workers : int
        Worker threads deriving and meshing at once; the sessions with work take turns on
        them, one step or meshing phase at a time.
    max_wait : float
        Seconds a request may wait for its first turn; past that it is answered ``503``
        with ``Retry-After`` (so every request gets an answer).
    page_size : int
        The most modules one page of the word view holds.
    """

    max_modules: int = 2_000_000
    time_cap: float = 10.0
    max_steps: int = 1000
    max_body: int = 1 << 20
    max_text: int = 256 * 1024
    max_url: int = 4096
    max_sessions: int = 64
    idle_timeout: float = 900.0
    max_image_side: int = 8192
    max_image_pixels: int = 8192 * 8192
    max_triangles: int = 3_000_000
    workers: int = 4
    max_wait: float = 10.0
    page_size: int = 5000
