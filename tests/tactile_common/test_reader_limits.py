"""The YAML readers (jaw config, scene) refuse, with one line and in well under a second,
files over the size limit, alias bombs, deep nesting and huge integers."""

import time
from pathlib import Path

import pytest

from hand_driver.config import load_config
from recognizer.scene import load_scene
from tactile_common.errors import InputError
from tactile_common.inputs import loads_json
from tactile_common.yamlfile import MAX_ALIASES, MAX_YAML_BYTES, read_yaml

ROOT = Path(__file__).resolve().parents[2]
BOMB = "a: &a [lol, lol, lol, lol, lol, lol, lol, lol, lol]\n" + "".join(
    f"{n}: &{n} [{', '.join([f'*{p}'] * 9)}]\n" for p, n in zip("abcdefgh", "bcdefghi"))


@pytest.mark.parametrize("text,msg", [
    ("x: " + "1" * 5000 + "\n", "integer of 5000 digits"),
    ("x: 100000000000000000000\n", "2**53"),
    ("x: 0x" + "f" * 40 + "\n", "is text in YAML 1.2, an integer in YAML 1.1"),
    ("x: " + "[" * 20000 + "]" * 20000 + "\n", "nested deeper than 32"),
    ("x: " + "{a: " * 200 + "1" + "}" * 200 + "\n", "nested deeper than 32"),
    (BOMB, f"more than {MAX_ALIASES} aliases"),
    ("description: |\n" + ("  " + "x" * 78 + "\n") * (MAX_YAML_BYTES // 80 + 10), "over the 64 KiB limit"),
    (b"x: \xff\xfe\n", "not valid UTF-8"),
])
def test_yaml_limits_one_line_fast(tmp_path, text, msg):
    p = tmp_path / "f.yaml"
    p.write_bytes(text if isinstance(text, bytes) else text.encode())
    for reader in (lambda: read_yaml(p, "scene"), lambda: load_scene(str(p)), lambda: load_config(p)):
        t0 = time.perf_counter()
        with pytest.raises(InputError, match=msg.replace("*", r"\*")) as exc:
            reader()
        assert time.perf_counter() - t0 < 0.5 and "\n" not in str(exc.value)


def test_yaml_within_limits_still_reads(tmp_path):
    p = tmp_path / "f.yaml"
    p.write_text("a: &x {r: 16, s: 1e-3, t: -.5, u: '1:30', big: 9007199254740992, ok: true}\nb: *x\n")
    same = {"r": 16, "s": 0.001, "t": -0.5, "u": "1:30", "big": 2 ** 53, "ok": True}
    assert read_yaml(p, "test") == {"a": same, "b": same}
    assert load_config(ROOT / "config/jaw.yaml").joints


@pytest.mark.parametrize("path,msg", [("/dev/zero", "not a regular file"), ("a" * 5000, "path of 5000 characters"),
                                      ("a\0b", "NUL"), ("/", "cannot read")])
def test_scene_paths_refused(path, msg):
    with pytest.raises(InputError, match=msg):
        load_scene(path)


@pytest.mark.parametrize("scene,msg", [
    ({"classes": [["circle"]]}, "unknown class"),
    ({"classes": ["circle"], "object": {"class": ["circle"], "params": {"r": 1}}}, "unknown class"),
    ({"classes": ["circle"], "object": {"class": {"a": 1}, "params": {"r": 1}}}, "unknown class"),
    ({"classes": ["circle"], "object": {"class": "circle", "params": {"r": 1}, "side": [1]}}, "side"),
])
def test_scene_wrong_types(scene, msg):
    with pytest.raises(InputError, match=msg):
        load_scene(scene)


@pytest.mark.parametrize("text,msg", [("1" * 400, "400 digits"), ("1" * 5000, "5000 digits"), ("1.5" + "0" * 100, "103 characters"),
                                      ("[" * 100000 + "]" * 100000, "nested deeper"), ("NaN", "NaN: numbers must be finite"),
                                      ("-Infinity", "-Infinity"), ("1" + "0" * 16, "2\\*\\*53")])
def test_json_number_and_depth_limits(text, msg):
    with pytest.raises(InputError, match=msg):
        loads_json(text, "x")
