"""``sylva texture --graph FILE`` and ``--save-graph``: a preset saved as a graph renders the
same image; a bad graph file is one error line with its position, not a traceback."""

import numpy as np
from PIL import Image

from sylva.cli import main


def test_cli_graph_round_trip_and_errors(tmp_path, capsys):
    g = tmp_path / "m.toml"
    png = tmp_path / "preset.png"
    assert main(["texture", "arabescato-marble", "--size", "40x24", "-o", str(png),
                 "--save-graph", str(g)]) == 0
    assert "[nodes.out]" in g.read_text() and 'type = "marble"' in g.read_text()
    out = tmp_path / "graph.png"
    assert main(["texture", "--graph", str(g), "-o", str(out)]) == 0
    with Image.open(png) as a, Image.open(out) as b:
        assert a.size == b.size == (40, 24)
        np.testing.assert_array_equal(np.asarray(a), np.asarray(b))
    assert main(["texture", "--graph", str(g), "-o", str(out), "--size", "20x10",
                 "--colors", "0:#000000,1:#ff0000"]) == 0
    with Image.open(out) as im:
        px = np.asarray(im)
        assert im.size == (20, 10) and (px[..., 1:] == 0).all() and px[..., 0].max() > 100
    bad = tmp_path / "bad.toml"
    bad.write_text('[graph]\noutput = "a"\n[nodes.a]\ntype = "clamp"\nsource = "g"\n'
                   '[nodes.g]\ntype = "gradient"\nsource = 0.5\n')
    capsys.readouterr()
    assert main(["texture", "--graph", str(bad), "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert f"{bad}:5:10:" in err and "takes a scalar" in err and "Traceback" not in err
    assert main(["texture", "--graph", str(g), "-o", str(out), "--octaves", "3"]) == 2
