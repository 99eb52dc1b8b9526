"""Seed 004's ``LSystemExecutor``: salted derivation, scale and random angles, then blocks.

The executor ties the randomness of one plant to a single integer, the *salt* (seed 004
§4.6, Appendix A):

1. With a derivation range (``derivation_var``, ``min_scale``, ``max_scale``), the salt picks
   ``k = limited(salt, derivation_var)`` extra derivations and the block scale grows with
   them linearly: ``scale = min_scale + k·(max_scale − min_scale)/(derivation_var − 1)``.
2. The word is derived ``derivations + k`` times (the engine's salted stochastic rewriting).
3. Before each symbol the turtle draws ``δ = (hash01(salt) − 0.5)·2·angle_var`` and each
   rotation turns by ``(±1 + δ)`` times the header angle; after each symbol
   ``salt = hash1d(salt)``.

``hash1d`` is Squirrel3 (seed 004 A.2).

Examples
--------
>>> hash1d(0), hash1d(1), round(hash01(0), 6)
(2957163356, 2179289154, 0.688518)
"""

from __future__ import annotations

from ..errors import SylvaError
from ..geometry.records import Geometry
from ..lsystem.ast import Program
from . import _kernels as K
from .interpreter import interpret

__all__ = ["generate", "hash01", "hash1d", "limited"]


def hash1d(x: int, seed: int = 0) -> int:
    """Squirrel3 noise of the integer ``x``: a ``uint32`` as a Python int."""
    return int(K.squirrel1d(int(x) & 0xFFFFFFFF, int(seed) & 0xFFFFFFFF))


def hash01(x: int, seed: int = 0) -> float:
    """:func:`hash1d` scaled to [0, 1]."""
    return hash1d(x, seed) / 4294967295.0


def limited(x: int, n: int, seed: int = 0) -> int:
    """An index in ``[0, n)`` drawn from ``x``: ``uint(hash01(x)·n)`` (at most ``n − 1``)."""
    return min(int(hash01(x, seed) * n), n - 1)


def generate(
    program: Program,
    *,
    salt: int = 0,
    derivations: int | None = None,
    min_scale: float = 1.0,
    max_scale: float | None = None,
    derivation_var: int | None = None,
    angle_var: float = 0.2,
    noise_seed: int = 0,
) -> Geometry:
    """Grow one plant of an engine-format program the way seed 004's executor does.

    Parameters
    ----------
    program : Program
        An engine-format L-system (``yaw``, ``pitch``, ``shrink`` settings).
    salt : int
        The plant's random key (seed 004 uses ``hash2D(x, z)`` of its position).
    derivations : int, optional
        Base number of derivation steps (default: the program's ``steps`` or 3).
    min_scale, max_scale : float
        Block scale range; without ``derivation_var`` the scale is ``min_scale``.
    derivation_var : int, optional
        How many derivation counts the salt may add (``ScaleDerivations``): ``k`` in
        ``[0, derivation_var − 1]``.
    angle_var : float
        Relative random angle variation (default 0.2, seed 004 §4.6).
    noise_seed : int
        Seed of the Squirrel3 noise (the engine's global ``Seed``).

    Returns
    -------
    Geometry
        Blocks split by output buffer (``block_buffer``).
    """
    try:
        from ..lsystem import derive  # the engine's public API
    except ImportError as exc:  # pragma: no cover - depends on the tree's progress
        raise SylvaError("sylva.lsystem.derive is not available in this installation") from exc
    if derivations is None:
        derivations = program.steps if program.steps is not None else 3
    scale = float(min_scale)
    if derivation_var is not None:
        if derivation_var < 1:
            raise SylvaError(f"derivation_var must be >= 1, got {derivation_var}")
        if max_scale is None:
            raise SylvaError("a derivation range needs max_scale")
        k = limited(salt, derivation_var, noise_seed)
        factor = (max_scale - min_scale) / (derivation_var - 1) if derivation_var > 1 else 0.0
        derivations += k
        scale = min_scale + k * factor
    word = derive(program, derivations, seed=salt)
    return interpret(
        word, program, dialect="engine", seed=salt, scale=scale, angle_var=angle_var,
        noise_seed=noise_seed,
    )  # fmt: skip
