"""A finger's rolls pool the truncation of their envelope's κ (tactile_jaw.curvature_pool):
exact rolls on the P-series cubical example, every joint rounded to a tick of a PH54."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from recognizer.curves import Pose
from recognizer.scene import SceneObject, load_scene
from tactile_jaw import curvature_pool
from tactile_jaw.curvature_pool import corrected, pool, pooled
from tactile_jaw.pipeline import feel
from tests.tactile_jaw.test_envelope_order import CONFIG, FINE, _true_kappa, roll, support_point, touch

CUBICAL = load_scene("config/scenes/cubical_parabola.yaml").object
#: where the left pad's normal points at the example's hump (its top near −85°) and beside it:
#: the exploration rolls a finger again and again near one place
HUMP_DEG = (-92.0, -88.0, -85.0, -85.0, -82.0, -78.0)


def rolls(centres_deg, seed: int, obj=CUBICAL):
    """The left finger's 18° rolls of 9 readings centred at ``centres_deg`` on ``obj``, felt."""
    rng = np.random.default_rng(seed)
    out = []
    for c in centres_deg:
        psis = math.radians(c) + np.linspace(-0.5, 0.5, 9) * math.radians(18.0)
        felt = feel(CONFIG, touch(roll(lambda p: support_point(obj, p), psis, FINE, rng)), 9)
        assert felt.problem is None, felt.problem
        out.append(felt)
    return out


def kappa_errors(felt, obj=CUBICAL):
    """Each touch's stated κ less the truth at its contact, and its stated σ."""
    out = []
    for t in felt:
        c = t.fit.contacts
        m = c.x.size // 2
        kappa, _, cov = t.samples.curvature
        out.append((abs(kappa) - _true_kappa(obj, c.x[m], c.y[m]), math.sqrt(cov[0, 0])))
    return np.array(out)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_the_cubics_bias_at_the_hump_is_taken_out_and_stated(seed):
    """At the hump the cubic d(ψ) states κ 0.6–1 % low with σ 0.1–0.2 % (z −5 … −9), and one
    roll's comparison with the quartic is within its noise, so the order rule keeps the cubic.
    Pooled over the finger's six rolls, the bias the cubic shows against the quartic on all of
    them is estimated and taken out of each cubic roll's κ, and what is left stated: every κ
    within 3 σ, the cubic rolls' mean error down by 30 % or more (a roll whose own
    comparison happened to be small keeps more of its bias, and states it); the rolls whose κ comes from
    another degree keep it."""
    felt = rolls(HUMP_DEG, seed)
    before, after = kappa_errors(felt), kappa_errors(pooled(felt))
    cubic = np.array([t.fit.kappa_degree == 3 for t in felt])
    assert np.any(cubic) and np.all(before[cubic, 0] / before[cubic, 1] < -5.0), before[:, 0] / before[:, 1]
    assert np.all(np.abs(after[:, 0] / after[:, 1]) < 3.0), after[:, 0] / after[:, 1]
    assert np.mean(np.abs(after[cubic, 0])) < 0.7 * np.mean(np.abs(before[cubic, 0]))
    np.testing.assert_array_equal(after[~cubic], before[~cubic])


def test_a_roll_whose_kappa_is_coarse_stays_out_of_the_pool(monkeypatch):
    """A roll whose difference to the richer degree is noisier than 2 % of its κ (the X-series
    jaw's 15–30 %: the first-order noise no longer holds) neither joins the pool nor is changed:
    the hump's rolls with their noise and their degrees' differences 256 times larger (each
    difference as significant as before: pooled, they would change)."""

    def coarse(t):
        lad = t.fit.ladder
        low = lad.values[3]
        return replace(t, fit=replace(t.fit, ladder=replace(lad, rows={k: 256.0 * r for k, r in lad.rows.items()},
                                                                 values={k: low + 256.0 * (v - low)
                                                                         for k, v in lad.values.items()})))

    felt = [coarse(t) for t in rolls(HUMP_DEG, 0)]
    for t, p in zip(felt, pooled(felt)):  # κ, κ_s kept (the samples' truncation column is another matter)
        assert p.samples.curvature is t.samples.curvature
    monkeypatch.setattr(curvature_pool, "LINEAR_SHARE", math.inf)
    assert any(p.samples.curvature is not t.samples.curvature for t, p in zip(felt, pooled(felt)))


def test_a_circle_keeps_its_kappa():
    """On a circle no degree is biased: the pooled test finds no truncation (Σ Δ²/v within its
    limit at every degree) and each touch's κ, κ_s and covariance stay as its fit states them."""
    circle = SceneObject("circle", {"r": 20.0}, Pose(0.0, 120.0, 0.0), "left", (-math.pi, math.pi))
    felt = rolls((-100.0, -92.0, -85.0, -78.0, -70.0), 4, circle)
    for t, p in zip(felt, pooled(felt)):
        assert p.samples.curvature is t.samples.curvature


def test_the_truth_put_in_keeps_its_value_and_takes_the_pooled_deviation():
    """tactile_jaw.separation.exact_touches puts the truth's κ, κ_s in a touch to ask what its
    stated noise would tell: pooling keeps those values and states the pooled covariance."""
    felt = rolls(HUMP_DEG[:3], 0)
    exact = [replace(t, samples=replace(t.samples, curvature=(0.5, 0.01, t.samples.curvature[2]))) for t in felt]
    for t, e, p in zip(pooled(felt), exact, pooled(exact)):
        assert p.samples.curvature[:2] == (0.5, 0.01)
        np.testing.assert_array_equal(p.samples.curvature[2], t.samples.curvature[2])


def test_the_pooled_bias_and_what_one_roll_takes_from_it():
    """(μ̂, s², ω) by the method of moments when Σ Δ²/v exceeds its χ² limit at 0.05,
    else None; a roll alone that shows a bias takes the richer degree (b̂ = Δ, w′ = 1, nothing left)."""
    var = np.full(4, 0.1)
    diff = np.array([-1.0, -0.9, -1.2, -0.8])  # one bias, spread within the noise: s² = 0
    centre, spread, omega = pool(diff, var)
    assert spread == 0.0 and centre == pytest.approx(-0.975)
    np.testing.assert_allclose(omega, 0.25)
    bias, blend, left = corrected(diff, var, (centre, spread, omega), 0)
    assert bias == pytest.approx(centre) and blend == pytest.approx(0.25)
    assert left == pytest.approx(3 * 0.25**2 * 0.1)  # the other rolls' noise in μ̂
    var = np.full(4, 0.25)
    diff = np.array([-3.0, 0.0, -3.0, 0.0])  # biases that differ: s² = Q's excess
    q = np.sum((diff + 1.5) ** 2 / 0.25)
    assert pool(diff, var)[1] == pytest.approx((q - 3) / (16 - 4))
    assert pool(diff / 3.0, var) is None  # Σ z² 8 on 4 rolls: within the limit 9.49
    assert pool(np.array([0.9]), np.array([0.25])) is None  # z 1.8: within the limit 1.96
    one = pool(np.array([1.8]), np.array([0.25]))
    assert corrected(np.array([1.8]), np.array([0.25]), one, 0) == pytest.approx((1.8, 1.0, 0.0))
    assert pool(np.array([1.0]), np.array([0.0])) is None
