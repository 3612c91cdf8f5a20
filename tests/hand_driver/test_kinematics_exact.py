"""Kinematics against exact geometry: FK, IK, and touches from a pad rolled on exact
curves, with and without encoder quantization (the bound is quantization_bound)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.optimize import brentq

from hand_driver import kinematics as kin
from hand_driver import units
from hand_driver.config import load_config
from recognizer.curves import CURVES, Pose
from tactile_common.angles import wrap_angle

CFG = load_config("config/jaw.yaml")


def test_ticks_angles_round_trip_and_direction():
    f = CFG.finger("left")  # direction -1
    q = kin.ticks_to_angles(f.joints, [2048 + 1024, 2048])
    assert q == pytest.approx([-math.pi / 2, 0.0])
    assert kin.angles_to_ticks(f.joints, q) == pytest.approx([3072, 2048])


def test_forward_kinematics_by_hand():
    f = CFG.finger("left")  # base (0, 40), L1 80, L2 65, pad right side, offset 8, length 52
    line = kin.finger_pad_line(f, np.array([math.pi / 2, -math.pi / 2]))
    # link 1 points +y to (0, 120); link 2 points +x; the pad is 8 mm below it (right side)
    assert line.joint2 == pytest.approx([0.0, 120.0])
    assert line.distal == pytest.approx([65.0, 112.0])
    assert line.proximal == pytest.approx([13.0, 112.0])
    assert line.normal == pytest.approx([0.0, -1.0])
    assert float(line.psi) == pytest.approx(-math.pi / 2)
    assert float(line.d) == pytest.approx(-112.0)


@settings(max_examples=60, deadline=None)
@given(st.sampled_from(["left", "right"]), st.floats(-1.5, 1.5), st.floats(-2.5, 2.5))
def test_ik_line_inverts_fk(name, q1, q2):
    f = CFG.finger(name)
    line = kin.finger_pad_line(f, np.array([q1, q2]))
    sols = kin.ik_line_solutions(f, float(line.psi), float(line.d))
    assert sols, "the line of a configuration is always reachable"
    for q in sols:
        again = kin.finger_pad_line(f, q)
        assert float(wrap_angle(again.psi - line.psi)) == pytest.approx(0.0, abs=1e-12)
        assert float(again.d) == pytest.approx(float(line.d), abs=1e-9)
    assert min(float(np.max(np.abs(wrap_angle(q - [q1, q2])))) for q in sols) < 1e-9


@settings(max_examples=40, deadline=None)
@given(st.sampled_from(["left", "right"]), st.sampled_from(["distal", "proximal"]),
       st.floats(-1.5, 1.5), st.floats(-2.5, 2.5))
def test_ik_corner_inverts_fk(name, end, q1, q2):
    f = CFG.finger(name)
    line = kin.finger_pad_line(f, np.array([q1, q2]))
    point = line.distal if end == "distal" else line.proximal
    sols = kin.ik_corner(f, point, margin_rad=-10.0, end=end)  # limits ignored
    assert sols
    for q in sols:
        again = kin.finger_pad_line(f, q)
        assert (again.distal if end == "distal" else again.proximal) == pytest.approx(point, abs=1e-9)


def test_ik_refuses_unreachable_line():
    with pytest.raises(kin.Unreachable, match="finger left"):
        kin.ik_line(CFG.finger("left"), 0.0, 1000.0)


# --------------------------------------------------------------------- rolling on exact curves

CASES = [  # (class, params, pose, side, finger, t of the middle contact)
    ("ellipse", {"a": 28.0, "b": 17.0}, Pose(0.3, 110.0, 0.0), "left", "left", 1.3),
    ("ellipse", {"a": 28.0, "b": 17.0}, Pose(0.3, 110.0, 0.0), "left", "right", -1.7),
    ("circle", {"r": 20.0}, Pose(0.0, 85.0, 10.0), "left", "left", 0.95),
    ("circle", {"r": 20.0}, Pose(0.0, 85.0, 10.0), "left", "right", -0.95),
    ("parabola", {"a": 6.0}, Pose(-1.9, 100.0, 25.0), "right", "left", 0.3),
]


def _roll(cls, params, pose, side, finger, t0, samples=31, step_deg=1.0):
    """Exact tangent-line joint angles for a pad rolled over the curve: increasing ψ."""
    curve = CURVES[cls](params)
    sign = 1.0 if side == "left" else -1.0  # solid on the left of increasing t: tangent is φ
    phi0 = float(curve.tangent_angle(t0)) + pose.theta + (0.0 if sign > 0 else math.pi)
    phis = phi0 + np.radians(step_deg) * (np.arange(samples) - samples // 2)

    def t_of(phi):
        g = lambda t: math.remainder(float(curve.tangent_angle(t)) + pose.theta + (0 if sign > 0 else math.pi) - phi, 2 * math.pi)  # noqa: E731
        return brentq(g, t0 - 1.0, t0 + 1.0, xtol=1e-15)

    ts = np.array([t_of(p) for p in phis])
    x, y = pose.apply(*curve.point(ts))
    f = CFG.finger(finger)
    q = np.array([kin.ik_tangent(f, (a, b), p + math.pi / 2) for a, b, p in zip(x, y, phis)])
    s = np.abs(curve.arc_length(ts[0], ts))
    return f, q, phis, x, y, s


@pytest.mark.parametrize("case", CASES, ids=[f"{c[0]}-{c[4]}" for c in CASES])
def test_touch_from_exact_pad_lines_matches_the_curve(case):
    f, q, phis, x, y, s = _roll(*case)
    line = kin.finger_pad_line(f, q)
    c = kin.touch_from_pad_lines(line.psi, line.d)
    assert np.all(np.diff(c.psi) > 0)
    assert np.max(np.abs(np.vectorize(math.remainder)(c.phi - phis, 2 * math.pi))) < 1e-12
    # truncation of the cubic d(ψ) over a 30° roll: well under the quantization effects
    assert np.max(np.hypot(c.x - x, c.y - y)) < 0.5
    assert np.max(np.abs(c.s - s)) < 0.8
    assert c.s[0] == 0.0 and np.all(np.diff(c.s) > 0)


@pytest.mark.parametrize("case", CASES, ids=[f"{c[0]}-{c[4]}" for c in CASES])
def test_quantized_touch_within_the_quantization_bound(case):
    """Encoder ticks rounded: every output is within (exact-data error) + the first-order
    worst-case quantization bound (×1.05 for second order), for several sub-tick phases."""
    f, q, phis, x, y, s = _roll(*case)
    exact_line = kin.finger_pad_line(f, q)
    exact = kin.touch_from_pad_lines(exact_line.psi, exact_line.d)
    trunc_pt = np.hypot(exact.x - x, exact.y - y)
    trunc_s = np.abs(exact.s - s)
    bound = kin.quantization_bound(f, q)
    half = units.half_tick_rad(kin.resolutions(f.joints))
    assert np.max(bound["phi"]) == pytest.approx(np.sum(half), rel=1e-6)  # ψ = β + q1 + q2
    rng = np.random.default_rng(7)
    for _ in range(5):
        phase = rng.uniform(-0.5, 0.5, size=2)  # a different encoder offset each time
        joints = tuple(type(j)(**{**j.__dict__, "zero_tick": j.zero_tick + p}) for j, p in zip(f.joints, phase))
        ticks = np.rint(kin.angles_to_ticks(joints, q))
        qq = kin.ticks_to_angles(joints, ticks)
        assert np.all(np.abs(qq - q) <= half + 1e-12)
        line = kin.finger_pad_line(f, qq)
        c = kin.touch_from_pad_lines(line.psi, line.d)
        phi_err = np.abs(np.vectorize(math.remainder)(c.phi - phis, 2 * math.pi))
        assert np.all(phi_err <= bound["phi"] * 1.05 + 1e-12)
        assert np.all(np.hypot(c.x - x, c.y - y) <= trunc_pt + 1.05 * bound["point"])
        assert np.all(np.abs(c.s - s) <= trunc_s + 1.05 * bound["s"])


def test_quantization_rms_matches_the_uniform_model():
    """The bound is worst case; the RMS error over random encoder phases is close to the
    uniform-quantization prediction σ = sqrt(Σ J²)·tick/√12 (within a factor 2)."""
    f, q, phis, x, y, s = _roll(*CASES[0])
    h = 1e-6
    base = kin.touch_from_pad_lines(*(lambda ln: (ln.psi, ln.d))(kin.finger_pad_line(f, q)))
    var = np.zeros_like(base.x)
    tick = units.rad_per_tick(kin.resolutions(f.joints))
    for i in range(q.shape[0]):
        for k in range(2):
            dq = np.zeros_like(q)
            dq[i, k] = h
            a = kin.touch_from_pad_lines(*(lambda ln: (ln.psi, ln.d))(kin.finger_pad_line(f, q + dq)))
            b = kin.touch_from_pad_lines(*(lambda ln: (ln.psi, ln.d))(kin.finger_pad_line(f, q - dq)))
            var += ((a.x - b.x) / (2 * h)) ** 2 * tick[k] ** 2
    predicted = math.sqrt(float(np.mean(var)) / 12)
    rng = np.random.default_rng(1)
    errs = []
    for _ in range(60):
        qq = q + rng.uniform(-0.5, 0.5, q.shape) * tick
        ln = kin.finger_pad_line(f, qq)
        errs.append(kin.touch_from_pad_lines(ln.psi, ln.d).x - base.x)
    measured = float(np.sqrt(np.mean(np.square(errs))))
    assert 0.5 * predicted < measured < 2.0 * predicted


def test_touch_rejects_bad_readings():
    with pytest.raises(Exception, match="distinct pad angles"):
        kin.touch_from_pad_lines([0.1, 0.1, 0.1], [1.0, 1.0, 1.0])
    with pytest.raises(Exception, match="≥ 3 pad lines"):
        kin.touch_from_pad_lines([0.1, 0.2], [1.0, 1.0])


def _line_through(point, psi):
    n = np.array([math.cos(psi), math.sin(psi)])
    z = np.zeros(2)
    return kin.PadLine(psi=np.float64(psi), d=np.float64(n @ point), normal=n, tangent=np.array([-n[1], n[0]]),
                       proximal=z, distal=z, joint2=z)


def test_crossing_and_nearest_point_of_pad_lines():
    corner = np.array([113.0, -7.5])
    a, b, c = (_line_through(corner, psi) for psi in (0.3, 1.1, -0.4))
    np.testing.assert_allclose(kin.crossing(a, b), corner, atol=1e-12)
    assert kin.crossing(a, _line_through(corner + 2.0, 0.3)) is None  # parallel
    normals = np.stack([a.normal, b.normal, c.normal])
    np.testing.assert_allclose(kin.nearest_point(normals, [a.d, b.d, c.d]), corner, atol=1e-12)
    # lines 1 mm off the corner on either side of two opposite pairs: the corner, in least squares
    off = [_line_through(corner + s * ln.normal, float(ln.psi)) for ln in (a, b) for s in (1.0, -1.0)]
    np.testing.assert_allclose(kin.nearest_point(np.stack([ln.normal for ln in off]), [ln.d for ln in off]),
                               corner, atol=1e-12)


def test_straight_line_nearest_points():
    """kin.straight_line on points of an exact line 0.5 rad from +x, in pairs 0.03 mm on either
    side of it: the line itself (the offsets cancel at every place), each point's
    coordinates along and across it, its ends; through a point off the line, the line through
    that point nearest them."""
    base, t = np.array([104.0, -6.0]), np.array([math.cos(0.5), math.sin(0.5)])
    n = np.array([-t[1], t[0]])
    s = np.repeat(np.linspace(-9.0, 15.0, 4), 2)
    off = 0.03 * np.array([1.0, -1.0] * 4)
    line = kin.straight_line(base + s[:, None] * t + off[:, None] * n)
    np.testing.assert_allclose(line.centre, base + s.mean() * t, atol=1e-12)
    assert abs(float(line.along @ t)) == pytest.approx(1.0, abs=1e-12)
    assert abs(float(line.across @ n)) == pytest.approx(1.0, abs=1e-12)
    assert line.worst == pytest.approx(0.03, abs=1e-12)
    np.testing.assert_allclose(np.abs(line.v), 0.03, atol=1e-12)
    np.testing.assert_allclose(np.sort(np.abs(line.u)), np.sort(np.abs(s - s.mean())), atol=1e-12)
    np.testing.assert_allclose(sorted(map(tuple, line.ends)), sorted([tuple(base - 9.0 * t), tuple(base + 15.0 * t)]),
                               atol=1e-12)
    # through a point 1 mm off the line at the points' middle: the parallel through it (a tilt
    # takes it farther from the points on one side than it brings it nearer on the other), 1 mm off
    through = base + 3.0 * t + 1.0 * n
    apart = kin.straight_line(base + s[:, None] * t, through=through)
    np.testing.assert_allclose(apart.centre, through)
    assert abs(float(apart.along @ t)) == pytest.approx(1.0, abs=1e-12) and apart.worst == pytest.approx(1.0, abs=1e-12)
    np.testing.assert_allclose(apart.u[:, None] * apart.along + apart.v[:, None] * apart.across,
                               base + s[:, None] * t - through, atol=1e-12)
