"""A scene with nothing to draw is written as a valid, empty file in every mesh format."""

from __future__ import annotations

import json
import re
import shutil
import subprocess

import numpy as np
import pytest

from sylva.cli import main
from sylva.geometry.exchange import write
from sylva.geometry.exchange.gltf_instanced import write_glb_instanced
from sylva.geometry.mesh import Scene

from .test_exchange import _gltf_validator_reports

meshio = pytest.importorskip("meshio")

NOTHING = "axiom = X\nX -> +X\n"  # turns, never draws


def test_empty_gltf_and_glb_pass_the_khronos_validator(tmp_path):
    files = []
    for name in ("empty.glb", "empty.gltf"):
        write(Scene([], name="nothing"), tmp_path / name)
        files.append(tmp_path / name)
    write_glb_instanced([], [], tmp_path / "instanced.glb")
    files.append(tmp_path / "instanced.glb")
    for report in _gltf_validator_reports(files):
        issues = report["issues"]
        # was EMPTY_ENTITY twice: "nodes": [] and "scenes"[0]["nodes"]: []
        assert issues["numErrors"] == 0 and issues["numWarnings"] == 0, report
    doc = json.loads((tmp_path / "empty.gltf").read_text())
    assert doc["scenes"] == [{"name": "nothing"}] and "nodes" not in doc


def test_cli_export_of_nothing_writes_a_valid_empty_file(tmp_path, capsys):
    src = tmp_path / "nothing.lsys"
    src.write_text(NOTHING)
    out = tmp_path / "nothing.glb"
    assert main(["export", str(src), "-n", "3", "-o", str(out)]) == 0
    assert "nothing to draw" in capsys.readouterr().err
    (report,) = _gltf_validator_reports([out])
    assert report["issues"]["numErrors"] == 0 and report["issues"]["numWarnings"] == 0


@pytest.mark.parametrize("ext", ["stl", "ply", "obj"])
def test_empty_stl_ply_obj_read_back_as_empty_meshes(ext, tmp_path):
    path = tmp_path / f"empty.{ext}"
    write(Scene([]), path)
    back = meshio.read(path)
    assert len(back.points) == 0
    assert sum(len(c.data) for c in back.cells) == 0
    if ext == "stl":  # 80-byte header and a zero triangle count, nothing else
        data = path.read_bytes()
        assert len(data) == 84 and np.frombuffer(data[80:], "<u4")[0] == 0


def test_empty_pov_scene_parses_and_renders(tmp_path):
    """POV-Ray refuses a camera whose location is its look_at point, which is where the
    camera of an empty scene's (zero) bounds used to be."""
    path = tmp_path / "empty.pov"
    write(Scene([]), path)
    cam = re.search(r"camera \{ location <([^>]*)> look_at <([^>]*)>", path.read_text())
    loc, at = (np.array([float(v) for v in g.split(",")]) for g in cam.groups())
    assert np.linalg.norm(loc - at) > 0.1
    povray = shutil.which("povray")
    if povray is None:
        pytest.skip("povray is not installed")
    run = subprocess.run([povray, f"+I{path}", f"+O{tmp_path / 'e.png'}", "+W16", "+H16",
                          "-D", "-GA"], capture_output=True, text=True, timeout=60,
                         check=False)
    assert run.returncode == 0 and (tmp_path / "e.png").exists(), run.stderr[-2000:]
