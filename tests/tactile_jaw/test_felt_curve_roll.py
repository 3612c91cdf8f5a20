"""A curved part felt while no touch was usable: before the flat phase refuses ("no rolling
touch on it was usable"), the finger that felt it rolls there once, over the pad normals
between the corner its roll ran onto and the far corner's cone
(tactile_jaw.explore.felt_curve_roll)."""

import json
import math
from pathlib import Path

import numpy as np
import pytest

from hand_driver.config import load_config
from hand_driver.motion import TouchResult
from recognizer.scene import load_scene
from tactile_jaw.choose import JawReach
from tactile_jaw.explore import felt_curve_roll
from tactile_jaw.pipeline import curved_part, feel, logged_samples
from tactile_jaw.rounds import Exploration
from tactile_jaw.settings import ExploreSettings

DATA = Path(__file__).parent / "data" / "p_semicubical_63_rolls.json"
CLASSES = ["line", "circle", "ellipse", "parabola", "hyperbola", "cubical_parabola", "semicubical_parabola"]
# calibrated P semicubical 63 of bench_explore --finite 10 --anywhere --calibrate --seed 613, moved as advised
OBJECT = {"class": "semicubical_parabola", "extent": [0.8843438143138711, 4.743298640410763],
          "params": {"a": 0.3358422314859873, "b": -1.2},
          "pose": {"theta": -2.7667652382687806, "x": 114.76014303719819, "y": 37.56814322632566}}


def _exploration():
    config = load_config("config/jaw-p-truth.yaml")
    out = Exploration()
    for raw in json.loads(DATA.read_text())["rolls"]:
        samples = logged_samples(config, raw["finger"], raw["ticks"], raw["psi"])
        out.touches.append(feel(config, TouchResult(raw["finger"], raw["touch"], raw["psi_center"], samples,
                                                    outcome="ok"), 9))
    return config, out


def _support_t(obj, psi: float) -> float:
    """The curve parameter of the exact object's support point at pad normal ψ (min of n·p
    over its boundary: the curve and its end corners)."""
    t = np.linspace(*obj.extent, 200001)
    x, y = obj.pose.apply(*obj.curve().point(t))
    return float(t[np.argmin(math.cos(psi) * x + math.sin(psi) * y)])


def test_the_finger_rolls_once_more_on_the_curved_part_it_felt_clear_of_both_corners():
    """The left roll at ψ −55.9…−37.9° kept 7 lines on the curve (ρ 14.7 mm), then ran onto
    its end corner; the next left roll turned about the far corner at −112.5 ± 9°. No touch was
    usable and the run was refused at once, naming no move. The roll now handed back ends at the
    stretch's last line on the curve (−42.4°), spans one roll (18°) away from that corner, stays
    out of the far corner's cone, and at every pad normal of it the exact object's support point
    lies on the curve clear of both end corners; the place aimed at lies within 0.5 mm of the
    curve."""
    config, out = _exploration()
    assert all(t.problem is not None for t in out.touches)  # nothing usable: the flat phase would refuse
    curve = curved_part(config, out.touches)
    assert curve is not None and abs(curve.fit.rho - 14.7) < 0.5
    settings = ExploreSettings.from_profile("balanced")
    aim = felt_curve_roll(config, out, settings, JawReach(config, settings, []))
    assert aim is not None and aim.finger == "left" and aim.kind == "felt"
    assert abs(aim.span - settings.roll_span_rad) < 1e-9
    last_on = float(np.max(curve.contacts.psi))
    assert abs(aim.psi + 0.5 * aim.span - last_on) < 1e-6  # its end at the stretch's end by the corner
    assert aim.psi - 0.5 * aim.span > math.radians(-103.5)  # short of the far corner's cone
    obj = load_scene({"classes": CLASSES, "object": OBJECT}).object
    lo, hi = obj.extent
    for psi in np.linspace(aim.psi - 0.5 * aim.span, aim.psi + 0.5 * aim.span, 9):
        t = _support_t(obj, float(psi))
        assert lo + 0.05 < t < hi - 0.05  # on the curve, not at a corner
    px, py = obj.pose.apply(*obj.curve().point(np.linspace(lo, hi, 200001)))
    assert float(np.min(np.hypot(px - aim.x, py - aim.y))) < 0.5


def test_no_roll_when_no_curved_part_was_felt():
    """The far corner's roll alone shows no curved part: nothing is handed back."""
    config, out = _exploration()
    out.touches = [t for t in out.touches if t.touch.touch == 6]
    settings = ExploreSettings.from_profile("balanced")
    assert felt_curve_roll(config, out, settings, JawReach(config, settings, [])) is None


# P semicubical 121 of bench_explore --finite 20 --anywhere --follow --seed 599 --config config/jaw-p.yaml, moved as advised
DATA_121 = Path(__file__).parent / "data" / "p_semicubical_121_moved_rolls.json"
OBJECT_121 = {"class": "semicubical_parabola", "extent": [1.054931092650383, 5.658266769670235],
              "params": {"a": 0.2815349761412611, "b": -1.2},
              "pose": {"theta": 2.3237614752263847, "x": 115.6137166757059, "y": -41.589991333245244}}


def test_the_roll_handed_back_ends_short_of_the_corner_its_felt_roll_turned_about():
    """The left roll 4 at ψ −92.25…−74.25° kept 3 lines on the curve, then turned about the
    curve's end corner (84.54, −26.83) mm (its pivot): the stretch curved_part keeps reaches
    two lines (−85.5°, −83.25°) through that corner, and the roll handed back over the stretch's
    last 18° (−101.25…−83.25°) ran onto the corner again and was rejected (no smooth curve's
    tangents), retiring the finger. Those two lines rest on the pivot (pipeline.on_pivots): the
    roll now ends at the stretch's last line on the curve (−87.75°), and at each of its 9 pad
    normals the exact object's support point lies on the curve clear of the end corner."""
    config = load_config("config/jaw-p.yaml")
    out = Exploration()
    for raw in json.loads(DATA_121.read_text())["rolls"]:
        samples = logged_samples(config, raw["finger"], raw["ticks"], raw["psi"])
        out.touches.append(feel(config, TouchResult(raw["finger"], raw["touch"], raw["psi_center"], samples,
                                                    outcome=raw["outcome"]), 9))
    curve = curved_part(config, out.touches)
    assert curve is not None and curve.touch.touch == 4 and out.touches[0].pivot is not None
    assert math.degrees(float(np.max(curve.contacts.psi))) > -84.0  # the stretch reaches the corner's lines
    settings = ExploreSettings.from_profile("balanced")
    aim = felt_curve_roll(config, out, settings, JawReach(config, settings, []))
    assert aim is not None and aim.finger == "left" and aim.kind == "felt"
    assert math.degrees(aim.psi + 0.5 * aim.span) == pytest.approx(-87.75, abs=0.01)
    obj = load_scene({"classes": CLASSES, "object": OBJECT_121}).object
    lo, hi = obj.extent
    for psi in np.linspace(aim.psi - 0.5 * aim.span, aim.psi + 0.5 * aim.span, 9):
        assert lo + 0.05 < _support_t(obj, float(psi)) < hi - 0.05  # on the curve, not at its end corner
