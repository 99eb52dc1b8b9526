"""ABOP's cut ``%``: the modules a cut removes (the rest of its branch), after a step."""

from __future__ import annotations

import numpy as np

from .._jit import road
from .lstring import SMALL_WORD, ModuleString

__all__ = ["_apply_cut", "_cut_keep"]

_kernels = road("sylva.lsystem._kernels", size=SMALL_WORD)  # the engine's road


def _cut_keep(word: ModuleString) -> np.ndarray | None:
    """The keep-mask of ABOP's cut for ``word``, or None when nothing is cut."""
    cut_id = word.alphabet.get("%")
    if cut_id < 0 or not (word.ids == cut_id).any():
        return None
    return _kernels.cut_mask(word.ids, cut_id)


def _apply_cut(word: ModuleString, cut_id: int, keep: np.ndarray | None = None) -> ModuleString:
    if keep is None:
        if cut_id < 0 or not (word.ids == cut_id).any():
            return word
        keep = _kernels.cut_mask(word.ids, cut_id)
    if not word.has_params:
        return ModuleString(word.alphabet, word.ids[keep])
    counts = np.diff(word.offsets)
    vals = word.values[np.repeat(keep, counts)]
    kept = counts[keep]
    off = np.zeros(kept.shape[0] + 1, np.int64)
    np.cumsum(kept, out=off[1:])
    return ModuleString(word.alphabet, word.ids[keep], off, vals)
