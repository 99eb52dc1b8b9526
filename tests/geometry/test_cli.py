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


def test_export_takes_an_example_name_as_every_other_command_does(tmp_path, capsys):
    out = tmp_path / "plant.glb"
    assert main(["export", "13-abop-1.24d-plant", "-o", str(out), "-n", "2"]) == 0
    back = trimesh.load(out, force="mesh", process=False)
    assert len(back.faces) > 0
    assert main(["export", "no-such-example", "-o", str(out)]) == 2
    assert "no built-in example of that name" in capsys.readouterr().err


@pytest.mark.parametrize("ext", ["stl", "ply"])
def test_export_up_axis_follows_the_format_and_the_option(t14, tmp_path, ext):
    heights = {}
    for up in (None, "y", "z"):
        out = tmp_path / f"plant-{up}.{ext}"
        extra = [] if up is None else ["--up", up]
        assert main(["export", str(t14), "-o", str(out), "-n", "2", *extra]) == 0
        heights[up] = trimesh.load(out, force="mesh", process=False).extents
    assert heights["z"].tolist() == pytest.approx(heights[None].tolist())  # STL, PLY: Z up
    assert heights["z"][2] == pytest.approx(heights["y"][1])
    assert heights["z"][2] > heights["z"][1]  # the plant stands up


def test_export_up_is_refused_for_fixed_frames(t14, tmp_path, capsys):
    assert main(["export", str(t14), "-o", str(tmp_path / "p.pov"), "--up", "z"]) == 2
    assert "--up" in capsys.readouterr().err
