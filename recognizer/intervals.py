"""Profile-likelihood σ's for a refined answer whose linearized σ's cannot be trusted.

recognizer.refine states each parameter's σ from (JᵀJ)⁻¹ at the optimum: right for a model
that is linear in its unknowns over the σ's, too small where the χ² valley bends. Touched
far out on one arm, a hyperbola's a and b trade along a curved ridge (bench_wide seed 1:
hyperbola σ coverage 86.8 %, RMS z 1.49, its out-on-an-arm answers 10–200 % off with
linearized σ's up to 5× too small). So, for the answer only, every shape parameter whose
linearized relative σ is above ``REL_SIGMA_CHECK`` gets its profile χ²: the parameter held
at a value, every other unknown (shape, pose, each sample's t) refitted. The ends of the
95 % profile-likelihood interval (χ² risen by ``CHI2_95``) are found by walking out from
the optimum in steps of ``STEP`` linearized σ's, each fit started from the last (the ridge
followed as it bends), and on to the 3 σ ends (χ² risen by ``CHI2_3SIGMA``); the stated σ
becomes the largest of the linearized one, the 95 % interval's half-width / 1.96 (the mean of
its two sides: the longer side alone put semicubical coverage at 98.1 %) and the σ whose
± 3σ leaves out 0.27 % by the 3 σ ends (``three_sigma``); its covariance rows and columns
are scaled alike (correlations kept). Positive parameters are profiled in their logarithm,
as refine fits them.

Why the 3 σ ends: a profile that rises slower on one side, or flattens beyond its 95 % ends
(Δχ² growing linearly, not quadratically, as a short stretch of an ellipse tends to a
parabola's), has its 3 σ end farther than 3/1.96 of its 95 % end, so its 95 % half-width
stated σ's that its own likelihood put the truth beyond 3 of (tools.bench_sigma contacts,
seed 137 then held out: a semicubical across both branches, b 0.345 ± 0.093 for a truth of
−0.153, z 5.34 where the profile puts the truth at Δχ² 6.2; seeds 103, 113, 137: 13 of
1,716 values beyond 3 σ, 7 with it, 94.8 → 95.0 % within 1.96 σ, median relative σ
0.0233 → 0.0236).

A profile walk stays in the answer's valley. When other fits of the answer's class (its
other starts: every slope root and branch of a cubic class, nested starts) ended in another
valley whose χ² is within ``CHI2_95`` of the answer's, the 95 % likelihood region is their
union, and ``rival_basins`` widens each σ to reach across it: touched on one branch far
from the cusp, a semicubical's |b| ≈ 10–15 (parabola-like) and its true b ≈ −0.5 fit
within Δχ² 1.6–2.1 (bench_wide seed 5, trials 13, 28, 34: the truth 21–64 stated σ away).
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
from scipy.optimize import brentq
from scipy.special import ndtr

from recognizer.curves import CURVES
from recognizer.refine import fit_held
from tactile_common.angles import wrap_angle

__all__ = ["profile_uncertainty", "rival_basins", "other_valleys", "same_valley", "interval95", "three_sigma", "REL_SIGMA_CHECK", "CHI2_95", "CHI2_3SIGMA"]

REL_SIGMA_CHECK = 0.02
"""linearized σ relative to the parameter (to max(|p|, 1) for the slopes c and b) above which
the profile is computed: below it the valley is quadratic to well within the σ's."""
CHI2_95 = 3.841458820694124
"""χ²₁ quantile at 0.95: the rise of the profile χ² at the ends of the 95 % interval."""
CHI2_VALLEY = 9.0
"""χ² rise (3 σ of one parameter) below which another valley of the answer's class weighs in
its σ's (``rival_basins``); beyond it a valley's weight exp(−Δχ²/2) is below 1.1 %."""
STEP = 0.75
"""linearized σ's per step of the walk along the profile."""
MAX_STEPS = 8
MAX_STEPS_3SIGMA = 12
"""steps of the walk on to the 3 σ end (``CHI2_3SIGMA``), 9 linearized σ's."""
MAX_SECANT = 6
"""fits past ``MAX_STEPS_3SIGMA`` steps towards a 3 σ end farther than 9 linearized σ's (a
profile that flattens: secant steps in √rise, each at most 4× as far out as the last)."""
CHI2_3SIGMA = 9.0
"""the rise of the profile χ² at 3 σ (χ²₁ quantile at 0.9973)."""
MAX_NFEV = 30
PROBE_SHARE = 0.1
"""a shape parameter whose linearized relative σ is below the walk's check but above this
share of it gets its profile probed (``_flatter``) and is walked if it flattens."""
PROBE_SIGMAS = 2.0
FLAT_RISE = 0.6
"""the share of a quadratic profile's rise below which a probed profile counts as flattening."""
_SLOPES = {("cubical_parabola", "c"), ("semicubical_parabola", "b")}


def _walk(problem, z_hat: np.ndarray, cov_z: np.ndarray, i: int, side: float, chi2_hat: float):
    """(offset of unknown i at the end of its 95 % profile interval on one side, the largest
    offset of every unknown along the way up to there, the offset where the profile has
    risen by ``CHI2_3SIGMA``): steps of ``STEP`` linearized σ's, each fit of the other
    unknowns started from the previous step's (the valley's ridge followed as it bends),
    until the profile χ² has risen by ``CHI2_95`` and then by ``CHI2_3SIGMA``, each end
    interpolated in √rise; an end not reached within ``MAX_STEPS`` (the 95 % end) or
    ``MAX_STEPS_3SIGMA`` steps is the last offset reached (a lower bound of it); None when
    a fit is not finite before the 95 % end (after it, the 3 σ end is the last offset
    reached). Every point of the walk up to the 95 % end lies in the 95 % likelihood
    region, so the other unknowns' offsets there are within their own profile intervals:
    they bound those from below."""
    sd = math.sqrt(cov_z[i, i])
    free = np.ones(z_hat.size, bool)
    free[i] = False
    lin = np.nan_to_num(cov_z[:, i] / cov_z[i, i], nan=0.0, posinf=0.0, neginf=0.0)
    zf = z_hat.copy()
    prev_delta, prev_root = 0.0, 0.0
    far = np.zeros(z_hat.size)
    prev_z = z_hat.copy()
    end95 = None
    n, slope = 0, 0.0
    while n < MAX_STEPS_3SIGMA + MAX_SECANT:
        n += 1
        if end95 is None and n > MAX_STEPS:
            end95 = (prev_delta, far)
        if n <= MAX_STEPS_3SIGMA:
            delta = side * STEP * sd * n
        else:  # past the steps, still below the 3 σ end: a secant step in √rise, at most 4× as far out
            reach = (3.0 - prev_root) / slope if slope > 0.0 else math.inf
            delta = side * min(abs(prev_delta) + max(reach, STEP * sd), 4.0 * abs(prev_delta))
        zf, rise = _fit_at(problem, z_hat, zf, lin, free, i, delta, chi2_hat)
        if not math.isfinite(rise):
            return None if end95 is None else (*end95, prev_delta)
        root = math.sqrt(max(rise, 0.0))
        slope = (root - prev_root) / max(abs(delta - prev_delta), 1e-300)
        if end95 is None and root >= math.sqrt(CHI2_95):
            frac = (math.sqrt(CHI2_95) - prev_root) / max(root - prev_root, 1e-12)
            far = np.maximum(far, np.abs(prev_z + frac * (zf - prev_z) - z_hat))
            end95 = (prev_delta + frac * (delta - prev_delta), far)
        if root >= math.sqrt(CHI2_3SIGMA):
            frac = (math.sqrt(CHI2_3SIGMA) - prev_root) / max(root - prev_root, 1e-12)
            return (*end95, prev_delta + frac * (delta - prev_delta))
        if end95 is None:
            far = np.maximum(far, np.abs(zf - z_hat))
        prev_delta, prev_root, prev_z = delta, root, zf.copy()
    return (*(end95 if end95 is not None else (prev_delta, far)), prev_delta)


def _fit_at(problem, z_hat: np.ndarray, zf: np.ndarray, lin: np.ndarray, free: np.ndarray, i: int, delta: float,
            chi2_hat: float):
    """(every unknown, profile χ² rise) with unknown i held at ``delta`` from the answer, the
    others refitted from ``zf`` moved along their linearized regression on unknown i."""
    zf, res = fit_held(problem, zf + lin * (delta - (zf[i] - z_hat[i])), free, MAX_NFEV, 1e-8)
    return zf, 2.0 * float(res.cost) - chi2_hat


def profile_uncertainty(cand, rel_check: float = REL_SIGMA_CHECK):
    """``cand`` (a recognizer.refine.RefinedCandidate, or a contact-stage candidate that
    carries its problem: recognizer.localize.profiled) with profile-likelihood σ's where
    its linearized ones are in doubt (relative σ above ``rel_check``; module docstring);
    unchanged otherwise. A parameter
    walked gets the larger of the half-width of its 95 % interval / 1.96 and
    ``three_sigma`` of its 3 σ ends; every other shape parameter at
    least the mean over the walk's two sides of the farthest it moved along them / 1.96
    (near a cubical's inflection a poorly determined a drags c along a bending valley: c
    off by 4.5 linearized σ's with the truth's χ² as low as the answer's)."""
    fit = getattr(cand, "fit", None)
    if fit is None:
        return cand
    problem, z_hat, cov_z, perm = fit
    names = CURVES[cand.cls].param_names
    unc = dict(cand.uncertainty)
    sides = dict(cand.profile_sides)
    scale = np.ones(len(names))
    dragged = np.zeros(z_hat.size)
    for j, name in enumerate(names):  # canonical name j is the problem's unknown perm[j]
        i = perm[j]
        p, sd = float(cand.params[name]), float(unc.get(name) or 0.0)
        ref = max(abs(p), 1.0) if (cand.cls, name) in _SLOPES else abs(p)
        if not (cov_z[i, i] > 0 and math.isfinite(cov_z[i, i]) and sd > PROBE_SHARE * rel_check * ref):
            continue
        if not sd > rel_check * ref and not _flatter(problem, z_hat, cov_z, i, float(cand.chi2)):
            continue
        with np.errstate(all="ignore"):
            walks = [_walk(problem, z_hat, cov_z, i, side, float(cand.chi2)) for side in (-1.0, 1.0)]
        if None in walks:
            continue
        dragged = np.maximum(dragged, 0.5 * (walks[0][1] + walks[1][1]))
        lo, hi = (_in_parameter(problem, i, p, w[0]) for w in walks)
        sides[name] = (lo, hi)
        sd_new = max(0.5 * (lo + hi) / 1.96, three_sigma(*(_in_parameter(problem, i, p, w[2]) for w in walks)))
        if math.isinf(sd_new):
            unc[name] = math.inf  # undetermined: stated ∞ (null), its covariance left as linearized
        elif math.isfinite(sd_new) and sd_new > sd:
            scale[j] = sd_new / sd
            unc[name] = sd_new
    for j, name in enumerate(names):  # how far each parameter moved along the walks
        i = perm[j]
        p, sd = float(cand.params[name]), float(unc.get(name) or 0.0)
        with np.errstate(over="ignore"):
            off = abs(p) * float(np.expm1(dragged[i])) if problem.names[i] in problem.pos_names else float(dragged[i])
        need = off / 1.96
        if math.isinf(need):
            unc[name] = math.inf
        elif math.isfinite(need) and sd > 0 and need > sd:
            scale[j] *= need / sd
            unc[name] = need
    return _widened(replace(cand, profile_sides=sides), unc, scale)


def _flatter(problem, z_hat: np.ndarray, cov_z: np.ndarray, i: int, chi2_hat: float) -> bool:
    """Whether unknown i's profile has risen by less than ``FLAT_RISE`` of a quadratic's
    ``PROBE_SIGMAS``² at ``PROBE_SIGMAS`` linearized σ's on either side (one fit a side): its
    valley flattens within its linearized σ's, so they are too small, whatever their size."""
    sd = math.sqrt(cov_z[i, i])
    free = np.ones(z_hat.size, bool)
    free[i] = False
    lin = np.nan_to_num(cov_z[:, i] / cov_z[i, i], nan=0.0, posinf=0.0, neginf=0.0)
    with np.errstate(all="ignore"):
        for side in (-1.0, 1.0):
            _, rise = _fit_at(problem, z_hat, z_hat.copy(), lin, free, i, side * PROBE_SIGMAS * sd, chi2_hat)
            if rise < FLAT_RISE * PROBE_SIGMAS ** 2:
                return True
    return False


def _in_parameter(problem, i: int, p: float, end: float) -> float:
    """|offset| of the parameter p at a walk's end (``end`` in the problem's unknown: a log
    parameter's back to the parameter)."""
    if problem.names[i] in problem.pos_names:
        with np.errstate(over="ignore"):  # a walk e^700 along a log parameter: undetermined
            return abs(p * float(np.expm1(end)))
    return abs(end)


def three_sigma(lo: float, hi: float) -> float:
    """The σ whose ± 3σ leaves out what a Gaussian does (2 Φ̄(3) = 0.27 %) when each side
    of the profile is Gaussian with its own σ, its 3 σ end at Δχ² ``CHI2_3SIGMA`` (``lo``,
    ``hi`` its distances from the answer): Φ̄(3σ/s_lo) + Φ̄(3σ/s_hi) = 2 Φ̄(3), s = end / 3.
    Equal sides give their own σ; unequal ones a σ between their mean and the longer, near
    the longer as the sides part (the short side's tail then holds nearly nothing)."""
    s_lo, s_hi = sorted((lo / 3.0, hi / 3.0))
    if not s_hi > 0.0 or not math.isfinite(s_hi):
        return s_hi
    target = 2.0 * float(ndtr(-3.0))

    def left_out(sd: float) -> float:  # falls as sd grows
        return float(ndtr(-3.0 * sd / s_hi)) + (float(ndtr(-3.0 * sd / s_lo)) if s_lo > 0.0 else 0.0) - target

    return s_hi if left_out(s_hi) >= 0.0 else brentq(left_out, s_lo, s_hi, xtol=1e-9 * s_hi)


def interval95(cand) -> dict:
    """Each shape parameter's 95 % interval [low, high] (None where its σ is not finite):
    p ± 1.96 σ (the stated σ, every widening included), and on the side where its profile
    reached farther (``profile_sides``: the walk's ends at Δχ² ``CHI2_95``) farther by half
    the difference of the two sides — that side's end where σ is the profile's mean
    half-width / 1.96. One σ per parameter states a symmetric interval; a profile that
    rises slower on one side puts the truth beyond 3 σ there as often as beyond 2.5 σ
    (tools.bench_sigma seed 113, contacts, a semicubical across both branches: b 1.10 ±
    0.10 from the 95 % half-width for a truth of 1.46, z 3.58 where the profile puts it at
    Δχ² 6.3; ± 0.148 with ``three_sigma``, interval [0.81, 1.45]). Never narrower than
    p ± 1.96 σ."""
    out = {}
    for name in CURVES[cand.cls].param_names:
        p, sd = float(cand.params[name]), cand.uncertainty.get(name)
        if sd is None or not math.isfinite(float(sd)) or not math.isfinite(p):
            out[name] = None
            continue
        lo_side, hi_side = cand.profile_sides.get(name, (0.0, 0.0))
        skew = 0.5 * (hi_side - lo_side) if math.isfinite(hi_side - lo_side) else 0.0
        half = 1.96 * float(sd)
        out[name] = [p - half - max(-skew, 0.0), p + half + max(skew, 0.0)]
    return out


#: the turn that maps a class's canonical curve onto itself (its pose θ is defined modulo it)
_HALF_TURN = ("line", "ellipse", "cubical_parabola")
#: the uncertainty keys of a pose held as the Pose's own θ, x, y (a line states an offset
#: instead, which no rival of a line has: it is fitted from one start)
_POSE_KEYS = ("pose_theta", "pose_x", "pose_y")


def _offset(cand, rival, key: str) -> float:
    """|rival − answer| in one uncertainty key; θ across the class's turn symmetry."""
    if key.startswith("pose_"):
        a, b = getattr(cand.pose, key[5:]), getattr(rival.pose, key[5:])
        if key == "pose_theta":
            period = math.pi if cand.cls in _HALF_TURN else 2.0 * math.pi
            return abs(wrap_angle((b - a) * 2.0 * math.pi / period)) * period / (2.0 * math.pi)
        return abs(b - a)
    return abs(float(rival.params[key]) - float(cand.params[key]))


def same_valley(cand, rival) -> bool:
    """Whether ``rival`` is ``cand``'s own valley again (another start that ended there):
    every shape and pose value within the larger of their two σ's."""
    for key, sd in cand.uncertainty.items():
        if key in CURVES[cand.cls].param_names or key in _POSE_KEYS:
            tol = max(float(sd or 0.0), float(rival.uncertainty.get(key) or 0.0))
            if not _offset(cand, rival, key) <= tol:
                return False
    return True


def other_valleys(cand, rivals) -> list:
    """(χ² rise, fit) of each other valley of ``cand``'s class below ``CHI2_VALLEY`` above its
    χ², each valley once; a valley below the answer's χ² (a fit continued past the budget the
    answer was chosen at) rises by 0. Only fits of the same observations (``n_obs``): a
    contact-stage fit left unrefined beside a refined answer has its χ² on other data."""
    out: list = []
    for r in sorted(rivals, key=lambda r: float(r.chi2)):
        rise = float(r.chi2) - float(cand.chi2)
        if r.cls != cand.cls or r.n_obs != cand.n_obs or not rise < CHI2_VALLEY or not r.params or not r.uncertainty:
            continue
        if same_valley(cand, r) or any(same_valley(v, r) for _, v in out):
            continue
        out.append((max(rise, 0.0), r))
    return out


def rival_basins(cand, rivals):
    """``cand`` with its σ's widened over the other valleys of its class (module
    docstring), the larger of two widths per value:

    - the 95 % region: in rival k's valley the profile χ² is about χ²_k + ((p − p_k)/σ_k)²,
      so a valley within ``CHI2_95`` of the answer reaches p_k ± σ_k √(CHI2_95 − Δχ²_k), and
      the σ is at least the distance to that far end / 1.96;
    - the valleys' mixture: each valley weighted by its relative likelihood
      w_k = exp(−Δχ²_k / 2) (the answer's own weight 1; equal parameter counts, so these are
      Akaike weights), the σ at least √(Σ w_k (σ_k² + (p_k − p̂)²) / Σ w_k) about the
      answer. Without it a valley just past ``CHI2_95`` counted for nothing: touched far
      out on one branch, a semicubical answered b −8.5 ± 0.25 where the truth's valley
      (b 0.26 refined, truth 0.42) lay Δχ² 4.6 higher (tools.bench_wide seed 89, trial 14:
      z 39 and −35);
    - each valley at most √Δχ²_k σ's away (beyond ``CHI2_95``; within it the far end rules):
      the profile χ² rises by Δχ²_k there, as it rises by z² at z σ's of a Gaussian. The
      mixture's weight alone left a valley at Δχ² 6 at z 4.6 (tools.bench_sigma seed 71,
      cubical far on one side, trial 29: the truth in that valley; z −2.62 now);
    - a valley below the answer (a fit continued past its budget, classify's
      ``_valleys_continued``) counts as one at the answer's level (Δχ² 0): the answer is
      kept, and its σ's reach across both. Counted for nothing before: a cubical far on one
      side answered a 27.9 ± 5.4 (truth −132.2, z 29.9) where the truth's valley fitted
      Δχ² 0.18 lower (tools.bench_sigma seed 509, trial 1 at 1 mm; a ± 84.7, z 1.89 now)."""
    unc = dict(cand.uncertainty)
    names = CURVES[cand.cls].param_names
    scale = {key: 1.0 for key in unc}
    near = [(float(r.chi2) - float(cand.chi2), r) for r in rivals
            if r.cls == cand.cls and r.n_obs == cand.n_obs and r.params and float(r.chi2) - float(cand.chi2) < CHI2_95]
    valleys = other_valleys(cand, rivals)  # the mixture: each other valley once
    weights = [math.exp(-0.5 * rise) for rise, _ in valleys]
    total = 1.0 + sum(weights)
    for key, sd in cand.uncertainty.items():
        if not (key in names or key in _POSE_KEYS):
            continue
        sd = float(sd or 0.0)
        need = 0.0
        for rise, r in near:  # every fit within CHI2_95: its far end
            sd_r = float(r.uncertainty.get(key) or 0.0)
            need = max(need, (_offset(cand, r, key) + math.sqrt(CHI2_95 - max(rise, 0.0)) * sd_r) / math.sqrt(CHI2_95))
        var = sd * sd
        for (rise, r), w in zip(valleys, weights):
            sd_r = float(r.uncertainty.get(key) or 0.0)
            var += w * (sd_r * sd_r + _offset(cand, r, key) ** 2)
            need = max(need, _offset(cand, r, key) / math.sqrt(max(rise, CHI2_95)))  # its z at most √Δχ²
        need = max(need, math.sqrt(var / total))
        if math.isfinite(need) and need > float(unc[key] or 0.0) * (1.0 + 1e-12):
            unc[key] = need
            scale[key] = need / sd if sd > 0 else 1.0  # no covariance to scale
    return _widened(cand, unc, np.array([scale.get(n, 1.0) for n in names]),
                    np.array([scale.get(k, 1.0) for k in _POSE_KEYS]))


def _widened(cand, unc: dict, scale: np.ndarray, pose_scale: np.ndarray | None = None):
    """``cand`` stating σ's ``unc``: covariance rows and columns scaled alike (shape
    parameters by ``scale``, θ, x, y by ``pose_scale``; correlations kept)."""
    pose_scale = np.ones(3) if pose_scale is None else pose_scale
    if np.all(scale == 1.0) and np.all(pose_scale == 1.0):
        return cand
    k = len(scale)
    cov = getattr(cand, "cov", None)
    # a σ widened past 1e154 times its linearized one (a walk along a log parameter that found
    # no end) overflows its variance to ∞: undetermined, as stated; no warning on the user's stderr
    # (tools.bench_sigma seed 1 --fresh, a hyperbola far on an arm at 1 mm printed one)
    with np.errstate(over="ignore", invalid="ignore"):
        if cov is not None and cov.shape == (k, k):
            cov = cov * np.outer(scale, scale)
        cov_pose = getattr(cand, "cov_pose", None)
        if cov_pose is not None:
            full = np.concatenate((scale, pose_scale if cov_pose.shape[0] == k + 3 else np.ones(cov_pose.shape[0] - k)))
            cov_pose = cov_pose * np.outer(full, full)
    fields = {"uncertainty": unc}
    if cov is not None:
        fields.update(cov=cov, cov_pose=cov_pose)
    return replace(cand, **fields)
