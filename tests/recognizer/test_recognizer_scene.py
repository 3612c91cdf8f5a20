import math
from pathlib import Path

import numpy as np
import pytest

from recognizer.curves import CURVES, DEFAULT_SIDE
from tactile_common.errors import InputError
from recognizer.scene import load_scene
from recognizer.touches import parse_noise

SCENES = Path(__file__).resolve().parents[2] / "config" / "scenes"
PARABOLA = {"class": "parabola", "params": {"a": 8.0}, "pose": {"theta": 0.0, "x": 85.0, "y": 0.0}}
MINE = ["default", "conics", "cubics", "all", "calibration", "line", "circle", "ellipse", "parabola", "hyperbola",
        "cubical_parabola", "semicubical_parabola"]


@pytest.mark.parametrize("name", MINE)
def test_example_scenes_load(name):
    sc = load_scene(SCENES / f"{name}.yaml")
    assert sc.name == name and sc.classes and set(sc.classes) <= set(CURVES)
    assert sc.object is not None and sc.object.cls in sc.classes
    assert 55 <= sc.object.pose.x < 160
    if name in CURVES:  # each class's example: a finite object (or a whole closed curve), every class a candidate
        assert sc.object.cls == name and sc.classes == tuple(CURVES)
        assert sc.object.finite or name in ("circle", "ellipse")


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
    ({"object": {**PARABOLA, "extent": [1.4, -1.4]}}, r"object\.extent: needs t0 < t1"),
    ({"object": {**PARABOLA, "extent": [0.5]}}, r"object\.extent: must be \[t0, t1\]"),
    ({"object": {**PARABOLA, "extent": [0, float("nan")]}}, r"object\.extent: must be a finite number"),
    ({"object": {"class": "circle", "params": {"r": 1}, "extent": [0, 1]}}, r"object\.extent: a circle is whole"),
    ({"object": {"class": "ellipse", "params": {"a": 2, "b": 1}, "closure": [[0, 0]]}},
     r"object\.closure: a ellipse is whole"),
    ({"object": {"class": "line", "extent": [-10, 10]}}, r"object\.closure: a line needs closure"),
    ({"object": {**PARABOLA, "closure": [[40, 30]]}}, r"object\.closure: needs extent"),
    ({"object": {**PARABOLA, "extent": [-1.4, 1.4], "closure": []}}, r"object\.closure: must be a non-empty list"),
    ({"object": {**PARABOLA, "extent": [-1.4, 1.4], "closure": [[40, 30, 1]]}}, r"object\.closure\[0\]: must be \[x, y\]"),
    # corners in the wrong order: the two closing segments cross each other
    ({"object": {**PARABOLA, "extent": [-1.4, 1.4], "closure": [[40, -30], [40, 30]]}},
     r"object\.closure: the boundary crosses itself \(closing segment 1 meets another closing segment\)"),
    # a closing segment cut through the curved part
    ({"object": {**PARABOLA, "extent": [-1.4, 1.4], "closure": [[5, 30], [5, -30]]}},
     r"object\.closure: the boundary crosses itself \(closing segment 2 meets the curve\)"),
    ({"object": {"class": "line", "pose": {"theta": 0, "x": 0, "y": 0}, "extent": [-10, 10], "closure": [[5, 0], [0, -5]]}}, "crosses itself"),
    ({"object": {"class": "line", "pose": {"theta": 0, "x": 0, "y": 0}, "extent": [-10, 10], "closure": [[0, 0]]}}, "encloses no area"),
    ({"object": {"class": "line", "pose": {"theta": 0, "x": 0, "y": 0}, "extent": [-10, 10], "closure": [[10, 5], [10, 5], [-10, 5]]}}, "zero length"),
    ({"object": {**PARABOLA, "extent": [-1.4, 1.4], "side": "left"}}, r"object\.side: the closed boundary puts the solid on the right"),
])
def test_bad_scenes_one_line(raw, msg):
    with pytest.raises(InputError, match=msg) as e:
        load_scene(raw)
    assert "\n" not in str(e.value)


@pytest.mark.parametrize("bad", ["1", True, None, float("inf"), float("nan")])
def test_scene_and_request_numbers_share_one_check(bad):
    """A bad number gets the same words in a scene and in a request (one finite_number)."""
    with pytest.raises(InputError) as in_scene:
        load_scene({"object": {**PARABOLA, "pose": {"x": bad}}})
    with pytest.raises(InputError) as in_request:
        parse_noise({"phi": 0.001, "pos": bad})
    assert str(in_scene.value).endswith(f"pose.x: must be a finite number, got {bad!r}")
    assert str(in_request.value) == f"noise.pos: must be a finite number, got {bad!r}"


def test_bad_file(tmp_path):
    p = tmp_path / "bad.yaml"
    p.write_text("classes: [line\n")
    with pytest.raises(InputError, match="bad.yaml: not valid YAML"):
        load_scene(p)
    with pytest.raises(InputError, match="cannot read"):
        load_scene(tmp_path / "nope.yaml")


def test_finite_objects():
    chord = load_scene({"object": {**PARABOLA, "extent": [-1.4, 1.4]}}).object
    assert chord.finite and chord.extent == (-1.4, 1.4) and chord.closure is None and chord.side == "right"
    assert np.allclose(chord.corners(), [[15.68, 22.4], [15.68, -22.4]])
    box = load_scene({"object": {"class": "line", "extent": [-10, 10], "closure": [[10, 5], [-10, 5]],
                                 "pose": {"theta": 0.0, "x": 100.0, "y": 1.0}}}).object
    assert box.side == "left"  # the solid above the line: on the left of increasing t
    x, y = box.outline(samples=3)
    assert np.allclose(np.stack([x, y], axis=-1), [(90, 1), (100, 1), (110, 1), (110, 6), (90, 6), (90, 1)])
    assert not load_scene({"object": PARABOLA}).object.finite  # unbounded, as before
