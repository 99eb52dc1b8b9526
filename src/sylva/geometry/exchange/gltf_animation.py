"""Animated binary glTF 2.0: a skinned mesh, its skeleton and keyframed joint transforms.

One mesh (one primitive per material, sharing ``POSITION``, ``NORMAL``, ``TEXCOORD_0``,
``COLOR_0``, ``JOINTS_0``, ``WEIGHTS_0`` and optional morph targets) is bound rigidly to a
flat skeleton: every vertex follows one joint (weight 1).  Joints are children of one
``skeleton`` node, so each joint's keyframes are its full transform (translation, rotation
quaternion, scale) in the skeleton's space; the animation samples them linearly (rotations
are slerped by the players).  Morph targets (e.g. leaf flutter) get a ``weights`` channel.
This plays in Blender's importer and three.js' ``GLTFLoader``, and the tests run the Khronos
validator on it.  Coordinates are sylva's (right-handed, +Y up), as glTF's.

Examples
--------
>>> import io, numpy as np
>>> from sylva.geometry.mesh import Mesh
>>> m = Mesh(np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]]), np.array([[0, 1, 2]]))
>>> eye = np.eye(4)[None]
>>> anim = SkinnedAnimation(m, np.zeros(3, int), eye, np.array([0.0, 1.0]),
...                         translation=np.zeros((2, 1, 3)),
...                         rotation=np.tile([0, 0, 0, 1.0], (2, 1, 1)))
>>> buf = io.BytesIO(); write_animated_glb(anim, buf)
>>> buf.getvalue()[:4]
b'glTF'
"""

from __future__ import annotations

import json
import struct
from dataclasses import dataclass, field

import numpy as np

from ..mesh import Mesh
from ._common import (
    PathOrFile,
    gltf_color0,
    material_groups,
    open_target,
    scaled_base,
    tint_scales,
)

__all__ = ["SkinnedAnimation", "animated_gltf_document", "write_animated_glb"]

_FLOAT, _UINT, _USHORT = 5126, 5125, 5123
_ARRAY, _ELEMENTS = 34962, 34963


@dataclass
class SkinnedAnimation:
    """A rigidly skinned mesh with keyframed joints.

    Attributes
    ----------
    mesh : Mesh
        The bind pose.
    vertex_joint : int[n]
        The joint each vertex follows.
    bind_matrices : float[j, 4, 4]
        Joint frames in the bind pose (the inverse bind matrices are their inverses).
    times : float[k]
        Strictly increasing keyframe times in seconds.
    translation : float[k, j, 3]
    rotation : float[k, j, 4]
        Unit quaternions ``(x, y, z, w)``.
    scale : float[k, j, 3] or None
    morph_targets : list of float[n, 3]
        Position displacements.
    weights : float[k, t] or None
        Morph weights per keyframe.
    joint_names : list of str or None
    name : str
        The animation's name.
    """

    mesh: Mesh
    vertex_joint: np.ndarray
    bind_matrices: np.ndarray
    times: np.ndarray
    translation: np.ndarray
    rotation: np.ndarray
    scale: np.ndarray | None = None
    morph_targets: list = field(default_factory=list)
    weights: np.ndarray | None = None
    joint_names: list | None = None
    name: str = "animation"

    def check(self) -> None:
        n = self.mesh.n_vertices
        j = len(self.bind_matrices)
        k = len(self.times)
        if self.vertex_joint.shape != (n,) or (n and (self.vertex_joint.min() < 0
                                                       or self.vertex_joint.max() >= j)):
            raise ValueError("vertex_joint: expected one joint index in [0, j) per vertex")
        if j > 65535:
            raise ValueError(f"{j} joints: glTF JOINTS_0 as unsigned short holds at most 65535")
        if k < 1 or np.any(np.diff(self.times) <= 0):
            raise ValueError("times: expected at least one strictly increasing time")
        if self.translation.shape != (k, j, 3) or self.rotation.shape != (k, j, 4):
            raise ValueError("translation/rotation: expected shapes (k, j, 3) and (k, j, 4)")
        if self.scale is not None and self.scale.shape != (k, j, 3):
            raise ValueError("scale: expected shape (k, j, 3)")
        if self.morph_targets and (self.weights is None
                                   or self.weights.shape != (k, len(self.morph_targets))):
            raise ValueError("weights: expected shape (k, number of morph targets)")


class _Buf:
    def __init__(self) -> None:
        self.parts: list[bytes] = []
        self.size = 0
        self.views: list[dict] = []
        self.accessors: list[dict] = []

    def add(self, arr: np.ndarray, kind: str, ctype: int, target: int | None = None,
            minmax: bool = False) -> int:
        data = np.ascontiguousarray(arr).tobytes()
        pad = (-self.size) % 4
        if pad:
            self.parts.append(b"\0" * pad)
            self.size += pad
        view = {"buffer": 0, "byteOffset": self.size, "byteLength": len(data)}
        if target is not None:
            view["target"] = target
        self.views.append(view)
        self.parts.append(data)
        self.size += len(data)
        count = int(arr.shape[0])
        acc = {"bufferView": len(self.views) - 1, "componentType": ctype, "count": count,
               "type": kind}
        if minmax:
            flat = arr.reshape(count, -1)
            acc["min"] = [float(x) for x in flat.min(0)]
            acc["max"] = [float(x) for x in flat.max(0)]
        self.accessors.append(acc)
        return len(self.accessors) - 1

    def blob(self) -> bytes:
        b = b"".join(self.parts)
        return b + b"\0" * ((-len(b)) % 4)


def _joint_table(vertex_joint: np.ndarray, n_joints: int) -> tuple[np.ndarray, np.ndarray]:
    """JOINTS_0 (u16[n, 4], distinct indices) and WEIGHTS_0 (f32[n, 4]) for rigid binding."""
    n = len(vertex_joint)
    j = vertex_joint.astype(np.int64)
    joints = np.empty((n, 4), np.uint16)
    joints[:, 0] = j
    joints[:, 1:] = 0  # unused slots: joint 0 with weight 0 (what the validator expects)
    weights = np.zeros((n, 4), np.float32)
    weights[:, 0] = 1.0
    return joints, weights


def animated_gltf_document(anim: SkinnedAnimation) -> tuple[dict, bytes]:
    """The glTF JSON (without the buffer URI) and the binary buffer of ``anim``."""
    anim.check()
    mesh = anim.mesh
    scales = tint_scales([mesh])
    J = len(anim.bind_matrices)
    n_pad = max(J, 4)  # at least four joints, so that the four JOINTS_0 slots differ
    b = _Buf()
    attrs = {
        "POSITION": b.add(mesh.vertices.astype(np.float32), "VEC3", _FLOAT, _ARRAY, True),
        "NORMAL": b.add(_unit(mesh.normals), "VEC3", _FLOAT, _ARRAY),
    }
    if mesh.uvs is not None:
        attrs["TEXCOORD_0"] = b.add(mesh.uvs.astype(np.float32), "VEC2", _FLOAT, _ARRAY)
    if mesh.colors is not None:
        attrs["COLOR_0"] = b.add(gltf_color0(mesh, scales), "VEC4", _FLOAT, _ARRAY)
    wind = (mesh.attributes or {}).get("WIND")
    if wind is not None and wind.shape[1] == 4:  # sylva.geometry.lod's wind vertex data
        attrs["_WIND"] = b.add(np.ascontiguousarray(wind, np.float32), "VEC4", _FLOAT, _ARRAY)
    jt, wt = _joint_table(anim.vertex_joint, n_pad)
    attrs["JOINTS_0"] = b.add(jt, "VEC4", _USHORT, _ARRAY)
    attrs["WEIGHTS_0"] = b.add(wt, "VEC4", _FLOAT, _ARRAY)
    targets = [{"POSITION": b.add(np.asarray(t, np.float32), "VEC3", _FLOAT, _ARRAY, True)}
               for t in anim.morph_targets]
    materials: list[dict] = []
    prims = []
    for mid, tris in material_groups(mesh):
        idx = mesh.indices[tris].reshape(-1).astype(np.uint32)
        prim = {"attributes": dict(attrs), "indices": b.add(idx, "SCALAR", _UINT, _ELEMENTS),
                "mode": 4}
        if targets:
            prim["targets"] = targets
        if mid < len(mesh.materials):
            prim["material"] = len(materials)
            materials.append(_material_json(mesh.materials[mid], scales))
        prims.append(prim)
    gl_mesh: dict = {"name": mesh.name, "primitives": prims}
    if targets:
        gl_mesh["weights"] = [0.0] * len(targets)
    bind = np.asarray(anim.bind_matrices, np.float64)
    if n_pad > J:
        bind = np.concatenate([bind, np.tile(np.eye(4), (n_pad - J, 1, 1))])
    ibm = np.linalg.inv(bind)
    ibm[:, 3, :] = (0.0, 0.0, 0.0, 1.0)  # exact affine bottom row
    ibm_acc = b.add(ibm.transpose(0, 2, 1).reshape(-1, 16).astype(np.float32), "MAT4", _FLOAT)
    # nodes: 0 mesh, 1 skeleton root, 2.. joints
    names = anim.joint_names or [f"joint{i}" for i in range(J)]
    names = list(names) + [f"pad{i}" for i in range(n_pad - J)]
    t0, q0, s0 = anim.translation[0], anim.rotation[0], (
        anim.scale[0] if anim.scale is not None else np.ones((J, 3)))
    nodes: list[dict] = [{"name": mesh.name, "mesh": 0, "skin": 0},
                         {"name": "skeleton", "children": list(range(2, 2 + n_pad))}]
    for i in range(n_pad):
        node: dict = {"name": names[i]}
        if i < J:
            node["translation"] = [float(x) for x in t0[i]]
            node["rotation"] = [float(x) for x in _unitq(q0[i:i + 1])[0]]
            if anim.scale is not None:
                node["scale"] = [float(x) for x in s0[i]]
        nodes.append(node)
    times = np.asarray(anim.times, np.float32)
    t_acc = b.add(times, "SCALAR", _FLOAT, None, True)
    samplers, channels = [], []

    def channel(node: int, path: str, values: np.ndarray, kind: str) -> None:
        samplers.append({"input": t_acc, "output": b.add(values.astype(np.float32), kind, _FLOAT),
                         "interpolation": "LINEAR"})
        channels.append({"sampler": len(samplers) - 1, "target": {"node": node, "path": path}})

    if len(times) > 1:
        for i in range(J):
            channel(2 + i, "translation", anim.translation[:, i], "VEC3")
            channel(2 + i, "rotation", _unitq(anim.rotation[:, i]), "VEC4")
            if anim.scale is not None:
                channel(2 + i, "scale", anim.scale[:, i], "VEC3")
        if targets:
            channel(0, "weights", np.asarray(anim.weights).reshape(-1), "SCALAR")
    blob = b.blob()
    doc: dict = {
        "asset": {"version": "2.0", "generator": "sylva gltf_animation"},
        "scene": 0,
        "scenes": [{"name": anim.name, "nodes": [0, 1]}],
        "nodes": nodes,
        "meshes": [gl_mesh],
        "skins": [{"inverseBindMatrices": ibm_acc, "skeleton": 1,
                   "joints": list(range(2, 2 + n_pad))}],
        "accessors": b.accessors,
        "bufferViews": b.views,
        "buffers": [{"byteLength": len(blob)}],
    }
    if channels:
        doc["animations"] = [{"name": anim.name, "samplers": samplers, "channels": channels}]
    if materials:
        doc["materials"] = materials
    return doc, blob


def _material_json(mat, scales: dict[str, float]) -> dict:
    a = float(mat.color[3])
    out: dict = {"name": mat.name, "pbrMetallicRoughness": {
        "baseColorFactor": scaled_base(mat, scales), "metallicFactor": float(mat.metallic),
        "roughnessFactor": float(mat.roughness)}}
    if mat.double_sided:
        out["doubleSided"] = True
    if mat.alpha_cutoff is not None:
        out["alphaMode"], out["alphaCutoff"] = "MASK", float(mat.alpha_cutoff)
    elif a < 1.0:
        out["alphaMode"] = "BLEND"
    return out


def _unit(n: np.ndarray) -> np.ndarray:
    n = np.asarray(n, np.float64)
    ln = np.linalg.norm(n, axis=1, keepdims=True)
    out = np.where(ln > 1e-12, n / np.maximum(ln, 1e-12), [0.0, 1.0, 0.0])
    return out.astype(np.float32)


def _unitq(q: np.ndarray) -> np.ndarray:
    q = np.asarray(q, np.float64)
    return q / np.linalg.norm(q, axis=-1, keepdims=True)


def write_animated_glb(anim: SkinnedAnimation, target: PathOrFile) -> None:
    """Write ``anim`` as a binary glTF (``.glb``) to a path or a binary file object."""
    doc, blob = animated_gltf_document(anim)
    js = json.dumps(doc, separators=(",", ":")).encode("utf-8")
    js += b" " * ((-len(js)) % 4)
    body = struct.pack("<II", len(js), 0x4E4F534A) + js
    body += struct.pack("<II", len(blob), 0x004E4942) + blob
    with open_target(target, binary=True) as fh:
        fh.write(struct.pack("<III", 0x46546C67, 2, 12 + len(body)))
        fh.write(body)
