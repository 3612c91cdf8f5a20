"""Invariants against exact curves (closed-form κ, κ_s) and a sympy derivation."""

import math

import mpmath
import numpy as np
import pytest
import sympy as sp

from recognizer import invariants as inv
from recognizer.curves import CURVES


def _kk(cls, params, t):
    c = CURVES[cls](params)
    t = np.asarray(t, float)
    return c.kappa(t), c.kappa_s(t), c.tangent_angle(t)


@pytest.mark.parametrize("a,b", [(2.8605, 1.7263), (1e3, 1.0), (1e-3, 0.9e-3), (5.0, 4.999)])
def test_ellipse_Ic1_Ic2(a, b):
    k, ks, _ = _kk("ellipse", {"a": a, "b": b}, [0.36, 1.86, 4.23, 2.9])
    for i, j in ((0, 1), (0, 2), (1, 3)):
        assert inv.I_c1(k[i], ks[i], k[j], ks[j]) == pytest.approx((a * b) ** (-2 / 3), rel=1e-8)
        assert inv.I_c2(k[i], ks[i], k[j], ks[j]) == pytest.approx((a * a + b * b) / (a * b) ** (4 / 3), rel=1e-8)


@pytest.mark.parametrize("a,b", [(1.3, 0.4), (1.0, 1e3), (1e3, 1e-1)])
def test_hyperbola_Ic1_Ic2(a, b):
    k, ks, _ = _kk("hyperbola", {"a": a, "b": b}, [-1.1, 0.2, 1.7])
    for i, j in ((0, 1), (0, 2), (1, 2)):
        assert inv.I_c1(k[i], ks[i], k[j], ks[j]) == pytest.approx(-((a * b) ** (-2 / 3)), rel=1e-8)
        assert inv.I_c2(k[i], ks[i], k[j], ks[j]) == pytest.approx((a * a - b * b) / (a * b) ** (4 / 3), rel=1e-7,
                                                                  abs=1e-9 * (a * a + b * b) / (a * b) ** (4 / 3))


@pytest.mark.parametrize("a", [0.7, 1e-3, 1e3])
def test_parabola_Ip_and_Ic(a):
    k, ks, _ = _kk("parabola", {"a": a}, [-2.0, 0.0, 0.3, 1.5])
    assert np.allclose(inv.I_p(k, ks), (2 * a) ** (-2 / 3), rtol=1e-12)
    assert abs(inv.I_c1(k[0], ks[0], k[2], ks[2])) < 1e-9 * (2 * a) ** (-2 / 3)
    assert inv.I_c2(k[0], ks[0], k[3], ks[3]) == pytest.approx((2 * a) ** (-2 / 3), rel=1e-9)


def test_diff23_has_no_cancellation():
    mpmath.mp.dps = 50
    for k1, k2 in ((1.0, 1.0 + 1e-12), (3e5, 3e5 * (1 - 1e-14)), (1e-9, 1.0000001e-9)):
        want = float(mpmath.cbrt(mpmath.mpf(k1)) ** 2 - mpmath.cbrt(mpmath.mpf(k2)) ** 2)
        assert inv.diff23(k1, k2) == pytest.approx(want, rel=1e-9)
        assert inv.diff23(-k1, k2) == pytest.approx(want, rel=1e-9)  # |κ|^{2/3}


@pytest.mark.parametrize("cls,params", [("cubical_parabola", {"a": 3.2543, "c": -2.3215}),
                                        ("cubical_parabola", {"a": -0.02, "c": 4.0}),
                                        ("semicubical_parabola", {"a": 1.5, "b": -0.8}),
                                        ("semicubical_parabola", {"a": 0.2, "b": 2.5})])
def test_cubic_invariants_and_slope_roots(cls, params):
    t = np.array([-0.6, 0.3, 1.2]) if cls == "cubical_parabola" else np.array([-1.6, -0.4, 0.9])
    k, ks, phi = _kk(cls, params, t)
    lam = np.tan(phi)
    if cls == "cubical_parabola":
        assert np.allclose(inv.I_cp1(lam, k, ks), params["a"], rtol=1e-10)
        assert np.allclose(inv.I_cp2(lam, k, ks), params["c"], rtol=1e-10, atol=1e-12)
        kk = inv.K_CUBICAL
    else:
        # errata (docs/recognition.md): the radicand is −a² on t < 0, a² on t > 0 — √|·| is a on both branches
        assert np.allclose(inv.I_scp1(lam, k, ks), params["a"], rtol=1e-10)
        assert np.allclose(inv.I_scp2(lam, k, ks), params["b"], rtol=1e-10, atol=1e-12)
        kk = inv.K_SEMICUBICAL
    # only the turn Δ between the touches is used: the canonical rotation stays unknown
    roots, resid = inv.slope_angles(k[0], ks[0], k[1], ks[1], float(phi[1] - phi[0]), kk)
    assert resid == 0.0
    truth = math.atan(math.tan(phi[0]))
    assert min(abs(math.remainder(r - truth, math.pi)) for r in roots) < 1e-9


def test_slope_equation_has_the_spurious_factor():
    """Errata (docs/recognition.md): eliminating λ₂ from I_cp2(λ₁) = I_cp2(λ₂), λ₂ = (λ₁+δ)/(1−λ₁δ), gives a quartic
    that is (1+λ₁²) × a quadratic; slope_angles solves that quadratic."""
    l, d, k1, k2, s1, s2 = sp.symbols("lambda delta k1 k2 s1 s2")
    f = lambda lam, k, s: lam - k**2 * (1 + lam**2) / (2 * (s + 3 * lam * k**2))  # noqa: E731
    l2 = (l + d) / (1 - l * d)
    num = sp.numer(sp.together(f(l, k1, s1) - f(l2, k2, s2)))
    q, r = sp.div(sp.Poly(sp.expand(num), l), sp.Poly(1 + l**2, l))
    assert r.is_zero and q.degree() == 2
    k, ks, phi = _kk("cubical_parabola", {"a": 3.2543, "c": -2.3215}, [-0.6, 0.3])
    delta = float(phi[1] - phi[0])
    vals = {d: math.tan(delta), k1: k[0], k2: k[1], s1: ks[0], s2: ks[1]}
    coeffs = [float(c) for c in sp.Poly(q.as_expr().subs(vals), l).all_coeffs()]
    want = sorted(np.roots(coeffs))
    assert min(abs(w - math.tan(phi[0])) for w in want) < 1e-9  # the true slope is a root
    roots, _ = inv.slope_angles(k[0], ks[0], k[1], ks[1], delta, inv.K_CUBICAL)
    assert sorted(math.tan(r) for r in roots) == pytest.approx(want, rel=1e-9)


def test_propagate_matches_analytic_variance():
    # I_p = |κ|^{2/3} + κ_s²/(9|κ|^{10/3}); at κ_s = 0 dI_p/dκ = (2/3)κ^{-1/3}
    k = 0.8
    var = inv.propagate(lambda a, b: inv.I_p(a, b), (k, 0.0), [np.diag([1e-6, 0.0])])
    assert var == pytest.approx(((2 / 3) * k ** (-1 / 3)) ** 2 * 1e-6, rel=1e-6)
