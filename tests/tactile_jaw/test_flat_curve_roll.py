"""A roll that crossed a finite curved object's end corner yet rolled on its curved part
makes the faces the pads press closing segments (tactile_jaw.pipeline.curved_part), so the
flat phase refuses instead of answering ``line``, and names a move away from that corner
(tactile_jaw.flat_phase.curve_stop): P cubical 116 of bench_explore --finite 20 --anywhere
--seed 139, whose left pad's rolls crossed the curve's end corner and whose right pad seated
three times on a closing segment, was answered line. Exact tangent lines of that object,
every joint read to its tick."""

from __future__ import annotations

import math

import numpy as np
from scipy import optimize

from hand_driver.flat_press import FlatResult
from hand_driver.sim.boundary import Boundary
from recognizer.scene import load_scene
from tactile_jaw.flat_phase import curve_stop
from tactile_jaw.pipeline import curve_refusal, curved_part, feel
from tactile_jaw.settings import ExploreSettings
from tests.tactile_jaw.test_envelope_order import CONFIG, FINE, roll, touch
from tests.tactile_jaw.test_flat import _face, _flat

#: P cubical 116 of bench_explore --finite 20 --anywhere --seed 139 (its scene file's object)
CUBICAL_116 = {"classes": ["line", "circle", "ellipse", "parabola", "hyperbola", "cubical_parabola",
                           "semicubical_parabola"],
               "object": {"class": "cubical_parabola", "params": {"a": 0.0003722537939441556, "c": -0.5},
                          "pose": {"theta": 0.22880048011269594, "x": 112.77588548639153, "y": -5.049062611768985},
                          "extent": [-35.18330789005761, 2.9319423241714677],
                          "closure": [[2.9319423241714677, -29.319423241714677],
                                      [-35.18330789005761, -29.319423241714677]]}}


def _support(obj, corners: np.ndarray):
    """The point where a pad line of normal ψ rests on the finite object: of its curve's
    tangent points within the extent (closed form: the root of n·tangent = 0) and its
    corners, the one of least n·p."""
    curve, pose = obj.curve(), obj.pose
    t0, t1 = obj.extent
    grid = np.linspace(t0, t1, 2001)

    def contact(psi: float) -> np.ndarray:
        n = np.array([math.cos(psi), math.sin(psi)])

        def across(t):
            a = float(curve.tangent_angle(np.array(t))) + pose.theta
            return math.cos(a) * n[0] + math.sin(a) * n[1]

        g = np.array([across(t) for t in grid])
        points = [np.array(pose.apply(*curve.point(np.array(optimize.brentq(across, grid[i], grid[i + 1],
                                                                               xtol=1e-14)))), dtype=float)
                  for i in np.nonzero(np.sign(g[:-1]) != np.sign(g[1:]))[0]]
        return min([*points, *corners], key=lambda p: float(n @ p))

    return contact


def _rolls():
    obj = load_scene(CUBICAL_116).object
    contact = _support(obj, Boundary(obj).corners)
    rng = np.random.default_rng(5)
    # the left pad's first roll of the run: 9 lines over 18°, centred at ψ −97.5°; its first
    # lines pivot about the curve's end corner (116.0, −5.8) mm, the rest roll on the curve
    psis = np.radians(-97.5 + np.linspace(-9.0, 9.0, 9))
    return obj, contact, feel(CONFIG, touch(roll(contact, psis, FINE, rng)), 9)


def test_a_roll_across_the_end_corner_that_felt_the_curve_makes_the_faces_closing_segments():
    """The roll is no touch (its lines are no smooth curve's tangents), but a stretch of it
    rolled on the curve: curved_part finds that stretch (its radius of curvature the curve's
    there, far from a corner's), so three seated presses on a closing segment are no line;
    the refusal's move brings the curve past the stretch's far end, away from the corner,
    within a roll. On main 635cb72 … b9110c0 curved_part looked at flat presses' scans only."""
    obj, contact, felt = _rolls()
    assert felt.problem is not None and felt.off_curve and felt.curve_at is not None, felt.problem
    chord = [_flat(_face(-41.6, math.radians(13.1), x0=85.2, x1=122.3), "right") for _ in range(3)]
    felt.touch.outcome = "rejected"  # as the exploration marks an unusable roll: felt as taken all the same
    found = curved_part(CONFIG, [*chord, felt])
    assert found is not None and found.finger == "left" and not isinstance(found.touch, FlatResult)
    c = found.contacts
    truth = np.array([contact(p) for p in c.psi])
    assert np.max(np.hypot(c.x - truth[:, 0], c.y - truth[:, 1])) < 0.2  # on the curve (5 lines: ~0.1 mm along the pad)
    corner = np.array([115.96, -5.80])
    assert np.min(np.hypot(c.x - corner[0], c.y - corner[1])) > 5.0
    assert 20.0 < found.fit.rho < 80.0 and found.fit.rho > 100.0 * found.fit.sigma_rho  # the curve's, not a pivot's
    assert "closing segments, not a line" in curve_refusal(found).reason
    stop = curve_stop(CONFIG, ExploreSettings.from_profile("balanced"), found, felt)
    assert stop.move is not None, str(stop)
    assert "away from the corner" in str(stop)


def test_rolls_about_a_blocks_corners_feel_no_curve():
    """The same roll about one corner, and across a straight segment between two corners (a
    block's): no stretch on a curved part, so the faces may still be a line."""
    psis = np.radians(-97.5 + np.linspace(-9.0, 9.0, 9))
    rng = np.random.default_rng(6)
    a, b = np.array([96.0, -2.4]), np.array([112.0, -6.0])
    on_corner = feel(CONFIG, touch(roll(lambda psi: a, psis, FINE, rng)), 9)
    across = feel(CONFIG, touch(roll(lambda psi: min((a, b), key=lambda p: math.cos(psi) * p[0] + math.sin(psi) * p[1]),
                                     psis, FINE, rng)), 9)
    for felt in (on_corner, across):
        assert felt.problem is not None and felt.off_curve and felt.curve_at is None, felt.problem
    assert curved_part(CONFIG, [on_corner, across]) is None
