"""glTF 2.0: binary ``.glb`` and ``.gltf`` (JSON with the buffer embedded as a data URI).

One glTF mesh per scene mesh, one primitive per material it uses (the primitives share the
vertex accessors: ``POSITION``, ``NORMAL``, ``TEXCOORD_0`` and ``COLOR_0`` when present),
PBR metallic-roughness materials, one node per mesh.  glTF is right-handed with +Y up, as
sylva is, so coordinates are written unchanged (``up="z"`` rotates them for tools that
want Z up, against the glTF convention).  Vertex colours are a tint of the material colour
and may pass one; ``COLOR_0`` must not, so tints are divided by a factor per material that
``baseColorFactor`` carries instead (:func:`~._common.tint_scales`).  Double-sided
materials (leaves, polygons: one face each) get ``doubleSided``.  The output passes the
Khronos ``gltf-validator`` without errors or warnings (the tests run it).

Examples
--------
>>> import io, numpy as np
>>> from sylva.geometry.mesh import Mesh
>>> m = Mesh(np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]]), np.array([[0, 1, 2]]))
>>> buf = io.BytesIO(); write_glb(m, buf)
>>> buf.getvalue()[:4]
b'glTF'
"""

from __future__ import annotations

import base64
import json
import struct

import numpy as np

from ._common import (
    PathOrFile,
    as_scene,
    gltf_color0,
    material_groups,
    open_target,
    oriented_scene,
    scaled_base,
    tint_scales,
)

__all__ = ["gltf_document", "write_glb", "write_gltf"]

_FLOAT = 5126
_UINT = 5125
_USHORT = 5123
_ARRAY = 34962
_ELEMENTS = 34963


class _Builder:
    def __init__(self) -> None:
        self.chunks: list[bytes] = []
        self.size = 0
        self.views: list[dict] = []
        self.accessors: list[dict] = []

    def view(self, data: bytes, target: int) -> int:
        pad = (-self.size) % 4
        if pad:
            self.chunks.append(b"\0" * pad)
            self.size += pad
        view = {"buffer": 0, "byteOffset": self.size, "byteLength": len(data)}
        if target is not None:
            view["target"] = target
        self.views.append(view)
        self.chunks.append(data)
        self.size += len(data)
        return len(self.views) - 1

    def accessor(self, arr: np.ndarray, kind: str, component: int, target: int, minmax=False):
        acc = {
            # a view, not a copy: the one join in blob() copies (and lets other threads run)
            "bufferView": self.view(memoryview(np.ascontiguousarray(arr)).cast("B"), target),
            "componentType": component,
            "count": int(arr.shape[0]),
            "type": kind,
        }
        if minmax:
            acc["min"] = [float(x) for x in arr.min(axis=0)]
            acc["max"] = [float(x) for x in arr.max(axis=0)]
        self.accessors.append(acc)
        return len(self.accessors) - 1

    def blob(self) -> bytes:
        pad = (-self.size) % 4
        return b"".join(self.chunks + [b"\0" * pad] if pad else self.chunks)


def _material_json(mat, scales: dict[str, float]) -> dict:
    a = float(mat.color[3])
    out: dict = {
        "name": mat.name,
        "pbrMetallicRoughness": {
            "baseColorFactor": scaled_base(mat, scales),
            "metallicFactor": float(mat.metallic),
            "roughnessFactor": float(mat.roughness),
        },
    }
    if mat.double_sided:
        out["doubleSided"] = True
    if mat.alpha_cutoff is not None:
        out["alphaMode"] = "MASK"
        out["alphaCutoff"] = float(mat.alpha_cutoff)
    elif a < 1.0:
        out["alphaMode"] = "BLEND"
    if getattr(mat, "billboard", False):
        # glTF has no billboard flag: say it in extras (see sylva.geometry.lod)
        out["extras"] = {"billboard": True}
    return out


class _Document:
    """A glTF document being built: meshes, nodes and materials over one buffer.

    :func:`gltf_document` writes a scene with it; the LOD writer
    (:mod:`.gltf_lod`) adds several scenes' meshes and its own nodes."""

    def __init__(self, scales: dict[str, float]) -> None:
        self.b = _Builder()
        self.scales = scales
        self.materials: list[dict] = []
        self.mat_index: dict[str, int] = {}
        self.meshes: list[dict] = []
        self.nodes: list[dict] = []
        self.images: list[dict] = []
        self.textures: list[dict] = []
        #: material name -> extra glTF material members (textures of baked images)
        self.material_extra: dict[str, dict] = {}

    def material(self, mat) -> int:
        if mat.name not in self.mat_index:
            self.mat_index[mat.name] = len(self.materials)
            js = _material_json(mat, self.scales)
            extra = self.material_extra.get(mat.name)
            if extra:
                pbr = extra.pop("pbrMetallicRoughness", {})
                js["pbrMetallicRoughness"].update(pbr)
                js.update(extra)
            self.materials.append(js)
        return self.mat_index[mat.name]

    def image(self, png: bytes, name: str) -> int:
        """A texture index for PNG bytes (stored in the buffer, sampled with mipmaps)."""
        view = self.b.view(png, None)
        self.images.append({"name": name, "bufferView": view, "mimeType": "image/png"})
        self.textures.append({"sampler": 0, "source": len(self.images) - 1})
        return len(self.textures) - 1

    def mesh(self, mesh) -> int | None:
        """The glTF mesh index of ``mesh`` (None when it has no triangles)."""
        b, scales = self.b, self.scales
        if mesh.n_triangles == 0:
            return None
        # the sorted vertices in use, by a mask: np.unique sorts or hashes every index
        mask = np.zeros(mesh.n_vertices, dtype=bool)
        mask[mesh.indices.reshape(-1)] = True
        used = np.flatnonzero(mask)
        # write only the vertices the triangles use (unused ones are validator warnings)
        remap = None
        if used.size != mesh.n_vertices:
            remap = np.full(mesh.n_vertices, 0, np.uint32)
            remap[used] = np.arange(used.size, dtype=np.uint32)

        def sel(a, used=used, remap=remap):
            return a[used] if remap is not None else a

        attrs = {
            "POSITION": b.accessor(sel(mesh.vertices), "VEC3", _FLOAT, _ARRAY, minmax=True),
            "NORMAL": b.accessor(sel(mesh.normals), "VEC3", _FLOAT, _ARRAY),
        }
        if mesh.uvs is not None:
            attrs["TEXCOORD_0"] = b.accessor(sel(mesh.uvs), "VEC2", _FLOAT, _ARRAY)
        if mesh.colors is not None:
            attrs["COLOR_0"] = b.accessor(sel(gltf_color0(mesh, scales)), "VEC4", _FLOAT, _ARRAY)
        for key, arr in sorted((mesh.attributes or {}).items()):
            kind = _KINDS.get(arr.shape[1])
            if key == "TANGENT" and arr.shape[1] == 4:  # glTF's own semantic
                attrs["TANGENT"] = b.accessor(sel(arr), "VEC4", _FLOAT, _ARRAY)
            elif kind is not None:  # custom attributes: an underscore, upper case
                attrs["_" + key.upper().lstrip("_")] = b.accessor(sel(arr), kind, _FLOAT, _ARRAY)
        nverts = int(used.size)
        prims = []
        for mid, tris in material_groups(mesh):
            idx = mesh.indices[tris]
            if remap is not None:
                idx = remap[idx]
            if nverts < 65535:
                ia = b.accessor(idx.reshape(-1).astype(np.uint16), "SCALAR", _USHORT, _ELEMENTS)
            else:
                ia = b.accessor(idx.reshape(-1).astype(np.uint32), "SCALAR", _UINT, _ELEMENTS)
            mat = mesh.materials[mid] if mid < len(mesh.materials) else None
            prim = {"attributes": dict(attrs), "indices": ia, "mode": 4}
            if mat is not None:
                prim["material"] = self.material(mat)
            prims.append(prim)
        self.meshes.append({"name": mesh.name, "primitives": prims})
        return len(self.meshes) - 1

    def finish(self, name: str, roots: list[int], extensions: list[str] = ()) -> tuple[dict, bytes]:
        blob = self.b.blob()
        doc: dict = {
            "asset": {"version": "2.0", "generator": "sylva"},
            "scene": 0,
            "scenes": [{"name": name}],
        }
        if extensions:
            doc["extensionsUsed"] = list(extensions)
        if self.nodes:  # an empty scene has no node list at all: empty arrays are invalid
            doc["scenes"][0]["nodes"] = list(roots)
            doc["nodes"] = self.nodes
        if self.meshes:
            doc["meshes"] = self.meshes
            doc["accessors"] = self.b.accessors
            doc["bufferViews"] = self.b.views
            doc["buffers"] = [{"byteLength": len(blob)}]
        if self.materials:
            doc["materials"] = self.materials
        if self.textures:
            doc["images"] = self.images
            doc["textures"] = self.textures
            doc["samplers"] = [{"magFilter": 9729, "minFilter": 9987}]
        return doc, blob


_KINDS = {1: "SCALAR", 2: "VEC2", 3: "VEC3", 4: "VEC4"}


def gltf_document(scene, *, up: str = "y") -> tuple[dict, bytes]:
    """The glTF JSON document (without ``buffers[0].uri``) and its binary buffer."""
    scene = oriented_scene(as_scene(scene), up)
    d = _Document(tint_scales(scene.meshes))
    for mesh in scene.meshes:
        k = d.mesh(mesh)
        if k is not None:
            d.nodes.append({"name": mesh.name, "mesh": k})
    return d.finish(scene.name, list(range(len(d.nodes))))


def glb_bytes(doc: dict, blob: bytes, target: PathOrFile) -> None:
    """Write a glTF document and its buffer as a GLB to ``target``."""
    js = json.dumps(doc, separators=(",", ":")).encode("utf-8")
    js += b" " * ((-len(js)) % 4)
    total = 12 + 8 + len(js) + (8 + len(blob) if blob else 0)
    # piece by piece: the buffer (hundreds of MB for a large plant) is not copied again
    with open_target(target, binary=True) as fh:
        fh.write(struct.pack("<III", 0x46546C67, 2, total))
        fh.write(struct.pack("<II", len(js), 0x4E4F534A))
        fh.write(js)
        if blob:
            fh.write(struct.pack("<II", len(blob), 0x004E4942))
            fh.write(blob)


def write_glb(scene, target: PathOrFile, *, up: str = "y") -> None:
    """Write binary glTF (``.glb``) to a path or a binary file object (``up``: the up axis,
    ``"y"`` as glTF specifies, or ``"z"``)."""
    doc, blob = gltf_document(scene, up=up)
    glb_bytes(doc, blob, target)


def write_gltf(scene, target: PathOrFile, *, up: str = "y") -> None:
    """Write JSON glTF (``.gltf``) with the buffer embedded as a base64 data URI."""
    doc, blob = gltf_document(scene, up=up)
    if "buffers" in doc:
        doc["buffers"][0]["uri"] = "data:application/octet-stream;base64," + base64.b64encode(
            blob
        ).decode("ascii")
    with open_target(target, binary=False) as fh:
        json.dump(doc, fh, indent=1)
