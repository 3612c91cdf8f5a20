"""The end-sample deletion test (tactile_jaw.end_sample, tactile_jaw.decide.without_corner_end)
against an exact parabola: a roll's end line that is a corner's line past the curve's end is
left out, an end line tangent to the curve is kept."""

from __future__ import annotations

import math
from dataclasses import dataclass
from types import SimpleNamespace

import numpy as np
import pytest

from recognizer.curves import Pose
from recognizer.result import Ranked, Recognition
from tactile_jaw.decide import MISFIT_ALPHA, without_corner_end
from tactile_jaw.end_sample import corner_end, end_z, tangent_point

A = 5.0  # the parabola (a t², 2a t), posed
POSE = Pose(0.3, 10.0, -4.0)
SIGMA = 1e-3  # each pad line's σ (mm)


def _normal(t: float) -> np.ndarray:
    """The unit normal of the posed parabola at t on its convex side: n·p is least at p(t)."""
    n = np.array([1.0, -t]) / math.hypot(1.0, t)
    c, s = math.cos(POSE.theta), math.sin(POSE.theta)
    return np.array([c * n[0] - s * n[1], s * n[0] + c * n[1]])


def _point(t: float) -> np.ndarray:
    x, y = POSE.apply(A * t * t, 2 * A * t)
    return np.array([float(x), float(y)])


def _answer(cov_scale: float = 1e-12) -> Recognition:
    ts = np.linspace(-0.3, 0.3, 7)
    contacts = [{"t": float(t), "x": float(_point(t)[0]), "y": float(_point(t)[1])} for t in ts]
    return Recognition("parabola", {"a": A}, POSE, contacts, ranking=[Ranked("parabola", True, 5.0, 10, 20.0, 0.5)],
                       cov_pose=np.eye(4) * cov_scale)


def test_support_is_the_tangent_lines_offset():
    vec = np.array([A, POSE.theta, POSE.x, POSE.y])
    for t in (-0.3, 0.0, 0.25):
        got = tangent_point("parabola", vec, (-1.0, 1.0), _normal(t), tuple(_point(t)), 2.0)[0]
        assert got == pytest.approx(float(_normal(t) @ _point(t)), abs=1e-9)


def test_a_tangent_end_line_is_on_the_curve_and_a_corner_line_lies_past_it():
    answer = _answer()
    t_end = 0.3
    tangent = end_z(answer, float(_normal(t_end) @ _point(t_end)), SIGMA, _normal(t_end), tuple(_point(t_end)), 6.0)
    assert abs(tangent) < 0.01
    # the pad turned on past the end: the line of the tangent direction at t 0.36 through the end corner p(0.3)
    turned = _normal(0.36)
    corner = end_z(answer, float(turned @ _point(t_end)), SIGMA, turned, tuple(_point(t_end)), 6.0)
    past = float(turned @ _point(t_end)) - float(turned @ _point(0.36))  # how far the corner line lies past
    assert past > 5 * SIGMA
    assert corner == pytest.approx(past / SIGMA, rel=1e-3)
    # the refit's own uncertainty at the end widens the denominator: a looser class fit, a smaller z
    loose = end_z(_answer(1e-4), float(turned @ _point(t_end)), SIGMA, turned, tuple(_point(t_end)), 6.0)
    assert 0 < loose < corner


@dataclass(frozen=True)
class _Touch:
    finger: str
    touch: int
    samples: tuple


def _roll(touch: int, ts: list[float], corner_last: bool = False):
    """A felt roll of degree 4 whose lines are the parabola's tangents at ``ts`` (ψ rising
    with t); with ``corner_last`` its last line turns on about the point of the one before."""
    normals = [_normal(t) for t in ts]
    d = [float(n @ _point(t)) for n, t in zip(normals, ts)]
    if corner_last:
        normals[-1] = _normal(ts[-1] + 0.03)
        d[-1] = float(normals[-1] @ _point(ts[-2]))
    n = len(ts)
    contacts = SimpleNamespace(degree=4, order=np.arange(n), x=np.array([_point(t)[0] for t in ts]),
                               y=np.array([_point(t)[1] for t in ts]))
    samples = tuple(SimpleNamespace(psi=float(t), reading=100 * touch + i) for i, t in enumerate(ts))
    return SimpleNamespace(touch=_Touch("left", touch, samples), lines=SimpleNamespace(d=np.array(d), normal=np.array(normals)),
                           fit=SimpleNamespace(contacts=contacts, line_sigma=np.full(n, SIGMA)))


def _refeel(touch, samples):
    return SimpleNamespace(touch=touch, problem=None, fit=None, lines=None)


def _recognizer(calls):
    def run(touches, classes=None, reach=None):
        calls.append(classes)
        return _answer()
    return run


def test_the_corner_end_of_a_roll_is_left_out_and_on_curve_ends_kept():
    touches = [_roll(2, list(np.linspace(-0.3, -0.1, 9))), _roll(5, list(np.linspace(0.1, 0.3, 9)), corner_last=True)]
    calls = []
    got = without_corner_end(_recognizer(calls), touches, _answer(), _refeel)
    assert got is not None
    deletion, rest = got
    assert (deletion.touch, deletion.end, deletion.reading, deletion.tested) == (5, "last", 508, 4)
    assert deletion.limit == pytest.approx(3.48, abs=0.01)  # norm.isf(1e-3 / 4)
    assert deletion.z > deletion.limit
    assert rest[0] is touches[0] and tuple(rest[1].touch.samples) == touches[1].touch.samples[:-1]
    assert calls == [("parabola",)] * 4  # one single-class refit per tested end
    assert deletion.event()["kind"] == "end_sample_left_out" and "touch 5's last sample" in deletion.note()


def test_on_curve_ends_are_kept_and_no_lower_degree_roll_is_tested():
    touches = [_roll(2, list(np.linspace(-0.3, -0.1, 9))), _roll(5, list(np.linspace(0.1, 0.3, 9)))]
    assert without_corner_end(_recognizer([]), touches, _answer(), _refeel) is None
    low = _roll(5, list(np.linspace(0.1, 0.3, 9)), corner_last=True)
    low.fit.contacts.degree = 3
    calls = []
    assert corner_end(_recognizer(calls), [touches[0], low], _answer(), _refeel, MISFIT_ALPHA) is None
    assert len(calls) == 2  # the degree-4 roll's two ends only


def test_no_answer_covariance_no_test():
    touches = [_roll(5, list(np.linspace(0.1, 0.3, 9)), corner_last=True)]
    answer = _answer()
    bare = Recognition(answer.cls, answer.params, answer.pose, answer.contacts, ranking=answer.ranking)
    assert without_corner_end(_recognizer([]), touches, bare, _refeel) is None


@pytest.mark.parametrize("cls, params", [("parabola", {"a": A}), ("ellipse", {"a": 30.0, "b": 12.0}),
                                         ("semicubical_parabola", {"a": 0.4, "b": -0.7})])
def test_support_gradient_is_the_supports_derivative(cls, params):
    """The envelope theorem's gradient (one curve evaluation at the tangent point) against
    central differences of the support itself, every shape and pose unknown."""
    from recognizer.curves import CURVES
    from tactile_jaw.end_sample import support_gradient
    vec = np.array(list(params.values()) + [POSE.theta, POSE.x, POSE.y])
    curve = CURVES[cls](params)
    t0 = 1.1
    phi = float(curve.tangent_angle(np.array([t0]))[0]) + POSE.theta
    near = tuple(float(q) for q in POSE.apply(*(float(q[0]) for q in curve.point(np.array([t0])))))
    for side in (1.0, -1.0):  # the normal toward the centre of curvature: n·p is least at t0
        normal = side * np.array([-math.sin(phi), math.cos(phi)])
        args = ((0.5, 1.7), normal, near, 3.0)
        h, t = tangent_point(cls, vec, *args)
        if math.isfinite(t):
            break
    assert t == pytest.approx(t0, abs=1e-4) and h == tangent_point(cls, vec, *args)[0]
    grad = support_gradient(cls, vec, t, normal)
    for i in range(vec.size):
        step = np.zeros(vec.size)
        step[i] = 1e-4
        fd = (tangent_point(cls, vec + step, *args)[0] - tangent_point(cls, vec - step, *args)[0]) / 2e-4
        assert grad[i] == pytest.approx(fd, rel=1e-4, abs=1e-6)
