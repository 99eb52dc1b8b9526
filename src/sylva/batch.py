"""Plant batches on the Dask road: programs × seeds × ages × parameter sweeps × cameras.

A plan (TOML) lists plant entries; each entry is expanded into *items*, the product of its
seeds, ages (derivation steps) and swept program constants, and every item is one Dask
task (:mod:`sylva.cluster`) that grows the plant once, writes its exports and renders it
from each camera.  ``manifest.parquet`` has one row per output file: the inputs, the seed,
the counts, the time the task took and the path.  Rendering happens in the workers, one
GL context per worker process (:mod:`sylva.render.context` makes one per process).

A plan::

    [output]
    formats = ["glb"]          # export formats per item (any of sylva export's)
    size = [320, 240]          # render size; no cameras: no renders

    [[plant]]
    source = "abop-1.24a-plant"   # an example name, a file (relative to the plan), text,
    seeds = [1, 2, 3]             # or a tree species ("quaking_aspen"; steps are years)
    steps = [3, 4]                # ages
    cameras = [{yaw = 30, pitch = 20}, {yaw = 120, pitch = 10}]
    [plant.sweep]                 # program constants, one run per value
    angle = [20.0, 25.7]

Examples
--------
>>> plan = parse_plan('[[plant]]\\nsource = "koch-snowflake"\\nseeds = [1, 2]\\nsteps = [1]')
>>> [(i.source, i.seed, i.steps) for i in plan.items]
[('koch-snowflake', 1, 1), ('koch-snowflake', 2, 1)]
"""

from __future__ import annotations

import itertools
import json
import re
import time
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ._atomic import atomic_path, make_folder
from .errors import SylvaError

__all__ = ["Item", "Plan", "parse_plan", "run_batch"]

_OUTPUT_KEYS = {"formats", "size"}
_PLANT_KEYS = {"source", "seeds", "steps", "cameras", "sweep"}
_FORMATS = {"glb", "gltf", "obj", "ply", "stl", "usd", "usda", "pov", "scad"}


@dataclass(frozen=True)
class Item:
    """One plant of a batch: grown once, exported, rendered from each camera."""

    index: int
    source: str
    seed: int
    steps: int | None
    params: tuple[tuple[str, float], ...] = ()
    cameras: tuple[tuple[float, float], ...] = ()


@dataclass
class Plan:
    """A parsed plan: its items and output settings."""

    items: list[Item]
    formats: tuple[str, ...] = ("glb",)
    size: tuple[int, int] = (320, 240)
    base: Path = field(default_factory=Path)


def _where(filename: str, what: str) -> str:
    return f"{filename}: {what}"


def _ints(v, name: str, filename: str) -> list:
    v = v if isinstance(v, list) else [v]
    if not v or not all(isinstance(x, int) and not isinstance(x, bool) for x in v):
        raise SylvaError(_where(filename, f"{name}: expected a whole number or a list of "
                                          f"them, got {v!r}"))  # fmt: skip
    return v


def parse_plan(text: str, filename: str = "<plan>", base=None) -> Plan:
    """Parse a plan (TOML text) into its items.

    Raises
    ------
    SylvaError
        Naming the file, line and column of a TOML error, or the key that is wrong and what
        was expected.
    """
    try:
        doc = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        m = re.search(r"\(at line (\d+), column (\d+)\)", str(exc))
        where = f"{filename}:{m.group(1)}:{m.group(2)}" if m else filename
        raise SylvaError(f"{where}: {str(exc).split(' (at line')[0]}; expected a TOML "
                         "plan") from None  # fmt: skip
    unknown = set(doc) - {"output", "plant"}
    if unknown:
        raise SylvaError(_where(filename, f"unknown table(s) {sorted(unknown)}; expected "
                                          "[output] and [[plant]]"))  # fmt: skip
    out = doc.get("output", {})
    bad = set(out) - _OUTPUT_KEYS
    if bad:
        raise SylvaError(_where(filename, f"[output]: unknown key(s) {sorted(bad)}; expected "
                                          f"{sorted(_OUTPUT_KEYS)}"))  # fmt: skip
    formats = tuple(out.get("formats", ["glb"]))
    for f in formats:
        if f not in _FORMATS:
            raise SylvaError(_where(filename, f"[output] formats: unknown format {f!r}; "
                                              f"expected some of {sorted(_FORMATS)}"))
    size = out.get("size", [320, 240])
    if (not isinstance(size, list) or len(size) != 2
            or not all(isinstance(s, int) and 8 <= s <= 4096 for s in size)):  # fmt: skip
        raise SylvaError(_where(filename, f"[output] size: expected [width, height] in "
                                          f"8..4096, got {size!r}"))  # fmt: skip
    plants = doc.get("plant", [])
    if not isinstance(plants, list) or not plants:
        raise SylvaError(_where(filename, "expected at least one [[plant]] table"))
    items: list[Item] = []
    for k, p in enumerate(plants, 1):
        bad = set(p) - _PLANT_KEYS
        if bad:
            raise SylvaError(_where(filename, f"[[plant]] #{k}: unknown key(s) {sorted(bad)}; "
                                              f"expected {sorted(_PLANT_KEYS)}"))
        source = p.get("source")
        if not isinstance(source, str) or not source:
            raise SylvaError(_where(filename, f"[[plant]] #{k}: expected source = \"NAME\""))
        seeds = _ints(p.get("seeds", [1]), f"[[plant]] #{k} seeds", filename)
        steps = p.get("steps")
        steps = [None] if steps is None else _ints(steps, f"[[plant]] #{k} steps", filename)
        cams = []
        for c in p.get("cameras", []):
            if not isinstance(c, dict) or set(c) - {"yaw", "pitch"}:
                raise SylvaError(_where(filename, f"[[plant]] #{k} cameras: expected "
                                                  "{yaw = DEG, pitch = DEG} tables"))
            cams.append((float(c.get("yaw", 30.0)), float(c.get("pitch", 20.0))))
        sweep = p.get("sweep", {})
        names = sorted(sweep)
        values = []
        for n in names:
            v = sweep[n] if isinstance(sweep[n], list) else [sweep[n]]
            if not v or not all(isinstance(x, (int, float)) and not isinstance(x, bool)
                                for x in v):  # fmt: skip
                raise SylvaError(_where(filename, f"[[plant]] #{k} sweep.{n}: expected "
                                                  "numbers"))
            values.append([float(x) for x in v])
        for seed, st, combo in itertools.product(seeds, steps, itertools.product(*values)):
            items.append(Item(len(items), source, seed, st, tuple(zip(names, combo)),
                              tuple(cams)))  # fmt: skip
    return Plan(items, formats, (size[0], size[1]), Path(base or "."))


def _source(item: Item, base: Path):
    p = base / item.source
    return p if p.suffix and p.is_file() else item.source


def _item_task(job) -> list[dict]:
    """One Dask task: grow an item, export it, render it from each camera."""
    from .grown import _is_species, tree
    from .plant import grow, resolve
    from .render import Camera

    item, formats, size, base, out, labels = job
    t0 = time.perf_counter()
    source = _source(item, Path(base))
    if _is_species(source):  # a Weber–Penn species or tree file: steps are years
        if item.params:
            raise SylvaError(f"{item.source}: a sweep sets an L-system's constants; a tree "
                             "species has none")  # fmt: skip
        if labels and item.cameras:
            raise SylvaError(f"{item.source}: --labels needs an L-system plant (its organs); "
                             "a tree species has no instance mask yet")  # fmt: skip
        plant = tree(source, age=item.steps, seed=item.seed)
    else:
        program = resolve(source)
        if item.params:
            unknown = [n for n, _ in item.params if n not in program.constants]
            if unknown:
                raise SylvaError(f"{item.source}: sweep of unknown constant(s) {unknown}; the "
                                 f"program has {sorted(program.constants)}")  # fmt: skip
            program = program.replace(constants={**program.constants, **dict(item.params)})
        plant = grow(program, item.steps, seed=item.seed)
    folder = Path(out) / "items" / f"{item.index:05d}"
    make_folder(folder)
    files = []
    for fmt in formats:
        files.append(("asset", fmt, None, plant.save(folder / f"plant.{fmt}"), None))
    scene = plant.scene
    for j, (yaw, pitch) in enumerate(item.cameras):
        cam = Camera.auto(scene.bounds(), "perspective", yaw=yaw, pitch=pitch,
                          aspect=size[0] / size[1])  # fmt: skip
        image = plant.render(size=size, camera=cam)
        path = folder / f"camera{j}.png"
        with atomic_path(path) as tmp:
            image.save(tmp, format="PNG")
        files.append(("render", "png", (yaw, pitch), path, None))
        if labels:
            files += _labels(plant, cam, size, folder, j, (yaw, pitch))
    dt = time.perf_counter() - t0
    stats = plant.stats
    return [{
        "item": item.index, "source": item.source, "seed": item.seed,
        "steps": -1 if item.steps is None else item.steps,
        "params": json.dumps(dict(item.params)), "kind": kind, "format": fmt,
        "yaw": None if cam is None else cam[0], "pitch": None if cam is None else cam[1],
        "path": str(Path(p).relative_to(out)), "modules": int(stats.get("modules", 0)),
        "segments": int(stats.get("segments", 0)), "leaves": int(stats.get("leaves", 0)),
        "triangles": int(sum(m.n_triangles for m in scene.meshes)), "seconds": dt,
        "near": None if clip is None else clip[0], "far": None if clip is None else clip[1],
    } for kind, fmt, cam, p, clip in files]  # fmt: skip


def _labels(plant, cam, size, folder: Path, j: int, view) -> list:
    """The instance mask (16-bit PNG of organ ids), the depth (float32 NPY and 16-bit PNG)
    and the COCO JSON of camera ``j``."""
    from PIL import Image

    from ._atomic import atomic_write
    from ._labels import coco, depth_png, label_images

    mask, cats, depth = label_images(plant, cam, size)
    mpath = folder / f"camera{j}.mask.png"
    with atomic_path(mpath) as tmp:
        Image.fromarray(mask.astype(np.uint16)).save(tmp, format="PNG")
    npath = folder / f"camera{j}.depth.npy"
    with atomic_write(npath, "wb") as fh:
        np.save(fh, depth.values.astype(np.float32))
    dpath = folder / f"camera{j}.depth.png"
    with atomic_path(dpath) as tmp:
        Image.fromarray(depth_png(depth)).save(tmp, format="PNG")
    doc = coco([(f"camera{j}.png", mask, cats)])
    doc["images"][0].update(depth_file=dpath.name, depth_near=depth.near,
                            depth_far=depth.far)  # fmt: skip
    cpath = folder / f"camera{j}.coco.json"
    with atomic_write(cpath, "w") as fh:
        fh.write(json.dumps(doc))
    clip = (depth.near, depth.far)
    return [("mask", "png", view, mpath, None), ("depth", "npy", view, npath, clip),
            ("depth", "png", view, dpath, clip), ("labels", "coco", view, cpath, None)]


def run_batch(plan: Plan, out, *, scheduler: str | None = None, workers: int | None = None,
              progress=False, labels: bool = False) -> dict:  # fmt: skip
    """Run every item of ``plan`` as a Dask task; write ``out/manifest.parquet``.

    With ``labels``, every render also gets its per-organ instance mask
    (``cameraJ.mask.png``, 16-bit organ ids, 0 the background), its depth and a COCO
    annotation file (``cameraJ.coco.json``: categories branch, leaf, flower; RLE masks),
    see :mod:`sylva._labels`.  The depth is the distance from the eye along the view axis
    in the plant's units (metres for species sized in metres): ``cameraJ.depth.npy``
    (float32, 0 the background) and ``cameraJ.depth.png`` (16-bit: 0 the background,
    ``v`` → ``near + (v − 1) / 65534 · (far − near)``); the manifest rows of both (kind
    ``depth``) and the COCO image entry (``depth_near``, ``depth_far``) give near and far.

    Returns
    -------
    dict
        ``items``, ``files`` and the manifest's path.
    """
    import pyarrow as pa
    import pyarrow.parquet as pq

    from .cluster import connect

    out = Path(out)
    make_folder(out)
    jobs = [(it, plan.formats, plan.size, str(plan.base), str(out), labels)
            for it in plan.items]
    rows: list[dict] = []
    with connect(scheduler, workers=workers, tasks=len(jobs)) as run:
        for r in run.map(_item_task, jobs, progress=progress, unit="item"):
            rows.extend(r)
    rows.sort(key=lambda r: (r["item"], r["path"]))
    table = pa.Table.from_pylist(rows, schema=pa.schema([
        ("item", pa.int32()), ("source", pa.string()), ("seed", pa.int64()),
        ("steps", pa.int32()), ("params", pa.string()), ("kind", pa.string()),
        ("format", pa.string()), ("yaw", pa.float32()), ("pitch", pa.float32()),
        ("path", pa.string()), ("modules", pa.int64()), ("segments", pa.int64()),
        ("leaves", pa.int64()), ("triangles", pa.int64()),
        ("seconds", pa.float64()), ("near", pa.float64()), ("far", pa.float64()),
    ]))  # fmt: skip
    manifest = out / "manifest.parquet"
    with atomic_path(manifest) as tmp:
        pq.write_table(table, tmp)
    return {"items": len(plan.items), "files": len(rows), "manifest": manifest}
