"""κ, κ_s of a finger's rolls with the truncation of their envelope fits pooled across them.

Each rolling touch states κ, κ_s from one degree k of d(ψ) (tactile_jaw.envelope.curvature_degree:
the degree with the least expected squared error judged on that roll alone) and keeps every
degree the order rule fitted (``EnvelopeFit.ladder``). The difference Δ of degree k to k + 2 (the
next degree that changes both: ``CurvatureLadder.difference``; k + 1 where k + 2 was not fitted)
holds the truncation bias b of degree k (the richer degree's is far smaller) and noise of
variance v (the difference of the two degrees' noise factors). On fine encoders a low degree's κ is precise but
biased where ρ(ψ) bends (a least-squares cubic's ρ is linear in ψ): on the P-series cubical's
hump the cubic's κ came out 0.65–1.43 % low with σ 0.1–0.2 % (z −3.5 … −11.6; seed 127,
tools.bench_explore --finite 20), where v^½ ≈ 0.5 %: one roll cannot tell b from its noise, and
the rule keeps the cubic on exactly the rolls whose Δ happened to be small. A finger's rolls on
the same object can: the exploration rolls a finger again and again near one place, where b is
systematic (same sign, similar size), and every roll that fitted degree k and the richer one
shows it, whichever degree it states.

So per finger and degree, each component (κ, κ_s) on its own: when the rolls' Σ Δ²/v exceeds its
χ² limit at ``TRUNCATION_ALPHA`` (else nothing changes), their biases are taken as b ~ N(μ, s²),
μ and s² by the method of moments (:func:`pool`), and each roll that states degree k has its bias
estimated by its posterior mean b̂ = (1 − w)μ̂ + wΔ, w = s²/(s² + v), and taken out. With ω the
roll's own weight in μ̂, the corrected value is (1 − w′)κ_k + w′κ_r + (1 − w)(b − μ̂) (r the richer
degree) with w′ = w + (1 − w)ω: its noise factor is (1 − w′)F_k + w′F_r, and what the pooled estimate leaves,
variance (1 − w)²((1 − ω)²s² + Σ_{other rolls} ω_j²(s² + v_j)), one more column. A finger's one
roll alone takes κ_r when its own Δ shows a bias. A roll with too few readings for degree k + 2
(its own Δ to k + 1 hardly shows κ_s's bias) takes the pool of k against k + 2 where it shows one:
b̂ = μ̂, its own value kept (:func:`unseen`). docs/exploration.md#pooled-truncation.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import replace
from typing import Any

import numpy as np
from scipy import stats

from recognizer.intervals import REL_SIGMA_CHECK
from recognizer.limits import MIN_NOISE
from tactile_jaw.envelope import TRUNCATION_ALPHA

#: a roll joins its finger's pool when the noise of its difference Δ in κ is within this share of
#: its κ: the first-order noise the test weighs Δ by holds there (κ = 1/ρ is near-linear over it;
#: recognizer.intervals doubts a linearized σ beyond the same share). An X-series roll's κ is
#: 15–30 % uncertain: pooled at that noise, 3 of the 178 usable rolls of seed 127's circles and
#: ellipses were "corrected" by up to 50 % on a difference of 2.4–3.5 of its first-order σ's
LINEAR_SHARE = REL_SIGMA_CHECK


def pool(diff: np.ndarray, var: np.ndarray, tested: bool = True) -> tuple[float, float, np.ndarray] | None:
    """The truncation bias of one degree against the next over a finger's rolls (``diff`` their
    differences Δ, ``var`` those differences' noise variances v) as b ~ N(μ, s²), by the method of
    moments (DerSimonian–Laird: s² the spread of Δ beyond their noise, μ̂ their mean weighted by
    1/(v + s²)): (μ̂, s², each roll's weight ω in μ̂); None when Σ Δ²/v is within its χ² limit at
    ``TRUNCATION_ALPHA`` (no bias shown) or a variance is not positive."""
    diff, var = np.asarray(diff, dtype=float), np.asarray(var, dtype=float)
    if not (np.all(var > 0.0) and np.all(np.isfinite(diff)) and np.all(np.isfinite(var))):
        return None
    if tested and float(np.sum(diff**2 / var)) <= stats.chi2.isf(TRUNCATION_ALPHA, diff.size):
        return None
    weight = 1.0 / var
    centre = float(np.sum(weight * diff) / np.sum(weight))
    q = float(np.sum(weight * (diff - centre) ** 2))
    scale = float(np.sum(weight) - np.sum(weight**2) / np.sum(weight))
    spread = max(0.0, (q - (diff.size - 1)) / scale) if scale > 0.0 else 0.0
    omega = (1.0 / (var + spread)) / np.sum(1.0 / (var + spread))
    return float(np.sum(omega * diff)), spread, omega


def corrected(diff: np.ndarray, var: np.ndarray, pooled_bias: tuple[float, float, np.ndarray],
              n: int) -> tuple[float, float, float]:
    """Roll ``n``'s bias estimate b̂ = (1 − w)μ̂ + wΔ_n (module docstring), the weight w′ of degree
    r in its corrected value, and the variance the pooled estimate leaves."""
    centre, spread, omega = pooled_bias
    w = spread / (spread + var[n])
    others = float(np.sum(np.delete(omega**2 * (spread + var), n)))
    left = (1.0 - w) ** 2 * ((1.0 - omega[n]) ** 2 * spread + others)
    return (1.0 - w) * centre + w * float(diff[n]), w + (1.0 - w) * float(omega[n]), left


def pooled(touches: Sequence[Any]) -> list[Any]:
    """``touches`` (tactile_jaw.pipeline.FeltTouch) with each rolling touch's stated κ, κ_s and
    their covariance pooled across its finger's rolls (module docstring): the bias of degree k
    against a richer degree r from every roll of the finger that fitted both, taken out of those that state
    κ, κ_s at degree k. A touch whose stated κ, κ_s are not its fit's own
    (tactile_jaw.separation.exact_touches puts the truth there) keeps them and takes the
    pooled covariance."""
    fingers: dict[str, list[int]] = {}
    for i, t in enumerate(touches):
        fit = getattr(t, "fit", None)
        if fit is None or fit.ladder is None or getattr(getattr(t, "samples", None), "curvature", None) is None:
            continue
        fingers.setdefault(t.finger, []).append(i)
    out = list(touches)
    blends: dict[int, np.ndarray] = {}  # a corrected roll's weight w′ of the richer degree, κ and κ_s
    for members in fingers.values():
        for k in sorted({touches[i].fit.kappa_degree for i in members}):
            stating = [i for i in members if touches[i].fit.kappa_degree == k
                       and touches[i].fit.ladder.difference(k) is not None]
            components: dict[int, list] = {i: [None, None] for i in stating}
            for richer in (k + 2, k + 1):  # k + 2 first: the degree that changes both κ and κ_s
                rolls = [i for i in members if _linear(touches[i].fit, k, richer)]
                if not rolls:
                    continue
                diff, var = (np.array(a) for a in list(zip(*(touches[i].fit.ladder.difference(k) for i in rolls)))[:2])
                for j in range(2):
                    bias = pool(diff[:, j], var[:, j])
                    if bias is None:
                        continue
                    for i in stating:
                        if components[i][j] is not None:
                            continue
                        if i in rolls:
                            components[i][j] = corrected(diff[:, j], var[:, j], bias, rolls.index(i))
                        elif richer == k + 2:  # too few readings for degree k + 2: the finger's bias
                            components[i][j] = unseen(var[:, j], bias)
            for i in stating:
                if any(c is not None for c in components[i]):
                    out[i] = _taken_out(touches[i], k, components[i])
                    blends[i] = np.array([0.0 if c is None else c[1] for c in components[i]])
        for i, column, own in _truncation_columns([touches[i] for i in members]):
            s = out[members[i]].samples
            # the roll's own term (its fit's last column; a term of a higher degree may come first)
            kept = np.delete(s.noise_factor, touches[members[i]].fit.noise_factor.shape[1] - 1, axis=1) if own \
                else s.noise_factor
            out[members[i]] = replace(out[members[i]], samples=replace(
                s, noise_factor=np.hstack([kept, column[:, None]])))
        for i, column in _kappa_truncation([touches[i] for i in members]):
            s = out[members[i]].samples
            kappa, kappa_s, cov = s.curvature
            column = column * (1.0 - blends.get(members[i], np.zeros(2)))  # a blend's richer share has none
            out[members[i]] = replace(out[members[i]], samples=replace(
                s, curvature=(kappa, kappa_s, cov + np.outer(column, column))))
    return out


def _kappa_truncation(rolls: Sequence[Any]) -> list[tuple[int, np.ndarray]]:
    """The truncation of one finger's ``rolls``' κ, κ_s (tactile_jaw.envelope.EnvelopeFit.kappa_terms:
    the terms one and two degrees above κ's degree not stated there), pooled per degree as the
    samples' (:func:`_truncation_columns`): √E[c²] times the term's κ, κ_s error per unit c, one
    column per term. Its error is as systematic as the samples', and on the P-series jaw larger than
    κ_s's own noise: a quartic's κ_s on a hyperbola's arm 10 of its σ's off with the readings exact
    (the quintic's right). Not where κ, κ_s are not the fit's own (tactile_jaw.separation.exact_touches).
    Returns (index in ``rolls``, (2,) column)."""
    return [(i, math.sqrt(square) * term.curvature)
            for i, term, square in _pooled_terms(rolls, "curvature", "kappa_terms")]


def _pooled_terms(rolls: Sequence[Any], stated: str, terms: str) -> list[tuple[int, Any, float]]:
    """Each term (tactile_jaw.envelope.NextTerm) of the ``rolls`` whose samples state ``stated``,
    from their fits' ``terms``, with its expected square E[c²] pooled per degree across the rolls
    (:func:`pool`, :func:`expected_square`): (index in ``rolls``, term, E[c²])."""
    by_degree: dict[int, list[tuple[int, Any]]] = {}
    for i, t in enumerate(rolls):
        if getattr(t.samples, stated, None) is None:
            continue
        for term in getattr(t.fit, terms, ()):
            if term.variance > 0.0:
                by_degree.setdefault(term.degree, []).append((i, term))
    out = []
    for members in by_degree.values():
        value = np.array([term.value for _, term in members])
        var = np.array([term.variance for _, term in members])
        bias = pool(value, var, tested=False)
        if bias is None:
            continue
        out += [(i, term, expected_square(value, var, bias, n)) for n, (i, term) in enumerate(members)]
    return out


def _truncation_columns(rolls: Sequence[Any]) -> list[tuple[int, np.ndarray, bool]]:
    """The samples' truncation of one finger's ``rolls`` (tactile_jaw.envelope.NextTerm: the terms
    one and two degrees above each roll's contacts' degree k, c = d^(j) of the richer fit, with
    its noise v) pooled per degree j across the rolls as κ's bias is (:func:`pool`,
    :func:`corrected`): each roll's expected squared c, b̂² + what the pooled estimate leaves,
    stated as one more noise-factor column √(b̂² + left)·e per term (e its pattern: a correlated
    error along the roll). One roll's c is mostly its noise (the richer degree's contacts are
    2–3× noisier); a finger rolls again near one place, where c is systematic. Stated here once:
    where a roll's own test found its k + 1 term (``NextTerm.own``, envelope._with_truncation's
    column, which the caller drops) the column is √max(E[c²], own²): the pool's E[c²] is the
    posterior of rolls alike, and a finger's lone roll's, Δ² + v, always holds its own; a roll
    whose own test finds more than its finger's pool allows is not like the others and keeps its
    own (X-series seed-283 ellipse 47, a roll of a finger's six: own column 4.5 mm over its samples,
    pooled 0.08 mm). Returns (index in
    ``rolls``, column, whether it replaces the roll's own column)."""
    columns = []
    for i, term, square in _pooled_terms(rolls, "noise_factor", "next_terms"):
        column = math.sqrt(max(square, term.own**2)) * term.pattern
        # A pattern's node (a vertex-centred roll's middle) comes out ~1e-17, not 0: below what
        # any instrument resolves, which a written touches file may not state (recognizer.touches).
        columns.append((i, np.where(np.abs(column) < MIN_NOISE, 0.0, column), term.own > 0.0))
    return columns


def expected_square(diff: np.ndarray, var: np.ndarray, pooled_bias: tuple[float, float, np.ndarray], n: int) -> float:
    """E[b_n²] of roll ``n``'s bias given the finger's rolls (``diff``, ``var`` as in :func:`pool`):
    b̂² (b̂ = (1 − w)μ̂ + wΔ_n, w = s²/(s² + v_n)) plus its posterior variance w·v_n + (1 − w)²·var μ̂,
    var μ̂ = 1/Σ 1/(v_j + s²). A finger's one roll: Δ_n² + v_n, its bias as large as its own
    difference allows."""
    centre, spread, _ = pooled_bias
    w = spread / (spread + var[n])
    estimate = (1.0 - w) * centre + w * float(diff[n])
    return estimate**2 + w * float(var[n]) + (1.0 - w) ** 2 / float(np.sum(1.0 / (var + spread)))


def unseen(var: np.ndarray, pooled_bias: tuple[float, float, np.ndarray]) -> tuple[float, float, float]:
    """:func:`corrected` for a roll that states degree k but has too few readings to fit k + 2
    (eight of a roll's nine kept: tactile_jaw.envelope.degrees), so its own difference to k + 1
    shows κ_s's truncation hardly at all (about the roll's middle one degree up changes κ or
    κ_s, not both: CurvatureLadder.difference): its bias is the finger's pooled one, b̂ = μ̂
    (w = 0, its own value kept: w′ = 0), leaving s² + Σ ω_j²(s² + v_j). P cubical 105 of
    bench_explore --finite 20 --anywhere --seed 157 --config config/jaw-p.yaml: a roll of 8
    readings on the hump stated the cubic's κ_s −3.26e-3 ± 0.13e-3 where the truth is −3.81e-3
    (the quartic's −3.34e-3), z 4.1, and no class fitted; the finger's rolls of 9 readings
    showed the cubic's κ_s off its quintic's by −0.3 … +0.4e-3."""
    centre, spread, omega = pooled_bias
    return centre, 0.0, spread + float(np.sum(omega**2 * (spread + var)))


def _linear(fit, k: int, richer: int) -> bool:
    """Whether ``fit`` compared degree k with ``richer`` and its difference's noise in κ is within
    ``LINEAR_SHARE`` of κ (the first-order noise holds)."""
    d = fit.ladder.difference(k)
    return d is not None and d[2] == richer and math.sqrt(d[1][0]) <= LINEAR_SHARE * abs(fit.ladder.values[k][0])


def _taken_out(touch, k: int, components) -> Any:
    """``touch`` with each component's (κ, κ_s) bias estimate taken out of its stated value and
    its covariance the blend of degree k and the richer one and what the estimate leaves (``components``:
    :func:`corrected` of each, or None to keep it)."""
    fit = touch.fit
    richer = fit.ladder.rows[fit.ladder.difference(k)[2]]
    factor = fit.ladder.own.copy()
    shift, left = np.zeros(2), np.zeros(2)
    for j, c in enumerate(components):
        if c is not None:
            shift[j], blend, left[j] = c
            factor[j] *= 1.0 - blend
            factor[j, : richer.shape[1]] += blend * richer[j]
    factor = np.hstack([factor, np.diag(np.sqrt(left))])
    s = touch.samples
    kappa, kappa_s, _ = s.curvature
    if (kappa, kappa_s) == (fit.kappa, fit.kappa_s):
        kappa, kappa_s = fit.kappa - float(shift[0]), fit.kappa_s - float(shift[1])
    return replace(touch, samples=replace(s, curvature=(kappa, kappa_s, factor @ factor.T)))
