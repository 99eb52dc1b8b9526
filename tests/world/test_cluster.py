"""Worlds on the Dask road: a 2-worker LocalCluster, a killed worker, resume, slice reads.

One cluster (2 worker processes, 127.0.0.1 only) serves the whole module; the worlds are
small (16 blocks of one 16-column chunk) so that the module stays within seconds.
"""

import os
import signal
from pathlib import Path

import numpy as np
import pytest

from sylva.cluster import connect
from sylva.errors import SylvaError
from sylva.world import World, WorldConfig, open_world

CFG = WorldConfig(seed=21, chunk_size=16)
SIZE = (64, 64)
BLOCK = 16  # one chunk per task: 16 tasks


@pytest.fixture(scope="module")
def cluster():
    import logging
    import warnings

    from distributed import Client, LocalCluster

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        lc = LocalCluster(n_workers=2, threads_per_worker=1, processes=True, host="127.0.0.1",
                          dashboard_address=None, silence_logs=logging.ERROR)
        client = Client(lc, set_as_default=False)
    yield lc.scheduler_address, client
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        client.close()
        lc.close()


@pytest.fixture(scope="module")
def serial(tmp_path_factory):
    """The reference: the world made in this process (the synchronous scheduler)."""
    path = tmp_path_factory.mktemp("serial") / "w.zarr"
    World(CFG, size=SIZE).generate(path, workers=1, block_columns=BLOCK)
    return path


def _files(path: Path) -> dict[str, bytes]:
    """Every file of a store (temporary files a killed task may leave aside)."""
    out = {}
    for p in sorted(path.rglob("*")):
        if p.is_file() and not p.name.startswith(".") and not p.name.endswith(".partial"):
            out[str(p.relative_to(path))] = p.read_bytes()
    return out


def _assert_same_store(a: Path, b: Path):
    fa, fb = _files(a), _files(b)
    assert sorted(fa) == sorted(fb)
    differ = [k for k in fa if fa[k] != fb[k]]
    assert not differ, differ


def test_two_workers_make_the_serial_world_byte_for_byte(cluster, serial, tmp_path):
    address, client = cluster
    seen = []
    path = tmp_path / "w.zarr"
    store = World(CFG, size=SIZE).generate(path, scheduler=address, block_columns=BLOCK,
                                           progress=lambda d, t: seen.append((d, t)))
    assert store.complete and len(store) == 16
    assert seen[-1] == (16, 16) and len(seen) == 16
    _assert_same_store(serial, path)
    # and both workers took part
    assert len(client.scheduler_info(n_workers=-1)["workers"]) == 2


def test_a_killed_worker_costs_only_its_tasks(cluster, serial, tmp_path):
    address, client = cluster
    killed = []

    def kill_one(done, total):
        if killed:
            return
        busy = {w: ks for w, ks in client.processing().items() if ks}
        if not busy:
            return
        victim = sorted(busy)[0]
        pids = client.run(os.getpid, workers=[victim])
        os.kill(pids[victim], signal.SIGKILL)
        killed.append((victim, len(busy[victim])))

    path = tmp_path / "w.zarr"
    store = World(CFG, size=SIZE).generate(path, scheduler=address, block_columns=BLOCK,
                                           progress=kill_one)
    assert killed and killed[0][1] >= 1  # the worker died holding a task
    assert store.complete
    _assert_same_store(serial, path)


def test_resume_completes_an_interrupted_store(serial, tmp_path):
    path = tmp_path / "w.zarr"

    def interrupt(done, total):
        if done == 5:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        World(CFG, size=SIZE).generate(path, workers=1, block_columns=BLOCK,
                                       progress=interrupt)
    part = open_world(path)
    assert not part.complete and len(part.missing()) == 11
    # a missing chunk reads as not written (height -1), a written one in full
    assert (part[48:64, 48:64].height == -1).all()
    assert (part[0:16, 0:16].height >= 0).all()
    with pytest.raises(SylvaError, match="not empty"):
        World(CFG, size=SIZE).generate(path, workers=1, block_columns=BLOCK)
    with pytest.raises(SylvaError, match="cannot resume"):
        World(WorldConfig(seed=22, chunk_size=16), size=SIZE).generate(
            path, workers=1, block_columns=BLOCK, resume=True)
    done = []
    store = World(CFG, size=SIZE).generate(path, workers=1, block_columns=BLOCK, resume=True,
                                           progress=lambda d, t: done.append(d))
    assert done[0] == 6 and done[-1] == 16  # only the 11 missing blocks were generated
    assert store.complete
    _assert_same_store(serial, path)


def test_a_slice_equals_the_region_generated_alone(serial, tmp_path):
    full = open_world(serial)
    region = full[16:48, 16:48]
    alone = World(CFG, size=(32, 32), origin=(16, 16)).generate(tmp_path / "a.zarr", workers=1)
    whole = alone[:, :]
    np.testing.assert_array_equal(region.voxels, whole.voxels)
    np.testing.assert_array_equal(region.height, whole.height)
    np.testing.assert_array_equal(region.biome, whole.biome)
    assert region.voxels.shape == (32, CFG.height, 32)

    def rows(t):
        cols = ["model", "x", "y", "z", "yaw", "column_x", "column_z"]
        return sorted(zip(*(t.column(c).to_pylist() for c in cols)))

    a, b = rows(region.plants()), rows(whole.plants())
    assert len(a) > 10 and a == b


def test_store_table_and_manifest(serial):
    store = open_world(serial)
    m = store.manifest
    assert m["format"] == "sylva-world" and m["complete"] and m["size"] == [64, 64]
    assert m["versions"]["zarr"].startswith("3.")
    t = store.plants()
    assert t.num_rows == store.n_plants > 0
    assert {"model", "x", "y", "z", "yaw", "scale", "biome", "stage"} <= set(t.column_names)
    stages = dict(zip(t.column("model").to_pylist(), t.column("stage").to_pylist()))
    for key, stage in stages.items():
        if key.startswith("shrub_"):
            assert stage == int(key.split("#")[1]) % 3
        else:
            assert stage == -1
    with pytest.raises(SylvaError, match="outside the world"):
        store[0:65, 0:8]
    with pytest.raises(SylvaError, match="not a sylva world store"):
        open_world(serial / "voxels")


def test_bad_scheduler_address():
    with pytest.raises(SylvaError, match="tcp://HOST:PORT"), connect("localhost-8786"):
        pass
    with pytest.raises(SylvaError, match="at least 1"), connect(workers=0):
        pass


def test_a_killed_client_leaves_a_store_that_resume_completes(serial, tmp_path):
    """The generating process is SIGKILLed mid-run (no cleanup of any kind): the chunks it
    finished stay, a half-written one is not counted, and --resume completes the store
    into the serial one, byte for byte."""
    import subprocess
    import sys
    import time

    path = tmp_path / "w.zarr"
    code = ("from sylva.world import World, WorldConfig; "
            f"World(WorldConfig(seed={CFG.seed}, chunk_size={CFG.chunk_size}), "
            f"size={SIZE}).generate({str(path)!r}, workers=1, block_columns={BLOCK})")
    proc = subprocess.Popen([sys.executable, "-c", code], env={**os.environ,
                            "PYTHONPATH": str(Path(__file__).parents[2] / "src")})  # fmt: skip
    try:
        deadline = time.monotonic() + 240
        while time.monotonic() < deadline and proc.poll() is None:
            if len(list((path / "done").glob("b_*.json"))) >= 4:
                break
            time.sleep(0.02)
        assert proc.poll() is None, "the run ended before it could be killed"
        os.kill(proc.pid, signal.SIGKILL)
    finally:
        proc.wait(timeout=60)
    part = open_world(path)
    left = len(part.missing())
    assert not part.complete and 0 < left <= 12
    store = World(CFG, size=SIZE).generate(path, workers=1, block_columns=BLOCK, resume=True)
    assert store.complete
    _assert_same_store(serial, path)


def test_a_full_disk_leaves_a_store_that_resume_completes(serial, tmp_path, monkeypatch):
    """The disk fills while the 6th block writes its tables (ENOSPC from the Parquet
    writer): the run stops with that error, the block is not counted, and a resumed run
    completes the store into the serial one."""
    import errno

    import pyarrow.parquet as pq

    real = pq.write_table
    calls = []

    def full(*args, **kwargs):
        calls.append(1)
        if len(calls) == 11:  # two tables a block: the 6th block's first
            raise OSError(errno.ENOSPC, "No space left on device")
        return real(*args, **kwargs)

    monkeypatch.setattr(pq, "write_table", full)
    path = tmp_path / "w.zarr"
    with pytest.raises(OSError, match="No space left"):
        World(CFG, size=SIZE).generate(path, workers=1, block_columns=BLOCK)
    monkeypatch.setattr(pq, "write_table", real)
    part = open_world(path)
    assert not part.complete and len(part.missing()) == 11
    store = World(CFG, size=SIZE).generate(path, workers=1, block_columns=BLOCK, resume=True)
    assert store.complete
    _assert_same_store(serial, path)


def test_batch_renders_in_the_worker_processes(cluster, tmp_path):
    """``sylva batch`` on the 2-process cluster: every worker renders with its own GL
    context (made in that process); the files (GLB, render, mask, depths, COCO) equal those
    of the in-process run, byte for byte."""
    import pyarrow.parquet as pq

    from sylva.batch import parse_plan, run_batch

    address, client = cluster
    plan = parse_plan('[output]\nformats = ["glb"]\nsize = [48, 32]\n[[plant]]\n'
                      'source = "abop-1.24a-plant"\nseeds = [1]\nsteps = [1, 2, 3, 4]\n'
                      'cameras = [{yaw = 30, pitch = 20}]\n')  # fmt: skip
    from distributed import get_task_stream

    a = run_batch(plan, tmp_path / "a", workers=1, labels=True)
    with get_task_stream(client) as ts:
        b = run_batch(plan, tmp_path / "b", scheduler=address, labels=True)
    assert a["files"] == b["files"] == 4 * 6  # glb, render, mask, 2 depths, coco
    for r in pq.read_table(a["manifest"]).to_pylist():
        assert (tmp_path / "a" / r["path"]).read_bytes() == (
            tmp_path / "b" / r["path"]).read_bytes(), r["path"]
    # both workers rendered (each in its own context)
    assert len({t["worker"] for t in ts.data if "_item_task" in str(t["key"])}) == 2
