"""Reading the project's YAML files (scenes, jaw configs, calibrated configs) in one place,
strictly and within limits.

Strict:

- **YAML 1.2 core-schema scalars**, not PyYAML's YAML 1.1: ``true``/``false`` are the only
  booleans, ``null``/``~``/nothing the only nulls, integers are decimal (``[-+]?[0-9]+``)
  and floats the core forms (``1.5``, ``1e-3``, ``.5``, ``.inf``, ``.nan``). No timestamps,
  no merge keys (``<<``). A plain scalar that YAML 1.1 read as something else — ``1:30``
  (sexagesimal 90), ``0x10``, ``0o17``, ``017`` (octal), ``1_000``, ``yes``/``no``/``on``/
  ``off`` — is refused, naming its line and what YAML 1.1 made of it: quote it for text,
  or write the number (``90``, ``16``) or ``true``/``false``. Nothing is read silently
  otherwise than its author meant under either version.
- **Duplicate keys** in a mapping are refused, naming the key and both lines (PyYAML keeps
  the last silently); so is a key **without a value** (``object:`` and nothing: what a file
  cut short after a key leaves; no key of the project's formats takes null), and a file
  whose last line has no newline (what a file cut mid-line leaves; every editor's file
  ends with one, or can).
- A file's refusals by its format (a missing key, a value out of range) name the line of
  the key they are about: :func:`read_yaml_located` returns a :class:`YamlLines` whose
  :meth:`~YamlLines.errors` adds "line N" to the format's one-line errors.

Within limits (one line, in well under a second): files over :data:`MAX_YAML_BYTES`, more
than :data:`MAX_ALIASES` aliases (``*name``: a "billion laughs" bomb expands a few aliases
into gigabytes), nesting deeper than :data:`~tactile_common.inputs.MAX_DEPTH` levels,
integers beyond 2**53 and number literals over 64 characters
(tactile_common.inputs.check_int).

Why PyYAML still: its scanner and parser are YAML 1.2-compatible for the block and flow
syntax our files use; what differs between the versions is the schema (how plain scalars
resolve), which PyYAML lets a loader replace (its implicit resolvers and constructors).
A YAML 1.2 library (ruamel.yaml) would be one more dependency for the same result.
"""

from __future__ import annotations

import contextlib
import math
import re
from pathlib import Path
from typing import Any, Iterator

import yaml

from tactile_common.errors import InputError
from tactile_common.inputs import MAX_DEPTH, MAX_NUMBER_CHARS, NumberLimit, bracket_depth, check_int, read_bounded

__all__ = ["read_yaml", "read_yaml_located", "YamlLines", "MAX_YAML_BYTES", "MAX_ALIASES"]

#: a jaw config is ~3 KB and a scene under 1 KB; the pure-Python parser reads 64 KiB in ~0.25 s
MAX_YAML_BYTES = 64 * 1024
MAX_ALIASES = 16

_STR, _INT, _FLOAT, _BOOL, _NULL = (f"tag:yaml.org,2002:{t}" for t in ("str", "int", "float", "bool", "null"))
#: YAML 1.2 core schema (https://yaml.org/spec/1.2.2/#1032-tag-resolution), integers decimal only
_CORE = (
    (_BOOL, r"true|True|TRUE|false|False|FALSE", "tTfF"),
    (_INT, r"[-+]?[0-9]+", "-+0123456789"),
    (_FLOAT, r"[-+]?(?:\.[0-9]+|[0-9]+(?:\.[0-9]*)?)(?:[eE][-+]?[0-9]+)?|[-+]?\.(?:inf|Inf|INF)|\.(?:nan|NaN|NAN)",
     "-+0123456789."),
    (_NULL, r"~|null|Null|NULL|", ["~", "n", "N", ""]),
)
#: what YAML 1.1 (PyYAML's default resolver) made of a plain scalar
_YAML11 = yaml.resolver.Resolver.yaml_implicit_resolvers
_KIND = {_BOOL: "a boolean", _INT: "an integer", _FLOAT: "a number"}


class _Limit(Exception):
    def __init__(self, message: str, mark=None):
        super().__init__(message)
        self.line = None if mark is None else mark.line + 1


def _yaml11_tag(text: str) -> str | None:
    for tag, regexp in _YAML11.get(text[:1], []):
        if regexp.match(text):
            return tag
    return None


def _refuse_yaml11(text: str, node, kind_tag: str) -> None:
    try:
        was = yaml.safe_load(text) if len(text) <= 24 else None  # a long one is not worth computing
    except yaml.YAMLError:
        was = None
    shown = text if len(text) <= 24 else text[:21] + "..."
    if kind_tag == _BOOL:
        advice, value = f"write {'true' if was else 'false'}", f" ({was!r})"
    elif isinstance(was, (int, float)) and not isinstance(was, bool):
        advice, value = f"write the number ({was!r})", f" ({was!r})"
    else:
        advice, value = "write a decimal number", ""
    raise _Limit(f"{shown!r} is text in YAML 1.2, {_KIND[kind_tag]}{value} in YAML 1.1; {advice}, or quote it "
                 f"if it is text", node.start_mark)


class _StrictLoader(yaml.SafeLoader):
    """PyYAML's safe loader with the YAML 1.2 core schema (module docstring), duplicate keys
    refused, alias, depth and number limits (checked while composing, before anything is
    built), and every mapping's and list's line numbers kept (:class:`YamlLines`)."""

    yaml_implicit_resolvers: dict = {}

    def __init__(self, stream) -> None:
        super().__init__(stream)
        self._depth = 0
        self._aliases = 0
        #: id(mapping or list) -> (its first line, {key or index: line})
        self.lines: dict[int, tuple[int, dict]] = {}

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


for _tag, _regexp, _first in _CORE:
    _StrictLoader.add_implicit_resolver(_tag, re.compile(rf"^(?:{_regexp})$"), list(_first))


def _core_int(loader: _StrictLoader, node) -> int:
    text = loader.construct_scalar(node)
    body = text.lstrip("+-")
    if len(body) > 1 and body[0] == "0" and node.style is None:
        raise _Limit(f"{text!r}: a leading zero (YAML 1.1 read it as octal {yaml.safe_load(text)!r}, YAML 1.2 as "
                     f"{int(text)}); write the number without it", node.start_mark)
    try:
        return check_int(text)
    except NumberLimit as exc:
        raise _Limit(str(exc), node.start_mark) from None


def _core_float(loader: _StrictLoader, node) -> float:
    text = loader.construct_scalar(node)
    if len(text) > MAX_NUMBER_CHARS:
        raise _Limit(f"a number of {len(text)} characters (at most {MAX_NUMBER_CHARS})", node.start_mark)
    low = text.lower()
    if low.endswith(".inf"):
        return -math.inf if low.startswith("-") else math.inf
    if low == ".nan":
        return math.nan
    return float(text)


def _core_str(loader: _StrictLoader, node) -> str:
    text = loader.construct_scalar(node)
    if node.style is None:  # plain: what YAML 1.1 made of it must be what it is now
        was = _yaml11_tag(text)
        if was in _KIND:
            _refuse_yaml11(text, node, was)
    return text


def _core_map(loader: _StrictLoader, node) -> Iterator[dict]:
    data: dict = {}
    yield data
    lines: dict = {}
    for key_node, value_node in node.value:
        key = loader.construct_object(key_node, deep=True)
        try:
            hash(key)
        except TypeError:
            raise _Limit("a mapping key that is a list or a mapping", key_node.start_mark) from None
        if key in lines:
            raise _Limit(f"duplicate key {key!r} (lines {lines[key]} and {key_node.start_mark.line + 1}); a key may "
                         f"appear once in a mapping", key_node.start_mark)
        lines[key] = key_node.start_mark.line + 1
        if value_node.tag == _NULL:
            raise _Limit(f"{key!r} has no value (a file cut short, or a value left out): write it, or delete the "
                         f"key", key_node.start_mark)
        data[key] = loader.construct_object(value_node, deep=True)
    loader.lines[id(data)] = (node.start_mark.line + 1, lines)


def _core_seq(loader: _StrictLoader, node) -> Iterator[list]:
    data: list = []
    yield data
    data.extend(loader.construct_object(child, deep=True) for child in node.value)
    loader.lines[id(data)] = (node.start_mark.line + 1, {k: c.start_mark.line + 1 for k, c in enumerate(node.value)})


for _tag, _fn in ((_INT, _core_int), (_FLOAT, _core_float), (_STR, _core_str), ("tag:yaml.org,2002:map", _core_map),
                  ("tag:yaml.org,2002:seq", _core_seq)):
    _StrictLoader.add_constructor(_tag, _fn)
for _tag in ("tag:yaml.org,2002:timestamp", "tag:yaml.org,2002:set", "tag:yaml.org,2002:omap",
             "tag:yaml.org,2002:pairs", "tag:yaml.org,2002:binary", "tag:yaml.org,2002:merge"):
    _StrictLoader.yaml_constructors.pop(_tag, None)  # YAML 1.1 types: an explicit tag of one is an error


_KEY_PATH = re.compile(r"[^.\[\]]+|\[\d+\]")


class YamlLines:
    """Where each key and item of a file's YAML tree was written: the line of a dotted key
    path (``fingers[0].base.x``), or of the deepest part of it the file has."""

    def __init__(self, root: Any, lines: dict[int, tuple[int, dict]]) -> None:
        self.root, self._lines = root, lines

    def line_of(self, key_path: str) -> int | None:
        node, line = self.root, None
        first = self._lines.get(id(node))
        if first is not None:
            line = first[0]
        for token in _KEY_PATH.findall(key_path.strip()):
            entry = self._lines.get(id(node))
            if entry is None:
                break
            key: Any = int(token[1:-1]) if token.startswith("[") and isinstance(node, list) else token.strip()
            if key not in entry[1]:
                break
            line, node = entry[1][key], node[key]
        return line

    @contextlib.contextmanager
    def errors(self, source: str) -> Iterator[None]:
        """Add "line N" to a one-line :class:`InputError` "SOURCE: key.path: ..." raised inside:
        the line of that key, or of the deepest mapping on its path the file has (a missing key)."""
        try:
            yield
        except InputError as exc:
            text = str(exc)
            prefix = f"{source}: "
            if not text.startswith(prefix) or text[len(prefix):].startswith("line "):
                raise
            rest = text[len(prefix):]
            line = self.line_of(rest.split(": ", 1)[0] if ": " in rest else "") or 1  # a scalar document: line 1
            raise InputError(f"{prefix}line {line}: {rest}") from None


def _load(path: str | Path, what: str) -> tuple[Any, dict]:
    raw = read_bounded(path, MAX_YAML_BYTES, what)
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        line = raw[:exc.start].count(b"\n") + 1
        raise InputError(f"{path}: {what} at line {line}: not valid UTF-8 (byte 0x{raw[exc.start]:02x} at offset "
                         f"{exc.start})") from None
    if text and not text.endswith("\n"):
        raise InputError(f"{path}: {what} at line {text.count(chr(10)) + 1}: the file does not end with a newline, "
                         f"as a file cut short does; if it is whole, end its last line")
    if text.count("[") + text.count("{") > MAX_DEPTH and bracket_depth(text, "\"'") > MAX_DEPTH:
        raise InputError(f"{path}: {what}: nested deeper than {MAX_DEPTH} levels")  # before PyYAML scans it all
    try:
        loader = _StrictLoader(text)
    except yaml.reader.ReaderError as exc:  # a control character: PyYAML checks them all first
        line = text[:exc.position].count("\n") + 1
        raise InputError(f"{path}: {what} at line {line}: a control character (#x{exc.character:04x}) YAML does "
                         f"not allow") from None
    try:
        return loader.get_single_data(), loader.lines
    except _Limit as exc:
        where = f" at line {exc.line}" if exc.line is not None else ""
        raise InputError(f"{path}: {what}{where}: {exc}") from None
    except yaml.constructor.ConstructorError as exc:
        mark = exc.problem_mark
        where = f" at line {mark.line + 1}" if mark is not None else ""
        raise InputError(f"{path}: {what}{where}: {str(exc.problem).splitlines()[0]} (a YAML 1.1 type or a tag "
                         f"this reader does not take)") from None
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        where = f" at line {mark.line + 1}" if mark is not None else ""
        raise InputError(f"{path}: not valid YAML{where}") from None
    except RecursionError:
        raise InputError(f"{path}: {what} nested too deeply") from None
    finally:
        loader.dispose()


def read_yaml(path: str | Path, what: str) -> Any:
    """Parse ``path`` as strict YAML within the limits; ``what`` names the file's role in errors."""
    return _load(path, what)[0]


def read_yaml_located(path: str | Path, what: str) -> tuple[Any, YamlLines]:
    """:func:`read_yaml` and where each key was written (:class:`YamlLines`)."""
    obj, lines = _load(path, what)
    return obj, YamlLines(obj, lines)
