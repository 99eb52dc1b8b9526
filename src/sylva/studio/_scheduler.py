"""The Studio's fair scheduler: one job per session, sessions served in turn.

A *job* is a generator that runs in the scheduler's worker threads (never on the event
loop) and ``yield``\\ s between two pieces of its work: two derivation steps, two phases of
meshing.  A worker runs a job for one *slice* (at least one piece, more while they take
less than ``quantum`` seconds), then puts it at the back of the queue when other sessions
wait, and takes the next: the sessions with work are served round robin.  A job that is
expected to be long, or has run for ``heavy_after`` seconds, is *heavy*: heavy jobs never
hold the last worker, which stays free for small requests, so a client asking for a small
thing is not stuck behind four others building large meshes.

Each session has at most one job running or ready to run.  A new request from the same
session supersedes the old one: a job that has not started yet is dropped at once, a
running one is asked to stop at its next ``yield`` (what it finished is kept), and the new
job waits behind it.  A job that does not get its first slice within ``max_wait`` seconds
is withdrawn, and its request is answered with :class:`Busy` (``503`` and
``Retry-After``), so nobody waits without an answer.
"""

from __future__ import annotations

import asyncio
import collections
import contextlib
import math
import threading
import time
from collections.abc import Callable, Generator
from typing import Any

from ._sessions import Session

__all__ = ["Busy", "Job", "Scheduler", "Superseded", "run_through"]


class Busy(Exception):
    """The server cannot take the request now; ``retry_after`` is in seconds."""

    def __init__(self, message: str, retry_after: int) -> None:
        self.retry_after = retry_after
        super().__init__(message)


class Superseded(Exception):
    """A newer request of the same session replaced this one before it ran."""


def run_through(gen: Generator) -> Any:
    """Run a job's generator to its end in the calling thread; return its value."""
    try:
        while True:
            next(gen)
    except StopIteration as stop:
        return stop.value


class Job:
    """One request's work: ``make()`` gives the generator, called in a worker thread."""

    def __init__(self, session: Session, make: Callable[[Job], Generator], loop,
                 heavy: bool = False) -> None:
        self.session = session
        # expected to be long (a large word), or it has been: it may not take the last
        # free worker, which stays for the small requests
        self.heavy = heavy
        self.make = make
        self.loop = loop
        self.future: asyncio.Future = loop.create_future()
        self.cancel = threading.Event()
        self.reason: str | None = None  # why it was asked to stop: "superseded", "time", …
        self.gen: Generator | None = None
        self.taken = False  # a worker has taken it: it started (or is starting)
        self.submitted = time.monotonic()
        self.started: float | None = None
        self.spent = 0.0  # seconds of worker time in finished slices
        self._slice_start: float | None = None

    def used(self) -> float:
        """Seconds of worker time this job has had, the running slice included."""
        t0 = self._slice_start
        return self.spent + (time.perf_counter() - t0 if t0 is not None else 0.0)

    def stop(self, reason: str) -> None:
        if self.reason is None:
            self.reason = reason
        self.cancel.set()


class Scheduler:
    """``workers`` threads serving the sessions' jobs round robin."""

    def __init__(self, workers: int, *, quantum: float = 0.02, max_wait: float = 10.0,
                 heavy_after: float = 0.1, name: str = "sylva-studio") -> None:
        self.quantum = float(quantum)
        self.heavy_after = float(heavy_after)
        self._heavy = 0  # heavy jobs in a slice now
        self._lanes = max(1, int(workers) - 1)  # the most of them at once
        self.max_wait = float(max_wait)
        self._cv = threading.Condition()
        self._ready: collections.deque[Job] = collections.deque()
        self._closed = False
        self._slices: collections.deque[float] = collections.deque(maxlen=64)
        self._threads = [threading.Thread(target=self._work, name=f"{name}-{i}", daemon=True)
                         for i in range(max(1, int(workers)))]
        for t in self._threads:
            t.start()

    # ---------------------------------------------------------------- the event loop side
    def submit(self, session: Session, make: Callable[[Job], Generator], *,
               heavy: bool = False) -> Job:
        """Queue a job for ``session``, superseding the one it has (call on the loop);
        ``heavy``: it is expected to take long."""
        job = Job(session, make, asyncio.get_running_loop(), heavy)
        with self._cv:
            if self._closed or session.closed:
                raise Busy("the server is shutting down or the session has ended", 5)
            waiting = session.next_job
            if waiting is not None:
                session.next_job = None
                self._deliver(waiting, None, Superseded(
                    "a newer request of this session replaced this one"))
            active = session.job
            if active is None:
                session.job = job
                self._ready.append(job)
                self._cv.notify_all()
            elif not active.taken:
                # not started yet: dropped at once
                self._ready.remove(active)
                self._deliver(active, None, Superseded(
                    "a newer request of this session replaced this one"))
                session.job = job
                self._ready.append(job)
                self._cv.notify_all()
            else:
                active.stop("superseded")
                session.next_job = job
        return job

    async def result(self, job: Job) -> Any:
        """The job's value (or its exception); :class:`Busy` when it waited ``max_wait``
        seconds without a turn."""
        try:
            return await asyncio.wait_for(asyncio.shield(job.future), self.max_wait)
        except TimeoutError:
            pass
        except asyncio.CancelledError:
            # the client went away: its work stops at the next step
            self.withdraw(job) or job.stop("gone")
            raise
        if self.withdraw(job):
            raise Busy(f"the server is busy: this request waited {self.max_wait:g} s for "
                       f"its turn; try again in {self.retry_after()} s",
                       self.retry_after()) from None
        return await job.future  # it runs: it ends at its own time budget

    def withdraw(self, job: Job) -> bool:
        """Take a job that has not started out of the queue; ``False`` if it has."""
        with self._cv:
            if job.taken or job.future.done():
                return False
            s = job.session
            if s.job is job:
                self._ready.remove(job)
                self._next(s)
            elif s.next_job is job:
                s.next_job = None
            else:  # pragma: no cover - every queued job is one of the two
                return False
        if not job.future.done():
            job.future.set_exception(Busy("withdrawn", self.retry_after()))
            job.future.exception()  # retrieved: nobody else waits on it
        return True

    def stop(self, session: Session) -> bool:
        """Stop the session's job and drop the one waiting; ``True`` if one was running."""
        with self._cv:
            waiting, session.next_job = session.next_job, None
            if waiting is not None:
                self._deliver(waiting, None, Superseded("stopped before it ran"))
            active = session.job
            if active is None:
                return False
            active.stop("stopped")
            return True

    def retry_after(self) -> int:
        """Seconds after which the queue is expected to be shorter: the work queued per
        worker at the recent slice length (1 to 30)."""
        with self._cv:
            queued = len(self._ready)
            recent = sorted(self._slices)
        slice_s = recent[len(recent) // 2] if recent else self.quantum
        per = queued * max(slice_s, self.quantum) / max(len(self._threads), 1)
        return int(min(max(math.ceil(per), 1), 30))

    @property
    def queued(self) -> int:
        return len(self._ready)

    def close(self) -> None:
        with self._cv:
            self._closed = True
            pending = list(self._ready)
            self._ready.clear()
            self._cv.notify_all()
        for job in pending:
            self._deliver(job, None, Busy("the server is shutting down", 5))
        for t in self._threads:
            t.join(timeout=30)

    # ---------------------------------------------------------------- the workers' side
    def _next(self, s: Session) -> None:
        """``s``'s job is over: its waiting job (if any) gets in line (lock held)."""
        nxt, s.next_job = s.next_job, None
        s.job = nxt
        if nxt is not None:
            self._ready.append(nxt)
            self._cv.notify_all()
        s.touch()

    def _deliver(self, job: Job, value, exc) -> None:
        def settle():
            if job.future.done():
                return
            if exc is None:
                job.future.set_result(value)
            else:
                job.future.set_exception(exc)

        # a closed loop: nobody waits for the answer any more
        with contextlib.suppress(RuntimeError):
            job.loop.call_soon_threadsafe(settle)

    def _work(self) -> None:
        while True:
            with self._cv:
                while not self._closed and (job := self._pick()) is None:
                    self._cv.wait()
                if self._closed:
                    return
                job.taken = True
                heavy = job.heavy
                self._heavy += heavy
            try:
                self._slice(job)
            finally:
                with self._cv:
                    self._heavy -= heavy
                    self._cv.notify_all()
            del job  # an idle worker holds nothing of a session (its mesh, its word)

    def _pick(self) -> Job | None:
        """The first job in line that may run now (lock held): a heavy one only while
        fewer than all workers but one run heavy jobs."""
        for i, job in enumerate(self._ready):
            if not job.heavy or self._heavy < self._lanes:
                del self._ready[i]
                return job
        return None

    def _slice(self, job: Job) -> None:
        t0 = time.perf_counter()
        job._slice_start = t0
        done, value, exc = False, None, None
        try:
            if job.gen is None:
                if job.session.closed:
                    raise Superseded("the session ended before this request ran")
                job.started = time.monotonic()
                job.session.cancel = job.cancel
                job.gen = job.make(job)
            while True:
                next(job.gen)
                if time.perf_counter() - t0 >= self.quantum and self._ready:
                    break  # others wait: back of the line
        except StopIteration as stop:
            done, value = True, stop.value
        except BaseException as e:  # noqa: BLE001 - handed to the request that asked
            done, exc = True, e
        finally:
            dt = time.perf_counter() - t0
            job.spent += dt
            job._slice_start = None
            job.heavy = job.heavy or job.spent > self.heavy_after
        with self._cv:
            self._slices.append(dt)
            if not done:
                self._ready.append(job)
                self._cv.notify_all()
                return
            self._next(job.session)
        job.gen = job.make = None
        self._deliver(job, value, exc)
