"""The fast scalar paths of the recognizer against the reference (vectorized NumPy) forms:
kernels vs recognizer.curves, scalar invariants vs their array forms, the closed-form
whitener vs Cholesky, the closed-form Jacobian vs differences of the residuals (every class),
the line/circle cost floor, and overflow answered instead of raised."""

import math

import numpy as np
import pytest

from recognizer import invariants as inv
from recognizer import contacts as L
from recognizer import solver as S
from recognizer.classify import recognize
from recognizer.curves import CURVES
from recognizer.result import RecognizeOptions
from recognizer.touches import parse_request

PARAMS = {"line": {}, "circle": {"r": 2.5}, "ellipse": {"a": 3.0, "b": 0.7}, "parabola": {"a": 0.4},
          "hyperbola": {"a": 1.3, "b": 0.2}, "cubical_parabola": {"a": -0.8, "c": 1.5},
          "semicubical_parabola": {"a": 0.6, "b": -1.2}}
TS = [-2.1, -0.7, 0.35, 1.9]


@pytest.mark.parametrize("cls", list(CURVES))
def test_kernels_match_curves(cls):
    c = CURVES[cls](PARAMS[cls])
    p = tuple(PARAMS[cls][k] for k in c.param_names)
    t = np.array(TS)
    x, y, phi, k, ks = c.frame(t)
    want = np.stack([x, y, phi, k, ks, c.speed(t)], 1)
    got = np.array([S.KERNELS[cls](p, ti) for ti in TS])
    assert np.allclose(got, want, rtol=1e-13, atol=1e-13)


def test_scalar_invariants_match_array_forms():
    rng = np.random.default_rng(4)
    for _ in range(200):
        k1, k2 = rng.normal(size=2) * 10.0 ** rng.uniform(-3, 3, 2)
        s1, s2 = rng.normal(size=2) * 10.0 ** rng.uniform(-3, 3, 2)
        c1, c2 = inv.I_c12_s(k1, s1, k2, s2)
        assert c1 == pytest.approx(float(inv.I_c1(k1, s1, k2, s2)), rel=1e-12)
        assert c2 == pytest.approx(float(inv.I_c2(k1, s1, k2, s2)), rel=1e-12)
        assert inv.pair_condition_s(k1, k2) == pytest.approx(float(inv.pair_condition(k1, k2)), rel=1e-12)
        assert inv.I_p_s(k1, s1) == pytest.approx(float(inv.I_p(k1, s1)), rel=1e-12)
    assert all(math.isnan(v) for v in inv.I_c12_s(0.0, 1.0, 2.0, 0.5))  # no pair invariants through κ = 0


def _contacts(cov=None, n=4, seed=0):
    rng = np.random.default_rng(seed)
    cov = np.zeros((n, 2, 2)) if cov is None else cov
    return L.Contacts(rng.normal(size=n), rng.normal(size=n), rng.uniform(-3, 3, n), rng.normal(size=n),
                      rng.normal(size=n), cov, np.full(n, 1e-3), np.full(n, 1e-3))


def test_whitener_closed_form_matches_cholesky():
    c = np.array([[[4e-6, 1e-7], [1e-7, 9e-6]], [[1e-8, -3e-9], [-3e-9, 2e-8]], [[0, 0], [0, 0]]])
    d = _contacts(c, n=3)
    L_ = d.scale
    fk = L.EPS_FLOOR * (np.abs(d.kappa) + 1 / L_)
    fks = L.EPS_FLOOR * (np.abs(d.kappa_s) + d.kappa**2 + np.abs(d.kappa) / L_ + 1 / L_**2)
    full = c.copy()
    full[:, 0, 0] += fk**2
    full[:, 1, 1] += fks**2
    W = d.whitener()
    assert np.allclose(W, np.linalg.inv(np.linalg.cholesky(full)), rtol=1e-12)
    assert np.allclose(W @ full @ np.transpose(W, (0, 2, 1)), np.eye(2), atol=1e-10)  # W·C·Wᵀ = I


@pytest.mark.parametrize("cls", list(CURVES))
def test_jacobian_matches_central_differences(cls):
    c = CURVES[cls](PARAMS[cls])
    t = np.array(TS[:3]) if cls != "semicubical_parabola" else np.array([0.4, 0.9, 1.6])
    x, y, phi, k, ks = c.frame(t)
    d = L.Contacts(x + 0.01, y - 0.02, phi + 0.003, k * 1.01, ks + 0.01, np.zeros((3, 2, 2)),
                   np.full(3, 1e-2), np.full(3, 1e-2))
    m = S.ContactModel(cls, d)
    z = m.pack(PARAMS[cls], 0.0, 0.0, 0.0, t)
    r, _, parts = m.eval(z)
    J = m.jac(z, parts)
    for j in range(len(z)):
        h = 1e-6 * max(abs(z[j]), 1.0)
        up, dn = z.copy(), z.copy()
        up[j] += h
        dn[j] -= h
        fd = (np.array(m.eval(up)[0]) - np.array(m.eval(dn)[0])) / (2 * h)
        assert np.allclose(J[:, j], fd, rtol=1e-6, atol=1e-6 * (np.abs(fd).max() + 1e-12)), j


@pytest.mark.parametrize("cls", ["line", "circle"])
def test_cost_floor_is_a_lower_bound(cls):
    d = _contacts(seed=2)
    d = d.flipped() if cls == "circle" and d.dominant_kappa() < 0 else d
    m = S.ContactModel(cls, d)
    floor = m.floor()
    assert floor > 0
    rng = np.random.default_rng(5)
    best = math.inf
    for _ in range(300):
        params = {"r": 10 ** rng.uniform(-2, 2)} if cls == "circle" else {}
        z = m.pack(params, rng.uniform(-3, 3), rng.normal(), rng.normal(), rng.normal(size=d.n))
        best = min(best, m.eval(z)[1])
    assert floor <= best * (1 + 1e-12)


NOISY_LINE = [  # x, y, φ, κ, κ_s: a 6 µm straight segment, κ and κ_s pure noise
    (110.02373676679962, 0.04235411611469891, -1.2456241645725472, -0.13426144858397968, -50.06319906445334),
    (110.02481184659202, 0.03914440301620893, -1.2452085066256617, -0.005567597964377385, 9.821369133127012),
    (110.02498956055076, 0.0386238601030535, -1.2469210217606193, 0.31889567388586865, 60.76113197187805),
    (110.02681225830686, 0.03323252169349032, -1.2442835005152117, 0.026361727932725978, 16.528364782577732),
    (110.02732863449127, 0.03169052450619778, -1.2456521184800862, 0.09022153265251018, -65.71236372753712),
]


def test_overflowing_fit_is_answered_not_raised():
    """Noisy contacts whose curved-class fits step to exp(log a) > 1e308 once raised
    OverflowError out of recognize; the overflow is now a failed step of that class."""
    sk, sks = 0.15705168263252103, 24.665231017706105
    obj = {"noise": {"phi": 1e-3, "pos": 6.3673306980088856e-06},
           "touches": [{"contact": {"x": x, "y": y, "phi": f, "kappa": k, "kappa_s": ks, "sigma_kappa": sk,
                                    "sigma_kappa_s": sks}} for x, y, f, k, ks in NOISY_LINE]}
    ans = recognize(parse_request(obj), RecognizeOptions()).to_json()
    assert ans["class"] == "line"
