"""Random programs and formats written to a missing, a read-only and a full target (issue
23, "Keep it so").

Hypothesis draws a program (a small random one, or a built-in example), an output format
and a target; every case must exit 2 with one line naming the path it could not write and
why, print no traceback, and leave the file that was there byte for byte as it was (and no
temporary file beside it).  A full disk needs ``RLIMIT_FSIZE`` on a child process, so the
whole hypothesis run happens in ONE child (:func:`_fuzz`), which reports back; the targets
and checks are those of ``test_write_failures.py`` (``_write_targets.py``).
"""

from __future__ import annotations

import contextlib
import io
import json
import os
import resource
import signal
import subprocess
import sys
from pathlib import Path

from _write_targets import (
    FULL_DISK_CAUSES,
    check_failure,
    read_only,
    same,
    seed,
)
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from sylva.geometry.exchange import usd_available

EXAMPLES = 25  # cases, all in the one child process
FORMATS = ["glb", "gltf", "obj", "ply", "stl", "scad", "pov", "svg", "png"]
# bytes a file may grow to on the "full" disk: less than any output
FULL_LIMIT = 16
OLD = b"the file that was there before\n"

_STEPS = st.lists(st.sampled_from(["F", "f", "+", "-", "&", "^", "/", "\\", "|", "!", "X",
                                   "[F]", "[+F]", "[-FX]", "[&F]"]), max_size=6).map("".join)


@st.composite
def _program(draw) -> str:
    """A small valid ``.lsys`` program that draws something."""
    rot = draw(st.sampled_from([15, 22.5, 25.7, 60, 90]))
    lines = [f"rot = {rot}", "axiom = F" + draw(_STEPS), "F -> F" + draw(_STEPS)]
    if draw(st.booleans()):
        lines.append("X -> " + draw(_STEPS))
    return "\n".join(lines) + "\n"


def _example_paths() -> list[str]:
    from sylva.data import examples

    return [str(e.path) for e in examples()]


def _argv(program: str, steps: int, out: Path) -> list[str]:
    if out.suffix == ".png":
        return ["render", program, "-n", str(steps), "--size", "24x24", "--msaa", "0",
                "-o", str(out)]
    return ["export", program, "-n", str(steps), "-o", str(out)]


def _outputs(out: Path) -> list[Path]:
    return [out, out.with_suffix(".mtl")] if out.suffix == ".obj" else [out]


def _run(argv: list[str], limit: int | None) -> tuple[int | str, str]:
    from sylva.cli import main

    err = io.StringIO()
    if limit is not None:
        resource.setrlimit(resource.RLIMIT_FSIZE, (limit, resource.RLIM_INFINITY))
    try:
        with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
            rc = main(argv)
    except BaseException as exc:  # noqa: BLE001 - a traceback is what the test reports
        import traceback

        rc = f"raised {type(exc).__name__}"
        err.write(traceback.format_exc())
    finally:
        if limit is not None:
            resource.setrlimit(resource.RLIMIT_FSIZE,
                               (resource.RLIM_INFINITY, resource.RLIM_INFINITY))
    return rc, err.getvalue()


def _fuzz(base: Path, examples: int) -> dict:
    """The hypothesis run, in the child: returns what it tried and how it ended."""
    signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
    formats = FORMATS + (["usda", "usdc"] if usd_available() else [])
    # compile what the writers use first, with no limit (and each full-disk case runs once
    # unlimited first), so that no cache file is written under the limit
    for ext in ("glb", "png"):
        rc, err = _run(_argv(_example_paths()[9], 1, base / f"warm.{ext}"), None)
        assert rc == 0, err
    targets = ["missing", "full"]
    probe = base / "probe"
    probe.mkdir()
    try:
        with read_only(probe):
            targets.append("read-only")
    except BaseException:  # noqa: BLE001 - pytest.skip: no immutable folders here
        pass
    programs = st.one_of(_program().map(lambda text: ("text", text)),
                         st.sampled_from(_example_paths()).map(lambda path: ("file", path)))
    tried: list[str] = []

    @settings(max_examples=examples, deadline=None, database=None,
              suppress_health_check=list(HealthCheck))
    @given(program=programs, steps=st.integers(0, 2), ext=st.sampled_from(formats),
           target=st.sampled_from(targets))
    def one(program, steps, ext, target):
        case = base / f"case{len(tried)}"
        case.mkdir()
        kind, program = program
        if kind == "text":
            (case / "p.lsys").write_text(program, encoding="utf-8")
            program = str(case / "p.lsys")
        tried.append(f"{target} {ext} {Path(program).name} -n {steps}")
        if target == "missing":
            folder = case / "no" / "such"
            out = folder / f"p.{ext}"
            rc, err = _run(_argv(program, steps, out), None)
            check_failure(rc, err, {*_outputs(out), folder}, ("does not exist",))
            assert not (case / "no").exists()
            return
        folder = case / "out"
        out = folder / f"p.{ext}"
        old = {p.name: OLD + p.name.encode() for p in _outputs(out)}
        seed(folder, old)
        if target == "full":
            # the same command once with no limit, elsewhere: a kernel this program needs
            # compiles and writes its cache file now, not under the limit (a cold cache)
            warm = case / "warm"
            warm.mkdir()
            _run(_argv(program, steps, warm / out.name), None)
            rc, err = _run(_argv(program, steps, out), FULL_LIMIT)
            causes = FULL_DISK_CAUSES
        else:
            with read_only(folder) as causes:
                rc, err = _run(_argv(program, steps, out), None)
        check_failure(rc, err, {*_outputs(out), folder}, causes)
        same(folder, old)

    try:
        one()
    except BaseException as exc:  # noqa: BLE001 - reported to the parent
        return {"ok": False, "tried": tried, "error": f"{type(exc).__name__}: {exc}"}
    return {"ok": True, "tried": tried, "targets": targets}


def test_random_programs_and_formats_fail_cleanly(tmp_path):
    here = os.path.dirname(os.path.abspath(__file__))
    code = ("import json, sys; from pathlib import Path; sys.path.insert(0, sys.argv[1]); "
            "import test_write_fuzz as t; "
            "r = t._fuzz(Path(sys.argv[2]), int(sys.argv[3])); "
            "sys.__stdout__.write('\\n' + json.dumps(r))")
    run = subprocess.run([sys.executable, "-c", code, here, str(tmp_path), str(EXAMPLES)],
                         capture_output=True, text=True, timeout=400, check=False)
    assert run.returncode == 0, run.stderr[-3000:]
    report = json.loads(run.stdout.strip().splitlines()[-1])
    assert report["ok"], report["error"] + "\n" + run.stdout[-3000:]
    assert len(report["tried"]) >= EXAMPLES, report
    # the cases covered each target and several formats
    assert {t.split()[0] for t in report["tried"]} == set(report["targets"]), report
    assert len({t.split()[1] for t in report["tried"]}) >= 3, report
    # nothing reached the child's own standard error behind sys.stderr's back
    assert "Traceback" not in run.stderr and "Exception ignored" not in run.stderr, run.stderr
