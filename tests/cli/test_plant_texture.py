"""L-system textures from sylva programs: seed 003 §4.8 ex. 8, L-Studio's parametric tree."""

from __future__ import annotations

import numpy as np
from PIL import Image

from sylva.cli import main
from sylva.lsystem import Derivation
from sylva.plant import plant_texture, resolve, texture_segments
from sylva.turtle import interpret

TREE = "36-seed003-lstudio-tree"


def test_listing_is_the_cpfg_tree():
    p = resolve(TREE)
    assert p.steps == 7 and p.seed == 2454 and p.settings["rot"] == 20
    weights = sorted(r.weight.value for r in p.rules if r.predecessor.symbol == "F")
    assert weights == [0.4, 0.6]


def _semicolons_on_path(text: str) -> list[int]:
    """For every F of a bracketed word: the ; before it on its path (an independent walk)."""
    count, stack, out = 0, [], []
    for ch in text:
        if ch == "[":
            stack.append(count)
        elif ch == "]":
            count = stack.pop()
        elif ch == ";":
            count += 1
        elif ch == "F":
            out.append(count)
    return out


def test_colour_index_advances_once_per_x_on_the_path():
    p = resolve(TREE)
    d = Derivation(p, seed=2454)
    d.advance(4)
    word = d.render_word()
    g = interpret(word, p)
    text = "".join(word.alphabet.names[i] for i in word.ids)
    expected = np.array(_semicolons_on_path(text)) % 8
    assert g.n_segments == len(expected) and expected.max() >= 3
    np.testing.assert_array_equal(g.seg_material, expected)
    segs = texture_segments(g, width=4.0)
    assert segs.width[0] == 4.0 and segs.width.min() < 4.0  # ! thins the line


def test_texture_is_seeded_and_fills_the_image():
    a = plant_texture(TREE, (96, 80), steps=5, background="#ffffff")
    b = plant_texture(TREE, (96, 80), steps=5, background="#ffffff")
    c = plant_texture(TREE, (96, 80), steps=5, seed=7, background="#ffffff")
    assert a.shape == (96, 80, 3)
    np.testing.assert_array_equal(a, b)
    assert not np.array_equal(a, c)
    ink = (a < 250).any(axis=2)
    rows, cols = np.flatnonzero(ink.any(axis=1)), np.flatnonzero(ink.any(axis=0))
    assert rows.max() - rows.min() > 0.8 * 96 or cols.max() - cols.min() > 0.8 * 80


def test_tileable_texture_wraps():
    img = plant_texture(TREE, (64, 64), steps=4, tileable=True, count=6, size=0.6)
    # copies are placed with wrap-around: ink reaches both opposite edges
    ink = (img > 8).any(axis=2)
    assert ink[:, 0].any() or ink[0, :].any()


def test_cli_draws_an_lsystem(capsys, tmp_path):
    out = tmp_path / "tree.png"
    code = main(["texture", "--lsystem", TREE, "-o", str(out), "--size", "64x48",
                 "--iterations", "3"])  # fmt: skip
    assert code == 0
    with Image.open(out) as im:
        assert im.size == (64, 48)
    assert main(["texture", "--lsystem", "no-such-plant", "-o", str(out)]) != 0
    assert "no such file" in capsys.readouterr().err
    assert main(["texture", "--lsystem", TREE, "-o", str(out), "--octaves", "3"]) != 0
    assert "not --octaves" in capsys.readouterr().err
