"""Where a cold ``make test`` goes: ``sylva warmup``'s compiling, kernel by kernel, and the
test suite's time, module by module.

    python benchmarks/cold_test.py warmup [--cache DIR] [--top N] [--json FILE]
    python benchmarks/cold_test.py parallel [--cache DIR] [--top N] [-j N]
    python benchmarks/cold_test.py pytest [--cache DIR] [--top N] [--json FILE] [PYTEST ARGS]

``warmup`` runs ``sylva warmup``'s groups one after the other (in the order their waits
allow), each in a fresh interpreter on the Numba cache ``--cache`` (default: a new empty
folder, what CI's clean clone has), and records every ``numba:compile`` event: the CPU
seconds each kernel (and signature) took to compile, its own time without the kernels
compiled inside it.  One group at a time, so that CPU seconds are not shared with a
sibling; ``sylva warmup`` itself runs the groups on all cores, and its wall time on N cores
is about the longest chain of groups or the sum over N, whichever is larger.

``parallel`` runs ``sylva warmup --profile`` itself (all cores, or ``-j``) on the cache:
its wall and CPU seconds, each group's compiling, and any kernel that two worker
processes both compiled (work done twice).

``pytest`` runs the suite (or the PYTEST ARGS) on the cache ``--cache`` (run ``warmup``
first on the same folder) with a plugin that records each test's wall and CPU seconds
(its process's and its waited-for children's: POV-Ray, node, Blender, Chromium) and any
kernel compiled while the tests run (there should be none after the warm-up), then prints
the slowest modules and tests.  PYTEST ARGS such as ``-n 2 --dist loadfile`` run it on
pytest-xdist's workers (``make test``'s way): each worker's tests, time in tests and CPU
seconds are printed too.

The machine may be shared: ``uptime`` is printed before and after; CPU seconds are what
a loaded machine stretches least.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent

# Inside the child: one warm-up group with every numba:compile event recorded.
PROBE = r"""
import json, os, resource, sys, time
T0, C0 = time.perf_counter(), time.process_time()
events = []
from numba.core import event as ev
stack = []
class L(ev.Listener):
    def on_start(self, event):
        f = event.data["dispatcher"].py_func
        stack.append([time.process_time(), 0.0, f"{f.__module__}.{f.__qualname__}"])
    def on_end(self, event):
        t0, inner, _ = stack.pop()
        dt = time.process_time() - t0
        if stack:
            stack[-1][1] += dt
        f = event.data["dispatcher"].py_func
        events.append({"module": f.__module__, "name": f.__qualname__,
                       "args": str(event.data["args"]), "total": dt, "self": dt - inner,
                       "top": not stack, "parent": stack[-1][2] if stack else None,
                       "root": stack[0][2] if stack else None})
ev.register("numba:compile", L())
from sylva.cli.warmup import _run_group
name, n, secs, err, _ = _run_group(sys.argv[1])
kids = resource.getrusage(resource.RUSAGE_CHILDREN)
with open(os.environ["SYLVA_COLD_EVENTS"], "w") as fh:
    json.dump({"group": name, "compiled": n, "secs": secs, "error": err,
               "wall": time.perf_counter() - T0, "cpu": time.process_time() - C0,
               "children_cpu": kids.ru_utime + kids.ru_stime, "events": events}, fh)
"""


def uptime() -> str:
    try:
        return subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip()
    except OSError:
        return "?"


def _order() -> list[str]:
    from sylva.cli.warmup import GROUPS

    out: list[str] = []
    while len(out) < len(GROUPS):
        for n, (_, waits, _) in GROUPS.items():
            if n not in out and all(w in out for w in waits):
                out.append(n)
    return out


def warmup(cache: Path, top: int, as_json: str | None) -> None:
    from sylva.cli.warmup import GROUPS

    print(f"# {uptime()}")
    print(f"# NUMBA_CACHE_DIR={cache}; groups one at a time")
    groups, events = [], []
    with tempfile.TemporaryDirectory(prefix="sylva-coldtest-") as tmp:
        for name in _order():
            out = Path(tmp) / f"{name}.json"
            env = dict(os.environ, NUMBA_CACHE_DIR=str(cache), SYLVA_COLD_EVENTS=str(out))
            env.pop("NUMBA_DISABLE_JIT", None)
            t = time.perf_counter()
            proc = subprocess.run([sys.executable, "-c", PROBE, name], env=env,
                                  capture_output=True, text=True)  # fmt: skip
            if proc.returncode:
                raise SystemExit(f"group {name} failed:\n{proc.stderr[-3000:]}")
            g = json.loads(out.read_text())
            g["wall"] = time.perf_counter() - t
            compiling = sum(e["total"] for e in g["events"] if e["top"])
            g["compiling"] = compiling
            groups.append(g)
            for e in g["events"]:
                e["group"] = name
            events += g["events"]
            print(f"# {name:<10} {g['wall']:6.1f} s wall, {g['cpu']:6.1f} s CPU "
                  f"(+{g['children_cpu']:.1f} children), compiling {compiling:6.1f} CPU s, "
                  f"{len(g['events'])} compiles{' ' + g['error'] if g['error'] else ''}",
                  flush=True)  # fmt: skip
    print(f"# {uptime()}")
    cpu = sum(g["cpu"] for g in groups)
    comp = sum(g["compiling"] for g in groups)
    print(f"\nall groups: {cpu:.1f} CPU s, of which compiling {comp:.1f} CPU s "
          f"({len(events)} kernel compiles)\n")
    print("| group | waits for | CPU s | compiling, CPU s | compiles |")
    print("|---|---|---:|---:|---:|")
    for g in groups:
        print(f"| {g['group']} | {', '.join(GROUPS[g['group']][1]) or '-'} | {g['cpu']:.1f} | "
              f"{g['compiling']:.1f} | {len(g['events'])} |")
    per_mod: dict[str, list] = {}
    per_kernel: dict[str, list] = {}
    for e in events:
        m = per_mod.setdefault(e["module"], [0.0, 0])
        m[0] += e["self"]
        m[1] += 1
        k = per_kernel.setdefault(f"{e['module']}.{e['name']}", [0.0, 0, set()])
        k[0] += e["self"]
        k[1] += 1
        k[2].add(e["group"])
    print("\n| kernel module | compiling, CPU s (own) | compiles |")
    print("|---|---:|---:|")
    for mod, (s, n) in sorted(per_mod.items(), key=lambda kv: -kv[1][0]):
        print(f"| {mod} | {s:.1f} | {n} |")
    print(f"\n| kernel (top {top}) | compiling, CPU s (own) | signatures | group |")
    print("|---|---:|---:|---|")
    for k, (s, n, gs) in sorted(per_kernel.items(), key=lambda kv: -kv[1][0])[:top]:
        print(f"| {k.removeprefix('sylva.')} | {s:.1f} | {n} | {', '.join(sorted(gs))} |")
    if as_json:
        Path(as_json).write_text(json.dumps({"groups": groups}, indent=1))


def parallel(cache: Path, top: int, jobs: int | None) -> None:
    print(f"# {uptime()}")
    with tempfile.TemporaryDirectory(prefix="sylva-coldtest-") as tmp:
        prof = Path(tmp) / "profile.jsonl"
        env = dict(os.environ, NUMBA_CACHE_DIR=str(cache))
        env.pop("NUMBA_DISABLE_JIT", None)
        cmd = [sys.executable, "-m", "sylva", "warmup", "--profile", str(prof)]
        if jobs:
            cmd += ["-j", str(jobs)]
        t = time.perf_counter()
        r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
        proc = subprocess.run(cmd, env=env, capture_output=True, text=True)
        r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
        wall = time.perf_counter() - t
        if proc.returncode:
            raise SystemExit(proc.stderr[-3000:])
        recs = [json.loads(ln) for ln in prof.read_text().splitlines() if ln]
    print(f"# {uptime()}")
    cpu = r1.ru_utime - r0.ru_utime + r1.ru_stime - r0.ru_stime
    print("\n".join("#   " + ln for ln in proc.stderr.splitlines()))
    comp = sum(r["cpu"] for r in recs if r["depth"] == 0)
    print(f"\nsylva warmup: {wall:.1f} s wall, {cpu:.1f} CPU s, compiling {comp:.1f} CPU s, "
          f"{len(recs)} compiles")
    per_group: dict[str, float] = {}
    for r in recs:
        if r["depth"] == 0:
            per_group[r["group"]] = per_group.get(r["group"], 0.0) + r["cpu"]
    for g, c in per_group.items():
        print(f"  {g:<10} compiling {c:6.1f} CPU s")
    per_kernel: dict[str, float] = {}
    for r in recs:
        k = f"{r['module'].removeprefix('sylva.')}.{r['name']}"
        per_kernel[k] = per_kernel.get(k, 0.0) + r["self"]
    print(f"\n| kernel (top {top}) | compiling, CPU s (own) |")
    print("|---|---:|")
    for k, sec in sorted(per_kernel.items(), key=lambda kv: -kv[1])[:top]:
        print(f"| {k} | {sec:.1f} |")
    seen: dict[tuple, set] = {}
    for r in recs:
        if r["module"].startswith("sylva."):
            seen.setdefault((r["module"], r["name"], r["args"]), set()).add(r["pid"])
    twice = [(k, sum(r["self"] for r in recs if (r["module"], r["name"], r["args"]) == k))
             for k, pids in seen.items() if len(pids) > 1]
    print(f"\nkernels compiled by two processes: {len(twice)}, "
          f"{sum(s for _, s in twice):.1f} CPU s in all")
    for (m, n, _), s in sorted(twice, key=lambda kv: -kv[1])[:top]:
        print(f"  {s:6.2f} s  {m}.{n}")


def pytest(cache: Path, top: int, as_json: str | None, extra: list[str]) -> None:
    print(f"# {uptime()}")
    with tempfile.TemporaryDirectory(prefix="sylva-coldtest-") as tmp:
        rec = Path(tmp) / "tests.json"
        env = dict(os.environ, NUMBA_CACHE_DIR=str(cache), SYLVA_TEST_TIMES=str(rec))
        env["PYTHONPATH"] = os.pathsep.join(
            [str(HERE), *filter(None, [env.get("PYTHONPATH", "")])])
        t = time.perf_counter()
        r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
        proc = subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "_test_times",
                               "-p", "no:cacheprovider", *extra], env=env)  # fmt: skip
        r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
        wall = time.perf_counter() - t
        data = json.loads(rec.read_text()) if rec.exists() else {"tests": [], "compiles": []}
        # under pytest -n (xdist) each worker wrote its own file: tests.json.gw0 ...
        workers = [json.loads(f.read_text()) for f in sorted(rec.parent.glob(rec.name + ".*"))]
        for w in workers:
            for t in w["tests"]:
                t["worker"] = w["worker"]
            data["tests"] += w["tests"]
            data["compiles"] += w["compiles"]
        data["workers"] = [{k: w.get(k) for k in ("worker", "proc_cpu", "collect_wall")}
                           for w in workers]  # fmt: skip
    print(f"# {uptime()}")
    cpu = r1.ru_utime - r0.ru_utime + r1.ru_stime - r0.ru_stime
    tests = data["tests"]
    print(f"\npytest: {wall:.1f} s wall, {cpu:.1f} CPU s (with children), {len(tests)} tests, "
          f"exit {proc.returncode}; collection {data.get('collect_wall', 0):.1f} s")
    for w in workers:
        mine = [t for t in tests if t.get("worker") == w["worker"]]
        print(f"  worker {w['worker']}: {len(mine)} tests, {sum(t['wall'] for t in mine):.1f} s "
              f"in tests, {w['proc_cpu']:.1f} CPU s (with children), collection "
              f"{w['collect_wall']:.1f} s")
    mods: dict[str, list] = {}
    for t in tests:
        mod = t["id"].split("::")[0]
        m = mods.setdefault(mod, [0.0, 0.0, 0])
        m[0] += t["wall"]
        m[1] += t["cpu"]
        m[2] += 1
    print(f"\n| module (top {top}) | tests | wall s | CPU s |")
    print("|---|---:|---:|---:|")
    for mod, (w, c, n) in sorted(mods.items(), key=lambda kv: -kv[1][0])[:top]:
        print(f"| {mod} | {n} | {w:.1f} | {c:.1f} |")
    print(f"\n| test (top {top}) | wall s | CPU s | setup s |")
    print("|---|---:|---:|---:|")
    for t in sorted(tests, key=lambda t: -t["wall"])[:top]:
        print(f"| {t['id']} | {t['wall']:.2f} | {t['cpu']:.2f} | {t['setup']:.2f} |")
    comp = data["compiles"]
    print(f"\nkernels compiled during the tests: {len(comp)}, "
          f"{sum(c['self'] for c in comp):.1f} CPU s")
    for c in sorted(comp, key=lambda c: -c["self"])[:top]:
        print(f"  {c['self']:6.2f} s  {c['module']}.{c['name']}{c['args']}  ({c['test']})")
    if as_json:
        Path(as_json).write_text(json.dumps({"wall": wall, "cpu": cpu, **data}, indent=1))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("what", choices=["warmup", "parallel", "pytest"])
    ap.add_argument("--cache", help="the Numba cache folder (default: a new empty one)")
    ap.add_argument("--top", type=int, default=15)
    ap.add_argument("--json", metavar="FILE")
    ap.add_argument("-j", "--jobs", type=int, help="parallel: worker processes")
    args, extra = ap.parse_known_args()
    with tempfile.TemporaryDirectory(prefix="sylva-coldtest-cache-") as fresh:
        cache = Path(args.cache) if args.cache else Path(fresh)
        if args.what == "warmup":
            warmup(cache, args.top, args.json)
        elif args.what == "parallel":
            parallel(cache, args.top, args.jobs)
        else:
            pytest(cache, args.top, args.json, extra)


if __name__ == "__main__":
    main()
