"""Outputs never replace what is not a regular file (issue 22): devices, FIFOs, sockets and
directories are refused even with --force; a full disk during a run ends with one line,
torque off and the log whole up to its last complete record. Every special file here is
made by the test in its own temporary directory (never /dev/null, /dev/full or any system
file)."""

from __future__ import annotations

import errno
import os
import socket
import stat
from pathlib import Path

import pytest

from hand_driver.log import read_log
from tactile_common.errors import InputError
from tactile_common.files import atomic_write, check_output, create_exclusive

ROOT = Path(__file__).resolve().parents[2]


def _fifo(tmp_path) -> Path:
    p = tmp_path / "fifo"
    os.mkfifo(p)
    return p


def _device(tmp_path) -> Path:
    """A character device node like /dev/full (1, 7), made here; skipped without the right."""
    p = tmp_path / "full"
    try:
        os.mknod(p, stat.S_IFCHR | 0o600, os.makedev(1, 7))
    except PermissionError:
        pytest.skip("making a device node needs root")
    return p


def _socket(tmp_path) -> Path:
    p = tmp_path / "sock"
    s = socket.socket(socket.AF_UNIX)
    s.bind(str(p))
    s.close()
    return p


def _directory(tmp_path) -> Path:
    p = tmp_path / "dir"
    p.mkdir()
    return p


SPECIAL = [(_fifo, "a FIFO"), (_device, "a character device"), (_socket, "a socket"), (_directory, "a directory")]


@pytest.mark.parametrize("make,what", SPECIAL)
def test_special_files_are_refused_even_with_force(tmp_path, make, what):
    p = make(tmp_path)
    before = os.lstat(p)
    for force in (False, True):
        with pytest.raises(InputError, match=f"is {what}"):
            check_output(p, force=force, flag="--touches")
        with pytest.raises(InputError, match=f"is {what}"):
            create_exclusive(p, force=True)
    with pytest.raises(InputError, match=f"is {what}"):
        atomic_write(p, "x", flag="--plot")
    after = os.lstat(p)
    assert (after.st_mode, after.st_ino) == (before.st_mode, before.st_ino)  # untouched
    assert [q.name for q in tmp_path.iterdir()] == [p.name]  # no temporary file left behind


def test_a_link_to_a_special_file_is_judged_by_its_target(tmp_path):
    link = tmp_path / "link"
    link.symlink_to(_fifo(tmp_path))
    with pytest.raises(InputError, match="is a FIFO"):
        check_output(link, force=True)
    plain = tmp_path / "plain"
    plain.write_text("old")
    check_output(plain, force=True)  # a regular file is still replaced with --force


@pytest.mark.parametrize("make,what", SPECIAL[:2])
@pytest.mark.parametrize("argv", [
    lambda p, log: ["replay", str(log), "--touches", str(p), "--force"],
    lambda p, log: ["demo", "--plot", str(p), "--force"],
    lambda p, log: ["demo", "--log", str(p), "--force"],
])
def test_commands_refuse_special_outputs_before_any_work(tmp_path, tactile_in_process, make, what, argv):
    """Issue 22: ``--touches`` (replay) and ``--plot`` (demo) with ``--force``, aimed at the
    full-disk device, renamed a regular file over it; ``--log`` there ended in a traceback.
    Here each output is a FIFO, socket or device node this test makes in its own directory."""
    p = make(tmp_path)
    log = tmp_path / "some.jsonl"
    log.write_text("{}\n")
    rc, out, err = tactile_in_process(argv(p, log))
    assert rc == 2 and err.count("\n") == 1 and f"is {what}" in err and "not a regular file" in err, err
    assert stat.S_IFMT(os.lstat(p).st_mode) == stat.S_IFMT(os.stat(p).st_mode) != stat.S_IFREG


def test_a_full_disk_during_a_demo_ends_with_one_line_torque_off_and_the_log_whole(tmp_path, monkeypatch,
                                                                                    tactile_in_process):
    """ENOSPC on the 300th record: exit 1 with one line (the log's LogWriteError, a
    DeviceFault), every emulated servo's torque off when the bus closed, and the log reads
    as cut after its last complete record."""
    import hand_driver.sim.server as server
    import tactile_common.files as files

    torque_at_exit = []
    real_exit = server.EmulatedBus.__exit__

    def recording_exit(self, *exc):
        self.wait_idle()  # the torque-off packets are in the pty: served before the bus stops
        torque_at_exit.extend(s.torque_on for s in self.servos.values())
        return real_exit(self, *exc)

    monkeypatch.setattr(server.EmulatedBus, "__exit__", recording_exit)
    real_create = files.create_exclusive

    class _FillingFile:
        def __init__(self, f):
            self.f, self.n = f, 0

        def write(self, data):
            self.n += 1
            if self.n >= 300:
                raise OSError(errno.ENOSPC, "No space left on device")
            return self.f.write(data)

        def fileno(self):
            return self.f.fileno()

        def close(self):
            self.f.close()

    monkeypatch.setattr("hand_driver.log.create_exclusive", lambda *a, **k: _FillingFile(real_create(*a, **k)))
    log = tmp_path / "run.jsonl"
    rc, out, err = tactile_in_process(["demo", "--log", str(log), "--json"])
    lines = [s for s in err.splitlines() if not s.startswith("  ")]  # progress lines start with two spaces
    assert rc == 1 and lines == [f"tactile demo: --log {log}: cannot write the run log (No space left on device); "
                                 f"the run stopped, the log is whole up to record 298"], err
    assert torque_at_exit and not any(torque_at_exit)
    c = read_log(log)
    assert c.records == 299 and c.verified and c.truncated and "without its end record" in c.cut
