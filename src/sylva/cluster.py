"""The one place sylva touches Dask: start or join a cluster, run tasks, show progress.

Everything sylva runs in parallel (the chunks of a world, the plant models, the items of a
batch) goes through :func:`connect` and :meth:`Runner.map`, so there is one road:

* ``connect(scheduler="tcp://HOST:PORT")`` (or the ``SYLVA_SCHEDULER`` variable) joins an
  existing ``dask.distributed`` cluster, one machine or many (``dask scheduler`` on one,
  ``dask worker tcp://HOST:PORT`` on each of the others; the workers need sylva installed
  and, for a world store, the output folder on a shared file system);
* otherwise a :class:`~distributed.LocalCluster` of worker *processes* sized to the
  machine (``workers=``, default: the cores) is started for the call and closed after it;
* a job too small to pay for starting processes (``workers=1``, one task, or fewer than
  :data:`MIN_TASKS` tasks when ``workers`` is not given) runs in this process on Dask's
  synchronous scheduler: still Dask, no process start-up (starting a cluster costs two
  seconds or more, what a 256 × 256 world takes on one core).

:meth:`Runner.map` keeps a bounded window of tasks in flight (so the client's memory does
not grow with the job), yields results as they complete, and draws a progress bar with the
rate and the time left on stderr.  Tasks must be pure functions of their arguments: when a
worker dies, Dask runs its tasks again on another worker, and the result is the same.

Examples
--------
>>> with connect(workers=1) as run:
...     sorted(run.map(abs, [-2, 1, -3], progress=False))
[1, 2, 3]
>>> run.kind
'synchronous'
"""

from __future__ import annotations

import contextlib
import logging
import os
import sys
from collections.abc import Callable, Iterable, Iterator
from typing import Any

from .errors import SylvaError

__all__ = ["Runner", "connect", "scheduler_address", "using"]

#: The environment variable naming an existing scheduler (``tcp://HOST:PORT``).
ENV = "SYLVA_SCHEDULER"

#: Fewer tasks than this run in this process unless ``workers`` asks for a cluster.
MIN_TASKS = 8


def scheduler_address(scheduler: str | None = None) -> str | None:
    """``scheduler``, else ``$SYLVA_SCHEDULER``, else None (a local cluster)."""
    address = scheduler or os.environ.get(ENV) or None
    if address is not None and "://" not in address:
        raise SylvaError(f"scheduler {address!r}: expected an address like tcp://HOST:PORT")
    return address


class Runner:
    """Runs tasks on a Dask client, or on the synchronous scheduler when ``client`` is None.

    Attributes
    ----------
    client : distributed.Client or None
    kind : str
        ``"scheduler"`` (an existing cluster), ``"local"`` (a LocalCluster started for the
        job) or ``"synchronous"`` (this process).
    dashboard : str or None
        The Dask dashboard's address, when the cluster serves one.
    """

    def __init__(self, client=None, kind: str = "synchronous",
                 dashboard: str | None = None) -> None:  # fmt: skip
        self.client = client
        self.kind = kind
        self.dashboard = dashboard

    @property
    def address(self) -> str | None:
        """The scheduler's address (None on the synchronous scheduler)."""
        return None if self.client is None else self.client.scheduler.address

    @property
    def workers(self) -> int:
        """Worker processes (1 for the synchronous scheduler)."""
        if self.client is None:
            return 1
        return max(1, len(self.client.scheduler_info(n_workers=-1)["workers"]))

    def map(self, fn: Callable, items: Iterable, *, progress: bool | Callable = True,
            weight: Callable[[Any], int] | None = None, total: int | None = None,
            unit: str = "task", window: int | None = None,
            retries: int = 2) -> Iterator:  # fmt: skip
        """Run ``fn(item)`` for every item; yield the results as they complete.

        Parameters
        ----------
        fn : callable
            A pure, importable (picklable) function.
        items : iterable
        progress : bool or callable
            True: a bar on stderr (items/s, time left); a callable gets ``(done, total)``
            after each task; False: nothing.
        weight : callable, optional
            How many units an item counts for in the progress (default 1).
        total : int, optional
            Total units (default: the sum of the weights).
        unit : str
            The name of a unit in the bar ("chunk").
        window : int, optional
            Tasks in flight at once (default: 4 per worker).
        retries : int
            Times a task that raised is tried again (a dead worker's tasks are rerun by the
            scheduler whatever this is).

        Yields
        ------
        object
            Each task's result, in completion order.
        """
        items = list(items)
        w = weight or (lambda _: 1)
        total = sum(w(i) for i in items) if total is None else total
        bar = _Progress(progress, total, unit, self)
        try:
            if self.client is None:
                yield from self._map_sync(fn, items, w, bar)
            else:
                yield from self._map_client(fn, items, w, bar, window, retries)
        finally:
            bar.close()

    def _map_sync(self, fn, items, w, bar) -> Iterator:
        import dask

        for item in items:
            result = dask.delayed(fn, pure=True)(item).compute(scheduler="synchronous")
            bar.update(w(item))
            yield result

    def _map_client(self, fn, items, w, bar, window, retries) -> Iterator:
        from distributed import as_completed

        window = window or 4 * self.workers
        it = iter(items)
        owner: dict = {}

        def submit(item):
            fut = self.client.submit(fn, item, pure=False, retries=retries)
            owner[fut.key] = item
            return fut

        first = [submit(i) for _, i in zip(range(window), it)]
        pending = as_completed(first, loop=self.client.loop)
        for fut in pending:
            item = owner.pop(fut.key)
            result = fut.result()
            fut.release()
            bar.update(w(item))
            nxt = next(it, None)
            if nxt is not None:
                pending.add(submit(nxt))
            yield result


class _Progress:
    """tqdm on stderr with the rate and the time left, or a callback, or nothing."""

    def __init__(self, progress, total: int, unit: str, runner: Runner) -> None:
        self.callback = progress if callable(progress) else None
        self.done = 0
        self.total = total
        self.bar = None
        if progress is True:
            from tqdm import tqdm

            where = {"synchronous": "this process (Dask's synchronous scheduler)",
                     "local": f"a local Dask cluster of {runner.workers} worker processes",
                     "scheduler": f"the Dask cluster at {runner.address} "
                                  f"({runner.workers} workers)"}[runner.kind]  # fmt: skip
            print(f"running {total} {unit}s on {where}", file=sys.stderr)
            if runner.dashboard:
                print(f"dask dashboard: {runner.dashboard}", file=sys.stderr)
            self.bar = tqdm(total=total, unit=unit, file=sys.stderr, dynamic_ncols=True,
                            smoothing=0.1, mininterval=0.5)  # fmt: skip

    def update(self, n: int) -> None:
        self.done += n
        if self.bar is not None:
            self.bar.update(n)
        if self.callback is not None:
            self.callback(self.done, self.total)

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()


@contextlib.contextmanager
def connect(scheduler: str | None = None, *, workers: int | None = None,
            tasks: int | None = None, memory_limit: str = "2GiB",
            dashboard: bool = True) -> Iterator[Runner]:  # fmt: skip
    """A :class:`Runner` for one job: an existing cluster, a local one, or this process.

    Parameters
    ----------
    scheduler : str, optional
        ``tcp://HOST:PORT`` of a running scheduler (default ``$SYLVA_SCHEDULER``).
    workers : int, optional
        Worker processes of the local cluster (default: the cores, at most ``tasks``);
        1 runs the tasks in this process on the synchronous scheduler.
    tasks : int, optional
        How many tasks the job has: one task never starts a cluster, nor fewer than
        :data:`MIN_TASKS` when ``workers`` is not given.
    memory_limit : str
        Memory per local worker (Dask pauses, then restarts, a worker beyond it).
    dashboard : bool
        Serve the Dask dashboard of a local cluster (on a free port, when ``bokeh`` is
        installed).

    Yields
    ------
    Runner
    """
    address = scheduler_address(scheduler)
    if workers is not None and workers < 1:
        raise SylvaError(f"workers: expected at least 1, got {workers}")
    if address is not None:
        from distributed import Client

        try:
            client = Client(address, timeout="20s", set_as_default=False)
        except (OSError, TimeoutError) as exc:
            raise SylvaError(f"cannot reach the Dask scheduler at {address}: {exc}") from None
        try:
            yield Runner(client, "scheduler", _link(client))
        finally:
            client.close()
        return
    n = workers or os.cpu_count() or 1
    if tasks is not None:
        n = min(n, max(tasks, 1))
        if workers is None and tasks < MIN_TASKS:
            n = 1
    if n <= 1:
        yield Runner(None, "synchronous")
        return
    import importlib.util

    from distributed import Client, LocalCluster

    served = dashboard and importlib.util.find_spec("bokeh") is not None
    with _quiet():
        cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                               host="127.0.0.1", memory_limit=memory_limit,
                               dashboard_address=":0" if served else None,
                               silence_logs=logging.ERROR)  # fmt: skip
        client = Client(cluster, set_as_default=False)
    try:
        yield Runner(client, "local", _link(client) if served else None)
    finally:
        with _quiet():
            client.close()
            cluster.close()


@contextlib.contextmanager
def using(runner: Runner | None, scheduler: str | None = None, *,
          workers: int | None = None, tasks: int | None = None) -> Iterator[Runner]:  # fmt: skip
    """``runner`` when one is given (a job of several steps on one cluster), else
    :func:`connect` for this step alone."""
    if runner is not None:
        yield runner
        return
    with connect(scheduler, workers=workers, tasks=tasks) as run:
        yield run


def _link(client) -> str | None:
    """The dashboard's address, when the scheduler serves one."""
    try:
        return client.dashboard_link if "dashboard" in client.scheduler_info()["services"] \
            else None
    except (KeyError, AttributeError, OSError):
        return None


@contextlib.contextmanager
def _quiet():
    """Dask's start-up and shut-down chatter (and its clean-shutdown warnings) off."""
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        yield
