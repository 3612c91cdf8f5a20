"""One strict YAML reader for scenes, jaw configs and calibrated configs (issue 22): YAML 1.2
core scalars, duplicate keys refused naming both lines, required keys required, every
refusal one line naming its line."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

from hand_driver.config import dump_config, load_config, perturbed
from recognizer.scene import load_scene
from tactile_common.errors import InputError
from tactile_common.yamlfile import read_yaml
from tools.cli import main

ROOT = Path(__file__).resolve().parents[2]
JAW = (ROOT / "config/jaw.yaml").read_text()
SCENE = """name: t
classes: [ellipse, circle]
noise: {phi: 0.0015, pos: 0.03}
object:
  class: ellipse
  params: {a: 28.0, b: 17.0}
  pose: {theta: 0.3, x: 110.0, y: 0.0}
"""


def _write(tmp_path, text: str, name: str = "f.yaml") -> Path:
    p = tmp_path / name
    p.write_text(text)
    return p


def _one_line(exc) -> str:
    msg = str(exc.value)
    assert "\n" not in msg
    return msg


@pytest.mark.parametrize("text,key,lines", [
    (SCENE + "  pose: {theta: 0.3, x: 120.0, y: 5.0}\n", "pose", (7, 8)),
    (SCENE.replace("classes: [ellipse, circle]\n", "classes: [ellipse, circle]\nclasses: [line]\n"), "classes", (2, 3)),
])
def test_duplicate_keys_in_a_scene_name_the_key_and_both_lines(tmp_path, text, key, lines):
    with pytest.raises(InputError) as exc:
        load_scene(str(_write(tmp_path, text)))
    assert f"duplicate key '{key}' (lines {lines[0]} and {lines[1]})" in _one_line(exc)


@pytest.mark.parametrize("key", ["pad", "base"])
def test_duplicate_keys_in_a_jaw_config(tmp_path, key):
    line = next(k for k, s in enumerate(JAW.splitlines()) if s.strip().startswith(f"{key}:"))
    lines = JAW.splitlines(keepends=True)
    lines.insert(line + 1, lines[line])
    with pytest.raises(InputError) as exc:
        load_config(_write(tmp_path, "".join(lines)))
    assert f"duplicate key '{key}' (lines {line + 1} and {line + 2})" in _one_line(exc)


@pytest.mark.parametrize("value,was", [("1:30", "90"), ("0x10", "16"), ("1_000", "1000"),
                                       ("yes", "True"), ("off", "False")])
def test_yaml_1_1_scalars_are_refused_with_what_they_were(tmp_path, value, was):
    """Sexagesimal, hexadecimal, octal, underscored and yes/no scalars were read as numbers
    and booleans (``phi: 1:30`` as 90); under YAML 1.2 they are text, so neither reading is
    taken silently."""
    p = _write(tmp_path, SCENE.replace("phi: 0.0015", f"phi: {value}"))
    with pytest.raises(InputError) as exc:
        load_scene(str(p))
    msg = _one_line(exc)
    assert "at line 3" in msg and f"'{value}' is text in YAML 1.2" in msg and f"({was})" in msg


def test_yaml_1_2_octal_is_text_and_refused_where_a_number_belongs(tmp_path):
    p = _write(tmp_path, SCENE.replace("phi: 0.0015", "phi: 0o17"))
    with pytest.raises(InputError, match=r"line 3: noise\.phi: must be a finite number, got '0o17'"):
        load_scene(str(p))


def test_leading_zero_is_refused(tmp_path):
    with pytest.raises(InputError, match=r"at line 1: '017': a leading zero \(YAML 1.1 read it as octal 15, YAML 1.2 "
                                         r"as 17\)"):
        read_yaml(_write(tmp_path, "x: 017\n"), "test")


def test_core_schema_floats_and_booleans(tmp_path):
    """``1e-3`` is a float (YAML 1.1 made it a string: "not a finite number"); quoted text
    stays text; only true/false are booleans."""
    p = _write(tmp_path, SCENE.replace("a: 28.0, b: 17.0", "a: 1e-3, b: 5E-4").replace("name: t", "name: '1:30'"))
    scene = load_scene(str(p))
    assert scene.object.params == {"a": 1e-3, "b": 5e-4} and scene.name == "1:30"
    assert read_yaml(_write(tmp_path, "a: true\nb: 'yes'\nc: .5\nd: -1.\nf: 2001-12-14\n"), "t") == \
        {"a": True, "b": "yes", "c": 0.5, "d": -1.0, "f": "2001-12-14"}


@pytest.mark.parametrize("text", ["a: 1\nobject:\n", "a: 1\nobject: ~\n", "a: 1\nobject: null\n"])
def test_a_key_without_a_value_is_refused(tmp_path, text):
    """A scene cut after ``object:`` read as a scene without an object."""
    with pytest.raises(InputError, match=r"at line 2: 'object' has no value"):
        read_yaml(_write(tmp_path, text), "scene")


def test_a_scene_object_without_pose_is_refused(tmp_path):
    """It was put in the palm (0, 0, 0) and explored for 30-55 s of robot time."""
    p = _write(tmp_path, SCENE.replace("  pose: {theta: 0.3, x: 110.0, y: 0.0}\n", ""))
    with pytest.raises(InputError) as exc:
        load_scene(str(p))
    assert re.search(r"f\.yaml: line 4: object\.pose: missing", _one_line(exc))
    for partial, missing in (("{theta: 0.3, x: 110.0}", "y"), ("{x: 110.0, y: 0.0}", "theta")):
        p = _write(tmp_path, SCENE.replace("{theta: 0.3, x: 110.0, y: 0.0}", partial))
        with pytest.raises(InputError, match=rf"line 7: object\.pose\.{missing}: missing"):
            load_scene(str(p))


def test_a_finger_without_base_is_refused(tmp_path):
    """It became (0, 0, 0 deg) silently."""
    lines = JAW.splitlines(keepends=True)
    k = next(i for i, s in enumerate(lines) if s.strip().startswith("base:"))
    del lines[k]
    with pytest.raises(InputError) as exc:
        load_config(_write(tmp_path, "".join(lines)))
    assert re.search(r"line \d+: fingers\[0\]\.base: missing \(required\)", _one_line(exc))
    with pytest.raises(InputError, match=r"line \d+: fingers\[0\]\.base\.angle_deg: missing"):
        load_config(_write(tmp_path, JAW.replace("base: {x: 0.0, y: 40.0, angle_deg: 0.0}", "base: {x: 0.0, y: 40.0}")))


def test_format_errors_name_the_line_of_their_key(tmp_path):
    bad = JAW.replace("link_mm: 65.0", "link_mm: -65.0", 1)
    line = next(k for k, s in enumerate(bad.splitlines()) if "link_mm: -65.0" in s) + 1
    with pytest.raises(InputError, match=rf"line {line}: fingers\[0\]\.joints\[1\]\.link_mm: -65.0 out of range"):
        load_config(_write(tmp_path, bad))
    with pytest.raises(InputError, match=r"f\.yaml: line 6: object\.params\.b: must be > 0"):
        load_scene(str(_write(tmp_path, SCENE.replace("b: 17.0", "b: -1"))))


def test_a_calibrated_config_reads_back_equal(tmp_path):
    """What tactile calibrate --out writes (yaml.safe_dump, a comment header) is read by the
    strict reader as the same config."""
    cfg = perturbed(load_config(ROOT / "config/jaw.yaml"), np.random.default_rng(3))
    p = tmp_path / "cal.yaml"
    dump_config(cfg, p, header="calibrated\nrms 0.02 mm")
    assert load_config(p) == type(cfg)(**{**cfg.__dict__, "source": str(p)})


def test_every_shipped_file_reads(tmp_path):
    for p in sorted((ROOT / "config").rglob("*.yaml")):
        read_yaml(p, "file")
    for p in sorted((ROOT / "config/scenes").glob("*.yaml")):
        load_scene(str(p))


def test_demo_refuses_an_object_outside_the_workspace_before_any_motion(tmp_path, capsys):
    p = _write(tmp_path, SCENE.replace("x: 110.0", "x: 300.0"))
    assert main(["demo", "--scene", str(p)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "line 7: object.pose: the object is outside the jaw's workspace" in err
    assert "the disk of radius 45 mm about (110, 0) mm" in err
    assert "emulated bus" not in err  # refused before the bus started


def test_a_file_cut_mid_line_is_refused(tmp_path):
    """A scene cut after ``name: con`` read as a valid scene of every class with no object
    (the damage bench's held-out seed 43 found three)."""
    with pytest.raises(InputError, match=r"f\.yaml: scene at line 1: the file does not end with a newline"):
        load_scene(str(_write(tmp_path, "name: con")))
    assert load_scene(str(_write(tmp_path, SCENE))).object is not None
