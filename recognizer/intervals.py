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
followed as it bends), and the stated σ
becomes the larger of the linearized one and the interval's half-width / 1.96 (the mean of
its two sides: the longer side alone put semicubical coverage at 98.1 %); its
covariance rows and columns are scaled alike (correlations kept). Positive parameters are
profiled in their logarithm, as refine fits them.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from recognizer.curves import CURVES
from recognizer.refine import least_squares

__all__ = ["profile_uncertainty", "REL_SIGMA_CHECK", "CHI2_95"]

REL_SIGMA_CHECK = 0.02
"""linearized σ relative to the parameter (to max(|p|, 1) for the slopes c and b) above which
the profile is computed: below it the valley is quadratic to well within the σ's."""
CHI2_95 = 3.841458820694124
"""χ²₁ quantile at 0.95: the rise of the profile χ² at the ends of the 95 % interval."""
STEP = 0.75
"""linearized σ's per step of the walk along the profile."""
MAX_STEPS = 8
MAX_NFEV = 30
_SLOPES = {("cubical_parabola", "c"), ("semicubical_parabola", "b")}


def _walk(problem, z_hat: np.ndarray, cov_z: np.ndarray, i: int, side: float, chi2_hat: float) -> float | None:
    """Offset of unknown i at the end of its 95 % profile interval on one side: steps of
    ``STEP`` linearized σ's, each fit of the other unknowns started from the previous
    step's (the valley's ridge followed as it bends), until the profile χ² has risen by
    ``CHI2_95``, the end interpolated in √rise; beyond ``MAX_STEPS`` steps the last offset
    reached (a lower bound of the end); None when a fit is not finite."""
    sd = math.sqrt(cov_z[i, i])
    free = np.ones(z_hat.size, bool)
    free[i] = False
    lin = cov_z[:, i] / cov_z[i, i]
    zf = z_hat.copy()
    prev_delta, prev_root = 0.0, 0.0
    for n in range(1, MAX_STEPS + 1):
        delta = side * STEP * sd * n
        start = zf + lin * (delta - (zf[i] - z_hat[i]))
        zf = start.copy()

        def fun(v):
            zf[free] = v
            return problem.residuals(zf)

        def jac(v):
            zf[free] = v
            return problem.jacobian(zf)[:, free]

        res = least_squares(fun, jac, start[free], problem.n_res, MAX_NFEV, 1e-8)
        zf[free] = res.x
        rise = 2.0 * float(res.cost) - chi2_hat
        if not math.isfinite(rise):
            return None
        root = math.sqrt(max(rise, 0.0))
        if root >= math.sqrt(CHI2_95):
            frac = (math.sqrt(CHI2_95) - prev_root) / max(root - prev_root, 1e-12)
            return prev_delta + frac * (delta - prev_delta)
        prev_delta, prev_root = delta, root
    return prev_delta


def profile_uncertainty(cand):
    """``cand`` (a recognizer.refine.RefinedCandidate) with profile-likelihood σ's where its
    linearized ones are in doubt (module docstring); unchanged otherwise."""
    fit = getattr(cand, "fit", None)
    if fit is None:
        return cand
    problem, z_hat, cov_z, perm = fit
    names = CURVES[cand.cls].param_names
    unc = dict(cand.uncertainty)
    scale = np.ones(len(names))
    for j, name in enumerate(names):  # canonical name j is the problem's unknown perm[j]
        i = perm[j]
        p, sd = float(cand.params[name]), float(unc.get(name) or 0.0)
        ref = max(abs(p), 1.0) if (cand.cls, name) in _SLOPES else abs(p)
        if not (sd > REL_SIGMA_CHECK * ref and cov_z[i, i] > 0 and math.isfinite(cov_z[i, i])):
            continue
        with np.errstate(all="ignore"):
            ends = [_walk(problem, z_hat, cov_z, i, side, float(cand.chi2)) for side in (-1.0, 1.0)]
        if None in ends:
            continue
        if problem.names[i] in problem.pos_names:  # log parameter: back to the parameter
            lo, hi = p * (math.exp(ends[0]) - 1.0), p * (math.exp(ends[1]) - 1.0)
        else:
            lo, hi = ends
        sd_new = 0.5 * (abs(lo) + abs(hi)) / 1.96
        if math.isfinite(sd_new) and sd_new > sd:
            scale[j] = sd_new / sd
            unc[name] = sd_new
    if np.all(scale == 1.0):
        return cand
    k = len(names)
    cov = cand.cov * np.outer(scale, scale) if cand.cov.shape == (k, k) else cand.cov
    cov_pose = cand.cov_pose
    if cov_pose is not None:
        full = np.concatenate((scale, np.ones(cov_pose.shape[0] - k)))
        cov_pose = cov_pose * np.outer(full, full)
    return replace(cand, uncertainty=unc, cov=cov, cov_pose=cov_pose)
