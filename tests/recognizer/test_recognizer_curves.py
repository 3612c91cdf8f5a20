"""Canonical curves checked against a sympy derivation of eqs. (1)-(2) from the
canonical parametrization itself (no formula of the paper is trusted)."""

import math

import numpy as np
import pytest
import sympy as sp
from scipy import integrate

from recognizer.curves import CURVES, Pose, validate_params
from tactile_common.errors import InputError

T = sp.symbols("t", real=True)
P = {n: sp.symbols(n, real=True) for n in ("a", "b", "c", "r")}
FORMS = {
    "line": (T, sp.Integer(0)),
    "circle": (P["r"] * sp.cos(T), P["r"] * sp.sin(T)),
    "ellipse": (P["a"] * sp.cos(T), P["b"] * sp.sin(T)),
    "parabola": (P["a"] * T**2, 2 * P["a"] * T),
    "hyperbola": (P["a"] * sp.cosh(T), P["b"] * sp.sinh(T)),
    "cubical_parabola": (T, P["a"] * T**3 + P["c"] * T),
    "semicubical_parabola": (T**2, P["a"] * T**3 + P["b"] * T**2),
}
PARAMS = {
    "line": [{}],
    "circle": [{"r": 2.5}, {"r": 1e-3}],
    "ellipse": [{"a": 2.8605, "b": 1.7263}, {"a": 1000.0, "b": 1.0}],
    "parabola": [{"a": 0.7}, {"a": 300.0}],
    "hyperbola": [{"a": 1.3, "b": 0.4}, {"a": 0.2, "b": 5.0}],
    "cubical_parabola": [{"a": 3.2543, "c": -2.3215}, {"a": -0.5, "c": 1.5}],
    "semicubical_parabola": [{"a": 1.5, "b": -0.8}, {"a": 0.3, "b": 2.0}],
}
TS = [-2.3, -0.7, -0.05, 0.03, 0.4, 1.1, 2.9]


def _exact(cls):
    x, y = FORMS[cls]
    xd, yd = sp.diff(x, T), sp.diff(y, T)
    sp2 = xd**2 + yd**2
    kappa = (xd * sp.diff(yd, T) - sp.diff(xd, T) * yd) / sp2 ** sp.Rational(3, 2)
    kappa_s = sp.diff(kappa, T) / sp.sqrt(sp2)
    syms = [T] + [P[n] for n in CURVES[cls].param_names]
    return {k: sp.lambdify(syms, e, "mpmath") for k, e in
            {"x": x, "y": y, "xd": xd, "yd": yd, "kappa": kappa, "kappa_s": kappa_s, "speed": sp.sqrt(sp2)}.items()}


@pytest.mark.parametrize("cls", list(CURVES))
def test_closed_forms_match_sympy(cls):
    import mpmath

    mpmath.mp.dps = 40
    ex = _exact(cls)
    for params in PARAMS[cls]:
        curve = CURVES[cls](params)
        args = [params[n] for n in curve.param_names]
        t = np.array(TS)
        got = {"x": curve.point(t)[0], "y": curve.point(t)[1], "kappa": curve.kappa(t),
               "kappa_s": curve.kappa_s(t), "speed": curve.speed(t)}
        phi = curve.tangent_angle(t)
        for i, ti in enumerate(TS):
            for k, v in got.items():
                want = float(ex[k](mpmath.mpf(ti), *args))
                assert v[i] == pytest.approx(want, rel=1e-11, abs=1e-13 * (1 + abs(want))), (cls, k, ti)
            xd, yd = float(ex["xd"](ti, *args)), float(ex["yd"](ti, *args))
            d = math.atan2(yd, xd) - phi[i]
            assert abs(math.remainder(d, 2 * math.pi)) < 1e-12, (cls, ti)


def test_kappa_is_dphi_ds_numerically():
    # κ = dφ/ds by central differences on the curve's own tangent angle and arc length
    for cls, plist in PARAMS.items():
        c = CURVES[cls](plist[0])
        for t in (-0.9, 0.35, 1.7):
            h = 1e-5
            dphi = math.remainder(float(c.tangent_angle(t + h) - c.tangent_angle(t - h)), 2 * math.pi)
            ds = float(c.arc_length(t - h, t + h))
            assert dphi / ds == pytest.approx(float(c.kappa(t)), rel=1e-6, abs=1e-9)


@pytest.mark.parametrize("cls", list(CURVES))
def test_arc_length_and_inverse(cls):
    for params in PARAMS[cls]:
        c = CURVES[cls](params)
        for t0, t1 in ((-1.2, 0.8), (0.1, 2.5), (-2.0, -0.3)):
            want = integrate.quad(lambda u: float(c.speed(u)), t0, t1, epsabs=0, epsrel=1e-13, limit=200)[0]
            got = float(c.arc_length(t0, t1))
            assert got == pytest.approx(want, rel=1e-9), (cls, params, t0, t1)
            back = float(c.t_at_arc_length(t0, got))
            assert back == pytest.approx(t1, rel=1e-9, abs=1e-9)


def test_pose_roundtrip_and_convention():
    p = Pose(0.3, 120.0, 15.0)
    x, y = p.apply(np.array([1.0, 0.0]), np.array([0.0, 2.0]))
    assert x[0] == pytest.approx(120 + math.cos(0.3)) and y[0] == pytest.approx(15 + math.sin(0.3))
    assert x[1] == pytest.approx(120 - 2 * math.sin(0.3))
    bx, by = p.inverse(x, y)
    assert np.allclose(bx, [1, 0]) and np.allclose(by, [0, 2])


@pytest.mark.parametrize("cls,params,msg", [
    ("ellipse", {"a": 1.0, "b": 2.0}, "a >= b"),
    ("ellipse", {"a": 1.0}, "missing"),
    ("circle", {"r": -1.0}, "> 0"),
    ("parabola", {"a": 1.0, "q": 2}, "unknown key"),
    ("cubical_parabola", {"a": 0.0, "c": 1.0}, "nonzero"),
    ("blob", {}, "unknown class"),
    ("hyperbola", {"a": float("nan"), "b": 1.0}, "finite"),
])
def test_validate_params_rejects(cls, params, msg):
    with pytest.raises(InputError, match=msg):
        validate_params(cls, params)


def test_a_circle_of_zero_radius_has_infinite_curvature_not_an_exception():
    """A refinement's log radius can underflow to r = 0 (bench_wide seed 89, a circle refined
    from a round ellipse): κ is ∞, which the refinement's nonfinite guards handle; Python's
    1.0 / 0.0 raised ZeroDivisionError out of recognize."""
    with np.errstate(divide="ignore"):
        k = CURVES["circle"]({"r": 0.0}).kappa(np.array([0.0, 1.0]))
    assert np.all(np.isinf(k))


@pytest.mark.parametrize("a", [0.0, 1e-12, 1e-9, 1e-6, 1e-3, -1e-7])
@pytest.mark.parametrize("b", [0.0, 0.7, -40.0])
def test_semicubical_arc_length_as_a_goes_to_zero(a, b):
    """The semicubical's closed-form arc length divides by 9a²: as a → 0 it cancelled to
    garbage (a = 1e-9, b = 0.7: −96 for 4.88) and at a = 0 it warned of a division by zero
    and gave NaN (printed during tools.bench_wide seed 101). It now states the arc of
    (t², a t³ + b t²) to 1e-12 relative, without a warning, down to the ray a = 0."""
    import warnings

    c = CURVES["semicubical_parabola"]({"a": a, "b": b})
    t = np.array([-3.0, -0.2, 0.0, 1e-4, 0.5, 2.0, 7.0])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        got = c.arc_length(np.zeros_like(t), t)
        back = [float(c.t_at_arc_length(0.5 * ti, s - g)) for ti, s, g in
                zip(t, got, c.arc_length(np.zeros_like(t), 0.5 * t)) if ti != 0]
    want = [math.copysign(integrate.quad(lambda u: float(c.speed(u)), 0.0, abs(ti), epsabs=0, epsrel=1e-13,
                                         limit=200)[0] if ti > 0 else
                          integrate.quad(lambda u: float(c.speed(u)), ti, 0.0, epsabs=0, epsrel=1e-13, limit=200)[0], ti)
            for ti in t]
    assert np.all(np.isfinite(got))
    assert got == pytest.approx(want, rel=1e-12, abs=1e-300)
    assert back == pytest.approx(t[t != 0], rel=1e-9)


@pytest.mark.parametrize("cls", list(CURVES))
def test_param_derivatives_match_sympy(cls):
    """∂x/∂p, ∂y/∂p and ∂φ/∂p at fixed t (refine's shape columns) against sympy, φ = atan2(y', x'),
    at the test shapes and at extremes: far out (t 15), near the cusp, steep, thin."""
    import mpmath

    mpmath.mp.dps = 40
    x, y = FORMS[cls]
    xd, yd = sp.diff(x, T), sp.diff(y, T)
    syms = [T] + [P[n] for n in CURVES[cls].param_names]
    exact = {n: [sp.lambdify(syms, e, "mpmath") for e in (sp.diff(x, P[n]), sp.diff(y, P[n]),
                 (xd * sp.diff(yd, P[n]) - yd * sp.diff(xd, P[n])) / (xd**2 + yd**2))]
             for n in CURVES[cls].param_names}
    extremes = {"ellipse": [{"a": 1.0, "b": 0.01}], "hyperbola": [{"a": 1.0, "b": 0.4}],
                "cubical_parabola": [{"a": 0.3, "c": 1e4}], "semicubical_parabola": [{"a": 1.0, "b": -0.5}]}
    ts = TS + [15.0, -8.5, 1e-4]
    for params in PARAMS[cls] + extremes.get(cls, []):
        curve = CURVES[cls](params)
        args = [params[n] for n in curve.param_names]
        derivs = curve.param_derivatives(np.array(ts))
        assert len(derivs) == len(curve.param_names)
        for name, cols in zip(curve.param_names, derivs):
            for i, ti in enumerate(ts):
                for got, f in zip(cols, exact[name]):
                    want = float(f(mpmath.mpf(ti), *args))
                    assert got[i] == pytest.approx(want, rel=1e-11, abs=1e-13 * (1 + abs(want))), (cls, name, ti)


def test_nearest_point_on_exact_curves():
    """Curve.nearest: a circle's nearest points lie on the rays from its centre (r = 10 mm,
    points 13, 3 and 17 mm from it, several at once): from the nearest of 2001 grid points
    (within half a spacing, π/2000), each of the 8 steps along the tangent (:meth:`project`)
    shrinks the angle's error by |1 − ρ/r| for a point at ρ from the centre; a parabola's
    (a = 2.5, from (6, 1) on its concave side) where the offset is along its normal."""
    circle = CURVES["circle"]({"r": 10.0})
    rho = np.array([13.0, 3.0, 17.0])
    px, py = rho * np.array([0.6, -0.8, 0.0]), rho * np.array([0.8, 0.6, -1.0])
    t = circle.nearest(np.linspace(*circle.t_period, 2001), px, py, 8)
    error = np.abs(np.angle(np.exp(1j * (t - np.arctan2(py, px)))))
    assert np.all(error <= 1.01 * math.pi / 2000 * np.abs(1.0 - rho / 10.0) ** 8)
    parabola = CURVES["parabola"]({"a": 2.5})
    grid = np.linspace(-20.0, 20.0, 2001)
    t = parabola.nearest(grid, 6.0, 1.0, 8)
    (cx,), (cy,) = parabola.point(t)
    ang = float(np.asarray(parabola.tangent_angle(t), float)[0])
    assert abs((6.0 - cx) * math.cos(ang) + (1.0 - cy) * math.sin(ang)) < 1e-4  # along the normal (0.4 mm on: ±0.4)
    gx, gy = parabola.point(grid)
    assert math.hypot(6.0 - cx, 1.0 - cy) <= float(np.min(np.hypot(gx - 6.0, gy - 1.0)))


@pytest.mark.parametrize("cls", list(CURVES))
def test_shared_intermediates_give_the_separate_methods_values(cls):
    """``point_tangent`` and ``speed_kappa`` (refine's model and Jacobian, session 32): the
    same bits as ``point``, ``tangent_angle``, ``speed`` and ``kappa`` one by one, at t's near
    and far, both signs, zero (the semicubical's cusp: κ infinite) and a NaN."""
    t = np.array([-40.0, -2.3, -0.7, -1e-9, 0.0, 3e-8, 0.4, 1.1, 2.9, 35.0, np.nan])
    for params in PARAMS[cls]:
        c = CURVES[cls](params)
        with np.errstate(all="ignore"):
            (x, y), phi = c.point_tangent(t)
            sp_, k = c.speed_kappa(t)
            want = (*c.point(t), c.tangent_angle(t), c.speed(t), c.kappa(t))
        for got, ref in zip((x, y, phi, sp_, k), want):
            assert np.asarray(got).tobytes() == np.asarray(ref, float).tobytes()
