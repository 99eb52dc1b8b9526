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

An impostor level embeds its atlas (PNG in the buffer): ``baseColorTexture`` (colour,
alpha tested with ``alphaMode: MASK``) and ``normalTexture``.  The output passes the
Khronos validator without errors or warnings.
"""

from __future__ import annotations

import numpy as np

from ..lod import LodChain
from ..mesh import Scene
from ._common import PathOrFile, check_up, oriented_scene, safe_name, tint_scales
from .gltf import _Document, glb_bytes

__all__ = ["NODE_MODES", "lod_document", "png_bytes", "write_lod_glb", "write_lod_gltf"]

NODE_MODES = ("msft", "all")


def lod_document(chain: LodChain, *, up: str = "y", nodes: str = "msft") -> tuple[dict, bytes]:
    """The glTF document and buffer of a LOD chain (see the module docstring)."""
    from ..lod import LodError

    if nodes not in NODE_MODES:
        raise LodError(f"nodes: expected one of {', '.join(NODE_MODES)}, got {nodes!r}")
    check_up(up)
    scenes = [oriented_scene(lv.scene, up) for lv in chain.levels]
    d = _Document(tint_scales([m for s in scenes for m in s.meshes]))
    name = safe_name(chain.name)
    for lv in chain.levels:
        for mat_name, img in lv.images.items():
            extra: dict = {}
            if "color" in img:
                t = d.image(png_bytes(img["color"], flip=True), f"{mat_name}_color")
                extra["pbrMetallicRoughness"] = {"baseColorTexture": {"index": t}}
            if "normal" in img:
                t = d.image(png_bytes(img["normal"], flip=True), f"{mat_name}_normal")
                extra["normalTexture"] = {"index": t}
            d.material_extra[mat_name] = extra
    level_nodes = []
    for i, sc in enumerate(scenes):
        mesh = Scene(sc.meshes).merged() if sc.meshes else None
        node = {"name": f"{name}_LOD{i}"}
        if mesh is not None:
            mesh.name = f"{name}_LOD{i}"
            k = d.mesh(mesh)
            if k is not None:
                node["mesh"] = k
        d.nodes.append(node)
        level_nodes.append(len(d.nodes) - 1)
    first = d.nodes[level_nodes[0]]
    if len(level_nodes) > 1:
        first["extensions"] = {"MSFT_lod": {"ids": level_nodes[1:]}}
        first["extras"] = {"MSFT_screencoverage": [float(c) for c in chain.coverage()]}
    children = level_nodes if nodes == "all" else level_nodes[:1]
    d.nodes.append({"name": name, "children": children})
    root = len(d.nodes) - 1
    ext = ["MSFT_lod"] if len(level_nodes) > 1 else []
    return d.finish(chain.name, [root], ext)


def write_lod_glb(chain: LodChain, target: PathOrFile, *, up: str = "y",
                  nodes: str = "msft") -> None:
    """Write a LOD chain as a binary glTF (``.glb``) file."""
    doc, blob = lod_document(chain, up=up, nodes=nodes)
    glb_bytes(doc, blob, target)


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

    from ._common import open_target

    doc, blob = lod_document(chain, up=up, nodes=nodes)
    if "buffers" in doc:
        doc["buffers"][0]["uri"] = ("data:application/octet-stream;base64,"
                                    + base64.b64encode(blob).decode("ascii"))
    with open_target(target, binary=False) as fh:
        json.dump(doc, fh, indent=1)
