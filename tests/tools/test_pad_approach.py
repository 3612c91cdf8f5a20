"""tools.pad_approach: where a flat pad sent to a place with an orientation lands."""

import math

import numpy as np

from recognizer.curves import CURVES, Pose
from tools.pad_approach import land, solid_left

POSE = Pose(0.4, 120.0, -10.0)


def _aim(curve, t, direction=1):
    x, y = POSE.apply(*curve.point(np.array([t])))
    phi = float(curve.tangent_angle(np.array([t]))[0]) + POSE.theta + (math.pi if direction < 0 else 0.0)
    return float(x[0]), float(y[0]), phi


def test_a_pad_sent_to_a_convex_place_lands_there_either_way_round():
    curve = CURVES["ellipse"]({"a": 30.0, "b": 12.0})
    for direction in (1, -1):
        left = solid_left(curve, [0.3, 1.0, 2.0], direction)
        assert left == (direction > 0)  # the interior on the left of a counter-clockwise travel
        for t in (0.2, 1.4, -2.9):
            got = land(curve, POSE, None, *_aim(curve, t, direction), left, direction, 8.0, 4.0, 30.0)
            assert got.why == "" and abs(got.t - t) < 1e-6 and got.miss_mm < 1e-5


def test_the_pad_lands_where_the_boundary_has_its_orientation_not_at_the_nearest_point():
    """A circle of r 20 mm, the pad sent 3 mm beside its point at t = 0 with the tangent
    0.1 rad off: the pad's face meets the circle where the tangent is the pad's, at t = 0.1
    (the point nearest the place is at t ≈ 0.15)."""
    curve = CURVES["circle"]({"r": 20.0})
    x, y, phi = _aim(curve, 0.0)
    u = np.array([math.cos(phi), math.sin(phi)])
    got = land(curve, POSE, None, x + 3.0 * u[0], y + 3.0 * u[1], phi + 0.1, True, 1, 8.0, 4.0, 20.0)
    assert got.why == "" and abs(got.t - 0.1) < 1e-7
    got = land(curve, POSE, None, x + 5.0 * u[0], y + 5.0 * u[1], phi, True, 1, 8.0, 4.0, 20.0)
    assert got.t is None and got.why == "the roll runs off the pad"  # lands 5 mm from the pad's middle


def test_a_concave_stretch_is_bridged_and_a_line_is_met_flat():
    cubic = CURVES["cubical_parabola"]({"a": 0.001, "c": 0.2})  # κ > 0 for t > 0, < 0 for t < 0
    left = solid_left(cubic, [10.0, 20.0, 30.0], 1)
    assert left
    ok = land(cubic, POSE, (-80.0, 80.0), *_aim(cubic, 20.0), left, 1, 6.0, 3.0, 60.0)
    assert ok.why == "" and abs(ok.t - 20.0) < 1e-6
    lost = land(cubic, POSE, (-80.0, 80.0), *_aim(cubic, -20.0), left, 1, 6.0, 3.0, 60.0)
    assert lost.t is None and "end" in lost.why
    line = CURVES["line"]({})
    x, y, phi = _aim(line, 5.0)
    got = land(line, POSE, (-50.0, 50.0), x, y, phi, solid_left(line, [0.0], 1), 1, 6.0, 3.0, 60.0)
    assert got.why == "" and abs(got.t - 5.0) < 0.01  # met flat: the point nearest the pad's middle, to the grid


def test_a_semicubical_branch_near_the_cusp_is_shadowed_and_no_roll_crosses_it():
    """Solid on the branches' convex side: the pad comes in between the branches; near the
    cusp the other branch lies within the pad and is met first by the pad's end; far out
    it does not; a place whose roll would reach the cusp is lost."""
    curve = CURVES["semicubical_parabola"]({"a": 1.0, "b": 0.3})
    left = solid_left(curve, [1.0, 2.0], 1)
    far = land(curve, POSE, (-8.0, 8.0), *_aim(curve, 3.0), left, 1, 1.0, 0.5, 10.0)
    assert far.why == "" and abs(far.t - 3.0) < 1e-6
    near = land(curve, POSE, (-8.0, 8.0), *_aim(curve, 0.5), left, 1, 1.0, 0.5, 10.0)
    assert near.t is None and "end" in near.why
    at_cusp = land(curve, POSE, (-8.0, 8.0), *_aim(curve, 0.3), left, 1, 0.1, 0.05, 10.0)
    assert at_cusp.t is None


def test_a_pad_tilted_a_little_seats_on_a_flat_stretch_and_not_a_lot():
    """A pad tilted 1e-4 rad meets a line (and a hyperbola far out on its arm) with its end;
    it turns to seat on the boundary under its middle and lands there; tilted 0.1 rad (more
    than ``SEAT_RAD``) it is lost."""
    line = CURVES["line"]({})
    hyp = CURVES["hyperbola"]({"a": 1.0, "b": 1.0})
    for curve, t, rng in ((line, 5.0, (-50.0, 50.0)), (hyp, 5.0, (-12.0, 12.0))):
        x, y, phi = _aim(curve, t)
        left = solid_left(curve, [t], 1)
        assert land(curve, POSE, rng, x, y, phi + 1e-4, left, 1, 6.0, 3.0, 60.0, seat=0.0).t is None
        got = land(curve, POSE, rng, x, y, phi + 1e-4, left, 1, 6.0, 3.0, 60.0)
        assert got.why == "" and abs(got.t - t) < 0.01
        assert land(curve, POSE, rng, x, y, phi + 0.1, left, 1, 6.0, 3.0, 60.0).t is None
