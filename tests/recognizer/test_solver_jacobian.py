"""recognizer.solver's closed-form Jacobian: ``DERIVATIVES`` (the kernels differentiated
in their shape parameters, and κ_s in t) against central differences of the kernels, every
class, near and far along the curve; and ``ContactModel.jac`` evaluates no kernel (until
session 22 its shape columns and dκ_s/dt were differences, 2 + (number of shape
parameters) further kernel evaluations per touch)."""

import numpy as np
import pytest

from recognizer import contacts as L
from recognizer.curves import CURVES
from recognizer.solver import DERIVATIVES, KERNELS, ContactModel

#: per class: parameter sets (in param_names order) and t values (t = 0 left out where κ is infinite)
CASES = {
    "line": ([()], [-3.0, 0.0, 2.0]),
    "circle": ([(1e-3,), (2.5,), (1e3,)], [-3.0, -0.4, 0.0, 1.1, 2.9]),
    "ellipse": ([(3.0, 0.7), (1.0, 1e-3), (1e3, 999.0), (0.5, 2.0)], [-3.0, -1.2, 0.0, 0.3, 1.5707, 2.2]),
    "parabola": ([(1e-3,), (0.4,), (1e3,)], [-40.0, -1.0, 0.0, 0.2, 3.0, 300.0]),
    "hyperbola": ([(1.3, 0.2), (1e-2, 40.0), (1e3, 1e3)], [-9.0, -1.0, 0.0, 0.3, 2.5, 12.0]),
    "cubical_parabola": ([(-0.8, 1.5), (3e-4, -0.9), (2.0, 0.0), (-1e-6, 20.0)], [-300.0, -1.0, 0.0, 1e-3, 0.7, 40.0]),
    "semicubical_parabola": ([(0.6, -1.2), (1.0, 0.0), (0.05, 18.0), (40.0, 3.0)], [-50.0, -0.8, -1e-3, 2e-2, 0.9, 15.0]),
}


def _central(f, v: float):
    """Central difference of f at v (f returns a tuple), step relative to v, and its rounding scale."""
    h = 1e-5 * max(abs(v), 1e-3)
    up, dn = np.array(f(v + h)), np.array(f(v - h))
    return (up - dn) / (2 * h), (np.abs(up) + np.abs(dn)) * 1e-16 / h


@pytest.mark.parametrize("cls", list(CASES))
def test_derivatives_match_central_differences_of_the_kernels(cls):
    kern, deriv = KERNELS[cls], DERIVATIVES[cls]
    params_list, ts = CASES[cls]
    for p in params_list:
        for t in ts:
            d = np.array(deriv(p, t))
            assert d.shape == (5 * len(p) + 1,) and np.all(np.isfinite(d)), (p, t)
            for j in range(len(p)):
                fd, rounding = _central(lambda v: kern(p[:j] + (v,) + p[j + 1:], t)[:5], p[j])
                tol = 1e-6 * (np.abs(fd) + np.abs(fd[:2]).max() * (np.arange(5) < 2)) + 10 * rounding + 1e-300
                assert np.all(np.abs(d[5 * j: 5 * j + 5] - fd) <= tol), (p, t, j, d[5 * j: 5 * j + 5], fd)
            fd, rounding = _central(lambda v: kern(p, v)[4:5], t)
            assert abs(d[-1] - fd[0]) <= 1e-6 * abs(fd[0]) + 10 * rounding[0] + 1e-300, (p, t, d[-1], fd[0])


@pytest.mark.parametrize("cls", list(CURVES))
def test_jacobian_evaluates_no_kernel(cls):
    c = CURVES[cls]({k: v for k, v in zip(CURVES[cls].param_names, CASES[cls][0][0])})
    t = np.array([0.4, 0.9, 1.6])
    x, y, phi, k, ks = c.frame(t)
    d = L.Contacts(x + 0.01, y - 0.02, phi + 0.003, k * 1.01, ks + 0.01, np.tile(np.diag([1e-4, 1e-2]), (3, 1, 1)),
                   np.full(3, 1e-2), np.full(3, 1e-2))
    m = ContactModel(cls, d)
    z = m.pack(c.params, 0.2, -0.1, 0.3, t)
    r, _, parts = m.eval(z)
    calls = []
    kern = m.kern
    m.kern = lambda p, tt: calls.append(tt) or kern(p, tt)
    J = m.jac(z, parts)
    assert calls == [] and J.shape == (15, len(z)) and np.all(np.isfinite(J))


@pytest.mark.parametrize("cls", ["circle", "ellipse", "semicubical_parabola"])
def test_jacobian_layout_matches_a_dense_build(cls):
    """``ContactModel.jac`` puts only the entries that depend on z into a copy of its
    constant Jacobian (``_layout``, session 32): every entry equals the closed forms placed
    row by row (x, y, φ, κ, κ_s per touch; shape, θ, x, y, one t column per touch), for 3
    and 4 touches with distinct deviations, and a second model of another touch count
    builds its own layout."""
    params, ts = CASES[cls]
    p = params[0]
    for n in (3, 4):
        t = np.array(ts[1: 1 + n], float) + 0.01
        names = CURVES[cls].param_names
        curve = CURVES[cls](dict(zip(names, p)))
        x, y = curve.point(t)
        data = L.Contacts(x + 0.01, y - 0.02, curve.tangent_angle(t) + 0.003, curve.kappa(t) * 1.01,
                          curve.kappa_s(t) + 0.1, np.tile(np.diag([0.04, 0.3]), (n, 1, 1)),
                          np.linspace(0.05, 0.08, n), np.linspace(2e-3, 5e-3, n))
        model = ContactModel(cls, data)
        z = model.pack(dict(zip(names, p)), 0.3, 0.1, -0.2, t)
        _, _, parts = model.eval(z)
        got = model.jac(z, parts)
        o, m = len(names), len(names) + 3 + n
        assert got.shape == (5 * n, m)
        pp, ct, st, fr = parts
        rows = model.rows
        for i in range(n):
            px, py, ph, kc, ksc, spd = fr[i]
            sp_, sf, w00, w01, w10, w11 = rows[i][5:]
            d = DERIVATIVES[cls](pp, t[i])
            want = np.zeros((5, m))
            for j, lg in enumerate(model.log):
                g = pp[j] if lg else 1.0
                dx, dy, df, dk, dks = (g * v for v in d[5 * j: 5 * j + 5])
                want[:, j] = ((ct * dx - st * dy) / sp_, (st * dx + ct * dy) / sp_, df / sf,
                              w00 * dk + w01 * dks, w10 * dk + w11 * dks)
            want[0, o: o + 3] = ((-st * px - ct * py) / sp_, 1.0 / sp_, 0.0)
            want[1, o: o + 3] = ((ct * px - st * py) / sp_, 0.0, 1.0 / sp_)
            want[2, o: o + 3] = (1.0 / sf, 0.0, 0.0)
            ang = ph + z[o]
            want[:, o + 3 + i] = (spd * np.cos(ang) / sp_, spd * np.sin(ang) / sp_, kc * spd / sf,
                                  w00 * ksc * spd + w01 * d[-1], w10 * ksc * spd + w11 * d[-1])
            np.testing.assert_allclose(got[5 * i: 5 * i + 5], want, rtol=1e-14, atol=0.0)
