"""Procedural textures: noise, cellular, patterns, fractals and L-system textures.

NumPy arrays in and out (float32 by default, float64 on request); numba kernels live in
private ``_*.py`` modules behind this documented API.

* :mod:`~sylva.texture.noise` — value, classic/improved Perlin, simplex and Worley noise
  in 2D, 3D and 4D; fBm, turbulence, ridged multifractal, domain warping; seamless and
  animated grids (:func:`noise_grid`).
* :mod:`~sylva.texture.patterns` — marble, wood, clouds, granite, bark, leaf, grass.
* :mod:`~sylva.texture.fractals` — Mandelbrot, Julia, Burning Ship, barnsleyj1, IFS.
* :mod:`~sylva.texture.lsystem_texture` — a small 2D L-system and turtle rasteriser.
* :mod:`~sylva.texture.colormap` — colour maps, gradients, normal maps.
* :mod:`~sylva.texture.presets` — recipes, named presets, TOML preset files.

Every random function takes ``seed``; ``seed=None`` selects Perlin's reference
permutation (see :mod:`sylva.texture.noise`).
"""

from __future__ import annotations

from .colormap import (
    COLORMAPS,
    Colormap,
    ColormapError,
    apply_colormap,
    get_colormap,
    gradient,
    normal_map,
    normalize,
    to_uint8,
)
from .fractals import (
    BARNSLEY_FERN,
    SIERPINSKI,
    FractalError,
    Ifs,
    barnsley_j1,
    burning_ship,
    colorize,
    ifs,
    in_mandelbrot,
    julia,
    mandelbrot,
)
from .lsystem_texture import (
    LSYSTEM_EXAMPLES,
    LSystemTextureError,
    Segments,
    draw_segments,
    lsystem_texture,
    rewrite,
    turtle,
)
from .noise import (
    FRACTALS,
    INTERPOLATIONS,
    KINDS,
    METRICS,
    REFERENCE_PERMUTATION,
    WORLEY_OUTPUTS,
    NoiseError,
    NoiseTables,
    domain_warp,
    fbm,
    improved_perlin,
    noise_grid,
    noise_tables,
    perlin,
    ridged,
    simplex,
    turbulence,
    value_noise,
    worley,
    worley_features,
)
from .patterns import bark, clouds, granite, grass, leaf, marble, wood
from .presets import (
    PRESETS,
    TEXTURE_KINDS,
    PresetError,
    load_preset,
    render,
    render_frames,
    save_preset,
)

__all__ = [
    "BARNSLEY_FERN",
    "COLORMAPS",
    "Colormap",
    "ColormapError",
    "FRACTALS",
    "FractalError",
    "INTERPOLATIONS",
    "Ifs",
    "KINDS",
    "LSYSTEM_EXAMPLES",
    "LSystemTextureError",
    "METRICS",
    "NoiseError",
    "NoiseTables",
    "PRESETS",
    "PresetError",
    "REFERENCE_PERMUTATION",
    "SIERPINSKI",
    "Segments",
    "TEXTURE_KINDS",
    "WORLEY_OUTPUTS",
    "apply_colormap",
    "bark",
    "barnsley_j1",
    "burning_ship",
    "clouds",
    "colorize",
    "domain_warp",
    "draw_segments",
    "fbm",
    "get_colormap",
    "gradient",
    "granite",
    "grass",
    "ifs",
    "improved_perlin",
    "in_mandelbrot",
    "julia",
    "leaf",
    "load_preset",
    "lsystem_texture",
    "mandelbrot",
    "marble",
    "noise_grid",
    "noise_tables",
    "normal_map",
    "normalize",
    "perlin",
    "render",
    "render_frames",
    "rewrite",
    "ridged",
    "save_preset",
    "simplex",
    "to_uint8",
    "turbulence",
    "turtle",
    "value_noise",
    "wood",
    "worley",
    "worley_features",
]
