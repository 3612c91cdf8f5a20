"""Jaw config: the default loads, round-trips, and every bad input is one clear line."""

from __future__ import annotations

import copy

import pytest
import yaml

from hand_driver.config import RETIRED_MOTION_KEYS, dump_config, load_config, parse_config
from hand_driver.log import RunLog, read_log
from tactile_common.errors import InputError
from tools.cli import main

DEFAULT = "config/jaw.yaml"


def _raw():
    with open(DEFAULT, encoding="utf-8") as fh:
        return yaml.safe_load(fh)


def test_default_config_loads_with_contract_keys():
    cfg = load_config(DEFAULT)
    assert [f.name for f in cfg.fingers] == ["left", "right"]
    assert [j.id for j in cfg.joints] == [1, 2, 3, 4]
    for j in cfg.joints:
        assert j.model == "XM430-W350" and j.zero_tick == 2048 and j.link_mm > 0
        assert j.min_deg < 0 < j.max_deg
    assert cfg.bus.protocol == 2.0 and cfg.bus.baudrate == 1_000_000


def test_dump_round_trips(tmp_path):
    cfg = load_config(DEFAULT)
    out = tmp_path / "jaw2.yaml"
    dump_config(cfg, out, header="a header line")
    again = load_config(out)
    assert again == cfg
    assert out.read_text().startswith("# a header line")


def test_fractional_zero_tick_round_trips_exactly(tmp_path):
    raw = _raw()
    raw["fingers"][0]["joints"][0]["zero_tick"] = 2051.123456789012
    cfg = parse_config(raw, "x.yaml")
    dump_config(cfg, tmp_path / "c.yaml")
    assert load_config(tmp_path / "c.yaml").joints[0].zero_tick == 2051.123456789012


@pytest.mark.parametrize("edit, words", [
    (lambda r: r.__setitem__("colour", 1), ["colour", "unknown key"]),
    (lambda r: r["motion"].__setitem__("a\nb", 1), ["motion.'a\\nb'", "unknown key"]),
    (lambda r: r["motion"].__setitem__("roll_samples", 31), ["motion.roll_samples", "no longer a setting", "profile"]),
    (lambda r: r["fingers"][0]["joints"][0].__setitem__("zero_tick", 5000), ["fingers[0].joints[0].zero_tick", "[0, 4095]"]),
    (lambda r: r["fingers"][1]["joints"][0].__setitem__("id", 1), ["fingers[1].joints[0].id", "used twice"]),
    (lambda r: r["fingers"][0]["joints"][1].__setitem__("min_deg", 10), ["min_deg", "[-180, 0]"]),
    (lambda r: r["fingers"][0]["joints"][1].__setitem__("model", "AX-12"), ["model", "XM430-W350"]),
    (lambda r: r["fingers"][0]["joints"][0].__setitem__("link_mm", -3), ["link_mm", "(0, 1000]"]),
    (lambda r: r["fingers"][0]["joints"][0].__setitem__("direction", 2), ["direction", "1 or -1"]),
    (lambda r: r["fingers"][0]["pad"].__setitem__("side", "up"), ["pad.side", "left, right"]),
    (lambda r: r["fingers"][0]["pad"].__setitem__("length_mm", 500), ["pad.length_mm", "out of range"]),
    (lambda r: r["fingers"][0]["joints"].pop(), ["exactly 2 joints"]),
    (lambda r: r["bus"].__setitem__("baudrate", "fast"), ["bus.baudrate", "not a Dynamixel baud rate", "57600"]),
    (lambda r: r["bus"].__setitem__("baudrate", 250000), ["bus.baudrate", "choose from 9600, 57600"]),
    (lambda r: r["motion"].__setitem__("goal_current_ma", 10), ["goal_current_ma", "contact_current_ma"]),
    (lambda r: r["motion"].__setitem__("move_speed_mm_s", 0), ["motion.move_speed_mm_s", "(0, 1000]"]),
    (lambda r: r["motion"].__setitem__("turn_speed_deg_s", -5), ["motion.turn_speed_deg_s", "(0, 1000]"]),
    (lambda r: r["workspace"].__setitem__("center_mm", [1]), ["workspace.center_mm"]),
    (lambda r: r["fingers"][0]["joints"][0].__setitem__("zero_tick", 100), ["max_deg", "outside 0..4095"]),
])
def test_bad_config_names_file_key_and_range(edit, words):
    raw = copy.deepcopy(_raw())
    edit(raw)
    with pytest.raises(InputError) as info:
        parse_config(raw, "bad.yaml")
    msg = str(info.value)
    assert "\n" not in msg and msg.startswith("bad.yaml: ")
    for w in words:
        assert w in msg


def test_unreadable_and_invalid_yaml(tmp_path):
    with pytest.raises(InputError, match="cannot read"):
        load_config(tmp_path / "missing.yaml")
    bad = tmp_path / "bad.yaml"
    bad.write_text("fingers: [\n")
    with pytest.raises(InputError, match="not valid YAML at line"):
        load_config(bad)


@pytest.mark.parametrize("edit, key", [
    (lambda r: r["fingers"][0]["joints"][0].__setitem__("zero_tick", -1), "zero_tick"),
    (lambda r: r["motion"].__setitem__("roll_step_deg", 1.0), "motion.roll_step_deg"),
    (lambda r: r["motion"].__setitem__("dwell_s", 1.0), "motion.dwell_s"),
])
def test_cli_exits_2_with_one_line(tmp_path, capsys, edit, key):
    raw = _raw()
    edit(raw)
    bad = tmp_path / "bad.yaml"
    bad.write_text(yaml.safe_dump(raw))
    code = main(["calibrate", "--config", str(bad), "--port", "/dev/null", "--out", str(tmp_path / "o.yaml")])
    err = capsys.readouterr().err
    assert code == 2
    assert err.count("\n") == 1 and key in err and "Traceback" not in err


def test_log_header_with_retired_motion_keys_still_reads(tmp_path):
    """Logs written while motion.roll_step_deg and roll_samples were read carry them in their
    header config: read without them (nothing recorded is lost)."""
    raw = _raw()
    old = copy.deepcopy(raw)
    old["motion"].update({k: 1 for k in RETIRED_MOTION_KEYS})
    path = tmp_path / "old.jsonl"
    with RunLog(path).open(config=old, scene=None, command=["demo"]):
        pass
    assert read_log(path).jaw_config() == parse_config(raw, f"{path}: header config")
