"""A mature quaking aspen from parameters to mesh, and the contact sheet of every species.

Run: ``PYTHONPATH=src python benchmarks/tree.py [--runs N] [--sheet] [--all]``.  Prints the
median and best of N warm runs of ``Tree("quaking_aspen", seed=7).grow().mesh()`` (the
first run, which imports and compiles, is reported apart), and with ``--sheet`` the time of
``sylva tree --sheet`` (every species at three ages, rendered).  The CPU time of the process
is printed beside the wall clock: on a loaded machine the wall clock mostly measures others.
``--all`` also grows every shipped species at its mature age (``Age``), warm (one run
first, then ``--runs`` timed ones), and prints the median CPU time of each and the slowest
(the issue's target: every species under 1 s); ``--species NAME`` (repeatable) does the
same for the named species only.

Before each timed run the previous tree's garbage is collected (``gc.collect()``, outside
the timing; its median is printed apart as the teardown): a tree is a graph of some 60,000
objects with reference cycles (parents and children), which Python frees only in a full
collection, and that collection comes when it comes -- in one run out of several, inside
the next tree's time, and the bigger the more trees have piled up (0.3--0.6 s of CPU
measured for the willow), which made the medians of two runs swing by up to 1.6x.
"""

import argparse
import gc
import statistics
import time

from sylva.tree import Tree


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--sheet", action="store_true")
    ap.add_argument("--all", action="store_true", help="every species at its mature age")
    ap.add_argument("--species", action="append", default=[], metavar="NAME",
                    help="this species at its mature age, as --all times each (repeatable)")
    a = ap.parse_args()
    times, cpu = [], []
    tree = None
    for i in range(a.runs + 1):
        tree = None
        gc.collect()  # the previous tree's garbage (see the module's docstring)
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
    if a.all or a.species:
        from sylva.tree import species_names

        worst = ("", 0.0)
        for name in species_names() if a.all else a.species:
            cpu_s, gc_s, leaves = [], [], 0
            t = None
            for i in range(a.runs + 1):
                t = None
                g = time.process_time()
                gc.collect()  # the previous tree's teardown, timed apart
                c = time.process_time()
                t = Tree(name, seed=7)
                t.grow().mesh()
                if i:
                    cpu_s.append(time.process_time() - c)
                    gc_s.append(c - g)
            leaves = t.stats()["leaves"]
            med = statistics.median(cpu_s)
            worst = max(worst, (name, med), key=lambda x: x[1])
            print(f"  {name:20s} {leaves:6d} leaves  CPU median {med:.2f} s "
                  f"(min {min(cpu_s):.2f}, max {max(cpu_s):.2f}; teardown "
                  f"{statistics.median(gc_s):.2f} s)")
        print(f"slowest mature species: {worst[0]} {worst[1]:.2f} s CPU over {a.runs} runs")
    if a.sheet:
        from sylva.cli._tree_sheet import contact_sheet

        t, c = time.perf_counter(), time.process_time()
        img = contact_sheet()
        print(f"contact sheet {img.size[0]}x{img.size[1]}: {time.perf_counter() - t:.1f} s, "
              f"CPU time {time.process_time() - c:.1f} s")


if __name__ == "__main__":
    main()
