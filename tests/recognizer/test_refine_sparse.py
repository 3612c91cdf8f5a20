"""recognizer.refine on large requests: the sparse solve and the covariance by blocks give
what the dense solve and the pseudo-inverse of the whole Jacobian give."""

from __future__ import annotations

import numpy as np
import pytest

from recognizer import refine, synth
from recognizer.curves import Pose
from recognizer.refine import _pinv_cov, _unknowns_cov, refine_one
from recognizer.result import Candidate
from recognizer.touches import NoiseModel, SamplesTouch

NOISE = NoiseModel(1.5e-3, 0.05)


def _touches(n_touch: int, n: int, seed: int, factor: bool = False):
    rng = np.random.default_rng(seed)
    shape = synth.random_shape("ellipse", rng)
    ts = np.linspace(-2.5, 2.5, n_touch)
    sn = synth.SynthNoise(NOISE.phi, NOISE.pos)
    tl, tt = synth.sample_shape(shape, ts, n, 0.01 * shape.size, 1, sn, rng, with_s=False)
    if factor:  # correlated sample errors, stated by a noise factor (3n × 2n)
        f = rng.normal(size=(3 * n, 2 * n)) * np.r_[[NOISE.pos] * 2 * n, [NOISE.phi] * n][:, None] / 2.0
        tl = [SamplesTouch(t.phi, t.x, t.y, None, noise_factor=f) for t in tl]
    start = Candidate("ellipse", dict(shape.params), shape.pose, np.array([t[n // 2] for t in tt]), 0.0, 0, 0)
    return shape, tl, start


@pytest.mark.parametrize("factor", [False, True])
def test_covariance_by_blocks_equals_the_pseudo_inverse(factor):
    _, touches, start = _touches(6, 9, 4, factor)
    fit = refine_one(start, touches, NOISE).fit
    problem, z, _, _ = fit
    jac = problem.jacobian(z)
    assert bool(problem.t_blocks()) == factor
    blocks, dense = _unknowns_cov(problem, jac), _pinv_cov(jac)
    sd_b, sd_d = np.sqrt(np.diag(blocks)), np.sqrt(np.diag(dense))
    assert np.max(np.abs(sd_b - sd_d) / sd_d) < 1e-7
    corr = dense / np.outer(sd_d, sd_d)
    assert np.max(np.abs(blocks / np.outer(sd_b, sd_b) - corr)) < 1e-6


def test_sparse_solve_agrees_with_the_dense_one(monkeypatch):
    """15 touches × 15 samples (230 unknowns): the sparse path's parameters within 1e-3 σ
    of the dense path's, the same χ² and σ's."""
    _, touches, start = _touches(15, 15, 7)
    start = Candidate("ellipse", {k: 1.02 * v for k, v in start.params.items()},
                      Pose(start.pose.theta + 0.01, start.pose.x + 0.3, start.pose.y - 0.2), start.t, 0.0, 0, 0)
    sparse_fit = refine_one(start, touches, NOISE)
    monkeypatch.setattr(refine, "SPARSE_UNKNOWNS", 10**6)
    dense_fit = refine_one(start, touches, NOISE)
    assert sparse_fit.fit[1].size > 200
    for k, v in dense_fit.params.items():
        assert abs(sparse_fit.params[k] - v) < 1e-3 * dense_fit.uncertainty[k]
        assert abs(sparse_fit.uncertainty[k] / dense_fit.uncertainty[k] - 1) < 1e-4
    assert abs(sparse_fit.chi2 - dense_fit.chi2) < 1e-6 * dense_fit.chi2
