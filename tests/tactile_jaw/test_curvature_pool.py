"""A finger's rolls pool the truncation of their envelope's κ (tactile_jaw.curvature_pool):
exact rolls on the P-series cubical example, every joint rounded to a tick of a PH54."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from hand_driver import kinematics as kin
from recognizer.curves import Pose
from recognizer.refine import FACTOR_RCOND
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
    another degree keep it (and state their own degree's truncation, :func:`test_the_quartics_kappa_s_truncation_is_stated`)."""
    felt = rolls(HUMP_DEG, seed)
    before, after = kappa_errors(felt), kappa_errors(pooled(felt))
    cubic = np.array([t.fit.kappa_degree == 3 for t in felt])
    assert np.any(cubic) and np.all(before[cubic, 0] / before[cubic, 1] < -5.0), before[:, 0] / before[:, 1]
    assert np.all(np.abs(after[:, 0] / after[:, 1]) < 3.0), after[:, 0] / after[:, 1]
    assert np.mean(np.abs(after[cubic, 0])) < 0.7 * np.mean(np.abs(before[cubic, 0]))
    np.testing.assert_array_equal(after[~cubic, 0], before[~cubic, 0])  # their truncation stated, not taken out
    assert np.all(after[~cubic, 1] >= before[~cubic, 1])


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
    for t, p in zip(felt, pooled(felt)):  # κ, κ_s kept (the truncation columns are another matter)
        assert p.samples.curvature[:2] == t.samples.curvature[:2]
    monkeypatch.setattr(curvature_pool, "LINEAR_SHARE", math.inf)
    assert any(p.samples.curvature[:2] != t.samples.curvature[:2] for t, p in zip(felt, pooled(felt)))


def test_a_circle_keeps_its_kappa():
    """On a circle no degree is biased: the pooled test finds no truncation (Σ Δ²/v within its
    limit at every degree) and each touch's κ, κ_s stay as its fit states them; their covariance
    only gains the next terms' pooled truncation (:func:`test_the_quartics_kappa_s_truncation_is_stated`:
    stated, as the samples' is, where no test shows it)."""
    circle = SceneObject("circle", {"r": 20.0}, Pose(0.0, 120.0, 0.0), "left", (-math.pi, math.pi))
    felt = rolls((-100.0, -92.0, -85.0, -78.0, -70.0), 4, circle)
    for t, p in zip(felt, pooled(felt)):
        assert p.samples.curvature[:2] == t.samples.curvature[:2]
        assert np.all(np.diag(p.samples.curvature[2]) >= np.diag(t.samples.curvature[2]))


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


def _whitened_error(felt, psis, obj) -> tuple[float, int]:
    """χ² of a felt roll's samples (x…, y…, φ…) less the true curve's tangent points at the
    readings' exact pad angles ``psis``, whitened by the roll's stated noise factor, and its rank."""
    s = felt.samples
    x, y, phi = (np.asarray(v, float) for v in (s.x, s.y, s.phi))
    truth = np.array([support_point(obj, p) for p in psis])
    turn = np.round((phi - psis) / (math.pi / 2)) * (math.pi / 2)
    error = np.concatenate([x - truth[:, 0], y - truth[:, 1], np.angle(np.exp(1j * (phi - turn - psis)))])
    factor = np.asarray(s.noise_factor, float)
    scale = np.sqrt(np.sum(factor**2, axis=1))  # each row by its own deviation, as the recognizer whitens
    u, sv, _ = np.linalg.svd(factor / scale[:, None], full_matrices=False)
    keep = sv > FACTOR_RCOND * sv[0]
    z = (u[:, keep].T @ (error / scale)) / sv[keep]
    return float(z @ z), int(np.count_nonzero(keep))


def test_the_stated_noise_covers_the_truncation_of_exact_rolls():
    """Exact rolls on the flat side of a 40 × 12 mm ellipse, every joint read to a PH54's tick:
    the order rule keeps the quartic or the quintic, whose truncation (0.2–0.3 µm across, the
    next terms of d(ψ)) one roll's test cannot see. Unpooled, the samples' error against the
    true curve has χ²/rank 6.2 (the symmetric roll at −90° alone 211 on 14: its quintic term
    vanishes, the sextic is what is left); with each roll's next two terms pooled over the
    finger and stated as noise, 0.89 (noise only, on a circle: 0.9 either way)."""
    ellipse = SceneObject("ellipse", {"a": 40.0, "b": 12.0}, Pose(0.0, 120.0, 0.0), "left", (-math.pi, math.pi))
    left = CONFIG.finger("left")
    felt, angles = [], []
    for centre in (-90.0, -89.0, -88.0, -86.0, -84.0):
        psis = math.radians(centre) + np.linspace(-0.5, 0.5, 9) * math.radians(18.0)
        q = np.array([kin.ik_tangent(left, support_point(ellipse, p), float(p)) for p in psis])
        t = feel(CONFIG, touch(q), 9)  # touch() reads each joint to its tick: one quantization
        assert t.problem is None, t.problem
        felt.append(t)
        angles.append(psis)

    def ratio(touches):
        chi2, rank = np.sum([_whitened_error(t, p, ellipse) for t, p in zip(touches, angles)], axis=0)
        return chi2 / rank

    assert ratio(felt) > 3.0
    assert 0.5 < ratio(pooled(felt)) < 1.5


def _with_own_truncation(t, size: float):
    """Felt roll ``t`` as if its own test had found its truncation against degree k + 1 of
    ``size`` (in units of c): envelope._with_truncation's last noise-factor column, x, y rows of
    the term's pattern, and the term's ``own``."""
    term = t.fit.next_terms[0]
    n = t.samples.x.size
    column = np.concatenate([size * term.pattern[: 2 * n], np.zeros(n)])[:, None]
    factor = np.hstack([t.samples.noise_factor, column])
    terms = (replace(term, own=size),) + t.fit.next_terms[1:]
    return replace(t, fit=replace(t.fit, noise_factor=factor, next_terms=terms),
                   samples=replace(t.samples, noise_factor=factor))


@pytest.mark.parametrize("scale", [0.1, 30.0])
def test_a_rolls_truncation_is_stated_once(scale):
    """A roll whose own test found its truncation against degree k + 1 (envelope._with_truncation)
    states it once, in the finger's pooled column of that term: √max(E[c²], own²) along the
    term's pattern, the own column dropped (before: both, the X-series jaw's χ²/dof at the truth
    0.46). The own size enters no other roll's statement."""
    felt = rolls(HUMP_DEG, 0)
    plain = pooled(felt)
    term = felt[0].fit.next_terms[0]
    assert term.degree == felt[0].fit.contacts.degree + 1 and term.own == 0.0
    pattern = term.pattern / np.linalg.norm(term.pattern)
    along = plain[0].samples.noise_factor.T @ pattern
    pooled_size = float(np.max(np.abs(along))) / np.linalg.norm(term.pattern)  # its pooled column, √E[c²]
    own = scale * pooled_size
    after = pooled([_with_own_truncation(felt[0], own)] + felt[1:])
    f = after[0].samples.noise_factor
    assert f.shape == plain[0].samples.noise_factor.shape
    np.testing.assert_allclose(f[:, :-3], plain[0].samples.noise_factor[:, :-3])  # the ticks' columns
    stated = np.max(np.abs(f.T @ pattern)) / np.linalg.norm(term.pattern)
    assert stated == pytest.approx(max(own, pooled_size), rel=1e-9)
    for a, b in zip(after[1:], plain[1:]):
        np.testing.assert_array_equal(a.samples.noise_factor, b.samples.noise_factor)


def _kappa_s_z(felt, obj) -> np.ndarray:
    """Each touch's stated κ_s less the truth at its contact, in its stated σ."""
    curve, pose = obj.curve(), obj.pose
    t = np.linspace(*obj.extent, 200001)
    px, py = curve.point(t)
    out = []
    for f in felt:
        c = f.fit.contacts
        m = c.x.size // 2
        cx, cy = pose.inverse(c.x[m], c.y[m])
        truth = float(curve.kappa_s(t[int(np.argmin(np.hypot(px - cx, py - cy)))]))
        _, kappa_s, cov = f.samples.curvature
        out.append((kappa_s - truth) / math.sqrt(cov[1, 1]))
    return np.array(out)


def test_the_quartics_kappa_s_truncation_is_stated():
    """Rolls of 9 readings on the hyperbola example's arm (t 0.03–0.43 from its vertex), every
    joint read to a PH54's tick: the order rule states κ_s from the quartic, whose least squares
    miss d(ψ)'s quintic term (κ_s = −ρ'/ρ³ comes from its odd coefficients), up to 8 of its σ's off
    the truth (the quintic's κ_s is right: the readings' noise is not what is off). The term's
    size c = d⁽⁵⁾ pooled over the finger's rolls and its effect on κ_s stated as noise: every κ_s
    within 3 σ."""
    hyperbola = load_scene("config/scenes/hyperbola.yaml").object
    rng = np.random.default_rng(0)
    felt = []
    for centre in (-112.0, -104.0, -98.0, -92.0):
        psis = math.radians(centre) + np.linspace(-0.5, 0.5, 9) * math.radians(18.0)
        f = feel(CONFIG, touch(roll(lambda p: support_point(hyperbola, p), psis, FINE, rng)), 9)
        assert f.problem is None, f.problem
        felt.append(f)
    before, after = _kappa_s_z(felt, hyperbola), _kappa_s_z(pooled(felt), hyperbola)
    worst = int(np.argmax(np.abs(before)))
    assert felt[worst].fit.kappa_degree == 4 and abs(before[worst]) > 5.0, before
    assert np.all(np.abs(after) < 3.0), after
