"""A decisive answer whose σ's are looser than the profile's target touches on where the
recognizer points (tactile_jaw.explore), unless that roll would measure nothing
(tactile_jaw.explore.futile_roll): its place at a corner a roll pivoted about, or an
orientation at which the same finger's earlier roll met its pad end."""

import math

import numpy as np

from hand_driver.motion import Sample, TouchResult
from tactile_jaw.choose import Aim
from tactile_jaw.explore import at_corner, futile_roll
from tactile_jaw.pipeline import CORNER_CLEARANCE_MM, FeltTouch

SPAN = math.radians(18.0)  # the balanced profile's roll


def _roll(finger: str, psi_deg: list[float], outcome: str) -> FeltTouch:
    samples = [Sample(reading=k, psi=math.radians(p), ticks=np.zeros(2, int), line=None, current_ma=None,
                      robot_time=0.0) for k, p in enumerate(psi_deg)]
    touch = TouchResult(finger, 6, math.radians(psi_deg[0] + 9.0), samples, outcome=outcome)
    return FeltTouch(touch, None, None, None, "a pad end, not the pad's face, touched", None)


def _aim(finger: str, psi_deg: float, x: float = 89.4, y: float = 5.8) -> Aim:
    return Aim(x, y, math.radians(psi_deg) - math.pi / 2, finger, "where the recognizer points")


def test_a_roll_where_the_finger_met_its_pad_end_is_futile():
    """P cubical 112 of bench_explore --finite 20 --anywhere --seed 191 (development seed):
    decisive with a ±1.3 %, the right pad's roll about ψ 82.5° had met its proximal end at its
    second sample (ψ 75.75°); the touch named lay at ψ 82.0°, rolled, and met that end again
    (2.3 s of robot time, answer unchanged)."""
    edge = _roll("right", [73.5, 75.75], "edge")
    why = futile_roll(_aim("right", 82.0), [edge], SPAN, np.empty((0, 2)))
    assert why is not None and "pad end" in why and "75.8 deg" in why
    # beyond half a span from where the pad end was met: that roll may land on the face
    assert futile_roll(_aim("right", 75.75 + 9.5), [edge], SPAN, np.empty((0, 2))) is None
    assert futile_roll(_aim("right", 75.75 - 8.5), [edge], SPAN, np.empty((0, 2))) is not None
    # another finger's pad end, or a roll of this finger that ended otherwise, says nothing
    assert futile_roll(_aim("left", 82.0), [edge], SPAN, np.empty((0, 2))) is None
    assert futile_roll(_aim("right", 82.0), [_roll("right", [73.5, 75.75], "ok")], SPAN, np.empty((0, 2))) is None


def test_a_roll_at_a_corner_is_futile():
    corner = np.array([[110.4, -8.8]])
    off = CORNER_CLEARANCE_MM
    assert at_corner(110.4 + 0.9 * off, -8.8, corner)
    assert not at_corner(110.4, -8.8 - 1.1 * off, corner)
    assert not at_corner(110.4, -8.8, np.empty((0, 2)))
    assert futile_roll(_aim("right", 70.0, 110.4, -8.8 + 0.5 * off), [], SPAN, corner) is not None
    assert futile_roll(_aim("right", 70.0, 110.4, -8.8 + 1.5 * off), [], SPAN, corner) is None
