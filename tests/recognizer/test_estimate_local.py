"""recognizer.estimate: κ, κ_s against the exact curves, convergence order, covariance
calibration, degenerate inputs."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from recognizer import synth
from recognizer.curves import CURVES, Pose
from tactile_common.errors import InputError
from recognizer.estimate import LocalGeometry, estimate_local
from recognizer.touches import SamplesTouch

# one contact per class, away from cusps and inflections (t, params)
CASES = {
    "circle": ({"r": 20.0}, 0.4),
    "ellipse": ({"a": 30.0, "b": 20.0}, 0.7),
    "parabola": ({"a": 8.0}, 0.6),
    "hyperbola": ({"a": 15.0, "b": 10.0}, 0.5),
    "cubical_parabola": ({"a": 0.002, "c": 0.3}, 6.0),
    "semicubical_parabola": ({"a": 0.25, "b": 0.5}, 5.0),
}
EXACT = synth.SynthNoise()  # a noise model of zeros: exact data


def _touch(cls, n, ds, direction=1, pose=Pose(0.4, 100.0, -20.0), with_s=True):
    params, t = CASES[cls]
    curve = CURVES[cls](params)
    touch, _ = synth.sample_touch(curve, pose, t, n, ds, direction, with_s=with_s)
    sign = 1.0 if direction > 0 else -1.0
    return touch, sign * float(curve.kappa(t)), float(curve.kappa_s(t))


@pytest.mark.parametrize("cls", list(CASES))
@pytest.mark.parametrize("method", ["central", "poly"])
def test_matches_exact_curves(cls, method):
    touch, k, ks = _touch(cls, 9, 0.5)
    g = estimate_local(touch, method, EXACT)
    tol_k, tol_ks = (5e-3, 5e-2) if method == "central" else (1e-7, 1e-4)
    assert abs(g.kappa - k) <= tol_k * abs(k)
    assert abs(g.kappa_s - ks) <= tol_ks * abs(ks) + 1e-12
    assert np.isclose(g.x, touch.x[4]) and np.isclose(g.y, touch.y[4])


@pytest.mark.parametrize("cls", ["ellipse", "hyperbola", "parabola"])
def test_central_converges_at_second_order(cls):
    """Halving the spacing divides the paper's central-difference error by ~4."""
    errs = []
    for ds in (0.8, 0.4, 0.2):
        touch, k, ks = _touch(cls, 3, ds)
        g = estimate_local(touch, "central", EXACT)
        errs.append((abs(g.kappa - k), abs(g.kappa_s - ks)))
    errs = np.array(errs)
    rates = np.log2(errs[:-1] / errs[1:])
    assert np.all(rates > 1.8) and np.all(rates < 2.2), rates


@pytest.mark.parametrize("cls", ["ellipse", "hyperbola"])
def test_poly_converges_faster_than_central(cls):
    """A fixed-degree polynomial fit (5 samples, degree 4 for κ_s, degree 3 for κ) has
    error O(Δs⁴) for κ (and the odd/even pairing gives κ_s O(Δs²)... measured here as
    at least fourth order for κ)."""
    errs = []
    for ds in (1.0, 0.5, 0.25):
        touch, k, ks = _touch(cls, 7, ds)
        g = estimate_local(touch, "poly", EXACT)
        errs.append(abs(g.kappa - k))
    errs = np.array(errs)
    rates = np.log2(errs[:-1] / errs[1:])
    assert np.all(rates > 3.5), rates


def test_direction_and_wraparound():
    """Reversed traversal flips κ; tangent angles crossing ±π unwrap."""
    touch, k, ks = _touch("circle", 9, 0.5, direction=-1, pose=Pose(-0.4 - np.pi / 2, 0.0, 0.0))
    wrapped = SamplesTouch((touch.phi + np.pi) % (2 * np.pi) - np.pi, touch.x, touch.y, touch.s)
    assert np.ptp(wrapped.phi) > np.pi  # really wraps
    g = estimate_local(wrapped, "poly", EXACT)
    assert k < 0 and abs(g.kappa - k) < 1e-9 * abs(k)
    assert abs(g.kappa_s) < 1e-7


def test_arc_length_from_positions_and_unequal_spacing():
    params, t = CASES["ellipse"]
    curve = CURVES["ellipse"](params)
    offsets = np.array([-2.0, -1.1, -0.5, 0.0, 0.4, 1.2, 1.9])
    ts = synth.t_at_arc(curve, t, offsets)
    x, y = curve.point(ts)
    touch = {"phi": curve.tangent_angle(ts), "x": x, "y": y}  # no s: from the positions
    g = estimate_local(touch, "auto", EXACT)
    assert abs(g.kappa - curve.kappa(t)) < 1e-5 * curve.kappa(t)
    assert abs(g.kappa_s - curve.kappa_s(t)) < 1e-3 * abs(curve.kappa_s(t))
    g3 = estimate_local({"phi": touch["phi"][2:5], "x": x[2:5], "y": y[2:5]}, "central", EXACT)
    assert abs(g3.kappa - curve.kappa(t)) < 1e-3 * curve.kappa(t)


def test_lines_and_inflections_give_zero_curvature():
    line, _ = synth.sample_touch(CURVES["line"]({}), Pose(1.0, 5.0, 5.0), 3.0, 9, 0.7)
    g = estimate_local(line, "auto", EXACT)
    assert abs(g.kappa) < 1e-12 and abs(g.kappa_s) < 1e-12
    cub = CURVES["cubical_parabola"]({"a": 0.002, "c": 0.3})
    touch, _ = synth.sample_touch(cub, Pose(), 0.0, 9, 0.5)
    g = estimate_local(touch, "auto", EXACT)
    assert abs(g.kappa) < 1e-9 and abs(g.kappa_s - float(cub.kappa_s(0.0))) < 1e-6 * abs(float(cub.kappa_s(0.0)))


@pytest.mark.parametrize("method,n", [("central", 9), ("poly", 9), ("poly", 5)])
def test_covariance_is_calibrated(method, n):
    """Over 200 noisy draws the empirical spread matches the propagated covariance
    within a factor 1.5 (φ 1.5 mrad, positions 0.06 mm, s from the positions)."""
    params, t = CASES["ellipse"]
    curve = CURVES["ellipse"](params)
    noise = synth.SynthNoise(1.5e-3, 0.06)
    rng = np.random.default_rng(7)
    est, pred = [], []
    for _ in range(200):
        touch, _ = synth.sample_touch(curve, Pose(), t, n, 1.2, 1, noise, rng, with_s=False)
        g = estimate_local(touch, method, noise)
        est.append((g.kappa, g.kappa_s))
        pred.append(np.sqrt(np.diag(g.cov)))
    rms = np.sqrt(np.mean((np.array(est) - [curve.kappa(t), curve.kappa_s(t)]) ** 2, axis=0))
    ratio = rms / np.mean(pred, axis=0)
    assert np.all(ratio > 1 / 1.5) and np.all(ratio < 1.5), ratio


def test_poly_beats_central_under_noise():
    params, t = CASES["ellipse"]
    curve = CURVES["ellipse"](params)
    noise = synth.SynthNoise(1.5e-3, 0.06)
    rng = np.random.default_rng(3)
    err = {"central": [], "poly": []}
    for _ in range(100):
        touch, _ = synth.sample_touch(curve, Pose(), t, 9, 1.2, 1, noise, rng, with_s=False)
        for m in err:
            g = estimate_local(touch, m, noise)
            err[m].append(g.kappa_s - curve.kappa_s(t))
    assert np.std(err["poly"]) < 0.2 * np.std(err["central"])


def test_noise_unknown_uses_residuals_and_never_nan():
    params, t = CASES["ellipse"]
    curve = CURVES["ellipse"](params)
    rng = np.random.default_rng(1)
    touch, _ = synth.sample_touch(curve, Pose(), t, 9, 1.2, 1, synth.SynthNoise(1e-3, 0.0), rng)
    g = estimate_local(touch, "auto", None)
    assert isinstance(g, LocalGeometry) and np.all(np.isfinite(g.cov))
    assert 1e-9 < g.cov[1, 1] and np.linalg.eigvalsh(g.cov).min() >= 0
    exact, _ = synth.sample_touch(curve, Pose(), t, 3, 1.2)
    g3 = estimate_local(exact, "auto", None)
    assert np.all(np.isfinite(g3.cov)) and g3.method == "central"


@pytest.mark.parametrize("bad,msg", [
    ({"phi": [0.1, 0.1, 0.1], "x": [0, 0, 0], "y": [0, 0, 0]}, "no arc length"),
    ({"phi": [0.1, 0.2, 0.3], "x": [0, 1, 2], "y": [0, 0, 0], "s": [0, 1, 1]}, "no arc length"),
    ({"phi": [0.1, 0.2], "x": [0, 1], "y": [0, 0]}, "at least 3"),
    ({"phi": [0.1, 0.2, 0.3], "x": [0, 1], "y": [0, 0, 0]}, "equal lengths"),
    ({"phi": [0.1, float("nan"), 0.3], "x": [0, 1, 2], "y": [0, 0, 0]}, "NaN"),
    ({"x": [0, 1, 2], "y": [0, 0, 0]}, "needs keys"),
])
def test_degenerate_inputs_raise_input_error(bad, msg):
    with pytest.raises(InputError, match=msg):
        estimate_local(bad, "auto", EXACT)


def test_unknown_method():
    with pytest.raises(InputError, match="method"):
        estimate_local({"phi": [0, 0.1, 0.2], "x": [0, 1, 2], "y": [0, 0.1, 0.3]}, "spline")


@settings(max_examples=25, deadline=None)
@given(phi=st.lists(st.floats(-10, 10), min_size=3, max_size=12),
       step=st.lists(st.floats(1e-3, 5.0), min_size=11, max_size=11))
def test_arbitrary_inputs_give_finite_answers(phi, step):
    """Any finite advancing samples give finite κ, κ_s and a finite PSD covariance."""
    n = len(phi)
    s = np.concatenate(([0.0], np.cumsum(step[: n - 1])))
    touch = {"phi": phi, "x": s, "y": np.zeros(n), "s": s}
    for noise in (None, synth.SynthNoise(1e-3, 0.01)):
        g = estimate_local(touch, "auto", noise)
        assert np.isfinite(g.kappa) and np.isfinite(g.kappa_s) and np.all(np.isfinite(g.cov))
        assert np.linalg.eigvalsh(g.cov).min() >= -1e-12 * max(1.0, np.abs(g.cov).max())
