"""Natural patterns built from noise: marble, wood, clouds, granite (seed 003), and the bark,
leaf and grass textures of seed 000 §2.5–2.6.

Every pattern returns a float array in [0, 1] of the requested shape (float32 unless
``dtype=np.float64``); colour it with :func:`sylva.texture.apply_colormap` (each pattern has
a matching named colour map).  ``scale`` is the number of base noise cells across the
width, ``tileable=True`` makes the image wrap seamlessly, and ``time`` animates the noise.
"""

from __future__ import annotations

import numpy as np

from .noise import NoiseError, noise_grid

__all__ = ["bark", "clouds", "granite", "grass", "leaf", "marble", "wood"]


def _shape2(shape):
    shape = tuple(int(s) for s in shape)
    if len(shape) != 2 or min(shape) < 1:
        raise NoiseError(f"this pattern needs a 2D shape (H, W), got {shape}")
    return shape


def _out(v, dtype):
    dt = np.dtype(np.float32 if dtype is None else dtype)
    return np.clip(v, 0.0, 1.0).astype(dt, copy=False)


def _xcoord(shape, tileable):
    """x in [0, 1) across the width, broadcastable to ``shape``."""
    w = shape[-1]
    x = np.arange(w, dtype=np.float64) / w if tileable else np.linspace(0.0, 1.0, w)
    return x.reshape((1,) * (len(shape) - 1) + (w,))


def marble(shape, *, scale=4.0, stripes=4.0, turbulence=2.0, octaves=6, persistence=0.5,
           lacunarity=2.0, seed=None, tileable=False, time=None, dtype=None):
    """Marble veins: ``0.5 + 0.5 sin(2 pi (stripes * x + turbulence * T(p)))``.

    ``T`` is Perlin's turbulence (sum of ``|improved noise|``, normalised to [0, 1]); with
    ``turbulence=0`` the result is pure stripes (seed 003 §4.3, fig. 17).  ``stripes``
    counts stripe periods across the width (rounded to a whole number when tileable).

    Parameters
    ----------
    shape : (H, W) or (D, H, W)
    scale, octaves, persistence, lacunarity, seed, tileable, time :
        Passed to :func:`~sylva.texture.noise_grid`.

    Returns
    -------
    ndarray, shape ``shape``, values in [0, 1]

    Examples
    --------
    >>> m = marble((32, 32), turbulence=0.0)
    >>> bool(np.allclose(m[0], m[-1]))  # no turbulence: vertical stripes
    True
    """
    t = noise_grid(shape, kind="improved", fractal="turbulence", scale=scale, octaves=octaves,
                   persistence=persistence, lacunarity=lacunarity, seed=seed,
                   tileable=tileable, time=time, dtype=np.float64)
    k = round(stripes) if tileable else stripes
    phase = k * _xcoord(shape, tileable) + turbulence * t
    return _out(0.5 + 0.5 * np.sin(2.0 * np.pi * phase), dtype)


def wood(shape, *, scale=2.0, rings=10.0, turbulence=0.15, center=(0.5, 0.5), grain=0.15,
         octaves=4, persistence=0.5, lacunarity=2.0, seed=None, tileable=False, time=None,
         dtype=None):
    """Wood rings: ``frac(rings * r + turbulence * T(p))`` around ``center``, plus grain.

    ``r`` is the distance to ``center`` (fractions of the width/height), ``T`` turbulence as
    in :func:`marble`; ``grain`` mixes in fine noise stretched along y (fibres).

    Tileable wood is a board's face rather than its end: concentric rings cannot repeat
    without a fold (the old toroidal distance creased and mirrored them at the joins), so
    the ring phase is ``k (x - center[0] + 0.3 B(p))`` with ``k = round(rings)`` whole rings
    across the width and ``B`` a smooth periodic noise (one cell across) that bends them
    into the figure of a flat-sawn plank; with the periodic turbulence and grain the tile
    repeats seamlessly in both axes (``center[1]`` is then unused).

    Examples
    --------
    >>> w = wood((48, 48), seed=1)
    >>> w.shape, float(w.min()) >= 0.0, float(w.max()) <= 1.0
    ((48, 48), True, True)
    """
    shape = _shape2(shape)
    h, w_ = shape
    t = noise_grid(shape, kind="improved", fractal="turbulence", scale=scale, octaves=octaves,
                   persistence=persistence, lacunarity=lacunarity, seed=seed,
                   tileable=tileable, time=time, dtype=np.float64)
    y = (np.arange(h, dtype=np.float64) / h)[:, None]
    x = (np.arange(w_, dtype=np.float64) / w_)[None, :]
    if tileable:
        # a board's face, not its end: the rings run along y as the lines of a phase that
        # grows by a whole number of rings across the width, bent by a periodic noise (the
        # figure of a flat-sawn plank); no centre, so nothing folds or repeats at the joins
        k = max(1, round(rings))
        bend = noise_grid(shape, kind="improved", scale=(1.0, max(1.0, round(h / w_))),
                          octaves=3, seed=None if seed is None else seed + 2, tileable=True,
                          time=time, dtype=np.float64)
        phase = k * (x - center[0] + 0.3 * bend)
    else:
        dx = x - center[0]
        dy = (y - center[1]) * h / w_
        phase = rings * np.sqrt(dx * dx + dy * dy)
    ring = np.mod(phase + turbulence * t, 1.0)
    ring = ring * ring * (3.0 - 2.0 * ring)
    fib = noise_grid(shape, kind="improved", scale=(scale * 16.0, scale * 16.0 * h / w_ / 12.0),
                     octaves=2, seed=None if seed is None else seed + 1, tileable=tileable,
                     time=time, dtype=np.float64)
    return _out((1.0 - grain) * ring + grain * (0.5 + fib), dtype)


def clouds(shape, *, scale=3.0, coverage=0.6, sharpness=1.0, octaves=8, persistence=0.5,
           lacunarity=2.0, seed=None, tileable=False, time=None, dtype=None):
    """Clouds: simplex fBm, thresholded by ``coverage`` (0: clear sky, 1: overcast look).

    ``v = clip((0.5 + 0.75 fbm - (1 - coverage)) / coverage, 0, 1) ** sharpness``.

    Examples
    --------
    >>> c = clouds((32, 64), seed=2, tileable=True)
    >>> c.dtype.name, c.shape
    ('float32', (32, 64))
    """
    if not 0.0 < coverage <= 1.0:
        raise NoiseError(f"coverage must lie in (0, 1], got {coverage}")
    f = noise_grid(shape, kind="simplex", scale=scale, octaves=octaves,
                   persistence=persistence, lacunarity=lacunarity, seed=seed,
                   tileable=tileable, time=time, dtype=np.float64)
    v = np.clip(0.5 + 0.75 * f, 0.0, 1.0)
    v = np.clip((v - (1.0 - coverage)) / coverage, 0.0, 1.0)
    return _out(v**sharpness, dtype)


def granite(shape, *, scale=24.0, octaves=4, seed=None, tileable=False, time=None,
            dtype=None):
    """Granite: a mosaic of flat-coloured crystals (Worley cell ids), dark grain
    boundaries (F2 - F1) and fine speckle (turbulence).

    Examples
    --------
    >>> g = granite((32, 32), seed=4)
    >>> 0.0 <= float(g.mean()) <= 1.0
    True
    """
    s2 = None if seed is None else seed + 2
    cell = noise_grid(shape, kind="worley", output="cell", scale=scale, seed=seed,
                      tileable=tileable, time=time, dtype=np.float64)
    edge = noise_grid(shape, kind="worley", output="f2-f1", scale=scale, seed=seed,
                      tileable=tileable, time=time, dtype=np.float64)
    speck = noise_grid(shape, kind="improved", fractal="turbulence", scale=scale * 2.0,
                       octaves=octaves, seed=s2, tileable=tileable, time=time,
                       dtype=np.float64)
    crystals = cell**1.5
    border = np.clip(edge / 0.08, 0.0, 1.0)
    v = (0.15 + 0.6 * crystals + 0.25 * (1.0 - speck)) * (0.55 + 0.45 * border)
    return _out(v, dtype)


def bark(shape, *, scale=6.0, stretch=0.05, cracks=0.18, detail=0.45, octaves=4,
         persistence=0.5, lacunarity=2.0, seed=None, tileable=False, time=None, dtype=None):
    """Bark with cracks along the branch (seed 000 §2.6); the branch runs along y.

    Step 1 makes stripes along the branch with noise whose y component is (almost) zero
    (``stretch=0`` is exactly the seed's "3D noise with y = 0"; a small ``stretch`` lets the
    cracks wander).  Step 2 modulates a second, isotropic noise with the stripes: where
    the stripe noise is near 0 (``|s| < cracks``) the bark is dark, elsewhere it is the
    detail noise.  ``time`` (or the third axis) selects the slice of the 3D detail noise.

    Examples
    --------
    >>> b = bark((64, 32), seed=5, stretch=0.0)
    >>> bool(np.all(b >= 0) and np.all(b <= 1))
    True
    """
    shape = _shape2(shape)
    h, w = shape
    sx = scale
    sy = max(scale * stretch, 1e-9) * h / w
    if stretch == 0 and not tileable:
        row = noise_grid((1, w), kind="improved", scale=(sx, 1e-9), octaves=octaves,
                         persistence=persistence, lacunarity=lacunarity, seed=seed,
                         dtype=np.float64)
        s = np.broadcast_to(row, shape)
    else:
        if tileable:
            sy = max(1.0, round(sy))
        s = noise_grid(shape, kind="improved", scale=(sx, sy), octaves=octaves,
                       persistence=persistence, lacunarity=lacunarity, seed=seed,
                       tileable=tileable, time=time, dtype=np.float64)
    d = noise_grid(shape, kind="improved", scale=scale * 2.0, octaves=octaves,
                   persistence=persistence, lacunarity=lacunarity,
                   seed=None if seed is None else seed + 1, tileable=tileable,
                   time=0.0 if time is None else time, dtype=np.float64)
    a = np.clip(np.abs(s) / max(cracks, 1e-9), 0.0, 1.0)
    crack = a * a * (3.0 - 2.0 * a)
    v = crack * ((1.0 - detail) + detail * (0.5 + d))
    return _out(v, dtype)


def leaf(shape, *, veins=9, vein_angle=0.6, vein_width=40.0, midrib=0.035, darkening=0.35,
         outline=True, noise=0.0, seed=None, dtype=None):
    """A leaf blade (seed 000 §2.5): brightest along the main vein, sine-shaped secondary
    veins, darker towards the edges.  The leaf's base is at the bottom row.

    Parameters
    ----------
    veins : float
        Secondary veins along the blade.
    vein_angle : float
        Slope of the secondary veins (how far they climb per unit of half-width).
    vein_width : float
        Exponent of the vein profile ``max(0, cos)**vein_width`` (larger: thinner).
    midrib : float
        Half-width of the main vein, as a fraction of the half-width.
    darkening : float
        Darkening at the edges, ``1 - darkening * u**2``.
    outline : bool
        Zero outside a pointed elliptical blade outline.
    noise : float
        Amount of added fBm (0, the default, is the seed's noise-free texture).
    seed : int, optional

    Examples
    --------
    >>> lf = leaf((64, 32))
    >>> float(lf[32, 16]) > float(lf[32, 4])  # the midrib is brighter than the blade
    True
    """
    shape = _shape2(shape)
    h, w = shape
    u = np.linspace(-1.0, 1.0, w)[None, :]
    v = np.linspace(1.0, 0.0, h)[:, None]
    au = np.abs(u)
    main = np.exp(-((u / midrib) ** 2))
    phase = veins * (v - vein_angle * au / max(veins, 1e-9) * 3.0)
    sec = np.maximum(0.0, np.cos(2.0 * np.pi * phase)) ** vein_width * (1.0 - 0.6 * au)
    shade = 1.0 - darkening * u * u
    val = 0.5 * shade + 0.45 * main + 0.25 * sec
    if noise:
        val = val + noise * noise_grid(shape, kind="simplex", scale=4.0, octaves=4, seed=seed,
                                       dtype=np.float64)
    if outline:
        half = np.sin(np.pi * np.clip(v, 0.0, 1.0)) ** 0.8 * (1.0 - 0.25 * v)
        val = np.where(au <= half, val, 0.0)
    return _out(val, dtype)


def grass(shape, *, scale=4.0, blade_stretch=1.0, patches=0.3, octaves=1, seed=None,
          tileable=False, time=None, dtype=None):
    """Grass seen from above (seed 000 §2.6), the recipe of the renderer's grass shader
    (``sylva_grass`` in ``render/shaders/textures.glsl``): two 2D Perlin noises, the second
    at a shifted position and 5.1 / 1.3 times the frequency (so no mirror "cross" appears),
    plus fine blade noise at 40 / 1.3 times it::

        v = 0.5 + 1.35 (0.3 a + 0.18 b + 0.1 blades)      (0.3: ``patches``)

    ``scale`` is the shader's: the width spans ``scale`` units of its ground plane, so the
    patch noise ``a`` has ``1.3 scale`` cells across the width, ``b`` ``5.1 scale`` and the
    blades ``40 scale`` (and ``43 scale / blade_stretch`` per width along y:
    ``blade_stretch > 1`` draws longer blades); ``octaves`` are the blade noise's octaves.
    The weights keep ``v`` inside [0, 1] (all but a few pixels in a million) and no noise
    is stretched across the image, so the texture is as even as the shader's: no long dark
    streaks.

    Examples
    --------
    >>> g = grass((32, 32), seed=3, tileable=True)
    >>> g.shape, g.dtype.name
    ((32, 32), 'float32')
    """
    shape = _shape2(shape)
    h, w = shape

    def layer(fx, fy, k, offset, oct_=1):
        sx, sy = fx * scale, fy * scale * h / w
        if tileable:
            sx, sy = max(1.0, round(sx)), max(1.0, round(sy))
        return noise_grid(shape, kind="improved", scale=(sx, sy), octaves=oct_,
                          seed=None if seed is None else seed + k, tileable=tileable,
                          time=time, offset=offset, dtype=np.float64)

    a = layer(1.3, 1.3, 2, (0.0, 0.0, 0.37, 0.0))
    b = layer(5.1, 5.1, 1, (17.31, 41.73, 0.37, 0.0))
    blades = layer(40.0, 43.0 / blade_stretch, 0, (3.1, 7.9, 0.61, 0.0), octaves)
    v = 0.5 + 1.35 * (patches * a + 0.18 * b + 0.1 * blades)
    return _out(v, dtype)
