"""glTF 2.0: binary ``.glb`` and ``.gltf`` (JSON with the buffer embedded as a data URI).

One glTF mesh per scene mesh, one primitive per material it uses (the primitives share the
vertex accessors: ``POSITION``, ``NORMAL``, ``TEXCOORD_0`` and ``COLOR_0`` when present),
PBR metallic-roughness materials, one node per mesh.  glTF is right-handed with +Y up, as
sylva is, so coordinates are written unchanged (``up="z"`` rotates them for tools that
want Z up, against the glTF convention).  Vertex colours are a tint of the material colour
and may pass one; ``COLOR_0`` must not, so tints are divided by a factor per material that
``baseColorFactor`` carries instead (:func:`~._common.tint_scales`).  Double-sided
materials (leaves, polygons: one face each) get ``doubleSided``.  Materials with baked images
(:mod:`._textures`) reference them as PBR textures, with a white ``baseColorFactor`` (the
image carries the colour) and ``COLOR_0`` the tint itself, clamped to [0, 1].  The output passes the
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
import os
import struct

import numpy as np

from ..._atomic import AtomicGroup
from ._common import (
    PathOrFile,
    as_scene,
    gltf_color0,
    material_groups,
    open_target,
    oriented_scene,
    scaled_base,
    target_path,
    tint_scales,
)
from ._textures import GltfTextures, needs_tangents, stem_of, tangents

__all__ = ["gltf_document", "write_glb", "write_glb_container", "write_gltf"]

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

    def view(self, data: bytes, target: int | None) -> int:
        pad = (-self.size) % 4
        if pad:
            self.chunks.append(b"\0" * pad)
            self.size += pad
        view = {"buffer": 0, "byteOffset": self.size, "byteLength": len(data)}
        if target is not None:  # image views have none
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
    if getattr(mat, "billboard", False):  # glTF has no billboard: say it (seed 002)
        out["extras"] = {"billboard": True}
    if getattr(mat, "texture", None) in ("bark", "leaf", "grass"):
        # the procedural texture, for viewers that draw it (the studio runs its graph's GLSL)
        out.setdefault("extras", {})["sylva_texture"] = mat.texture
    return out


def gltf_document(scene, *, up: str = "y", images: list | None = None,
                  stem: str = "scene") -> tuple[dict, bytes]:
    """The glTF JSON document (without ``buffers[0].uri``) and its binary buffer.

    Baked material images (:mod:`._textures`) are embedded in the buffer, or, when
    ``images`` is a list, referenced as files ``<stem>.<material>.<slot>.png`` beside the
    document and appended to it as ``(name, PNG bytes)``."""
    scene = oriented_scene(as_scene(scene), up)
    tex = GltfTextures(stem, embed=images is None)
    scales = tex.scales(scene.meshes, tint_scales(scene.meshes))
    b = _Builder()
    materials: list[dict] = []
    mat_index: dict[str, int] = {}
    meshes: list[dict] = []
    nodes: list[dict] = []
    for mesh in scene.meshes:
        if mesh.n_triangles == 0:
            continue
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
        if needs_tangents(mesh):  # normal maps: the tangent frame, not left to the client
            attrs["TANGENT"] = b.accessor(sel(tangents(mesh)), "VEC4", _FLOAT, _ARRAY)
        if mesh.colors is not None:
            attrs["COLOR_0"] = b.accessor(sel(gltf_color0(mesh, scales)), "VEC4", _FLOAT, _ARRAY)
        for key, arr in sorted((mesh.attributes or {}).items()):  # e.g. WIND (geometry.lod)
            name = "TANGENT" if key == "TANGENT" else "_" + key.upper().lstrip("_")
            kind = {1: "SCALAR", 2: "VEC2", 3: "VEC3", 4: "VEC4"}.get(arr.shape[1])
            if name not in attrs and kind and (name != "TANGENT" or kind == "VEC4"):
                attrs[name] = b.accessor(sel(arr), kind, _FLOAT, _ARRAY)
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
                if mat.name not in mat_index:
                    mat_index[mat.name] = len(materials)
                    materials.append(tex.material(mat, _material_json(mat, scales)))
                prim["material"] = mat_index[mat.name]
            prims.append(prim)
        meshes.append({"name": mesh.name, "primitives": prims})
        nodes.append({"name": mesh.name, "mesh": len(meshes) - 1})
    doc: dict = {
        "asset": {"version": "2.0", "generator": "sylva"},
        "scene": 0,
        "scenes": [{"name": scene.name}],
    }
    tex.finish(doc, b)
    if images is not None:
        images.extend(tex.files)
    blob = b.blob()
    if nodes:  # an empty scene has no node list at all: empty arrays are invalid glTF
        doc["scenes"][0]["nodes"] = list(range(len(nodes)))
        doc["nodes"] = nodes
    if meshes:
        doc["meshes"] = meshes
        doc["accessors"] = b.accessors
        doc["bufferViews"] = b.views
        doc["buffers"] = [{"byteLength": len(blob)}]
    if materials:
        doc["materials"] = materials
    return doc, blob


def write_glb(scene, target: PathOrFile, *, up: str = "y") -> None:
    """Write binary glTF (``.glb``) to a path or a binary file object (``up``: the up axis,
    ``"y"`` as glTF specifies, or ``"z"``)."""
    doc, blob = gltf_document(scene, up=up, stem=stem_of(target_path(target)))
    write_glb_container(doc, blob, target)


def write_glb_container(doc: dict, blob: bytes, target: PathOrFile) -> None:
    """The GLB container of a glTF document and its binary buffer, to a path or a binary
    file object."""
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


def write_gltf(scene, target: PathOrFile, *, up: str = "y") -> None:
    """Write JSON glTF (``.gltf``) with the buffer embedded as a base64 data URI.

    Baked material images are PNG files beside a path target (``<stem>.<material>.<slot>
    .png``, written in one :class:`~sylva._atomic.AtomicGroup` with the document, which
    appears last), and embedded in the buffer for a file object."""
    files: list | None = [] if isinstance(target, (str, os.PathLike)) else None
    doc, blob = gltf_document(scene, up=up, images=files,
                              stem=stem_of(target_path(target)))  # fmt: skip
    if "buffers" in doc:
        doc["buffers"][0]["uri"] = "data:application/octet-stream;base64," + base64.b64encode(
            blob
        ).decode("ascii")
    if files:
        folder = os.path.dirname(os.fspath(target))
        with AtomicGroup() as group:
            for name, data in files:
                with group.open(os.path.join(folder, name), "wb") as fh:
                    fh.write(data)
            with group.open(target, "w", main=True) as fh:
                json.dump(doc, fh, indent=1)
        return
    with open_target(target, binary=False) as fh:
        json.dump(doc, fh, indent=1)
