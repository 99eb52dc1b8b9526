"""Cold start: the first and the second run of each command on an empty Numba cache.

    python benchmarks/cold_start.py [--only NAME,...] [--warmup] [--keep DIR]

A fresh install has no compiled kernels: Numba compiles each one the first time a command
reaches it and caches it on disk.  This benchmark gives every command its own empty cache
(``NUMBA_CACHE_DIR`` pointed at a new folder, which is what a fresh virtualenv has: Numba
then neither reads nor writes the package's ``__pycache__``), runs it twice, and prints the
wall time of both runs, the time Numba spent compiling in the first run and the kernel
modules that took it (from Numba's ``numba:compile`` events; a kernel compiled inside
another is counted once, in the one that called it).  ``import sylva`` is timed as the
best of five runs in fresh interpreters.

``--warmup`` runs ``sylva warmup`` into one shared cache first and then every command once
on it: what a user sees after the warm-up (or ``make demo``).

The machine is shared: ``uptime`` is printed before and after; compare figures from the
same run.
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

from sylva.data import find

# name: (what it is, argv after ``sylva`` or a Python snippet marked "py:")
COMMANDS = {
    "import": ("import sylva", "py:import sylva"),
    "derive": ("sylva derive 01-koch-snowflake -n 4", ["derive", "01-koch-snowflake", "-n", "4"]),
    "render-2d": (
        "sylva render 01-koch-snowflake --size 320x240",
        ["render", "01-koch-snowflake", "-o", "{tmp}/k.png", "--size", "320x240"],
    ),
    "render-3d": (
        "sylva render 16-abop-1.25-bush --size 320x240",
        ["render", "16-abop-1.25-bush", "-o", "{tmp}/b.png", "--size", "320x240"],
    ),
    "export": (
        "sylva export 16-abop-1.25-bush -o b.glb",
        ["export", "{bush}", "-o", "{tmp}/b.glb"],  # export takes a path, not a name
    ),
    "animate": (
        "sylva animate 10-abop-1.24a-plant -n 3 --size 160x120 -o a.gif",
        ["animate", "10-abop-1.24a-plant", "-n", "3", "--size", "160x120", "-o", "{tmp}/a.gif"],
    ),
    "texture": (
        "sylva texture marble --size 256x256",
        ["texture", "marble", "-o", "{tmp}/m.png", "--size", "256x256"],
    ),
    "tree": (
        "sylva tree {species} --size 320x240 -o t.png",
        ["tree", "{species}", "-o", "{tmp}/t.png", "--size", "320x240"],
    ),
    "world": (
        "sylva world --seed 3 --size 64x64 -o w.png",
        ["world", "--seed", "3", "--size", "64x64", "-o", "{tmp}/w.png", "--quiet"],
    ),
    "studio": (
        "studio: first derive + mesh of an example",
        "py:from sylva.studio._work import _warm_up; _warm_up()",
    ),
}

# Run inside the child: record every numba:compile event, run the command, dump the events.
PROBE = r"""
import json, os, sys, time
T0 = time.perf_counter()
events = []
def _install():
    from numba.core import event as ev
    stack = []
    class L(ev.Listener):
        def on_start(self, event):
            stack.append([time.process_time(), 0.0])
        def on_end(self, event):
            t0, inner = stack.pop()
            dt = time.process_time() - t0
            if stack:
                stack[-1][1] += dt
            d = event.data["dispatcher"]
            f = d.py_func
            events.append({"module": f.__module__, "name": f.__qualname__,
                           "args": str(event.data["args"]), "total": dt, "self": dt - inner,
                           "top": not stack})
    ev.register("numba:compile", L())
def _dump():
    with open(os.environ["SYLVA_COLD_EVENTS"], "w") as fh:
        json.dump({"wall": time.perf_counter() - T0, "events": events}, fh)
_install()
what = sys.argv[1]
try:
    if what.startswith("py:"):
        exec(what[3:])  # noqa: S102  (the benchmark's own snippets, not user text)
        rc = 0
    else:
        from sylva.cli import main
        rc = main(json.loads(what))
finally:
    _dump()
sys.exit(rc)
"""


def default_species() -> str:
    from sylva.tree import species_names

    names = species_names()
    return "quaking_aspen" if "quaking_aspen" in names else names[0]


def run(what, cache: Path, tmp: Path, probe: bool) -> dict:
    env = dict(os.environ, NUMBA_CACHE_DIR=str(cache))
    env.pop("NUMBA_DISABLE_JIT", None)
    if isinstance(what, list):
        arg = json.dumps([a.format(tmp=tmp, species=SPECIES, bush=BUSH) for a in what])
    else:
        arg = what
    events = tmp / "events.json"
    env["SYLVA_COLD_EVENTS"] = str(events)
    if probe:
        cmd = [sys.executable, "-c", PROBE, arg]
    elif arg.startswith("py:"):
        cmd = [sys.executable, "-c", arg[3:]]
    else:
        cmd = [sys.executable, "-m", "sylva", *json.loads(arg)]
    t = time.perf_counter()
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    proc = subprocess.run(cmd, env=env, capture_output=True, text=True, cwd=tmp)
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    wall = time.perf_counter() - t
    cpu = (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)
    if proc.returncode != 0:
        raise SystemExit(f"{cmd[-1]!r} failed ({proc.returncode}):\n{proc.stderr[-3000:]}")
    out = {"wall": wall, "cpu": cpu, "stderr": proc.stderr}
    if probe:
        out.update(json.loads(events.read_text()))
        out["wall"] = wall
    return out


def summarise(events: list[dict]) -> tuple[float, dict[str, tuple[float, int]]]:
    """Seconds compiling in all (top-level events) and per kernel module (self time)."""
    total = sum(e["total"] for e in events if e["top"])
    per: dict[str, list] = {}
    for e in events:
        mod = e["module"].removeprefix("sylva.")
        acc = per.setdefault(mod, [0.0, 0])
        acc[0] += e["self"]
        acc[1] += 1
    return total, {m: (s, n) for m, (s, n) in per.items()}


def uptime() -> str:
    try:
        return subprocess.run(["uptime"], capture_output=True, text=True).stdout.strip()
    except OSError:
        return "?"


def time_import(cache: Path, tmp: Path, n: int = 5) -> tuple[float, float, float]:
    """Best wall and CPU seconds of ``n`` fresh interpreters importing sylva, and the CPU
    seconds of a bare interpreter (a loaded machine stretches the wall time, not these)."""
    runs = [run("py:import sylva", cache, tmp, probe=False) for _ in range(n)]
    base = min(run("py:pass", cache, tmp, probe=False)["cpu"] for _ in range(3))
    return min(r["wall"] for r in runs), min(r["cpu"] for r in runs), base


SPECIES = "?"
BUSH = str(find("16-abop-1.25-bush").path)


def main() -> None:
    global SPECIES
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--only", default="", help="comma-separated command names")
    ap.add_argument("--warmup", action="store_true",
                    help="run `sylva warmup` into a shared cache first, then each command once")
    ap.add_argument("--top", type=int, default=3, help="kernel modules shown per command")
    ap.add_argument("--detail", action="store_true", help="list every kernel compiled")
    ap.add_argument("--json", metavar="FILE", help="also write the figures as JSON")
    args = ap.parse_args()
    SPECIES = default_species()
    names = [n for n in args.only.split(",") if n] or list(COMMANDS)
    unknown = sorted(set(names) - set(COMMANDS))
    if unknown:
        ap.error(f"unknown command(s) {', '.join(unknown)}; choose from {', '.join(COMMANDS)}")
    print(f"# {uptime()}")
    print(f"# python {sys.version.split()[0]}, {os.cpu_count()} cores")
    rows = []
    with tempfile.TemporaryDirectory(prefix="sylva-cold-") as root:
        root = Path(root)
        shared = root / "shared-cache"
        if args.warmup:
            t = time.perf_counter()
            r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
            proc = subprocess.run([sys.executable, "-m", "sylva", "warmup"],
                                  env=dict(os.environ, NUMBA_CACHE_DIR=str(shared)),
                                  capture_output=True, text=True)
            r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
            if proc.returncode:
                raise SystemExit(proc.stderr)
            cpu = r1.ru_utime - r0.ru_utime + r1.ru_stime - r0.ru_stime
            print(f"# sylva warmup: {time.perf_counter() - t:.1f} s ({cpu:.1f} s CPU)")
            print("\n".join("#   " + ln for ln in proc.stderr.splitlines()))
        for name in names:
            label, what = COMMANDS[name]
            label = label.format(species=SPECIES)
            cache = shared if args.warmup else root / f"cache-{name}"
            tmp = root / f"tmp-{name}"
            tmp.mkdir()
            if name == "import":
                best, cpu, base = time_import(cache, tmp)
                rows.append((label, best, None, None,
                             f"{cpu:.2f} s CPU (python alone {base:.2f} s CPU)"))
                print(f"# {name}: {best:.2f} s ({cpu:.2f} s CPU)", flush=True)
                continue
            first = run(what, cache, tmp, probe=True)
            second = None if args.warmup else run(what, cache, tmp, probe=False)
            total, per = summarise(first["events"])
            top = sorted(per.items(), key=lambda kv: -kv[1][0])[: args.top]
            where = ", ".join(f"{m} {s:.1f} s ({n})" for m, (s, n) in top)
            rows.append((label, first, second, total, where))
            print(f"# {name}: {first['wall']:.1f} s ({first['cpu']:.1f} s CPU) / "
                  + (f"{second['wall']:.1f} s ({second['cpu']:.1f} s CPU)" if second else "-"),
                  flush=True)
            if args.detail:
                for e in sorted(first["events"], key=lambda e: -e["self"]):
                    print(f"#   {e['self']:6.2f} s  {e['module']}.{e['name']}{e['args']}")
    print(f"# {uptime()}")
    print()
    print("| command | first run, s (CPU s) | second run, s (CPU s) | compiling in the first, "
          "CPU s | where (kernel module: CPU s compiling (kernels compiled)) |")
    print("|---|---:|---:|---:|---|")
    for label, a, b, c, where in rows:
        if isinstance(a, float):  # import sylva
            print(f"| `{label}` | {a:.2f} | | | {where} |")
            continue
        bs = "" if b is None else f"{b['wall']:.1f} ({b['cpu']:.1f})"
        print(f"| `{label}` | {a['wall']:.1f} ({a['cpu']:.1f}) | {bs} | {c:.1f} | {where} |")
    if args.json:
        Path(args.json).write_text(json.dumps(
            [{"command": r[0], "first": r[1], "second": r[2], "compiling": r[3]} for r in rows],
            indent=1, default=str))


if __name__ == "__main__":
    main()
