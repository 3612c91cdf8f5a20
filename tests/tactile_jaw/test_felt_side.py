"""An open answer's rolls that cannot tell it from a closed rival: the move named is to the side
felt's unfelt stretch, not to the other side, which on a branch closed by a chord is that chord
(tactile_jaw.explore.felt_side_places, tactile_jaw.choose.budget_advice, felt_side_stop)."""

from __future__ import annotations

import math
from pathlib import Path
from types import SimpleNamespace

import numpy as np

from hand_driver.config import load_config
from recognizer.curves import CURVES, Pose
from recognizer.result import Recognition
from tactile_jaw.choose import JawReach, budget_advice
from tactile_jaw.decide import Why
from tactile_jaw.explore import PAST_END_FRACTION, felt_side_places
from tactile_jaw.settings import ExploreSettings

ROOT = Path(__file__).resolve().parents[2]
CONFIG = load_config(ROOT / "config" / "jaw-p.yaml")
REACH = JawReach(CONFIG, ExploreSettings.from_profile("balanced"))
# a semicubical branch (t², a t³ + b t²) of t 0.9–4.8, closed by a chord, cusp side toward the palm
PARAMS = {"a": 0.33, "b": -1.2}
POSE = Pose(0.3, 107.0, -34.0)
CURVE = CURVES["semicubical_parabola"](PARAMS)
T0, T1 = 0.9, 4.8
WHY = Why("semicubical_parabola and ellipse both fit", "rival", "ellipse")


def _at(t: float) -> tuple[float, float]:
    x, y = POSE.apply(*CURVE.point(np.array([t])))
    return float(x[0]), float(y[0])


def _t_of(x: float, y: float) -> float:
    """The branch's t nearest (x, y), checked to lie on it."""
    t = np.linspace(0.05, 8.0, 80001)
    px, py = POSE.apply(*CURVE.point(t))
    k = int(np.argmin(np.hypot(px - x, py - y)))
    assert math.hypot(px[k] - x, py[k] - y) < 0.05
    return float(t[k])


def _felt(lo: float, hi: float, cls: str = "semicubical_parabola", params=PARAMS):
    """An answer whose contacts lie at t lo…hi, and a touch (9 samples, travelling toward larger t,
    the right pad's way) about each."""
    ts = np.linspace(lo, hi, 6)
    touches = []
    for t in ts:
        u = np.linspace(t - 0.3, t + 0.3, 9)
        x, y = POSE.apply(*CURVE.point(u))
        touches.append(SimpleNamespace(samples=SimpleNamespace(
            x=x, y=y, phi=np.asarray(CURVE.tangent_angle(u)) + POSE.theta)))
    contacts = [{"t": float(t), "x": _at(t)[0], "y": _at(t)[1]} for t in ts]
    return Recognition(cls, dict(params), POSE, contacts), touches


def _samples(touches):
    return (np.concatenate([t.samples.x for t in touches]), np.concatenate([t.samples.y for t in touches]))


def test_the_place_is_past_the_felt_stretch_where_the_branch_opens_out():
    answer, touches = _felt(1.6, 2.9)
    (x, y, phi), (bx, by, bphi) = felt_side_places(answer, touches, [_at(T0)])  # the cusp-side corner pivoted about
    t_far = 2.9 + PAST_END_FRACTION * 1.3
    assert abs(_t_of(x, y) - t_far) < 0.01 and t_far < T1  # on the object, short of its far end
    assert abs(math.remainder(phi - float(CURVE.tangent_angle(np.array([t_far]))[0]) - POSE.theta, 2 * math.pi)) < 1e-6
    assert abs(_t_of(bx, by) - 1.6) < 0.01  # and the felt stretch's other end, kept
    assert abs(math.remainder(bphi - float(CURVE.tangent_angle(np.array([1.6]))[0]) - POSE.theta, 2 * math.pi)) < 1e-6
    # the radius of curvature there has grown 5x over the felt end's: what tells the branch from an ellipse
    rho = 1.0 / np.abs(CURVE.kappa(np.array([1.6, t_far])))
    assert rho[1] / rho[0] > 4.0
    # no corner met: the cusp side's place (t 0.3) is on the branch, but the far side's radius is larger
    (x2, y2, _), _ = felt_side_places(answer, touches, [])
    assert abs(_t_of(x2, y2) - t_far) < 0.01


def test_no_place_across_the_cusp_or_past_a_corner_or_on_a_closed_answer():
    answer, touches = _felt(1.0, 2.0)  # the cusp side's place would be at t 0: across the cusp
    (x, y, _), _ = felt_side_places(answer, touches, [])
    assert abs(_t_of(x, y) - 3.0) < 0.01
    answer, touches = _felt(2.0, 3.6)  # places at t 0.4 (past the cusp-side corner) and 5.2 (past the far one)
    (x, y, _), _ = felt_side_places(answer, touches, [])
    assert abs(_t_of(x, y) - 5.2) < 0.01
    (x, y, _), _ = felt_side_places(answer, touches, [_at(T1)])  # the far end corner pivoted about: the cusp side
    assert abs(_t_of(x, y) - 0.4) < 0.01
    assert felt_side_places(answer, touches, [_at(T0), _at(T1)]) == ()  # both ends closed by corners
    ellipse = Recognition("ellipse", {"a": 20.0, "b": 12.0}, POSE, answer.contacts)
    assert felt_side_places(ellipse, touches, []) == ()


def test_the_refusal_names_the_move_to_the_felt_side_not_to_the_closing_chord():
    answer, touches = _felt(1.6, 2.9)
    touched = _samples(touches)
    chord = (_at(T1)[0] + 3.0, _at(T1)[1] + 6.0, 2.86)  # where the other finger met the closing chord
    felt_side = felt_side_places(answer, touches, [_at(T0)])
    before = budget_advice(answer, WHY, touched, REACH, 8, None, [chord], True, None)
    assert "other side" in before and before.move is not None
    after = budget_advice(answer, WHY, touched, REACH, 8, None, [chord], True, None, felt_side)
    assert "other side" not in after and "goes on past them on this side" in after
    move = after.move
    assert move is not None and move["about"] == [felt_side[0][0], felt_side[0][1]]
    # the moved places are the felt side's two, each rolled through by a pad
    assert len(move["places"]) == 2 and all(p["finger"] is not None for p in move["places"])
    c, s = math.cos(math.radians(move["turn_deg"])), math.sin(math.radians(move["turn_deg"]))
    for (x, y, _), p in zip(felt_side, move["places"]):
        ax, ay = move["about"]
        mx, my = ax + c * (x - ax) - s * (y - ay) + move["dx"], ay + s * (x - ax) + c * (y - ay) + move["dy"]
        assert math.hypot(mx - p["x"], my - p["y"]) < 0.01
    # without a felt-side place (a closed answer) the other side's move stands
    assert budget_advice(answer, WHY, touched, REACH, 8, None, [chord], True, None, ()) == before
