"""Targets a CLI writer cannot write to, and the checks of its failure, shared by
``test_write_failures.py`` (every writer, fixed cases) and ``test_write_fuzz.py`` (random
programs and formats).

A read-only folder is made immutable as root (root ignores permission bits); a full disk
is a child process with ``RLIMIT_FSIZE`` (and ``SIGXFSZ`` ignored, so a write past the
limit fails with ``EFBIG`` as one past a full disk fails with ``ENOSPC``).
"""

from __future__ import annotations

import contextlib
import fcntl
import os
import re
import textwrap
from pathlib import Path

import pytest

MESSAGE = re.compile(r"^sylva: error: cannot write (?P<path>.+?): (?P<cause>.+)$", re.M)
FULL_DISK_CAUSES = ("larger than this system allows",)


def check_failure(rc, err: str, allowed: set[Path], causes: tuple[str, ...]) -> None:
    """Exit 2, no traceback, one ``cannot write PATH: CAUSE`` line naming one of
    ``allowed`` with one of ``causes``."""
    assert rc == 2, (rc, err)
    assert "Traceback" not in err and "Exception ignored" not in err, err
    found = MESSAGE.search(err)
    assert found, err
    assert Path(found["path"]) in allowed, err
    assert any(c in found["cause"] for c in causes), err


def seed(folder: Path, files: dict[str, bytes]) -> None:
    folder.mkdir(parents=True, exist_ok=True)
    for f, data in files.items():
        (folder / f).write_bytes(data)


def same(folder: Path, files: dict[str, bytes]) -> None:
    assert sorted(os.listdir(folder)) == sorted(files), "a temporary file was left behind"
    for f, data in files.items():
        assert (folder / f).read_bytes() == data, f"{f} was changed by the failed write"


_FS_IOC_GETFLAGS, _FS_IOC_SETFLAGS, _FS_IMMUTABLE_FL = 0x80086601, 0x40086602, 0x10


def _set_immutable(folder: Path, on: bool) -> None:
    fd = os.open(folder, os.O_RDONLY | os.O_DIRECTORY)
    try:
        buf = bytearray(fcntl.ioctl(fd, _FS_IOC_GETFLAGS, b"\0" * 8))
        flags = int.from_bytes(buf[:4], "little")
        flags = flags | _FS_IMMUTABLE_FL if on else flags & ~_FS_IMMUTABLE_FL
        fcntl.ioctl(fd, _FS_IOC_SETFLAGS, flags.to_bytes(4, "little") + bytes(buf[4:]))
    finally:
        os.close(fd)


@contextlib.contextmanager
def read_only(folder: Path):
    """A folder nobody may add a file to (yields the causes a write there is refused
    with).  Root ignores permission bits, so as root the folder is made immutable
    (``chattr +i``), which binds root too."""
    if os.geteuid() != 0:
        folder.chmod(0o555)
        try:
            yield ("permission denied",)
        finally:
            folder.chmod(0o755)
        return
    try:
        _set_immutable(folder, True)
    except OSError as exc:
        pytest.skip(f"running as root and {folder} cannot be made immutable: {exc}")
    try:
        yield ("operation not permitted",)
    finally:
        _set_immutable(folder, False)


# A child that runs [name, argv, limit] jobs from stdin, each under RLIMIT_FSIZE = limit,
# and prints {name: (rc, stderr)}.
FULL_DISK_CHILD = textwrap.dedent("""
    import contextlib, io, json, resource, signal, sys, traceback
    from sylva.cli import main
    signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
    results = {}
    for name, argv, limit in json.load(sys.stdin):
        err = io.StringIO()
        resource.setrlimit(resource.RLIMIT_FSIZE, (limit, resource.RLIM_INFINITY))
        try:
            with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
                rc = main(argv)
        except BaseException:
            rc = "raised"
            err.write(traceback.format_exc())
        finally:
            resource.setrlimit(resource.RLIMIT_FSIZE,
                               (resource.RLIM_INFINITY, resource.RLIM_INFINITY))
        results[name] = (rc, err.getvalue())
    json.dump(results, sys.stdout)
""")
