"""``_gridplan.run_blocks``: the threads that run a grid's serial ``nogil`` kernels (one
pool per process): every block once, the caller's thread taking its share, nested calls
and forked children served without a deadlock, a kernel's error raised to the caller."""

import os
import sys
import threading

import numba
import numpy as np
import pytest

from sylva.texture import _gridplan as gp


def _record(c0, c1, out, who):
    for c in range(c0, c1):
        out[c] += 1
        who[c] = threading.get_ident()


@pytest.fixture
def two_threads():
    old = numba.get_num_threads()
    numba.set_num_threads(min(2, numba.config.NUMBA_NUM_THREADS))
    yield numba.get_num_threads()
    numba.set_num_threads(old)


def test_every_block_runs_once_on_the_pool_and_the_caller(two_threads):
    for n in (1, 2, 7, 64, 1000):
        out, who = np.zeros(n, np.int64), np.zeros(n, np.int64)
        gp.run_blocks(_record, n, (out, who))
        assert (out == 1).all()
    # one pool for every call (no threads started per grid)
    pools = set()
    for _ in range(3):
        gp.run_blocks(_record, 64, (np.zeros(64, np.int64), np.zeros(64, np.int64)))
        pools.add(id(gp._pool["pool"]))
    assert len(pools) == 1


def test_a_call_from_a_pool_thread_runs_serially_instead_of_waiting_on_itself(two_threads):
    if two_threads < 2:
        pytest.skip("one thread: nothing runs on the pool")
    inner = np.zeros(50, np.int64)

    def outer(c0, c1, out):
        for c in range(c0, c1):
            out[c] += 1
        gp.run_blocks(_record, 50, (inner[:], np.zeros(50, np.int64)))  # nested

    out = np.zeros(8, np.int64)
    t = threading.Thread(target=gp.run_blocks, args=(outer, 8, (out,)), daemon=True)
    t.start()
    t.join(60)
    assert not t.is_alive()  # no deadlock
    assert (out == 1).all()


def test_a_kernels_error_reaches_the_caller_after_every_thread_stopped(two_threads):
    done = np.zeros(40, np.int64)

    def bad(c0, c1, out):
        for c in range(c0, c1):
            out[c] = 1
            if c == 13:
                raise ValueError("block 13")

    with pytest.raises(ValueError, match="block 13"):
        gp.run_blocks(bad, 40, (done,))
    assert done[13] == 1


def test_after_an_error_no_thread_takes_more_blocks(two_threads):
    import time

    done = np.zeros(200, np.int64)

    def first_fails(c0, c1, out):
        for c in range(c0, c1):
            if c == 0:
                raise ValueError("block 0")
            time.sleep(0.01)
            out[c] = 1

    with pytest.raises(ValueError, match="block 0"):
        gp.run_blocks(first_fails, 200, (done,))
    assert done[0] == 0 and done.sum() < 100  # the rest was not computed for nothing


@pytest.mark.skipif(not hasattr(os, "fork") or sys.platform == "darwin", reason="POSIX fork")
def test_a_forked_child_starts_its_own_threads(two_threads):
    gp.run_blocks(_record, 16, (np.zeros(16, np.int64), np.zeros(16, np.int64)))  # a pool
    r, w = os.pipe()
    pid = os.fork()
    if pid == 0:  # the child: its parent's pool threads do not exist here
        try:
            out = np.zeros(64, np.int64)
            gp.run_blocks(_record, 64, (out, np.zeros(64, np.int64)))
            os.write(w, b"ok" if (out == 1).all() else b"no")
        finally:
            os._exit(0)
    os.close(w)
    import signal
    import time

    deadline = time.monotonic() + 60
    while (done := os.waitpid(pid, os.WNOHANG))[0] == 0 and time.monotonic() < deadline:
        time.sleep(0.05)
    if done[0] == 0:  # waiting on threads that were not forked with it
        os.kill(pid, signal.SIGKILL)
        os.waitpid(pid, 0)
        pytest.fail("the forked child hung in run_blocks")
    assert os.read(r, 2) == b"ok" and done[1] == 0


def test_a_bigger_pool_leaves_the_old_one_usable_for_a_call_that_took_it():
    # a call that took the pool just before another call (with more numba threads) grew it
    old = gp._threads(2)
    bigger = gp._threads(gp._pool["size"] + 1)
    assert bigger is not old and gp._threads(1) is bigger
    assert old.submit(lambda: 7).result(timeout=30) == 7  # not shut down under it


def test_run_tasks_gives_each_result_in_order_one_numba_thread_each(two_threads):
    import time

    seen = []

    def task(i):
        def run():
            seen.append((threading.get_ident(), numba.get_num_threads()))
            time.sleep(0.02)  # long enough that the pool's thread takes some
            return i * i

        return run

    assert gp.run_tasks([task(i) for i in range(6)]) == [0, 1, 4, 9, 16, 25]
    assert len(seen) == 6 and {n for _, n in seen} == {1}
    assert numba.get_num_threads() == two_threads  # the caller's count is back
    if two_threads >= 2:
        assert len({t for t, _ in seen}) == 2


def test_run_tasks_raises_a_tasks_error_and_restores_the_thread_count(two_threads):
    def bad():
        raise ValueError("task failed")

    with pytest.raises(ValueError, match="task failed"):
        gp.run_tasks([lambda: 1, bad, lambda: 3])
    assert numba.get_num_threads() == two_threads


@pytest.mark.parametrize("shape", [(96, 128), (4, 48, 64), (4, 4, 32, 32)], ids=["2d", "3d", "4d"])
@pytest.mark.parametrize("kind", ["improved", "simplex"])
def test_warped_grids_do_not_depend_on_the_thread_count(two_threads, shape, kind):
    # the warp fields go side by side (run_tasks), the rows on run_blocks' threads (work
    # enough for noise_grid to use both)
    from sylva.texture import noise_grid

    kw = dict(kind=kind, octaves=2, scale=5.0, seed=3, warp=0.8)
    many = noise_grid(shape, **kw)
    numba.set_num_threads(1)
    one = noise_grid(shape, **kw)
    np.testing.assert_array_equal(one, many)
    assert one.std() > 0.05


def test_warped_grids_under_numbas_workqueue_layer_run_their_fields_one_by_one():
    # numba's own threading layer (where neither OpenMP nor TBB is installed, as on macOS)
    # aborts the process when two threads launch parallel kernels at once: run_tasks then
    # runs the warp fields one by one (without that, this child died of SIGABRT)
    import subprocess

    code = (
        "import numba, numpy as np\n"
        "from sylva.texture import noise_grid, _gridplan as gp\n"
        "numba.set_num_threads(min(2, numba.config.NUMBA_NUM_THREADS))\n"
        "a = noise_grid((96, 128), kind='improved', octaves=2, scale=5.0, seed=3, warp=0.8)\n"
        "assert numba.threading_layer() == 'workqueue' and not gp._concurrent_kernels()\n"
        "print(round(float(a.std()), 6))\n"
    )
    env = dict(os.environ, NUMBA_THREADING_LAYER="workqueue")
    got = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True,
                         text=True, timeout=300)
    assert got.returncode == 0, got.stderr[-2000:]
    from sylva.texture import noise_grid

    here = noise_grid((96, 128), kind="improved", octaves=2, scale=5.0, seed=3, warp=0.8)
    assert float(got.stdout.split()[-1]) == round(float(here.std()), 6)
