"""Binary glTF 2.0 with ``EXT_mesh_gpu_instancing``: static meshes plus instanced ones.

A world has one large terrain mesh and thousands of copies of a few plant models.  Each
model is written once, as a glTF mesh on a node that carries the
``EXT_mesh_gpu_instancing`` extension with per-instance ``TRANSLATION``, ``ROTATION``
(unit quaternions x, y, z, w) and ``SCALE`` accessors.  Materials are PBR
metallic-roughness; a material whose ``texture`` names an image file (PNG or JPEG) gets it
embedded as its base-colour texture with a repeating sampler (block-unit UVs repeat a tile
once per block), ``alpha_cutoff`` becomes ``alphaMode: MASK`` and a base alpha below one
``BLEND``.  The output passes the Khronos ``gltf-validator``.

Examples
--------
>>> import io, numpy as np
>>> from sylva.geometry.mesh import Mesh
>>> tri = Mesh(np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]]), np.array([[0, 1, 2]]))
>>> inst = InstancedMesh(tri, translation=np.array([[0, 0, 0], [2, 0, 0]]))
>>> buf = io.BytesIO(); write_glb_instanced([tri], [inst], buf)
>>> buf.getvalue()[:4], len(inst)
(b'glTF', 2)
"""

from __future__ import annotations

import json
import struct
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..mesh import Material, Mesh, Scene
from ._common import PathOrFile, gltf_color0, open_target, scaled_base, tint_scales
from .gltf import _Builder

__all__ = ["EXTENSION", "InstancedMesh", "write_glb_instanced"]

EXTENSION = "EXT_mesh_gpu_instancing"

_FLOAT, _UINT = 5126, 5125
_ARRAY, _ELEMENTS = 34962, 34963
_REPEAT, _NEAREST, _NEAREST_MIPMAP_LINEAR = 10497, 9728, 9986


@dataclass
class InstancedMesh:
    """A mesh drawn many times.

    Attributes
    ----------
    mesh : Mesh
    translation : float[k, 3]
    rotation : float[k, 4] or None
        Unit quaternions ``(x, y, z, w)``; identity when absent.
    scale : float[k, 3] or None
        Per-axis scale; one when absent.
    name : str or None
    """

    mesh: Mesh
    translation: np.ndarray
    rotation: np.ndarray | None = None
    scale: np.ndarray | None = None
    name: str | None = None

    def __post_init__(self) -> None:
        self.translation = np.ascontiguousarray(self.translation, np.float32).reshape(-1, 3)
        k = self.translation.shape[0]
        if self.rotation is not None:
            self.rotation = np.ascontiguousarray(self.rotation, np.float32).reshape(k, 4)
            norm = np.linalg.norm(self.rotation, axis=1, keepdims=True)
            if np.any(norm == 0):
                raise ValueError("instance rotations must be unit quaternions, got a zero one")
            self.rotation = (self.rotation / norm).astype(np.float32)
        if self.scale is not None:
            self.scale = np.ascontiguousarray(self.scale, np.float32)
            if self.scale.ndim == 1:
                self.scale = np.repeat(self.scale[:, None], 3, axis=1)
            self.scale = self.scale.reshape(k, 3)

    def __len__(self) -> int:
        return int(self.translation.shape[0])


class _Doc(_Builder):
    """gltf.py's buffer builder plus the instanced document's materials, textures, meshes
    and nodes."""

    def __init__(self, scales: dict[str, float] | None = None) -> None:
        super().__init__()
        self.scales = scales or {}
        self.materials: list[dict] = []
        self.mat_index: dict[str, int] = {}
        self.images: list[dict] = []
        self.textures: list[dict] = []
        self.image_index: dict[str, int] = {}
        self.meshes: list[dict] = []
        self.nodes: list[dict] = []

    def texture(self, path: Path) -> int | None:
        key = str(path.resolve())
        if key not in self.image_index:
            suffix = path.suffix.lower()
            mime = {".png": "image/png", ".jpg": "image/jpeg", ".jpeg": "image/jpeg"}.get(suffix)
            if mime is None or not path.is_file():
                return None
            view = self.view(path.read_bytes(), None)
            self.images.append({"bufferView": view, "mimeType": mime, "name": path.stem})
            self.textures.append({"sampler": 0, "source": len(self.images) - 1})
            self.image_index[key] = len(self.textures) - 1
        return self.image_index[key]

    def material(self, mat: Material) -> int:
        if mat.name in self.mat_index:
            return self.mat_index[mat.name]
        a = float(mat.color[3])
        pbr: dict = {"baseColorFactor": scaled_base(mat, self.scales),
                     "metallicFactor": float(mat.metallic),
                     "roughnessFactor": float(mat.roughness)}  # fmt: skip
        if mat.texture:
            t = self.texture(Path(mat.texture))
            if t is not None:
                pbr["baseColorTexture"] = {"index": t}
        out: dict = {"name": mat.name, "pbrMetallicRoughness": pbr}
        if mat.double_sided:
            out["doubleSided"] = True
        if mat.alpha_cutoff is not None:
            out["alphaMode"] = "MASK"
            out["alphaCutoff"] = float(mat.alpha_cutoff)
        elif a < 1.0:
            out["alphaMode"] = "BLEND"
        self.materials.append(out)
        self.mat_index[mat.name] = len(self.materials) - 1
        return self.mat_index[mat.name]

    def mesh(self, mesh: Mesh, name: str) -> int | None:
        if mesh.n_triangles == 0:
            return None
        attrs = {
            "POSITION": self.accessor(mesh.vertices.astype(np.float32), "VEC3", _FLOAT, _ARRAY,
                                      minmax=True),
            "NORMAL": self.accessor(mesh.normals.astype(np.float32), "VEC3", _FLOAT, _ARRAY),
        }  # fmt: skip
        if mesh.uvs is not None:
            attrs["TEXCOORD_0"] = self.accessor(mesh.uvs.astype(np.float32), "VEC2", _FLOAT,
                                                _ARRAY)  # fmt: skip
        if mesh.colors is not None:
            attrs["COLOR_0"] = self.accessor(gltf_color0(mesh, self.scales), "VEC4", _FLOAT,
                                             _ARRAY)  # fmt: skip
        tm = mesh.triangle_materials()
        prims = []
        for mid in np.unique(tm):
            idx = mesh.indices[tm == mid].astype(np.uint32).ravel()
            used = int(mid) if 0 <= mid < len(mesh.materials) else 0
            prim = {"attributes": attrs,
                    "indices": self.accessor(idx, "SCALAR", _UINT, _ELEMENTS),
                    "material": self.material(mesh.materials[used])}  # fmt: skip
            if mesh.uvs is None:
                # a textured material needs TEXCOORD_0: drop the texture instead
                self.materials[prim["material"]]["pbrMetallicRoughness"].pop("baseColorTexture",
                                                                              None)
            prims.append(prim)
        self.meshes.append({"name": name, "primitives": prims})
        return len(self.meshes) - 1

    def glb(self, scene_name: str, extra_used: bool) -> bytes:
        doc: dict = {
            "asset": {"version": "2.0", "generator": "sylva"},
            "scene": 0,
            "scenes": [{"name": scene_name, "nodes": list(range(len(self.nodes)))}],
            "nodes": self.nodes,
            "meshes": self.meshes,
            "materials": self.materials,
            "accessors": self.accessors,
            "bufferViews": self.views,
        }
        if self.images:
            doc["images"] = self.images
            doc["textures"] = self.textures
            doc["samplers"] = [{"magFilter": _NEAREST, "minFilter": _NEAREST_MIPMAP_LINEAR,
                                "wrapS": _REPEAT, "wrapT": _REPEAT}]  # fmt: skip
        if extra_used:
            doc["extensionsUsed"] = [EXTENSION]
        if not self.nodes:  # nothing to draw: empty arrays are invalid glTF, leave them out
            del doc["nodes"], doc["scenes"][0]["nodes"]
        if not self.meshes:
            del doc["meshes"]
        if not self.materials:
            del doc["materials"]
        if not self.accessors:
            del doc["accessors"], doc["bufferViews"]
        blob = self.blob()
        if blob:
            doc["buffers"] = [{"byteLength": len(blob)}]
        js = json.dumps(doc, separators=(",", ":")).encode("utf-8")
        js += b" " * ((-len(js)) % 4)
        total = 12 + 8 + len(js) + (8 + len(blob) if blob else 0)
        out = struct.pack("<4sII", b"glTF", 2, total) + struct.pack("<I4s", len(js), b"JSON") + js
        if blob:
            out += struct.pack("<I4s", len(blob), b"BIN\0") + blob
        return out


def write_glb_instanced(
    static: Mesh | Scene | Sequence[Mesh],
    instanced: Sequence[InstancedMesh],
    target: PathOrFile,
    *,
    name: str = "scene",
) -> None:
    """Write static meshes and instanced meshes as one ``.glb``.

    Parameters
    ----------
    static : Mesh, Scene or sequence of Mesh
        Drawn once each (one node per mesh).
    instanced : sequence of InstancedMesh
        Each becomes one mesh and one node with ``EXT_mesh_gpu_instancing``; instanced
        meshes with no instances are skipped.
    target : path or binary file object
    name : str
        The glTF scene's name.
    """
    if isinstance(static, Mesh):
        static = [static]
    elif isinstance(static, Scene):
        static = list(static.meshes)
    doc = _Doc(tint_scales([*static, *(inst.mesh for inst in instanced if len(inst))]))
    for i, m in enumerate(static):
        mi = doc.mesh(m, m.name or f"mesh_{i}")
        if mi is not None:
            doc.nodes.append({"name": m.name or f"mesh_{i}", "mesh": mi})
    used = False
    for i, inst in enumerate(instanced):
        if len(inst) == 0:
            continue
        label = inst.name or inst.mesh.name or f"instanced_{i}"
        mi = doc.mesh(inst.mesh, label)
        if mi is None:
            continue
        attrs = {"TRANSLATION": doc.accessor(inst.translation, "VEC3", _FLOAT, None)}
        if inst.rotation is not None:
            attrs["ROTATION"] = doc.accessor(inst.rotation, "VEC4", _FLOAT, None)
        if inst.scale is not None:
            attrs["SCALE"] = doc.accessor(inst.scale, "VEC3", _FLOAT, None)
        doc.nodes.append({"name": label, "mesh": mi,
                          "extensions": {EXTENSION: {"attributes": attrs}}})  # fmt: skip
        used = True
    data = doc.glb(name, used)
    with open_target(target, binary=True) as fh:
        fh.write(data)
