"""A closed object's other side (X-series ellipse 50 of bench_explore --finite 20 --anywhere
--seed 157, development seed since session 17: a 22.8, b 13.7; the right pad rolls on its
lower side, the left pad reaches its upper side only at pad normals −98…−92°, contact 46–50 mm
along its 52 mm pad). tactile_jaw.explore.other_side_aim sends the left pad where the answer
on the right's rolls says it can roll; tactile_jaw.choose._goal_stop advises the move that
brings that side within its reach when no move brings the wanted touch there."""

import math

import numpy as np
import pytest

from hand_driver.config import load_config
from recognizer.curves import CURVES, Pose
from recognizer.result import Recognition
from tactile_jaw.choose import JawReach, _goal_stop, place_goal
from tactile_jaw.explore import other_side_aim
from tactile_jaw.settings import ExploreSettings

CONFIG = load_config("config/jaw.yaml")
A, B = 22.809611400153518, 13.68576684009211
TRUTH = Pose(-2.893244886778503, 119.48179714875533, -28.70834092702876)
#: the answer on the right pad's first three rolls (a ±28 %, b ±23 %)
FITTED = ({"a": 21.643076094387833, "b": 12.621017337728249}, Pose(0.19977764900320416, 118.6711926842554, -30.009025573477544))


@pytest.fixture(scope="module")
def reach():
    return JawReach(CONFIG, ExploreSettings.from_profile("balanced"))


def _places(pose: Pose):
    """(x, y, φ, pad normal ψ in degrees) along the true ellipse placed at ``pose``."""
    curve = CURVES["ellipse"]({"a": A, "b": B})
    t = np.linspace(-math.pi, math.pi, 1441)
    x, y = pose.apply(*curve.point(t))
    phi = np.asarray(curve.tangent_angle(t), float) + pose.theta
    return x, y, phi, np.degrees(np.remainder(phi + math.pi / 2 + math.pi, 2 * math.pi) - math.pi)


@pytest.mark.parametrize("params, pose", [FITTED, ({"a": A, "b": B}, TRUTH)])
def test_the_left_pad_is_sent_to_the_upper_side(reach, params, pose):
    aim = other_side_aim(Recognition("ellipse", params=params, pose=pose), CONFIG.finger("left"), reach)
    assert aim is not None and aim.finger == "left" and aim.kind == "side"
    assert -98.0 <= math.degrees(math.remainder(aim.psi, 2 * math.pi)) <= -90.0


def test_an_open_answer_sends_no_finger(reach):
    rec = Recognition("parabola", params={"a": 5.0}, pose=TRUTH)
    assert other_side_aim(rec, CONFIG.finger("left"), reach) is None


def test_the_move_for_the_other_side_when_the_wanted_touch_is_out_of_any_reach(reach):
    """The touch the recognizer wanted lay at the major axis's far end (pad normal −150°), which
    no pad reaches however the object is moved or turned; the left pad's probe met the upper
    side at ψ −110° at its pad's end. The advice is the move after which the left pad rolls
    there (before: no move, "place the object so that more of its curved part faces a finger")."""
    x, y, phi, psi = _places(TRUTH)
    lower = (psi > 45.0) & (psi < 100.0)
    j = int(np.argmin(np.abs(psi + 150.0)))
    k = int(np.argmin(np.abs(psi + 110.0)))
    goal = place_goal(float(x[j]), float(y[j]), float(phi[j]), (x[lower], y[lower]))
    stop = _goal_stop("the touch budget of 8 is spent", goal, reach, [(float(x[k]), float(y[k]), float(phi[k]))])
    assert stop.move is not None and "which the other finger met but has not rolled on" in stop
    m = stop.move
    turn = math.radians(m["turn_deg"])
    ax, ay = m["about"]
    c, s = math.cos(turn), math.sin(turn)
    px = ax + c * (x[k] - ax) - s * (y[k] - ay) + m["dx"]
    py = ay + s * (x[k] - ax) + c * (y[k] - ay) + m["dy"]
    assert reach.finger(float(px), float(py), float(phi[k]) + turn, [CONFIG.finger("left")]) is not None
