"""tools/ros_bag.py's pieces on every class, without a run: the recognized curve's polyline
lies on the answered curve (each class's implicit equation, written out here) through its
contacts; the pose covariance; a flat press's contact touch."""

from __future__ import annotations

import math

import numpy as np
import pytest

from recognizer.curves import CURVES, Pose
from tools.ros_bag import CURVE_POINTS, curve_points, pose_covariance

ANSWERS = [
    ("line", {}, [-12.0, 3.0, 20.0], lambda x, y, p: y),
    ("circle", {"r": 20.0}, [-2.0, 0.3, 1.0], lambda x, y, p: np.hypot(x, y) / p["r"] - 1),
    ("ellipse", {"a": 28.0, "b": 17.0}, [0.2, 1.1, 2.5], lambda x, y, p: (x / p["a"]) ** 2 + (y / p["b"]) ** 2 - 1),
    ("parabola", {"a": 8.0}, [-1.2, 0.1, 0.9], lambda x, y, p: (y ** 2 - 4 * p["a"] * x) / (4 * p["a"]) ** 2),
    ("hyperbola", {"a": 15.0, "b": 20.0}, [-0.8, 0.0, 0.5],
     lambda x, y, p: (x / p["a"]) ** 2 - (y / p["b"]) ** 2 - 1 + (x < 0)),
    ("cubical_parabola", {"a": 0.0008, "c": -0.5}, [-25.0, -3.0, 5.0],
     lambda x, y, p: (y - p["a"] * x ** 3 - p["c"] * x) / 100.0),
    ("semicubical_parabola", {"a": 0.5, "b": -0.2}, [-3.0, -1.0, 2.0],
     lambda x, y, p: ((y - p["b"] * x) ** 2 - p["a"] ** 2 * x ** 3) / 1e3 + (x < -1e-9)),
]


@pytest.mark.parametrize("cls, params, ts, implicit", ANSWERS, ids=[a[0] for a in ANSWERS])
def test_curve_polyline_lies_on_the_answer_through_its_contacts(cls, params, ts, implicit):
    pose = Pose(0.7, 104.0, -6.0)
    curve = CURVES[cls](params)
    cx, cy = pose.apply(*curve.point(np.array(ts)))
    answer = {"class": cls, "params": params, "pose": pose.to_json(),
              "contacts": [{"t": t, "x": float(x), "y": float(y)} for t, x, y in zip(ts, cx, cy)]}
    xy = curve_points(answer)
    assert xy.shape == (CURVE_POINTS, 2) and np.all(np.isfinite(xy))
    u, v = pose.inverse(xy[:, 0], xy[:, 1])
    assert np.allclose(implicit(u, v, params), 0.0, atol=1e-9)
    step = np.max(np.hypot(*np.diff(xy, axis=0).T))
    for x, y in zip(cx, cy):  # every contact on the polyline, within a segment's length
        assert np.min(np.hypot(xy[:, 0] - x, xy[:, 1] - y)) <= step
    if curve.t_period is None:  # 20 mm of arc beyond the outermost contacts
        t_lo, t_hi = (float(t) for t in pose_params_of(curve, xy[[0, -1]], pose))
        assert float(curve.arc_length(t_lo, min(ts))) == pytest.approx(20.0, rel=1e-6)
        assert float(curve.arc_length(max(ts), t_hi)) == pytest.approx(20.0, rel=1e-6)


def pose_params_of(curve, points, pose):
    """The canonical t of the polyline's two ends (their x, or the t whose x and y they are)."""
    u, v = pose.inverse(points[:, 0], points[:, 1])
    if curve.name in ("line", "cubical_parabola"):
        return u
    if curve.name == "parabola":
        return v / (2 * curve.a)
    if curve.name == "hyperbola":
        return np.arcsinh(v / curve.b)
    return np.sign(v - curve.b * u) * np.sqrt(u) * np.sign(curve.a)  # semicubical: t = ±√x


def test_pose_covariance_in_si_units_and_unknowns():
    cov = np.array(pose_covariance({"pose_x": 0.5, "pose_y": 0.2, "pose_theta": 0.01})).reshape(6, 6)
    assert np.allclose(np.diag(cov), [0.5e-3 ** 2, 0.2e-3 ** 2, 0, 0, 0, 1e-4], rtol=1e-12, atol=0)
    assert np.count_nonzero(cov - np.diag(np.diag(cov))) == 0
    line = pose_covariance({"pose_theta": 0.002})  # a line's answer has no pose_x / pose_y
    assert line[0] == -1.0 and line[7] == -1.0 and line[35] == pytest.approx(4e-6)
    assert math.isclose(sum(abs(c) for c in line), 2 + 4e-6)


def test_a_flat_press_is_one_contact_and_a_line_has_no_pose_sigma(tmp_path):
    """A flat press reaches the recognizer as one contact touch (the face's middle and
    angle): one contact point and one tangent; a line answer's pose covariance says
    unknown where its σ is missing."""
    from hand_driver.config import config_to_mapping, load_config
    from test_ros_bag import read_bag  # the bag tests' independent reader (pytest puts tests/tools on the path)
    from tools.ros_bag import BagWriter

    path = tmp_path / "flat.mcap"
    with open(path, "wb") as stream:
        bag = BagWriter(stream, durable=True)
        bag.record({"type": "header", "start_time": "2026-11-26T12:00:00+00:00", "monotonic_origin": 100.0,
                    "config": config_to_mapping(load_config("config/jaw.yaml"))})
        bag.record({"type": "reading", "i": 0, "t": 100.5, "ticks": [1942, 2154, 1942, 2154]})
        bag.record({"type": "sample", "touch": 3, "reading": 0})
        bag.record({"type": "event", "kind": "touch_used", "message": "m", "touch": 3,
                    "samples": {"contact": {"x": 105.0, "y": 10.0, "phi": math.pi, "kappa": 0, "kappa_s": 0}}})
        bag.answer({"class": "line", "params": {}, "pose": {"theta": math.pi, "x": 0.0, "y": 10.0},
                    "contacts": [{"t": -105.0, "x": 105.0, "y": 10.0}], "uncertainty": {"pose_theta": 0.001}})
        bag.close()
    messages = read_bag(path)
    (touch,) = messages["/jaw/touches"]
    contacts, tangents = touch.msg.markers
    assert [(p.x, p.y) for p in contacts.points] == [(0.105, 0.01)] and len(tangents.points) == 2
    assert touch.ns == 1_795_694_400_500_000_000  # 12:00:00 + (100.5 - 100.0) s
    (pose,) = messages["/recognition/pose"]
    assert list(pose.msg.pose.covariance)[:8:7] == [-1.0, -1.0]
    (curve,) = messages["/recognition/curve"]
    ys = {round(p.y, 12) for p in curve.msg.markers[0].points}
    assert ys == {0.01}
