"""The recognition tree (paper §5, Fig. 2) over the scene's classes, with statistics.

For every class the scene allows (and the touches suffice for, touches.MIN_TOUCHES) the
class is fitted to every touch (recognizer.localize: the invariants' closed-form
solution, then the exact contact equations by least squares). Its consistency test
is a χ² test at level ``alpha`` on the whitened residuals of every measurement (position,
tangent angle, κ, κ_s of every touch): the invariants' consistency across every pair of
touches is what this tests, with each measurement's propagated uncertainty (a contact's
κ/κ_s covariance, the noise model's φ and position deviations). With zero covariance
(exact data) the floor contacts.EPS_FLOOR (1e-7 relative) stands in for the deviations.
Consistent classes are ranked by BIC = −2 ln L + k·ln(n_obs) (k: fitted unknowns), and
the best is kept unless a simpler class of which it is a limit (``CHOICE_LIMIT_OF``: a line of
every curved class, a circle of the ellipse, a parabola of the ellipse and hyperbola; the
parabola is also a limit of both cubic families, ``LIMIT_OF``, which BIC decides) is
also consistent and the richer class does not pass a likelihood-ratio test against it
(−2Δln L above the χ² quantile at ``MODEL_ALPHA`` for the extra parameters): so a
circle beats an ellipse with a ≈ b and a line beats a flat conic unless the data say
otherwise with confidence 1 − MODEL_ALPHA, while classes that are not limits of each
other (a parabola and a semicubical parabola) are compared by BIC alone. No consistent class: ``unclassified`` with the
invariant and the measurement that disagreed most, against their uncertainty.
"""

from __future__ import annotations

import math
import time
from functools import lru_cache

import numpy as np
from scipy import special, stats

from recognizer import invariants as inv
from recognizer.class_limits import LIMIT_OF
from recognizer.contacts import EPS_FLOOR, Contacts
from recognizer.localize import N_SHAPE, fit_class, fit_class_every_start, fit_continued, line_correlation, profiled
from recognizer.nested import NESTED_FROM, nested_candidates
from recognizer.curves import CURVES, Pose
from recognizer.refine import MAX_NFEV, RefinedCandidate, refine_candidates
from recognizer.starts import clear_of_cusp, conic_start, cusp_clearance, hyperbola_asymptote, pose_from, semicubical_scan
from recognizer.starts import starts as class_starts
from recognizer.result import Candidate, Ranked, Recognition, RecognizeOptions
from recognizer.scale_free import Unit
from recognizer.intervals import CHI2_VALLEY, interval95, other_valleys, profile_uncertainty, rival_basins, same_valley
from recognizer.next_touch import next_touch
from recognizer.touches import MIN_TOUCHES, ContactTouch, NoiseModel, Request, SamplesTouch
from tactile_common.angles import wrap_angle
from tactile_common.blas import one_blas_thread

__all__ = ["recognize", "contacts_of", "options_for", "close_rivals", "DEFAULT_SAMPLES_NOISE", "RIVAL_BIC"]

#: φ and position deviations assumed for samples-touches when neither the request nor
#: the scene gives a noise model (the jaw's encoder and pad-line resolution)
DEFAULT_SAMPLES_NOISE = NoiseModel(phi=1e-3, pos=0.05)
#: the limits ``choose`` prefers unless the richer class passes the likelihood-ratio test:
#: LIMIT_OF (recognizer.class_limits) without the parabola as a limit of the cubic families, which BIC alone decides.
#: Measured (bench_wide, 280 trials, seed 1, right class with 3 / 3 + 2 random / 3 + ≤ 2
#: suggested touches): with them, parabola 97.5/95.0/97.5 % → 100/100/100 % but
#: semicubical 65.0/75.0/90.0 % → 50.0/67.5/87.5 % (a semicubical's branch touched on
#: one side fits a parabola within the test's 10.8 more often than a parabola's touches
#: fit a semicubical better by BIC's penalty)
CHOICE_LIMIT_OF = {**LIMIT_OF, "parabola": frozenset({"ellipse", "hyperbola"})}
#: distinct places (contacts.Contacts.places) a class needs to be tested: as many as touches
#: (touches.MIN_TOUCHES: its invariants need pairs of places), but one for the line, whose test
#: is that κ and κ_s vanish where it is touched (two spare degrees of freedom at one place:
#: a flat press measures that over its whole seated segment, and the jaw presses a face at
#: one place again and again: tactile_jaw.flat)
MIN_PLACES = {**MIN_TOUCHES, "line": 1}
#: a contact-stage answer's shape parameter whose linearized relative σ is above this is walked
#: along its profile (recognizer.intervals; refined answers: above 2 %): 3-5 touches, ~5 ms a
#: parameter; near a cubical's inflection c's valley stays flat 4.5 linearized σ's out at a
#: relative σ of 0.8 %, while exact data away from the extremes (σ's at the 1e-7 floor) are
#: not walked at all
CONTACT_REL_SIGMA_CHECK = 1e-3
#: level of the likelihood-ratio test a class must pass against a simpler class it contains
MODEL_ALPHA = 1e-3
#: two consistent classes neither of which is a limit of the other (``LIMIT_OF``) whose BICs
#: lie less than this apart are not told apart: the answer is a refusal naming both
#: (:func:`close_rivals`). ΔBIC ≈ −2 ln(Bayes factor): below 6 the better class's posterior
#: odds are under e³ ≈ 20:1 (equal priors: under 95 %), short of Kass & Raftery's "strong"
#: evidence. Nested classes are decided by the likelihood-ratio test (``MODEL_ALPHA``)
#: instead: the richer one always fits at least as well. Measured: tools.bench_wide seed 9
#: (development), hyperbola trial 11 far on an arm, answered cubical parabola at ΔBIC 3.1.
#: Measured on the recorded rankings of 584 bench_wide answers (development seeds 1, 9, 11, 31 and 5 twice,
#: last session's code):
#: of the 3-touch answers with a rival below 6, 47 of 104 were wrong (below 2: 34 of 63),
#: above it 47 of 480; with ≤ 2 suggested touches 2 of 10 below 6, 1 of 576 above. Refusing
#: below 6 (``RecognizeOptions.close_rivals = "refuse"``) would cost 1-3 right semicubicals
#: per seed with suggested touches (far out on a branch, an ellipse as close: a coin
#: flip), so by default the answer names the rival and says it could not tell
RIVAL_BIC = 6.0
#: how an unclassified answer begins when the classes tested fail but others of the scene were
#: not tested for too few touches (distinct places): not "no class of the scene fits", since an
#: untested class may fit once more touches are usable (dev seed 83 semicubical 27: 2 touches
#: clear of the corners, the parabola failed and the semicubical was never tested)
NONE_TESTED_FITS = "no class tested fits"
_MEAS = ("x", "y", "phi", "kappa", "kappa_s")


def _pos_sd(nz: NoiseModel) -> float:
    """One isotropic deviation per contact position (the larger of across and along the
    tangent); refinement weighs every sample across and along its tangent separately."""
    return max(nz.pos, nz.along)


def contacts_of(request: Request, options: RecognizeOptions,
                default_noise: NoiseModel = DEFAULT_SAMPLES_NOISE) -> Contacts:
    """Local geometry of every touch: contacts as given (covariance from the request or
    zero); samples-touches through recognizer.estimate.estimate_local (their deviations
    ``default_noise`` when neither the options nor the request state any)."""
    noise = options.noise or request.noise
    rows = []
    for i, t in enumerate(request.touches):
        if isinstance(t, ContactTouch):
            nz = noise or NoiseModel()
            rows.append((t.x, t.y, t.phi, t.kappa, t.kappa_s, t.cov, _pos_sd(nz), nz.phi))
        else:
            from recognizer.estimate import estimate_local

            g = estimate_local(t, method=options.estimator, noise=noise, where=f"{request.source}.touches[{i}]")
            nz = noise or default_noise
            # the contact sample's own φ, with its stated deviation: the estimator's smoothed
            # φ carries a truncation error no covariance states (up to 1e-2 rad on noise-free
            # hyperbola touches, judged at the 1e-7 floor: right classes were rejected)
            phi_m = float(np.asarray(t.phi, float)[len(t.phi) // 2])
            kappa, kappa_s, cov = (g.kappa, g.kappa_s, g.cov) if t.curvature is None else t.curvature
            rows.append((g.x, g.y, phi_m, kappa, kappa_s, np.asarray(cov, float), _pos_sd(nz), nz.phi))
    cols = list(zip(*rows))
    arr = [np.array(c, dtype=float) for c in cols[:5]]
    return Contacts(*arr, np.array(cols[5], dtype=float).reshape(-1, 2, 2), np.array(cols[6], float),
                    np.array(cols[7], float), 0.5 * _roll(request))


def options_for(request: Request, overrides: dict | None = None) -> RecognizeOptions:
    """RecognizeOptions of a request: ``overrides`` (command-line flags; a ``profile`` there
    sets all of that profile's options) > the request's explicit options > the request's
    profile > the scene's profile > ``DEFAULT_PROFILE`` (``balanced``) for a request with
    samples-touches (or none yet); a request of contacts only keeps the invariants-only
    defaults (``RecognizeOptions``)."""
    from tactile_common.errors import InputError
    from recognizer.profiles import DEFAULT_PROFILE, get_profile, resolve_options

    overrides = dict(overrides or {})
    contacts_only = bool(request.touches) and all(isinstance(t, ContactTouch) for t in request.touches)
    opts = resolve_options(request.options, request.scene, None if contacts_only else DEFAULT_PROFILE)
    flag_profile = overrides.pop("profile", None)
    if flag_profile is not None:
        opts.update(get_profile(flag_profile, "--profile").options())
    opts.update(overrides)
    alpha = float(opts.get("alpha", 1e-3))
    if not 0.0 < alpha < 0.5:
        raise InputError(f"alpha: must be in (0, 0.5), got {alpha}")
    return RecognizeOptions(estimator=opts.get("estimator", "auto"), refine=bool(opts.get("refine", False)),
                            alpha=alpha, noise=request.noise, profile=opts.get("profile"),
                            reach=request.options.get("reach"), missed=request.options.get("missed", ()))


def _pair_invariants(d: Contacts) -> dict:
    """I_c1, I_c2 of every pair with first-order σ; ill-conditioned pairs are marked."""
    out = {"pairs": [], "I_c1": [], "I_c2": [], "I_c1_sigma": [], "I_c2_sigma": [], "condition": []}
    noisy = bool(np.any(d.cov))
    k, ks = d.kappa.tolist(), d.kappa_s.tolist()
    for i in range(d.n):
        for j in range(i + 1, d.n):
            c1, c2 = inv.I_c12_s(k[i], ks[i], k[j], ks[j])
            s1 = s2 = 0.0
            if noisy:
                vals = (k[i], ks[i], k[j], ks[j])
                with np.errstate(all="ignore"):
                    s1 = math.sqrt(inv.propagate(inv.I_c1, vals, [d.cov[i], d.cov[j]]))
                    s2 = math.sqrt(inv.propagate(inv.I_c2, vals, [d.cov[i], d.cov[j]]))
            out["pairs"].append([i, j])
            out["I_c1"].append(c1)
            out["I_c2"].append(c2)
            out["I_c1_sigma"].append(s1)
            out["I_c2_sigma"].append(s2)
            out["condition"].append(inv.pair_condition_s(k[i], k[j]))
    return out


def _class_invariants(cand: Candidate, d: Contacts, pairs: dict) -> dict:
    """The invariants of the answered class, evaluated at the touches."""
    cls = cand.cls
    if cls in ("ellipse", "hyperbola"):
        return {k: pairs[k] for k in ("pairs", "I_c1", "I_c2", "condition")}
    if cls == "parabola":
        return {"I_p": inv.I_p(d.kappa, d.kappa_s).tolist(), "I_c1": pairs["I_c1"], "pairs": pairs["pairs"]}
    if cls in ("line", "circle"):
        return {"kappa": d.kappa.tolist(), "kappa_s": d.kappa_s.tolist()}
    # cubic classes: λ from the tangent rotation relative to the recovered canonical frame
    sign = 1.0
    if cls == "semicubical_parabola" and d.kappa[np.argmax(np.abs(d.kappa))] < 0:
        sign = -1.0
    phi = d.phi + (np.pi if sign < 0 else 0.0)
    lam = np.tan(phi - cand.pose.theta)
    k = sign * d.kappa
    if cls == "cubical_parabola":
        return {"lambda": lam.tolist(), "I_cp1": inv.I_cp1(lam, k, d.kappa_s).tolist(),
                "I_cp2": inv.I_cp2(lam, k, d.kappa_s).tolist()}
    return {"lambda": lam.tolist(), "I_scp1": inv.I_scp1(lam, k, d.kappa_s).tolist(),
            "I_scp2": inv.I_scp2(lam, k, d.kappa_s).tolist()}


@lru_cache(maxsize=256)
def chi2_limit(alpha: float, dof: int) -> float:
    """The χ² test's rejection threshold: P(χ²_dof > limit) = alpha."""
    return float(stats.chi2.isf(alpha, dof))


def _candidate(fit, alpha: float) -> Candidate:
    dof = max(fit.n_obs - fit.n_free, 1)
    limit = chi2_limit(alpha, dof)
    chi2 = float(fit.chi2)
    k = fit.n_free
    res = fit.residuals.ravel().tolist()
    w = max(range(len(res)), key=lambda i: abs(res[i]))  # the first of equals, as np.argmax
    worst = f"{_MEAS[w % 5]} at touch {w // 5} is off by {abs(res[w]):.3g} standard deviations"
    return Candidate(fit.cls, fit.params, fit.pose, np.asarray(fit.t, float), chi2, dof, fit.n_obs,
                     loglik=-0.5 * chi2, bic=chi2 + k * math.log(fit.n_obs),
                     p_value=float(special.chdtrc(dof, chi2)) if chi2 <= 10 * limit else 0.0, consistent=chi2 <= limit,
                     uncertainty=dict(fit.sigma), worst=worst,
                     reason=None if chi2 <= limit else f"chi2 {chi2:.3g} > {limit:.3g} (dof {dof})")


#: with refinement on, a class whose invariant-stage χ² is within this factor of its limit
#: is refined and judged on the refined fit
REFINE_WITHIN = 100.0
#: with refinement on, classes fitted from every start, each fit refined (one start's fit can
#: sit in the wrong basin: the cubic classes' branches and slope roots; the hyperbola's scan
#: far out on an arm against its invariants' and conic's starts near the vertex; the
#: ellipse's scan along the valley of ellipses a short stretch fits)
EVERY_START = ("ellipse", "hyperbola", "cubical_parabola", "semicubical_parabola")


def _best_per_class(cands: list[Candidate]) -> list[Candidate]:
    """One candidate per class (several starts of a cubic class): the consistent one of
    lowest BIC, else the lowest χ²; in first-seen class order."""
    best: dict[str, Candidate] = {}
    for c in cands:
        b = best.get(c.cls)
        if b is None or (c.consistent, -c.bic, -c.chi2) > (b.consistent, -b.bic, -b.chi2):
            best[c.cls] = c
    return list(best.values())


#: a richer class whose own fits reach within this of its consistent limit's χ² is not
#: started again from the limit's fit (each nested start costs a refinement, 0.1-0.3 s CPU)
NESTED_MARGIN = 1.0


def _lowest_chi2(cands: list[Candidate]) -> dict[str, int]:
    """Each class's candidate of lowest χ² (its index; the first of equals)."""
    best: dict[str, int] = {}
    for i, c in enumerate(cands):
        if c.cls not in best or c.chi2 < cands[best[c.cls]].chi2:
            best[c.cls] = i
    return best


#: each class's best refined fit within RESTART_BIC of the best BIC is refined once more
#: from itself, every sample's t projected afresh onto its curve
RESTART_BIC = 15.0
#: a restarted fit that stopped at its evaluation budget (``refine.MAX_NFEV``) having gained
#: more than ``RESTART_GAIN`` in χ² is refined again, up to ``RESTART_ROUNDS`` refinements in all
#: (tools.bench_wide seed 149, ellipse trial 11, thin, at its sharp end: restarted once, the
#: ellipse went 76.8 → 75.5 in its 40 evaluations and the answer was semicubical at 73.4;
#: two rounds more: 74.4, 72.8, the truth's valley 72.5)
RESTART_ROUNDS, RESTART_GAIN = 3, 0.5


def _other_branch(cands: list[Candidate]) -> list[int]:
    """When no semicubical fit is consistent: the semicubical's lowest-χ² refined fit on the branch
    (the sign of its t's) its best fit is not on, if it stopped at its evaluation budget. The solve
    never crosses the cusp (``SemicubicalParabola.keep_branch``), so each branch is a valley of its
    own, and a fit stopped on one while still moving says nothing of it (P-jaw semicubical far out
    on its branch, docs/recognition.md session 29: that branch's best start stopped at χ² 425 at
    its budget and, refined on, went 94, 16, 14.3 on 27 dof; only the other branch's 166 was
    restarted, and the answer was an ellipse at 48)."""
    cls = "semicubical_parabola"
    own = [i for i, c in enumerate(cands) if c.cls == cls and isinstance(c, RefinedCandidate) and math.isfinite(c.chi2)]
    if not own or any(cands[i].consistent for i in own):
        return []
    lowest = min(own, key=lambda i: cands[i].chi2)
    sign = -np.sign(np.asarray(cands[lowest].t, float)[0])
    branch = [i for i in own if np.all(np.sign(np.asarray(cands[i].t, float)) == sign)]
    best = min(branch, key=lambda i: cands[i].chi2, default=None)
    return [best] if best is not None and cands[best].nfev >= MAX_NFEV else []


def _restarted(cands: list[Candidate], request: Request, options: RecognizeOptions) -> list[Candidate]:
    """``cands`` with each class's best refined fit near the best BIC (``RESTART_BIC``)
    refined once more from its own parameters and pose; the new fit is kept where it fits
    better. The solve over shape, pose and every sample's t can stall with samples' t in a
    poor configuration on a flat valley; projected afresh, they let it go on (tools.bench_wide
    seed 11, ellipse trial 0, a short stretch: the ellipse stalled at χ² 53.7 and the answer
    was semicubical at 42.4; restarted, 39.1 in 40 evaluations, the truth's valley 38.1). The
    semicubical's fit on its other branch, where that one stopped at its budget, too (:func:`_other_branch`)."""
    top = min((c.bic for c in cands if math.isfinite(c.bic)), default=math.inf) + RESTART_BIC
    again = [i for i in _lowest_chi2(cands).values() if isinstance(cands[i], RefinedCandidate) and cands[i].bic <= top]
    again += [i for i in _other_branch(cands) if i not in again]
    out = list(cands)
    for i, c in zip(again, refine_candidates([cands[i] for i in again], request, options)):
        if c.chi2 < out[i].chi2:
            out[i] = c
    gained = {i: cands[i].chi2 - out[i].chi2 for i in again}
    for _ in range(RESTART_ROUNDS - 1):  # still crawling: at its budget, and the last round gained
        more = [i for i in again if out[i].nfev >= MAX_NFEV and gained[i] > RESTART_GAIN]
        if not more:
            break
        for i, c in zip(more, refine_candidates([out[i] for i in more], request, options)):
            gained[i] = out[i].chi2 - c.chi2
            if c.chi2 < out[i].chi2:
                out[i] = c
    return out


def _nested_fits(cands: list[Candidate], request: Request, options: RecognizeOptions) -> list[Candidate]:
    """Refined fits of every richer class started next to its limit class's fit
    (recognizer.nested), where its own starts fitted worse than a consistent limit by more
    than ``NESTED_MARGIN``: the richer class contains its limit, so it never fits worse."""
    best = {cls: cands[i] for cls, i in _lowest_chi2(cands).items()}
    starts = []
    for limit, richer in ((lim, r) for lim, rs in NESTED_FROM.items() if lim in best for r in rs):
        if richer in request.classes and best[limit].consistent and \
                (richer not in best or best[richer].chi2 > best[limit].chi2 + NESTED_MARGIN):
            starts += nested_candidates(best[limit], richer)
    fits = refine_candidates(starts, request, options) if starts else []
    return [f for f in fits if math.isfinite(f.chi2)]


#: what placing a closed-form start (``starts.pose_from``) raises on degenerate touches
_PLACING_ERRORS = (ArithmeticError, ValueError, np.linalg.LinAlgError)


def _best_placed(cls: str, placed: list, dof: int, n_obs: int) -> Candidate | None:
    """The best placed of ``placed`` ((``pose_from``'s (θ, x, y, cost), params, t) each) as a
    candidate of ``cls``, or None when none is placed at a finite cost."""
    placed = [q for q in placed if math.isfinite(q[0][3])]
    if not placed:
        return None
    (th, x, y, cost), p, t = min(placed, key=lambda q: q[0][3])
    return Candidate(cls, dict(p), Pose(th, x, y), np.asarray(t, float), cost, dof, n_obs)


def _contact_limit(cls: str, d: Contacts, alpha: float) -> float:
    """The χ² bound a contact-stage fit of ``cls`` to ``d`` is tested against: 5 residuals per
    touch less the class's shape parameters and each touch's t (as ``localize`` counts them)."""
    return chi2_limit(alpha, max(5 * d.n - (N_SHAPE[cls] + d.n), 1))


def _best_starts_refined(d: Contacts, request: Request, options: RecognizeOptions,
                         cands: list[Candidate]) -> list[Candidate]:
    """Noise-free samples that no class fits yet: every class refined from its best placed
    closed-form start (``starts.pose_from``), not from its contact fit. The contact fit
    weighs the estimated κ, κ_s, whose truncation error on noise-free samples exceeds
    their stated deviation, and moves an exact start away (tools.bench_wide --set wide
    seed 9, hyperbola trial 3 far on an arm: the invariants' start exact, its contact fit
    16 % off, whose refinement stopped at χ² 6e13; from the start itself, exact). The
    ellipse and hyperbola also start from the conic through every sample (``_samples_conic``)."""
    dof, n_obs = (cands[0].dof, cands[0].n_obs) if cands else (1, 1)
    out = []
    for cls in request.classes:
        sign = CURVES[cls].kappa_sign
        dom = d.dominant_kappa()
        dd = d.flipped() if sign != 0 and dom != 0 and math.copysign(1.0, dom) != sign else d
        try:
            placed = [(pose_from(cls, p, t, dd), p, t) for p, t in class_starts(cls, dd, True)]
            placed += [(pose_from(cls, p, t, way), p, t) for way, p, t in _samples_conic(cls, d, request)]
        except _PLACING_ERRORS:
            continue
        best = _best_placed(cls, placed, dof, n_obs)
        out += [best] if best is not None else []
    fits = refine_candidates(out, request, options) if out else []
    return [f for f in fits if math.isfinite(f.chi2)]


def _samples_conic(cls: str, d: Contacts, request: Request) -> list[tuple[Contacts, dict, list]]:
    """(contacts in the direction of travel tried, params, t per touch) of the ellipse or
    hyperbola through every sample's position and tangent (``starts.conic_start`` on the
    samples as contacts; each touch's t its contact sample's), in both directions of travel.
    Three contacts far out on an arm lie within rounding of a pair of lines: their conic is
    noise (tools.bench_wide --set wide seed 251, hyperbola trial 7 at t 3.5–5.3: every start
    crawled, refined χ² 7.7e8, unclassified); the 27 noise-free samples give the truth to
    rounding. Only samples-touches (none: no start)."""
    if cls not in ("ellipse", "hyperbola") or not all(isinstance(t, SamplesTouch) for t in request.touches):
        return []
    x, y, phi = (np.concatenate([np.asarray(getattr(t, k), float) for t in request.touches]) for k in ("x", "y", "phi"))
    mid = np.cumsum([0] + [len(t.phi) for t in request.touches[:-1]]) + [len(t.phi) // 2 for t in request.touches]
    zero = np.zeros_like(x)
    out = []
    for way, turn in ((d, 0.0), (d.flipped(), math.pi)):
        samples = Contacts(x, y, phi + turn, zero, zero, np.zeros((x.size, 2, 2)), zero, zero, extent=d.scale)
        out += [(way, p, [t[int(m)] for m in mid]) for p, t in conic_start(cls, samples)]
    return out


def _samples_conic_fit(cands: list[Candidate], d: Contacts, request: Request,
                       options: RecognizeOptions) -> list[Candidate]:
    """The ellipse refined from the conic through every sample's position and tangent
    (``_samples_conic``), in its better placed direction of travel, when no ellipse fit is
    within ``RESTART_BIC`` of the best BIC (those are refined on from themselves,
    ``_restarted``; a better ellipse rival there moved a parabola's suggested touch and lost
    its answer: bench_wide seed 179 parabola trial 6, docs/benchmarks.md session 33). At a thin ellipse's
    sharp end the touches' κ pin the vertex curvature a/b² but not b/a: the contact fits
    (invariants, the conic through three contacts, the scan) sit along that valley where
    the contacts' truncated κ, κ_s put them, and the refinement over every sample crawls
    along it at its evaluation budget (tools.bench_wide --set wide seed 547, ellipse trial 2,
    b/a 0.12: contact fits b/a 0.08–0.09 refined to χ² 84.6 and 103, the answer a
    semicubical at 66.2 while the truth refined from itself fits 62.8; only starts within
    b/a 0.10–0.15 reach it). The 27 samples' positions and tangents, 54 equations for the
    conic's 5 ratios, put it at b/a 0.11 (refined 63.1) without κ or κ_s."""
    cls = "ellipse"
    if not (options.refine and cls in request.classes and d.n >= MIN_TOUCHES[cls]):
        return []
    top = min((c.bic for c in cands if math.isfinite(c.bic)), default=math.inf) + RESTART_BIC
    if any(c.cls == cls and c.bic <= top for c in cands):
        return []
    try:
        placed = [(pose_from(cls, p, t, way), p, t) for way, p, t in _samples_conic(cls, d, request)]
    except _PLACING_ERRORS:
        return []
    start = _best_placed(cls, placed, 1, 1)
    return [] if start is None else [f for f in refine_candidates([start], request, options) if math.isfinite(f.chi2)]


#: scan starts refined directly when every semicubical contact fit puts a touch at its cusp
CLEAR_SCAN_STARTS = 3
#: ... among the scan's starts within this χ² of its best (positions and tangents of the
#: contacts), those farthest from the cusp
CLEAR_SCAN_BAND = 20.0


#: ``_valleys_continued``: the answer class's other fits stopped at their budget within this
#: many valley widths (``CHI2_VALLEY``) above the answer are solved on for one budget, the lowest
#: ``CONTINUE_FITS`` of them still moving outside its valley up to ``CONTINUE_ROUNDS`` budgets in all
CONTINUE_WITHIN, CONTINUE_FITS, CONTINUE_ROUNDS = 4.0, 2, 3


def _valleys_continued(chosen: Candidate, fits: list[Candidate], request: Request,
                       options: RecognizeOptions, d: Contacts) -> list[Candidate]:
    """``fits`` with the answer class's fits outside the answer's own valley
    (``intervals.same_valley``) within ``CONTINUE_WITHIN`` × ``CHI2_VALLEY`` of its χ² solved
    on, each while it still improves: the σ's across the class's valleys
    (``intervals.rival_basins``) count only valleys a fit reached. A refined answer's refined
    fits that stopped at their evaluation budget (``refine.MAX_NFEV``: still moving) are refined
    again: touched on one branch near the cusp, a semicubical answered in its parabola-like
    valley b 11.5 (χ² 51.5, scale-free units) where the truth's valley (b 0.90, χ² 55.7) had
    two fits crawling towards it at 61.4 and 62.3, each at 40 evaluations: b z 24
    (tools.bench_wide seed 5, trial 4, development). A contact-stage answer's contact fits
    are solved on for another iteration budget each round (``localize.fit_continued``; one
    that had converged stops at once): a cubical far on one side answered a 44.5 ± 4.7 mm
    (χ² 14.07) where the truth's valley (a −143.6, c 2.15, χ² 16.32: the truth −174.7 at
    profile χ² 16.38) had two fits started at a ≈ −5e3 mm still crawling at −641, χ² 29.4:
    a z 47 (tools.bench_sigma --kind contacts seed 587, trial 2; z 1.03 now). Every such
    fit is solved on for one budget, and the lowest ``CONTINUE_FITS`` of those still moving
    outside the answer's valley for the rest: a cubical far on one side answered a −30.8
    (χ² 44.72, scale-free units) whose two lowest other fits (46.6, 51.5) slid into its own
    valley, while two at 68.5 and 73.0 (a 397, 406) reach the truth's valley (a 182, χ²
    45.01) in two budgets: a z −132 (tools.bench_sigma --fresh seed 607 trial 1 at 1e-3 mm)."""
    refined = isinstance(chosen, RefinedCandidate)
    top = float(chosen.chi2) + CONTINUE_WITHIN * CHI2_VALLEY
    moving = sorted((i for i, f in enumerate(fits) if f.cls == chosen.cls and isinstance(f, RefinedCandidate) == refined
                     and (not refined or f.nfev >= MAX_NFEV) and float(chosen.chi2) < f.chi2 <= top
                     and not same_valley(chosen, f)), key=lambda i: fits[i].chi2)
    # a contact fit's σ's where it is consistent, as in _recognize
    limit = math.inf if refined else _contact_limit(chosen.cls, d, options.alpha)
    out = list(fits)

    def step(f: Candidate) -> tuple[Candidate, bool]:
        """(f solved on for one more budget, whether it is still moving)"""
        if refined:
            g = refine_candidates([f], request, options)[0]
        else:
            fit = fit_continued(f, d, sigma_below=limit)
            g = f if fit is None else _candidate(fit, options.alpha)
        if not g.chi2 < f.chi2:
            return f, False
        return g, not (refined and g.nfev < MAX_NFEV)

    going = []
    for i in moving:  # one budget each: where a fit goes, not where it stopped, picks the ones to follow
        out[i], on = step(out[i])
        if on and not same_valley(chosen, out[i]):
            going.append(i)
    for i in sorted(going, key=lambda i: out[i].chi2)[:CONTINUE_FITS]:
        for _ in range(CONTINUE_ROUNDS - 1):
            out[i], on = step(out[i])
            if not on:
                break
    return out


def _circle_from_ellipse(cands: list[Candidate], request: Request, options: RecognizeOptions) -> list[Candidate]:
    """A refined circle fit started at the best consistent ellipse (r = √(ab), its centre and
    t's) when that ellipse's own a − b is within the likelihood-ratio test's limit of 0
    (``MODEL_ALPHA``, from its σ_a, σ_b) yet every circle fit lies beyond that limit of the
    ellipse's χ², or there is none: the circle is the ellipse with a = b, so its fit can only
    lose by that much from its own starts' basin, not from the data (X-series seed 61 circle
    18: no circle start, the answer an ellipse b/a 0.997, a − b 0.4 σ from 0)."""
    if not (options.refine and "circle" in request.classes):
        return []
    ell = [c for c in cands if c.cls == "ellipse" and c.consistent]
    if not ell:
        return []
    e = min(ell, key=lambda c: c.chi2)
    limit = chi2_limit(MODEL_ALPHA, N_SHAPE["ellipse"] - N_SHAPE["circle"])
    circle = min((c.chi2 for c in cands if c.cls == "circle"), default=math.inf)
    if circle <= e.chi2 + limit:
        return []
    a, b = float(e.params["a"]), float(e.params["b"])
    sa, sb = e.uncertainty.get("a"), e.uncertainty.get("b")
    var = (sa or 0.0) ** 2 + (sb or 0.0) ** 2 if sa is not None and sb is not None else math.inf
    if not (math.isfinite(var) and (a - b) ** 2 <= limit * var):
        return []
    start = Candidate("circle", {"r": math.sqrt(a * b)}, e.pose, np.asarray(e.t, float), e.chi2, e.dof, e.n_obs)
    return [f for f in refine_candidates([start], request, options) if math.isfinite(f.chi2)]


def _clear_of_cusp_fits(cands: list[Candidate], d: Contacts, request: Request,
                        options: RecognizeOptions) -> list[Candidate]:
    """Refined semicubical fits from its scan's best starts clear of the cusp
    (``starts.semicubical_scan``: every touch at least its reach from the cusp), when the
    semicubical's best fit is inconsistent and some semicubical fit (the best or another) puts
    a touch nearer: the fits of the valley beside the cusp stalled there, and the best may be
    another valley's, clear of the cusp and inconsistent (tools.bench_wide --set wide seed 601,
    semicubical trial 15, far out on a branch: four contact fits at χ² 7.3 with the first touch
    0.035 of arc from the cusp, its roll reaching 0.082, stalled at 2,288–2,681; the best, 1,383,
    clear of it; the semicubical ended at its parabola limit, 80.46, and the answer was
    parabola; from the scan's starts, 67.84, the truth's own 69.35). The contact fit sees one point per
    touch, not how far its samples reach: from a start clear of the cusp it can slide to a
    consistent fit whose cusp lies within a touch's roll, where the refinement piles that
    touch's samples at the cusp and stalls (tools.bench_wide seed 5, semicubical trial 3
    after two suggested touches: every contact fit at χ² 13.5, refined 4.7e4, the answer
    ellipse; from the scan's start clear of the cusp, the truth's 61)."""
    cls = "semicubical_parabola"
    if not (options.refine and cls in request.classes and d.reach > 0):
        return []
    own = [c for c in cands if c.cls == cls]
    best = min(own, key=lambda c: c.chi2, default=None)
    if best is None or best.consistent or all(clear_of_cusp((c.params, list(c.t)), d.reach) for c in own):
        return []
    dom = d.dominant_kappa()
    dd = d.flipped() if dom != 0 and math.copysign(1.0, dom) != CURVES[cls].kappa_sign else d
    placed = []
    for params, t in semicubical_scan(dd):
        th, x, y, cost = pose_from(cls, params, t, dd)
        if math.isfinite(cost):
            placed.append((cost, cusp_clearance((params, t)), Candidate(cls, params, Pose(th, x, y), np.asarray(t, float),
                                                                        cost, own[0].dof, own[0].n_obs)))
    # the contact data cannot tell these apart: the ones farthest from the cusp first
    low = min((p[0] for p in placed), default=math.inf)
    placed = sorted((p for p in placed if p[0] <= low + CLEAR_SCAN_BAND), key=lambda p: -p[1])
    starts = [p[2] for p in placed[:CLEAR_SCAN_STARTS]]
    fits = refine_candidates(starts, request, options) if starts else []
    return [f for f in fits if math.isfinite(f.chi2)]


#: the asymptote starts are also refined when every touch's tangent lies within this (rad) of
#: their mean direction although not within its noise: the turn of a rectangular hyperbola's
#: tangent from its asymptote at t = 1.5 (e^{−3}), half the arm's t below the starts' FAR_T.
#: A touch nearer the vertex (the tangents' noise 1.5 mrad, a turn of 7–10 mrad) leaves the
#: stretch far on its arm for the other starts: tools.bench_wide seeds 11 and 9 (development),
#: hyperbola trials 3 and 11 far on an arm after a suggested touch at t 2.4–2.5 with the
#: others at t 3.7–5.8: no hyperbola start reached the truth's valley (refined: χ² 3e6;
#: the truth's 54), the answer unclassified; from the asymptote starts they reach the truth's valley
FAR_ARM_TURN = math.exp(-3.0)


def _far_arm_fits(cands: list[Candidate], d: Contacts, request: Request,
                  options: RecognizeOptions) -> list[Candidate]:
    """Refined hyperbola fits from its asymptote starts (``starts.hyperbola_asymptote``),
    in both directions of travel, when no hyperbola fit is consistent, or none fits better
    than a consistent limit of it (line, parabola) by ``NESTED_MARGIN`` (it sits at the
    limit), or another consistent class fits better than every hyperbola fit by more than
    ``NESTED_MARGIN`` (its fits left in a valley beside the truth's: tools.bench_wide --set
    wide seed 349, trial 15, far on an arm, the hyperbola at χ² 98.7, 5 below its line
    limit, the answer a cubical at 80.9 while the truth refined from itself fits 79.8),
    and the touches' tangents agree with one direction within their noise (χ² at
    ``options.alpha``: far out on an arm, or nearly straight) or within ``FAR_ARM_TURN``
    (a touch nearer the vertex, such as a suggested one). There every other start places the touches by tangents
    within their noise of the asymptote's, the contact fit of three nearly collinear points
    slides toward the limit a → 0 where the refinement cannot follow, and the κ's that
    orient the data (``Contacts.dominant_kappa``) are noise: the hyperbola bent the wrong
    way fits no better than a line (tools.bench_wide --set wide, hyperbolas far on an arm:
    10 of 20 noisy trials of development seeds 1, 5, 9, 11 and 31 unclassified or another
    class while the truth, refined from itself, passes; seed 1 trial 11 oriented wrong).
    The samples tell both: the asymptote starts are refined directly."""
    cls = "hyperbola"
    if not (options.refine and cls in request.classes and d.n >= MIN_TOUCHES[cls]):
        return []
    own = [c for c in cands if c.cls == cls]
    best = min((c.chi2 for c in own if c.consistent), default=math.inf)
    limits = min((c.chi2 for c in cands if c.consistent and cls in LIMIT_OF.get(c.cls, ())), default=math.inf)
    others = min((c.chi2 for c in cands if c.consistent and c.cls != cls), default=math.inf)
    if best < limits - NESTED_MARGIN and best <= others + NESTED_MARGIN:  # bends beyond its limits, beaten by none
        return []
    dev = np.abs(np.asarray(wrap_angle(d.phi - _circmean(d.phi)), float))
    with np.errstate(divide="ignore", invalid="ignore"):
        turn = (dev / d.sig_phi) ** 2
    if not (float(np.sum(turn)) <= chi2_limit(options.alpha, d.n - 1) or float(np.max(dev)) <= FAR_ARM_TURN):
        return []
    dof, n_obs = (own[0].dof, own[0].n_obs) if own else (cands[0].dof, cands[0].n_obs) if cands else (1, 1)
    starts = []
    for dd in (d, d.flipped()):
        for params, t in hyperbola_asymptote(dd):
            th, x, y, cost = pose_from(cls, params, t, dd)
            if math.isfinite(cost):
                starts.append(Candidate(cls, params, Pose(th, x, y), np.asarray(t, float), cost, dof, n_obs))
    fits = refine_candidates(starts, request, options) if starts else []
    return [f for f in fits if math.isfinite(f.chi2)]


def _circmean(a: np.ndarray) -> float:
    return math.atan2(float(np.sum(np.sin(a))), float(np.sum(np.cos(a))))


def lr_limit(simpler: str, richer: str, consistent: list[Candidate]) -> float:
    """The likelihood-ratio test's threshold for ``richer`` against ``simpler``: the χ²
    quantile for the extra shape parameters at ``MODEL_ALPHA`` shared (Bonferroni) among the
    consistent classes richer than ``simpler`` (``CHOICE_LIMIT_OF``): the answer is the best
    of them, so the simpler class is tested against each, and its false-rejection rate is
    the sum of theirs. A line against five consistent curved classes: 1e-3 / 5 (tools.bench_wide seed
    67, a line segment after two suggested touches: a cubical 18.1 below the line's χ², over
    the single test's 16.3 for 3 parameters, under the shared 19.7)."""
    m = max(sum(1 for c in consistent if c.cls in CHOICE_LIMIT_OF.get(simpler, ())), 1)
    return chi2_limit(MODEL_ALPHA / m, N_SHAPE[richer] - N_SHAPE[simpler])


def choose(consistent: list[Candidate]) -> Candidate:
    """The consistent candidate of lowest BIC, replaced by a simpler class it is a limit of
    (``CHOICE_LIMIT_OF``) while the richer one fails the likelihood-ratio test against it."""
    best = min(consistent, key=lambda c: c.bic)
    while True:
        simpler = [c for c in consistent if best.cls in CHOICE_LIMIT_OF.get(c.cls, ())
                   and 2.0 * (best.loglik - c.loglik) <= lr_limit(c.cls, best.cls, consistent)]
        if not simpler:
            return best
        best = min(simpler, key=lambda c: c.bic)


def also_fits(chosen: Candidate, consistent: list[Candidate]) -> list[dict]:
    """The consistent classes of which the answer is a limit (``LIMIT_OF``: a line of every
    curved class, a circle of the ellipse, a parabola of the conics and cubics), best χ²
    first: each fits the touches within their noise, so the answer is the simplest of them,
    not the only one (a cubical touched within 1e-4 of its size from its inflection, or
    with slope 3e4, a hyperbola far out on an arm: answered line). ``gain``: how much
    lower its χ² is; ``needed``: the likelihood-ratio test's threshold it stayed below
    (``MODEL_ALPHA``; classes that BIC alone compares with the answer: null)."""
    out = []
    for c in sorted(consistent, key=lambda c: c.chi2):
        if c.cls not in LIMIT_OF.get(chosen.cls, ()):
            continue
        tested = c.cls in CHOICE_LIMIT_OF.get(chosen.cls, ())
        out.append({"class": c.cls, "chi2": c.chi2, "gain": chosen.chi2 - c.chi2,
                    "needed": lr_limit(chosen.cls, c.cls, consistent) if tested else None})
    return out


def close_rivals(chosen: Candidate, consistent: list[Candidate]) -> list[Candidate]:
    """The consistent classes, neither a limit of the answer nor the answer a limit of them
    (``LIMIT_OF``), whose BIC is less than ``RIVAL_BIC`` above the answer's (or below it:
    the answer may be a simpler nested class than the lowest BIC), lowest BIC first: the
    touches do not tell them from the answer. A parabola and the cubic families (which BIC
    alone compares) are not rivals: the richer class contains the parabola, so its BIC lies
    ln n_obs less its χ² gain above it whether the parabola is right or not (tools.bench_wide
    seed 101, development: 3.69–4.74 above 16 right parabola answers, 3.74–4.73 above 7
    semicubicals answered parabola); ``also_fits`` names it (docs/recognition.md#close-rivals)."""
    def nested(a: str, b: str) -> bool:
        return a in LIMIT_OF.get(b, ()) or b in LIMIT_OF.get(a, ())
    return sorted((c for c in consistent if c.cls != chosen.cls and not nested(c.cls, chosen.cls)
                   and c.bic - chosen.bic < RIVAL_BIC), key=lambda c: c.bic)


def _rivals_reason(chosen: Candidate, rivals: list[Candidate]) -> str:
    """The close rivals in words: every class, its χ² and BIC, and what settles it."""
    both = [chosen] + rivals
    fits = " and ".join(f"{c.cls} (chi2 {c.chi2:.3g}, BIC {c.bic:.4g})" for c in both)
    gap = max(abs(c.bic - chosen.bic) for c in rivals)
    return (f"close rivals: {fits} fit, BIC {gap:.2g} apart (less than {RIVAL_BIC:g}: odds below 20:1): "
            f"the touches cannot tell them apart; a touch where they differ (next_touch) can")


def _rival_entries(chosen: Candidate, rivals: list[Candidate]) -> list[dict]:
    """``also_fits`` entries of close rivals: as the nested classes', with ``rival_bic``, the
    rival's BIC above the answer's (negative: below it, the answer a simpler nested class)."""
    return [{"class": c.cls, "chi2": c.chi2, "gain": chosen.chi2 - c.chi2, "needed": None,
             "rival_bic": c.bic - chosen.bic} for c in rivals]


def _valleys_note(best: Candidate, walked: Candidate, fits: list[Candidate], unit: Unit) -> str | None:
    """The answer's note when other valleys of its class widened its σ's
    (``intervals.rival_basins``): each valley's parameters (in mm, as the answer's) and χ²
    against the answer's (a valley below it: a fit continued past its budget); None when none did."""
    valleys = other_valleys(walked, fits) if best is not walked else []
    if not valleys:
        return None
    where = "; ".join(", ".join(f"{k} {v * unit.param(r.cls, k):.3g}" for k, v in r.params.items())
                      + f" at chi2 {r.chi2:.3g}" for _, r in valleys)
    return (f"{'another valley' if len(valleys) == 1 else 'other valleys'} of {best.cls} within chi2 "
            f"{CHI2_VALLEY:g} of the answer's {walked.chi2:.3g} ({where}): the stated sigmas and intervals "
            f"reach across {'both' if len(valleys) == 1 else 'them'}")


def _too_few_places(cls: str, places: list[list[int]], n: int) -> str:
    """Why ``cls`` is not tested: fewer places than it needs (touches at one place count once)."""
    if n < MIN_TOUCHES[cls]:
        return f"needs {MIN_TOUCHES[cls]} touches, got {n}"
    return f"needs {MIN_PLACES[cls]} touches at distinct places, got {len(places)}"


def _same_places(places: list[list[int]]) -> str:
    """The touches at one place, for a person: 'touches 0, 1, 2 at one place within their noise'."""
    same = "; ".join("touches " + ", ".join(map(str, g)) for g in places if len(g) > 1)
    return f"{same} at one place within their noise ({len(places)} distinct)" if same else ""


def _unclassified_reason(cands: list[Candidate], skipped: dict, pairs: dict, d: Contacts, untested: dict) -> str:
    if not cands and untested and len(untested) == len(skipped):
        need: dict[str, list[str]] = {}
        for cls, why in untested.items():
            need.setdefault(why, []).append(cls)
        same = _same_places(d.places())
        return ("no class of the scene could be tested (no spare degrees of freedom): " + (same + "; " if same else "")
                + "; ".join(f"{', '.join(cs)}: {why}" for why, cs in need.items()))
    parts = []
    if cands:
        best = min(cands, key=lambda c: c.chi2 / chi2_limit(1e-3, c.dof))
        parts.append(f"closest class {best.cls}: {best.reason}; {best.worst}")
    # the conic invariant across pairs, for a person to see how far from a conic
    good = [i for i, q in enumerate(pairs["condition"]) if q > 1e-3 and math.isfinite(pairs["I_c1"][i])]
    if len(good) >= 2:
        v = np.array([pairs["I_c1"][i] for i in good])
        scale = max(float(np.max(np.abs(v))), 1e-300)
        sig = max(max(pairs["I_c1_sigma"][i] for i in good), EPS_FLOOR * scale)
        parts.append(f"I_c1 over {len(good)} pairs spans {float(v.min()):.4g}..{float(v.max()):.4g} "
                     f"({(float(v.max()) - float(v.min())) / sig:.3g} sigma)")
    same = _same_places(d.places())
    if same:
        parts.append(same)
    for cls, why in skipped.items():
        parts.append(f"{cls} not tested: {why}")
    if untested:  # a class not yet tested may fit: more touches, not "no class fits"
        return f"{NONE_TESTED_FITS} ({', '.join(untested)} need more touches): " + "; ".join(parts)
    return "no class of the scene fits: " + "; ".join(parts) if parts else "no class of the scene fits"


def recognize(request: Request, options: RecognizeOptions | None = None) -> Recognition:
    """Recognize the class, parameters, pose and contacts from a validated request, its
    numerics in units of the touches' spread (recognizer.scale_free), the answer in mm."""
    options = options or options_for(request)
    unit = Unit.of(request)
    with one_blas_thread():  # small matrices: BLAS threads only contend (tactile_common.blas)
        return unit.answer(_recognize(unit.request(request), unit.options(options), unit))


def _recognize(request: Request, options: RecognizeOptions, unit: Unit) -> Recognition:
    t0 = time.perf_counter()
    default_noise = unit.noise(DEFAULT_SAMPLES_NOISE)
    d = contacts_of(request, options, default_noise)
    t_est = time.perf_counter()
    cands: list[Candidate] = []
    skipped: dict[str, str] = {}  # class → why it has no fit: untested, or hopeless from its start
    untested: dict[str, str] = {}
    places = d.places()
    tested = []
    for cls in request.classes:
        if d.n < MIN_TOUCHES[cls] or len(places) < MIN_PLACES[cls]:
            skipped[cls] = untested[cls] = _too_few_places(cls, places, d.n)
            continue
        limit = _contact_limit(cls, d, options.alpha)
        give_up = 1e4 * limit
        if options.refine and cls in EVERY_START:
            fits = fit_class_every_start(cls, d, give_up=give_up, sigma_below=limit)
        else:
            fits = [f for f in (fit_class(cls, d, give_up=give_up, sigma_below=limit),) if f is not None]
        if not fits:
            skipped[cls] = "its invariants give no solution within 1e5 sigma of the touches"
            continue
        tested.append(cls)
        cands += [_candidate(f, options.alpha) for f in fits]
    if not options.refine and not any(c.consistent for c in cands):
        # the contact stage fitted each class from its two best-placed starts; before "no class
        # fits", every start of the classes with several valleys (fast profile, P-series cubical
        # of dev seed 13 object 10: χ² 56.9 on 23 dof from two starts, 11.0 from every start)
        for cls in (c for c in tested if c in EVERY_START):
            limit = _contact_limit(cls, d, options.alpha)
            cands += [_candidate(f, options.alpha)
                      for f in fit_class_every_start(cls, d, give_up=1e4 * limit, sigma_below=limit)]
    if options.refine:
        # every class the invariants solve near consistency is refined (a cubic class from
        # every slope root and branch), and judged on the refined fit: stage 1's χ² on three
        # touches can reject a right class that all samples together fit within their noise
        near = [i for i, c in enumerate(cands) if c.chi2 <= REFINE_WITHIN * chi2_limit(options.alpha, c.dof)]
        for i, c in zip(near, refine_candidates([cands[i] for i in near], request, options)):
            cands[i] = c
        if d.eased and not any(c.consistent for c in cands):
            # exact positions and angles (noise-free samples) and no class consistent: the
            # invariant stage's κ, κ_s from arc lengths of chords can miss their 1e-7 floor,
            # so the refined fit of positions and angles judges every other class it solved
            rest = [i for i in range(len(cands)) if i not in set(near)]
            for i, c in zip(rest, refine_candidates([cands[i] for i in rest], request, options)):
                cands[i] = c
            if not any(c.consistent for c in cands):
                cands += _best_starts_refined(d, request, options, cands)
        cands += _clear_of_cusp_fits(cands, d, request, options)
        cands += _far_arm_fits(cands, d, request, options)
        cands += _samples_conic_fit(cands, d, request, options)
        cands += _nested_fits(cands, request, options)
        cands += _circle_from_ellipse(cands, request, options)
        cands = _restarted(cands, request, options)
        # a class too few distinct places test is not fitted, whichever start reached it (a far
        # arm's or a limit's: P hyperbola 93 of bench_explore --seed 191, three presses of a face
        # at two places, listed the hyperbola untested and in also_fits at once)
        cands = [c for c in cands if c.cls not in untested]
    fits, cands = cands, _best_per_class(cands)
    consistent = [c for c in cands if c.consistent]
    ranking = sorted(cands, key=lambda c: (not c.consistent, c.bic))
    ranked = [Ranked(c.cls, c.consistent, c.chi2, c.dof, c.bic, c.p_value) for c in ranking]
    timing = {"estimate_ms": 1e3 * (t_est - t0)}
    if not consistent:
        pairs = _pair_invariants(unit.contacts(d))
        reason = _unclassified_reason(cands, skipped, pairs, d, untested)
        leader = min(cands, key=lambda c: c.chi2 / chi2_limit(options.alpha, c.dof), default=None)
        nxt = _suggest(request, options, cands, leader, d, timing, default_noise)
        timing["total_ms"] = 1e3 * (time.perf_counter() - t0)
        return Recognition("unclassified", {}, None, [], {k: pairs[k] for k in ("pairs", "I_c1", "I_c2")},
                           {}, reason, ranked, timing, nxt, untested=untested)
    chosen = choose(consistent)
    if not options.refine and chosen.cls in EVERY_START:  # (refined: its fits come from every start)
        first, (chosen, valleys) = chosen, _every_valley(chosen, d, options.alpha)
        fits, cands = fits + valleys, [chosen if c is first else c for c in cands]  # next_touch's leader is in cands
        c = chosen
        ranked = sorted((Ranked(c.cls, c.consistent, c.chi2, c.dof, c.bic, c.p_value) if r.cls == c.cls else r
                         for r in ranked), key=lambda r: (not r.consistent, r.bic))
    rivals = close_rivals(chosen, consistent)
    if rivals and options.close_rivals == "refuse":
        nxt = _suggest(request, options, cands, chosen, d, timing, default_noise)
        timing["total_ms"] = 1e3 * (time.perf_counter() - t0)
        return Recognition("unclassified", {}, None, [], {}, {}, _rivals_reason(chosen, rivals), ranked, timing, nxt,
                           untested=untested, also_fits=[{"class": chosen.cls, "chi2": chosen.chi2, "gain": 0.0,
                                                          "needed": None, "rival_bic": 0.0}]
                           + _rival_entries(chosen, rivals))
    also = also_fits(chosen, consistent) + _rival_entries(chosen, rivals)
    # the answer's σ's where the linearized ones are in doubt, and across its class's other valleys
    walked = profile_uncertainty(chosen) if isinstance(chosen, RefinedCandidate) else \
        profile_uncertainty(profiled(chosen, d), rel_check=CONTACT_REL_SIGMA_CHECK)
    others = _valleys_continued(chosen, [f for f in fits if f is not chosen], request, options, d)
    best = rival_basins(walked, others)
    dh = unit.contacts(d)  # the invariants a person reads, in mm
    pairs = _pair_invariants(dh) if best.cls in ("ellipse", "hyperbola", "parabola") else {}
    nxt = _suggest(request, options, cands, chosen, d, timing, default_noise)
    timing["total_ms"] = 1e3 * (time.perf_counter() - t0)
    said = "; ".join(filter(None, (_rivals_reason(chosen, rivals) if rivals else None,
                                   _valleys_note(best, walked, others, unit)))) or None
    unc = _line_offset_at_hand(best, d, unit) if best.cls == "line" else dict(best.uncertainty)
    return Recognition(best.cls, dict(best.params), best.pose, best.contacts(), _class_invariants(best, dh, pairs),
                       unc, said, ranked, timing, nxt, untested=untested, also_fits=also,
                       interval=interval95(best), cov_pose=_stated_cov_pose(best))


def _stated_cov_pose(best: Candidate) -> np.ndarray | None:
    """A refined curve answer's covariance of (shape parameters, θ, x, y) with its rows and
    columns scaled to the stated σ's (``best.uncertainty``; correlations kept), or None (a line,
    an unrefined fit, a σ not stated or undetermined)."""
    cov = getattr(best, "cov_pose", None)
    if best.cls == "line" or cov is None:
        return None
    keys = list(CURVES[best.cls].param_names) + ["pose_theta", "pose_x", "pose_y"]
    stated = np.array([best.uncertainty.get(k) or np.nan for k in keys], float)
    with np.errstate(invalid="ignore", divide="ignore"):
        scale = stated / np.sqrt(np.diag(cov))
    if cov.shape != (len(keys), len(keys)) or not np.all(np.isfinite(scale)):
        return None
    with np.errstate(all="ignore"):
        scaled = cov * np.outer(scale, scale)
    return scaled if np.all(np.isfinite(scaled)) else None  # an undetermined direction: not tested


def _line_offset_at_hand(best: Candidate, d: Contacts, unit: Unit) -> dict:
    """A line answer's σ's with ``pose_offset`` moved from the foot of the perpendicular from
    the touches' middle O (the fit's) to the foot from the hand origin H (the answer's pose):
    the offset there is d_O − H·n(θ), so σ² = σ_d² + λ² σ_θ² + 2 λ ρ σ_d σ_θ, λ = H·(cos θ, sin θ)
    the distance along the line between the feet and ρ the fit's θ–offset correlation
    (``localize.line_correlation``; without it the stated σ was off by up to 4 % on bench_sigma's
    line segments at 1e4 mm, where λ is comparable to the touches' spread). In units of U."""
    unc = dict(best.uncertainty)
    s_d, s_t = unc.get("pose_offset"), unc.get("pose_theta")
    if s_d is None or s_t is None or unit.identity:
        return unc
    th = float(best.pose.theta)
    lever = -(unit.ox * math.cos(th) + unit.oy * math.sin(th)) / unit.u
    rho = line_correlation(best, d)
    with np.errstate(all="ignore"):
        var = float(s_d) ** 2 + (lever * float(s_t)) ** 2 + 2.0 * lever * rho * float(s_d) * float(s_t)
    unc["pose_offset"] = math.sqrt(max(var, 0.0)) if math.isfinite(var) else math.inf
    return unc


def _every_valley(chosen: Candidate, d: Contacts, alpha: float) -> tuple[Candidate, list[Candidate]]:
    """The contact stage's answer of a class with several valleys (``EVERY_START``), fitted
    from every start of its class (``fit_class_every_start``): (the fit of lowest χ² —
    the chosen fit or a lower valley its two best-placed starts missed —, every fit). The
    class is the one already chosen; its other valleys within ``CHI2_95`` widen the σ's
    (intervals.rival_basins). Noisy contacts far on one side of a cubical: the two best
    placed starts ended at χ² 13.7 where another start reaches 9.4; a semicubical across
    both branches: |b| ≈ 7–15 answered 14–20 σ from the truth whose valley lies Δχ²
    1.4–2.4 higher (tools.bench_sigma seed 1, development)."""
    limit = _contact_limit(chosen.cls, d, alpha)
    valleys = [_candidate(f, alpha) for f in
               fit_class_every_start(chosen.cls, d, give_up=1e4 * limit, sigma_below=limit)]
    lower = [v for v in valleys if v.consistent and v.chi2 < chosen.chi2 and v.uncertainty]
    return (min(lower, key=lambda v: v.chi2) if lower else chosen), valleys


def _roll(request: Request) -> float:
    """The median arc length (mm) of the request's samples-touches: how long a touch is."""
    rolls = [float(np.sum(np.hypot(np.diff(t.x), np.diff(t.y)))) for t in request.touches
             if isinstance(t, SamplesTouch) and len(t.x) > 1]
    return float(np.median(rolls)) if rolls else 0.0


def _suggest(request: Request, options: RecognizeOptions, cands: list[Candidate], leader: Candidate | None,
             d: Contacts, timing: dict, default_noise: NoiseModel = DEFAULT_SAMPLES_NOISE) -> dict | None:
    """recognizer.next_touch for a request with samples-touches (None otherwise)."""
    sizes = [len(t.phi) for t in request.touches if isinstance(t, SamplesTouch)]
    if not sizes or leader is None:
        return None
    t0, c0 = time.perf_counter(), time.process_time()
    noise = options.noise or request.noise or default_noise
    try:
        out = next_touch(cands, leader, d, noise, int(np.median(sizes)), options.reach, _roll(request),
                         options.missed)
    except (np.linalg.LinAlgError, ValueError, ArithmeticError):  # numerics of a degenerate candidate:
        out = None  # no suggestion rather than no answer
    timing["next_touch_ms"] = 1e3 * (time.perf_counter() - t0)
    timing["next_touch_cpu_ms"] = 1e3 * (time.process_time() - c0)
    return out
