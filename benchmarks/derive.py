"""Derivation speed: sylva against lindenmayer 1.5.4 (npm), measured in the same run.

    python benchmarks/derive.py [--repeat N] [--no-peer]

Each figure is the median of several runs after a warm-up (compilation excluded).  The
peer runs when ``node`` is on PATH; ``npm ci`` in ``benchmarks/peers`` is done on demand.
Figures are symbols (or modules) of the final word per second of the whole derivation,
except for the context-sensitive rows, which count every module rewritten in every step,
the tropism row, which counts the modules the turtle interprets per second (ABOP §2.3
bending after every step; the peer has no turtle), and the open L-system row, which counts
module-steps per second of a tree of 82 k modules whose 8,192 buds ask the light
environment (Palubicki's shadow grid) after every step: derivation, the turtle's trace and
the grid together (``--open-steps``, default 100; the issue's figure is 1,000).
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from sylva.data import find
from sylva.lsystem import derive, loads
from sylva.turtle import interpret

PEERS = Path(__file__).parent / "peers"

WORKLOADS = {
    # name: (sylva program text, steps, target M/s, how the size is counted)
    "koch": ("axiom = F++F++F\nF -> F-F++F-F", 10, 400.0),
    "plant": ("axiom = X\nX -> F[+X]F[-X]+X\nF -> FF", 11, 400.0),
    "stochastic": (
        "axiom = F\nF ->(33) F[+F]F[-F]F\nF ->(33) F[+F]F\nF ->(34) F[-F]F",
        10,
        150.0,
    ),
    "signal": ("axiom = b" + "a" * 99_999 + "\nb < a -> b\nb -> a", 5, 43.0),
    "bracketed": (None, 5, 20.0),
    "parametric": ("R = 1.456\naxiom = A(1)\nA(s) -> F(s)[+A(s/R)][-A(s/R)]", 18, 8.0),
    # interpretation, not derivation: the turtle walks ABOP Fig. 2.8b (T, e) at n = 10
    "tropism": (None, 10, 5.0),
    # an open L-system: a fixed tree whose buds read their light every step
    "open": (None, 100, 1.0),
}
#: Workloads that time the turtle (modules interpreted per second); the peer has none.
TURTLE = ("tropism",)
#: Workloads that time an open L-system with its environment (module-steps per second).
OPEN = ("open",)
LABELS = {
    "koch": "D0L Koch, 10 steps",
    "plant": "bracketed plant ABOP 1.24d, 11 steps",
    "stochastic": "stochastic plant ABOP 1.27, 10 steps",
    "signal": "flat context-sensitive signal, 100 k modules",
    "bracketed": "bracketed context-sensitive, tree of 116 k modules",
    "parametric": "parametric A(s) -> F(s)[+A(s/R)][-A(s/R)], 18 steps",
    "tropism": "turtle with tropism: ABOP Fig. 2.8b, n = 10 (interpret)",
    "open": "open L-system, light: 82 k-module tree, {steps} steps",
}


def bracketed_axiom() -> str:
    plant = derive(loads("axiom = X\nX -> F[+X][-X]FX\nF -> FF"), 9)
    return "S" + plant.to_text()


def program(name: str):
    text, steps, _ = WORKLOADS[name]
    if name == "bracketed":
        text = "ignore = +-\naxiom = " + bracketed_axiom() + "\nS < F -> S\nS -> F"
    if name == "tropism":
        text = find("abop-2.8b-ternary-tree").path.read_text(encoding="utf-8")
    return loads(text), steps


def measure_turtle(name: str, repeat: int, **overrides) -> tuple[float, int]:
    p, steps = program(name)
    word = derive(p, steps, seed=1)
    interpret(word, p, **overrides)  # compile the walk
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        interpret(word, p, **overrides)
        times.append(time.perf_counter() - t)
    return statistics.median(times), len(word)


def open_program(name: str = "open"):
    """A tree of 13 binary levels with a bud ``?E(q,u,v,w) A(n)`` at each of its 8,192
    tips; a bud counts the steps it spent in light (the word keeps its size)."""
    tree = derive(loads("axiom = X\nX -> F(1)[&(35)X]/(137.5)[&(35)X]"), 13).to_text()
    text = "axiom = " + tree.replace("X", "?E(0,0,0,0)A(0)")
    return loads(text + "\n?E(q,u,v,w) < A(n) : q > 0.5 -> A(n + 1)\n")


def measure_open(name: str, repeat: int, steps: int) -> tuple[float, int]:
    from sylva.environments import Light
    from sylva.lsystem import Derivation
    from sylva.plant import turtle_locate

    p = open_program(name)
    env, locate = Light(voxel=0.5, shadow=0.1), turtle_locate(p)
    d = Derivation(p, environment=env, locate=locate)
    d.advance(2)  # compile
    times = []
    for _ in range(max(1, repeat // 3)):
        d = Derivation(p, environment=env, locate=locate)
        t = time.perf_counter()
        d.advance(steps)
        times.append(time.perf_counter() - t)
    return statistics.median(times), len(d.word) * steps


def measure(name: str, repeat: int) -> tuple[float, int]:
    p, steps = program(name)
    derive(p, min(steps, 3), seed=1)  # compile the kernels this workload uses
    times = []
    w = None
    for _ in range(repeat):
        t = time.perf_counter()
        w = derive(p, steps, seed=1)
        times.append(time.perf_counter() - t)
    size = len(w) * (steps if name in ("signal", "bracketed") else 1)
    return statistics.median(times), size


def peer(names: list[str]) -> dict:
    node = shutil.which("node")
    if node is None:
        return {}
    if not (PEERS / "node_modules" / "lindenmayer").exists():
        npm = shutil.which("npm")
        if npm is None:
            return {}
        subprocess.run([npm, "ci", "--no-audit", "--no-fund"], cwd=PEERS, check=False,
                       stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    with tempfile.NamedTemporaryFile("w", suffix=".txt", delete=False) as f:
        f.write(bracketed_axiom())
    env = dict(os.environ, SYLVA_BRACKETED_AXIOM=f.name)
    try:
        out = subprocess.run([node, str(PEERS / "lindenmayer_bench.js"), *names], env=env,
                             capture_output=True, text=True, timeout=600, check=False)
    finally:
        os.unlink(f.name)
    if out.returncode != 0:
        print("lindenmayer peer failed:", out.stderr.strip()[:500], file=sys.stderr)
        return {}
    res = json.loads(out.stdout)
    if "bracketed" in res:
        res["bracketed"]["length"] *= 1  # one step in the peer: modules of that step
    return res


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=7)
    ap.add_argument("--no-peer", action="store_true")
    ap.add_argument("--open-steps", type=int, default=WORKLOADS["open"][1],
                    help="steps of the open L-system row (default 100)")
    ap.add_argument("names", nargs="*", default=list(WORKLOADS))
    args = ap.parse_args()
    rows = []
    for name in args.names:
        if name in OPEN:
            sec, size = measure_open(name, args.repeat, args.open_steps)
        else:
            sec, size = (measure_turtle if name in TURTLE else measure)(name, args.repeat)
        rows.append((name, size / sec / 1e6, sec))
    theirs = {} if args.no_peer else peer([n for n in args.names
                                            if n not in TURTLE and n not in OPEN])
    print(f"{'workload':56s} {'sylva M/s':>10s} {'target':>7s} {'peer M/s':>9s} {'ratio':>7s}")
    for name, mps, _sec in rows:
        target = WORKLOADS[name][2]
        p = theirs.get(name)
        pm = p["length"] / p["seconds"] / 1e6 if p else None
        ratio = f"{mps / pm:6.1f}x" if pm else "     -"
        pms = f"{pm:9.2f}" if pm else "        -"
        flag = "" if mps >= target else "  (below target)"
        label = LABELS[name].format(steps=args.open_steps)
        print(f"{label:56s} {mps:10.1f} {target:7.0f} {pms} {ratio}{flag}")
        if name in OPEN:
            print(f"{'  seconds per step':56s} {_sec / args.open_steps:10.3f}")
    if "tropism" in args.names:  # the same word and walk without bending, for comparison
        sec, size = measure_turtle("tropism", args.repeat, elasticity=0.0)
        print(f"{'  the same word without tropism (elasticity = 0)':56s} {size / sec / 1e6:10.1f}")
    print("peer: lindenmayer 1.5.4 on node " + (subprocess.run(
        ["node", "--version"], capture_output=True, text=True).stdout.strip()
        if theirs else "(not run)"))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
