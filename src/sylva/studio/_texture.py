"""The Studio's Texture mode: a texture graph's TOML, its image and its nodes (issue 22).

A client picks a shipped preset (each one is a graph: :func:`sylva.texture.graph.from_recipe`)
or edits a graph's TOML; the server reads the text with the graph loader (a bad text is a
:class:`~sylva.texture.graph.GraphError` with its line and column, answered as such), renders
it with the CPU graph kernel (:meth:`~sylva.texture.graph.Graph.image`, the function
``sylva texture --graph`` calls) as a PNG, and lists its nodes for the tree beside the image.
Saving writes the TOML and the PNG at the graph's own size together, atomically
(:class:`sylva._atomic.AtomicGroup`), inside the workspace.
"""

from __future__ import annotations

import io
import time
from functools import lru_cache

from ..errors import SylvaError

__all__ = ["GRAPH_SUFFIXES", "PREVIEW_SIDE", "node_list", "preset_list", "preset_text",
           "render", "save"]

GRAPH_SUFFIXES = (".toml",)
PREVIEW_SIDE = 256  # the longer side of the image while editing
MAX_SIDE = 2048  # the longest side a graph may ask for (its own size, saved)


@lru_cache(maxsize=1)
def preset_list() -> list[dict]:
    """The shipped presets: name, kind and description."""
    from ..texture.presets import PRESETS

    return [{"name": name, "kind": r["kind"], "description": r.get("description", "")}
            for name, r in PRESETS.items()]


def preset_text(name: str) -> str:
    """The TOML of preset ``name`` as a graph."""
    from ..texture.graph import from_recipe
    from ..texture.presets import PRESETS

    if name not in PRESETS:
        raise SylvaError(f"no texture preset named {name!r}")
    return from_recipe(name).dumps()


def _graph(text: str, filename: str | None):
    from ..texture import graph as tg

    return tg.loads(text, filename=filename or "<graph>")


def node_list(g) -> list[dict]:
    """The graph's nodes, inputs first and the output last: name, type, category, what
    feeds each input (a node name or a number) and the parameters."""
    from ..texture.graph import Node
    from ..texture.graph._nodes import walk

    d = g.to_dict()
    order = walk(g.output)
    names = list(d["nodes"])
    out = []
    for n, name in zip(order, names, strict=True):
        body = d["nodes"][name]
        inputs = {k: body[k] for k in n.inputs}
        params = {k: v for k, v in body.items() if k != "type" and k not in inputs}
        out.append({"name": name, "type": n.type, "category": n.spec.category,
                    "output": n.spec.output, "inputs": inputs,
                    "links": [k for k, v in n.inputs.items() if isinstance(v, Node)],
                    "params": params})
    return out


def _size_of(g, *, full: bool = True) -> tuple[int, int]:
    w, h = g.size or (512, 512)
    if full and max(w, h) > MAX_SIDE:
        raise SylvaError(f"the graph's size {w}x{h} is larger than the Studio renders "
                         f"({MAX_SIDE} pixels a side)")
    return int(w), int(h)


def _png(image) -> bytes:
    from PIL import Image

    buf = io.BytesIO()
    Image.fromarray(image).save(buf, format="PNG")
    return buf.getvalue()


def render(text: str, *, side: int | None = PREVIEW_SIDE, filename: str | None = None) -> dict:
    """Read and render a graph's TOML.

    Parameters
    ----------
    text : str
    side : int or None
        The longer side of the image (the graph's aspect kept); ``None``: the graph's size.

    Returns
    -------
    dict
        ``png`` (bytes), ``width``, ``height``, ``size`` (the graph's own), ``nodes``
        (:func:`node_list`), ``output`` (its type: scalar or colour), ``ms``.
    """
    t0 = time.perf_counter()
    g = _graph(text, filename)
    w, h = _size_of(g, full=side is None)
    if side is not None and max(w, h) > side:
        k = side / max(w, h)
        w, h = max(1, round(w * k)), max(1, round(h * k))
    image = g.image((h, w))
    png = _png(image)
    return {"png": png, "width": w, "height": h, "size": list(_size_of(g, full=False)),
            "nodes": node_list(g), "output": g.output.spec.output,
            "ms": (time.perf_counter() - t0) * 1e3}


def save(workspace, rel: object, text: str, *, overwrite: bool) -> dict:
    """Save ``text`` at ``rel`` (a ``.toml`` workspace path) and its image at the graph's
    size beside it (the same name, ``.png``), both or neither."""
    from .._atomic import AtomicGroup, describe_os_error
    from ._workspace import WorkspaceError, _save_status

    path = workspace.resolve(rel, suffixes=GRAPH_SUFFIXES)
    png_path = path.with_suffix(".png")
    g = _graph(text, str(rel))  # a text that does not read is not saved
    png = _png(g.image(_size_of(g)[::-1]))
    try:
        for p in (path, png_path):
            if p.exists() and not overwrite:
                raise WorkspaceError(f"{workspace.relative(p)} exists already", 409)
            if p.exists() and not p.is_file():
                raise WorkspaceError(f"{workspace.relative(p)} is not a file", 409)
        path.parent.mkdir(parents=True, exist_ok=True)
        if not path.parent.resolve().is_relative_to(workspace.root):
            raise WorkspaceError(f"{rel!r} leaves the workspace", 403)
        with AtomicGroup() as group:
            with group.open(png_path, "wb") as fh:
                fh.write(png)
            with group.open(path, "w", main=True, newline="") as fh:
                fh.write(text)
    except OSError as exc:
        raise WorkspaceError(describe_os_error(exc, rel), _save_status(exc)) from None
    return {"path": workspace.relative(path), "image": workspace.relative(png_path),
            "saved": len(text), "png_bytes": len(png)}
