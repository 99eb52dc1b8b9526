"""A texture graph's fused kernel calls the row and point kernels that ``noise_grid`` uses,
with the same types: numba then loads them from the cache ``sylva warmup`` filled instead
of compiling a copy per graph (issue 25: a constant argument such as ``f(2, x)`` made numba
compile ``f`` and its callees once per value, 74 copies and 60 CPU s in the graph tests)."""

import numba
import numpy as np

from sylva.texture import _gridkernels32 as gk32
from sylva.texture import _sampling
from sylva.texture import graph as tg
from sylva.texture.graph import _compile
from sylva.texture.graph._compile import _Emit


def _literal(dispatcher) -> list[str]:
    return [str(sig) for sig in dispatcher.signatures if "Literal" in str(sig)]


def test_graph_kernels_call_the_noise_kernels_without_literal_copies():
    # a row road (float32 lattice fBm on the image grid) and a point road (a warped fBm
    # samples fractal_at per pixel), each equal to what noise_grid / fbm give
    flat = tg.Graph(tg.fbm(kind="perlin", scale=3.0, octaves=2, seed=4))
    warped = tg.Graph(tg.fbm(kind="value", scale=3.0, octaves=2, seed=4, warp=0.5))
    # the compiled road (a small image on a cold kernel would run it as Python)
    a = _compile.evaluate(flat, (4, 16), np.float32, road="compiled")
    b = _compile.evaluate(warped, (4, 16), np.float64, road="compiled")
    assert a.shape == b.shape == (4, 16) and np.isfinite(a).all() and np.isfinite(b).all()
    # the fused kernels may come from numba's disk cache (an earlier run, sylva warmup), and
    # then their callees are never typed in this process: type each once more, uncached
    for g, dtype in ((flat, np.float32), (warped, np.float64)):
        em = _compile._Emit(g, (4, 16), dtype)
        kernel = _compile._load(em.source([em.emit(g.output, None)], False))
        assert kernel.signatures  # evaluate() ran it
        numba.njit(nogil=True, error_model="numpy")(kernel.py_func).compile(kernel.signatures[0])
    assert gk32.row_lattice32.signatures and _sampling.fractal_at.signatures
    assert _literal(gk32.row_lattice32) == []
    assert _literal(_sampling.fractal_at) == []


def test_structural_arguments_are_typed_not_literal():
    assert _Emit.i(3) == "np.int64(3)"
    assert _Emit.b(1) == "np.bool_(True)" and _Emit.b(False) == "np.bool_(False)"
