"""Turtle + tube mesh throughput on a bracketed 3D plant with about a million segments.

Run: ``python benchmarks/mesh.py [--segments 1000000] [--detail 8] [--repeat 5]``

Measures, after a warm-up that compiles the kernels:

* ``turtle``: :func:`sylva.turtle.interpret` over the word's arrays;
* ``mesh``: :func:`sylva.geometry.build.build_branches` (continuous tubes, parallel-transport
  frames, mitred shared rings, caps, normals, UVs);
* segments per second for both together, median and best of ``--repeat`` rounds, in two
  cases: built after the buffer pool was emptied (every page fresh from the kernel, which
  zeroes it), and built again at once (the pages of the previous build reused, as when the
  studio re-derives, an animation meshes frame after frame or a world grows plant after
  plant; see :mod:`sylva.geometry.buffers`);
* ``peer``: the issue's reference, a straightforward vectorised NumPy tube builder
  (:func:`numpy_tubes`), on the same turtle output, and the ratios to it (median to
  median, best to best; the three alternate in every round, so all meet the same load);
* ``floor``: allocating and writing, in parallel and without arithmetic, fresh arrays as
  large as all that a build writes (the turtle's records, the tube plan, the mesh) — on
  this VM fresh pages cost about twice the writes themselves, so no build on fresh pages
  that returns new arrays can beat it;
* peak memory per triangle: the growth of the process's peak resident set during one
  turtle + mesh run from an empty pool (Linux ``VmHWM`` after resetting it), divided by the
  triangle count; it includes the turtle's records and the finished mesh.

The word comes from a 3D bracketed plant (every X splits into three pitched, rolled
branches), derived by plain string rewriting and turned into a ModuleString through a
byte lookup (word construction is not timed).
"""

from __future__ import annotations

import argparse
import os
import resource
import statistics
import sys
import time

import numpy as np

from sylva.geometry import buffers
from sylva.geometry.build import build_branches
from sylva.lsystem.lstring import Alphabet, ModuleString
from sylva.turtle import interpret

RULES = {"X": "F[&+X]/[&-X]\\[^X]FX", "F": "FF"}


def plant_word(min_segments: int) -> ModuleString:
    word = "X"
    while word.count("F") < min_segments:
        word = "".join(RULES.get(c, c) for c in word)
    alphabet = Alphabet()
    table = np.zeros(256, np.int32)
    for ch in sorted(set(word)):
        table[ord(ch)] = alphabet.id(ch)
    ids = table[np.frombuffer(word.encode("ascii"), np.uint8)]
    return ModuleString(alphabet, ids)


def numpy_tubes(g, d: int):
    """The issue's reference: a straightforward vectorised NumPy tube builder.

    Every segment gets its own start and end ring (no sharing, no mitres, no caps), with
    normals, UVs and indices, from NumPy array operations alone — written with care: in
    float32 (the mesh's type) and into preallocated arrays (a first version in float64 with
    concatenations ran about 1.7x slower; the ratio is taken to this faster one)."""
    start = g.seg_start.astype(np.float32)
    end = g.seg_end.astype(np.float32)
    n = len(start)
    axis = end - start
    axis /= np.linalg.norm(axis, axis=1, keepdims=True)
    ref = g.seg_ref
    bin_ = np.cross(axis, ref)
    ang = np.linspace(0.0, 2.0 * np.pi, d + 1, dtype=np.float32)
    c, s = np.cos(ang)[None, :, None], np.sin(ang)[None, :, None]
    normals = np.empty((n, 2, d + 1, 3), np.float32)
    normals[:, 0] = c * ref[:, None, :] + s * bin_[:, None, :]
    normals[:, 1] = normals[:, 0]
    r = g.seg_radius
    verts = np.empty((n, 2, d + 1, 3), np.float32)
    np.multiply(r[:, 0, None, None], normals[:, 0], out=verts[:, 0])
    verts[:, 0] += start[:, None, :]
    np.multiply(r[:, 1, None, None], normals[:, 1], out=verts[:, 1])
    verts[:, 1] += end[:, None, :]
    uvs = np.empty((n, 2, d + 1, 2), np.float32)
    uvs[..., 0] = np.linspace(0.0, 1.0, d + 1, dtype=np.float32)
    uvs[:, 0, :, 1] = 0.0
    uvs[:, 1, :, 1] = 1.0
    j = np.arange(d, dtype=np.uint32)
    quad = np.stack([j, j + 1, d + 2 + j, j, d + 2 + j, d + 1 + j], axis=1).reshape(-1, 3)
    idx = np.empty((n, 2 * d, 3), np.uint32)
    base = np.arange(n, dtype=np.uint32) * np.uint32(2 * (d + 1))
    np.add(quad[None], base[:, None, None], out=idx)
    return verts.reshape(-1, 3), normals.reshape(-1, 3), uvs.reshape(-1, 2), idx.reshape(-1, 3)


def run_once(word: ModuleString, detail: int) -> tuple[float, float, int, int, float, float]:
    """Wall and CPU seconds of the turtle and of the mesh, segments and triangles."""
    c0, t0 = time.process_time(), time.perf_counter()
    g = interpret(word, dialect="abop", rot=28.0, thick=0.05, thick_factor=0.85)
    c1, t1 = time.process_time(), time.perf_counter()
    m = build_branches(g, detail=detail)
    c2, t2 = time.process_time(), time.perf_counter()
    run_once.mesh_bytes = sum(
        a.nbytes
        for a in (m.vertices, m.normals, m.uvs, m.colors, m.indices, m.material_ids)
        if a is not None
    )
    return t1 - t0, t2 - t1, g.n_segments, m.n_triangles, c1 - c0, c2 - c1


def _status_kib(field: str) -> int:
    with open("/proc/self/status") as fh:
        for line in fh:
            if line.startswith(field + ":"):
                return int(line.split()[1])
    raise OSError(f"{field} not in /proc/self/status")


def peak_memory(word: ModuleString, detail: int) -> dict:
    """Peak resident-set growth of one turtle + mesh run (Linux: resets VmHWM first)."""
    buffers.release()
    with open("/proc/self/clear_refs", "w") as fh:
        fh.write("5")  # reset the peak RSS to the current RSS
    base = _status_kib("VmRSS")
    _, _, n, t, _, _ = run_once(word, detail)
    return {"kib": _status_kib("VmHWM") - base, "triangles": t, "segments": n}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--segments", type=int, default=1_000_000)
    ap.add_argument("--detail", type=int, default=8)
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--no-memory", action="store_true")
    args = ap.parse_args(argv)
    word = plant_word(args.segments)
    run_once(plant_word(10), args.detail)  # compile
    g = interpret(word, dialect="abop", rot=28.0, thick=0.05, thick_factor=0.85)
    fresh, again, peer = [], [], []
    for _ in range(args.repeat):  # the three alternate, so that all meet the same load
        buffers.release()
        fresh.append(run_once(word, args.detail))  # every page fresh
        again.append(run_once(word, args.detail))  # the pages of the build before
        t0 = time.perf_counter()
        numpy_tubes(g, args.detail)
        peer.append(time.perf_counter() - t0)
    n, tris = fresh[0][2], fresh[0][3]
    print(f"word: {len(word):,} modules; {n:,} segments; {tris:,} triangles at {args.detail} sides")
    print(f"threads: {os.cpu_count()} cpus (numba threads: {_numba_threads()})")
    print(f"load average: {os.getloadavg()[0]:.1f} (other processes share the cores)")
    print(f"median and best of {args.repeat} rounds; M segments/s in brackets")
    tn, bn = statistics.median(peer), min(peer)
    for title, runs in (("built on fresh pages:", fresh), ("built again, pooled pages:", again)):
        print(title)
        for name, k, c in (("turtle", (0,), (4,)), ("mesh", (1,), (5,)), ("total", (0, 1), (4, 5))):
            wall = [sum(r[i] for i in k) for r in runs]
            cpu = statistics.median([sum(r[i] for i in c) for r in runs])
            med, low = statistics.median(wall), min(wall)
            print(
                f"  {name + ':':7} {med * 1e3:7.1f} ms ({n / med / 1e6:5.2f})  best "
                f"{low * 1e3:7.1f} ms ({n / low / 1e6:5.2f})  cpu {cpu * 1e3:7.1f} ms"
            )
    print(
        f"peer:    {tn * 1e3:7.1f} ms ({n / tn / 1e6:5.2f})  best {bn * 1e3:7.1f} ms "
        f"({n / bn / 1e6:5.2f})  a straightforward vectorised NumPy tube builder, mesh only"
    )
    ratio = {
        key: (tn / statistics.median([r[0] + r[1] for r in runs]),
              bn / min(r[0] + r[1] for r in runs))
        for key, runs in (("fresh", fresh), ("again", again))
    }  # fmt: skip
    print(
        f"target: 5 M segments/s where such a builder makes 0.87 M/s (issue 3), i.e. "
        f"{5 / 0.87:.2f}x the peer; turtle + mesh are {ratio['again'][0]:.2f}x the peer built "
        f"again ({ratio['again'][1]:.2f}x best to best), {ratio['fresh'][0]:.2f}x on fresh pages "
        f"({ratio['fresh'][1]:.2f}x)"
    )
    written = {
        "turtle records": sum(a.nbytes for a in _segment_arrays(g)),
        "tube plan": n * 18 + 2 * (n + 1) * 8,  # cont, prev, dup, v1, voff, toff
        "mesh": run_once.mesh_bytes,
    }
    floor = fresh_write_floor(sum(written.values()) // 4)
    sizes = ", ".join(f"{k} {v / 2**20:.0f}" for k, v in written.items())
    low = min(r[0] + r[1] for r in fresh)
    print(
        f"floor:   {floor * 1e3:7.1f} ms  allocating and writing, in parallel and without "
        f"arithmetic, fresh arrays as large as all a build writes (MiB: {sizes}); the best "
        f"build on fresh pages takes {low / floor:.1f}x that"
    )
    del g
    if not args.no_memory:
        p = peak_memory(word, args.detail)
        print(f"peak memory: {p['kib'] / 1024:.0f} MiB for {p['triangles']:,} triangles = "
              f"{p['kib'] * 1024 / p['triangles']:.1f} bytes per triangle")  # fmt: skip
    return 0


def _segment_arrays(g) -> list[np.ndarray]:
    return [g.seg_start, g.seg_end, g.seg_radius, g.seg_color, g.seg_material, g.seg_module,
            g.seg_parent, g.seg_depth, g.seg_ref]  # fmt: skip


def fresh_write_floor(words: int) -> float:
    """Seconds to allocate and write ``words`` float32 on every numba thread — best of three."""
    import numba

    @numba.njit(parallel=True)
    def fill(a):
        n = a.shape[0]
        for c in numba.prange(256):
            for i in range(c * n // 256, (c + 1) * n // 256):
                a[i] = 1.0

    fill(np.empty(16, np.float32))
    best = float("inf")
    for _ in range(3):
        t0 = time.perf_counter()
        fill(np.empty(words, np.float32))
        best = min(best, time.perf_counter() - t0)
    return best


def _numba_threads() -> int:
    import numba

    return numba.get_num_threads()


if __name__ == "__main__":
    resource.setrlimit(resource.RLIMIT_CORE, (0, 0))
    sys.exit(main())
