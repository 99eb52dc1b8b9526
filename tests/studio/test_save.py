"""The Studio's saves: atomic, the replaced file's mode and owner kept, a full disk said so."""

from __future__ import annotations

import contextlib
import os
import resource
import signal
import stat
import subprocess

import pytest

from sylva.studio._workspace import Workspace, WorkspaceError

PLANT = "rot = 25.7\naxiom = F\nF -> F[+F]F[-F]F\n"
# a definition bigger than the file size limit below, smaller than the Studio's text limit
BIG = "axiom = F\nF -> F[+F]F\n" + "# a long comment line to make the file big\n" * 3000


@pytest.fixture()
def client(live):
    with live.client(timeout=30) as c:  # a session opened the way the page opens one
        yield c


def _mode(path) -> int:
    return stat.S_IMODE(os.stat(path).st_mode)


def _umask() -> int:
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def test_save_keeps_mode_and_owner_of_the_file_it_replaces(client, workspace):
    path = workspace / "shared.lsys"
    path.write_text("axiom = F\n", encoding="utf-8")
    path.chmod(0o640)
    owner = (65534, 65534) if os.geteuid() == 0 else None  # only root can give files away
    if owner:
        os.chown(path, *owner)
    r = client.put("/api/file", json={"path": "shared.lsys", "text": PLANT, "overwrite": True})
    assert r.status_code == 200, r.text
    assert path.read_text(encoding="utf-8") == PLANT
    assert _mode(path) == 0o640  # was 0600: the temporary file's mode
    if owner:
        st = os.stat(path)
        assert (st.st_uid, st.st_gid) == owner
    # a new file gets the ordinary mode (0666 less the umask), not a temporary file's 0600
    r = client.put("/api/file", json={"path": "fresh.lsys", "text": PLANT})
    assert r.status_code == 200, r.text
    assert _mode(workspace / "fresh.lsys") == 0o666 & ~_umask()


@contextlib.contextmanager
def _file_size_limit(nbytes: int):
    """Files of this process may not grow past ``nbytes`` (a write past it fails with
    ``EFBIG``, as one on a full disk fails with ``ENOSPC``)."""
    old_handler = signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
    soft, hard = resource.getrlimit(resource.RLIMIT_FSIZE)
    resource.setrlimit(resource.RLIMIT_FSIZE, (nbytes, hard))
    try:
        yield
    finally:
        resource.setrlimit(resource.RLIMIT_FSIZE, (soft, hard))
        signal.signal(signal.SIGXFSZ, old_handler)


def _hidden(folder) -> list[str]:
    return [n for n in os.listdir(folder) if n.startswith(".")]


def test_full_disk_is_a_507_with_the_cause_and_the_old_file_survives(client, workspace):
    path = workspace / "big.lsys"
    path.write_text(PLANT, encoding="utf-8")
    assert len(BIG) > 64 * 1024
    with _file_size_limit(64 * 1024):
        r = client.put("/api/file", json={"path": "big.lsys", "text": BIG, "overwrite": True})
    assert r.status_code == 507, r.text  # Insufficient Storage, not "internal error"
    body = r.json()
    assert body["error"] != "internal" and "report" not in body["message"]
    assert body["message"] == ("cannot write big.lsys: the file is larger than this system "
                               "allows")
    assert path.read_text(encoding="utf-8") == PLANT
    assert _hidden(workspace) == []


@pytest.fixture()
def tiny_disk(tmp_path):
    """A 64 kB tmpfs: a really full disk (``ENOSPC``), where this user may mount one."""
    mnt = tmp_path / "disk"
    mnt.mkdir()
    run = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=64k", "tmpfs", str(mnt)],
                         capture_output=True, text=True, check=False)
    if run.returncode != 0:
        pytest.skip(f"cannot mount a small tmpfs here: {run.stderr.strip()}")
    try:
        yield mnt
    finally:
        subprocess.run(["umount", str(mnt)], check=False)


def test_really_full_disk_says_the_disk_is_full(tiny_disk):
    ws = Workspace(tiny_disk)
    ws.write("plant.lsys", PLANT, overwrite=False)
    with pytest.raises(WorkspaceError) as err:
        ws.write("plant.lsys", BIG * 2, overwrite=True)
    assert err.value.status == 507
    assert str(err.value) == "cannot write plant.lsys: the disk is full"
    assert (tiny_disk / "plant.lsys").read_text(encoding="utf-8") == PLANT
    assert _hidden(tiny_disk) == []
