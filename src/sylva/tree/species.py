"""Species: the presets shipped in ``sylva/tree/species/*.txt`` and the user's own.

Each file is a tree configuration in the block format read by
:class:`~sylva.tree.parameters.ParameterManager` (``[global]`` and ``[level N]`` blocks);
its ``Name``, ``Source`` and ``Description`` text parameters say what it is and where its
numbers come from.  Every file is checked before it is grown
(:func:`~sylva.tree._schema.check_species`): an unknown key, a value out of its range or a
missing level is a :class:`~sylva.errors.SylvaError` with the file, line and column.

User species are the ``*.txt`` files in the folders of ``SYLVA_SPECIES_PATH`` (separated by
``os.pathsep``), else in ``~/.config/sylva/species`` (``$XDG_CONFIG_HOME/sylva/species``).
A user file named like a shipped species replaces it.  ``sylva tree --example`` prints the
annotated example (every key, its range and meaning), :func:`example_text`.

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
from ._schema import check_species
from .parameters import ParameterManager

__all__ = ["SpeciesError", "example_text", "load_species", "shipped_species", "species_info",
           "species_names", "species_text", "user_species", "user_species_dirs"]


class SpeciesError(SylvaError, ValueError):
    """An unknown species name or a missing configuration file."""


def _folder():
    return resources.files(__package__).joinpath("species")


def _key(name: str) -> str:
    return name.strip().lower().replace(" ", "_").replace("-", "_")


def shipped_species() -> list[str]:
    """The species shipped with sylva, sorted."""
    return sorted(p.name[:-4] for p in _folder().iterdir() if p.name.endswith(".txt"))


def user_species_dirs() -> list[Path]:
    """The folders searched for user species (see the module docstring)."""
    env = os.environ.get("SYLVA_SPECIES_PATH")
    if env:
        return [Path(os.path.expanduser(p)) for p in env.split(os.pathsep) if p]
    base = os.environ.get("XDG_CONFIG_HOME") or os.path.join(os.path.expanduser("~"), ".config")
    return [Path(base) / "sylva" / "species"]


def user_species() -> dict[str, Path]:
    """``{name: path}`` of the user's species files (earlier folders win)."""
    out: dict[str, Path] = {}
    for d in user_species_dirs():
        if d.is_dir():
            for p in sorted(d.glob("*.txt")):
                out.setdefault(_key(p.stem), p)
    return out


def species_names() -> list[str]:
    """Shipped and user species, sorted (file names without ``.txt``)."""
    return sorted(set(shipped_species()) | set(user_species()))


def species_text(name: str) -> tuple[str, str]:
    """``(text, filename)`` of a species name or a configuration file path."""
    key = _key(name)
    users = user_species()
    if key in users:
        return users[key].read_text(encoding="utf-8"), str(users[key])
    if key in shipped_species():
        return _folder().joinpath(key + ".txt").read_text("utf-8"), f"{key}.txt"
    path = Path(os.path.expanduser(name))
    if path.is_file():
        return path.read_text(encoding="utf-8"), str(path)
    raise SpeciesError(
        f"unknown species or configuration file {name!r}: expected one of "
        + ", ".join(species_names()) + " or a path to a .txt configuration"
    )


def load_species(name: str, seed: int = 0) -> ParameterManager:
    """The :class:`ParameterManager` of a species name or a configuration file (checked)."""
    text, filename = species_text(name)
    check_species(text, filename)
    return ParameterManager.from_text(text, seed=seed, filename=filename)


def species_info(name: str) -> dict[str, str]:
    """``Name``, ``Source`` and ``Description`` of a species (empty strings when absent), and
    ``origin``: ``"shipped"`` or the user file's path."""
    pm = load_species(name)
    info = {k: pm.text(k, default="") for k in ("Name", "Source", "Description")}
    users = user_species()
    info["origin"] = str(users[_key(name)]) if _key(name) in users else "shipped"
    return info


def example_text() -> str:
    """The annotated example species file: every key a species file may set."""
    return resources.files(__package__).joinpath("species_example.txt").read_text("utf-8")
