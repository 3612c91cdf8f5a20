"""The run log: JSON Lines, durable record by record.

One JSON object per line. The first line is the header, then, in the order they
happened:

- ``{"type": "header", "format": "tactile-jaw-log", "version": 1, "start_time": ISO-8601,
  "monotonic_origin": s, "config": {...}, "scene": {...}|null, "versions": {...},
  "command": [...], "settings": {...}}``
- ``{"type": "reading", "i": n, "t": s, "ticks": [...], "current_ma": [...]|null,
  "moving": [...]|null}`` — every joint reading taken, ``t`` on the monotonic clock of
  the header, ``i`` counting readings from 0; joint order is the config's (left finger's
  joints, then the right finger's).
- ``{"type": "touch_start", "touch": k, "finger": name, "psi": rad, "reading": i}``
- ``{"type": "sample", "touch": k, "finger": name, "psi": rad, "reading": i}`` — reading
  ``i`` is an in-contact reading of touch ``k``: the pad line it gives is one sample of
  the rolling move.
- ``{"type": "touch_end", "touch": k, "finger": name, "reading": i, "samples": m, "outcome": str}``
- ``{"type": "event", "kind": str, "message": str, ...}`` — faults, retries, no-contact
  results, progress.
- ``{"type": "result", "recognition": {the answer, docs/formats.md}, "robot_time_s": s}``

Each record is flushed and fsync'd before :meth:`RunLog.write` returns, so a killed
process, a crash or a pulled cable loses nothing already logged (measured cost of one
flush + fsync: about 0.2 ms on the development machine's ext4 disk). :func:`read_log`
accepts a log whose last line was cut by a crash.
"""

from __future__ import annotations

import datetime
import json
import math
import os
import platform
import time
from dataclasses import dataclass, field
from importlib import metadata
from pathlib import Path
from typing import Any, Iterable

from tactile_common.errors import InputError
from tactile_common.files import create_exclusive

LOG_FORMAT = "tactile-jaw-log"
LOG_VERSION = 1
_VERSIONED_PACKAGES = ("tactile-jaw", "numpy", "scipy", "dynamixel-sdk", "pyserial", "pyyaml")


def package_versions() -> dict[str, str]:
    """Versions of Python and of the packages a run depends on (``"absent"`` if missing)."""
    versions = {"python": platform.python_version()}
    for name in _VERSIONED_PACKAGES:
        try:
            versions[name] = metadata.version(name)
        except metadata.PackageNotFoundError:
            versions[name] = "absent"
    return versions


def _plain(value: Any) -> Any:
    """JSON-safe copy: numpy scalars/arrays, tuples and dataclass-free mappings to plain types.

    A non-finite float becomes ``None`` so that no line ever holds NaN.
    """
    if isinstance(value, dict):
        return {str(k): _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if hasattr(value, "tolist"):  # numpy array or scalar
        return _plain(value.tolist())
    if isinstance(value, bool) or value is None or isinstance(value, (int, str)):
        return value
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    if isinstance(value, Path):
        return str(value)
    raise TypeError(f"cannot log a value of type {type(value).__name__}")


class RunLog:
    """Append-only JSON Lines log; use as a context manager.

    ``RunLog(path).open(header_fields)`` writes the header; :meth:`reading` is shaped to be
    passed as the bus's ``on_reading`` callback.
    """

    def __init__(self, path: str | os.PathLike[str]) -> None:
        self.path = Path(path)
        self._file = None
        self.readings = 0
        self.monotonic_origin = 0.0

    def open(self, *, config: dict[str, Any], scene: dict[str, Any] | None,
             command: list[str] | None = None, settings: dict[str, Any] | None = None,
             force: bool = False) -> "RunLog":
        """Create the file and write the header; an existing file is refused unless ``force``
        (tactile_common.files.create_exclusive)."""
        self._file = create_exclusive(self.path, force=force, flag="--log")
        self.monotonic_origin = time.monotonic()
        self.write({
            "type": "header",
            "format": LOG_FORMAT,
            "version": LOG_VERSION,
            "start_time": datetime.datetime.now(datetime.timezone.utc).isoformat(),
            "monotonic_origin": self.monotonic_origin,
            "config": config,
            "scene": scene,
            "versions": package_versions(),
            "command": command or [],
            "settings": settings or {},
        })
        return self

    def write(self, record: dict[str, Any]) -> None:
        """Append one record, flush it and fsync it."""
        if self._file is None:
            raise RuntimeError("RunLog.write before open")
        self._file.write(json.dumps(_plain(record), separators=(",", ":"), allow_nan=False) + "\n")
        self._file.flush()
        os.fsync(self._file.fileno())

    def reading(self, state: Any) -> int:
        """Log one joint reading (a ``hand_driver.bus.JointState``); returns its index ``i``.
        Shaped as the bus's ``on_reading`` callback."""
        i = self.readings
        self.write({
            "type": "reading", "i": i, "t": state.t_monotonic,
            "ticks": list(state.ticks),
            "current_ma": None if state.current_ma is None else list(state.current_ma),
            "moving": None if getattr(state, "moving", None) is None else list(state.moving),
        })
        self.readings += 1
        return i

    def event(self, kind: str, message: str, **data: Any) -> None:
        self.write({"type": "event", "kind": kind, "message": message, **data})

    def close(self) -> None:
        if self._file is not None:
            try:
                self._file.flush()
                os.fsync(self._file.fileno())
            finally:
                self._file.close()
                self._file = None

    def __enter__(self) -> "RunLog":
        return self

    def __exit__(self, exc_type, exc, tb) -> None:
        if exc is not None and self._file is not None:
            line = str(exc).splitlines()[0] if str(exc) else ""
            self.event("fault", f"{type(exc).__name__}: {line}")
        self.close()


@dataclass
class LoggedTouch:
    """One touch as the log recorded it: finger, orientations and the readings in contact."""
    touch: int
    finger: str
    psi_center: float | None = None
    psi: list[float] = field(default_factory=list)
    readings: list[int] = field(default_factory=list)
    outcome: str | None = None  # from touch_end; None if the run stopped inside the touch


@dataclass
class LogContents:
    header: dict[str, Any]
    readings: list[dict[str, Any]]
    touches: list[LoggedTouch]
    events: list[dict[str, Any]]
    result: dict[str, Any] | None
    truncated: bool


def read_log(path: str | os.PathLike[str]) -> LogContents:
    """Parse a run log. A last line cut short by a crash is dropped (``truncated``);
    any other malformed line raises :class:`InputError` naming the line."""
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as exc:
        raise InputError(f"{path}: cannot read the log ({exc.strerror})") from None
    lines = text.split("\n")
    truncated = False
    if lines and lines[-1] == "":
        lines.pop()
    elif lines:
        truncated = True  # no final newline: the writer died mid-line
        lines.pop()
    records = _parse_lines(path, lines)
    if not records or records[0].get("type") != "header" or records[0].get("format") != LOG_FORMAT:
        raise InputError(f"{path}: line 1 is not a {LOG_FORMAT} header")
    if records[0].get("version") != LOG_VERSION:
        raise InputError(f"{path}: line 1: log version {records[0].get('version')!r}, this program reads {LOG_VERSION}")
    readings: list[dict[str, Any]] = []
    touches: dict[int, LoggedTouch] = {}
    events: list[dict[str, Any]] = []
    result = None
    for lineno, rec in enumerate(records[1:], start=2):
        kind = rec.get("type")
        if kind == "reading":
            if rec.get("i") != len(readings):
                raise InputError(f"{path}: line {lineno}: reading index {rec.get('i')!r}, expected {len(readings)}")
            readings.append(rec)
        elif kind in ("touch_start", "sample", "touch_end"):
            k = rec.get("touch")
            if not isinstance(k, int):
                raise InputError(f"{path}: line {lineno}: {kind} without an integer 'touch'")
            touch = touches.setdefault(k, LoggedTouch(touch=k, finger=str(rec.get("finger"))))
            if kind == "touch_start":
                touch.psi_center = rec.get("psi")
            elif kind == "sample":
                i = rec.get("reading")
                if not isinstance(i, int) or not 0 <= i < len(readings):
                    raise InputError(f"{path}: line {lineno}: sample names reading {i!r}, not yet logged")
                touch.readings.append(i)
                touch.psi.append(float(rec["psi"]))
            else:
                touch.outcome = str(rec.get("outcome", "ok"))
        elif kind == "event":
            events.append(rec)
        elif kind == "result":
            result = rec
        else:
            raise InputError(f"{path}: line {lineno}: unknown record type {kind!r}")
    return LogContents(header=records[0], readings=readings,
                       touches=[touches[k] for k in sorted(touches)],
                       events=events, result=result, truncated=truncated)


def _parse_lines(path: Path, lines: Iterable[str]) -> list[dict[str, Any]]:
    records = []
    for lineno, line in enumerate(lines, start=1):
        try:
            rec = json.loads(line)
        except json.JSONDecodeError as exc:
            raise InputError(f"{path}: line {lineno}: not JSON ({exc.msg})") from None
        if not isinstance(rec, dict):
            raise InputError(f"{path}: line {lineno}: not a JSON object")
        records.append(rec)
    return records
