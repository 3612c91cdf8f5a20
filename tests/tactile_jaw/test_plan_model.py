"""The explorer's object model (felt tangent lines → predicted tangent) against exact
ellipse support functions, and the opened jaw's pose."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from hand_driver import kinematics as kin
from hand_driver.config import load_config
from hand_driver.cycle import LIMIT_MARGIN_RAD
from hand_driver.motion import Sample, TouchResult
from tactile_jaw.pipeline import FeltTouch
from tactile_jaw.plan import (MODEL_EXTRAPOLATE_DEG, PROBE_PAD_MARGIN, PROBE_SAMPLES, PROBE_SPAN_DEG, ObjectModel, open_pose,
                              probe_face_contact, retreat_offset)

CONFIG = load_config("config/jaw.yaml")


def ellipse_support(psi, a, b, theta, c):
    """Closed form: the line of normal n(ψ) first meeting the ellipse, d = min n·p over it,
    and the tangent point p = c − A n / √(nᵀ A n), A = R diag(a², b²) Rᵀ."""
    r = np.array([[math.cos(theta), -math.sin(theta)], [math.sin(theta), math.cos(theta)]])
    amat = r @ np.diag([a * a, b * b]) @ r.T
    n = np.array([math.cos(psi), math.sin(psi)])
    root = math.sqrt(float(n @ amat @ n))
    return float(n @ c) - root, np.asarray(c) - amat @ n / root


def test_support_closed_form_matches_dense_sampling():
    a, b, theta, c = 28.0, 17.0, 0.3, np.array([110.0, 0.0])
    t = np.linspace(0, 2 * math.pi, 200001)
    pts = np.stack([a * np.cos(t), b * np.sin(t)], axis=-1) @ np.array(
        [[math.cos(theta), math.sin(theta)], [-math.sin(theta), math.cos(theta)]]) + c
    for psi in np.radians([-120.0, -90.0, -30.0, 45.0, 100.0]):
        d, p = ellipse_support(psi, a, b, theta, c)
        v = pts @ np.array([math.cos(psi), math.sin(psi)])
        assert d == pytest.approx(float(v.min()), abs=1e-6)
        assert np.hypot(*(p - pts[int(np.argmin(v))])) < 1e-2


@settings(max_examples=25, deadline=None)
@given(a=st.floats(15.0, 35.0), ratio=st.floats(0.5, 1.0), theta=st.floats(-math.pi, math.pi),
       psi0=st.floats(-math.pi, math.pi))
def test_model_predicts_tangent_lines_between_and_beyond_felt_ones(a, ratio, theta, psi0):
    """Two touches' worth of lines 20° apart on ellipses with radii of curvature 7..70 mm:
    inside their span the prediction is within 0.08 mm (d) and 1.6 mm (point) of the exact
    tangent (measured worst over 3000 random cases: 0.055 mm, 1.24 mm); 10° beyond, within
    0.45 mm and 7.5 mm (measured 0.31 mm, 5.6 mm), inside the planner's 10 mm approach margin."""
    b, c = a * ratio, np.array([110.0, 0.0])
    model = ObjectModel(c, 45.0)
    for centre in (psi0, psi0 + math.radians(20.0)):
        for k in range(-2, 3):
            psi = centre + math.radians(3.0 * k)
            model.add(psi, ellipse_support(psi, a, b, theta, c)[0])
    for off, tol_d, tol_p in ((5.0, 0.08, 1.6), (10.0, 0.08, 1.6), (20.0, 0.08, 1.6),
                              (-10.0, 0.45, 7.5), (30.0, 0.45, 7.5)):
        psi = psi0 + math.radians(off)
        d_true, p_true = ellipse_support(psi, a, b, theta, c)
        d, p = model.tangent(psi)
        assert d == pytest.approx(d_true, abs=tol_d)
        assert np.hypot(*(p - p_true)) < tol_p


def test_model_refuses_where_nothing_was_felt():
    model = ObjectModel([110.0, 0.0], 45.0)
    assert model.tangent(0.0) is None
    model.add(0.0, 10.0)
    assert model.tangent(0.0) is None  # one line: no derivative, no contact point
    model.add(math.radians(4.0), 10.2)
    assert model.tangent(math.radians(2.0)) is not None
    assert model.tangent(math.radians(4.0 + MODEL_EXTRAPOLATE_DEG + 1.0)) is None


def test_open_pose_puts_every_pad_on_the_workspace_edge_outside_the_disk():
    q = open_pose(CONFIG)
    ws = CONFIG.workspace
    centre = np.asarray(ws.center_mm)
    for f, sl in zip(CONFIG.fingers, CONFIG.joint_slices().values()):
        assert kin.within_limits(f.joints, q[sl])
        line = kin.finger_pad_line(f, q[sl])
        assert float(line.normal @ centre) - float(line.d) == pytest.approx(ws.radius_mm, abs=1e-9)
        for end in (line.proximal, line.distal):
            assert np.hypot(*(end - centre)) >= ws.radius_mm - 1e-9


def test_retreat_offset_where_the_workspace_edge_is_out_of_reach():
    """At a pad normal far past its zero-angle normal the left finger cannot stretch out to
    the workspace edge; where the model knows the object (an ellipse felt there) the pad
    retreats to the farthest line it reaches, still ≥ 10 mm outside the predicted tangent;
    where nothing was felt it may not come inward at all."""
    left = CONFIG.finger("left")
    ws = CONFIG.workspace
    a, b, theta, c = 20.0, 12.0, 0.0, np.array(ws.center_mm, dtype=float)
    psi = math.radians(-128.0)
    bare = ObjectModel(ws.center_mm, ws.radius_mm)
    with pytest.raises(kin.Unreachable):
        kin.ik_line(left, psi, bare.edge(psi), margin_rad=LIMIT_MARGIN_RAD)
    assert retreat_offset(left, bare, psi) is None
    model = ObjectModel(ws.center_mm, ws.radius_mm)
    for k in range(-4, 5):
        model.add(psi + math.radians(3.0 * k), ellipse_support(psi + math.radians(3.0 * k), a, b, theta, c)[0])
    d = retreat_offset(left, model, psi)
    assert d is not None and model.edge(psi) < d <= ellipse_support(psi, a, b, theta, c)[0] - 10.0 + 0.1
    kin.ik_line(left, psi, d, margin_rad=LIMIT_MARGIN_RAD)  # reachable
    with pytest.raises(kin.Unreachable):
        kin.ik_line(left, psi, d - 1.0, margin_rad=LIMIT_MARGIN_RAD)  # and the farthest out that is


def _probe(points, psis) -> tuple[FeltTouch, np.ndarray]:
    """A left-finger probe whose samples put the pad through ``points`` with normals ``psis``
    (two joints: the line fixes the pad), read through whole encoder ticks as the jaw reads
    them; and each point's position along its sample's pad (mm)."""
    left = CONFIG.finger("left")
    q = [kin.ik_tangent(left, p, a, margin_rad=LIMIT_MARGIN_RAD) for p, a in zip(points, psis)]
    ticks = np.rint([kin.angles_to_ticks(left.joints, qk) for qk in q])
    samples = [Sample(k, float(a), t, kin.finger_pad_line_from_ticks(CONFIG, "left", t), None, 0.0)
               for k, (a, t) in enumerate(zip(psis, ticks))]
    touch = TouchResult("left", 0, float(np.mean(psis)), samples)
    u = np.array([float(kin.finger_pad_line(left, qk).pad_coordinate(p)) for qk, p in zip(q, points)])
    return FeltTouch(touch, kin.finger_pad_line_from_ticks(CONFIG, "left", ticks), None, None, None, None), u


def left_pad_length() -> float:
    return CONFIG.finger("left").pad.length_mm


def _probe_psis(psi0_deg: float) -> np.ndarray:
    return math.radians(psi0_deg) + np.radians(np.linspace(-PROBE_SPAN_DEG / 2, PROBE_SPAN_DEG / 2, PROBE_SAMPLES))


@pytest.mark.parametrize("radius", [8.0, 15.0, 25.0, 40.0])
@pytest.mark.parametrize("psi0_deg", [-110.0, -90.0, -70.0])
def test_a_probe_rolling_on_a_circle_is_a_face_contact(radius, psi0_deg):
    """A probe's 4 samples over 6° on circles of radius 8–25 mm at the workspace's centre,
    pad lines through whole ticks (up to 0.1 mm off, so the slope d' over 6° and with it
    the point along the pad are uncertain by ~2 mm): a face contact, found where it was
    (the cubic envelope's arc length, noise ~100 mm in ρ over 6°, refused most of these)."""
    c = np.array(CONFIG.workspace.center_mm)
    psis = _probe_psis(psi0_deg)
    try:
        felt, u_true = _probe([c - radius * np.array([math.cos(a), math.sin(a)]) for a in psis], psis)
    except kin.Unreachable:
        pytest.skip("this circle's contact is off the pad at this pad normal")
    margin, length = PROBE_PAD_MARGIN * left_pad_length(), left_pad_length()
    u = probe_face_contact(CONFIG, felt)
    if np.all((u_true > margin + 2.5) & (u_true < length - margin - 2.5)):  # well on the pad's face
        assert u == pytest.approx(u_true[PROBE_SAMPLES // 2], abs=2.5)
    elif np.any((u_true < margin - 2.5) | (u_true > length - margin + 2.5)):  # well past the margin
        assert u is None


@pytest.mark.parametrize("pad_u, face", [(1.5, False), (50.5, False), (26.0, True)])
def test_a_probe_pivoting_about_one_point_is_a_face_contact_only_off_the_pad_ends(pad_u, face):
    """Pad lines turning about one point: a pad end resting on the object (refused) or a
    corner on the pad's face (its lines are the solid's support lines: kept for the model)."""
    left = CONFIG.finger("left")
    psis = _probe_psis(-90.0)
    line = kin.finger_pad_line(left, kin.ik_line(left, float(np.mean(psis)), -20.0, margin_rad=LIMIT_MARGIN_RAD))
    corner = line.proximal + pad_u * line.tangent
    felt, u_true = _probe([corner] * PROBE_SAMPLES, psis)
    assert np.allclose(u_true, pad_u, atol=1.0)
    u = probe_face_contact(CONFIG, felt)
    assert (u is not None) == face
    if face:
        assert u == pytest.approx(pad_u, abs=2.5)
