"""Reading the project's YAML files (scenes, jaw configs) in one place, within limits.

Every failure is an :class:`~tactile_common.errors.InputError` of one line that names the
file, what it was meant to be, and (for a syntax error or a limit) the line. A file is
refused, in well under a second, when it is over :data:`MAX_YAML_BYTES`, holds more than
:data:`MAX_ALIASES` aliases (``*name``: a "billion laughs" bomb expands a few aliases into
gigabytes), nests deeper than :data:`~tactile_common.inputs.MAX_DEPTH` levels or writes an
integer beyond 2**53 (tactile_common.inputs.check_int).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import yaml

from tactile_common.errors import InputError
from tactile_common.inputs import MAX_DEPTH, NumberLimit, bracket_depth, check_int, decode_utf8, read_bounded

__all__ = ["read_yaml", "MAX_YAML_BYTES", "MAX_ALIASES"]

#: a jaw config is ~3 KB and a scene under 1 KB; the pure-Python parser reads 64 KiB in ~0.25 s
MAX_YAML_BYTES = 64 * 1024
MAX_ALIASES = 16


class _Limit(Exception):
    def __init__(self, message: str, mark=None):
        super().__init__(message)
        self.line = None if mark is None else mark.line + 1


class _BoundedLoader(yaml.SafeLoader):
    """PyYAML's safe loader with alias, depth and integer limits (checked while composing,
    before anything is built)."""

    def __init__(self, stream) -> None:
        super().__init__(stream)
        self._depth = 0
        self._aliases = 0

    def compose_node(self, parent, index):
        if self.check_event(yaml.AliasEvent):
            self._aliases += 1
            if self._aliases > MAX_ALIASES:
                raise _Limit(f"more than {MAX_ALIASES} aliases (*name)", self.peek_event().start_mark)
        self._depth += 1
        try:
            if self._depth > MAX_DEPTH:
                raise _Limit(f"nested deeper than {MAX_DEPTH} levels", self.peek_event().start_mark)
            return super().compose_node(parent, index)
        finally:
            self._depth -= 1


def _bounded_int(loader: _BoundedLoader, node):
    text = loader.construct_scalar(node).replace("_", "")
    if ":" in text:  # YAML 1.1 sexagesimal (1:30): PyYAML's own reading, kept within the limits
        value = yaml.SafeLoader.construct_yaml_int(loader, node)
        if abs(value) > 2 ** 53:
            raise _Limit("an integer beyond 2**53", node.start_mark)
        return value
    try:
        sign = -1 if text.startswith("-") else 1
        body = text.lstrip("+-")
        if body.startswith("0") and len(body) > 1 and body[1] in "0123456789":  # YAML 1.1 octal 017
            return sign * check_int("0o" + body[1:])
        return check_int(text)
    except NumberLimit as exc:
        raise _Limit(str(exc), node.start_mark) from None
    except ValueError:
        return yaml.SafeLoader.construct_yaml_int(loader, node)


_BoundedLoader.add_constructor("tag:yaml.org,2002:int", _bounded_int)


def read_yaml(path: str | Path, what: str) -> Any:
    """Parse ``path`` as YAML within the limits; ``what`` names the file's role in errors."""
    text = decode_utf8(read_bounded(path, MAX_YAML_BYTES, what), f"{path}: {what}")
    if text.count("[") + text.count("{") > MAX_DEPTH and bracket_depth(text, "\"'") > MAX_DEPTH:
        raise InputError(f"{path}: {what}: nested deeper than {MAX_DEPTH} levels")  # before PyYAML scans it all
    try:
        return yaml.load(text, Loader=_BoundedLoader)
    except _Limit as exc:
        where = f" at line {exc.line}" if exc.line is not None else ""
        raise InputError(f"{path}: {what}{where}: {exc}") from None
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        where = f" at line {mark.line + 1}" if mark is not None else ""
        raise InputError(f"{path}: not valid YAML{where}") from None
    except RecursionError:
        raise InputError(f"{path}: {what} nested too deeply") from None
