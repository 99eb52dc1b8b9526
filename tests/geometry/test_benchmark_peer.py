"""The mesh benchmark's peer builds real tubes, so the ratio printed against it means something."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np

from sylva.turtle import interpret

_PATH = Path(__file__).resolve().parents[2] / "benchmarks" / "mesh.py"


def _bench():
    spec = importlib.util.spec_from_file_location("sylva_bench_mesh", _PATH)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_numpy_peer_builds_tubes_around_every_segment():
    bench = _bench()
    g = interpret(bench.plant_word(200), dialect="abop", rot=28.0, thick=0.05, thick_factor=0.85)
    d = 8
    verts, normals, uvs, idx = bench.numpy_tubes(g, d)
    n = g.n_segments
    assert verts.shape == (n * 2 * (d + 1), 3) and idx.shape == (n * 2 * d, 3)
    assert idx.max() == len(verts) - 1
    assert np.allclose(np.linalg.norm(normals, axis=1), 1.0, atol=1e-5)
    ring = verts.reshape(n, 2, d + 1, 3)
    centre = np.stack([g.seg_start, g.seg_end], axis=1)[:, :, None, :]
    dist = np.linalg.norm(ring - centre, axis=3)
    assert np.allclose(dist, g.seg_radius[:, :, None], rtol=1e-4, atol=1e-6)
    # the normal at each ring vertex points from the axis to it
    off = (ring - centre).reshape(-1, 3)
    assert np.all(np.einsum("ij,ij->i", off, normals) > 0)
    # each side quad joins the start ring to the end ring of its own segment
    seg = idx // (2 * (d + 1))
    assert np.all(seg == seg[:, :1])
    assert uvs.min() >= 0.0 and uvs.max() <= 1.0
