"""The atomic-write path every writer uses: a failed write never destroys a good file."""

import doctest
import errno
import os
import resource
import stat
import subprocess
import sys
import textwrap

import pytest

from sylva import _atomic
from sylva._atomic import AtomicGroup, atomic_path, atomic_write, describe_os_error


def test_doctests():
    assert doctest.testmod(_atomic).failed == 0


def test_failed_write_keeps_old_file_and_leaves_no_temp(tmp_path):
    target = tmp_path / "a.glb"
    target.write_bytes(b"good" * 1000)
    with pytest.raises(ValueError), atomic_write(target) as fh:
        fh.write(b"bad")
        raise ValueError("writer failed")
    assert target.read_bytes() == b"good" * 1000
    assert os.listdir(tmp_path) == ["a.glb"]


def test_mode_of_replaced_file_is_kept(tmp_path):
    target = tmp_path / "plant.lsys"
    target.write_text("old")
    os.chmod(target, 0o640)
    with atomic_write(target, "w") as fh:
        fh.write("new")
    assert target.read_text() == "new"
    assert stat.S_IMODE(os.stat(target).st_mode) == 0o640


def test_new_file_gets_umask_mode_not_0600(tmp_path):
    with atomic_write(tmp_path / "n.txt", "w") as fh:
        fh.write("x")
    mask = os.umask(0)
    os.umask(mask)
    assert stat.S_IMODE(os.stat(tmp_path / "n.txt").st_mode) == 0o666 & ~mask


def test_group_commits_all_or_nothing(tmp_path):
    (tmp_path / "a.obj").write_text("old obj")
    (tmp_path / "a.mtl").write_text("old mtl")
    with pytest.raises(RuntimeError), AtomicGroup() as g:
        with g.open(tmp_path / "a.mtl", "w") as fh:
            fh.write("new mtl")
        with g.open(tmp_path / "a.obj", "w", main=True) as fh:
            fh.write("new")
            raise RuntimeError
    assert (tmp_path / "a.obj").read_text() == "old obj"
    assert (tmp_path / "a.mtl").read_text() == "old mtl"
    assert sorted(os.listdir(tmp_path)) == ["a.mtl", "a.obj"]


def test_atomic_path_keeps_suffix(tmp_path):
    with atomic_path(tmp_path / "img.png") as tmp:
        assert tmp.endswith(".png") and os.path.dirname(tmp) == str(tmp_path)
        with open(tmp, "wb") as fh:
            fh.write(b"png")
    assert (tmp_path / "img.png").read_bytes() == b"png"


def test_directory_target_is_refused(tmp_path):
    with pytest.raises(IsADirectoryError), atomic_write(tmp_path) as fh:
        fh.write(b"x")


def test_full_disk_in_child_keeps_good_file(tmp_path):
    """A write past RLIMIT_FSIZE (a full disk, as far as the writer can tell) fails with
    EFBIG and leaves the existing file whole."""
    target = tmp_path / "big.bin"
    target.write_bytes(b"g" * 4096)
    code = textwrap.dedent(f"""
        import resource, signal, sys
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
        resource.setrlimit(resource.RLIMIT_FSIZE, (65536, 65536))
        from sylva._atomic import atomic_write, describe_os_error
        try:
            with atomic_write({str(target)!r}) as fh:
                fh.write(b"n" * 1_000_000)
        except OSError as e:
            print(describe_os_error(e, {str(target)!r}))
            sys.exit(2)
    """)
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert r.returncode == 2, r.stderr
    assert "larger than this system allows" in r.stdout and str(target) in r.stdout
    assert target.read_bytes() == b"g" * 4096
    assert os.listdir(tmp_path) == ["big.bin"]
    assert resource.RLIMIT_FSIZE  # the mechanism the test relies on exists here


def test_describe_missing_folder(tmp_path):
    missing = tmp_path / "nope" / "x.png"
    try:
        with atomic_write(missing) as fh:
            fh.write(b"x")
    except OSError as e:
        msg = describe_os_error(e, missing)
    assert msg == f"cannot write {missing}: the folder {tmp_path / 'nope'} does not exist"


def test_error_in_the_writer_names_the_target_not_the_temp(tmp_path):
    """``write()`` on a full disk raises ENOSPC without a file name, and an error on the
    temporary file names the hidden temporary: both come out naming the target."""
    target = tmp_path / "out.glb"
    with pytest.raises(OSError) as err, atomic_write(target):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
    assert err.value.filename == str(target)
    assert describe_os_error(err.value) == f"cannot write {target}: the disk is full"
    with pytest.raises(OSError) as err, atomic_path(target) as tmp:
        raise OSError(errno.EFBIG, os.strerror(errno.EFBIG), tmp)
    assert err.value.filename == str(target)
    # an error about some other file (a texture read) keeps its own name
    with pytest.raises(OSError) as err, atomic_write(target):
        raise FileNotFoundError(errno.ENOENT, "no such file", "/elsewhere/bark.png")
    assert err.value.filename == "/elsewhere/bark.png"
    assert os.listdir(tmp_path) == []


def test_os_error_from_a_tools_words(tmp_path):
    from sylva._atomic import os_error_from_text

    log = "[out#0/mp4] Error writing trailer: No space left on device\n"
    e = os_error_from_text(log, tmp_path / "a.mp4", "ffmpeg")
    assert (e.errno, e.filename) == (errno.ENOSPC, str(tmp_path / "a.mp4"))
    e = os_error_from_text("Conversion failed!\n", "a.mp4", "ffmpeg")
    assert describe_os_error(e) == "cannot write a.mp4: ffmpeg failed: conversion failed!"


def test_save_buffered_goes_through_checked_writes(tmp_path):
    """Pillow's encoders write to the descriptor and miss a short write: a JPEG past a
    file size limit came out truncated with no error.  Through save_buffered it fails."""
    target = tmp_path / "img.jpg"
    target.write_bytes(b"old jpeg")
    code = textwrap.dedent(f"""
        import resource, signal, sys
        import numpy as np
        from PIL import Image
        from sylva._atomic import save_buffered
        img = Image.fromarray(np.random.default_rng(0).integers(0, 255, (64, 64, 3),
                                                                 dtype=np.uint8))
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
        resource.setrlimit(resource.RLIMIT_FSIZE, (2000, resource.RLIM_INFINITY))
        try:
            save_buffered({str(target)!r}, lambda fh: img.save(fh, format="JPEG"))
        except OSError as e:
            sys.exit(e.errno)
    """)
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert r.returncode == errno.EFBIG, r.stderr
    assert target.read_bytes() == b"old jpeg"
    assert os.listdir(tmp_path) == ["img.jpg"]
