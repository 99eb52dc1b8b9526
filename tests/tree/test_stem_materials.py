"""The Stem object and the material database."""

import numpy as np
import pytest

from sylva.errors import LSystemSyntaxError
from sylva.geometry.mesh import vertex_normals
from sylva.tree.materials import MaterialDatabase, MaterialError, MaterialSpec
from sylva.tree.stem import Stem, stems_to_arrays


def _bent_stem(sides=8):
    s = Stem(sides=sides)
    t = np.linspace(0, 1, 7)
    pts = np.stack([0.3 * t**2, 2 * t, 0.1 * t], 1)
    s.add_points(pts, None, 0.2 * (1 - 0.8 * t))
    return s


def test_rings_have_the_radius_around_the_axis_and_face_outward():
    s = _bent_stem()
    v, n, uv, tri, joints, tri_stem = stems_to_arrays([s])
    assert v.shape == (7 * 9, 3) and tri.shape == (2 * 8 * 6, 3)
    rings = v.reshape(7, 9, 3)
    centres = s.positions
    radii = np.linalg.norm(rings - centres[:, None, :], axis=2)
    assert np.allclose(radii, s.radii[:, None], atol=1e-5)
    assert np.allclose(rings[:, 0], rings[:, -1])  # the seam is duplicated
    # the triangles' winding agrees with the outward normals
    fn = vertex_normals(v, tri)
    assert np.all(np.einsum("ij,ij->i", fn, n) > 0)
    # u runs around 0..1, v grows along the stem
    assert np.allclose(uv[:9, 0], np.linspace(0, 1, 9))
    assert np.all(np.diff(uv.reshape(7, 9, 2)[:, 0, 1]) > 0)
    assert np.all(tri_stem == 0) and np.all(joints == -1)


def test_many_stems_in_one_pass_with_different_sides_and_lobes():
    a, b = _bent_stem(8), _bent_stem(5)
    c = Stem(sides=6, lobes=5, lobe_depth=0.2)
    c.add_points([[0, 0, 0], [0, 1, 0], [0, 2, 0]], None, [0.3, 0.3, 0.3], [4, 5, 6])
    short = Stem()
    short.add_point([0, 0, 0], None, 0.1)  # one point: no tube
    v, n, uv, tri, joints, tri_stem = stems_to_arrays([a, short, b, c])
    assert len(v) == 7 * 9 + 7 * 6 + 3 * 7
    assert set(np.unique(tri_stem)) == {0, 2, 3}
    lobed = v[joints == 4]
    r = np.linalg.norm(lobed[:, [0, 2]], axis=1)
    assert r.max() > 0.33 and r.min() < 0.27  # lobes bulge and dent the first ring
    with pytest.raises(ValueError):
        Stem(sides=2)


def test_given_orientations_are_used():
    s = Stem(sides=4)
    frame = np.eye(3)[[2, 0, 1]].T  # columns: x -> z, tangent -> x, z -> y
    s.add_points([[0, 0, 0], [1, 0, 0]], np.stack([frame, frame]), [1.0, 1.0])
    v = stems_to_arrays([s])[0]
    assert np.allclose(v[:5, 0], 0.0, atol=1e-6)  # the first ring lies in the x = 0 plane


def test_material_database_default_and_lookup():
    db = MaterialDatabase.default()
    assert {"bark", "leaf", "bark.aspen", "leaf.aspen", "leaf.billboard"} <= set(db.names())
    leaf = db["leaf.billboard"]
    assert leaf.billboard and leaf.double_sided and leaf.alpha_test == 0.5
    m = leaf.to_material()
    assert m.double_sided and m.alpha_cutoff == 0.5 and m.texture == "leaf"
    assert db.get("bark.unknown", "bark").color == db["bark"].color
    with pytest.raises(MaterialError, match="unknown material"):
        db["nothing"]
    assert db.id_of("leaf") == 1
    db.register(MaterialSpec("extra", (1, 0, 0, 1)))
    again = MaterialDatabase.from_text(db.dumps())
    assert again.names() == db.names() and again["extra"].color == (1, 0, 0, 1)


@pytest.mark.parametrize(
    ("text", "line", "words"),
    [
        ("[global]\ncolor = 1 1 1\n", 1, "material NAME"),
        ("[material a]\nshine = 3\n", 2, "unknown material attribute"),
        ("[material a]\ncolor = 1\n", 2, "3 or 4 numbers"),
        ("[material a]\ndouble_sided = \"yes\"\n", 2, "true or false"),
    ],
)
def test_material_file_errors(text, line, words):
    with pytest.raises(LSystemSyntaxError) as info:
        MaterialDatabase.from_text(text, "m.txt")
    assert words in str(info.value) and info.value.line == line
