"""A mature quaking aspen from parameters to mesh, and the contact sheet of every species.

Run: ``PYTHONPATH=src python benchmarks/tree.py [--runs N] [--sheet] [--all]``.  Prints the
median and best of N warm runs of ``Tree("quaking_aspen", seed=7).grow().mesh()`` (the
first run, which imports and compiles, is reported apart), and with ``--sheet`` the time of
``sylva tree --sheet`` (every species at three ages, rendered).  The CPU time of the process
is printed beside the wall clock: on a loaded machine the wall clock mostly measures others.
``--all`` also grows every shipped species at its mature age (``Age``), warm, and prints the
median CPU time of each and the slowest (the issue's target: every species under 1 s).
"""

import argparse
import statistics
import time

from sylva.tree import Tree


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--sheet", action="store_true")
    ap.add_argument("--all", action="store_true", help="every species at its mature age")
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
    if a.all:
        from sylva.tree import species_names

        worst = ("", 0.0)
        for name in species_names():
            cpu_s = []
            for i in range(3):
                c = time.process_time()
                t = Tree(name, seed=7)
                t.grow().mesh()
                if i:
                    cpu_s.append(time.process_time() - c)
            med = statistics.median(cpu_s)
            worst = max(worst, (name, med), key=lambda x: x[1])
            print(f"  {name:20s} {t.stats()['leaves']:6d} leaves  CPU median {med:.2f} s")
        print(f"slowest mature species: {worst[0]} {worst[1]:.2f} s CPU")
    if a.sheet:
        from sylva.cli._tree_sheet import contact_sheet

        t, c = time.perf_counter(), time.process_time()
        img = contact_sheet()
        print(f"contact sheet {img.size[0]}x{img.size[1]}: {time.perf_counter() - t:.1f} s, "
              f"CPU time {time.process_time() - c:.1f} s")


if __name__ == "__main__":
    main()
