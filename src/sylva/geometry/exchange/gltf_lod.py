"""glTF 2.0 with levels of detail: ``MSFT_lod`` and plain named nodes.

A :class:`~sylva.geometry.lod.LodChain` is written as one node per level, named
``NAME_LOD0``, ``NAME_LOD1``, … (the suffix Unity's, Unreal's and Godot's importers read
as a LOD group), each with one mesh (a primitive per material, ``_WIND`` data where the
level has it).  The root node ``NAME`` holds the levels:

``nodes="msft"`` (default)
    Only ``NAME_LOD0`` is a child of the root; it carries the ``MSFT_lod`` extension
    (``ids``: the nodes of the coarser levels, finest first) and, in its ``extras``,
    ``MSFT_screencoverage``: one screen-coverage value per level (the fraction of the
    screen height below which the viewer moves to the next level; below the last the
    plant is culled), as the extension's specification puts it.  ``MSFT_lod`` is in
    ``extensionsUsed``, not ``extensionsRequired``: a viewer without it shows LOD0.
``nodes="all"``
    Every level is a child of the root (and LOD0 still carries ``MSFT_lod``), for tools
    that build their LOD group from the node names (Unity, Godot); a plain viewer then
    draws every level at once.

Each level is written by :func:`~.gltf.gltf_document` and the documents are joined over
one buffer (materials that come out identical are shared).  An impostor level embeds its
atlas (PNG in the buffer): ``baseColorTexture`` (colour, alpha tested with ``alphaMode:
MASK``) and ``normalTexture``.  The output passes the Khronos validator without errors or
warnings.
"""

from __future__ import annotations

import json

import numpy as np

from ..lod import LodChain
from ..mesh import Mesh, Scene
from ._common import PathOrFile, check_up, open_target, safe_name
from .gltf import gltf_document, write_glb_container

__all__ = ["NODE_MODES", "lod_document", "png_bytes", "write_lod_glb", "write_lod_gltf"]

NODE_MODES = ("msft", "all")


def _shift_textures(obj, offset: int) -> None:
    """Add ``offset`` to every texture ``index`` in a material's JSON (in place)."""
    if isinstance(obj, dict):
        for key, value in obj.items():
            if key.endswith("Texture") and isinstance(value, dict) and "index" in value:
                value["index"] += offset
            else:
                _shift_textures(value, offset)
    elif isinstance(obj, list):
        for value in obj:
            _shift_textures(value, offset)


class _Merged:
    """Several glTF documents (one per level) joined over one buffer."""

    def __init__(self) -> None:
        self.doc: dict = {"nodes": [], "meshes": [], "accessors": [], "bufferViews": [],
                          "materials": [], "images": [], "textures": [], "samplers": []}
        self.chunks: list[bytes] = []
        self.size = 0
        self.materials: dict[str, int] = {}
        self.extensions: set[str] = set()

    def _append(self, data: bytes) -> int:
        pad = (-self.size) % 4
        if pad:
            self.chunks.append(b"\0" * pad)
            self.size += pad
        base = self.size
        self.chunks.append(data)
        self.size += len(data)
        return base

    def image(self, png: bytes, name: str) -> int:
        d = self.doc
        d["bufferViews"].append({"buffer": 0, "byteOffset": self._append(png),
                                 "byteLength": len(png)})
        d["images"].append({"name": name, "bufferView": len(d["bufferViews"]) - 1,
                            "mimeType": "image/png"})
        if not d["samplers"]:
            d["samplers"].append({"magFilter": 9729, "minFilter": 9987})
        d["textures"].append({"sampler": 0, "source": len(d["images"]) - 1})
        return len(d["textures"]) - 1

    def add(self, doc: dict, blob: bytes) -> tuple[int | None, dict[int, int]]:
        """Add one document's meshes; returns its mesh index and material index map."""
        d = self.doc
        base = self._append(blob) if blob else self.size
        views, accs = len(d["bufferViews"]), len(d["accessors"])
        samplers, images, textures = len(d["samplers"]), len(d["images"]), len(d["textures"])
        for v in doc.get("bufferViews", []):
            d["bufferViews"].append({**v, "byteOffset": v.get("byteOffset", 0) + base})
        for a in doc.get("accessors", []):
            d["accessors"].append({**a, "bufferView": a["bufferView"] + views})
        for s in doc.get("samplers", []):
            d["samplers"].append(s)
        for im in doc.get("images", []):
            d["images"].append({**im, "bufferView": im["bufferView"] + views}
                               if "bufferView" in im else im)
        for t in doc.get("textures", []):
            t = dict(t)
            t["source"] = t["source"] + images
            if "sampler" in t:
                t["sampler"] += samplers
            d["textures"].append(t)
        remap = {}
        for k, m in enumerate(doc.get("materials", [])):
            m = json.loads(json.dumps(m))
            _shift_textures(m, textures)
            key = json.dumps(m, sort_keys=True)  # shared only when identical
            if key not in self.materials:
                self.materials[key] = len(d["materials"])
                d["materials"].append(m)
            remap[k] = self.materials[key]
        self.extensions.update(doc.get("extensionsUsed", []))
        mesh_index = None
        for mesh in doc.get("meshes", []):
            prims = []
            for p in mesh["primitives"]:
                p = dict(p)
                p["attributes"] = {k: v + accs for k, v in p["attributes"].items()}
                p["indices"] += accs
                if "material" in p:
                    p["material"] = remap[p["material"]]
                prims.append(p)
            d["meshes"].append({**mesh, "primitives": prims})
            mesh_index = len(d["meshes"]) - 1
        return mesh_index, remap


def lod_document(chain: LodChain, *, up: str = "y", nodes: str = "msft") -> tuple[dict, bytes]:
    """The glTF document and buffer of a LOD chain (see the module docstring).

    Each level is written by :func:`~.gltf.gltf_document` (as one merged mesh) and the
    documents are joined; materials that come out identical are shared."""
    from ..lod import LodError

    if nodes not in NODE_MODES:
        raise LodError(f"nodes: expected one of {', '.join(NODE_MODES)}, got {nodes!r}")
    check_up(up)
    name = safe_name(chain.name)
    out = _Merged()
    level_nodes = []
    for i, lv in enumerate(chain.levels):
        meshes = [m for m in lv.scene.meshes if m.n_triangles]
        node: dict = {"name": f"{name}_LOD{i}"}
        if meshes:
            mesh = Mesh.merge(meshes, name=f"{name}_LOD{i}")
            doc, blob = gltf_document(Scene([mesh], name=mesh.name), up=up)
            k, remap = out.add(doc, blob)
            if k is not None:
                node["mesh"] = k
            for mat_name, img in lv.images.items():  # a baked impostor atlas
                for old, new in remap.items():
                    mat = out.doc["materials"][new]
                    if doc["materials"][old]["name"] != mat_name:
                        continue
                    if "color" in img:
                        t = out.image(png_bytes(img["color"], flip=True), f"{mat_name}_color")
                        mat["pbrMetallicRoughness"]["baseColorTexture"] = {"index": t}
                    if "normal" in img:
                        t = out.image(png_bytes(img["normal"], flip=True), f"{mat_name}_normal")
                        mat["normalTexture"] = {"index": t}
        out.doc["nodes"].append(node)
        level_nodes.append(len(out.doc["nodes"]) - 1)
    first = out.doc["nodes"][level_nodes[0]]
    if len(level_nodes) > 1:
        first["extensions"] = {"MSFT_lod": {"ids": level_nodes[1:]}}
        first["extras"] = {"MSFT_screencoverage": [float(c) for c in chain.coverage()]}
        out.extensions.add("MSFT_lod")
    out.doc["nodes"].append({"name": name,
                             "children": level_nodes if nodes == "all" else level_nodes[:1]})
    blob = b"".join(out.chunks + [b"\0" * ((-out.size) % 4)])
    doc = {"asset": {"version": "2.0", "generator": "sylva"}, "scene": 0,
           "scenes": [{"name": chain.name, "nodes": [len(out.doc["nodes"]) - 1]}]}
    if out.extensions:
        doc["extensionsUsed"] = sorted(out.extensions)
    doc.update({k: v for k, v in out.doc.items() if v})
    if blob:
        doc["buffers"] = [{"byteLength": len(blob)}]
    return doc, blob


def _glb(doc: dict, blob: bytes, target: PathOrFile) -> None:
    write_glb_container(doc, blob, target)


def write_lod_glb(chain: LodChain, target: PathOrFile, *, up: str = "y",
                  nodes: str = "msft") -> None:
    """Write a LOD chain as a binary glTF (``.glb``) file."""
    doc, blob = lod_document(chain, up=up, nodes=nodes)
    _glb(doc, blob, target)


def level_triangles(doc: dict) -> dict[str, int]:
    """Triangles per node name of a LOD document (for checks)."""
    out = {}
    acc = doc.get("accessors", [])
    for node in doc.get("nodes", []):
        if "mesh" in node:
            prims = doc["meshes"][node["mesh"]]["primitives"]
            out[node["name"]] = int(sum(acc[p["indices"]]["count"] for p in prims) // 3)
    return out


def png_bytes(image: np.ndarray, *, flip: bool = False) -> bytes:
    """PNG bytes of a ``uint8`` image (``flip``: bottom row first: glTF's ``v`` runs down,
    sylva's up)."""
    import io

    from PIL import Image

    a = np.ascontiguousarray(image[::-1] if flip else image)
    buf = io.BytesIO()
    Image.fromarray(a).save(buf, format="PNG")
    return buf.getvalue()


def write_lod_gltf(chain: LodChain, target: PathOrFile, *, up: str = "y",
                   nodes: str = "msft") -> None:
    """Write a LOD chain as JSON glTF (``.gltf``) with the buffer as a data URI."""
    import base64
    import json

    doc, blob = lod_document(chain, up=up, nodes=nodes)
    if "buffers" in doc:
        doc["buffers"][0]["uri"] = ("data:application/octet-stream;base64,"
                                    + base64.b64encode(blob).decode("ascii"))
    with open_target(target, binary=False) as fh:
        json.dump(doc, fh, indent=1)
