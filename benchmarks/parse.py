"""Parsing speed of the ``.lsys`` reader on large generated files, in MB/s.

    python benchmarks/parse.py [--mb MB] [--repeat N] [names ...]

Issue 23: 80,000 assignments took 37 s and a 67 MB file did not finish in 4 min 40 s,
because the hint of an unknown-variable error copied every known name on every line.
Each row reads a generated file of about ``--mb`` megabytes and prints the median of
``--repeat`` reads.  Literal assignments, the common case, get the whole ``--mb`` (50 MB by
default); the rows that go through the LALR parser (about 10,000 lines a second) get a
fiftieth of it.  Wall and CPU seconds are both printed: on a shared machine the CPU time is
the steadier figure (MB/s is by wall time).  Reading is linear: the ``x2`` column is the CPU
time for the file divided by the CPU time for a file half its size, about 2.0 when linear
and about 4 when quadratic.
"""

from __future__ import annotations

import argparse
import statistics
import time

from sylva.lsystem.dialects import lsysvis


def literals(n: int) -> str:
    return "\n".join(f"v{i} = {i}.25" for i in range(n)) + "\naxiom = F\nF -> F(v1)\n"


def expressions(n: int) -> str:
    lines = ["v0 = 1"] + [f"v{i} = v{i - 1} * 0.5 + {i}" for i in range(1, n)]
    return "\n".join(lines) + "\naxiom = F\n"


def rules(n: int) -> str:
    lines = ["g = 2", "axiom = A(1)"]
    lines += [f"A(x) : x > {i} -> A(x + g)[+F(x / g)]" for i in range(n)]
    return "\n".join(lines) + "\n"


ROWS = {
    # name: (generator, bytes per line (about), share of --mb, label)
    "literals": (literals, 21, 1.0, "name = number assignments"),
    "expressions": (expressions, 30, 0.02, "name = expression assignments"),
    "rules": (rules, 40, 0.02, "parametric rules with a condition"),
}


def measure(make, n: int, repeat: int) -> tuple[float, float, int]:
    """Median wall and CPU seconds of reading ``make(n)``, and its size in bytes."""
    text = make(n)
    wall, cpu = [], []
    for _ in range(repeat):
        t, c = time.perf_counter(), time.process_time()
        lsysvis.parse(text)
        wall.append(time.perf_counter() - t)
        cpu.append(time.process_time() - c)
    return statistics.median(wall), statistics.median(cpu), len(text.encode())


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--mb", type=float, default=50.0)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("names", nargs="*", default=list(ROWS))
    args = ap.parse_args()
    lsysvis.parse("axiom = F\nF -> F\n")  # build the grammar once
    print(f"{'file':34s} {'MB':>6s} {'lines':>8s} {'wall s':>7s} {'cpu s':>6s} {'MB/s':>6s} "
          f"{'x2':>5s}")  # fmt: skip
    for name in args.names:
        make, per_line, share, label = ROWS[name]
        n = max(int(args.mb * share * 1e6 / per_line), 10)
        sec, cpu, size = measure(make, n, args.repeat)
        _, half, _ = measure(make, n // 2, args.repeat)
        print(f"{label:34s} {size / 1e6:6.1f} {n:8d} {sec:7.2f} {cpu:6.2f} {size / 1e6 / sec:6.1f} "
              f"{cpu / half:5.2f}")  # fmt: skip
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
