"""Every command that writes a file, on a missing folder, a read-only folder and a full disk.

Each must exit 2 with one line naming the file it could not write and why (no traceback),
leave the previous output byte for byte as it was, and leave no temporary file behind.
The commands run in this process (``main([...])``) where they can; the full disk is a
child process with ``RLIMIT_FSIZE`` (and ``SIGXFSZ`` ignored, so a write past the limit
fails with ``EFBIG`` as one past a full disk fails with ``ENOSPC``), one child for all the
commands, each under a limit of half its output's size.
"""

from __future__ import annotations

import io
import json
import subprocess
import sys
from pathlib import Path

import pytest
from _write_targets import (
    FULL_DISK_CAUSES,
    FULL_DISK_CHILD,
    check_failure,
    read_only,
    same,
    seed,
)

from sylva.cli import main
from sylva.data import examples
from sylva.geometry.exchange import usd_available

PLANT = str(next(e.path for e in examples() if e.name == "10-abop-1.24a-plant"))
GROW = ["10-abop-1.24a-plant", "-n", "1", "--size", "48x48", "--msaa", "0"]
WORLD = ["world", "--size", "8x8", "--chunk", "8", "--workers", "1", "--quiet"]

# name: (arguments, with {out} for the output folder; the files the command writes there)
CASES = {
    **{f"export-{ext}": (["export", PLANT, "-n", "2", "-o", f"{{out}}/plant.{ext}"],
                         [f"plant.{ext}"] + (["plant.mtl"] if ext == "obj" else []))
       for ext in ("glb", "gltf", "obj", "ply", "stl", "scad", "pov", "svg", "usda", "usdc")},
    "render-png": (["render", *GROW, "-o", "{out}/plant.png"], ["plant.png"]),
    "render-jpg": (["render", *GROW, "-o", "{out}/plant.jpg"], ["plant.jpg"]),
    "animate-gif": (["animate", *GROW, "-o", "{out}/grow.gif"], ["grow.gif"]),
    "animate-mp4": (["animate", *GROW, "-o", "{out}/grow.mp4"], ["grow.mp4"]),
    "texture-png": (["texture", "marble", "--size", "48x48", "-o", "{out}/m.png"], ["m.png"]),
    "texture-gif": (["texture", "marble", "--size", "48x48", "--frames", "2",
                     "-o", "{out}/m.gif"], ["m.gif"]),
    "texture-preset": (["texture", "marble", "--save-preset", "{out}/m.toml"], ["m.toml"]),
    "tree-glb": (["tree", "hazel_shrub", "--age", "1", "-o", "{out}/t.glb"], ["t.glb"]),
    "tree-png": (["tree", "hazel_shrub", "--age", "1", "--size", "32x32", "-o", "{out}/t.png"],
                 ["t.png"]),
    # big enough that the chunks, tiles and atlas sylva keeps in the system's temp folder
    # stay under the limit (plants make the GLB ~500 kB): the file that hits it is the output
    "world-glb": ([*WORLD, "-o", "{out}/w.glb"], ["w.glb"]),
    "world-png": ([*WORLD, "--no-plants", "--image-size", "400x300", "-o", "{out}/w.png"],
                  ["w.png"]),
    "gallery": (["gallery", "-o", "{out}", "--only", "01-koch", "--size", "32x32"],
                ["01-koch-snowflake.png", "index.html"]),
}
NEEDS_USD = {"export-usda", "export-usdc"}


def _params():
    for name in CASES:
        marks = ()
        if name in NEEDS_USD:
            marks = pytest.mark.skipif(not usd_available(), reason="usd-core is not installed")
        yield pytest.param(name, marks=marks)


def _argv(name: str, folder: Path) -> list[str]:
    return [a.replace("{out}", str(folder)) for a in CASES[name][0]]


def _check_failure(name: str, folder: Path, rc, err: str, causes: tuple[str, ...]) -> None:
    # the message names one of the command's outputs (or, for the gallery, its folder)
    check_failure(rc, err, {folder / f for f in CASES[name][1]} | {folder}, causes)


@pytest.fixture(scope="module")
def good(tmp_path_factory) -> dict[str, dict[str, bytes]]:
    """Every command run once as it should: its outputs, the files that must survive."""
    out = {}
    base = tmp_path_factory.mktemp("good")
    for name in CASES:
        if name in NEEDS_USD and not usd_available():
            continue
        folder = base / name
        folder.mkdir()
        assert main(_argv(name, folder)) == 0, name
        out[name] = {f: (folder / f).read_bytes() for f in CASES[name][1]}
    return out


@pytest.mark.parametrize("name", list(_params()))
def test_missing_folder(name, good, tmp_path, capsys):
    folder = tmp_path / "no" / "such"
    if name == "gallery":
        # the gallery makes its folder; a file where a folder should be stops it
        (tmp_path / "no").write_text("a file, not a folder")
        causes = ("not a directory",)
    else:
        causes = ("does not exist",)
    rc = main(_argv(name, folder))
    err = capsys.readouterr().err
    _check_failure(name, folder, rc, err, causes)
    if name != "gallery":
        assert str(tmp_path / "no") in err and not (tmp_path / "no").exists()


@pytest.mark.parametrize("name", list(_params()))
def test_read_only_folder(name, good, tmp_path, capsys):
    folder = tmp_path / "ro"
    seed(folder, good[name])
    with read_only(folder) as causes:
        rc = main(_argv(name, folder))
    err = capsys.readouterr().err
    _check_failure(name, folder, rc, err, causes)
    same(folder, good[name])


@pytest.fixture(scope="module")
def full_disk(good, tmp_path_factory):
    """Every command re-run in one child process whose files may not grow past half the
    size of the command's smallest output (the largest, for OBJ: its small .mtl is then
    written whole and its .obj fails, and neither may replace the old one)."""
    base = tmp_path_factory.mktemp("full")
    jobs = []
    for name, files in good.items():
        folder = base / name
        seed(folder, files)
        sizes = [len(data) for data in files.values()]
        limit = (max(sizes) if name == "export-obj" else min(sizes)) // 2
        jobs.append((name, _argv(name, folder), limit))
    run = subprocess.run([sys.executable, "-c", FULL_DISK_CHILD], input=json.dumps(jobs),
                         capture_output=True, text=True, timeout=300, check=False)
    assert run.returncode == 0, run.stderr
    return base, json.loads(run.stdout), run.stderr


@pytest.mark.parametrize("name", list(_params()))
def test_full_disk(name, good, full_disk):
    base, results, _ = full_disk
    rc, err = results[name]
    folder = base / name
    _check_failure(name, folder, rc, err, FULL_DISK_CAUSES)
    same(folder, good[name])


def test_full_disk_child_printed_no_traceback(full_disk):
    """Nothing reached the child's own standard error behind sys.stderr's back (a
    library's ``__del__`` repeating a failed flush, ffmpeg's complaints)."""
    stderr = full_disk[2]
    assert "Traceback" not in stderr and "Exception ignored" not in stderr, stderr


def test_broken_stdout_is_still_quiet(monkeypatch, capsys):
    """A closed pipe on stdout (``sylva derive ... | head``) stays a quiet exit 0, while a
    broken pipe met writing a file (ffmpeg gone) is an error."""

    class Closed(io.StringIO):
        def write(self, s):
            raise BrokenPipeError(32, "Broken pipe")

    monkeypatch.setattr(sys, "stdout", Closed())
    assert main(["derive", "10-abop-1.24a-plant", "-n", "1"]) == 0
    monkeypatch.undo()
    assert capsys.readouterr().err == ""



def test_a_failed_read_is_not_called_a_write(monkeypatch, capsys, tmp_path):
    import sylva.cli.export as export

    def unreadable(args):
        raise PermissionError(13, "Permission denied", "/data/in.lsys")

    monkeypatch.setattr(export, "run", unreadable)
    assert main(["export", "in.lsys", "-o", str(tmp_path / "out.glb")]) == 2
    assert capsys.readouterr().err == "sylva: error: cannot open /data/in.lsys: permission denied\n"
