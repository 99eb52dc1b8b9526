"""A mature quaking aspen from parameters to mesh, and the contact sheet of every species.

Run: ``PYTHONPATH=src python benchmarks/tree.py [--runs N] [--sheet]``.  Prints the median and
best of N warm runs of ``Tree("quaking_aspen", seed=7).grow().mesh()`` (the first run, which
imports and compiles, is reported apart), and with ``--sheet`` the time of
``sylva tree --sheet`` (every species at three ages, rendered).  The CPU time of the process
is printed beside the wall clock: on a loaded machine the wall clock mostly measures others.
"""

import argparse
import statistics
import time

from sylva.tree import Tree


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--sheet", action="store_true")
    a = ap.parse_args()
    times, cpu = [], []
    for i in range(a.runs + 1):
        t, c = time.perf_counter(), time.process_time()
        tree = Tree("quaking_aspen", seed=7).grow()
        tm = tree.mesh()
        dt, dc = time.perf_counter() - t, time.process_time() - c
        if i == 0:
            print(f"first run {dt:.2f} s")
        else:
            times.append(dt)
            cpu.append(dc)
    s = tree.stats()
    print(f"mature quaking aspen: {s['leaves']} leaves, {sum(s['stems'])} stems, "
          f"{tm.mesh.n_triangles} triangles; warm median {statistics.median(times):.2f} s, "
          f"best {min(times):.2f} s over {len(times)} runs; CPU time median "
          f"{statistics.median(cpu):.2f} s (a shared machine's wall clock waits for others)")
    if a.sheet:
        from sylva.cli._tree_sheet import contact_sheet

        t = time.perf_counter()
        img = contact_sheet()
        print(f"contact sheet {img.size[0]}x{img.size[1]}: {time.perf_counter() - t:.1f} s")


if __name__ == "__main__":
    main()
