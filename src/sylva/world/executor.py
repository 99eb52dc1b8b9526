"""Seed 004's ``LSystemExecutor``: salted derivation, derivation range, blocks, optimise pass.

The voxel engine's stochastic rewriting (spec §4.7) differs from sylva's own engine (which
hashes seed, step and position): one *salt* drives a chain of Squirrel3 hashes,

::

    derive(axiom, n, salt):  w = step(axiom, salt)
                             repeat n − 1 times: salt = hash1d(salt, seed); w = step(w, salt)
    step(word, salt):        i = 1
                             for c in word:
                                 no production   -> c
                                 one production  -> it
                                 n_c productions -> productions[c][floor(hash01(i, salt)·n_c)]
                                                    i += 1

so ``i`` counts only the occurrences of symbols with several productions.  :func:`derive`
implements this on :class:`~sylva.lsystem.Program` / :class:`~sylva.lsystem.ModuleString`
(vectorised over the word).  :func:`grow` is the whole executor (§4.6): the salt may add
derivations and scale the blocks with them, the engine turtle of :mod:`sylva.turtle` draws
the blocks with per-symbol angle variation ``δ = (hash01(salt) − 0.5)·2·angleVar``, and the
optional *optimise* pass removes branch blocks (buffer 0) hidden inside leaf blocks
(buffer 1).

Examples
--------
>>> from sylva.lsystem import loads
>>> p = loads("0 90 0.7\\nX\\nX > U[&X][^X]UX\\nU > UU\\n", dialect="engine")
>>> [str(derive(p, n, salt=5)) for n in range(3)]  # spec §4.7 test vector
['X', 'U[&X][^X]UX', 'UU[&U[&X][^X]UX][^U[&X][^X]UX]UUU[&X][^X]UX']
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import _jit
from ..errors import SylvaError
from ..lsystem import ModuleString, Program
from ..turtle import interpret
from .hashing import hash01, hash1d
from .terrain import K  # the world kernels' road

__all__ = ["PlantBlocks", "derive", "grow", "scale_derivations", "step"]

#: Pairs of blocks up to which the containment test of a cold cache runs its Python source
#: (about a microsecond a pair, against a second of compiling).
SMALL_PAIRS = 1 << 16


class _Table:
    """Productions of a program as flat id arrays: option ``o`` of symbol ``s`` writes
    ``succ[off[o]:off[o+1]]``; symbol ``s`` has options ``first[s] .. first[s]+count[s]``."""

    def __init__(self, program: Program, word: ModuleString) -> None:
        alphabet = word.alphabet
        rules: dict[int, list[np.ndarray]] = {}
        for r in program.productions:
            if r.has_context or r.condition is not None or r.predecessor.params:
                raise SylvaError(
                    "seed 004's executor rewrites context-free, parameter-free rules only; "
                    f"got {r!r}"
                )
            if any(m.args for m in r.successor):
                raise SylvaError(f"seed 004's executor has no parameters; got {r!r}")
            sid = alphabet.id(r.predecessor.symbol)
            ids = np.array([alphabet.id(m.symbol) for m in r.successor], np.int64)
            rules.setdefault(sid, []).append(ids)
        n_sym = len(alphabet)
        self.count = np.zeros(n_sym, np.int64)
        self.first = np.zeros(n_sym, np.int64)
        succ: list[np.ndarray] = []
        for s in range(n_sym):
            self.first[s] = len(succ)
            options = rules.get(s)
            if options is None:
                succ.append(np.array([s], np.int64))  # identity a -> a
                self.count[s] = 1
            else:
                succ.extend(options)
                self.count[s] = len(options)
        lengths = np.array([len(x) for x in succ], np.int64)
        self.off = np.zeros(len(succ) + 1, np.int64)
        np.cumsum(lengths, out=self.off[1:])
        self.succ = np.concatenate(succ) if succ else np.zeros(0, np.int64)
        self.alphabet = alphabet


def _step_ids(ids: np.ndarray, table: _Table, salt: int) -> np.ndarray:
    n_c = table.count[ids]
    choice = np.zeros(ids.shape[0], np.int64)
    multi = n_c > 1
    if multi.any():
        i = np.arange(1, int(multi.sum()) + 1, dtype=np.int64)
        r = hash01(hash1d(i, salt))
        choice[multi] = np.minimum(np.floor(r * n_c[multi]).astype(np.int64), n_c[multi] - 1)
    opt = table.first[ids] + choice
    start = table.off[opt]
    length = table.off[opt + 1] - start
    total = int(length.sum())
    if total == 0:
        return np.zeros(0, np.int64)
    # gather: position j of the output reads succ[start[k] + (j - out_off[k])]
    out_off = np.cumsum(length) - length
    owner = np.repeat(np.arange(ids.shape[0]), length)
    idx = start[owner] + (np.arange(total) - out_off[owner])
    return table.succ[idx]


def _word(program: Program, word) -> ModuleString:
    if word is None:
        return ModuleString.from_modules([m.symbol for m in program.axiom])
    if isinstance(word, str):
        return ModuleString.from_modules(list(word))
    return word


def step(program: Program, word: ModuleString | str | None, salt: int) -> ModuleString:
    """One salted rewriting step of ``word`` (default: the axiom).

    Parameters
    ----------
    program : Program
        Context-free, parameter-free rules (the engine format); several rules for one
        symbol choose uniformly.
    word : ModuleString or str or None
    salt : int

    Returns
    -------
    ModuleString
    """
    w = _word(program, word)
    table = _Table(program, w)
    ids = _step_ids(w.ids.astype(np.int64), table, salt)
    return ModuleString(table.alphabet, ids.astype(w.ids.dtype))


def derive(
    program: Program, n: int, salt: int = 0, *, seed: int = 0, limit: int = 5_000_000
) -> ModuleString:
    """Derive the axiom ``n`` times with the salt chain of seed 004 (spec §4.7).

    Parameters
    ----------
    program : Program
    n : int
        Derivation steps (``n ≤ 0`` returns the axiom).
    salt : int
        The plant's salt.
    seed : int
        The grammar seed of the salt chain (``hash1d(salt, seed)`` between steps).
    limit : int
        Largest word allowed, in modules.

    Returns
    -------
    ModuleString

    Raises
    ------
    SylvaError
        When the word would exceed ``limit`` modules.
    """
    w = _word(program, None)
    table = _Table(program, w)
    ids = w.ids.astype(np.int64)
    for k in range(max(int(n), 0)):
        if k:
            salt = hash1d(salt, seed)
        ids = _step_ids(ids, table, salt)
        if ids.shape[0] > limit:
            raise SylvaError(
                f"the word grew past {limit} modules after {k + 1} derivations; "
                "expected fewer derivations"
            )
    return ModuleString(table.alphabet, ids.astype(w.ids.dtype))


def scale_derivations(salt: int, derivation_var: int, min_scale: float, max_scale: float,
                      seed: int = 0) -> tuple[int, float]:  # fmt: skip
    """Seed 004's ``ScaleDerivations``: extra derivations ``k`` and the block scale.

    ``k = limited(salt, derivation_var)`` in ``[0, derivation_var − 1]`` and ``scale =
    min_scale + k·(max_scale − min_scale)/(derivation_var − 1)``: size grows linearly with
    the number of derivations.

    Examples
    --------
    >>> k, s = scale_derivations(7, 3, 0.7, 1.0)
    >>> k in (0, 1, 2) and abs(s - (0.7 + 0.15 * k)) < 1e-12
    True
    """
    if derivation_var < 1:
        raise SylvaError(f"derivation_var must be >= 1, got {derivation_var}")
    k = min(int(hash01(hash1d(salt, seed)) * derivation_var), derivation_var - 1)
    factor = (max_scale - min_scale) / (derivation_var - 1) if derivation_var > 1 else 0.0
    return k, float(min_scale + k * factor)


@dataclass(frozen=True)
class PlantBlocks:
    """The blocks of one plant, in plant coordinates (the first block's base at y = 0).

    Attributes
    ----------
    center : float32[n, 3]
    size : float32[n]
        Edge length of each axis-aligned cube.
    buffer : int32[n]
        Output buffer (0 trunk and branches, 1 leaves …).
    derivations : int
    scale : float
    """

    center: np.ndarray
    size: np.ndarray
    buffer: np.ndarray
    derivations: int
    scale: float

    def __len__(self) -> int:
        return int(self.size.shape[0])

    def bounds(self) -> np.ndarray:
        """float32[2, 3]: the lower and upper corner of all blocks."""
        if len(self) == 0:
            return np.zeros((2, 3), np.float32)
        h = self.size[:, None] / 2
        return np.stack([(self.center - h).min(0), (self.center + h).max(0)]).astype(np.float32)


def _dedupe(center, size, buffer):
    key = np.round(np.concatenate([center, size[:, None], buffer[:, None]], 1) * 1024.0)
    _, first = np.unique(key, axis=0, return_index=True)
    first.sort()
    return center[first], size[first], buffer[first]


def grow(
    program: Program,
    salt: int,
    *,
    derivations: int,
    min_scale: float = 1.0,
    max_scale: float | None = None,
    derivation_var: int | None = None,
    angle_var: float = 0.2,
    optimize: bool = False,
    seed: int = 0,
) -> PlantBlocks:
    """Grow one plant the way seed 004's ``GenerateBasedOn`` does.

    Parameters
    ----------
    program : Program
        An engine-format L-system (``yaw``, ``pitch``, ``shrink`` settings).
    salt : int
        The plant's key (``hash2D(x, z)`` of its position, or a cache entry's salt).
    derivations : int
        Base derivation count.
    min_scale, max_scale : float
        Block scale; with ``derivation_var`` it grows linearly with the extra derivations.
    derivation_var : int, optional
        How many derivation counts the salt chooses from (``ScaleDerivations``).
    angle_var : float
        Relative random variation of every rotation (0.2 in seed 004).
    optimize : bool
        Remove buffer-0 blocks lying entirely inside a buffer-1 block.
    seed : int
        The engine's global seed of the hash chains.

    Returns
    -------
    PlantBlocks
        Identical blocks are merged; coordinates are shifted so that the first block
        rests on y = 0.
    """
    scale = float(min_scale)
    n = int(derivations)
    if derivation_var is not None:
        if max_scale is None:
            raise SylvaError("a derivation range needs max_scale")
        k, scale = scale_derivations(salt, derivation_var, min_scale, max_scale, seed)
        n += k
    word = derive(program, n, salt, seed=seed)
    geo = interpret(word, program, dialect="engine", seed=int(salt) & 0xFFFFFFFF, scale=scale,
                    angle_var=angle_var, noise_seed=int(seed) & 0xFFFFFFFF)  # fmt: skip
    center = geo.block_center.astype(np.float64)
    size = geo.block_size.astype(np.float64)
    buffer = geo.block_buffer.astype(np.int32)
    if center.shape[0]:
        center, size, buffer = _dedupe(center, size, buffer)
    if optimize and center.shape[0] and (buffer == 1).any():
        b0 = np.flatnonzero(buffer == 0)
        b1 = buffer == 1
        with _jit.small(b0.shape[0] * int(b1.sum()) <= SMALL_PAIRS):
            hidden = K.contained(center[b0], size[b0], center[b1], size[b1], 1e-6)
        keep = np.ones(center.shape[0], np.bool_)
        keep[b0[hidden]] = False
        center, size, buffer = center[keep], size[keep], buffer[keep]
    if center.shape[0]:  # the first block rests on y = 0
        center = center - np.array([0.0, center[0, 1] - size[0] / 2.0, 0.0])
    return PlantBlocks(center.astype(np.float32), size.astype(np.float32), buffer, n, scale)
