"""Several processes compiling into one numba cache (``sylva warmup``'s workers, the suite
on ``pytest -n 2``): each signature's cached code stays its own."""

import json
import os
import subprocess
import sys
from pathlib import Path

import sylva

SRC = str(Path(sylva.__file__).parent.parent)

KERNEL = """from numba import njit


@njit(cache=True)
def step(x):
    return x + 1
"""

# Both processes reach numba's save together (a barrier of two files), and each waits a
# second between reading the index and writing it: unlocked, both would read an empty
# index, both take data file 1 and the index keeps one signature.
_SAVE = """
import os, sys, time
from pathlib import Path
sys.path.insert(0, sys.argv[1])
import sylva  # every sylva process locks its cache saves, once numba is imported
from numba.core import caching
locked, write_index = caching.IndexDataCacheFile.save, caching.IndexDataCacheFile._save_index
me, other = Path(sys.argv[2]), Path(sys.argv[3])

def slow_index(self, overloads):
    time.sleep(1.0)
    write_index(self, overloads)

def together(self, key, data):
    me.touch()
    deadline = time.monotonic() + 120
    while not other.exists() and time.monotonic() < deadline:
        time.sleep(0.01)
    locked(self, key, data)

caching.IndexDataCacheFile._save_index = slow_index
caching.IndexDataCacheFile.save = together
import kern
print(kern.step(int(sys.argv[4])) if sys.argv[4] == "1" else kern.step(float(sys.argv[4])))
"""

_LOAD = """
import json, sys
sys.path.insert(0, sys.argv[1])
import kern
values = [kern.step(1), kern.step(2.5)]
print(json.dumps({"values": values, "hits": sorted(map(str, kern.step.stats.cache_hits)),
                  "misses": sorted(map(str, kern.step.stats.cache_misses))}))
"""


def test_two_processes_saving_two_signatures_of_one_kernel_keep_both(tmp_path):
    (tmp_path / "kern.py").write_text(KERNEL, encoding="utf-8")
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path / "cache"),
               PYTHONPATH=SRC + os.pathsep + os.environ.get("PYTHONPATH", ""))  # fmt: skip
    env.pop("NUMBA_DISABLE_JIT", None)
    a, b = tmp_path / "a", tmp_path / "b"
    procs = []
    for me, other, arg in ((a, b, "1"), (b, a, "2.5")):
        cmd = [sys.executable, "-c", _SAVE, str(tmp_path), str(me), str(other), arg]
        procs.append(subprocess.Popen(cmd, env=env, stdout=subprocess.PIPE,
                                      stderr=subprocess.PIPE, text=True))  # fmt: skip
    outs = [p.communicate(timeout=300) for p in procs]
    for p, (_, err) in zip(procs, outs):
        assert p.returncode == 0, err
    assert [o.strip() for o, _ in outs] == ["2", "3.5"]
    # a third process loads both signatures from the cache, each with its own code
    load = subprocess.run([sys.executable, "-c", _LOAD, str(tmp_path)], env=env,
                          capture_output=True, text=True, timeout=300)  # fmt: skip
    assert load.returncode == 0, load.stderr
    got = json.loads(load.stdout)
    assert got["values"] == [2, 3.5]
    # nothing compiled: both came from the cache (unlocked, one of them is lost)
    assert got == {"values": [2, 3.5], "hits": ["(float64,)", "(int64,)"], "misses": []}


_ORDER = """
import sys
sys.path.insert(0, sys.argv[1])
if sys.argv[2] == "numba first":
    import numba
import sylva
assert sys.argv[2] == "numba first" or "numba" not in sys.modules  # no import for the lock
from numba.core import caching
print(getattr(caching.IndexDataCacheFile.save, "_sylva_serialised", False))
"""


def test_every_sylva_process_locks_its_saves_whenever_numba_comes():
    env = dict(os.environ, PYTHONPATH=SRC + os.pathsep + os.environ.get("PYTHONPATH", ""))
    for order in ("numba first", "sylva first"):
        run = subprocess.run([sys.executable, "-c", _ORDER, SRC, order], env=env,
                             capture_output=True, text=True, timeout=120)  # fmt: skip
        assert run.returncode == 0, run.stderr
        assert run.stdout.strip() == "True", order


_FAILING = """
import sys, warnings
sys.path.insert(0, sys.argv[1])
from sylva import _jit
def broken():
    raise OSError("no cache folder")
_jit.after_numba(broken)
with warnings.catch_warnings(record=True) as seen:
    warnings.simplefilter("always")
    import numba
print(numba.__name__, [str(w.message) for w in seen if "broken" in str(w.message)])
"""


def test_a_failing_after_numba_hook_warns_and_numba_still_imports():
    env = dict(os.environ, PYTHONPATH=SRC + os.pathsep + os.environ.get("PYTHONPATH", ""))
    run = subprocess.run([sys.executable, "-c", _FAILING, SRC], env=env,
                         capture_output=True, text=True, timeout=120)  # fmt: skip
    assert run.returncode == 0, run.stderr
    assert run.stdout.startswith("numba ")  # imported
    assert "sylva: broken after numba's import failed: no cache folder" in run.stdout
