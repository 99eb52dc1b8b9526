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
    # (the graph runs its float32 lattice rows a block at a time, as noise_grid does)
    assert gk32._lat_rows.signatures and _sampling.fractal_at.signatures
    assert _literal(gk32._lat_rows) == []
    assert _literal(_sampling.fractal_at) == []


def test_structural_arguments_are_typed_not_literal():
    assert _Emit.i(3) == "np.int64(3)"
    assert _Emit.b(1) == "np.bool_(True)" and _Emit.b(False) == "np.bool_(False)"


def test_generated_sources_name_the_texture_kernels_they_call(tmp_path):
    # numba's cache of a generated graph module does not notice a change in the grid
    # kernels it calls: the generated source carries a hash of the texture package's
    # sources, so an upgraded sylva writes (and compiles) new files instead of running an
    # old file's cached code with the old kernels inlined
    g = tg.Graph(tg.fbm(kind="perlin", scale=3.0, octaves=2, seed=4))
    em = _compile._Emit(g, (4, 16), np.float32)
    src = em.source([em.emit(g.output, None)], False)
    assert _compile._stamp() in src.splitlines()
    for name, text in (("a.py", "x = 1\n"), ("sub/b.py", "y = 2\n")):
        (tmp_path / name).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / name).write_text(text, encoding="utf-8")
    before = _compile._sources_hash(tmp_path)
    assert _compile._sources_hash(tmp_path) == before  # the same sources, the same files
    (tmp_path / "sub/b.py").write_text("y = 3\n", encoding="utf-8")  # one kernel changed
    assert _compile._sources_hash(tmp_path) != before
