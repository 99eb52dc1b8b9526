"""The skin: greedy meshing, faces between solid and air, seams between chunks."""

import numpy as np
import pytest

from sylva.world import Block, World, WorldConfig, generate_chunk, quads_to_mesh, skin_quads
from sylva.world.blocks import texture_id
from sylva.world.meshing import quad_area


def unit_faces(quads):
    """Expand quads into the set of unit faces (direction, layer, b, c, texture)."""
    out = set()
    for d, layer, b0, c0, sb, sc, t in quads.tolist():
        for b in range(b0, b0 + sb):
            for c in range(c0, c0 + sc):
                out.add((d, layer, b, c, t))
    return out


def test_single_block():
    vox = np.zeros((3, 3, 3), np.uint8)
    vox[1, 1, 1] = Block.STONE
    q = skin_quads(vox)
    assert sorted(q[:, 0].tolist()) == [0, 1, 2, 3, 4, 5]
    m = quads_to_mesh(q)
    assert m.n_triangles == 12
    # outward normals: each face's normal points away from the block centre
    centre = m.vertices.reshape(-1, 4, 3).mean(axis=1)
    n = m.normals.reshape(-1, 4, 3)[:, 0]
    assert np.all(np.sum((centre - 1.5) * n, axis=1) > 0)
    # counter-clockwise seen from outside: the triangle normal agrees with the vertex normal
    tri = m.vertices[m.indices.astype(int)]
    cross = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    assert np.all(np.sum(cross * m.normals[m.indices[:, 0]], axis=1) > 0)


def test_hidden_faces_are_not_emitted():
    vox = np.zeros((4, 3, 4), np.uint8)
    vox[1:3, 0, 1:3] = Block.STONE  # a 2 x 1 x 2 slab on the floor
    q = skin_quads(vox, greedy=False)
    # top 4 + sides 8, none between the blocks and none at y < 0
    assert len(q) == 12
    g = skin_quads(vox)
    assert len(g) == 5  # greedy: one quad per side and the top
    assert unit_faces(g) == unit_faces(q)


def test_water_faces_only_against_air():
    vox = np.zeros((3, 4, 3), np.uint8)
    vox[:, 0, :] = Block.SAND
    vox[:, 1, :] = Block.WATER
    q = skin_quads(vox)
    water, sand = texture_id("water"), texture_id("sand")
    got = sorted((d, t) for d, t in q[:, [0, 6]].tolist())
    # the water's surface (against air) and the sand's top (seen through the water); no
    # water face against water or sand, no sand face against sand
    assert got == [(2, sand), (2, water)]


def test_greedy_keeps_the_area():
    cfg = WorldConfig(seed=3, chunk_size=16)
    c1 = generate_chunk(cfg, 0, 0, greedy=True)
    c2 = generate_chunk(cfg, 0, 0, greedy=False)
    assert quad_area(c1.quads).sum() == len(c2.quads)
    assert len(c1.quads) < len(c2.quads) / 2
    assert unit_faces(c1.quads) == unit_faces(c2.quads)


@pytest.mark.parametrize("closed", [False, True])
def test_chunks_agree_at_their_borders(closed):
    """The faces of 2 x 2 chunks are exactly the faces of one chunk of twice the size."""
    small = WorldConfig(seed=21, chunk_size=12)
    big = WorldConfig(seed=21, chunk_size=24)
    bounds = (0, 0, 24, 24) if closed else None
    parts = set()
    for cx in range(2):
        for cz in range(2):
            q = generate_chunk(small, cx, cz, bounds=bounds, greedy=False).quads
            faces = unit_faces(q)
            assert not faces & parts  # no face is emitted twice
            parts |= faces
    whole = unit_faces(generate_chunk(big, 0, 0, bounds=bounds, greedy=False).quads)
    assert parts == whole


def test_closed_world_has_walls():
    cfg = WorldConfig(seed=2, chunk_size=8)
    w = World(cfg, size=(8, 8))
    walls = w.chunk(0, 0).quads
    open_ = generate_chunk(cfg, 0, 0).quads
    assert set(np.unique(walls[:, 0])) == {0, 1, 2, 4, 5}
    assert quad_area(walls).sum() > quad_area(open_).sum()


def test_box_validation():
    with pytest.raises(ValueError, match="margin"):
        skin_quads(np.zeros((3, 3, 3), np.uint8), lo=(0, 0, 0), hi=(3, 3, 3))
