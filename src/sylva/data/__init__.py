"""Built-in example L-systems shipped with sylva (all three dialects).

>>> names = [e.name for e in examples()]
>>> "01-koch-snowflake" in names
True
>>> find("koch-snowflake").path.suffix
'.lsys'
"""

from __future__ import annotations

from dataclasses import dataclass
from importlib import resources
from pathlib import Path

from ..errors import SylvaError

__all__ = ["Example", "examples", "find"]


@dataclass(frozen=True)
class Example:
    """A built-in example: its name (the file stem) and the path of its text."""

    name: str
    path: Path

    @property
    def title(self) -> str:
        """The first comment line of the file, without the comment mark."""
        for line in self.path.read_text(encoding="utf-8").splitlines():
            s = line.strip()
            if s.startswith(("#", ";")):
                return s.lstrip("#; ").strip()
        return self.name


def _folder() -> Path:
    return Path(str(resources.files(__name__) / "examples"))


def examples() -> list[Example]:
    """Every built-in example, in gallery order."""
    files = sorted(p for p in _folder().iterdir() if p.suffix in (".lsys", ".txt"))
    return [Example(p.stem, p) for p in files]


def find(name: str) -> Example:
    """The example whose name is ``name``, or ends with it (``"koch-snowflake"``).

    Raises
    ------
    SylvaError
        When no example (or more than one) matches.
    """
    all_ = examples()
    exact = [e for e in all_ if e.name == name or e.path.name == name]
    if exact:
        return exact[0]
    hits = [e for e in all_ if e.name.endswith(name) or e.name.split("-", 1)[-1] == name]
    if not hits:
        hits = [e for e in all_ if name in e.name]
    if len(hits) == 1:
        return hits[0]
    if not hits:
        raise SylvaError(
            f"no built-in example named {name!r}; `sylva examples` lists them"
        )
    raise SylvaError(
        f"{name!r} matches several examples: " + ", ".join(e.name for e in hits)
    )
