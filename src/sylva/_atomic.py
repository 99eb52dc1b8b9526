"""Atomic writes: a file on disk is either the old one or the new one, never half of each.

Every writer of sylva that puts a file at a user's path goes through this module
(exports, renders, animations, textures, worlds, the gallery, the studio's saves).  The
new content is written to a temporary file in the *same directory* as the target, flushed
and ``fsync``-ed, given the mode (and, where the process may, the owner) of the file it
replaces, and only then renamed over the target with :func:`os.replace`, which is atomic
on POSIX and on Windows.  If anything fails before the rename — a full disk, a killed
process, an exception in the writer — the temporary file is removed and the target is
left exactly as it was.

A format with companion files (OBJ's ``.mtl``, a ``.gltf`` with images beside it) writes
them in one :class:`AtomicGroup`: every member is written and synced first, then the
companions are renamed, and the main file last, so a reader that sees the new main file
also sees its companions.

Examples
--------
>>> import os, tempfile
>>> from pathlib import Path
>>> d = tempfile.mkdtemp()
>>> p = os.path.join(d, "plant.txt")
>>> with atomic_write(p, "w") as fh:
...     _ = fh.write("F[+F]F")
>>> Path(p).read_text()
'F[+F]F'
>>> try:
...     with atomic_write(p, "w") as fh:
...         _ = fh.write("half a")
...         raise RuntimeError("disk full")
... except RuntimeError:
...     pass
>>> Path(p).read_text()      # the good file survived the failed write
'F[+F]F'
>>> sorted(os.listdir(d))   # and no temporary file is left behind
['plant.txt']
"""

from __future__ import annotations

import contextlib
import errno
import os
import stat
import tempfile
from collections.abc import Iterator
from typing import IO, Any

__all__ = [
    "AtomicGroup",
    "atomic_path",
    "atomic_write",
    "describe_os_error",
    "is_write_error",
    "make_folder",
    "os_error_from_text",
    "save_buffered",
]

PathLike = str | os.PathLike


def _umask() -> int:
    # The umask can only be read by setting it; do it once, at import (single-threaded).
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


_UMASK = _umask()


def _temp_name(target: str) -> str:
    """A fresh, hidden temporary file beside ``target`` that keeps its suffix (libraries
    such as Pillow, imageio and usd-core pick the format from it)."""
    folder, name = os.path.split(target)
    stem, suffix = os.path.splitext(name)
    fd, tmp = tempfile.mkstemp(dir=folder or ".", prefix=f".{stem}.", suffix=f".tmp{suffix}")
    os.close(fd)
    return tmp


def _adopt_metadata(tmp: str, target: str) -> None:
    """Give ``tmp`` the mode and owner of ``target`` (or a new file's default mode)."""
    try:
        st = os.stat(target)
    except FileNotFoundError:
        os.chmod(tmp, 0o666 & ~_UMASK)
        return
    os.chmod(tmp, stat.S_IMODE(st.st_mode))
    if hasattr(os, "chown"):
        # Only root may give a file away; a user keeps their own files' owner anyway.
        with contextlib.suppress(OSError):
            os.chown(tmp, st.st_uid, st.st_gid)


def _fsync_path(path: str) -> None:
    fd = os.open(path, os.O_RDONLY)
    try:
        os.fsync(fd)
    finally:
        os.close(fd)


def _fsync_dir(folder: str) -> None:
    if os.name != "posix":
        return
    try:
        fd = os.open(folder or ".", os.O_RDONLY)
    except OSError:
        return
    try:
        os.fsync(fd)
    except OSError:
        pass
    finally:
        os.close(fd)


def _discard(path: str) -> None:
    with contextlib.suppress(FileNotFoundError):
        os.unlink(path)


def _check_target(target: str) -> None:
    if os.path.isdir(target):
        raise IsADirectoryError(errno.EISDIR, "is a directory", target)


def _name_target(exc: BaseException, members: list[tuple[str, str, bool]]) -> None:
    """Make an ``OSError`` of a write name the file the user asked for.

    ``write()`` on a full disk raises ``ENOSPC`` without a file name, and an error on the
    temporary file names the hidden temporary; both are renamed to the target (the last
    member written, when the error names no file), so the message says which output failed.
    """
    if not isinstance(exc, OSError) or not members:
        return
    exc.sylva_write = True
    targets = {tmp: target for tmp, target, _ in members}
    if exc.filename is None:
        exc.filename = members[-1][1]
    elif exc.filename in targets:
        exc.filename = targets[exc.filename]


class AtomicGroup:
    """Several files that appear together: companions first, the main file last.

    Use :meth:`open` for a file object or :meth:`path` for a temporary path that a library
    writes itself; nothing is renamed until the ``with`` block ends without an exception.

    >>> import os, tempfile
    >>> d = tempfile.mkdtemp()
    >>> with AtomicGroup() as g:
    ...     with g.open(os.path.join(d, "a.mtl"), "w") as fh:
    ...         _ = fh.write("newmtl bark")
    ...     with g.open(os.path.join(d, "a.obj"), "w", main=True) as fh:
    ...         _ = fh.write("mtllib a.mtl")
    >>> sorted(os.listdir(d))
    ['a.mtl', 'a.obj']
    """

    def __init__(self) -> None:
        self._members: list[tuple[str, str, bool]] = []  # (tmp, target, main)

    def path(self, target: PathLike, *, main: bool = False) -> str:
        """A temporary path beside ``target`` (same suffix) to write with any library."""
        target = os.fspath(target)
        _check_target(target)
        try:
            tmp = _temp_name(target)
        except OSError as exc:  # no folder, no permission: name the target, not the temp
            exc.filename = target
            exc.sylva_write = True
            raise
        self._members.append((tmp, target, main))
        return tmp

    def open(
        self,
        target: PathLike,
        mode: str = "wb",
        *,
        main: bool = False,
        encoding: str | None = "utf-8",
        newline: str | None = "\n",
    ) -> IO[Any]:
        """A file object writing to a temporary file beside ``target``."""
        if "b" in mode:
            encoding = newline = None
        tmp = self.path(target, main=main)
        return open(tmp, mode, encoding=encoding, newline=newline)  # noqa: SIM115

    def commit(self) -> None:
        order = [m for m in self._members if not m[2]] + [m for m in self._members if m[2]]
        for tmp, target, _ in order:
            _fsync_path(tmp)
            _adopt_metadata(tmp, target)
        folders = set()
        for tmp, target, _ in order:
            os.replace(tmp, target)
            folders.add(os.path.dirname(target))
        for folder in folders:
            _fsync_dir(folder)
        self._members.clear()

    def abort(self) -> None:
        for tmp, _, _ in self._members:
            _discard(tmp)
        self._members.clear()

    def __enter__(self) -> AtomicGroup:
        return self

    def __exit__(self, exc_type, exc, tb) -> None:
        if exc_type is None:
            try:
                self.commit()
            except BaseException as failure:
                _name_target(failure, self._members)
                self.abort()
                raise
        else:
            _name_target(exc, self._members)
            self.abort()


@contextlib.contextmanager
def atomic_write(
    target: PathLike,
    mode: str = "wb",
    *,
    encoding: str | None = "utf-8",
    newline: str | None = "\n",
) -> Iterator[IO[Any]]:
    """Open ``target`` for writing so that it is replaced only once the block succeeds."""
    with AtomicGroup() as group, group.open(
        target, mode, main=True, encoding=encoding, newline=newline
    ) as fh:
        yield fh


@contextlib.contextmanager
def atomic_path(target: PathLike) -> Iterator[str]:
    """A temporary path (same folder, same suffix) that becomes ``target`` on success.

    For libraries that insist on a file name: ``img.save(tmp)``, usd-core's ``Export``,
    ffmpeg.
    """
    with AtomicGroup() as group:
        yield group.path(target, main=True)


def describe_os_error(exc: OSError, path: PathLike | None = None, *, verb: str = "write") -> str:
    """A one-line message for a failed file operation: the path and the cause in words
    (``cannot write PATH: the disk is full``; ``verb`` replaces *write*)."""
    where = os.fspath(path) if path is not None else (exc.filename or "")
    causes = {
        errno.ENOSPC: "the disk is full",
        errno.EDQUOT: "the disk quota is exhausted",
        errno.EFBIG: "the file is larger than this system allows",
        errno.EACCES: "permission denied",
        errno.EPERM: "operation not permitted",
        errno.ENOENT: "no such file or directory",
        errno.ENOTDIR: "a part of the path is not a directory",
        errno.EISDIR: "it is a directory",
        errno.EROFS: "the file system is read-only",
        errno.ENAMETOOLONG: "the file name is too long",
    }
    cause = causes.get(exc.errno or -1) or (exc.strerror or str(exc)).lower()
    if exc.errno == errno.ENOENT and where:
        folder = os.path.dirname(os.path.abspath(where))
        if not os.path.isdir(folder):
            cause = f"the folder {folder} does not exist"
    return f"cannot {verb} {where}: {cause}" if where else f"cannot {verb}: {cause}"


def is_write_error(exc: BaseException) -> bool:
    """True for an ``OSError`` met writing a file through this module (or marked so by
    :func:`make_folder`), as opposed to one met reading."""
    return isinstance(exc, OSError) and getattr(exc, "sylva_write", False)


def make_folder(folder: PathLike) -> None:
    """``mkdir -p`` whose failure counts as a failed write (see :func:`is_write_error`)."""
    try:
        os.makedirs(folder, exist_ok=True)
    except OSError as exc:
        exc.sylva_write = True
        raise


#: The causes a tool (ffmpeg, usd-core) may report in words instead of an errno.
_TOOL_ERRNOS = (errno.ENOSPC, errno.EDQUOT, errno.EFBIG, errno.EACCES, errno.EPERM,
                errno.EROFS, errno.ENOENT, errno.ENOTDIR, errno.EISDIR, errno.ENAMETOOLONG)


def os_error_from_text(text: str, path: PathLike, tool: str) -> OSError:
    """The ``OSError`` a tool that reports failures as text (ffmpeg's log, usd-core's
    ``Tf.ErrorException``) met: the errno whose message appears in ``text`` (``"No space
    left on device"``, ``"File too large"``...), else ``EIO`` with the tool's last line."""
    low = text.lower()
    for code in _TOOL_ERRNOS:
        if os.strerror(code).lower() in low:
            return OSError(code, os.strerror(code), os.fspath(path))
    last = next((ln.strip() for ln in reversed(text.splitlines()) if ln.strip()), "")
    return OSError(errno.EIO, f"{tool} failed: {last}" if last else f"{tool} failed",
                   os.fspath(path))


def save_buffered(target: PathLike, save) -> None:
    """Write what ``save(file)`` writes into memory, then to ``target`` atomically.

    For Pillow: its C encoders write to a file's descriptor directly and miss a short
    ``write()`` (on a full disk a JPEG comes out truncated, with no error).  Through an
    in-memory file every byte goes through Python's checked writes.
    """
    import io

    buf = io.BytesIO()
    save(buf)
    with atomic_write(target) as fh:
        fh.write(buf.getbuffer())
