"""A roll's contact travels along the curve (tactile_jaw.plan.RolledArc): the closed form against
exact curves, and a move's feasibility that holds the contact at its aim no longer promises a
roll whose contact runs off the pad (tactile_jaw.choose.JawReach.finger with curvature)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
from scipy import integrate

from hand_driver import kinematics as kin
from hand_driver.config import load_config
from hand_driver.cycle import LIMIT_MARGIN_RAD
from hand_driver.motion import roll_angles
from recognizer.curves import CURVES, Pose
from recognizer.result import Recognition
from tactile_jaw.choose import JawReach, curvature_at
from tactile_jaw.plan import PLAN_PAD_MARGIN, RolledArc, rolled_arc
from tactile_jaw.settings import ExploreSettings

ROOT = Path(__file__).resolve().parents[2]
CONFIG = load_config(ROOT / "config" / "jaw.yaml")
SETTINGS = ExploreSettings.from_profile("balanced")
ELLIPSE = CURVES["ellipse"]({"a": 30.0, "b": 15.0})


def _ellipse_place(t0: float) -> tuple[np.ndarray, float, float, float]:
    """(point, ψ, κ, κ_s) at t0 of ELLIPSE (counterclockwise: the solid lies left of travel, so
    the pad's normal pointing into it is the tangent + π/2)."""
    t = np.array([t0])
    p = np.array([float(v[0]) for v in ELLIPSE.point(t)])
    return p, float(ELLIPSE.tangent_angle(t)[0]) + math.pi / 2, float(ELLIPSE.kappa(t)[0]), float(ELLIPSE.kappa_s(t)[0])


def _ellipse_contact(psi: float) -> np.ndarray:
    """The exact point of ELLIPSE whose inward normal is ψ: where the outward normal
    (cos t / a, sin t / b) points along −n(ψ)."""
    t = math.atan2(-math.sin(psi) * ELLIPSE.b, -math.cos(psi) * ELLIPSE.a)
    return np.array([ELLIPSE.a * math.cos(t), ELLIPSE.b * math.sin(t)])


def test_a_rolls_contact_is_the_closed_form_integral_of_the_radius_of_curvature_over_the_roll():
    half = math.radians(9.0)
    for t0 in (0.3, 1.0, 2.0, -2.6):
        p0, psi0, kappa, kappa_s = _ellipse_place(t0)
        arc = rolled_arc(float(p0[0]), float(p0[1]), psi0, kappa, kappa_s)
        assert np.allclose(arc.contact(psi0), p0, atol=1e-12)
        for a in (psi0 - half, psi0 + half):
            exact = _ellipse_contact(a)
            travel = float(np.hypot(*(exact - p0)))
            assert travel > 1.4  # what a contact held at the aim leaves out
            # ρ linear in ψ from κ, κ_s (eqs. 6, 7): the rest is third order in the roll
            assert np.hypot(*(arc.contact(a) - exact)) < 0.15 + 0.02 * travel
            # the closed form is p₀ − ∫ρ(u) n'(u) du over the roll, ρ(u) = ρ₀ + ρ'(u − ψ₀)
            quad = [integrate.quad(lambda u, k=k: (arc.rho + arc.drho * (u - psi0)) * (-math.sin(u), math.cos(u))[k],
                                   psi0, a, epsabs=1e-12)[0] for k in (0, 1)]
            assert np.allclose(arc.contact(a), p0 - np.array(quad), atol=1e-9)
    # a circle: exact
    c, rho = np.array([100.0, -5.0]), 43.0
    psi0 = math.radians(-90.0)
    arc = RolledArc(*(c - rho * kin.unit(psi0)), psi0, rho)
    for a in np.radians([-99.0, -81.0, -60.0]):
        assert np.allclose(arc.contact(float(a)), c - rho * kin.unit(float(a)), atol=1e-9)


def test_a_move_is_not_promised_a_roll_whose_contact_runs_off_the_pad():
    # a circle of ρ 43 mm under the left pad at (100, 10) mm, pad normal −90°: held at the aim
    # the contact lies 10.3–10.7 mm along the pad at both ends of an 18° roll; travelling along
    # the circle it is 3.3 mm along at −81° (calibrated cubical 54 of seed 281: ~6.8 mm of travel)
    reach, left, rho = JawReach(CONFIG, SETTINGS), CONFIG.finger("left"), 43.0
    x, y, psi0 = 100.0, 10.0, math.radians(-90.0)
    centre = np.array([x, y]) + rho * kin.unit(psi0)
    ends = []
    for a in roll_angles(psi0, SETTINGS.roll_span_rad, SETTINGS.samples_per_touch)[[0, -1]]:
        p = centre - rho * kin.unit(float(a))
        ends.append([float(kin.finger_pad_line(left, q).pad_coordinate(p))
                     for q in kin.ik_line_solutions(left, float(a), float(kin.unit(float(a)) @ p))
                     if kin.within_limits(left.joints, q, LIMIT_MARGIN_RAD)])
    margin = PLAN_PAD_MARGIN * left.pad.length_mm
    assert any(not any(margin <= u <= left.pad.length_mm - margin for u in end) for end in ends)
    assert reach.finger(x, y, psi0 - math.pi / 2, [left]) is not None  # the old promise
    assert reach.finger(x, y, psi0 - math.pi / 2, [left], curvature=(1.0 / rho, 0.0)) is None
    # a tighter curve's contact travels less and stays on the pad
    assert reach.finger(x, y, psi0 - math.pi / 2, [left], curvature=(1.0 / 10.0, 0.0)) is not None


def test_a_goal_place_takes_the_answered_curves_curvature_where_it_lies_on_it():
    pose = Pose(0.4, 105.0, 3.0)
    rec = Recognition("ellipse", {"a": 30.0, "b": 15.0}, pose=pose)
    for t0 in (0.3, 2.0):
        x, y = (float(np.ravel(v)[0]) for v in pose.apply(*ELLIPSE.point(np.array([t0]))))
        kappa, kappa_s = curvature_at(rec, x, y)
        assert math.isclose(kappa, float(ELLIPSE.kappa(np.array([t0]))[0]), rel_tol=1e-6)
        assert math.isclose(kappa_s, float(ELLIPSE.kappa_s(np.array([t0]))[0]), rel_tol=1e-5, abs_tol=1e-9)
    x, y = (float(np.ravel(v)[0]) for v in pose.apply(0.0, 15.0 + 2.0))  # 2 mm off the curve
    assert curvature_at(rec, x, y) is None
    assert curvature_at(Recognition("line", {}, pose=pose), x, y) is None
