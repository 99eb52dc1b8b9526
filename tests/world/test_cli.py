"""``sylva world``."""

import numpy as np
import pytest
from PIL import Image

from sylva.cli import main


def test_glb_and_biome_map(tmp_path, capsys):
    out = tmp_path / "w.glb"
    rc = main(["world", "--seed", "3", "--size", "32x24", "--chunk", "16", "-o", str(out),
               "--biomes", "--workers", "1", "--quiet"])
    assert rc == 0
    assert out.read_bytes()[:4] == b"glTF"
    img = np.asarray(Image.open(tmp_path / "w.biomes.png"))
    assert img.shape == (24, 32, 3)
    again = tmp_path / "again.glb"
    main(["world", "--seed", "3", "--size", "32x24", "--chunk", "16", "-o", str(again),
          "--workers", "1", "--quiet"])
    assert again.read_bytes() == out.read_bytes()  # the same seed gives the same world


def test_png_render(tmp_path):
    out = tmp_path / "w.png"
    rc = main(["world", "--seed", "5", "--size", "24x24", "--chunk", "8", "-o", str(out),
               "--image-size", "160x120", "--workers", "1", "--quiet", "--no-shadows"])
    assert rc == 0
    img = np.asarray(Image.open(out).convert("RGB")).astype(int)
    assert img.shape == (120, 160, 3)
    sky = np.array([0x9F, 0xC8, 0xEF])
    not_sky = np.any(np.abs(img - sky) > 12, axis=-1)
    assert 0.1 < not_sky.mean() < 0.95  # the world fills part of the frame


def test_bad_output(tmp_path, capsys):
    assert main(["world", "--size", "8x8", "-o", str(tmp_path / "w.obj"), "--quiet"]) == 2
    assert "expected a .png, .glb or .zarr" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        main(["world", "--size", "0x8", "-o", "x.png"])


def test_other_sylva_plants(tmp_path):
    from sylva.data import find

    out = tmp_path / "w.glb"
    lsys = find("abop-1.24a-plant").path
    rc = main(["world", "--seed", "2", "--size", "32x32", "--chunk", "16", "-o", str(out),
               "--workers", "1", "--quiet", "--no-grass", "--tree-variants", "2",
               *[f"--plant={b}={lsys}" for b in ("grassland", "woodland", "shrubland",
                 "savanna", "seasonal_forest", "boreal_forest", "tundra",
                 "subtropical_desert", "tropical_forest", "tropical_rainforest",
                 "temperate_rainforest", "cold_desert", "ice")]])  # fmt: skip
    assert rc == 0
    data = out.read_bytes()
    assert b"lsys_10_abop_1_24a_plant#" in data
    assert main(["world", "--size", "8x8", "-o", str(out), "--plant", "mars=oak",
                 "--quiet"]) == 2


def test_zarr_store_with_models(tmp_path, capsys):
    import json

    from sylva.world import open_world

    out = tmp_path / "w.zarr"
    rc = main(["world", "--seed", "3", "--size", "32x24", "--chunk", "16", "-o", str(out),
               "--workers", "1", "--quiet"])
    assert rc == 0
    store = open_world(out)
    assert store.complete and store.size == (32, 24)
    files = store.manifest["model_files"]
    assert sorted(files) == sorted(set(store.plants().column("model").to_pylist()))
    for f in files.values():
        assert (out / f).read_bytes()[:4] == b"glTF"
    manifest = json.loads((out / "manifest.json").read_text())
    assert manifest["config"]["seed"] == 3
    # an existing store is not overwritten; --resume on a complete one has nothing to do
    assert main(["world", "--seed", "3", "--size", "32x24", "--chunk", "16", "-o", str(out),
                 "--workers", "1", "--quiet"]) == 2
    assert "--resume" in capsys.readouterr().err
    assert main(["world", "--seed", "3", "--size", "32x24", "--chunk", "16", "-o", str(out),
                 "--workers", "1", "--quiet", "--resume"]) == 0
