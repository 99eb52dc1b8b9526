"""Wind (sway by level, tips, thin branches, gusts, flutter) and glTF animation export."""

import json
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

from sylva.geometry.exchange.gltf_animation import SkinnedAnimation, write_animated_glb
from sylva.tree import Tree, Wind, growth_animation, wind_animation

ROOT = Path(__file__).resolve().parents[2]
NODE_DIR = ROOT / "tests" / "geometry" / "_node"


@pytest.fixture(scope="module")
def shrub():
    return Tree("hazel_shrub", seed=3).grow(4.0).mesh()


def _displacement(tm, wind, times):
    geo = tm.geometry
    rest = geo.joint_matrix[:, :3, 3]
    return np.stack([np.linalg.norm(wind.joint_matrices(geo, t)[:, :3, 3] - rest, axis=1)
                     for t in times])


def test_calm_wind_is_the_rest_pose(shrub):
    geo = shrub.geometry
    w = Wind(strength=0.0, flutter=0.0)
    assert np.allclose(w.joint_matrices(geo, 1.3), geo.joint_matrix, atol=1e-9)
    v, _ = w.deform(shrub, 2.0)
    assert np.allclose(v, shrub.mesh.vertices, atol=1e-5)


def test_sway_grows_toward_the_tips_and_with_level_and_strength(shrub):
    geo = shrub.geometry
    times = np.linspace(0, 4, 9)
    d = _displacement(shrub, Wind(1.0, seed=1), times).mean(0)
    d_strong = _displacement(shrub, Wind(2.0, seed=1), times).mean(0)
    assert d_strong.mean() > 1.5 * d.mean()
    lv = geo.joint_level
    means = [d[lv == k].mean() for k in range(lv.max() + 1)]
    assert means[0] < means[2]
    amp = Wind(1.0, seed=1)._setup(geo)["amp"]
    med = [np.median(amp[lv == k]) for k in range(lv.max() + 1)]
    assert med[0] < med[1] < med[2]  # per-joint bend rises with the level
    # along each chain a child joint moves at least about as far as its parent (tips most)
    p = geo.joint_parent
    has = p >= 0
    assert np.mean(d[has] >= d[p[has]] - 1e-6) > 0.9
    # the wind bends the crown downwind on average
    rest = geo.joint_matrix[:, :3, 3]
    moved = np.mean([Wind(1.5, seed=1).joint_matrices(geo, t)[:, 0, 3] - rest[:, 0]
                     for t in times], axis=0)
    assert moved[lv == 2].mean() > 0


def test_thinner_branches_sway_more(shrub):
    geo = shrub.geometry
    w = Wind(1.0, seed=2)
    s = w._setup(geo)
    lv2 = geo.joint_level == 2
    r = geo.joint_radius[lv2]
    amp = s["amp"][lv2]
    thin, thick = r < np.percentile(r, 25), r > np.percentile(r, 75)
    assert amp[thin].mean() > amp[thick].mean()


def test_gusts_vary_in_time_and_are_seeded():
    t = np.linspace(0, 20, 200)
    g1, g2 = Wind(seed=1).gust(t), Wind(seed=2).gust(t)
    assert g1.std() > 0.05 and np.array_equal(g1, Wind(seed=1).gust(t))
    assert not np.allclose(g1, g2)
    assert g1.min() >= 0.15 and g1.max() <= 1.35


def test_leaves_flutter(shrub):
    w = Wind(1.0, seed=4)
    v1, _ = w.deform(shrub, 0.10)
    v2, _ = w.deform(shrub, 0.17)
    leaf = shrub.vertex_leaf >= 0
    assert np.abs(v1[leaf] - v2[leaf]).max() > 0
    quiet = Wind(1.0, seed=4, flutter=0.0)
    a = quiet.deform(shrub, 0.10)[0]
    assert np.abs(v1[leaf] - a[leaf]).max() > 0


def _validate(paths):
    node = shutil.which("node")
    if node is None:
        pytest.skip("node is not installed: cannot run the Khronos glTF validator")
    if not (NODE_DIR / "node_modules" / "gltf-validator").is_dir():
        pytest.skip("tests/geometry/_node/node_modules is missing (run `npm ci` there)")
    out = subprocess.run([node, str(NODE_DIR / "validate.js"), *map(str, paths)],
                         capture_output=True, text=True, check=True, timeout=120)
    return json.loads(out.stdout)


def _read_glb(path):
    data = Path(path).read_bytes()
    (n,) = np.frombuffer(data[12:16], np.uint32)
    return json.loads(data[20:20 + int(n)])


def test_wind_and_growth_glb_pass_the_khronos_validator(tmp_path, shrub):
    wind = wind_animation(shrub, Wind(1.5, seed=1), seconds=1.0, fps=8)
    growth = growth_animation(Tree("hazel_shrub", seed=3), 0.2, 4.0, seconds=1.0, fps=6)
    pw, pg = tmp_path / "wind.glb", tmp_path / "growth.glb"
    write_animated_glb(wind, pw)
    write_animated_glb(growth, pg)
    for report in _validate([pw, pg]):
        issues = report["issues"]
        bad = [m for m in issues["messages"] if m["severity"] <= 1]
        assert issues["numErrors"] == 0 and issues["numWarnings"] == 0, (report["file"], bad)
        assert report["info"]["animationCount"] == 1 and report["info"]["hasSkins"]
    doc = _read_glb(pw)
    paths = {c["target"]["path"] for c in doc["animations"][0]["channels"]}
    assert paths == {"translation", "rotation", "weights"}
    assert len(doc["meshes"][0]["primitives"][0]["targets"]) == 3
    assert len(doc["skins"][0]["joints"]) == shrub.geometry.n_joints
    gdoc = _read_glb(pg)
    assert {c["target"]["path"] for c in gdoc["animations"][0]["channels"]} == {
        "translation", "rotation", "scale"}


def test_growth_keyframes_start_small_and_end_at_the_bind_pose():
    a = growth_animation(Tree("hazel_shrub", seed=3), 0.2, 4.0, seconds=1.0, fps=4)
    assert np.allclose(a.translation[-1], a.bind_matrices[:, :3, 3], atol=1e-6)
    assert np.allclose(a.scale[-1], 1.0, atol=1e-6)
    born_late = a.scale[0, :, 0] < 1e-3
    assert born_late.mean() > 0.5  # most of the tree does not exist at age 0.2


def test_skinned_animation_checks_its_shapes(tmp_path):
    from sylva.geometry.mesh import Mesh

    m = Mesh(np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]]), np.array([[0, 1, 2]]))
    bad = SkinnedAnimation(m, np.array([0, 0, 5]), np.eye(4)[None], np.array([0.0, 1.0]),
                           np.zeros((2, 1, 3)), np.tile([0, 0, 0, 1.0], (2, 1, 1)))
    with pytest.raises(ValueError, match="vertex_joint"):
        write_animated_glb(bad, tmp_path / "x.glb")
    bad2 = SkinnedAnimation(m, np.zeros(3, int), np.eye(4)[None], np.array([1.0, 1.0]),
                            np.zeros((2, 1, 3)), np.tile([0, 0, 0, 1.0], (2, 1, 1)))
    with pytest.raises(ValueError, match="increasing"):
        write_animated_glb(bad2, tmp_path / "x.glb")


def _qmat(q):
    x, y, z, w = q.T
    return np.stack([
        np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)], -1),
        np.stack([2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)], -1),
        np.stack([2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)], -1),
    ], 1)


def _pose(anim, k):
    """What a glTF player draws at keyframe k (linear blend skinning, one joint per vertex)."""
    n = len(anim.bind_matrices)
    m = np.zeros((n, 4, 4))
    m[:, 3, 3] = 1.0
    scale = anim.scale[k] if anim.scale is not None else np.ones((n, 3))
    m[:, :3, :3] = _qmat(anim.rotation[k]) * scale[:, None, :]
    m[:, :3, 3] = anim.translation[k]
    skin = (m @ np.linalg.inv(anim.bind_matrices))[anim.vertex_joint]
    v = anim.mesh.vertices.astype(np.float64)
    return np.einsum("nij,nj->ni", skin[:, :3, :3], v) + skin[:, :3, 3]


def test_growth_pose_matches_the_tree_grown_to_that_age():
    anim = growth_animation(Tree("hazel_shrub", seed=3), 0.2, 4.0, seconds=1.0, fps=4)
    n_bark = Tree("hazel_shrub", seed=3).grow(4.0).mesh().n_bark_vertices
    for k, age in enumerate(np.linspace(0.2, 4.0, 5)):
        tm = Tree("hazel_shrub", seed=3).grow(age).mesh()
        bark = tm.mesh.vertices[tm.vertex_leaf < 0]
        posed = _pose(anim, k)[:n_bark]
        assert posed[:, 1].max() == pytest.approx(bark[:, 1].max(), rel=1e-3, abs=1e-4)
        assert np.abs(posed[:, [0, 2]]).max() == pytest.approx(
            np.abs(bark[:, [0, 2]]).max(), rel=0.05, abs=1e-3)


def test_wind_pose_matches_the_deformed_mesh(shrub):
    w = Wind(1.5, seed=1, flutter=0.0)
    anim = wind_animation(shrub, w, seconds=1.0, fps=4)
    for k, t in enumerate(anim.times):
        want, _ = w.deform(shrub, float(t))
        assert np.allclose(_pose(anim, k), want, atol=2e-4)
