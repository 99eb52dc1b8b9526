"""Cold start: what ``import sylva`` loads, the compile message and ``sylva warmup``."""

import io
import json
import os
import re
import subprocess
import sys
from pathlib import Path

import sylva

SRC = str(Path(sylva.__file__).parent.parent)


def _python(code: str, **env) -> subprocess.CompletedProcess:
    e = dict(os.environ, PYTHONPATH=SRC + os.pathsep + os.environ.get("PYTHONPATH", ""), **env)
    return subprocess.run([sys.executable, "-c", code], env=e, capture_output=True, text=True,
                          timeout=600)


def test_import_sylva_loads_no_numba_gl_or_server():
    code = (
        "import json, sys, sylva\n"
        "print(json.dumps(sorted(m for m in sys.modules if m.split('.')[0] in "
        "('numba', 'llvmlite', 'moderngl', 'scipy', 'starlette', 'uvicorn', 'PIL') "
        "or m.endswith(('_kernels', '_gridkernels', '_cellkernels', '_simd')))))\n"
    )
    proc = _python(code)
    assert proc.returncode == 0, proc.stderr
    assert json.loads(proc.stdout) == []


def test_lazy_kernels_load_on_first_use():
    # a derivation that needs a compiled kernel (context-sensitive) imports it then
    code = (
        "import sys, sylva\n"
        "w = sylva.derive(sylva.loads('axiom = baaa\\nb < a -> b'), 2)\n"
        "print(w.to_text(), 'sylva.lsystem._kernels' in sys.modules)\n"
    )
    proc = _python(code)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.split() == ["bbba", "True"]


_RASTER = (
    "import numpy as np\n"
    "from sylva._jit import announce\n"
    "announce()\n"  # before numba is imported: the message must still come
    "from sylva.texture import _raster\n"
    "rgb = np.zeros((8, 8, 3)); alpha = np.zeros((8, 8)); z = np.zeros(1)\n"
    "_raster.draw_segments(rgb, alpha, z, z, z + 4, z + 4, z + 1, np.ones((1, 3)), False)\n"
    "print(round(float(alpha.sum()), 6))\n"
)


def test_a_first_run_says_once_that_it_compiles(tmp_path):
    cache = str(tmp_path / "numba-cache")
    first = _python(_RASTER, NUMBA_CACHE_DIR=cache)
    assert first.returncode == 0, first.stderr
    lines = [ln for ln in first.stderr.splitlines() if "compiling" in ln]
    # a file, not a terminal: one line per kernel module, with the count of its kernels
    assert len(lines) == 1
    assert re.fullmatch(
        r"sylva: compiling sylva's texture kernels, once: 1/\d+ \(a first run compiles what "
        r"it uses and caches it; `sylva warmup` compiles everything ahead\)", lines[0]
    )
    second = _python(_RASTER, NUMBA_CACHE_DIR=cache)
    assert second.returncode == 0, second.stderr
    assert "compiling" not in second.stderr  # loaded from the cache: nothing to say
    assert second.stdout == first.stdout and float(first.stdout) > 0


def test_the_message_counts_a_terminal_line_up(tmp_path):
    from sylva._jit import _Progress

    class Tty(io.StringIO):
        def isatty(self):
            return True

    class Dispatcher:
        def __init__(self, name):
            def f():
                pass

            f.__module__ = "sylva.lsystem._kernels"
            f.__qualname__ = f.__name__ = name
            self.py_func = f

    out = Tty()
    prog = _Progress(out)
    for name in ("a", "b", "a"):  # a kernel compiled again (another signature) counts once
        prog.start(Dispatcher(name))
    prog.finish()
    text = out.getvalue()
    assert "\rcompiling sylva's derivation kernels, once: 1/" in text
    assert "\rcompiling sylva's derivation kernels, once: 2/" in text
    assert "once: 3/" not in text
    assert text.endswith("(cached now)\x1b[K\n")


def test_warmup_compiles_ahead_so_that_the_command_compiles_nothing(tmp_path):
    cache = tmp_path / "numba-cache"
    env = {"NUMBA_CACHE_DIR": str(cache)}
    profile = tmp_path / "profile.jsonl"
    warm = _python("from sylva.cli import main; raise SystemExit(main(['warmup', '--only', "
                   f"'derivation', '--jobs', '1', '--profile', {str(profile)!r}]))", **env)
    assert warm.returncode == 0, warm.stderr
    # --profile: a JSON line per kernel compiled, with its CPU seconds (a compile inside
    # another counts in both totals, once in the "self" seconds)
    recs = [json.loads(ln) for ln in profile.read_text().splitlines()]
    assert {r["group"] for r in recs} == {"derivation"}
    assert any(r["module"] == "sylva.lsystem._kernels" and r["name"] == "rewrite_table"
               for r in recs)  # fmt: skip
    assert all(0 <= r["self"] <= r["cpu"] for r in recs) and sum(r["cpu"] for r in recs) > 0.1
    lines = warm.stderr.splitlines()
    assert lines[0].startswith("sylva warmup: compiling sylva's kernels once, 1 groups on 1 ")
    assert re.fullmatch(r"  \[1/1\] derivation (\d+) kernels compiled in [\d.]+ s - .*", lines[1])
    assert int(lines[1].split()[2]) >= 3
    assert lines[-1].startswith("sylva warmup: done in ")
    # what it compiled is in the cache: the derivation kernels' index files (the examples
    # that grow in a world environment also compile the terrain's noise)
    index = [p.name for p in cache.rglob("*.nbi")]
    assert any(n.startswith("_kernels.rewrite") for n in index)
    # and a command that uses them now loads them: no compile message
    run = _python("from sylva.cli import main; raise SystemExit(main(['derive', "
                  "'18-abop-1.31a-hogeweg', '-n', '4']))", **env)
    assert run.returncode == 0, run.stderr
    assert run.stdout.strip() and "compiling" not in run.stderr


def test_warmup_names_an_unknown_group():
    proc = _python("from sylva.cli import main; raise SystemExit(main(['warmup', '--only', "
                   "'derivatoin']))")
    assert proc.returncode == 2
    assert "unknown group derivatoin; expected one of derivation, plants" in proc.stderr


# ------------------------------------------------------------------ the interpreted road
_COLD_SMALL = (
    "import json, collections\n"
    "from numba.core import event\n"
    "seen = collections.Counter()\n"
    "class L(event.Listener):\n"
    "    def on_start(self, ev):\n"
    "        seen[ev.data['dispatcher'].py_func.__module__] += 1\n"
    "    def on_end(self, ev):\n"
    "        pass\n"
    "event.register('numba:compile', L())\n"
    "from sylva.plant import grow\n"
    "out = {}\n"
    "for name in ('01-koch-snowflake', '18-abop-1.31a-hogeweg', '32-abop-2.10-parametric',\n"
    "             '24-seed000-bush-leaves', '40-sylva-topiary-query'):\n"
    "    p = grow(name)\n"
    "    out[name] = [len(p.word), p.scene.n_triangles]\n"
    "print(json.dumps({'compiled': sorted(m for m in seen if m.startswith('sylva')),\n"
    "                  'plants': out}))\n"
)


def test_small_work_on_a_cold_cache_runs_interpreted_and_compiles_nothing(tmp_path):
    # a fresh install: the first plants come at once (the kernels' own Python source),
    # instead of after tens of seconds of compiling (issue 25)
    proc = _python(_COLD_SMALL, NUMBA_CACHE_DIR=str(tmp_path / "numba-cache"))
    assert proc.returncode == 0, proc.stderr
    got = json.loads(proc.stdout)
    assert got["compiled"] == []
    # and the plants are the plants: ABOP's figures' word sizes (the seeds' own tests pin
    # the words), with meshes
    assert got["plants"]["01-koch-snowflake"][0] == 1792
    assert all(tris > 0 for _, tris in got["plants"].values())
    assert not list((tmp_path / "numba-cache").rglob("*.nbi"))  # nothing was cached


def test_a_first_render_on_a_cold_cache_says_nothing_about_compiling(tmp_path):
    out = tmp_path / "k.png"
    proc = _python("from sylva.cli import main; raise SystemExit(main(['render', "
                   f"'01-koch-snowflake', '--size', '64x48', '-o', {str(out)!r}]))",
                   NUMBA_CACHE_DIR=str(tmp_path / "numba-cache"))  # fmt: skip
    assert proc.returncode == 0, proc.stderr
    assert "compiling" not in proc.stderr and out.stat().st_size > 0


# (example, steps): every kind of word the turtle and the mesh builder meet — 2D, 3D with
# leaves, polygons, parametric, context-sensitive, stochastic, tropism, query modules,
# seed 004's engine turtle, blocks — kept small, the interpreted road is slow
_ROADS = [
    ("01-koch-snowflake", 3), ("09-seed000-hilbert-3d", None), ("18-abop-1.31a-hogeweg", 12),
    ("24-seed000-bush-leaves", 3), ("25-seed000-bush-stochastic", 3),
    ("29-seed004-acacia", None), ("32-abop-2.10-parametric", None), ("33-sylva-fern", 4),
    ("34-sylva-flowering-herb", None), ("39-abop-2.8d-ternary-tree", 4),
    ("40-sylva-topiary-query", 6), ("14-abop-1.24e-plant", 3),
]


def test_the_interpreted_road_equals_the_compiled_road(monkeypatch):
    import numpy as np

    from sylva.plant import grow

    for name, steps in _ROADS:
        monkeypatch.setenv("SYLVA_JIT", "never")
        a = grow(name, steps)
        monkeypatch.setenv("SYLVA_JIT", "always")
        b = grow(name, steps)
        assert a.word.to_text() == b.word.to_text(), name
        assert [m.name for m in a.scene.meshes] == [m.name for m in b.scene.meshes], name
        for ma, mb in zip(a.scene.meshes, b.scene.meshes, strict=True):
            for attr in ("vertices", "normals", "uvs", "colors", "indices", "material_ids"):
                x, y = getattr(ma, attr), getattr(mb, attr)
                assert (x is None) == (y is None), (name, attr)
                if x is None:
                    continue
                assert x.shape == y.shape and x.dtype == y.dtype, (name, attr)
                if x.dtype.kind == "f":
                    # the compiled rings fuse multiply-adds in float32 (a rounding or two)
                    np.testing.assert_allclose(x, y, rtol=1e-6, atol=1e-6, err_msg=name)
                else:
                    np.testing.assert_array_equal(x, y, err_msg=f"{name} {attr}")


_TOY = '''
import numpy as np
from numba import njit

@njit(cache=True)
def total(a):
    s = 0.0
    for x in a:
        s += x
    return s
'''


def test_a_road_runs_small_calls_interpreted_until_the_kernel_compiles(tmp_path, monkeypatch):
    import importlib

    import numpy as np

    from sylva import _jit

    (tmp_path / "toyroad_kernels.py").write_text(_TOY)
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.delenv("SYLVA_JIT", raising=False)
    real = importlib.import_module("toyroad_kernels")
    k = _jit.road("toyroad_kernels", size=10)
    assert k.total(np.ones(5)) == 5.0 and not real.total.signatures  # interpreted
    with _jit.compiled():
        assert k.total(np.ones(5)) == 5.0 and real.total.signatures  # compiled on demand
    assert k.total(np.ones(3)) == 3.0  # compiled now: the compiled road from here on

    (tmp_path / "toyroad2_kernels.py").write_text(_TOY)
    real2 = importlib.import_module("toyroad2_kernels")
    k2 = _jit.road("toyroad2_kernels", size=10)
    assert k2.total(np.ones(50)) == 50.0 and real2.total.signatures  # large: compiles

    (tmp_path / "toyroad3_kernels.py").write_text(_TOY)
    real3 = importlib.import_module("toyroad3_kernels")
    k3 = _jit.road("toyroad3_kernels")  # a module road: small() decides
    with _jit.small(True):
        assert k3.total(np.ones(4)) == 4.0 and not real3.total.signatures
        assert _jit.interpreting(k3, "total")
    with _jit.small(False):
        assert k3.total(np.ones(4)) == 4.0 and real3.total.signatures
        assert not _jit.interpreting(k3, "total")


# ------------------------------------------------------------ noise and worlds (issue 25)
_COLD_WORLD = (
    "import json, collections\n"
    "from numba.core import event\n"
    "seen = collections.Counter()\n"
    "class L(event.Listener):\n"
    "    def on_start(self, ev):\n"
    "        f = ev.data['dispatcher'].py_func\n"
    "        seen[f.__module__ + '.' + f.__name__] += 1\n"
    "    def on_end(self, ev):\n"
    "        pass\n"
    "event.register('numba:compile', L())\n"
    "import numpy as np\n"
    "from sylva.texture import fbm, marble, noise_grid\n"
    "from sylva.world import World, WorldConfig, tile_image\n"
    "store = World(WorldConfig(seed=3, vegetation=False), size=(32, 32)).generate()\n"
    "quads = store.n_quads\n"
    "store.close()\n"
    "m = marble((64, 64), seed=2)\n"
    "tiles = [tile_image(n, 32, 3) for n in ('stone', 'water', 'leaves', 'gravel', 'dirt')]\n"
    "v = fbm(np.arange(50.0) / 7, np.arange(50.0) / 9, kind='perlin', octaves=3)\n"
    "print(json.dumps({'compiled': sorted(k for k in seen if k.startswith('sylva')),\n"
    "                  'quads': quads, 'ptp': float(np.ptp(m)),\n"
    "                  'tiles': [int(t[..., :3].std() > 1) for t in tiles]}))\n"
)


def test_a_first_small_world_and_noise_on_a_cold_cache_compile_only_the_mesher(tmp_path):
    # the noise grids, the lattice fBm at points, the atlas's Worley and simplex tiles and
    # the terrain kernels take the interpreted roads; greedy meshing alone compiles (a
    # voxel loop too long for Python); it was 60 s of compiling (issue 25)
    proc = _python(_COLD_WORLD, NUMBA_CACHE_DIR=str(tmp_path / "numba-cache"))
    assert proc.returncode == 0, proc.stderr
    got = json.loads(proc.stdout)
    assert got["compiled"] == ["sylva.world._kernels._face_tex",
                               "sylva.world._kernels._visible",
                               "sylva.world._kernels.greedy_quads"]  # fmt: skip
    assert got["quads"] > 100 and got["ptp"] > 0.5 and got["tiles"] == [1] * 5


def _noise_cases():
    import numpy as np

    from sylva.texture import fbm, noise_grid, ridged, turbulence

    rng = np.random.default_rng(1)
    p = [rng.uniform(-40, 40, 300) for _ in range(4)]
    out = []
    for kind in ("value", "perlin", "improved"):
        for f, interp, nd, period in [(fbm, None, 2, None), (turbulence, "cosine", 3, 8),
                                      (ridged, "linear", 4, None), (fbm, "quintic", 2, 5),
                                      (ridged, "cubic", 3, None)]:  # fmt: skip
            per = None if period is None else (period,) * nd
            out.append(f(*p[:nd], kind=kind, octaves=4, seed=5, interpolation=interp,
                         period=per, dtype=np.float64))  # fmt: skip
        out.append(fbm(0.3, 0.7, kind=kind, octaves=3))  # a scalar
        for shape, tile, fractal in [((33, 47), True, "fbm"), ((5, 9, 11), False, "ridged")]:
            out.append(noise_grid(shape, kind=kind, fractal=fractal, octaves=3, seed=2,
                                  tileable=tile, dtype=np.float64))  # fmt: skip
    for kind, shape, tile, output in [("worley", (17, 23), True, "f2-f1"),
                                      ("worley", (4, 5, 6), False, "cell"),
                                      ("simplex", (19, 21), True, "f1"),
                                      ("simplex", (4, 5, 6), False, "f1"),
                                      ("value", (2, 3, 4, 5), False, "f1")]:  # fmt: skip
        out.append(noise_grid(shape, kind=kind, octaves=2, seed=4, tileable=tile,
                              output=output, dtype=np.float64))  # fmt: skip
    return out


def test_the_cold_noise_roads_equal_the_compiled_ones(monkeypatch):
    # lattice noise by its source on whole arrays, simplex and Worley grids by their source
    # sample by sample: the compiled kernels' values bit for bit (float64)
    import numpy as np

    from sylva.texture import noise_grid

    monkeypatch.setenv("SYLVA_JIT", "never")
    cold = _noise_cases()
    cold32 = noise_grid((20, 30), kind="improved", octaves=3, seed=1)
    monkeypatch.setenv("SYLVA_JIT", "always")
    warm = _noise_cases()
    warm32 = noise_grid((20, 30), kind="improved", octaves=3, seed=1)
    assert len(cold) == len(warm) == 29
    for i, (a, b) in enumerate(zip(cold, warm, strict=True)):
        np.testing.assert_array_equal(a, b, err_msg=str(i))
    # float32 output: the float64 road rounded once against the float32 kernels
    assert cold32.dtype == warm32.dtype == np.float32
    np.testing.assert_allclose(cold32, warm32, rtol=0, atol=5e-7)


def test_a_small_world_is_the_same_on_both_roads(monkeypatch):
    import numpy as np

    from sylva import _jit
    from sylva.data import find
    from sylva.lsystem import load
    from sylva.world import WorldConfig, tile_image
    from sylva.world.chunks import generate_chunks
    from sylva.world.executor import grow

    def make():
        cfg = WorldConfig(seed=3, chunk_size=16)
        with _jit.small(True):  # as World.generate of a small world
            chunks = generate_chunks(cfg, 0, 0, 2, 2, keep_voxels=True)
        tiles = [tile_image(n, 16, 3) for n in ("stone", "water", "leaves_birch")]
        acacia = load(find("acacia").path, dialect="engine")  # blocks' containment test
        blocks = grow(acacia, 1234, derivations=4, optimize=True)
        return chunks, tiles, blocks

    monkeypatch.setenv("SYLVA_JIT", "never")
    cold = make()
    monkeypatch.setenv("SYLVA_JIT", "always")
    warm = make()
    for a, b in zip(cold[0], warm[0], strict=True):
        for attr in ("height", "humidity", "temperature", "biome", "quads", "voxels"):
            np.testing.assert_array_equal(getattr(a, attr), getattr(b, attr), err_msg=attr)
        for attr in ("keys", "position", "yaw", "column"):
            np.testing.assert_array_equal(getattr(a.plants, attr), getattr(b.plants, attr))
    assert sum(len(c.plants.keys) for c in warm[0]) > 0
    for a, b in zip(cold[1], warm[1], strict=True):
        np.testing.assert_array_equal(a, b)
    assert len(warm[2]) > 10
    for attr in ("center", "size", "buffer"):
        np.testing.assert_array_equal(getattr(cold[2], attr), getattr(warm[2], attr))
