"""Client sessions: each page (or API client) has its own derivation, isolated from others.

A session is made only when asked for: ``POST /api/session`` with the page token that the
server writes into its own page (a cross-site page can neither read that token nor send
the custom header without a CORS preflight, which this server never grants).  It is then
named by a random token that the page holds and sends in the ``X-Sylva-Session`` header;
no cookie is involved, so a request from another site never reaches a session.

The store holds at most ``capacity`` sessions and never evicts an active one: a session
idle for longer than ``idle_timeout`` seconds is released (its word, history and meshes
with it), and when every slot is held by an active client a new one is refused with the
time after which to try again.
"""

from __future__ import annotations

import contextlib
import ctypes
import ctypes.util
import math
import secrets
import threading
import time
from dataclasses import dataclass, field
from typing import Any

__all__ = ["HEADER", "PAGE_HEADER", "Session", "SessionStore", "TooManySessions",
           "release_memory"]

HEADER = "x-sylva-session"
_RETRY_FULL = 5  # seconds
PAGE_HEADER = "x-sylva-page"


class TooManySessions(Exception):
    """Every session slot is held by an active client; ``retry_after`` is in seconds."""

    def __init__(self, message: str, retry_after: int) -> None:
        self.retry_after = retry_after
        super().__init__(message)


@dataclass(eq=False)
class Session:
    """The state of one client: its program, its derivation and what was last drawn."""

    id: str
    created: float = field(default_factory=time.monotonic)
    last_used: float = field(default_factory=time.monotonic)
    # set to stop the running job between two of its steps (each job brings its own)
    cancel: threading.Event = field(default_factory=threading.Event)
    program: Any = None
    derivation: Any = None
    text: str | None = None
    filename: str | None = None
    overrides: dict = field(default_factory=dict)
    # the load request the derivation was made from (the same one again keeps it)
    loaded: str | None = None
    # the last derivation step: (seconds, modules before, modules after), for estimates
    last_step: tuple[float, int, int] | None = None
    timings: dict = field(default_factory=dict)
    # seed 001's two progress figures of the running job: steps derived, modules interpreted
    progress: dict = field(default_factory=dict)
    # the debugger's per-rule profile, one entry a step (sylva.studio._debug)
    profile: list = field(default_factory=list)
    # the Tree and World modes' last grown object and its GLB (sylva.studio._grown)
    grown: Any = None
    # what the last mesh was built from, and the pieces the rule-trace debugger needs
    drawn: Any = None  # sylva.studio._work.Drawn
    # the scheduler's: the job running or ready to run, and the one waiting behind it
    job: Any = None
    next_job: Any = None
    closed: bool = False

    @property
    def busy(self) -> bool:
        return self.job is not None

    def touch(self) -> None:
        self.last_used = time.monotonic()

    def release(self) -> None:
        """Forget the program, the words and the meshes (the session is gone)."""
        self.closed = True
        self.cancel.set()
        self.program = self.derivation = self.drawn = self.text = None
        self.last_step = None
        self.overrides, self.timings = {}, {}
        self.grown, self.profile, self.progress = None, [], {}


class SessionStore:
    """At most ``capacity`` sessions; only those idle past ``idle_timeout`` are evicted."""

    def __init__(self, capacity: int, idle_timeout: float) -> None:
        self.capacity = int(capacity)
        self.idle_timeout = float(idle_timeout)
        self._sessions: dict[str, Session] = {}

    def __len__(self) -> int:
        return len(self._sessions)

    def __contains__(self, sid: object) -> bool:
        return sid in self._sessions

    @staticmethod
    def new_id() -> str:
        return secrets.token_urlsafe(24)

    @staticmethod
    def valid_id(sid: str | None) -> bool:
        return bool(sid) and 16 <= len(sid) <= 64 and all(
            c.isascii() and (c.isalnum() or c in "-_") for c in sid
        )

    def idle(self, s: Session, now: float | None = None) -> bool:
        now = time.monotonic() if now is None else now
        return not s.busy and now - s.last_used > self.idle_timeout

    def evict_idle(self) -> int:
        """Release the sessions idle for longer than the timeout; return how many."""
        now = time.monotonic()
        old = [s.id for s in self._sessions.values() if self.idle(s, now)]
        for sid in old:
            self.drop(sid)
        return len(old)

    def drop(self, sid: str) -> bool:
        """Release session ``sid`` (its running job is asked to stop)."""
        s = self._sessions.pop(sid, None)
        if s is None:
            return False
        s.release()
        return True

    def close(self) -> None:
        """Stop every session's running work and forget them all."""
        for sid in list(self._sessions):
            self.drop(sid)

    def create(self) -> Session:
        """A new session, or :class:`TooManySessions` when every slot is held by an active
        client (an active one is never evicted to make room)."""
        if len(self._sessions) >= self.capacity:
            self.evict_idle()
        if len(self._sessions) >= self.capacity:
            now = time.monotonic()
            waits = [self.idle_timeout - (now - s.last_used)
                     for s in self._sessions.values() if not s.busy]
            # a slot frees when a session idles out or its page is closed (which nobody
            # can foresee): ask again soon, not at the idle-out
            wait = min(waits) if waits else _RETRY_FULL
            retry = int(min(max(math.ceil(wait), 1), _RETRY_FULL))
            raise TooManySessions(
                f"the server holds {self.capacity} active sessions, its most; "
                f"try again in {retry} s", retry)
        sid = self.new_id()
        while sid in self._sessions:  # pragma: no cover - 192 random bits
            sid = self.new_id()
        s = Session(sid)
        self._sessions[sid] = s
        return s

    def get(self, sid: str | None) -> Session | None:
        """The session ``sid`` (touched), or ``None`` when there is no such session."""
        s = self._sessions.get(sid) if sid else None
        if s is not None:
            s.touch()
        return s


_libc = None


def release_memory() -> None:
    """Hand freed heap memory back to the system (glibc keeps it otherwise), so that the
    resident size falls again once idle sessions' words and meshes are released."""
    global _libc
    if _libc is None:
        name = ctypes.util.find_library("c")
        _libc = False
        with contextlib.suppress(OSError, AttributeError):
            lib = ctypes.CDLL(name)
            lib.malloc_trim.argtypes = [ctypes.c_size_t]
            _libc = lib
    if _libc:
        _libc.malloc_trim(0)
