"""Touches traversed against a class's canonical direction: the flipped contacts' whitener
must whiten the re-signed κ/κ_s covariance (the cross term changes sign with κ)."""

import numpy as np
import pytest

from recognizer import localize as L
from recognizer.contacts import Contacts
from recognizer.curves import CURVES, Pose


def _cov(n, rho, rng):
    out = []
    for _ in range(n):
        sk, sks = rng.uniform(1e-4, 1e-3), rng.uniform(1e-5, 1e-4)
        out.append([[sk * sk, rho * sk * sks], [rho * sk * sks, sks * sks]])
    return np.array(out)


def test_flipped_whitener_whitens_resigned_covariance():
    rng = np.random.default_rng(3)
    n = 4
    cov = _cov(n, 0.9, rng)
    d = Contacts(rng.normal(size=n), rng.normal(size=n), rng.uniform(-3, 3, n), rng.normal(size=n),
                   rng.normal(size=n), cov, np.full(n, 1e-3), np.full(n, 1e-3))
    f = d.flipped()
    D = np.diag([-1.0, 1.0])
    W = np.array([r[7:] for r in f.rows()]).reshape(-1, 2, 2)
    C = np.array([D @ c @ D for c in d.cov])
    # the floors (≤ 1e-5 of these variances) aside, W·(D C D)·Wᵀ = I; the unflipped W is off by ~1
    assert np.allclose(W @ C @ np.transpose(W, (0, 2, 1)), np.eye(2), atol=1e-3)
    assert np.allclose(f.cov, C)


@pytest.mark.parametrize("rho", [0.95, -0.95])
def test_correlated_covariance_same_chi2_both_directions(rho):
    """An ellipse's contacts with correlated κ/κ_s errors give one χ² whichever way they are
    traversed (the reversed touches are flipped to the canonical direction inside)."""
    rng = np.random.default_rng(7)
    c = CURVES["ellipse"]({"a": 40.0, "b": 25.0})
    t = np.array([-0.9, 0.3, 1.4])
    pose = Pose(0.4, 10.0, -5.0)
    x, y = pose.apply(*c.point(t))
    phi = np.asarray(c.tangent_angle(t)) + pose.theta
    k, ks = np.asarray(c.kappa(t), float), np.asarray(c.kappa_s(t), float)
    cov = _cov(3, rho, rng)
    e = np.array([rng.multivariate_normal([0, 0], cc) for cc in cov])
    sp = np.full(3, 1e-3)
    fwd = Contacts(x, y, phi, k + e[:, 0], ks + e[:, 1], cov, sp, sp)
    rc = cov.copy()
    rc[:, 0, 1] *= -1
    rc[:, 1, 0] *= -1
    rev = Contacts(x[::-1], y[::-1], (phi + np.pi)[::-1], -(k + e[:, 0])[::-1], (ks + e[:, 1])[::-1],
                     rc[::-1], sp, sp)
    f1, f2 = L.fit_class("ellipse", fwd), L.fit_class("ellipse", rev)
    assert f1.chi2 < 30  # a consistent fit with 3·5 − 8 = 7 degrees of freedom
    assert f2.chi2 == pytest.approx(f1.chi2, rel=1e-6)


def test_a_stated_extent_is_the_scale_and_the_flipped_view_keeps_it():
    """``Contacts(..., extent=L)`` takes L as the touches' scale (the floors' length) instead
    of computing it; without it the scale is the largest distance between two contacts; the
    flipped view keeps the scale either way and floors its deviations alike."""
    x, y = np.array([0.0, 3.0, 0.0]), np.array([0.0, 0.0, 4.0])
    zero = np.zeros(3)
    kw = dict(phi=np.array([0.1, 0.2, 0.3]), kappa=np.array([0.5, 0.4, 0.3]), kappa_s=zero,
              cov=np.zeros((3, 2, 2)), sig_pos=zero, sig_phi=zero)
    assert Contacts(x, y, **kw).scale == pytest.approx(5.0, rel=1e-15)
    stated = Contacts(x, y, **kw, extent=250.0)
    assert stated.scale == 250.0 and stated.flipped().scale == 250.0
    assert stated.rows()[0][5] == pytest.approx(1e-7 * 250.0, rel=1e-12)  # σ_pos floor EPS_FLOOR·L
    assert stated.flipped().rows()[0][5] == stated.rows()[0][5]
