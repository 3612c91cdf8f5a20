"""A refusal whose rival the rolls of one side cannot tell apart at the jaw's resolution
advises the move that brings the object's other side within a pad's roll
(tactile_jaw.decide.beyond_resolution, tactile_jaw.choose.other_side_stop). Random X-series
ellipse 55 of bench_explore --finite 20 --anywhere --seed 199 (a 16.3, b 9.78): the right pad
rolled on its lower end 7 times (ellipse and semicubical within 7.4 in χ², expected gap 0.29),
the left pad met its upper side only at its pad's far end; the move to the most telling touch
(108, −34) mm, pad normal 32°, followed, was refused again."""

import math

import numpy as np

from hand_driver.config import load_config
from recognizer.curves import CURVES, Pose
from recognizer.result import Ranked, Recognition
from tactile_jaw import decide
from tactile_jaw.choose import JawReach, budget_advice, curvature_at, next_aim
from tactile_jaw.decide import Why, beyond_resolution
from tactile_jaw.settings import ExploreSettings
from tests.tactile_jaw.test_choose import _moved

CONFIG = load_config("config/jaw.yaml")
REACH = JawReach(CONFIG, ExploreSettings.from_profile("balanced"))
A, B = 16.298303932244547, 9.778982359346728
TRUTH = Pose(-2.9228845597870157, 122.91, -28.98)
ELLIPSE = Recognition("ellipse", {"a": A, "b": B}, pose=TRUTH, uncertainty={"a": 3.0, "b": 2.0},
                      ranking=[Ranked("ellipse", True, 7.1, 21, 312.4, 0.99),
                               Ranked("semicubical_parabola", True, 14.5, 21, 319.7, 0.85)])
#: the most telling touch the recognizer named (within no pad's reach as the object lies)
WANTED = {"x": 108.0, "y": -34.0, "phi": math.radians(32.0) - math.pi / 2, "gain": 3.4, "why": "w"}


def _places(lo: float, hi: float):
    """(x, y, φ) along the true ellipse where a pad's normal ψ lies in [lo, hi] deg."""
    curve = CURVES["ellipse"]({"a": A, "b": B})
    t = np.linspace(-math.pi, math.pi, 1441)
    x, y = TRUTH.apply(*curve.point(t))
    phi = np.asarray(curve.tangent_angle(t), float) + TRUTH.theta
    psi = np.degrees(np.remainder(phi + math.pi / 2 + math.pi, 2 * math.pi) - math.pi)
    keep = (psi >= lo) & (psi <= hi)
    return x[keep], y[keep], phi[keep], psi[keep]


def test_the_move_for_a_rival_beyond_the_resolution_brings_the_other_side_within_reach():
    x, y, _, _ = _places(46.0, 106.0)  # the right pad's rolls: ψ 55–97.5° ± 9°
    ux, uy, uphi, upsi = _places(-91.0, -89.0)  # the left pad's probe at ψ −90° met the upper side
    left = (float(ux[0]), float(uy[0]), float(uphi[0]))
    assert REACH.finger(*left, [CONFIG.finger("left")]) is None
    why = Why("ellipse and semicubical_parabola both fit", "rival", "semicubical_parabola")
    before = budget_advice(ELLIPSE, why, (x, y), REACH, 8, anywhere=lambda: WANTED, also=[left])
    after = budget_advice(ELLIPSE, why, (x, y), REACH, 8, anywhere=lambda: WANTED, also=[left], one_side=True)
    assert after.move is not None and "the object's other side can" in after
    assert after.move != before.move
    mx, my = _moved(after.move, left[0], left[1])
    assert REACH.finger(mx, my, left[2] + math.radians(after.move["turn_deg"]), [CONFIG.finger("left")],
                        curvature_at(ELLIPSE, left[0], left[1])) is not None  # its contact travelling over the roll
    # the felt side stays inside the workspace disk with its margin, or no farther out
    fx, fy = _moved(after.move, x, y)
    here = np.hypot(x - 110.0, y)
    assert np.all(np.hypot(fx - 110.0, fy) <= np.maximum(45.0 - 3.0, here) + 1e-6)


def test_without_another_sides_place_the_advice_is_as_before():
    x, y, _, _ = _places(46.0, 106.0)
    why = Why("ellipse and semicubical_parabola both fit", "rival", "semicubical_parabola")
    plain = budget_advice(ELLIPSE, why, (x, y), REACH, 8, anywhere=lambda: WANTED)
    assert budget_advice(ELLIPSE, why, (x, y), REACH, 8, anywhere=lambda: WANTED, one_side=True) == plain


def test_beyond_resolution_scales_the_expected_gap_to_the_budget(monkeypatch):
    touches = [object()] * 7
    rival = Why("r", "rival", "semicubical_parabola")
    for gap, expected in ((0.29, True), (8.0, True), (9.0, False), (None, False)):
        monkeypatch.setattr(decide, "rivals_gap", lambda *args, g=gap: g)
        # 9.0 × 8 / 7 = 10.3: the budget's touches alike could reach DECISIVE_CHI2
        assert beyond_resolution(None, ELLIPSE, rival, touches, 8) is expected
    assert beyond_resolution(None, ELLIPSE, Why("r", "resolution", "parabola"), touches, 8)
    assert not beyond_resolution(None, ELLIPSE, Why("u", "unstable"), touches, 8)
    assert not beyond_resolution(None, ELLIPSE, Why("i", "imprecise"), touches, 8)


def test_a_stop_for_a_rival_beyond_the_resolution_names_the_other_sides_move():
    """Stopped before the budget (no touch within reach tells them apart, or kind ``resolution``:
    before, "more touches of this jaw are not expected to tell them apart", naming no move)."""
    x, y, _, _ = _places(46.0, 106.0)
    ux, uy, uphi, _ = _places(-91.0, -89.0)
    left = (float(ux[0]), float(uy[0]), float(uphi[0]))
    for kind in ("resolution", "rival"):
        why = Why("ellipse and semicubical_parabola both fit", kind, "semicubical_parabola")
        aim, stop = next_aim(ELLIPSE, why, (x, y), REACH, list(CONFIG.fingers), [], anywhere=lambda: WANTED,
                             also=[left], one_side=lambda: True)
        assert aim is None and stop.move is not None and "the object's other side can" in stop
        _, plain = next_aim(ELLIPSE, why, (x, y), REACH, list(CONFIG.fingers), [], anywhere=lambda: WANTED,
                            also=[left], one_side=lambda: False)
        assert "the object's other side can" not in plain
