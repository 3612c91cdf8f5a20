"""Writing files without destroying any: the one check every command's output goes through,
and whole files written to a temporary name beside the target and renamed into place.

- :func:`check_output` refuses an existing file unless ``force`` and refuses, even with it,
  a file the same command reads (``demo --config X --log X``, ``replay L --touches L``)
  and anything that is not a regular file (a device such as ``/dev/full``, a FIFO, a
  socket, a directory; a symbolic link is judged by what it points to): ``--force``
  replaces files, never the special files a rename would destroy.
- :func:`atomic_write` / :func:`atomic_path` write a whole file (config, touches, table,
  plot) under a temporary name in the same directory, fsync it and ``os.replace`` it onto
  the target: a reader sees the old file or the new one, never half of either; a crash
  leaves at most a ``.NAME.*.tmp`` file beside it.

Append-only logs (hand_driver.log.RunLog) are not rewritten whole: they are created with
:func:`create_exclusive` (``O_EXCL``: never opened on top of anything, so never a FIFO
that blocks or a device) and fsync'd record by record.
"""

from __future__ import annotations

import contextlib
import os
import stat
import tempfile
from pathlib import Path
from typing import Iterable, Iterator

from tactile_common.errors import InputError

__all__ = ["check_output", "atomic_write", "atomic_path", "create_exclusive"]

_UMASK = os.umask(0o022)  # read once at import (os.umask can only read by setting) ...
os.umask(_UMASK)  # ... and restored at once: the files get the mode a plain open() would give


def _same_file(a: Path, b: Path) -> bool:
    try:
        return a.resolve() == b.resolve() or (a.exists() and b.exists() and os.path.samefile(a, b))
    except (OSError, ValueError):
        return False


def _special(path: Path) -> str | None:
    """What ``path`` is when it exists and is not a regular file (following links), else None."""
    try:
        mode = os.stat(path).st_mode
    except (OSError, ValueError):
        return None
    for test, what in ((stat.S_ISDIR, "a directory"), (stat.S_ISCHR, "a character device"),
                       (stat.S_ISBLK, "a block device"), (stat.S_ISFIFO, "a FIFO (named pipe)"),
                       (stat.S_ISSOCK, "a socket")):
        if test(mode):
            return what
    return None if stat.S_ISREG(mode) else "not a regular file"


def _refuse_special(out: Path, flag: str) -> None:
    what = _special(out)
    if what == "a directory":
        raise InputError(f"{flag} {out}: is a directory; give a file name")
    if what is not None:
        raise InputError(f"{flag} {out}: is {what}, not a regular file; outputs only replace regular files "
                         f"(even with --force): give a file name")


def check_output(path: str | os.PathLike[str], *, force: bool, reads: Iterable = (), flag: str = "--out") -> Path:
    """The output ``path`` of a command, refused (one-line :class:`InputError`) when it is one
    of the files the command reads (``reads``; even with ``force``), when it exists and is not
    a regular file (even with ``force``), or when it exists without ``force``."""
    out = Path(path)
    for src in reads:
        if src is not None and _same_file(out, Path(src)):
            raise InputError(f"{flag} {out}: is a file this command reads ({src}); choose another path")
    try:
        exists = out.exists() or out.is_symlink()
    except (OSError, ValueError) as exc:
        raise InputError(f"{flag} {str(out)[:200]}: not a usable path ({exc})") from None
    _refuse_special(out, flag)
    if exists and not force:
        raise InputError(f"{flag} {out}: exists; pass --force to overwrite it")
    return out


@contextlib.contextmanager
def atomic_path(path: str | os.PathLike[str], flag: str = "--out") -> Iterator[Path]:
    """Yield a temporary path beside ``path`` (same suffix, so writers that pick a format by
    extension still do); when the block ends without error, fsync it and rename it onto
    ``path``; on error remove it and leave ``path`` as it was."""
    target = Path(path)
    try:
        target.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(dir=target.parent, prefix=f".{target.name}.", suffix=f".tmp{target.suffix}")
    except OSError as exc:
        raise InputError(f"{flag} {target}: cannot write ({exc.strerror or exc})") from None
    os.close(fd)
    tmp_path = Path(tmp)
    try:
        yield tmp_path
        with open(tmp_path, "rb+") as fh:
            os.fsync(fh.fileno())
        os.chmod(tmp_path, 0o666 & ~_UMASK)
        _refuse_special(target, flag)  # again: it may have appeared while the file was written
        os.replace(tmp_path, target)
    except OSError as exc:
        raise InputError(f"{flag} {target}: cannot write ({exc.strerror or exc})") from None
    finally:
        with contextlib.suppress(FileNotFoundError):
            tmp_path.unlink()
    _fsync_dir(target.parent)


def atomic_write(path: str | os.PathLike[str], data: str | bytes, flag: str = "--out") -> Path:
    """Write ``data`` (text is UTF-8) as the whole of ``path``, atomically (see :func:`atomic_path`)."""
    raw = data.encode("utf-8") if isinstance(data, str) else data
    with atomic_path(path, flag) as tmp:
        tmp.write_bytes(raw)
    return Path(path)


def create_exclusive(path: str | os.PathLike[str], *, force: bool, flag: str = "--log"):
    """Create a new file for appending records, unbuffered (``write`` goes straight to the
    file: a failed write leaves nothing behind in a buffer). An existing file is refused
    unless ``force`` (then removed and created anew); anything but a regular file is refused
    even then. Returns the open binary file."""
    target = Path(path)
    try:
        target.parent.mkdir(parents=True, exist_ok=True)
        if force:
            _refuse_special(target, flag)
            with contextlib.suppress(FileNotFoundError):
                target.unlink()
        fd = os.open(target, os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_CLOEXEC", 0), 0o666)
    except FileExistsError:
        raise InputError(f"{flag} {target}: exists; pass --force to overwrite it") from None
    except OSError as exc:
        raise InputError(f"{flag} {target}: cannot write ({exc.strerror or exc})") from None
    return open(fd, "wb", buffering=0)


def _fsync_dir(directory: Path) -> None:
    """Make the rename durable (POSIX); a platform without directory fds skips it."""
    try:
        fd = os.open(directory, os.O_RDONLY)
    except OSError:
        return
    try:
        os.fsync(fd)
    except OSError:
        pass
    finally:
        os.close(fd)
