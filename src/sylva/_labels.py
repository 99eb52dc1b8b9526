"""Training labels of a rendered plant: a per-organ instance mask, depth and COCO annotations.

Every leaf, every polygon (flowers, petals) and every branch — an axis of segments, a new
one at each bracket — gets its own id.  The mask is an unlit render of the plant in which
each organ's vertices carry its id as a colour (ids on a grid of 16 levels per channel, so
that the sRGB output rounds back to the id), drawn without antialiasing, textures,
shadows or ground, from the same camera as the image.  :func:`coco` turns a mask into a
COCO detection/segmentation document (run-length encoded masks, bounding boxes, areas).
:func:`label_images` also returns the depth of the same render: the distance from the eye
along the view axis of each pixel, in the plant's units (metres for species sized in
metres), 0 where the mask is background (:class:`sylva.render.offscreen.DepthImage`).

Examples
--------
>>> branch_ids(np.array([-1, 0, 1, 1, 0]), np.array([0, 0, 1, 0, 0]))
array([0, 0, 1, 0, 0])
"""

from __future__ import annotations

import dataclasses

import numpy as np

__all__ = ["CATEGORIES", "branch_ids", "coco", "depth_png", "instance_mask", "label_images"]

#: COCO categories of the organs.
CATEGORIES = [{"id": 1, "name": "branch"}, {"id": 2, "name": "leaf"},
              {"id": 3, "name": "flower"}]  # fmt: skip
_STEP = 16  # 16 levels a channel: rounding absorbs the renderer's few-unit errors
_N = 256 // _STEP


def branch_ids(parent: np.ndarray, depth: np.ndarray) -> np.ndarray:
    """Branch (axis) of each segment: a segment continues its parent's axis when it has
    the parent's bracket depth, and starts a new one otherwise."""
    out = np.empty(parent.shape[0], np.int64)
    n = 0
    for k in range(parent.shape[0]):
        p = int(parent[k])
        if p >= 0 and depth[k] == depth[p]:
            out[k] = out[p]
        else:
            out[k] = n
            n += 1
    return out


def _id_colors(ids: np.ndarray) -> np.ndarray:
    """Linear colours whose sRGB encoding is the id on the 8-step grid (id 0: background)."""
    q = _STEP * np.stack([(ids // _N**2) % _N, (ids // _N) % _N, ids % _N], 1) / 255.0
    lin = np.where(q <= 0.04045, q / 12.92, ((q + 0.055) / 1.055) ** 2.4)
    return lin.astype(np.float32)


def instance_mask(plant, camera, size) -> tuple[np.ndarray, dict[int, int]]:
    """Render the organ ids of ``plant`` (a :class:`sylva.plant.Plant`) from ``camera``.

    Returns
    -------
    (uint16[h, w], dict)
        The mask (0 background) and each id's category (:data:`CATEGORIES`).
    """
    mask, cats, _ = label_images(plant, camera, size)
    return mask, cats


def label_images(plant, camera, size):
    """The instance mask, its categories and the depth of one render of ``plant``.

    Returns
    -------
    (uint16[h, w], dict, DepthImage)
        As :func:`instance_mask`, and the depth of the same pixels (0 where the mask is 0).
    """
    from .geometry.build import build_mesh
    from .render.offscreen import Renderer

    g = plant.geometry
    nb = 0
    cats: dict[int, int] = {}
    seg = np.zeros(0, np.int64)
    if g.seg_start.shape[0]:
        seg = branch_ids(g.seg_parent, g.seg_depth) + 1
        nb = int(seg.max())
        cats.update({i: 1 for i in range(1, nb + 1)})
    leaf = nb + 1 + np.arange(g.leaf_pos.shape[0])
    cats.update({int(i): 2 for i in leaf})
    n_poly = max(len(g.poly_offsets) - 1, 0)
    poly = nb + 1 + len(leaf) + np.arange(n_poly)
    cats.update({int(i): 3 for i in poly})
    if len(cats) >= _N**3:
        raise ValueError(f"{len(cats)} organs: the mask holds at most {_N**3 - 1}")
    ids = dataclasses.replace(
        g, seg_color=_id_colors(seg), leaf_color=_id_colors(leaf),
        poly_color=_id_colors(poly), vertex_colors=True,
        materials=[dataclasses.replace(m, color=(1.0, 1.0, 1.0, 1.0), texture=None)
                   for m in g.materials],
    )  # fmt: skip
    scene = build_mesh(ids, detail=plant._detail, mode=plant._mode, taper=plant._taper,
                       colors=True)  # fmt: skip
    for m in scene.meshes:
        m.materials = [dataclasses.replace(x, color=(1.0, 1.0, 1.0, 1.0), texture=None,
                                           alpha_cutoff=None) for x in m.materials]
    img, depth = Renderer.default().render(scene, size=size, camera=camera, lit=False,
                                           msaa=0, shadows=False, ground=False, bg="black",
                                           textures=False, sky=False, depth=True)  # fmt: skip
    img = np.asarray(img, np.int64)
    q = np.minimum(np.rint(img / _STEP).astype(np.int64), _N - 1)
    mask = q[..., 0] * _N**2 + q[..., 1] * _N + q[..., 2]
    mask[~np.isin(mask, list(cats))] = 0
    depth.values[mask == 0] = 0.0
    return mask.astype(np.uint16), cats, depth


def depth_png(depth) -> np.ndarray:
    """``uint16[h, w]`` encoding of a :class:`~sylva.render.offscreen.DepthImage`: 0 is the
    background, ``1 + round((d - near) / (far - near) · 65534)`` a drawn pixel (so
    ``d = near + (v - 1) / 65534 · (far - near)``, within half a step of the float)."""
    d = depth.values.astype(np.float64)
    span = max(depth.far - depth.near, 1e-12)
    v = 1.0 + np.rint(np.clip((d - depth.near) / span, 0.0, 1.0) * 65534.0)
    return np.where(d > 0, v, 0).astype(np.uint16)


def coco(masks: list[tuple[str, np.ndarray, dict[int, int]]]) -> dict:
    """A COCO document for ``(file_name, mask, categories)`` triples (one image each)."""
    from pycocotools import mask as mask_util

    images, anns = [], []
    for image_id, (name, mask, cats) in enumerate(masks, 1):
        h, w = mask.shape
        images.append({"id": image_id, "file_name": name, "width": int(w), "height": int(h)})
        for i in np.unique(mask):
            if i == 0:
                continue
            m = np.asfortranarray((mask == i).astype(np.uint8))
            rle = mask_util.encode(m)
            rle["counts"] = rle["counts"].decode("ascii")
            x, y, bw, bh = (float(v) for v in mask_util.toBbox(rle))
            anns.append({"id": len(anns) + 1, "image_id": image_id,
                         "category_id": cats[int(i)], "segmentation": rle,
                         "area": float(mask_util.area(rle)), "bbox": [x, y, bw, bh],
                         "iscrowd": 0, "organ": int(i)})  # fmt: skip
    return {"info": {"description": "sylva batch labels"}, "images": images,
            "annotations": anns, "categories": CATEGORIES}  # fmt: skip
