"""A damaged run log is answered "line N: ..." (InputError, exit 2), never a traceback or a
quiet wrong answer: bytes decoded strictly, every field of every record checked."""

import json
from pathlib import Path

import pytest

from hand_driver.config import config_to_mapping, load_config
from hand_driver.log import read_log
from tactile_common.errors import InputError
from tools.cli import main

ROOT = Path(__file__).resolve().parents[2]
CONFIG = config_to_mapping(load_config(ROOT / "config/jaw.yaml"))
N = sum(len(f["joints"]) for f in CONFIG["fingers"])
FINGER = CONFIG["fingers"][0]["name"]


def _records():
    return [
        {"type": "header", "format": "tactile-jaw-log", "version": 1, "start_time": "t", "monotonic_origin": 0.0,
         "config": CONFIG, "scene": None, "versions": {}, "command": [], "settings": {}},
        {"type": "reading", "i": 0, "t": 0.1, "ticks": [2048] * N, "current_ma": [1.0] * N, "moving": [False] * N},
        {"type": "touch_start", "touch": 0, "finger": FINGER, "psi": 0.5, "reading": 0},
        {"type": "reading", "i": 1, "t": 0.2, "ticks": [2050] * N, "current_ma": None, "moving": None},
        {"type": "sample", "touch": 0, "finger": FINGER, "psi": 0.5, "reading": 1},
        {"type": "touch_end", "touch": 0, "finger": FINGER, "reading": 1, "samples": 1, "outcome": "ok"},
        {"type": "event", "kind": "note", "message": "m"},
    ]


def _write(path, records):
    path.write_text("".join(json.dumps(r) + "\n" for r in records))


def test_valid_log_reads(tmp_path):
    _write(tmp_path / "l.jsonl", _records())
    c = read_log(tmp_path / "l.jsonl")
    assert len(c.readings) == 2 and c.touches[0].psi == [0.5]
    assert c.jaw_config() == c.config == load_config(ROOT / "config/jaw.yaml")  # parsed once, by the reader


def test_header_without_a_jaw_config_is_read_and_refused_by_replay(tmp_path, capsys):
    """The records are still checked (without the jaw's shape); replay refuses the log with
    the config parser's one line, once."""
    recs = _records()
    recs[0]["config"] = {**CONFIG, "fingers": CONFIG["fingers"][:1]}
    p = tmp_path / "l.jsonl"
    _write(p, recs)
    c = read_log(p)
    assert c.config is None and len(c.readings) == 2
    with pytest.raises(InputError, match=r"l\.jsonl: header config: fingers: expected a list of exactly 2 fingers$"):
        c.jaw_config()
    assert main(["replay", str(p)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "header config: fingers: expected a list of exactly 2 fingers" in err


@pytest.mark.parametrize("line,change,msg", [
    (4, lambda r: r.pop("psi"), "sample without 'psi'"),
    (4, lambda r: r.update(psi="x"), "psi must be a finite number"),
    (1, lambda r: r.update(ticks=["a"] * N), r"ticks\[0\] must be integer ticks"),
    (1, lambda r: r.update(ticks=[1e308] * N), r"ticks\[0\] must be integer ticks"),
    (1, lambda r: r.update(ticks=[None] * N), r"ticks\[0\] must be integer ticks"),
    (1, lambda r: r.update(ticks=[2048] * (N - 1)), f"ticks has {N - 1} values, the jaw has {N} joints"),
    (1, lambda r: r.update(ticks=[2 ** 40] * N), "ticks outside the servo.s 32-bit"),
    (1, lambda r: r.update(current_ma=[1.0]), "current_ma has 1 values"),
    (1, lambda r: r.update(moving=["yes"] * N), r"moving\[0\] must be booleans"),
    (1, lambda r: r.update(i=True), "reading index True"),
    (2, lambda r: r.update(finger="thumb"), "finger 'thumb' is not one of"),
    (2, lambda r: r.update(touch=-1), r"touch -1 outside"),
    (5, lambda r: r.update(samples="3"), "samples must be an integer"),
    (6, lambda r: r.update(kind=3), "kind must be a string"),
    (6, lambda r: r.update(type="bogus"), "unknown record type 'bogus'"),
    (0, lambda r: r.update(config=[]), "config must be a mapping"),
])
def test_damaged_field_names_its_line(tmp_path, line, change, msg):
    recs = _records()
    change(recs[line])
    _write(tmp_path / "l.jsonl", recs)
    with pytest.raises(InputError, match=rf"line {line + 1}: {msg}"):
        read_log(tmp_path / "l.jsonl")


def test_bad_bytes_and_huge_numbers(tmp_path, capsys):
    p = tmp_path / "l.jsonl"
    _write(p, _records())
    raw = bytearray(p.read_bytes())
    second = raw.index(b"\n") + 1
    raw[second + 3] = 0xFF
    p.write_bytes(bytes(raw))
    with pytest.raises(InputError, match="line 2: not valid UTF-8"):
        read_log(p)
    assert main(["replay", str(p)]) == 2
    assert "line 2: not valid UTF-8" in capsys.readouterr().err
    recs = _records()
    text = "".join(json.dumps(r) + "\n" for r in recs).replace('"t": 0.2', '"t": 1' + "0" * 5000)
    p.write_text(text)
    with pytest.raises(InputError, match="line 4: an integer of 5001 digits"):
        read_log(p)
