"""The exploration's use of what a touch that was not a usable roll still told: a flat
press whose scan rolled on the curved part sends its finger to roll there
(tactile_jaw.explore.scanned_curve); a finger whose rolls left the curve it felt rolls on
short of where they left it (tactile_jaw.explore.rolls_on_within); a budget refusal names
the curve past the felt stretch (tactile_jaw.explore.past_felt_end)."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from hand_driver.motion import TouchResult
from recognizer.scene import load_scene
from tactile_jaw.choose import JawReach
from tactile_jaw.explore import scanned_curve
from tactile_jaw.pipeline import FeltTouch
from tactile_jaw.settings import ExploreSettings
from tests.tactile_jaw.test_envelope_order import support_point
from tests.tactile_jaw.test_flat import CONFIG_P, _press_scan

#: pose (θ, x, y) of P semicubical 132 of bench_explore --finite 20 --anywhere --seed 127
POSE_132 = (-2.931560619086004, 93.38003226428751, -10.289152229581992)
ZIGZAG = math.radians(-90.0) + np.radians([0, 3, -3, 6, -6, 9, -9, 12, -12, 15, -15, 18, -18, 21, -21, 24, -24, 27])


def test_a_press_whose_scan_rolled_on_the_curve_aims_its_finger_there():
    """The left pad's press turned 54° on the hyperbola example's branch without seating (P
    cubicals 109 and 113 of finite seed 127 were refused after such a scan, ρ 11 mm): the
    finger's next roll is aimed at a point of that branch, its pad normal within the scan's
    turn; a scan that turned about a corner aims nothing and is not felt again."""
    obj = load_scene("config/scenes/hyperbola.yaml").object
    reach = JawReach(CONFIG_P, ExploreSettings.from_profile("balanced"))
    branch = _press_scan(lambda p: support_point(obj, p), ZIGZAG)
    no_curve: set[int] = set()
    aim = scanned_curve(CONFIG_P, branch, reach, no_curve)
    assert aim is not None and aim.kind == "scan" and aim.finger == "left" and not no_curve
    # on the branch: the curve's support point at the aim's pad normal is the point aimed at
    assert np.hypot(*(support_point(obj, aim.psi) - np.array(aim.point))) < 0.05
    assert ZIGZAG.min() <= math.remainder(aim.psi, 2 * math.pi) <= ZIGZAG.max()
    corner = _press_scan(lambda p: np.array([100.0, 2.0]), ZIGZAG)
    assert scanned_curve(CONFIG_P, corner, reach, no_curve) is None and no_curve == {id(corner)}


def test_a_budget_refusal_names_the_curve_past_the_reach_not_a_place_past_its_end():
    """P semicubical 132 of finite seed 127: the left pad rolled t 1.2–2.8 of the branch,
    its rolls left the curved part at the cusp-side corner, and the recognizer's most
    telling touch lay there, "within a pad's reach". The refusal names instead the branch as
    far past the felt stretch's other end (t 4.0), which no pad reaches: a move brings it
    within a roll. With no limit where the touch lies, the recognizer's touch stands."""

    from recognizer.curves import CURVES, Pose
    from recognizer.result import Recognition
    from tactile_jaw.explore import PAST_END_FRACTION, past_felt_end

    params, pose = {"a": 0.34617667522706214, "b": -1.2}, Pose(POSE_132[0], POSE_132[1], POSE_132[2])
    curve = CURVES["semicubical_parabola"](params)

    def place(t):  # (x, y, φ) of a left-pad touch at t: pad normal ψ = φ + π/2 toward the solid
        x, y = (float(np.ravel(v)[0]) for v in pose.apply(*curve.point(np.array([t]))))
        return x, y, math.remainder(float(np.ravel(curve.tangent_angle(np.array([t])))[0]) + pose.theta,
                                    2 * math.pi)

    ts = [1.6, 2.2, 2.8]
    touches = [SimpleNamespace(samples=SimpleNamespace(phi=np.array([place(t)[2]]))) for t in ts]
    rec = Recognition("semicubical_parabola", params, pose,
                      contacts=[{"t": t, "x": place(t)[0], "y": place(t)[1]} for t in ts])
    reach = JawReach(CONFIG_P, ExploreSettings.from_profile("balanced"))
    wx, wy, w_phi = place(1.2)
    wanted = {"x": wx, "y": wy, "phi": w_phi}
    assert reach.finger(wx, wy, w_phi) is not None  # the left pad reaches the recognizer's touch
    span = math.radians(18.0)
    limit = [(w_phi + math.pi / 2 + math.radians(5.0), -1.0)]  # its rolls left the curve just above ψ there
    found = past_felt_end(rec, touches, lambda: wanted, reach, span, lambda name: limit)()
    fx, fy, f_phi = place(2.8 + PAST_END_FRACTION * (2.8 - 1.6))
    assert (found["x"], found["y"]) == pytest.approx((fx, fy)) and "past where" in found["what"]
    assert math.remainder(found["phi"] - f_phi, 2 * math.pi) == pytest.approx(0.0, abs=1e-9)
    assert reach.finger(fx, fy, f_phi) is None  # out of reach: the refusal names a move
    assert past_felt_end(rec, touches, lambda: wanted, reach, span, lambda name: [])() is wanted
    # no limit there, but a corner a roll pivoted about 1.5 mm from the place (P cubical 104 of
    # seed 139): a roll there runs onto it, and the curve past the other end is named instead
    corner = np.array([[wx + 1.5, wy]])
    found = past_felt_end(rec, touches, lambda: wanted, reach, span, lambda name: [], corner)()
    assert (found["x"], found["y"]) == pytest.approx((fx, fy)) and "past where" in found["what"]
    far = np.array([[wx + 2.5, wy]])  # beyond the clearance: the recognizer's touch stands
    assert past_felt_end(rec, touches, lambda: wanted, reach, span, lambda name: [], far)() is wanted


def test_a_finger_that_felt_the_curve_rolls_on_within_where_it_left_it():
    """Calibrated P semicubical 130 of finite seed 127: the right pad felt the curve at ψ 82.5°
    and 110°, then crossed the closing segment twice; with an orientation left short of those
    rolls it rolls on (answered right, 18.8 s; refused with 2 usable touches before). A finger
    that never felt the curve, or has no orientation left, retires."""
    from tactile_jaw.explore import rolls_on_within

    touch = TouchResult("right", 3, 1.5, [], outcome="ok")
    felt = [FeltTouch(touch, None, None, None, None, None)]  # a usable roll of the right pad
    assert rolls_on_within("right", felt, math.radians(95.0))
    assert not rolls_on_within("right", felt, None)
    assert not rolls_on_within("left", felt, math.radians(95.0))



@pytest.mark.parametrize("lines, felt", [(33, 65), (15, 65), (9, 14)])
def test_the_search_for_a_passing_run_is_bounded(monkeypatch, lines, felt):
    """A scan whose runs all fail (tactile_jaw.pipeline._passing_runs, as smooth_stretch and
    curve_hint search them): a flat press's 33-line scan feels ``MAX_RUN_FITS`` runs, those
    dropping the fewest lines (≤ 10), not all 434 (P line 4 of finite seed 199: 18 min of
    CPU); a roll of the accurate profile's 15 samples or the balanced one's 9 feels all of
    its runs of at least ``CURVE_HINT_SAMPLES``."""
    from hand_driver.motion import Sample
    from tactile_jaw import pipeline

    calls = []

    def failing(config, touch, samples, **kwargs):
        calls.append(len(touch.samples))
        return SimpleNamespace(problem="off the curved part")

    monkeypatch.setattr(pipeline, "feel", failing)
    scan = TouchResult("left", 8, 0.0, [Sample(k, 0.01 * k, None, None, None, 0.0) for k in range(lines)], outcome="ok")
    assert list(pipeline._passing_runs(None, scan, pipeline.CURVE_HINT_SAMPLES)) == []
    assert len(calls) == felt and pipeline.MAX_RUN_FITS == 65
    assert min(calls) == max(lines - 10, pipeline.CURVE_HINT_SAMPLES)
