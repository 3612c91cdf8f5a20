"""Reading untrusted bytes within stated limits: files of bounded size, strict UTF-8 and
JSON whose numbers and nesting are bounded. Every refusal is one-line :class:`InputError`
(exit 2), raised before the work the input would cost.

The limits (docs/formats.md states them for users):

- a number literal has at most :data:`MAX_NUMBER_CHARS` characters and an integer's
  magnitude is at most 2**53 (:data:`MAX_INT`: the integers every JSON reader holds exactly);
- JSON and YAML nest at most :data:`MAX_DEPTH` levels;
- a whole file read by :func:`read_bounded` has at most the size its reader states.
"""

from __future__ import annotations

import json
import math
import os
import stat
from pathlib import Path

from tactile_common.errors import InputError

__all__ = ["NumberLimit", "MAX_NUMBER_CHARS", "MAX_INT", "MAX_DEPTH", "MAX_PATH_CHARS", "read_bounded", "decode_utf8",
           "loads_json", "bracket_depth", "check_int", "check_path_text", "megabytes", "finite_number"]

MAX_NUMBER_CHARS = 64
MAX_INT = 2 ** 53
MAX_DEPTH = 32
MAX_PATH_CHARS = 1024


def megabytes(n: int) -> str:
    """A size for people: KiB below 1 MiB, else MiB."""
    return f"{n / 2 ** 10:.4g} KiB" if n < 2 ** 20 else f"{n / 2 ** 20:.4g} MiB"


class NumberLimit(Exception):
    """Raised from json's number hooks; turned into InputError with the caller's ``where``."""


def check_int(text: str) -> int:
    """An integer literal within the limits; :class:`NumberLimit` past them, ValueError if
    it is not an integer literal."""
    digits = sum(ch.isdigit() for ch in text[:MAX_NUMBER_CHARS + 1]) if len(text) <= MAX_NUMBER_CHARS else len(text)
    if digits > 20:
        raise NumberLimit(f"an integer of {digits} digits (|n| <= 2**53, write larger values as floats)")
    if len(text) > MAX_NUMBER_CHARS:
        raise NumberLimit(f"a number of {len(text)} characters (at most {MAX_NUMBER_CHARS})")
    value = int(text, 0) if text.lstrip("+-")[:2].lower() in ("0x", "0o", "0b") else int(text)
    if abs(value) > MAX_INT:
        raise NumberLimit(f"integer {value} beyond 2**53 (write larger values as floats)")
    return value


def _json_float(text: str) -> float:
    if len(text) > MAX_NUMBER_CHARS:
        raise NumberLimit(f"a number of {len(text)} characters (at most {MAX_NUMBER_CHARS})")
    return float(text)


def _json_constant(name: str):
    raise NumberLimit(f"{name}: numbers must be finite (JSON has no NaN or Infinity)")


_DECODER = json.JSONDecoder(parse_int=check_int, parse_float=_json_float, parse_constant=_json_constant)


def bracket_depth(text: str, quotes: str = '"') -> int:
    """Deepest ``[``/``{`` nesting of a text, outside strings delimited by ``quotes``."""
    depth = deepest = 0
    in_str = esc = False
    quote = ""
    for ch in text:
        if in_str:
            if esc:
                esc = False
            elif ch == "\\":
                esc = True
            elif ch == quote:
                in_str = False
        elif ch in quotes:
            in_str, quote = True, ch
        elif ch in "[{":
            depth += 1
            deepest = max(deepest, depth)
        elif ch in "]}":
            depth -= 1
    return deepest


def loads_json(text: str, where: str):
    """Decode one JSON document within the number and nesting limits."""
    if text.count("[") + text.count("{") > MAX_DEPTH and bracket_depth(text) > MAX_DEPTH:
        raise InputError(f"{where}: JSON nested deeper than {MAX_DEPTH} levels")
    try:
        return _DECODER.decode(text)
    except json.JSONDecodeError as exc:
        raise InputError(f"{where}: not valid JSON ({exc.msg} at line {exc.lineno} column {exc.colno})") from None
    except NumberLimit as exc:
        raise InputError(f"{where}: {exc}") from None
    except (ValueError, RecursionError) as exc:
        raise InputError(f"{where}: not valid JSON ({exc})") from None


def decode_utf8(raw: bytes, where: str) -> str:
    """Strict UTF-8, whatever the locale; the error names the first bad byte."""
    try:
        return raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise InputError(f"{where}: not valid UTF-8 (byte 0x{raw[exc.start]:02x} at offset {exc.start})") from None


def check_path_text(path, what: str) -> Path:
    """A path given as text: at most MAX_PATH_CHARS characters, no NUL."""
    text = str(path)
    if len(text) > MAX_PATH_CHARS:
        raise InputError(f"{what}: a path of {len(text)} characters (at most {MAX_PATH_CHARS})")
    if "\0" in text:
        raise InputError(f"{what}: a path with a NUL character")
    return Path(text)


def read_bounded(path, limit: int, what: str, *, regular_only: bool = True) -> bytes:
    """The bytes of ``path``, refused when larger than ``limit``: by size before reading a
    regular file, by a bounded read otherwise. ``regular_only`` refuses devices and pipes
    (``/dev/zero``, a FIFO nobody writes) without blocking on them."""
    p = check_path_text(path, what)
    try:
        fd = os.open(p, os.O_RDONLY | (os.O_NONBLOCK if regular_only else 0))
        with open(fd, "rb", closefd=True) as fh:
            st = os.fstat(fd)
            if regular_only and not stat.S_ISREG(st.st_mode):
                raise InputError(f"{p}: cannot read {what} (not a regular file)")
            if st.st_size > limit:
                raise InputError(f"{p}: {what} of {megabytes(st.st_size)} is over the {megabytes(limit)} limit")
            raw = fh.read(limit + 1)
    except InputError:
        raise
    except OSError as exc:
        raise InputError(f"{p}: cannot read {what} ({exc.strerror or exc})") from None
    if len(raw) > limit:
        raise InputError(f"{p}: {what} is over the {megabytes(limit)} limit")
    return raw


def finite_number(v, where: str) -> float:
    """``v`` as a float when it is a finite int or float (not a bool); else a one-line
    InputError naming ``where``. The one number check of the request and scene readers."""
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
        raise InputError(f"{where}: must be a finite number, got {v!r}")
    return float(v)
