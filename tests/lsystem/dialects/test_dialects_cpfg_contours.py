"""cpfg's contour files (``contour: id file.con`` in the view file, cuspy's format): read
into the setting ``contours`` for the generalised cylinders; bad files name file, line,
column."""

from __future__ import annotations

import pytest

from sylva.errors import LSystemSyntaxError, SylvaWarning
from sylva.lsystem import load
from sylva.lsystem.dialects._cpfg_contour import Contour, read_contour

CON = """cver 1 3
name: leaf.con
points: 3 5
type: cr
samples: 8
-1.0 0.5 0.0 3
0.0 1.0 0.0 1
1.0 0.5 0.0 1
"""


def test_a_contour_file_reads_with_its_multiplicities():
    c = read_contour(CON, "leaf.con")
    assert c == Contour(((-1.0, 0.5, 0.0),) * 3 + ((0.0, 1.0, 0.0), (1.0, 0.5, 0.0)),
                        True, 8)  # fmt: skip
    # cuspy 1.1 reads 'open' after 'type: '; the old header 'n dim closed|open'
    assert not read_contour("cver 1 1\nname: x\npoints: 1 1\ntype: open\n0 0 0 1\n").closed
    old = read_contour("2 2 closed\n0 1\n1 0\n")
    assert old.points == ((0.0, 1.0, 0.0), (1.0, 0.0, 0.0)) and old.closed


def test_the_view_file_passes_its_contours_on(tmp_path):
    (tmp_path / "leaf.con").write_text(CON)
    (tmp_path / "p.l").write_text("Lsystem: 1\nderivation length: 0\nAxiom: @#(2)F\n"
                                  "endlsystem\n")  # fmt: skip
    (tmp_path / "p.v").write_text("contour: 2 leaf.con\n")
    p = load(tmp_path / "p.l")
    assert list(p.settings["contours"]) == [2]
    assert p.settings["contours"][2] == read_contour(CON)
    (tmp_path / "p.v").write_text("contour: 3 gone.con\n")
    with pytest.warns(SylvaWarning, match=r"p\.v:1: contour 3: cannot read gone\.con"):
        assert "contours" not in load(tmp_path / "p.l").settings
    (tmp_path / "p.v").write_text("contour: one leaf.con\n")
    with pytest.raises(LSystemSyntaxError) as e:
        load(tmp_path / "p.l")
    assert (e.value.line, e.value.column) == (1, 10) and "'one' is not a whole" in str(e.value)


@pytest.mark.parametrize("text, line, column, what", [
    ("cver 2 0\n", 1, 1, "contour format 2.0 is not known"),
    ("cver 1 3\nname: a\npoint: 1 1\n", 3, 1, "expected 'points: n m'"),
    ("cver 1 3\nname: a\npoints: 1 1\ntype: c\nsamples: 8\n 0 0 zero 1\n", 6, 2,
     "expected a point 'x y z multiplicity'"),
    ("cver 1 2\nname: a\npoints: 2 3\ntype: or\n0 0 0 1\n1 1 0 1\n", 3, 1,
     "the multiplicities make 2 points, not 3"),
    ("cver 1 2\nname: a\npoints: 2 2\ntype: or\n0 0 0 1\n", 5, 1, "the file ends after 1"),
])  # fmt: skip
def test_bad_contour_files_name_the_line_and_column(text, line, column, what):
    with pytest.raises(LSystemSyntaxError) as e:
        read_contour(text, "bad.con")
    assert (e.value.filename, e.value.line, e.value.column) == ("bad.con", line, column)
    assert what in e.value.message
