"""Contact physics: pads stop exactly at tangency on every curve class, pad ends stop on
the boundary, nothing ever penetrates, fingers are independent."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from hand_driver import kinematics as kin
from hand_driver.config import load_config
from hand_driver.sim.physics import ContactWorld
from recognizer.curves import CURVES, Pose
from recognizer.scene import SceneObject
from tactile_common.angles import wrap_angle

CFG = load_config("config/jaw.yaml")
LEFT = CFG.finger("left")
RIGHT_PARK = np.array([-1.3, -0.9])

# (class, params, side, t*): the solid is locally convex toward the pad at t*
CLASSES = [
    ("ellipse", {"a": 28.0, "b": 17.0}, "left", 1.2),
    ("circle", {"r": 20.0}, "left", 0.4),
    ("parabola", {"a": 6.0}, "right", 0.4),
    ("hyperbola", {"a": 10.0, "b": 8.0}, "right", 0.3),
    ("cubical_parabola", {"a": 2e-5, "c": 0.01}, "right", -40.0),
    ("semicubical_parabola", {"a": 0.5, "b": 0.2}, "left", 4.0),
    ("line", {}, "right", 0.0),
]


def _object_touching_at(cls, params, side, t, at=(105.0, 18.0)):
    """The object posed so that its boundary at t is at ``at`` with outward normal +y."""
    curve = CURVES[cls](params)
    phi = float(curve.tangent_angle(t)) + (0.0 if side == "left" else math.pi)  # solid on the left
    theta = math.pi - phi  # the solid-on-the-left tangent points along -x: solid below, normal +y
    px, py = curve.point(t)
    c, s = math.cos(theta), math.sin(theta)
    pose = Pose(theta, at[0] - (c * float(px) - s * float(py)), at[1] - (s * float(px) + c * float(py)))
    kappa_left = float(curve.kappa(t)) * (1.0 if side == "left" else -1.0)
    assert kappa_left >= 0.0, "test set-up: the boundary must be convex toward the pad"
    return SceneObject(cls, params, pose, side)


@pytest.mark.parametrize("cls, params, side, t", CLASSES, ids=[c[0] for c in CLASSES])
def test_pad_stops_at_exact_tangency(cls, params, side, t):
    obj = _object_touching_at(cls, params, side, t)
    world = ContactWorld(CFG, obj)
    psi = -math.pi / 2  # pad facing down onto the point (105, 18)
    d_touch = -18.0
    q_out = kin.ik_line(LEFT, psi, d_touch - 5.0, contact=(105.0, 23.0))
    q_in = kin.ik_line(LEFT, psi, d_touch + 5.0, contact=(105.0, 13.0))
    q_from, q_to = np.r_[q_out, RIGHT_PARK], np.r_[q_in, RIGHT_PARK]
    assert not world.penetrates(q_from, [0]) and world.penetrates(q_to, [0])
    q = world.constrain(q_from, q_to)
    line = kin.finger_pad_line(LEFT, q[:2])
    assert float(wrap_angle(line.psi - psi)) == pytest.approx(0.0, abs=1e-12)  # ψ = q1 + q2 is linear in q
    assert float(line.d) == pytest.approx(d_touch, abs=1e-4)
    assert not world.penetrates(q, [0])
    assert world.penetrates(q + 1e-5 * (q_to - q_from), [0])
    assert q[2:] == pytest.approx(RIGHT_PARK)
    info = {c.finger: c for c in world.contact_info(q)}
    assert info["left"].gap_mm < 0.05 and not info["left"].penetrating


@pytest.mark.parametrize("t", [0.1, 0.4, 0.9, 1.7])
def test_a_fine_jaw_stops_at_tangency_within_a_fraction_of_its_tick(t):
    """The stop is the last configuration without penetration, so whatever gap the bisection
    leaves is on one side: a bias in every reading, which must stay far below what the jaw's
    encoders resolve. The P-series jaw's tick moves its pad ~6e-4 mm; the former 1e-6 rad
    tolerance left up to 1e-4 mm (its circles' r came out high by ~5e-5 mm, z +1 on average)."""
    fine = load_config("config/jaw-p.yaml")
    left = fine.finger("left")
    world = ContactWorld(fine, _object_touching_at("circle", {"r": 20.0}, "left", t))
    q_out = kin.ik_line(left, -math.pi / 2, -23.0, contact=(105.0, 23.0))
    q_in = kin.ik_line(left, -math.pi / 2, -13.0, contact=(105.0, 13.0))
    q = world.constrain(np.r_[q_out, RIGHT_PARK], np.r_[q_in, RIGHT_PARK])
    assert not world.penetrates(q, [0])
    assert float(kin.finger_pad_line(left, q[:2]).d) == pytest.approx(-18.0, abs=2e-6)


def test_pad_end_stops_on_a_disk():
    """Edge contact: the fingertip corner pushed radially into a disk stops on its circle."""
    obj = SceneObject("circle", {"r": 20.0}, Pose(0.0, 85.0, 10.0), "left")
    world = ContactWorld(CFG, obj)
    m = np.array([math.cos(1.2), math.sin(1.2)])
    c = np.array([85.0, 10.0])
    sols_out = [q for q in kin.ik_corner(LEFT, c + 25.0 * m)
                if float(-kin.finger_pad_line(LEFT, q).tangent @ m) > 0.3]  # the pad leaves the disk
    assert sols_out
    q_out = sols_out[0]
    assert not world.penetrates(np.r_[q_out, RIGHT_PARK])
    q_in = min(kin.ik_corner(LEFT, c + 15.0 * m, margin_rad=-10), key=lambda q: float(np.sum((q - q_out) ** 2)))
    q = world.constrain(np.r_[q_out, RIGHT_PARK], np.r_[q_in, RIGHT_PARK])
    line = kin.finger_pad_line(LEFT, q[:2])
    ab = line.distal - line.proximal
    u = float(np.clip((c - line.proximal) @ ab / (ab @ ab), 0.0, 1.0))
    assert float(np.hypot(*(line.proximal + u * ab - c))) == pytest.approx(20.0, abs=1e-4)  # touching
    assert u in (0.0, 1.0)  # at a pad end: an edge contact
    assert not world.penetrates(q)


def test_far_from_the_object_every_step_is_free():
    obj = SceneObject("circle", {"r": 10.0}, Pose(0.0, 200.0, 0.0), "left")
    world = ContactWorld(CFG, obj)
    q0 = np.array([0.5, 0.3, -0.5, -0.3])
    assert world.clearance(q0) > 5.0
    assert np.array_equal(world.constrain(q0, q0 + 0.001), q0 + 0.001)


def test_a_blocked_finger_does_not_stop_the_other():
    obj = _object_touching_at("circle", {"r": 20.0}, "left", 0.4)
    world = ContactWorld(CFG, obj)
    q_out = kin.ik_line(LEFT, -math.pi / 2, -23.0, contact=(105.0, 23.0))
    q_in = kin.ik_line(LEFT, -math.pi / 2, -13.0, contact=(105.0, 13.0))
    q = world.constrain(np.r_[q_out, -0.7, -0.5], np.r_[q_in, -0.6, -0.4])
    assert q[2:] == pytest.approx([-0.6, -0.4])
    assert float(kin.finger_pad_line(LEFT, q[:2]).d) == pytest.approx(-18.0, abs=1e-4)


ELLIPSE = ContactWorld(CFG, SceneObject("ellipse", {"a": 28.0, "b": 17.0}, Pose(0.3, 110.0, 0.0), "left"))


@settings(max_examples=60, deadline=None)
@given(st.lists(st.floats(-1.2, 1.2), min_size=4, max_size=4), st.lists(st.floats(-1.2, 1.2), min_size=4, max_size=4))
def test_constrained_steps_never_penetrate(a, b):
    q_from, q_to = np.array(a), np.array(b)
    if ELLIPSE.penetrates(q_from):
        return
    q = ELLIPSE.constrain(q_from, q_to)
    assert not ELLIPSE.penetrates(q)
    moved = q - q_from
    full = q_to - q_from
    for i in range(2):  # each finger went a fraction of its own step along the straight line
        sl = slice(2 * i, 2 * i + 2)
        if float(full[sl] @ full[sl]) > 1e-12:
            frac = float(moved[sl] @ full[sl] / (full[sl] @ full[sl]))
            assert -1e-12 <= frac <= 1 + 1e-12
            assert moved[sl] == pytest.approx(frac * full[sl], abs=1e-12)
