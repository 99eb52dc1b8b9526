"""cpfg's colour maps (``.map``) and material files (``.mat``): the colours of ``;(n)``.

cpfg colours what it draws by the current colour index (``;`` / ``,`` step it, ``;(n)`` /
``,(n)`` set it), looked up in a colour map (``cpfg -m file.map``) or a material table
(``cpfg -M file.mat``); the cpfg manual §1.2.2, §6 and the vlab Tools manual's palette and
medit.  Both are binary:

``.map``
    768 bytes: 256 entries of ``r g b``, one byte each (0–255), entry 0 first.
``.mat``
    records of 15 bytes, one per defined index: the index, the transparency (0 opaque …
    255 clear), the ambient ``r g b``, the diffuse ``r g b``, the emissive ``r g b``, the
    specular ``r g b`` and the specular exponent (0–255).  Indices without a record keep
    OpenGL's default material (diffuse 0.8 grey, ambient 0.2).

The byte values are display (sRGB) colours; sylva's colours are linear, so they are decoded
(:func:`srgb_to_linear`).  :func:`palette_materials` makes sylva's material table: the
diffuse colour (plus the emissive one) as the base colour, the opacity ``1 − t``, and the
roughness ``√(2 / (n + 2))`` of the exponent ``n`` (Blinn–Phong to a GGX roughness).

Examples
--------
>>> import numpy as np
>>> data = np.arange(768, dtype=np.uint8).tobytes()
>>> read_colormap(data)[1].round(4).tolist()   # the bytes 3, 4, 5
[0.0009, 0.0012, 0.0015]
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .._atomic import atomic_write
from ..errors import SylvaError
from .mesh import Material

__all__ = [
    "CpfgMaterial",
    "linear_to_srgb",
    "palette_materials",
    "read_colormap",
    "read_materials",
    "srgb_to_linear",
    "write_colormap",
    "write_materials",
]

RECORD = 15


def srgb_to_linear(c) -> np.ndarray:
    """The sRGB transfer function undone: display values in [0, 1] to linear ones."""
    c = np.asarray(c, np.float64)
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


def linear_to_srgb(c) -> np.ndarray:
    """Linear values in [0, 1] to display (sRGB) ones."""
    c = np.clip(np.asarray(c, np.float64), 0.0, 1.0)
    return np.where(c <= 0.0031308, c * 12.92, 1.055 * c ** (1 / 2.4) - 0.055)


def _bytes(source, what: str) -> tuple[bytes, str]:
    if isinstance(source, (bytes, bytearray, memoryview)):
        return bytes(source), f"<{what}>"
    path = Path(os.fspath(source))
    try:
        return path.read_bytes(), str(path)
    except OSError as e:
        raise SylvaError(f"{path}: cannot read the {what} ({e.strerror or e})") from None


def read_colormap(source) -> np.ndarray:
    """``float64[256, 3]``: the linear colours of a ``.map`` file (a path, or its bytes).

    Raises
    ------
    SylvaError
        Unless the file holds 768 bytes (256 × ``r g b``), naming it.
    """
    data, name = _bytes(source, "colour map")
    if len(data) != 768:
        raise SylvaError(f"{name}: a cpfg colour map holds 768 bytes (256 colours of r g b, "
                         f"one byte each); this one holds {len(data)}")  # fmt: skip
    rgb = np.frombuffer(data, np.uint8).reshape(256, 3) / 255.0
    return srgb_to_linear(rgb)


def write_colormap(colors, path) -> Path:
    """Write linear ``colors`` (``[n <= 256, 3]``; missing entries black) as a ``.map``."""
    c = np.zeros((256, 3))
    colors = np.asarray(colors, np.float64).reshape(-1, 3)
    if colors.shape[0] > 256:
        raise SylvaError(f"a colour map holds 256 colours, got {colors.shape[0]}")
    c[: colors.shape[0]] = colors
    data = np.round(linear_to_srgb(c) * 255).astype(np.uint8).tobytes()
    path = Path(path)
    with atomic_write(path, "wb", encoding=None, newline=None) as fh:
        fh.write(data)
    return path


@dataclass(frozen=True)
class CpfgMaterial:
    """One entry of a ``.mat`` file, in display values (0–1) as the file stores them."""

    ambient: tuple[float, float, float] = (0.2, 0.2, 0.2)
    diffuse: tuple[float, float, float] = (0.8, 0.8, 0.8)
    emissive: tuple[float, float, float] = (0.0, 0.0, 0.0)
    specular: tuple[float, float, float] = (0.0, 0.0, 0.0)
    shininess: float = 0.0
    transparency: float = 0.0
    defined: bool = False


def read_materials(source) -> list[CpfgMaterial]:
    """The 256 entries of a ``.mat`` file (a path, or its bytes); indices without a record
    are ``CpfgMaterial()`` (OpenGL's default, ``defined=False``).

    Raises
    ------
    SylvaError
        When the length is not a whole number of 15-byte records, naming the file.
    """
    data, name = _bytes(source, "material file")
    if len(data) % RECORD:
        raise SylvaError(f"{name}: a cpfg material file is made of 15-byte records (index, "
                         "transparency, ambient, diffuse, emissive and specular r g b, "
                         f"exponent); {len(data)} bytes is not a whole number of them")  # fmt: skip
    out = [CpfgMaterial() for _ in range(256)]
    rec = np.frombuffer(data, np.uint8).reshape(-1, RECORD)
    for r in rec:
        v = r / 255.0
        out[int(r[0])] = CpfgMaterial(tuple(v[2:5]), tuple(v[5:8]), tuple(v[8:11]),
                                      tuple(v[11:14]), float(r[14]), float(v[1]), True)  # fmt: skip
    return out


def write_materials(materials, path) -> Path:
    """Write ``materials`` (a list of :class:`CpfgMaterial`, index = position, or a dict
    index -> material) as a ``.mat`` file: one record per defined entry."""
    items = materials.items() if isinstance(materials, dict) else enumerate(materials)
    rows = []
    for i, m in items:
        if isinstance(materials, dict) or m.defined:
            vals = [m.transparency, *m.ambient, *m.diffuse, *m.emissive, *m.specular]
            b = np.round(np.clip(vals, 0, 1) * 255).astype(np.uint8).tolist()
            rows.append(bytes([int(i), *b, int(np.clip(round(m.shininess), 0, 255))]))
    path = Path(path)
    with atomic_write(path, "wb", encoding=None, newline=None) as fh:
        fh.write(b"".join(rows))
    return path


def palette_materials(materials: list[CpfgMaterial]) -> tuple[np.ndarray, list[Material]]:
    """The palette (``float64[256, 3]``, linear) and sylva's material table
    (``color_0`` … ``color_255``) of a ``.mat`` file's entries."""
    palette = np.zeros((len(materials), 3))
    table = []
    for i, m in enumerate(materials):
        rgb = np.clip(np.add(m.diffuse, m.emissive), 0.0, 1.0)
        lin = srgb_to_linear(rgb)
        palette[i] = lin
        rough = float(np.sqrt(2.0 / (m.shininess + 2.0)))
        table.append(Material(f"color_{i}", (*map(float, lin), 1.0 - m.transparency),
                              roughness=rough))  # fmt: skip
    return palette, table
