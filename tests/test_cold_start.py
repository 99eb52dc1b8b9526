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
    # what it compiled is in the cache: the derivation kernels' index files
    index = [p.name for p in cache.rglob("*.nbi")]
    assert index and all(n.startswith("_kernels.") for n in index)
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
