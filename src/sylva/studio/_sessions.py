"""Client sessions: each browser (or API client) has its own derivation, isolated from others.

A session is named by a random id carried in a cookie (``sylva_session``) or in the
``X-Sylva-Session`` header.  The store holds at most ``max_sessions``; idle ones are
evicted after ``idle_timeout`` seconds, and the least recently used idle one makes room for
a new client when the store is full.
"""

from __future__ import annotations

import asyncio
import secrets
import threading
import time
from dataclasses import dataclass, field
from typing import Any

__all__ = ["COOKIE", "HEADER", "Session", "SessionStore", "TooManySessions"]

COOKIE = "sylva_session"
HEADER = "x-sylva-session"


class TooManySessions(Exception):
    """Every session slot is held by a client that is busy."""


@dataclass
class Session:
    """The state of one client: its program, its derivation and what was last drawn."""

    id: str
    created: float = field(default_factory=time.monotonic)
    last_used: float = field(default_factory=time.monotonic)
    lock: asyncio.Lock = field(default_factory=asyncio.Lock)
    cancel: threading.Event = field(default_factory=threading.Event)
    program: Any = None
    derivation: Any = None
    text: str | None = None
    filename: str | None = None
    overrides: dict = field(default_factory=dict)
    # the last derivation step: (seconds, modules before, modules after), for estimates
    last_step: tuple[float, int, int] | None = None
    timings: dict = field(default_factory=dict)
    # what the last mesh was built from, and the pieces the rule-trace debugger needs
    drawn: Any = None  # sylva.studio._work.Drawn

    @property
    def busy(self) -> bool:
        return self.lock.locked()

    def touch(self) -> None:
        self.last_used = time.monotonic()


class SessionStore:
    """At most ``capacity`` sessions, evicting idle ones."""

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
        return secrets.token_urlsafe(18)

    @staticmethod
    def valid_id(sid: str | None) -> bool:
        return bool(sid) and 16 <= len(sid) <= 64 and all(
            c.isalnum() or c in "-_" for c in sid
        )

    def evict_idle(self) -> int:
        """Drop the sessions idle for longer than the timeout; return how many."""
        now = time.monotonic()
        old = [
            s.id for s in self._sessions.values()
            if not s.busy and now - s.last_used > self.idle_timeout
        ]
        for sid in old:
            self._drop(sid)
        return len(old)

    def _drop(self, sid: str) -> None:
        s = self._sessions.pop(sid, None)
        if s is not None:
            s.cancel.set()

    def close(self) -> None:
        """Stop every session's running work and forget them all."""
        for sid in list(self._sessions):
            self._drop(sid)

    def get(self, sid: str) -> Session:
        """The session ``sid``, made if it does not exist (evicting to make room)."""
        s = self._sessions.get(sid)
        if s is None:
            self.evict_idle()
            if len(self._sessions) >= self.capacity:
                idle = [x for x in self._sessions.values() if not x.busy]
                if not idle:
                    raise TooManySessions(
                        f"the server holds {self.capacity} busy sessions; try again shortly"
                    )
                self._drop(min(idle, key=lambda x: x.last_used).id)
            s = Session(sid)
            self._sessions[sid] = s
        s.touch()
        return s
