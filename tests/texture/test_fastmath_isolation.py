"""The float64 road keeps its bits whatever compiled it first.

numba compiles a kernel that does not set ``fastmath`` with the flags of the kernel whose
compilation first reached it (the option is inherited when not set), and caches that code:
the float32 road's ``fastmath=True`` kernels call the float64 road's Worley search, and a
cache filled by ``sylva warmup`` with the float32 group first gave ``worley(0.3, 1.7,
seed=7)`` as 0.6920756412114424 instead of 0.6920756412114425 (``a*a + b*b`` contracted
into a fused multiply-add).  Every float64-road kernel therefore says ``fastmath=False``.
"""

from __future__ import annotations

import importlib

import pytest

FLOAT64_ROAD = ("_cellkernels", "_kernels", "_sampling", "_gridkernels", "_fractal_kernels",
                "_worleyn", "_raster")  # fmt: skip


@pytest.mark.parametrize("name", FLOAT64_ROAD)
def test_every_float64_kernel_sets_fastmath_off(name):
    from numba.core.registry import CPUDispatcher

    mod = importlib.import_module(f"sylva.texture.{name}")
    kernels = [v for v in vars(mod).values()
               if isinstance(v, CPUDispatcher) and v.py_func.__module__ == mod.__name__
               and v.targetoptions.get("inline", "never") != "always"]  # fmt: skip
    assert kernels
    loose = [k.py_func.__name__ for k in kernels if k.targetoptions.get("fastmath") is not False]
    assert not loose, f"{name}: kernels without fastmath=False: {loose}"
