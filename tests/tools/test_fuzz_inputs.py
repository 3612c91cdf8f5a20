"""Property-based fuzz of every reader of untrusted input: the recognition stream, the jaw
config, the scene and the run log. Whatever the input, the answer is a result or a
one-line InputError (``{"error": ...}`` in the stream), never another exception, and the
stream answers every non-blank line. tools/bench_fuzz.py is the 10,000-line benchmark."""

import io
import json
import sys
from pathlib import Path

import yaml
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from hand_driver.config import config_to_mapping, load_config, parse_config
from hand_driver.log import read_log
from recognizer.curves import Pose
from recognizer.scene import load_scene
from tactile_common.errors import InputError
from tools.bench_fuzz import json_paths, replace_at
from tools.bench_recognizer import exact_request
from tools.cli import main

ROOT = Path(__file__).resolve().parents[2]
GOOD = exact_request("ellipse", {"a": 28.6, "b": 17.3}, [0.36, 1.86, 4.23], Pose(0.3, 120.0, 15.0), False)
JAW = config_to_mapping(load_config(ROOT / "config/jaw.yaml"))
FAST = settings(max_examples=60, deadline=None, derandomize=True,
                suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large,
                                       HealthCheck.function_scoped_fixture])

scalars = (st.none() | st.booleans() | st.integers(-2 ** 70, 2 ** 70)
           | st.floats(allow_nan=True, allow_infinity=True) | st.text(max_size=12)
           | st.sampled_from(["circle", "ellipse", "/dev/zero", "a" * 3000, "config/scenes/all.yaml"]))
values = st.recursive(scalars, lambda c: st.lists(c, max_size=5) | st.dictionaries(st.text(max_size=8), c, max_size=5),
                      max_leaves=20)


@st.composite
def mutated(draw, base):
    """``base`` with the value at one path replaced by an arbitrary JSON-like value."""
    return replace_at(base, draw(st.sampled_from(list(json_paths(base)))), draw(values))


def _line(obj) -> bytes:
    return json.dumps(obj).encode()  # NaN / Infinity written as the tokens Python's json allows


REQUEST = {**GOOD, "scene": {"classes": ["circle", "ellipse"]}, "noise": {"phi": 0.001, "pos": 0.01},
           "options": {"alpha": 0.001, "timeout_s": 5}}
stream_lines = st.lists(mutated(REQUEST).map(_line)
                        | st.binary(max_size=120).map(lambda b: b.replace(b"\n", b" "))
                        | st.sampled_from([b"", b"   ", b"[" * 5000, b"1" * 5000, b'{"touches": [' + b"1," * 700 + b"1]}"]),
                        min_size=1, max_size=6)


@settings(FAST, max_examples=30)
@given(stream_lines)
def test_stream_answers_every_line(monkeypatch, capsys, lines):
    monkeypatch.setattr(sys, "stdin", io.TextIOWrapper(io.BytesIO(b"\n".join(lines) + b"\n")))
    assert main(["recognize", "--stream", "-"]) == 0
    out = capsys.readouterr().out.splitlines()
    assert len(out) == sum(1 for b in lines if b.strip())
    for answer in out:
        obj = json.loads(answer)
        assert ("class" in obj) != ("error" in obj)
        if "error" in obj:
            assert isinstance(obj["error"], str) and "\n" not in obj["error"]


def _one_line_or_ok(fn):
    try:
        return fn()
    except InputError as exc:
        assert "\n" not in str(exc)
        return None


@FAST
@given(mutated(JAW))
def test_config_reader(tmp_path_factory, obj):
    p = tmp_path_factory.mktemp("cfg") / "jaw.yaml"
    p.write_text(yaml.safe_dump(obj))
    _one_line_or_ok(lambda: load_config(p))
    _one_line_or_ok(lambda: parse_config(obj, "fuzz"))


SCENE = {"name": "s", "classes": ["circle", "ellipse"], "noise": {"phi": 0.001, "pos": 0.01},
         "object": {"class": "circle", "params": {"r": 20.0}, "pose": {"theta": 0.0, "x": 110.0, "y": 0.0}}}


@FAST
@given(mutated(SCENE), st.binary(max_size=200))
def test_scene_reader(tmp_path_factory, obj, raw):
    _one_line_or_ok(lambda: load_scene(obj))
    d = tmp_path_factory.mktemp("scene")
    (d / "a.yaml").write_bytes(raw)
    (d / "b.yaml").write_text(yaml.safe_dump(obj) if not isinstance(obj, float) else "x: 1\n")
    _one_line_or_ok(lambda: load_scene(str(d / "a.yaml")))
    _one_line_or_ok(lambda: load_scene(str(d / "b.yaml")))


LOG = [
    {"type": "header", "format": "tactile-jaw-log", "version": 1, "start_time": "t", "monotonic_origin": 0.0,
     "config": JAW, "scene": None, "versions": {}, "command": [], "settings": {}},
    {"type": "reading", "i": 0, "t": 0.1, "ticks": [2048] * 4, "current_ma": [1.0] * 4, "moving": [False] * 4},
    {"type": "touch_start", "touch": 0, "finger": "left", "psi": 0.5, "reading": 1},
    {"type": "sample", "touch": 0, "finger": "left", "psi": 0.5, "reading": 0},
    {"type": "touch_end", "touch": 0, "finger": "left", "reading": 1, "samples": 1, "outcome": "ok"},
    {"type": "event", "kind": "note", "message": "m"},
    {"type": "result", "recognition": None, "robot_time_s": 1.0},
]


@FAST
@given(st.integers(0, len(LOG) - 1), mutated({"r": 0}), st.integers(0, 10 ** 6), st.integers(0, 255))
def test_log_reader(tmp_path_factory, line, mutation, pos, byte):
    recs = [dict(r) for r in LOG]
    victim = recs[line]
    key = sorted(victim)[pos % len(victim)]
    victim[key] = mutation.get("r") if isinstance(mutation, dict) else mutation
    raw = bytearray("".join(json.dumps(r) + "\n" for r in recs).encode())
    d = tmp_path_factory.mktemp("log")
    (d / "a.jsonl").write_bytes(bytes(raw))
    _one_line_or_ok(lambda: read_log(d / "a.jsonl"))
    raw[pos % len(raw)] = byte  # and one flipped byte anywhere
    (d / "b.jsonl").write_bytes(bytes(raw))
    _one_line_or_ok(lambda: read_log(d / "b.jsonl"))
