import math
from pathlib import Path

import pytest

from recognizer.curves import CURVES, DEFAULT_SIDE
from tactile_common.errors import InputError
from recognizer.scene import load_scene

SCENES = Path(__file__).resolve().parents[2] / "config" / "scenes"
MINE = ["conics", "ellipse", "circle", "parabola", "hyperbola", "cubics", "all"]


@pytest.mark.parametrize("name", MINE)
def test_example_scenes_load(name):
    sc = load_scene(SCENES / f"{name}.yaml")
    assert sc.name == name and sc.classes and set(sc.classes) <= set(CURVES)
    assert sc.object is not None and sc.object.cls in sc.classes
    assert 60 < sc.object.pose.x < 160


def test_defaults_and_inline():
    sc = load_scene({"classes": ["ellipse", "line"], "object": {"class": "ellipse", "params": {"a": 2, "b": 1},
                                                              "pose": {"theta_deg": 90, "x": 1, "y": 2}}})
    assert sc.classes == ("line", "ellipse")  # canonical order
    assert sc.object.side == DEFAULT_SIDE["ellipse"] == "left"
    assert sc.object.pose.theta == pytest.approx(math.pi / 2)
    assert load_scene({}).classes == tuple(CURVES) and load_scene({}).object is None


def test_relative_path_uses_base_dir(tmp_path):
    (tmp_path / "s.yaml").write_text("classes: [circle]\n")
    assert load_scene("s.yaml", base_dir=tmp_path).classes == ("circle",)


@pytest.mark.parametrize("raw,msg", [
    ({"classes": ["blob"]}, "unknown class 'blob'"),
    ({"classes": []}, "non-empty"),
    ({"colour": 1}, "unknown key"),
    ({"object": {"class": "ellipse", "params": {"a": 1, "b": 2}}}, "a >= b"),
    ({"object": {"class": "ellipse", "params": {"a": 1}}}, "missing"),
    ({"object": {"class": "circle", "params": {"r": 0}}}, "> 0"),
    ({"object": {"class": "circle", "params": {"r": 1}, "side": "up"}}, "side"),
    ({"object": {"class": "circle", "params": {"r": 1}, "pose": {"z": 1}}}, "unknown key"),
    ({"object": {"class": "circle", "params": {"r": 1}, "pose": {"x": float("inf")}}}, "finite"),
    ({"noise": {"phi": -1}}, ">= 0"),
    ({"profile": 3}, "profile"),
])
def test_bad_scenes_one_line(raw, msg):
    with pytest.raises(InputError, match=msg) as e:
        load_scene(raw)
    assert "\n" not in str(e.value)


def test_bad_file(tmp_path):
    p = tmp_path / "bad.yaml"
    p.write_text("classes: [line\n")
    with pytest.raises(InputError, match="bad.yaml: not valid YAML"):
        load_scene(p)
    with pytest.raises(InputError, match="cannot read"):
        load_scene(tmp_path / "nope.yaml")
