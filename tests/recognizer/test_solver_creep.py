"""recognizer.solver's creep rule (``CREEP_STEPS``, ``CREEP_CHI2``): a noisy contact fit whose
χ² no longer falls by a noticeable fraction of its own noise stops there, with the χ² (and
so the verdict) of the fit run to the iteration cap; exact data still fits to rounding."""

import math

import numpy as np

from recognizer import contacts as L
from recognizer import solver
from recognizer.classify import chi2_limit
from recognizer.curves import CURVES
from recognizer.solver import ContactModel


def _straight_touches(rng) -> L.Contacts:
    """Three noisy touches of a straight edge 45 mm long (σ 0.05 mm, 1.5 mrad; κ, κ_s ~ 0)."""
    x = np.array([0.0, 20.0, 45.0])
    sk, sks = 2e-3, 2e-4
    return L.Contacts(x + rng.normal(0, 0.05, 3), rng.normal(0, 0.05, 3), rng.normal(0, 1.5e-3, 3),
                      rng.normal(0, sk, 3), rng.normal(0, sks, 3), np.tile(np.diag([sk**2, sks**2]), (3, 1, 1)),
                      np.full(3, 0.05), np.full(3, 1.5e-3))


def _solve_counting(model: ContactModel, z0: np.ndarray):
    """(z, χ², iterations): one Jacobian per iteration."""
    calls = []
    jac = model.jac
    model.jac = lambda z, parts: calls.append(1) or jac(z, parts)
    try:
        z, cost, _, _ = model.solve(z0.copy())
    finally:
        model.jac = jac
    return z, cost, len(calls)


def test_a_creeping_fit_stops_early_with_the_capped_fits_chi2(monkeypatch):
    # an ellipse fitted to a straight edge: χ² flat to 1e-4 after a few steps while its
    # axes keep drifting (the touches do not determine them); run to the cap it takes 40
    d = _straight_touches(np.random.default_rng(3))
    model = ContactModel("ellipse", d)
    t = -math.pi / 2 + np.array([0.0, 20.0, 45.0]) / 800.0
    z0 = model.pack({"a": 400.0, "b": 200.0}, 0.0, 22.0, 200.0, t)
    z, cost, iters = _solve_counting(model, z0)
    monkeypatch.setattr(solver, "CREEP_CHI2", 0.0)  # the rule off: to the 40-iteration cap
    z_cap, cost_cap, iters_cap = _solve_counting(model, z0)
    assert iters_cap == 40
    assert iters <= 15
    dof = 5 * d.n - (5 + d.n)
    assert 0.0 <= cost - cost_cap < 0.05 * math.sqrt(2 * dof)  # within a small fraction of χ²'s noise
    limit = chi2_limit(1e-3, dof)
    assert (cost <= limit) == (cost_cap <= limit)  # the same verdict


def test_a_converging_noisy_fit_is_not_cut_short():
    # the right class from a start 5 % off: χ² falls fast, then the fit converges (no creep)
    rng = np.random.default_rng(7)
    c = CURVES["ellipse"]({"a": 30.0, "b": 12.0})
    t = np.array([0.3, 1.1, 2.0])
    x, y, phi, k, ks = c.frame(t)
    sk, sks = 1e-3, 1e-4
    d = L.Contacts(x + rng.normal(0, 0.03, 3), y + rng.normal(0, 0.03, 3), phi + rng.normal(0, 1.5e-3, 3),
                   k + rng.normal(0, sk, 3), ks + rng.normal(0, sks, 3), np.tile(np.diag([sk**2, sks**2]), (3, 1, 1)),
                   np.full(3, 0.03), np.full(3, 1.5e-3))
    model = ContactModel("ellipse", d)
    z0 = model.pack({"a": 31.5, "b": 11.4}, 0.02, 0.3, -0.2, t + 0.03)
    z, cost, _ = _solve_counting(model, z0)
    # the minimum: Gauss–Newton step from z is negligible (gradient ~ 0 in scaled units)
    r, _, parts = model.eval(z)
    J = model.jac(z, parts)
    g = J.T @ np.array(r) / np.linalg.norm(J, axis=0)
    assert np.linalg.norm(g) < 1e-6 * max(math.sqrt(cost), 1.0)
    p = model.params_of(z)
    assert abs(p["a"] - 30.0) < 3.0 and abs(p["b"] - 12.0) < 1.5


def test_exact_data_still_fits_to_rounding():
    # noise-free contacts: the rule is off, the fit goes on to the cost floor (1e-12)
    c = CURVES["hyperbola"]({"a": 2.0, "b": 0.7})
    t = np.array([0.2, 0.9, 1.7, 2.4])
    x, y, phi, k, ks = c.frame(t)
    d = L.Contacts(x, y, phi, k, ks, np.zeros((4, 2, 2)), np.zeros(4), np.zeros(4))
    assert d.exact
    model = ContactModel("hyperbola", d)
    z0 = model.pack({"a": 2.1, "b": 0.66}, 0.01, -0.05, 0.04, t * 1.02)
    z, cost, _ = _solve_counting(model, z0)
    p = model.params_of(z)
    assert cost < 1e-12
    assert abs(p["a"] - 2.0) < 1e-9 and abs(p["b"] - 0.7) < 1e-9
