"""An end sample of a roll on the object's end corner, found against the answer's class fit
(docs/exploration.md, "An end sample on the end corner: a deletion test against the class
fit"): each end line (first or last in ψ) of a used roll of degree ≥ ``MIN_DEGREE``, its roll
felt again without it and the answer's class refitted, has the deleted residual

  z = (d_e − ĥ_e) / √(σ_e² + J C Jᵀ),

d_e the end line's d, σ_e its σ (tactile_jaw.envelope.EnvelopeFit.line_sigma), ĥ_e the refitted
curve's support in that line's direction (:func:`tangent_point`), C the refit's stated shape–pose
covariance (recognizer.result.Recognition.cov_pose) and J the gradient of ĥ_e in it (by the
envelope theorem, :func:`support_gradient`): a
standard normal when the line is a tangent of the class's curve, positive on the corner side
(a line turning about the end corner lies past the curve's continuation)."""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any, Callable, Sequence

import numpy as np
from scipy import stats

from recognizer.curves import CURVES, Pose
from recognizer.result import Recognition, shape_pose_vector
from tactile_common.errors import InputError

#: only rolls of at least this envelope degree are tested: a lower-degree roll's order rule
#: (tactile_jaw.envelope) would have taken up a turning end line with a higher degree
MIN_DEGREE = 4
#: the tangent point is sought over the refit's contacts' t range widened this many times
#: that range on each side (1× missed v3 hyperbola 9's, at t 1.37 beyond the contacts' 0.04–0.66)
T_WIDEN = 3.0
#: points sampled on that t range
T_POINTS = 100_001
#: the tangent point nearest the end contact counts within max(this × the roll's chord,
#: ``NEAR_MIN_MM``) of it (a farther local minimum of n·p: a cubical past its inflection, the
#: semicubical's other branch)
NEAR_CHORDS = 2.0
NEAR_MIN_MM = 2.0

Refeel = Callable[[Any, int], Any]


@dataclass(frozen=True)
class EndDeletion:
    """The end sample :func:`corner_end` deletes: its roll's finger and touch number, which end
    (``first`` or ``last`` in ψ), the sample's log reading, its z, the limit and how many ends
    were tested."""

    finger: str
    touch: int
    end: str
    reading: int
    z: float
    limit: float
    tested: int

    def note(self) -> str:
        return (f"{self.finger}: touch {self.touch}'s {self.end} sample (reading {self.reading}) left out: its pad line "
                f"lies z = {self.z:.2f} past the answer's curve refitted without it (limit {self.limit:.2f} over "
                f"{self.tested} tested roll ends): the pad turned about the object's end corner")

    def event(self) -> dict:
        return {"type": "event", "kind": "end_sample_left_out", "finger": self.finger, "touch": self.touch,
                "end": self.end, "reading": self.reading, "z": self.z, "limit": self.limit, "tested": self.tested,
                "message": self.note()}


def tangent_point(cls: str, vec: np.ndarray, t_range: tuple[float, float], normal: np.ndarray,
                  near: tuple[float, float], radius: float) -> tuple[float, float]:
    """(the support n·p of the curve (class ``cls``, (shape parameters, θ, x, y) ``vec``) in the
    direction ``normal``: n·p at the local minimum along t in ``t_range`` nearest the point
    ``near`` within ``radius`` (mm), the t of that minimum), both NaN when there is none."""
    names = CURVES[cls].param_names
    pose = Pose(*vec[len(names):])
    t = np.linspace(t_range[0], t_range[1], T_POINTS)
    x, y = pose.apply(*CURVES[cls](dict(zip(names, vec[:len(names)]))).point(t))
    v = normal[0] * x + normal[1] * y
    i = np.flatnonzero((v[1:-1] < v[:-2]) & (v[1:-1] <= v[2:])) + 1
    dist = np.hypot(x[i] - near[0], y[i] - near[1])
    i, dist = i[dist < radius], dist[dist < radius]
    if not i.size:
        return math.nan, math.nan
    j = i[np.argmin(dist)]
    return float(v[j]), float(t[j])


def support_gradient(cls: str, vec: np.ndarray, t: float, normal: np.ndarray) -> np.ndarray:
    """∂ĥ/∂(shape parameters, θ, x, y) of the support ĥ = n·p(t*) at its tangent point ``t``:
    n·p is stationary in t there, so by the envelope theorem ĥ moves as n·∂p/∂vec with t held
    (the shape parameters' columns ``Curve.param_derivatives`` turned by θ, θ's R'(θ)·p, the
    translation's n). One curve evaluation where central differences of the support took
    two searches of ``T_POINTS`` points per unknown."""
    names = CURVES[cls].param_names
    k = len(names)
    curve = CURVES[cls](dict(zip(names, vec[:k])))
    c, s = math.cos(vec[k]), math.sin(vec[k])
    tt = np.array([t])
    px, py = (float(q[0]) for q in curve.point(tt))
    grad = [normal[0] * (c * float(dx[0]) - s * float(dy[0])) + normal[1] * (s * float(dx[0]) + c * float(dy[0]))
            for dx, dy, _ in curve.param_derivatives(tt)]
    grad += [normal[0] * (-s * px - c * py) + normal[1] * (c * px - s * py), normal[0], normal[1]]
    return np.array(grad, float)


def end_z(refit: Recognition, d: float, sigma: float, normal: np.ndarray, near: tuple[float, float],
          chord: float) -> float:
    """The deleted residual of a pad line (its ``d`` and σ ``sigma``, unit ``normal``, end contact
    ``near``, its roll's ``chord`` mm) against ``refit``, the class fitted without it; NaN
    when the refit states no covariance or has no tangent point there."""
    if refit.cov_pose is None or not refit.contacts:
        return math.nan
    cls = refit.cls
    vec = shape_pose_vector(cls, refit.params, refit.pose)
    ts = np.array([c["t"] for c in refit.contacts], float)
    width = max(float(np.ptp(ts)), 1e-6)
    args = ((float(ts.min()) - T_WIDEN * width, float(ts.max()) + T_WIDEN * width), normal, near,
            max(NEAR_CHORDS * chord, NEAR_MIN_MM))
    h, t = tangent_point(cls, vec, *args)
    if not math.isfinite(h):
        return math.nan
    jac = support_gradient(cls, vec, t, normal)
    var = sigma * sigma + float(jac @ refit.cov_pose @ jac)
    return (d - h) / math.sqrt(var) if math.isfinite(var) and var > 0 else math.nan


def corner_end(recognize_touches: Callable[..., Recognition], touches: Sequence[Any], recognition: Recognition,
               refeel: Refeel, alpha: float) -> tuple[EndDeletion, list] | None:
    """(the end sample to delete, the touches with its roll felt again without it), or None:
    every end of every used roll of degree ≥ ``MIN_DEGREE`` tested (:func:`end_z`, its roll
    felt again by ``refeel(touch, samples)``, tactile_jaw.pipeline.feel, and only the
    answer's class refitted), the one of largest z past the one-sided Bonferroni limit
    norm.isf(``alpha`` / ends tested). An end whose roll does not feel again as usable or
    whose refit is no class is not tested."""
    cls = recognition.cls
    if cls in ("unclassified", "line") or recognition.cov_pose is None:
        return None
    tested = []  # (z, index, end, the refelt touch, the sample)
    for k, felt in enumerate(touches):
        fit = getattr(felt, "fit", None)
        if fit is None or felt.lines is None or fit.contacts.degree < MIN_DEGREE:
            continue
        c = fit.contacts
        chord = float(np.hypot(c.x[-1] - c.x[0], c.y[-1] - c.y[0]))
        ordered = sorted(felt.touch.samples, key=lambda s: s.psi)
        for e, kept, gone in ((0, ordered[1:], ordered[0]), (-1, ordered[:-1], ordered[-1])):
            again = refeel(replace(felt.touch, samples=kept), len(kept))
            if again.problem is not None:
                continue
            try:
                refit = recognize_touches(list(touches[:k]) + [again] + list(touches[k + 1:]), classes=(cls,))
            except InputError:
                continue
            if refit.cls != cls:
                continue
            line = int(c.order[e])
            z = end_z(refit, float(felt.lines.d[line]), float(fit.line_sigma[e]), np.asarray(felt.lines.normal[line]),
                      (float(c.x[e]), float(c.y[e])), chord)
            if math.isfinite(z):
                tested.append((z, k, e, again, gone))
    if not tested:
        return None
    limit = float(stats.norm.isf(alpha / len(tested)))
    z, k, e, again, gone = max(tested, key=lambda row: row[0])
    if z <= limit:
        return None
    felt = touches[k]
    deletion = EndDeletion(felt.touch.finger, felt.touch.touch, "first" if e == 0 else "last", int(gone.reading),
                           float(z), limit, len(tested))
    return deletion, list(touches[:k]) + [again] + list(touches[k + 1:])
