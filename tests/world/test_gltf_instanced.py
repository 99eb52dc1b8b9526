"""GLB with EXT_mesh_gpu_instancing: structure, round trip of the instance data, validator."""

import io
import json
import shutil
import struct
import subprocess
from pathlib import Path

import numpy as np
import pytest

from sylva.geometry.exchange.gltf_instanced import EXTENSION, InstancedMesh, write_glb_instanced
from sylva.geometry.mesh import Material, Mesh
from sylva.world.export import write_world_glb

NODE_DIR = Path(__file__).resolve().parents[1] / "geometry" / "_node"


def _read_glb(data: bytes):
    magic, version, total = struct.unpack_from("<4sII", data)
    assert magic == b"glTF" and version == 2 and total == len(data)
    n, kind = struct.unpack_from("<I4s", data, 12)
    assert kind == b"JSON"
    doc = json.loads(data[20 : 20 + n])
    rest = data[20 + n :]
    blob = b""
    if rest:
        m, kind = struct.unpack_from("<I4s", rest)
        assert kind == b"BIN\0"
        blob = rest[8 : 8 + m]
    return doc, blob


def _accessor(doc, blob, i, dtype, width):
    acc = doc["accessors"][i]
    view = doc["bufferViews"][acc["bufferView"]]
    a = np.frombuffer(blob, dtype, acc["count"] * width, view["byteOffset"])
    return a.reshape(acc["count"], width)


def _quad():
    return Mesh(np.array([[0, 0, 0], [1, 0, 0], [1, 0, 1], [0, 0, 1]], np.float32),
                np.array([[0, 2, 1], [0, 3, 2]]), uvs=np.array([[0, 0], [1, 0], [1, 1], [0, 1]]),
                materials=[Material("m", (0.5, 0.5, 0.5, 1.0))], name="quad")


def test_instances_round_trip():
    t = np.array([[0, 0, 0], [5, 1, 2], [-3, 0, 7]], np.float32)
    yaw = np.array([0.0, 1.0, 2.0])
    q = np.stack([np.zeros(3), np.sin(yaw / 2), np.zeros(3), np.cos(yaw / 2)], 1)
    s = np.array([1.0, 2.0, 0.5])
    buf = io.BytesIO()
    write_glb_instanced([_quad()], [InstancedMesh(_quad(), t, q, s, name="plants")], buf)
    doc, blob = _read_glb(buf.getvalue())
    assert doc["extensionsUsed"] == [EXTENSION]
    node = [n for n in doc["nodes"] if "extensions" in n]
    assert len(node) == 1 and len(doc["nodes"]) == 2
    attrs = node[0]["extensions"][EXTENSION]["attributes"]
    np.testing.assert_allclose(_accessor(doc, blob, attrs["TRANSLATION"], np.float32, 3), t)
    np.testing.assert_allclose(_accessor(doc, blob, attrs["ROTATION"], np.float32, 4), q,
                               atol=1e-6)
    np.testing.assert_allclose(_accessor(doc, blob, attrs["SCALE"], np.float32, 3),
                               np.repeat(s[:, None], 3, 1))
    # the instanced mesh is stored once
    assert len(doc["meshes"]) == 2


def test_rejects_zero_quaternions():
    with pytest.raises(ValueError):
        InstancedMesh(_quad(), np.zeros((1, 3)), np.zeros((1, 4)))


def _validate(paths):
    node = shutil.which("node")
    if node is None or not (NODE_DIR / "node_modules" / "gltf-validator").is_dir():
        pytest.skip("the glTF validator needs node and tests/geometry/_node/node_modules "
                    "(npm ci there)")
    run = subprocess.run([node, str(NODE_DIR / "validate.js"), *map(str, paths)],
                         capture_output=True, text=True, timeout=180, check=False)
    assert run.returncode == 0, run.stderr
    return json.loads(run.stdout)


def test_world_glb_passes_the_validator(small_store, tmp_path):
    out = tmp_path / "world.glb"
    info = write_world_glb(small_store, out, tiles=tmp_path / "tiles")
    assert info["instances"] == small_store.n_plants
    assert info["models"] < info["instances"]  # repeated plants are instanced
    doc, _ = _read_glb(out.read_bytes())
    assert EXTENSION in doc["extensionsUsed"]
    assert len(doc["images"]) >= 5 and doc["samplers"][0]["wrapS"] == 10497
    assert any(m.get("alphaMode") == "MASK" for m in doc["materials"])  # grass tufts
    (tmp_path / "plain.glb").write_bytes(b"")
    write_glb_instanced([_quad()], [InstancedMesh(_quad(), np.zeros((2, 3)))],
                        tmp_path / "plain.glb")
    for report in _validate([out, tmp_path / "plain.glb"]):
        issues = report["issues"]
        assert issues["numErrors"] == 0, issues["messages"]
        assert issues["numWarnings"] == 0, issues["messages"]
