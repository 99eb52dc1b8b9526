"""The world benchmark runs and prints its figures (a tiny world; no timings asserted)."""

import runpy
from pathlib import Path

BENCH = Path(__file__).resolve().parents[2] / "benchmarks" / "world.py"


def test_benchmark_smoke(capsys):
    main = runpy.run_path(str(BENCH))["main"]
    assert main(["--size", "48x32", "--chunk", "16", "--sample", "2", "--workers", "1",
                 "--block", "16"]) == 0
    out = capsys.readouterr().out
    for label in ("before :", "serial :", "block  :", "sync   :", "dask 1 :", "speed-up",
                  "overhead:"):
        assert label in out
    assert "chunks/s" in out and "M blocks/s" in out and "peak RSS" in out
    assert "task " in out and "CPU " in out and "ms/chunk" in out
