"""Parameters, contact parameters t (quadrant and branch resolved) and pose, per class.

For one class and the touches' local geometry (x, y, φ, κ, κ_s with covariances,
recognizer.contacts):

1. Direction. The canonical curves have a fixed κ sign when traversed in increasing t
   (ellipse, circle, semicubical +; parabola, hyperbola −). Touches going the other way
   see φ + π and −κ (κ_s unchanged); they are flipped to the canonical direction. A
   reversed cubical parabola is the same curve turned by π, a reversed line the line
   turned by π: no flip for those.
2. Closed-form starts from the invariants and the touches' positions and tangents
   (recognizer.starts), each placed by its pose and scored.
3. The exact contact equations of every touch by Levenberg–Marquardt from the best starts
   (recognizer.solver).
4. Canonical answer: ellipse a ≥ b (else swap, θ += π/2, t −= π/2) and θ in (−π/2, π/2]
   (the ellipse's half-turn symmetry, t += π); circle θ = 0; line (x, y) the foot of the
   perpendicular from the hand origin; every other class θ in (−π, π]; periodic t in
   (−π, π]. Standard deviations of the shape parameters from the Jacobian at the solution.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from recognizer.contacts import Contacts
from recognizer.curves import CURVES, Pose
from recognizer.result import Candidate
from recognizer.solver import ContactModel, svd
from recognizer.starts import pose_from, starts
from tactile_common.angles import wrap_angle

__all__ = ["Fit", "fit_class", "fit_class_every_start", "fit_continued", "N_SHAPE", "scaled_covariance", "profiled",
           "ProfiledCandidate", "line_correlation"]

#: shape parameters + pose degrees of freedom not lost to a symmetry (BIC counts these)
N_SHAPE = {"line": 0 + 2, "circle": 1 + 2, "ellipse": 2 + 3, "parabola": 1 + 3, "hyperbola": 2 + 3,
           "cubical_parabola": 2 + 3, "semicubical_parabola": 2 + 3}
_NUMERIC_ERRORS = (ArithmeticError, ValueError)  # math raises where NumPy gives inf/nan


@dataclass
class Fit:
    cls: str
    params: dict
    pose: Pose
    t: np.ndarray
    chi2: float
    n_obs: int
    n_free: int
    residuals: np.ndarray  # whitened, (n, 5): x, y, φ, κ, κ_s
    sigma: dict
    init_params: dict



def _canonical(cls: str, params: dict, th: float, X: float, Y: float, t: np.ndarray):
    t = np.asarray(t, float).copy()
    if cls == "ellipse" and params["b"] > params["a"]:
        params = {"a": params["b"], "b": params["a"]}
        th += np.pi / 2
        t -= np.pi / 2
    if cls == "ellipse":
        w = float(wrap_angle(th))
        if w > np.pi / 2 or w <= -np.pi / 2:
            w = float(wrap_angle(w - np.pi))
            t += np.pi
        th = w
    elif cls == "circle":
        t += th
        th = 0.0
    elif cls == "line":
        ux, uy = math.cos(th), math.sin(th)
        tau = X * ux + Y * uy
        X, Y = X - tau * ux, Y - tau * uy
        t += tau
    if CURVES[cls].t_period is not None:
        t = wrap_angle(t)
    return params, float(wrap_angle(th)), X, Y, t


#: a start whose position-and-angle χ² per observation exceeds this (~1e5 σ) is not refined
HOPELESS_PER_OBS = 1e10


def fit_class(cls: str, data: Contacts, max_starts: int = 2, give_up: float = math.inf,
              sigma_below: float = math.inf) -> Fit | None:
    """Fit one class to every touch: closed-form starts, then Levenberg–Marquardt (recognizer.solver).

    Returns None when the class has no closed-form start or, on exact data, its best start
    is hopeless (position-and-angle χ² > HOPELESS_PER_OBS per observation; with exact
    positions and angles but uncertain κ, κ_s such a start is first eased,
    ``_eased_start``); ``give_up`` stops the iterations of a class
    whose χ² stays above it. The parameters' standard deviations (``Fit.sigma``) are
    computed only for a χ² ≤ ``sigma_below`` (a class that fails its test reports none)."""
    fits = _fit_starts(cls, data, max_starts, give_up, sigma_below, every=False)
    return fits[0] if fits else None


def fit_class_every_start(cls: str, data: Contacts, give_up: float = math.inf,
                          sigma_below: float = math.inf) -> list[Fit]:
    """One fit per closed-form start (every slope root and branch of the cubic classes,
    the hyperbola's invariants, conic and scan), the 10 best placed, best first: the
    invariants' noisy start can sit on the wrong branch, and a later refinement over every
    sample cannot jump branches, so each is offered to it. (The semicubical's scan gives up
    to 6 starts; with 8 its 2 without a turning point displaced other starts that had
    found the best fit: tools.bench_wide seed 1, semicubical trial 24, 5 touches.)"""
    return _fit_starts(cls, data, 10, give_up, sigma_below, every=True)


def fit_continued(cand: Candidate, data: Contacts, sigma_below: float = math.inf) -> Fit | None:
    """``cand``, a contact-stage fit of ``data``, solved on from where it stopped for another
    of the solver's iteration budgets (a fit that had converged stops at its first step); None
    where its residuals are not finite there. A fit started far out along a curved valley
    crawls down it: a cubical touched far on one side, started at a −4.8e3 mm, stopped at its
    40 iterations at a −641, χ² 29.4, and went on to −264, 17.3 in three more budgets
    (tools.bench_sigma --kind contacts seed 587, trial 2). None too for a fit at a limit of its
    class, a parameter solved in logarithms at 0 (a hyperbola at a = 0, its line limit): there is
    no interior point to solve on from (bench_sigma --fresh seed 607, line trial 2 at 1e-4 mm:
    a math domain error)."""
    d = _oriented(cand.cls, data)
    model = ContactModel(cand.cls, d)
    if not all(cand.params[k] > 0 for k, lg in zip(model.names, model.log) if lg):
        return None
    z = model.pack(cand.params, cand.pose.theta, cand.pose.x, cand.pose.y, np.asarray(cand.t, float))
    z, cost, r, parts = model.solve(z)
    if r is None or not np.isfinite(cost):
        return None
    return _finish(model, cand.cls, d, z, cost, r, parts, dict(cand.params), sigma_below)


def _oriented(cls: str, data: Contacts) -> Contacts:
    """The touches in the class's canonical direction (module docstring, 1)."""
    sign = CURVES[cls].kappa_sign
    if sign != 0:
        dom = data.dominant_kappa()
        if dom != 0 and math.copysign(1.0, dom) != sign:
            return data.flipped()
    return data


def _fit_starts(cls: str, data: Contacts, max_starts: int, give_up: float, sigma_below: float,
                every: bool) -> list[Fit]:
    d = _oriented(cls, data)
    model = ContactModel(cls, d)
    placed = []
    try:
        closed_form = starts(cls, d, every_pair=every)
    except _NUMERIC_ERRORS:  # an overflow NumPy would have turned into a non-finite start
        closed_form = []
    for params, t in closed_form:
        if not all(map(math.isfinite, t)):
            continue
        try:  # cost of position and angle: well-conditioned at any aspect
            th, X, Y, cost = pose_from(cls, params, t, d)
        except _NUMERIC_ERRORS:
            continue
        if cost < math.inf:
            placed.append((cost, (params, th, X, Y, t), params))
    if not placed:
        return []
    placed.sort(key=lambda s: s[0])
    if placed[0][0] > HOPELESS_PER_OBS * 3 * d.n and not d.eased:
        return []
    solved = []
    tried = set()  # a start met before (several pairs giving one frame) solves to the same fit
    for cost0, z0, p0 in placed[:max_starts]:
        if every and cost0 > HOPELESS_PER_OBS * 3 * d.n and not d.eased:
            continue
        z = model.pack(*z0)
        key = z.tobytes()
        if key in tried:
            continue
        tried.add(key)
        if cost0 > give_up and d.eased:
            z = _eased_start(cls, d, z, cost0)
        z, cost, r, parts = model.solve(z, give_up=give_up)
        if np.isfinite(cost):
            solved.append((cost, z, r, parts, p0))
        if not every and cost < give_up * 1e-3:
            break
    solved.sort(key=lambda s: s[0])
    if every:  # starts that converged to the same fit (several pairs give one frame) once
        kept = []
        for sol in solved:
            if not any(np.allclose(sol[1], k[1], rtol=1e-6, atol=1e-9) for k in kept):
                kept.append(sol)
        solved = kept
    return [_finish(model, cls, d, z, cost, r, parts, p0, sigma_below)
            for cost, z, r, parts, p0 in (solved if every else solved[:1])]


def _eased_start(cls: str, d: Contacts, z0: np.ndarray, cost0: float) -> np.ndarray:
    """A start for touches whose positions and angles are far more certain than their κ, κ_s
    (noise-free samples: exact positions, estimated curvatures). A closed-form start made
    from poorly conditioned κ, κ_s can miss the positions by 1e5 of their σ, where the fit
    gives up although the class is right. So first fit with the position and angle
    deviations widened until the start is within about one of them and return that fit's
    solution (the caller iterates from it with the stated deviations)."""
    f = math.sqrt(cost0 / (3 * d.n))
    rows = d.rows()
    wide = Contacts(d.x, d.y, d.phi, d.kappa, d.kappa_s, d.cov,
                    np.array([r[5] * f for r in rows]), np.array([r[6] * f for r in rows]))
    z, cost, _, _ = ContactModel(cls, wide).solve(z0)
    return z if math.isfinite(cost) else z0


#: a column-scaled singular value below this fraction of the largest is zero to rounding:
#: the direction it spans is not determined by the touches (its σ's are infinite)
SINGULAR = 1e-14


def scaled_covariance(J: np.ndarray) -> np.ndarray:
    """(JᵀJ)⁻¹ from the SVD of J with its columns scaled to unit norm: well-conditioned at
    any scale and aspect (an unscaled Jacobian's columns span 1e-10…1e10 at the extremes,
    and dropping its small singular values gave a badly determined direction zero variance,
    σ_a/a = 1e-23). No singular value is dropped: a direction numerically undetermined
    (below ``SINGULAR``, or a zero column) gets infinite variance in every unknown it
    involves, never zero."""
    with np.errstate(over="ignore"):  # a column beyond 1e154 (a diverged fit) is left unscaled
        cn = np.sqrt(np.einsum("ij,ij->j", J, J))
    dead = ~(cn > 0)
    cn[dead | ~np.isfinite(cn)] = 1.0
    _, s, Vt = svd(J / cn)
    m = J.shape[1]
    if s.size < m:  # fewer residuals than unknowns: the missing directions are undetermined
        s = np.concatenate((s, np.zeros(m - s.size)))
        Vt = np.vstack((Vt, _complement(Vt)))
    zero = ~(s > SINGULAR * s[0]) if s.size and s[0] > 0 else np.ones(m, bool)
    inv = np.where(zero, 0.0, 1.0 / np.where(zero, 1.0, s) ** 2)
    cov = (Vt.T * inv) @ Vt
    lost = (np.abs(Vt[zero]) > 1e-8).any(axis=0) | dead  # unknowns an undetermined direction moves
    cov[lost, :] = cov[:, lost] = np.nan
    cov[lost, lost] = np.inf
    return cov / np.outer(cn, cn)


def _complement(Vt: np.ndarray) -> np.ndarray:
    """Orthonormal rows spanning the complement of Vt's rows."""
    _, _, vt = np.linalg.svd(np.eye(Vt.shape[1]) - Vt.T @ Vt)
    return vt[: Vt.shape[1] - Vt.shape[0]]


def _gauge_free(model: ContactModel, z, J: np.ndarray) -> tuple[np.ndarray, tuple[str, ...]]:
    """J's columns in unknowns without the class's gauge freedom, and the names of its pose
    columns: a circle's θ is absorbed by its t's (held); a line's position along itself
    too, so its pose is (θ, offset across the line), θ's column turning the line about its
    foot on the normal (rotation about the pose point moved that foot along the normal by
    the point's distance τ along the line)."""
    o = model.np
    if model.cls == "circle":
        return np.delete(J, o, axis=1), ("x", "y")
    if model.cls != "line":
        return J, ("theta", "x", "y")
    th, X, Y = (float(v) for v in z[o: o + 3])
    c, s = math.cos(th), math.sin(th)
    jn = -s * J[:, o + 1] + c * J[:, o + 2]  # offset along the normal n = (−sin θ, cos θ)
    tau = X * c + Y * s
    out = np.delete(J, o + 2, axis=1)
    out[:, o] = J[:, o] + tau * jn
    out[:, o + 1] = jn
    return out, ("theta", "offset")


def _finish(model: ContactModel, cls: str, d: Contacts, z, cost, r, parts, p0, sigma_below: float) -> Fit:
    """The Fit at the solution z: parameters, σ's (χ² ≤ ``sigma_below``: shape parameters
    and pose, from the column-scaled Jacobian, ``scaled_covariance``), canonical form."""
    params = model.params_of(z)
    th, X, Y = (float(v) for v in z[model.np: model.np + 3])
    t = z[model.np + 3:]
    sigma = {}
    J = model.jac(z, parts) if cost <= sigma_below else None
    if J is not None and np.all(np.isfinite(J)):
        Jg, pose_names = _gauge_free(model, z, J)
        with np.errstate(over="ignore", invalid="ignore"):
            var = np.diag(scaled_covariance(Jg))
        for idx, (name, lg) in enumerate(zip(model.names, model.log)):
            sd = math.sqrt(max(float(var[idx]), 0.0))
            sigma[name] = sd * params[name] if lg else sd
        for idx, name in enumerate(pose_names):
            sigma[f"pose_{name}"] = math.sqrt(max(float(var[model.np + idx]), 0.0))
    if cls == "ellipse" and params["b"] > params["a"] and sigma:  # the axes swap below: so do their σ's
        sigma["a"], sigma["b"] = sigma["b"], sigma["a"]
    params, th, X, Y, t = _canonical(cls, params, th, X, Y, t)
    return Fit(cls, params, Pose(th, X, Y), t, cost, 5 * d.n, N_SHAPE[cls] + d.n, r.reshape(-1, 5), sigma, p0)


@dataclass
class ProfiledCandidate(Candidate):
    """A contact-stage candidate with what recognizer.intervals needs to profile it:
    ``fit`` = (problem, unknowns, their covariance, canonical permutation)."""

    fit: tuple | None = field(default=None, repr=False, compare=False)


class _ContactProblem:
    """The contact fit as recognizer.intervals walks it: residuals and Jacobian of z."""

    def __init__(self, model: ContactModel, n: int):
        self.model, self.n_res = model, 5 * n
        self.names = list(model.names) + ["theta", "x", "y"] + [f"t{i}" for i in range(n)]
        self.pos_names = tuple(nm for nm, lg in zip(model.names, model.log) if lg)

    def residuals(self, z: np.ndarray) -> np.ndarray:
        r, _, _ = self.model.eval(z)
        return np.full(self.n_res, 1e30) if r is None else np.clip(np.array(r), -1e30, 1e30)

    def jacobian(self, z: np.ndarray) -> np.ndarray:
        r, _, parts = self.model.eval(z)
        if r is None:
            return np.zeros((self.n_res, z.size))
        J = self.model.jac(z, parts)
        return np.where(np.isfinite(J), np.clip(J, -1e120, 1e120), 0.0)


def profiled(cand: Candidate, data: Contacts) -> Candidate:
    """``cand``, a contact-stage fit of ``data``, as a ProfiledCandidate that
    recognizer.intervals.profile_uncertainty can walk (its unknowns packed from the
    canonical answer, the same curve and residuals; their covariance ``scaled_covariance``,
    a circle's θ held); ``cand`` itself for a line (no shape parameter) or when the
    residuals are not finite there."""
    if cand.cls == "line" or not cand.params:
        return cand
    model = ContactModel(cand.cls, _oriented(cand.cls, data))
    z = model.pack(cand.params, cand.pose.theta, cand.pose.x, cand.pose.y, np.asarray(cand.t, float))
    r, cost, parts = model.eval(z)
    if r is None:
        return cand
    J = model.jac(z, parts)
    if not np.all(np.isfinite(J)):
        return cand
    o = model.np
    with np.errstate(over="ignore", invalid="ignore"):
        if cand.cls == "circle":  # θ held: its row and column 0
            c = scaled_covariance(np.delete(J, o, axis=1))
            cov = np.zeros((z.size, z.size))
            keep = np.delete(np.arange(z.size), o)
            cov[np.ix_(keep, keep)] = c
        else:
            cov = scaled_covariance(J)
    fields = {f: getattr(cand, f) for f in Candidate.__dataclass_fields__}
    return ProfiledCandidate(**fields, fit=(_ContactProblem(model, data.n), z, cov, list(range(o))))


def line_correlation(cand: Candidate, data: Contacts) -> float:
    """The correlation of a line answer's θ and its offset across itself at the foot of
    the perpendicular from the origin (the touches' middle, in recognizer.scale_free's
    units): from a refined fit's ``cov_pose`` (θ, x, y), else from the contact fit's
    column-scaled covariance (``_gauge_free``'s θ turns the line about that foot); 0 where
    neither is finite. recognizer.classify states the offset's σ at the hand origin's foot
    with it (the θ term's lever is the distance between the two feet)."""
    th = float(cand.pose.theta)
    n = np.array([-math.sin(th), math.cos(th)])
    cov = getattr(cand, "cov_pose", None)
    if cov is not None and np.shape(cov) == (3, 3):
        c_tt, c_td, c_dd = float(cov[0, 0]), float(cov[0, 1:] @ n), float(n @ cov[1:, 1:] @ n)
    else:
        model = ContactModel("line", _oriented("line", data))
        z = model.pack({}, th, float(cand.pose.x), float(cand.pose.y), np.asarray(cand.t, float))
        r, _, parts = model.eval(z)
        if r is None:
            return 0.0
        J = model.jac(z, parts)
        if not np.all(np.isfinite(J)):
            return 0.0
        with np.errstate(over="ignore", invalid="ignore"):
            c = scaled_covariance(_gauge_free(model, z, J)[0])
        o = model.np
        c_tt, c_td, c_dd = float(c[o, o]), float(c[o, o + 1]), float(c[o + 1, o + 1])
    with np.errstate(all="ignore"):
        rho = c_td / math.sqrt(c_tt * c_dd) if c_tt > 0 and c_dd > 0 else 0.0
    return float(np.clip(rho, -1.0, 1.0)) if math.isfinite(rho) else 0.0
