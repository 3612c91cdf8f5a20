"""The run log: JSON Lines, durable record by record, that proves it is whole.

One JSON object per line. The first line is the header, then, in the order they
happened:

- ``{"type": "header", "format": "tactile-jaw-log", "version": 2, "start_time": ISO-8601,
  "monotonic_origin": s, "config": {...}, "scene": {...}|null, "versions": {...},
  "command": [...], "settings": {...}}``
- ``{"type": "reading", "i": n, "t": s, "ticks": [...], "current_ma": [...]|null,
  "moving": [...]|null}`` — every joint reading taken, ``t`` on the monotonic clock of
  the header, ``i`` counting readings from 0; joint order is the config's (left finger's
  joints, then the right finger's).
- ``{"type": "touch_start", "touch": k, "finger": name, "psi": rad, "reading": i}`` —
  with ``"kind": "flat"`` for a flat press (hand_driver.flat_press; default "roll")
- ``{"type": "sample", "touch": k, "finger": name, "psi": rad, "reading": i}`` — reading
  ``i`` is an in-contact reading of touch ``k``: the pad line it gives is one sample of
  the rolling move.
- ``{"type": "touch_end", "touch": k, "finger": name, "reading": i, "samples": m, "outcome": str}`` —
  a flat press's also ``"roles"``: each sample's, P, Q, seat or scan
- ``{"type": "event", "kind": str, "message": str, ...}`` — faults, retries, no-contact
  results, progress.
- ``{"type": "result", "recognition": {the answer, docs/formats.md}, "robot_time_s": s}``
- ``{"type": "end"}`` — the last record of a log whose writer closed it (version 2).

Version 2 (docs/formats.md, run log): every record carries ``seq`` (its line number − 1)
and, as its last field, ``h``: 16 hex digits of BLAKE2b-64 over the previous record's
``h`` and this record's bytes without ``h`` (a hash chain). A reader tells a whole log
(ends with ``end``), a log cut by a crash (its last line cut mid-record, or no ``end``:
whole up to its last complete record) and damage ("line N: ..."). Version 1 logs (no
``seq``, ``h`` or ``end``) still read, unverified; the cross-checks of :func:`read_log`
(counts, references, order) apply to both.

Each record is written whole with one ``write`` on an unbuffered file, then fsync'd,
before :meth:`RunLog.write` returns, so a killed process, a crash or a pulled cable loses
nothing already logged (measured cost of one write + fsync: about 0.2 ms on the
development machine's ext4 disk; the hash adds ~2 µs). A write that fails (a full disk)
raises :class:`LogWriteError`, a :class:`~tactile_common.errors.DeviceFault`: the run
stops with torque off, and the log stays whole up to its last complete record.
"""

from __future__ import annotations

import datetime
import hashlib
import json
import math
import os
import platform
import re
import time
from dataclasses import dataclass, field
from importlib import metadata
from pathlib import Path
from typing import Any, Iterable

from hand_driver.config import JawConfig, parse_config
from tactile_common.errors import DeviceFault, InputError
from tactile_common.files import create_exclusive
from tactile_common.inputs import decode_utf8, loads_json, read_bounded

LOG_FORMAT = "tactile-jaw-log"
LOG_VERSION = 2
#: versions read_log reads: 1 (no seq, hash chain or end record: read unverified) and 2
READ_VERSIONS = (1, 2)
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


def chain_hash(previous: str, body: bytes) -> str:
    """The hash chain's link: BLAKE2b-64 (16 hex digits) of the previous record's ``h`` and
    this record's bytes without ``h``."""
    return hashlib.blake2b(previous.encode("ascii") + body, digest_size=8).hexdigest()


class LogWriteError(DeviceFault):
    """The run log could not be written (a full disk, an I/O error): the run stops, torque
    off; the log is whole up to its last complete record."""


class RunLog:
    """Append-only JSON Lines log with a hash chain; use as a context manager.

    ``RunLog(path).open(header_fields)`` writes the header; :meth:`reading` is shaped to be
    passed as the bus's ``on_reading`` callback; :meth:`close` writes the ``end`` record.
    """

    def __init__(self, path: str | os.PathLike[str]) -> None:
        self.path = Path(path)
        self._file = None
        self._hash = ""
        self._failed: str | None = None
        self.records = 0
        self.readings = 0
        self.monotonic_origin = 0.0

    def open(self, *, config: dict[str, Any], scene: dict[str, Any] | None,
             command: list[str] | None = None, settings: dict[str, Any] | None = None,
             force: bool = False) -> "RunLog":
        """Create the file and write the header; an existing file is refused unless ``force``,
        and anything but a regular file even then (tactile_common.files.create_exclusive)."""
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
        """Append one record (with its ``seq`` and ``h``) in one write, and fsync it;
        :class:`LogWriteError` when the file cannot take it."""
        if self._file is None:
            raise RuntimeError("RunLog.write before open")
        if self._failed is not None:
            raise LogWriteError(self._failed)
        plain = _plain(record)
        rec = {"type": plain.get("type"), "seq": self.records,
               **{k: v for k, v in plain.items() if k not in ("type", "seq", "h")}}
        body = json.dumps(rec, separators=(",", ":"), allow_nan=False).encode("ascii")
        h = chain_hash(self._hash, body)
        line = body[:-1] + b',"h":"' + h.encode("ascii") + b'"}\n'
        try:
            view = memoryview(line)
            while view:
                view = view[self._file.write(view):]
            os.fsync(self._file.fileno())
        except OSError as exc:
            self._failed = (f"--log {self.path}: cannot write the run log ({exc.strerror or exc}); "
                            f"the run stopped, the log is whole up to record {self.records - 1}")
            raise LogWriteError(self._failed) from None
        self._hash = h
        self.records += 1

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
        """Write the ``end`` record (unless a write failed) and close the file."""
        if self._file is None:
            return
        try:
            if self._failed is None:
                self.write({"type": "end"})
        finally:
            self._file.close()
            self._file = None

    def __enter__(self) -> "RunLog":
        return self

    def __exit__(self, exc_type, exc, tb) -> None:
        if exc is not None and self._file is not None and self._failed is None:
            line = str(exc).splitlines()[0] if str(exc) else ""
            try:
                self.event("fault", f"{type(exc).__name__}: {line}")
            except LogWriteError:
                pass  # the exception already on its way says what stopped the run
        try:
            self.close()
        except LogWriteError:
            if exc is None:
                raise


@dataclass
class LoggedTouch:
    """One touch as the log recorded it: finger, orientations and the readings in contact."""
    touch: int
    finger: str
    psi_center: float | None = None
    psi: list[float] = field(default_factory=list)
    readings: list[int] = field(default_factory=list)
    outcome: str | None = None  # from touch_end; None if the run stopped inside the touch
    kind: str = "roll"  # touch_start's kind: "roll" (a rolling touch) or "flat" (a flat press)
    roles: list[str] = field(default_factory=list)  # a flat press's sample roles (P, Q, seat, scan), from touch_end


@dataclass
class LogContents:
    header: dict[str, Any]
    readings: list[dict[str, Any]]
    touches: list[LoggedTouch]
    events: list[dict[str, Any]]
    result: dict[str, Any] | None
    #: the log does not end as its writer closed it: ``cut`` says how (its last line cut
    #: mid-record, or no ``end`` record); everything read before is whole
    truncated: bool
    #: the header's jaw config, parsed once by :func:`read_log`; None when it is not a valid
    #: one (``config_error`` says why: :meth:`jaw_config` raises it)
    config: JawConfig | None = None
    config_error: str | None = None
    version: int = LOG_VERSION
    #: the hash chain and the record numbers were checked (version 2; a version 1 log has neither)
    verified: bool = False
    #: why the log counts as cut (None when it ends with its ``end`` record, or is version 1)
    cut: str | None = None
    #: complete records read (lines, the header included)
    records: int = 0

    def integrity(self) -> str:
        """One sentence for people: whole and verified, cut (where), or not verifiable."""
        if not self.verified:
            return (f"version {self.version} log: it carries no record numbers or hash chain, so it cannot be "
                    f"verified (read as it is: {self.records} records)"
                    + (f"; the run was cut: {self.cut}" if self.cut else ""))
        if self.cut:
            return f"the run was cut: {self.cut}; the {self.records} records before are whole (hash chain verified)"
        return f"whole: {self.records} records, hash chain verified, closed by its end record"

    def jaw_config(self) -> JawConfig:
        """The header's jaw config; InputError naming what is wrong when it is not a valid one."""
        if self.config is None:
            raise InputError(self.config_error or "the log's header has no jaw config")
        return self.config


#: a 10-minute exploration logs ~10 MB; the header (config and scene) is a few kB
MAX_LOG_BYTES = 256 * 2 ** 20
MAX_LINE_BYTES = 4 * 2 ** 20
#: Dynamixel Present Position is a signed 32-bit register
_TICK_RANGE = (-2 ** 31, 2 ** 31 - 1)


class _Check:
    """Field checks of one record; each failure is one line naming the log, line and field."""

    def __init__(self, path: Path, lineno: int, rec: dict) -> None:
        self.where, self.rec = f"{path}: line {lineno}", rec

    def fail(self, msg: str) -> None:
        raise InputError(f"{self.where}: {msg}")

    def get(self, key: str, kinds: tuple, what: str, *, optional: bool = False):
        if key not in self.rec:
            if optional:
                return None
            self.fail(f"{self.rec.get('type')} without {key!r}")
        v = self.rec[key]
        if optional and v is None:
            return None
        ok = isinstance(v, kinds) and not (isinstance(v, bool) and bool not in kinds)
        if ok and isinstance(v, float) and not math.isfinite(v):
            ok = False
        if not ok:
            self.fail(f"{key} must be {what}, got {_short(v)}")
        return v

    def integer(self, key: str, lo: int, hi: int, *, optional: bool = False) -> int | None:
        v = self.get(key, (int,), "an integer", optional=optional)
        if v is not None and not lo <= v <= hi:
            self.fail(f"{key} {v} outside [{lo}, {hi}]")
        return v

    def number(self, key: str, *, optional: bool = False) -> float | None:
        return self.get(key, (int, float), "a finite number", optional=optional)

    def values(self, key: str, n: int | None, kinds: tuple, what: str, *, nulls: bool = False,
               optional: bool = False) -> list | None:
        v = self.get(key, (list,), f"a list of {what}", optional=optional)
        if v is None:
            return None
        if n is not None and len(v) != n:
            self.fail(f"{key} has {len(v)} values, the jaw has {n} joints")
        for j, e in enumerate(v):
            if e is None and nulls:
                continue
            if isinstance(e, bool) and bool not in kinds or not isinstance(e, kinds) \
                    or isinstance(e, float) and not math.isfinite(e):
                self.fail(f"{key}[{j}] must be {what}, got {_short(e)}")
        return v


def _short(v: Any) -> str:
    text = repr(v)
    return text if len(text) <= 40 else text[:37] + "..."


def _header_config(path: Path, header: dict) -> tuple[JawConfig | None, str | None]:
    """The header's jaw config, or None and why it is not one: the log is still read
    (its records are checked without the jaw's shape), and replay refuses it."""
    try:
        return parse_config(header.get("config"), f"{path}: header config", recorded=True), None
    except InputError as exc:
        return None, str(exc)


_HASH_TAIL = re.compile(rb',"h":"([0-9a-f]{16})"\}\Z')
#: what a log may hold after its ``result`` record (the documented tail): a ``fault`` event
#: (raised while the run was closing) and the ``end`` record
_AFTER_RESULT = ("event", "end")


def read_log(path: str | os.PathLike[str]) -> LogContents:
    """Parse and verify a run log, read as bytes and decoded strictly (UTF-8).

    A version 2 log's record numbers and hash chain are checked line by line; a log whose
    last line was cut mid-record (no final newline) or that lacks its ``end`` record is read
    up to its last complete record and marked cut (``truncated``, ``cut``). Any other damage
    raises :class:`InputError` "LOG: line N: ...": bad bytes, JSON, a record out of sequence
    or not what was written, a record type or field wrong, or a cross-check failed (a
    touch's samples differ from its ``touch_end`` count, a reading referenced before it was
    logged or out of order, a touch's finger changing, a record after ``result`` other than
    the documented tail). Version 1 logs are read with the same checks, unverified. Files
    over :data:`MAX_LOG_BYTES` are refused."""
    path = Path(path)
    raw = read_bounded(path, MAX_LOG_BYTES, "the log")
    lines = raw.split(b"\n")
    cut = None
    if lines and lines[-1] == b"":
        lines.pop()
    elif lines:
        lines.pop()  # no final newline: the writer died mid-line
        cut = f"its last line ({len(lines) + 1}) was cut mid-record"
    records = _parse_lines(path, lines)
    if not records or records[0].get("type") != "header" or records[0].get("format") != LOG_FORMAT:
        raise InputError(f"{path}: line 1 is not a {LOG_FORMAT} header")
    header = records[0]
    version = header.get("version")
    if version not in READ_VERSIONS or isinstance(version, bool):
        raise InputError(f"{path}: line 1: log version {_short(version)}, this program reads "
                         f"{', '.join(map(str, READ_VERSIONS))}")
    if version >= 2:
        _verify_chain(path, lines, records)
        if records[-1].get("type") != "end" and cut is None:
            cut = f"it ends at line {len(records)} without its end record (the writer was stopped)"
    c = _Check(path, 1, header)
    c.get("config", (dict,), "a mapping")
    c.get("scene", (dict,), "a mapping or null", optional=True)
    c.get("settings", (dict,), "a mapping", optional=True)
    c.number("monotonic_origin", optional=True)
    config, config_error = _header_config(path, header)
    n_joints = len(config.joints) if config else None
    fingers = {f.name for f in config.fingers} if config else None
    readings: list[dict[str, Any]] = []
    touches: dict[int, LoggedTouch] = {}
    start_reading: dict[int, int] = {}
    ended: set[int] = set()
    events: list[dict[str, Any]] = []
    result = None
    result_line = 0
    last_t = -math.inf
    for lineno, rec in enumerate(records[1:], start=2):
        c = _Check(path, lineno, rec)
        kind = rec.get("type")
        if result is not None and kind not in _AFTER_RESULT:
            c.fail(f"a {_short(kind)} record after the result (line {result_line}); only a fault event and "
                   f"the end record may follow it")
        if kind == "reading":
            if rec.get("i") != len(readings) or isinstance(rec.get("i"), bool):
                c.fail(f"reading index {_short(rec.get('i'))}, expected {len(readings)}")
            t = c.number("t", optional=True)  # the writer logs a non-finite clock as null
            if t is not None:
                if t < last_t:
                    c.fail(f"reading time {t} is before the previous reading's ({last_t}): readings out of order")
                last_t = t
            ticks = c.values("ticks", n_joints, (int,), "integer ticks")
            if n_joints is None and readings and len(ticks) != len(readings[0]["ticks"]):
                c.fail(f"ticks has {len(ticks)} values, the first reading {len(readings[0]['ticks'])}")
            if any(not _TICK_RANGE[0] <= t <= _TICK_RANGE[1] for t in ticks):
                c.fail("ticks outside the servo's 32-bit position range")
            c.values("current_ma", len(ticks), (int, float), "numbers", nulls=True, optional=True)
            c.values("moving", len(ticks), (bool, int), "booleans", optional=True)
            readings.append(rec)
        elif kind in ("touch_start", "sample", "touch_end"):
            _touch_record(c, kind, rec, touches, start_reading, ended, fingers, len(readings))
        elif kind == "event":
            c.get("kind", (str,), "a string")
            c.get("message", (str,), "a string")
            if result is not None and rec.get("kind") != "fault":
                c.fail(f"a {_short(rec.get('kind'))} event after the result (line {result_line}); only a fault "
                       f"event and the end record may follow it")
            events.append(rec)
        elif kind == "result":
            if result is not None:
                c.fail(f"a second result (the first is line {result_line})")
            c.get("recognition", (dict,), "a mapping or null", optional=True)
            c.number("robot_time_s", optional=True)
            result, result_line = rec, lineno
        elif kind == "end" and version >= 2:
            if lineno != len(records):
                c.fail("records after the end record")
        else:
            c.fail(f"unknown record type {_short(kind)}")
    return LogContents(header=header, readings=readings,
                       touches=[touches[k] for k in sorted(touches)],
                       events=events, result=result, truncated=cut is not None, config=config,
                       config_error=config_error, version=version, verified=version >= 2, cut=cut,
                       records=len(records))


def _touch_record(c: "_Check", kind: str, rec: dict, touches: dict, start_reading: dict, ended: set,
                  fingers: set | None, n_readings: int) -> None:
    """One touch_start / sample / touch_end record, checked against the touch so far."""
    k = c.integer("touch", 0, 10 ** 9)
    finger = c.get("finger", (str,), "a finger name")
    if fingers is not None and finger not in fingers:
        c.fail(f"finger {_short(finger)} is not one of the header config's ({', '.join(sorted(fingers))})")
    if kind == "touch_start":
        if k in touches:
            c.fail(f"touch {k} starts a second time")
        touch = touches[k] = LoggedTouch(touch=k, finger=finger)
        touch.psi_center = float(c.number("psi"))
        start_reading[k] = c.integer("reading", 0, n_readings - 1, optional=True) or 0
        touch.kind = c.get("kind", (str,), "a string", optional=True) or "roll"
        if touch.kind not in ("roll", "flat"):
            c.fail(f"touch kind {_short(touch.kind)}, expected roll or flat")
        return
    touch = touches.get(k)
    if touch is None:
        c.fail(f"a {kind} of touch {k}, which has no touch_start before it")
    if touch.finger != finger:
        c.fail(f"touch {k} was felt by {touch.finger}, this record says {finger}")
    if k in ended:
        c.fail(f"a {kind} of touch {k} after its touch_end")
    if kind == "sample":
        i = rec.get("reading")
        if isinstance(i, bool) or not isinstance(i, int) or not 0 <= i < n_readings:
            c.fail(f"sample names reading {_short(i)}, not yet logged")
        if i < start_reading[k]:
            c.fail(f"sample names reading {i}, before its touch started (reading {start_reading[k]})")
        if touch.readings and i <= touch.readings[-1]:
            c.fail(f"sample names reading {i}, not after the touch's previous sample (reading {touch.readings[-1]})")
        psi = float(c.number("psi"))
        touch.readings.append(i)
        touch.psi.append(psi)
        return
    c.integer("reading", 0, n_readings - 1, optional=True)
    expected = c.integer("samples", 0, 10 ** 6, optional=True)
    if expected is not None and expected != len(touch.readings):
        c.fail(f"touch_end counts {expected} samples, the log holds {len(touch.readings)} for touch {k}")
    touch.outcome = c.get("outcome", (str,), "a string", optional=True) or "ok"
    ended.add(k)
    if touch.kind == "flat":
        roles = c.get("roles", (list,), "a list of sample roles")
        if len(roles) != len(touch.readings) or any(r not in ("P", "Q", "seat", "scan") for r in roles):
            c.fail(f"roles must name P, Q, seat or scan for each of the touch's {len(touch.readings)} samples")
        touch.roles = list(roles)


def _verify_chain(path: Path, lines: list[bytes], records: list[dict[str, Any]]) -> None:
    """Each record's ``seq`` is its line number − 1 and its ``h`` follows from the previous
    record's (module docstring); the first line that does not is named."""
    previous = ""
    for lineno, (line, rec) in enumerate(zip(lines, records), start=1):
        where = f"{path}: line {lineno}"
        seq = rec.get("seq")
        if seq != lineno - 1 or isinstance(seq, bool):
            hint = ("a record is missing before it" if isinstance(seq, int) and not isinstance(seq, bool)
                    and seq > lineno - 1 else "a record is repeated or moved" if isinstance(seq, int) else
                    "not a record as written")
            raise InputError(f"{where}: record number {_short(seq)}, expected {lineno - 1} ({hint})")
        m = _HASH_TAIL.search(line)
        if m is None:
            raise InputError(f"{where}: no hash at the end of the record (\"h\", the last field): not as written")
        h = m.group(1).decode("ascii")
        if chain_hash(previous, line[:m.start()] + b"}") != h:
            raise InputError(f"{where}: the record is not what was written (its hash does not follow from "
                             f"line {lineno - 1}'s)" if lineno > 1 else f"{where}: the header is not what was "
                             f"written (its hash does not match)")
        previous = h


def _parse_lines(path: Path, lines: Iterable[bytes]) -> list[dict[str, Any]]:
    records = []
    for lineno, line in enumerate(lines, start=1):
        where = f"{path}: line {lineno}"
        if len(line) > MAX_LINE_BYTES:
            raise InputError(f"{where}: a line of {len(line)} bytes (at most {MAX_LINE_BYTES})")
        rec = loads_json(decode_utf8(line, where), where)
        if not isinstance(rec, dict):
            raise InputError(f"{where}: not a JSON object")
        records.append(rec)
    return records
