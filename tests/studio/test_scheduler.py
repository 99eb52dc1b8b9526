"""The fair scheduler without a server: round robin across sessions, one job per session,
superseding, and an answer for every request."""

from __future__ import annotations

import asyncio
import threading
import time

import pytest

from sylva.studio._scheduler import Busy, Scheduler, Superseded
from sylva.studio._sessions import Session


def session(name: str) -> Session:
    return Session(name * 20)


def pieces(log: list, name: str, n: int, gate: threading.Event | None = None,
           delay: float = 0.0):
    """A job of ``n`` pieces that logs each one (and waits at ``gate`` before the first)."""

    def make(job):
        if gate is not None:
            gate.wait(30)
        for i in range(n):
            if job.cancel.is_set():
                log.append((name, "stopped"))
                return f"{name} stopped"
            log.append((name, i))
            if delay:
                time.sleep(delay)
            yield
        return f"{name} done"

    return make


def test_sessions_take_turns_round_robin():
    """One worker, a long job of session A queued first and a short one of B second: B is
    done after one turn of A, not after all of A (first come, first served would be)."""
    log: list = []

    async def main():
        sched = Scheduler(1, quantum=0.0)
        try:
            gate = threading.Event()
            ja = sched.submit(session("a"), pieces(log, "a", 20, gate))
            jb = sched.submit(session("b"), pieces(log, "b", 2))
            gate.set()
            return await asyncio.gather(sched.result(ja), sched.result(jb))
        finally:
            sched.close()

    assert asyncio.run(main()) == ["a done", "b done"]
    order = [name for name, _ in log]
    assert order[:4] == ["a", "b", "a", "b"]  # turn by turn
    assert order.index("b") < 2 and len(order) == 22


def test_a_new_request_supersedes_the_old_one():
    log: list = []

    async def main():
        sched = Scheduler(1, quantum=0.0)
        try:
            s = session("s")
            gate = threading.Event()
            other = sched.submit(session("o"), pieces(log, "o", 3, gate))  # holds the worker
            queued = sched.submit(s, pieces(log, "q", 3))
            newer = sched.submit(s, pieces(log, "n", 3))  # q had not started: dropped
            with pytest.raises(Superseded):
                await sched.result(queued)
            gate.set()
            await sched.result(other)
            # a running job is asked to stop at its next piece; the next one waits for it
            gate2 = threading.Event()
            running = sched.submit(session("r"), pieces(log, "r", 1000, gate2, delay=0.01))
            gate2.set()
            while not log or log[-1][0] != "r":
                await asyncio.sleep(0.01)
            r = running.session
            latest = sched.submit(r, pieces(log, "l", 2))
            assert running.reason is None or running.reason == "superseded"
            return await sched.result(newer), await sched.result(running), \
                await sched.result(latest), r
        finally:
            sched.close()

    n, stopped, latest, r = asyncio.run(main())
    assert n == "n done" and latest == "l done" and stopped == "r stopped"
    assert ("q", 0) not in log
    # the superseded job stopped before the new one of its session began
    assert log.index(("r", "stopped")) < log.index(("l", 0))
    assert r.job is None and r.next_job is None


def test_a_request_without_a_turn_is_answered_busy():
    async def main():
        sched = Scheduler(1, quantum=0.0, max_wait=0.2)
        gate = threading.Event()
        try:
            hog = sched.submit(session("h"), pieces([], "h", 1, gate))
            late = sched.submit(session("l"), pieces([], "l", 1))
            with pytest.raises(Busy) as exc:
                await sched.result(late)
            assert 1 <= exc.value.retry_after <= 30
            assert late.session.job is None  # withdrawn: nothing left queued for it
            gate.set()
            return await sched.result(hog)
        finally:
            gate.set()
            sched.close()

    assert asyncio.run(main()) == "h done"


def test_stop_ends_the_running_job_and_drops_the_waiting_one():
    log: list = []

    async def main():
        sched = Scheduler(1, quantum=0.0)
        try:
            s = session("s")
            first = sched.submit(s, pieces(log, "f", 1000, delay=0.01))
            while not log:
                await asyncio.sleep(0.01)
            waiting = sched.submit(s, pieces(log, "w", 1))
            assert sched.stop(s) is True
            with pytest.raises(Superseded):
                await sched.result(waiting)
            return await sched.result(first)
        finally:
            sched.close()

    assert asyncio.run(main()) == "f stopped"


def test_a_job_of_a_session_that_ended_does_not_run():
    log: list = []

    async def main():
        sched = Scheduler(1, quantum=0.0)
        try:
            gate = threading.Event()
            hog = sched.submit(session("h"), pieces(log, "h", 1, gate))
            s = session("s")
            queued = sched.submit(s, pieces(log, "s", 1))
            s.release()  # DELETE /api/session, or released while it waited
            gate.set()
            await sched.result(hog)
            with pytest.raises(Superseded):
                await sched.result(queued)
            with pytest.raises(Busy):
                sched.submit(s, pieces(log, "t", 1))
        finally:
            sched.close()

    asyncio.run(main())
    assert ("s", 0) not in log
