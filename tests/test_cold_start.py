"""Cold start: what ``import sylva`` loads, the compile message and ``sylva warmup``."""

import io
import json
import os
import re
import subprocess
import sys
from pathlib import Path

import sylva

SRC = str(Path(sylva.__file__).parent.parent)


def _python(code: str, **env) -> subprocess.CompletedProcess:
    e = dict(os.environ, PYTHONPATH=SRC + os.pathsep + os.environ.get("PYTHONPATH", ""), **env)
    return subprocess.run([sys.executable, "-c", code], env=e, capture_output=True, text=True,
                          timeout=600)


def test_import_sylva_loads_no_numba_gl_or_server():
    code = (
        "import json, sys, sylva\n"
        "print(json.dumps(sorted(m for m in sys.modules if m.split('.')[0] in "
        "('numba', 'llvmlite', 'moderngl', 'scipy', 'starlette', 'uvicorn', 'PIL') "
        "or m.endswith(('_kernels', '_gridkernels', '_cellkernels', '_simd')))))\n"
    )
    proc = _python(code)
    assert proc.returncode == 0, proc.stderr
    assert json.loads(proc.stdout) == []


def test_lazy_kernels_load_on_first_use():
    # a derivation that needs a compiled kernel (context-sensitive) imports it then
    code = (
        "import sys, sylva\n"
        "w = sylva.derive(sylva.loads('axiom = baaa\\nb < a -> b'), 2)\n"
        "print(w.to_text(), 'sylva.lsystem._kernels' in sys.modules)\n"
    )
    proc = _python(code)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.split() == ["bbba", "True"]


_RASTER = (
    "import numpy as np\n"
    "from sylva._jit import announce\n"
    "announce()\n"  # before numba is imported: the message must still come
    "from sylva.texture import _raster\n"
    "rgb = np.zeros((8, 8, 3)); alpha = np.zeros((8, 8)); z = np.zeros(1)\n"
    "_raster.draw_segments(rgb, alpha, z, z, z + 4, z + 4, z + 1, np.ones((1, 3)), False)\n"
    "print(round(float(alpha.sum()), 6))\n"
)


def test_a_first_run_says_once_that_it_compiles(tmp_path):
    cache = str(tmp_path / "numba-cache")
    first = _python(_RASTER, NUMBA_CACHE_DIR=cache)
    assert first.returncode == 0, first.stderr
    lines = [ln for ln in first.stderr.splitlines() if "compiling" in ln]
    # a file, not a terminal: one line per kernel module, with the count of its kernels
    assert len(lines) == 1
    assert re.fullmatch(
        r"sylva: compiling sylva's texture kernels, once: 1/\d+ \(a first run compiles what "
        r"it uses and caches it; `sylva warmup` compiles everything ahead\)", lines[0]
    )
    second = _python(_RASTER, NUMBA_CACHE_DIR=cache)
    assert second.returncode == 0, second.stderr
    assert "compiling" not in second.stderr  # loaded from the cache: nothing to say
    assert second.stdout == first.stdout and float(first.stdout) > 0


def test_the_message_counts_a_terminal_line_up(tmp_path):
    from sylva._jit import _Progress

    class Tty(io.StringIO):
        def isatty(self):
            return True

    class Dispatcher:
        def __init__(self, name):
            def f():
                pass

            f.__module__ = "sylva.lsystem._kernels"
            f.__qualname__ = f.__name__ = name
            self.py_func = f

    out = Tty()
    prog = _Progress(out)
    for name in ("a", "b", "a"):  # a kernel compiled again (another signature) counts once
        prog.start(Dispatcher(name))
    prog.finish()
    text = out.getvalue()
    assert "\rcompiling sylva's derivation kernels, once: 1/" in text
    assert "\rcompiling sylva's derivation kernels, once: 2/" in text
    assert "once: 3/" not in text
    assert text.endswith("(cached now)\x1b[K\n")


def test_warmup_compiles_ahead_so_that_the_command_compiles_nothing(tmp_path):
    cache = tmp_path / "numba-cache"
    env = {"NUMBA_CACHE_DIR": str(cache)}
    warm = _python("from sylva.cli import main; raise SystemExit(main(['warmup', '--only', "
                   "'derivation', '--jobs', '1']))", **env)
    assert warm.returncode == 0, warm.stderr
    lines = warm.stderr.splitlines()
    assert lines[0].startswith("sylva warmup: compiling sylva's kernels once, 1 groups on 1 ")
    assert re.fullmatch(r"  \[1/1\] derivation (\d+) kernels compiled in [\d.]+ s - .*", lines[1])
    assert int(lines[1].split()[2]) >= 3
    assert lines[-1].startswith("sylva warmup: done in ")
    # what it compiled is in the cache: the derivation kernels' index files (the examples
    # that grow in a world environment also compile the terrain's noise)
    index = [p.name for p in cache.rglob("*.nbi")]
    assert any(n.startswith("_kernels.rewrite") for n in index)
    # and a command that uses them now loads them: no compile message
    run = _python("from sylva.cli import main; raise SystemExit(main(['derive', "
                  "'18-abop-1.31a-hogeweg', '-n', '4']))", **env)
    assert run.returncode == 0, run.stderr
    assert run.stdout.strip() and "compiling" not in run.stderr


def test_warmup_names_an_unknown_group():
    proc = _python("from sylva.cli import main; raise SystemExit(main(['warmup', '--only', "
                   "'derivatoin']))")
    assert proc.returncode == 2
    assert "unknown group derivatoin; expected one of derivation, plants" in proc.stderr


# ------------------------------------------------------------------ the interpreted road
_COLD_SMALL = (
    "import json, collections\n"
    "from numba.core import event\n"
    "seen = collections.Counter()\n"
    "class L(event.Listener):\n"
    "    def on_start(self, ev):\n"
    "        seen[ev.data['dispatcher'].py_func.__module__] += 1\n"
    "    def on_end(self, ev):\n"
    "        pass\n"
    "event.register('numba:compile', L())\n"
    "from sylva.plant import grow\n"
    "out = {}\n"
    "for name in ('01-koch-snowflake', '18-abop-1.31a-hogeweg', '32-abop-2.10-parametric',\n"
    "             '24-seed000-bush-leaves', '40-sylva-topiary-query'):\n"
    "    p = grow(name)\n"
    "    out[name] = [len(p.word), p.scene.n_triangles]\n"
    "print(json.dumps({'compiled': sorted(m for m in seen if m.startswith('sylva')),\n"
    "                  'plants': out}))\n"
)


def test_small_work_on_a_cold_cache_runs_interpreted_and_compiles_nothing(tmp_path):
    # a fresh install: the first plants come at once (the kernels' own Python source),
    # instead of after tens of seconds of compiling (issue 25)
    proc = _python(_COLD_SMALL, NUMBA_CACHE_DIR=str(tmp_path / "numba-cache"))
    assert proc.returncode == 0, proc.stderr
    got = json.loads(proc.stdout)
    assert got["compiled"] == []
    # and the plants are the plants: ABOP's figures' word sizes (the seeds' own tests pin
    # the words), with meshes
    assert got["plants"]["01-koch-snowflake"][0] == 1792
    assert all(tris > 0 for _, tris in got["plants"].values())
    assert not list((tmp_path / "numba-cache").rglob("*.nbi"))  # nothing was cached


def test_a_first_render_on_a_cold_cache_says_nothing_about_compiling(tmp_path):
    out = tmp_path / "k.png"
    proc = _python("from sylva.cli import main; raise SystemExit(main(['render', "
                   f"'01-koch-snowflake', '--size', '64x48', '-o', {str(out)!r}]))",
                   NUMBA_CACHE_DIR=str(tmp_path / "numba-cache"))  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    assert "compiling" not in proc.stderr and out.stat().st_size > 0


# (example, steps): every kind of word the turtle and the mesh builder meet — 2D, 3D with
# leaves, polygons, parametric, context-sensitive, stochastic, tropism, query modules,
# seed 004's engine turtle, blocks — kept small, the interpreted road is slow
_ROADS = [
    ("01-koch-snowflake", 3), ("09-seed000-hilbert-3d", None), ("18-abop-1.31a-hogeweg", 12),
    ("24-seed000-bush-leaves", 3), ("25-seed000-bush-stochastic", 3),
    ("29-seed004-acacia", None), ("32-abop-2.10-parametric", None), ("33-sylva-fern", 4),
    ("34-sylva-flowering-herb", None), ("39-abop-2.8d-ternary-tree", 4),
    ("40-sylva-topiary-query", 6), ("14-abop-1.24e-plant", 3),
]


def test_the_interpreted_road_equals_the_compiled_road(monkeypatch):
    import numpy as np

    from sylva.plant import grow

    for name, steps in _ROADS:
        monkeypatch.setenv("SYLVA_JIT", "never")
        a = grow(name, steps)
        monkeypatch.setenv("SYLVA_JIT", "always")
        b = grow(name, steps)
        assert a.word.to_text() == b.word.to_text(), name
        assert [m.name for m in a.scene.meshes] == [m.name for m in b.scene.meshes], name
        for ma, mb in zip(a.scene.meshes, b.scene.meshes, strict=True):
            for attr in ("vertices", "normals", "uvs", "colors", "indices", "material_ids"):
                x, y = getattr(ma, attr), getattr(mb, attr)
                assert (x is None) == (y is None), (name, attr)
                if x is None:
                    continue
                assert x.shape == y.shape and x.dtype == y.dtype, (name, attr)
                if x.dtype.kind == "f":
                    # the compiled rings fuse multiply-adds in float32 (a rounding or two)
                    np.testing.assert_allclose(x, y, rtol=1e-6, atol=1e-6, err_msg=name)
                else:
                    np.testing.assert_array_equal(x, y, err_msg=f"{name} {attr}")


_TOY = '''
import numpy as np
from numba import njit

@njit(cache=True)
def total(a):
    s = 0.0
    for x in a:
        s += x
    return s
'''


def test_a_road_runs_small_calls_interpreted_until_the_kernel_compiles(tmp_path, monkeypatch):
    import importlib

    import numpy as np

    from sylva import _jit

    (tmp_path / "toyroad_kernels.py").write_text(_TOY)
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.delenv("SYLVA_JIT", raising=False)
    real = importlib.import_module("toyroad_kernels")
    k = _jit.road("toyroad_kernels", size=10)
    assert k.total(np.ones(5)) == 5.0 and not real.total.signatures  # interpreted
    with _jit.compiled():
        assert k.total(np.ones(5)) == 5.0 and real.total.signatures  # compiled on demand
    assert k.total(np.ones(3)) == 3.0  # compiled now: the compiled road from here on

    (tmp_path / "toyroad2_kernels.py").write_text(_TOY)
    real2 = importlib.import_module("toyroad2_kernels")
    k2 = _jit.road("toyroad2_kernels", size=10)
    assert k2.total(np.ones(50)) == 50.0 and real2.total.signatures  # large: compiles

    (tmp_path / "toyroad3_kernels.py").write_text(_TOY)
    real3 = importlib.import_module("toyroad3_kernels")
    k3 = _jit.road("toyroad3_kernels")  # a module road: small() decides
    with _jit.small(True):
        assert k3.total(np.ones(4)) == 4.0 and not real3.total.signatures
        assert _jit.interpreting(k3, "total")
    with _jit.small(False):
        assert k3.total(np.ones(4)) == 4.0 and real3.total.signatures
        assert not _jit.interpreting(k3, "total")
