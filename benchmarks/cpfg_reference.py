"""Compare sylva's derived words with cpfg's own, model by model, on a vlab checkout.

vlab (Algorithmic Botany's Virtual Laboratory) is GPL-3 and not part of sylva; neither
is its cpfg.  Issue 24 allows building cpfg from vlab's public source to produce
reference strings: its output is data, used here only to compare.  For each cpfg model
under ``oofs/`` (found as :mod:`benchmarks.cpfg_corpus` finds them), this script runs the
cpfg binary without graphics on the model with the files its ``specifications`` name,
has it write the derived string (``-str``: cpfg's text form, each parameter printed with
C's ``%g``, six significant digits, lines broken every 70 characters), derives the same
model with sylva (the corpus runner's reading: :func:`sylva.lsystem.dialects.cpfg.parse`
with the view file, colour map, material and environment file, then
:class:`sylva.lsystem.Derivation` to the ``derivation length``) and compares the words
module by module: the symbols, the number of parameters, and each parameter within
cpfg's printing (six significant digits of a 32-bit float: relative ``1e-5``, absolute
``1e-6``).

Per model it prints one line::

    equal        N modules
    differ       at module K of N/M: cpfg X(…) sylva Y(…)   (the first difference)
    stochastic   counts equal / counts differ: …             (random streams differ)
    cpfg failed  (its message) / sylva failed (its message) / timeout
    skipped      needs environment program X
    cut later    equal once the cuts cpfg makes only in the next step are made: cpfg
                 keeps a ``%`` produced in the last step, and the rest of its branch,
                 in its word (and drops them in the next step); sylva cuts right away
    no env       the object has an environment file (-e): sylva answers it with a
                 built-in environment, cpfg here runs without one (its environment
                 programs are not built), so the words are not comparable

A model is *stochastic* when it has ``seed:``, a production with a probability, or calls
``ran``/``nran``/``srand``: cpfg's random stream (``srand48``) is not sylva's, so only the
module count per symbol is compared, and only as information.

Building cpfg (Debian 12 / Ubuntu 22.04, as root; outside sylva's tree)::

    apt-get install -y qtbase5-dev qt5-qmake freeglut3-dev bison flex \\
        libreadline-dev g++ make
    git clone https://github.com/AlgorithmicBotany/vlab /tmp/vlab
    cp -a /tmp/vlab /tmp/cpfgbuild && cd /tmp/cpfgbuild
    for d in misc image comm directoryWatcher; do
        (cd libs/$d && qmake && make -j2); done
    (cd vlabcpp && qmake && make -j2)     # cpfg's default preprocessor, run by name
    (cd cpfg && qmake && make -j2)
    # the binaries: /tmp/cpfgbuild/.binaries/bin/cpfg and .../vlabcpp

cpfg runs ``vlabcpp`` from ``PATH``; this script puts the cpfg binary's folder first on
it.  With ``-g`` (no graphics) cpfg needs no display and no Qt platform plugin: it
derives, writes the string and exits.

Usage::

    PYTHONPATH=src .venv/bin/python benchmarks/cpfg_reference.py PATH_TO_VLAB
        [--cpfg PATH | env SYLVA_CPFG] [--only SUBSTRING] [--all] [--timeout 60]

Without ``--all`` only the models of ``11-CPFG/01-Introduction`` and ``10-manuals/11-CPFG``
run (the ones issue 24's "Done when" names); ``--only`` picks models by a part of their
path.
"""

from __future__ import annotations

import argparse
import multiprocessing as mp
import os
import re
import subprocess
import sys
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from cpfg_corpus import _needs, cpfg_command, find_models  # noqa: E402

_STOCHASTIC = re.compile(r"^\s*seed\s*:|\b(?:n?ran|srand)\s*\(", re.MULTILINE | re.IGNORECASE)
_DEFAULT_SETS = ("11-CPFG/01-Introduction", "10-manuals/11-CPFG")
REL, ABS = 1e-5, 1e-6


# ---------------------------------------------------------------- cpfg's side
def parse_cpfg_string(text: str, names=()) -> tuple[list[str], list[tuple[float, ...]]]:
    """The modules of cpfg's ``-str`` output: a symbol, ``(a,b,…)`` after it when it has
    parameters (cpfg breaks the line every 70 characters; the breaks are dropped).

    cpfg's string has one character per module (``@Gs`` is three modules, as in sylva's
    reading); a name of sylva's alphabet ``names`` of more characters (``?H``, a query
    module, which cpfg keeps as ``?`` and ``H(x,y,z)``) is read as one module, the
    longest that starts there."""
    text = text.replace("\n", "")
    multi = {m for m in names if len(m) > 1 and "(" not in m}
    lengths = sorted({len(m) for m in multi}, reverse=True)
    syms: list[str] = []
    pars: list[tuple[float, ...]] = []
    i, n = 0, len(text)
    while i < n:
        c = next((text[i : i + k] for k in lengths if text[i : i + k] in multi), text[i])
        i += len(c)
        if i < n and text[i] == "(":
            j = text.index(")", i)
            pars.append(tuple(float(v) for v in text[i + 1 : j].split(",")))
            i = j + 1
        else:
            pars.append(())
        syms.append(c)
    return syms, pars


def run_cpfg(cpfg: Path, model: Path, files: dict, timeout: float) -> tuple[str, object]:
    """Run cpfg on ``model`` without graphics; ``("ok", its -str text)`` or
    ``("cpfg failed", message)`` / ``("timeout", None)``."""
    env = dict(os.environ)
    env["PATH"] = f"{cpfg.parent}{os.pathsep}{env.get('PATH', '')}"
    env.setdefault("QT_QPA_PLATFORM", "offscreen")
    with tempfile.TemporaryDirectory(prefix="cpfgref-") as tmp:
        out = Path(tmp) / "word.str"
        args = [str(cpfg), "-g"]
        if files["mat"] is not None:
            args += ["-M", str(files["mat"])]
        else:  # -g asks for a colour map or material file; it reads it only to draw
            cmap = files["map"]
            if cmap is None:
                cmap = Path(tmp) / "none.map"
                cmap.write_bytes(bytes(768))
            args += ["-m", str(cmap)]
        args += ["-str", str(out), model.name]
        if files["view"] is not None:
            args.append(str(files["view"]))
        else:
            empty = Path(tmp) / "none.v"
            empty.write_text("")
            args.append(str(empty))
        try:
            p = subprocess.run(args, cwd=model.parent, env=env, capture_output=True,
                               timeout=timeout, text=True, errors="replace")  # fmt: skip
        except subprocess.TimeoutExpired:
            return "timeout", None
        if not out.is_file() or out.stat().st_size == 0:
            msg = " / ".join((p.stdout + p.stderr).split("\n"))[-300:]
            return "cpfg failed", f"rc={p.returncode} {msg}"
        return "ok", out.read_text("latin-1")


# ---------------------------------------------------------------- sylva's side
def _derive(model: str, files: dict, queue) -> None:
    out: dict = {}
    try:
        warnings.simplefilter("ignore")
        from sylva.lsystem import Derivation
        from sylva.lsystem.dialects import cpfg
        from sylva.plant import environment_for, query_for

        text = Path(model).read_text("latin-1")
        program = cpfg.parse(text, model, view=files["view"] or False, colormap=files["map"],
                             materials=files["mat"], environment=files["env"])  # fmt: skip
        seed = program.seed if program.seed is not None else 1
        env, locate = environment_for(program, seed)
        d = Derivation(program, seed=seed, limit=5_000_000, query=query_for(program, seed),
                       environment=env, locate=locate)  # fmt: skip
        d.advance(program.steps or 0)
        w = d.word
        from sylva.lsystem.ast import Num

        out["weights"] = any(r.weight != Num(1.0) for r in program.rules)  # probabilities
        out["names"] = list(w.alphabet.names)
        out["ids"] = w.ids.copy()
        out["offsets"] = w.offsets.copy()
        out["values"] = w.values.copy()
        out["status"] = "ok"
    except Exception as e:  # noqa: BLE001 - every failure is reported
        out["status"] = "sylva failed"
        out["message"] = " / ".join(f"{type(e).__name__}: {e}".splitlines())[:300]
    queue.put(out)


def run_sylva(model: Path, files: dict, timeout: float) -> dict:
    ctx = mp.get_context("fork")
    queue = ctx.Queue()
    p = ctx.Process(target=_derive, args=(str(model), files, queue))
    p.start()
    try:
        out = queue.get(timeout=timeout)
    except Exception:  # noqa: BLE001 - queue.Empty: out of time
        out = {"status": "timeout"}
    p.join(1)
    if p.is_alive():
        p.kill()
        p.join()
    return out


# ---------------------------------------------------------------- comparing
def _fmt(sym: str, params) -> str:
    if not len(params):
        return sym
    return sym + "(" + ",".join(f"{float(v):g}" for v in params) + ")"


def _close(a: float, b: float) -> bool:
    if a == b or (a != a and b != b):
        return True
    return abs(a - b) <= max(ABS, REL * max(abs(a), abs(b)))


def first_difference(cpfg_word, sylva: dict) -> tuple[int, str, str] | None:
    """The first module where the words differ, as (index, cpfg's module, sylva's), or
    None when they are equal (a shorter word differs at its end)."""
    syms, pars = cpfg_word
    names, ids, off = sylva["names"], sylva["ids"], sylva["offsets"]
    vals = sylva["values"].astype(np.float32).astype(np.float64)
    n = min(len(syms), len(ids))
    index = {s: i for i, s in enumerate(names)}
    cids = np.array([index.get(s, -1) for s in syms[:n]], dtype=np.int64)
    bad = np.flatnonzero(cids != ids[:n].astype(np.int64))
    stop = int(bad[0]) if bad.size else n
    offl = off.tolist()
    for k in range(stop):  # parameters, up to the first symbol that differs
        a, b = offl[k], offl[k + 1]
        p = pars[k]
        if len(p) != b - a or not all(_close(x, y) for x, y in zip(p, vals[a:b].tolist())):
            stop = k
            break
    if stop == n and len(syms) == len(ids):
        return None

    def at(k: int) -> tuple[str, str]:
        c = _fmt(syms[k], pars[k]) if k < len(syms) else "(end)"
        s = _fmt(names[ids[k]], vals[offl[k] : offl[k + 1]]) if k < len(ids) else "(end)"
        return c, s

    c, s = at(stop)
    return stop, c, s


def drop_cuts(word):
    """cpfg's word with the cuts it has not made yet: a ``%`` (no parameters) and the rest
    of its branch, which cpfg removes in the next step (sylva right after the step)."""
    syms, pars = word
    keep_s, keep_p = [], []
    k, n = 0, len(syms)
    while k < n:
        if syms[k] == "%" and not pars[k]:
            depth = 0
            k += 1
            while k < n and not (syms[k] == "]" and depth == 0):
                depth += (syms[k] == "[") - (syms[k] == "]")
                k += 1
            continue
        keep_s.append(syms[k])
        keep_p.append(pars[k])
        k += 1
    return keep_s, keep_p


def counts(syms) -> dict[str, int]:
    out: dict[str, int] = {}
    for s in syms:
        out[s] = out.get(s, 0) + 1
    return out


def compare(cpfg_bin: Path, model: Path, timeout: float) -> tuple[str, str]:
    files = cpfg_command(model)
    needs = _needs(files["env"])
    if needs is not None:
        return "skipped", f"needs environment program {needs}"
    text = model.read_text("latin-1")
    c_status, c_word = run_cpfg(cpfg_bin, model, files, timeout)
    s = run_sylva(model, files, timeout)
    stochastic = bool(_STOCHASTIC.search(text)) or bool(s.get("weights"))
    if c_status != "ok":
        tail = f"; sylva {s['status']}" if s["status"] != "ok" else ""
        return c_status, f"{c_word or ''}{tail}"
    if s["status"] != "ok":
        return s["status"], s.get("message", f"over {timeout:g}s")
    c_word = parse_cpfg_string(c_word, s["names"])
    n_c, n_s = len(c_word[0]), len(s["ids"])
    diff = first_difference(c_word, s)
    if diff is None:
        return "equal", f"{n_c} modules" + (" (stochastic)" if stochastic else "")
    k, cm, sm = diff
    where = f"at module {k} of {n_c}/{n_s}: cpfg {cm[:60]} sylva {sm[:60]}"
    if stochastic:
        cc = counts(c_word[0])
        sc = counts([s["names"][i] for i in s["ids"].tolist()])
        if cc == sc:
            return "stochastic", f"counts equal ({n_c} modules); words differ {where}"
        keys = sorted(set(cc) | set(sc), key=lambda x: -(cc.get(x, 0) + sc.get(x, 0)))
        shown = " ".join(f"{x}:{cc.get(x, 0)}/{sc.get(x, 0)}" for x in keys
                         if cc.get(x, 0) != sc.get(x, 0))[:120]  # fmt: skip
        return "stochastic", f"counts differ (cpfg/sylva) {shown}; {n_c}/{n_s} modules"
    if "%" in c_word[0] and first_difference(drop_cuts(c_word), s) is None:
        return "cut later", (
            f"equal once cpfg's pending cuts (% and the rest of its branch, "
            f"removed by cpfg in the next step) are dropped; {where}"
        )
    if files["env"] is not None:  # cpfg ran without -e: nothing answered its ?E modules
        return "no env", f"cpfg ran without its environment program; {where}"
    ctx = " ".join(c_word[0][max(0, k - 12) : k + 1])
    return "differ", f"{where}  [cpfg before: {ctx.replace(' ', '')}]"


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("vlab", type=Path)
    ap.add_argument("--cpfg", type=Path, default=os.environ.get("SYLVA_CPFG"),
                    help="the cpfg binary (default: env SYLVA_CPFG)")  # fmt: skip
    ap.add_argument("--only", default=None, help="models whose path contains SUBSTRING")
    ap.add_argument("--all", action="store_true", help="every cpfg model under oofs/")
    ap.add_argument("--timeout", type=float, default=60.0)
    args = ap.parse_args(argv)
    if args.cpfg is None or not Path(args.cpfg).is_file():
        ap.error("give the cpfg binary with --cpfg PATH or SYLVA_CPFG")
    cpfg_bin = Path(args.cpfg).resolve()
    import sylva.lsystem.dialects.cpfg  # noqa: F401 - loaded once, shared by the children
    import sylva.plant  # noqa: F401

    root = args.vlab / "oofs"
    rows = []
    for model in find_models(args.vlab):
        name = str(model.relative_to(root)).replace("ext/", "")
        if args.only is not None:
            if args.only not in name and args.only not in str(model):
                continue
        elif not args.all and not any(s in name for s in _DEFAULT_SETS):
            continue
        t0 = time.perf_counter()
        status, detail = compare(cpfg_bin, model, args.timeout)
        rows.append(status)
        print(f"{status:12s} {name}  {detail}  ({time.perf_counter() - t0:.1f}s)", flush=True)
    tally: dict[str, int] = {}
    for r in rows:
        tally[r] = tally.get(r, 0) + 1
    print()
    print(f"{len(rows)} models: " + ", ".join(f"{v} {k}" for k, v in sorted(tally.items())))
    return 0


if __name__ == "__main__":
    sys.exit(main())
