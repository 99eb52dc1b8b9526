"""``sylva export FILE -o OUT``."""

from __future__ import annotations

import xml.etree.ElementTree as ET

import pytest
import trimesh

from sylva.cli import main

T14 = """bg = 1, 1, 1
rot = 35
color = 0.4, 0.2, 0.1

axiom = X

X -> F[+X]F[-X]+(20)X
F -> FF

X ->> ; (0,0.7,0)F
"""


@pytest.fixture()
def t14(tmp_path):
    path = tmp_path / "t14.lsys"
    path.write_text(T14)
    return path


@pytest.mark.parametrize("ext", ["glb", "obj", "stl", "ply"])
def test_export_writes_the_format_of_the_extension(t14, tmp_path, ext, capsys):
    out = tmp_path / f"plant.{ext}"
    assert main(["export", str(t14), "-o", str(out), "-n", "3", "--detail", "5"]) == 0
    back = trimesh.load(out, force="mesh", process=False)
    # seed 001 T14 at step 3: 65 segments -> tubes of 5 sides (20 axes: 2 caps each)
    assert len(back.faces) > 65 * 2 * 5
    assert "183 modules" in capsys.readouterr().err


def test_export_svg_draws_the_turtle_lines(t14, tmp_path):
    out = tmp_path / "plant.svg"
    assert main(["export", str(t14), "-o", str(out), "-n", "2"]) == 0
    d = " ".join(
        p.get("d") for p in ET.parse(out).getroot().iter("{http://www.w3.org/2000/svg}path")
    )
    assert d.count("L") == 19  # T14 step 2: 19 drawn segments


def test_export_rejects_unknown_extensions(t14, tmp_path, capsys):
    assert main(["export", str(t14), "-o", str(tmp_path / "plant.fbx")]) == 2
    assert "cannot tell the export format" in capsys.readouterr().err


ACACIA = """45.0 45.0 0.8
^uA1S&F+F+F+F
U > uU
A > +uuE
A > -uE
A > uE
E > x[++++UE1S&F+F+F+F]+UE
E > x[++UE1S&F+F+F+F]-UE
"""


def test_export_engine_program_as_blocks_per_buffer(tmp_path):
    src = tmp_path / "acacia.txt"
    src.write_text(ACACIA)
    outs = []
    for seed in (1, 1, 2):
        out = tmp_path / f"acacia{len(outs)}.glb"
        assert main(["export", str(src), "-o", str(out), "-n", "3", "--seed", str(seed)]) == 0
        outs.append(out.read_bytes())
        scene = trimesh.load(out, force="scene", process=False)
        names = {g.visual.material.name for g in scene.geometry.values()}
        assert names == {"buffer_0", "buffer_1"}  # trunk and leaves
    assert outs[0] == outs[1] and outs[0] != outs[2]
