"""Cold start: what ``import sylva`` loads, the compile message and ``sylva warmup``."""

import json
import os
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
