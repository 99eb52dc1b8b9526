"""Light sources for the Phong model of seed 004 §3.4–3.6.

Two kinds: a :class:`Sun` (directional, "global" light: parallel rays, no fall-off, optionally
casting shadows) and :class:`PointLight` (fall-off ``1 / (Kc + Kl d + Kq d²)`` with the Ogre3D
range-100 constants ``Kc = 1, Kl = 0.045, Kq = 0.0075``).  Each light has an ambient, a diffuse
and a specular intensity (RGB); a point light's three terms are all multiplied by its
attenuation, and the sun's diffuse and specular terms by its shadow factor.

Examples
--------
>>> round(attenuation(10.0), 4)
0.4545
>>> attenuation(0.0)
1.0
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["ATTENUATION", "MAX_POINT_LIGHTS", "PointLight", "Sun", "attenuation", "default_lights"]

#: (constant, linear, quadratic) fall-off coefficients: seed 004 §3.6, a range of about 100.
ATTENUATION = (1.0, 0.045, 0.0075)
#: Point lights the shader takes at once.
MAX_POINT_LIGHTS = 8


def attenuation(distance, coefficients=ATTENUATION):
    """Point-light fall-off ``1 / (Kc + Kl d + Kq d²)``.

    Parameters
    ----------
    distance : float or ndarray
        Distance from the lit point to the light (≥ 0).
    coefficients : tuple of 3 float
        ``(Kc, Kl, Kq)``.

    Returns
    -------
    float or ndarray
        In ``(0, 1]`` when ``Kc = 1``.
    """
    kc, kl, kq = coefficients
    d = np.asarray(distance, dtype=np.float64)
    out = 1.0 / (kc + kl * d + kq * d * d)
    return float(out) if out.ndim == 0 else out


def _rgb(value, name: str) -> np.ndarray:
    a = np.asarray(value, dtype=np.float64)
    if a.ndim == 0:
        a = np.repeat(a, 3)
    if a.shape != (3,) or not np.all(np.isfinite(a)) or np.any(a < 0):
        raise ValueError(f"{name} must be a non-negative number or RGB triple, got {value!r}")
    return a


@dataclass
class Sun:
    """A directional light.

    Parameters
    ----------
    direction : array_like of 3 float
        Where the rays travel (from the light), as in seed 004 (the shader negates it).
    color : float or RGB
        Diffuse intensity.
    ambient : float or RGB
        Ambient intensity (the sun also carries the sky's ambient term).
    specular : float or RGB
        Specular intensity.
    shadows : bool
        Whether it casts shadows (shadow mapping).
    """

    direction: tuple[float, float, float] = (-0.45, -1.0, -0.35)
    color: object = 0.85
    ambient: object = 0.25
    specular: object = 0.5
    shadows: bool = True

    def __post_init__(self) -> None:
        d = np.asarray(self.direction, dtype=np.float64).reshape(3)
        n = float(np.linalg.norm(d))
        if not n > 0:
            raise ValueError("the sun's direction must not be the zero vector")
        self.direction = d / n
        self.color = _rgb(self.color, "color")
        self.ambient = _rgb(self.ambient, "ambient")
        self.specular = _rgb(self.specular, "specular")


@dataclass
class PointLight:
    """A point light with attenuation.

    Parameters
    ----------
    position : array_like of 3 float
    color, ambient, specular : float or RGB
        Intensities before attenuation.
    attenuation : tuple of 3 float
        ``(Kc, Kl, Kq)``; the default is :data:`ATTENUATION`.
    """

    position: tuple[float, float, float] = (0.0, 10.0, 0.0)
    color: object = 1.0
    ambient: object = 0.0
    specular: object = 0.5
    attenuation: tuple[float, float, float] = ATTENUATION

    def __post_init__(self) -> None:
        self.position = np.asarray(self.position, dtype=np.float64).reshape(3)
        self.color = _rgb(self.color, "color")
        self.ambient = _rgb(self.ambient, "ambient")
        self.specular = _rgb(self.specular, "specular")
        att = tuple(float(c) for c in self.attenuation)
        if len(att) != 3 or min(att) < 0 or att[0] + att[1] + att[2] <= 0:
            raise ValueError(f"attenuation must be 3 non-negative numbers, got {self.attenuation}")
        self.attenuation = att


def default_lights() -> list:
    """The lights used when none are given: one shadow-casting sun from the upper left front."""
    return [Sun()]
