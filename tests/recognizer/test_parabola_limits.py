"""The parabola as a limit of ellipses, hyperbolas, cubical and semicubical parabolas
(docs/recognition.md#nested-classes): family members whose vertex (or hump) has the
parabola's vertex curvature 1/(2a), placed vertex on vertex, deviate from the parabola on a
fixed window by an amount that shrinks to 0 like 1/D (D the family's distance parameter),
with the leading coefficient the derivation gives for the cubic families. This is what
``recognizer.class_limits.LIMIT_OF["parabola"]`` states."""

import math

import numpy as np
import pytest

from recognizer.class_limits import LIMIT_OF
from recognizer.curves import CURVES

A_P = 2.0  # the parabola (a t², 2 a t): vertex curvature 1/(2a) = 0.25 / mm
W = 10.0  # the window: points within W (mm) of the vertex, along the vertex tangent


def member(cls: str, D: float) -> tuple[dict, float]:
    """(parameters, vertex t) of the family member at distance D (docs/recognition.md)."""
    if cls in ("ellipse", "hyperbola"):  # a → ∞ with b²/(2a) = a_p; vertex t = 0
        return {"a": D, "b": math.sqrt(2.0 * A_P * D)}, 0.0
    if cls == "cubical_parabola":  # hump at t_h = D of (t, a t³ + c t), a c < 0: |c| = 3 a t_h²
        a = 1.0 / (12.0 * A_P * D)
        return {"a": a, "c": -3.0 * a * D * D}, D
    # semicubical (t², a t³ + b t²), hump at x_h = t_h² = D on the branch t < 0 (b > 0)
    a = 2.0 * math.sqrt(D) / (3.0 * A_P)
    b = D / A_P
    return {"a": a, "b": b}, -2.0 * b / (3.0 * a)


def deviation(cls: str, D: float) -> float:
    """Largest distance (mm, measured across the vertex tangent) between the member and the
    parabola y = x²/(4 a_p) in the vertex frame, over the window |x| ≤ W."""
    params, tv = member(cls, D)
    curve = CURVES[cls](params)
    x0, y0 = (float(v) for v in curve.point(tv))
    phi0 = float(curve.tangent_angle(tv))
    k0 = float(curve.kappa(tv))
    assert abs(abs(k0) - 1.0 / (2.0 * A_P)) <= 1e-12 / A_P  # the vertex curvatures agree exactly
    # t over a window of arc length ≈ 2W around the vertex (speed is nearly constant there)
    sp = float(curve.speed(tv))
    t = tv + np.linspace(-1.5 * W / sp, 1.5 * W / sp, 4001)
    px, py = curve.point(t)
    dx, dy = px - x0, py - y0
    u = dx * math.cos(phi0) + dy * math.sin(phi0)  # along the vertex tangent
    v = math.copysign(1.0, k0) * (-dx * math.sin(phi0) + dy * math.cos(phi0))  # towards the centre
    inside = np.abs(u) <= W
    assert u[inside].min() < -0.99 * W and u[inside].max() > 0.99 * W
    return float(np.max(np.abs(v[inside] - u[inside] ** 2 / (4.0 * A_P))))


def test_limit_of_states_the_parabola_families():
    assert LIMIT_OF["parabola"] == {"ellipse", "hyperbola", "cubical_parabola", "semicubical_parabola"}


@pytest.mark.parametrize("cls", sorted(LIMIT_OF["parabola"]))
def test_member_tends_to_the_parabola(cls):
    Ds = [1e2, 1e3, 1e4]
    devs = [deviation(cls, D) for D in Ds]
    assert devs[-1] < 1e-2  # a 1e-3 of the window's 10 mm
    for d0, d1 in zip(devs, devs[1:]):  # like 1/D: ten times farther, ten times closer
        assert 0.07 < d1 / d0 < 0.14
    if cls in ("ellipse", "hyperbola"):  # leading term W⁴/(32 a_p² a)
        assert devs[-1] == pytest.approx(W**4 / (32 * A_P**2 * Ds[-1]), rel=0.05)
    if cls == "cubical_parabola":  # leading term W³/(12 a_p t_h)
        assert devs[-1] == pytest.approx(W**3 / (12 * A_P * Ds[-1]), rel=0.05)
    if cls == "semicubical_parabola":  # leading term W³/(24 a_p x_h)
        assert devs[-1] == pytest.approx(W**3 / (24 * A_P * Ds[-1]), rel=0.05)


def test_semicubical_hump_in_its_parameters():
    """The hump of (t², a t³ + b t²) has curvature 9a²/(8|b|): a_p = 4|b|/(9a²)."""
    for a, b in [(0.48, 4.3), (2.0, -0.7), (0.01, 30.0)]:
        c = CURVES["semicubical_parabola"]({"a": a, "b": b})
        th = -2 * b / (3 * a)
        assert float(c.kappa(th)) == pytest.approx(9 * a * a / (8 * abs(b)), rel=1e-12)
        assert float(c.tangent_angle(th)) % math.pi == pytest.approx(0.0, abs=1e-12)


def test_cubical_hump_in_its_parameters():
    """The humps of (t, a t³ + c t), a c < 0, at t = ±√(−c/(3a)) have |κ| = 2√(3|ac|)."""
    for a, c in [(0.3, -2.0), (-1e-3, 5.0)]:
        cu = CURVES["cubical_parabola"]({"a": a, "c": c})
        for th in (math.sqrt(-c / (3 * a)), -math.sqrt(-c / (3 * a))):
            assert abs(float(cu.kappa(th))) == pytest.approx(2 * math.sqrt(3 * abs(a * c)), rel=1e-12)
