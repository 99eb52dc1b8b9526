"""The folder the Studio may read and write: no path given by a client can leave it."""

from __future__ import annotations

import errno
import os
from pathlib import Path, PurePosixPath

from .._atomic import atomic_write, describe_os_error
from ..errors import SylvaError

__all__ = ["SUFFIXES", "Workspace", "WorkspaceError"]

SUFFIXES = (".lsys", ".txt", ".ls")
_MAX_FILES = 2000
_MAX_DEPTH = 6
_NAME_MAX = 255  # bytes in one file or folder name (Linux, macOS, Windows)


class WorkspaceError(SylvaError):
    """A path outside the workspace, of a kind the Studio does not handle, or missing.

    ``status`` is the HTTP status the server answers with."""

    def __init__(self, message: str, status: int = 400) -> None:
        self.status = status
        super().__init__(message)


def _save_status(exc: OSError) -> int:
    """The HTTP status of a failed save: 507 Insufficient Storage for a full disk or quota,
    403 where the server may not write, 409 where a file stands in the way of a folder of
    the path (or a folder in the way of the file), 400 for a name the system refuses, 500
    for the rest."""
    if exc.errno in (errno.ENOSPC, errno.EDQUOT, errno.EFBIG):
        return 507
    if exc.errno in (errno.EACCES, errno.EPERM, errno.EROFS):
        return 403
    if exc.errno in (errno.EEXIST, errno.ENOTDIR, errno.EISDIR):
        return 409
    if exc.errno in (errno.ENAMETOOLONG, errno.EINVAL):
        return 400
    return 500


def decode(data: bytes) -> str:
    """Text of a definition file: UTF-8 (with or without BOM), UTF-16 with a BOM, else
    Windows-1250 (LSysVis saved in the system's encoding) and finally Latin-1."""
    if data.startswith((b"\xff\xfe", b"\xfe\xff")):
        return data.decode("utf-16")
    for enc in ("utf-8-sig", "cp1250"):
        try:
            return data.decode(enc)
        except UnicodeDecodeError:
            continue
    return data.decode("latin-1")


class Workspace:
    """Files with the suffixes :data:`SUFFIXES` under ``root``."""

    def __init__(self, root: str | os.PathLike) -> None:
        self.root = Path(root).resolve()
        if not self.root.is_dir():
            raise WorkspaceError(f"workspace {self.root} is not a folder")

    def resolve(self, rel: object, *, suffixes: tuple[str, ...] = SUFFIXES) -> Path:
        """The absolute path of ``rel`` (a relative, ``/``-separated path), checked to stay
        inside the workspace and to end in one of ``suffixes``."""
        if not isinstance(rel, str) or not rel.strip():
            raise WorkspaceError("give a file path relative to the workspace")
        if len(rel) > 255 or "\x00" in rel or "\\" in rel or ":" in rel:
            raise WorkspaceError(f"{rel!r} is not a valid workspace path")
        pure = PurePosixPath(rel)
        if any(len(part.encode("utf-8")) > _NAME_MAX for part in pure.parts):
            # the system would refuse it (ENAMETOOLONG): a bad path, not a server error
            raise WorkspaceError(f"{rel!r} has a name longer than {_NAME_MAX} bytes")
        if pure.is_absolute() or any(part in ("..", ".") or part.startswith(".")
                                     for part in pure.parts):
            raise WorkspaceError(f"{rel!r} leaves the workspace or names a hidden file", 403)
        if pure.suffix.lower() not in suffixes:
            raise WorkspaceError(
                f"{rel!r}: the Studio opens and saves {', '.join(suffixes)} files only"
            )
        path = (self.root / Path(*pure.parts)).resolve()
        if not path.is_relative_to(self.root):
            raise WorkspaceError(f"{rel!r} leaves the workspace", 403)
        return path

    def relative(self, path: Path) -> str:
        return path.relative_to(self.root).as_posix()

    def list(self, *, suffixes: tuple[str, ...] = SUFFIXES) -> list[dict]:
        """Every file ending in one of ``suffixes`` (default: the definition files) in the
        workspace (hidden folders skipped), sorted."""
        out: list[dict] = []
        for dirpath, dirnames, filenames in os.walk(self.root):
            here = Path(dirpath)
            depth = len(here.relative_to(self.root).parts)
            dirnames[:] = sorted(d for d in dirnames if not d.startswith(".")
                                 and depth < _MAX_DEPTH)
            for name in sorted(filenames):
                if name.startswith(".") or Path(name).suffix.lower() not in suffixes:
                    continue
                p = here / name
                try:
                    real = p.resolve()
                    if not real.is_relative_to(self.root) or not real.is_file():
                        continue
                    size = real.stat().st_size
                except OSError:
                    continue
                out.append({"path": self.relative(p), "size": size})
                if len(out) >= _MAX_FILES:
                    return out
        return out

    def read(self, rel: object, max_bytes: int, *,
             suffixes: tuple[str, ...] = SUFFIXES) -> str:
        path = self.resolve(rel, suffixes=suffixes)
        try:
            if not path.is_file():
                raise WorkspaceError(f"{rel}: no such file in the workspace", 404)
            if path.stat().st_size > max_bytes:
                raise WorkspaceError(f"{rel} is larger than {max_bytes:,} bytes", 413)
            return decode(path.read_bytes())
        except OSError as exc:
            raise WorkspaceError(describe_os_error(exc, rel, verb="read"),
                                 _save_status(exc)) from None

    def write(self, rel: object, text: str, *, overwrite: bool) -> str:
        """Save ``text`` as UTF-8, atomically; return the relative path."""
        path = self.resolve(rel)
        try:
            if path.exists() and not overwrite:
                raise WorkspaceError(f"{rel} exists already", 409)
            if path.exists() and not path.is_file():
                raise WorkspaceError(f"{rel} is not a file", 409)
            path.parent.mkdir(parents=True, exist_ok=True)
            if not path.parent.resolve().is_relative_to(self.root):
                raise WorkspaceError(f"{rel!r} leaves the workspace", 403)
            # a temporary file beside it, renamed over it: the mode and owner of the file
            # it replaces are kept, and a failed save leaves the old file whole
            with atomic_write(path, "w", newline="") as fh:
                fh.write(text)
        except OSError as exc:
            raise WorkspaceError(describe_os_error(exc, rel), _save_status(exc)) from None
        return self.relative(path)
