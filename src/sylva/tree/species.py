"""Species presets: configuration files shipped in ``sylva/tree/species/*.txt``.

Each file is a tree configuration in the block format read by
:class:`~sylva.tree.parameters.ParameterManager` (``[global]`` and ``[level N]`` blocks);
its ``Name``, ``Source`` and ``Description`` text parameters say what it is and where its
numbers come from.

Examples
--------
>>> "quaking_aspen" in species_names()
True
>>> load_species("quaking_aspen", seed=1).text("Name")
'quaking aspen'
"""

from __future__ import annotations

import os
from importlib import resources
from pathlib import Path

from ..errors import SylvaError
from .parameters import ParameterManager

__all__ = ["SpeciesError", "load_species", "species_info", "species_names", "species_text"]


class SpeciesError(SylvaError, ValueError):
    """An unknown species name or a missing configuration file."""


def _folder():
    return resources.files(__package__).joinpath("species")


def species_names() -> list[str]:
    """The shipped species, sorted (file names without ``.txt``)."""
    return sorted(p.name[:-4] for p in _folder().iterdir() if p.name.endswith(".txt"))


def species_text(name: str) -> tuple[str, str]:
    """``(text, filename)`` of a species name or a configuration file path."""
    key = name.strip().lower().replace(" ", "_").replace("-", "_")
    if key in species_names():
        return _folder().joinpath(key + ".txt").read_text("utf-8"), f"{key}.txt"
    path = Path(os.path.expanduser(name))
    if path.is_file():
        return path.read_text(encoding="utf-8"), str(path)
    raise SpeciesError(
        f"unknown species or configuration file {name!r}: expected one of "
        + ", ".join(species_names()) + " or a path to a .txt configuration"
    )


def load_species(name: str, seed: int = 0) -> ParameterManager:
    """The :class:`ParameterManager` of a species name or a configuration file."""
    text, filename = species_text(name)
    return ParameterManager.from_text(text, seed=seed, filename=filename)


def species_info(name: str) -> dict[str, str]:
    """``Name``, ``Source`` and ``Description`` of a species (empty strings when absent)."""
    pm = load_species(name)
    return {k: pm.text(k, default="") for k in ("Name", "Source", "Description")}
