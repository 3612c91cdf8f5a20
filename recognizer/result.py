"""Recognition results: the answer (docs/formats.md), the per-class candidate, the options."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from recognizer.curves import CURVES, Pose
from recognizer.touches import MissedPlace, NoiseModel, Reach

__all__ = ["Recognition", "Ranked", "Candidate", "RecognizeOptions", "shape_pose_vector"]


@dataclass
class RecognizeOptions:
    """How to recognize: ``estimator`` for samples-touches (see recognizer.estimate),
    ``refine`` (least squares over every sample, recognizer.refine), ``alpha`` the
    false-rejection rate of each χ² consistency test, ``noise`` the measurement noise
    (None: exact contacts; a default for samples-touches, docs/recognition.md), ``profile`` a name
    of recognizer.profiles.PROFILES or None, ``reach`` the hand-frame disk the robot can
    touch (``next_touch`` stays inside it) or None, ``missed`` the places where touches sent
    were lost (``next_touch`` keeps off the stretch a pad sent there meets), ``close_rivals``
    what to do when a class that is not nested with the answer fits within
    recognizer.classify.RIVAL_BIC:
    ``name`` answers the best class and says it could not tell (the rival in ``also_fits``,
    the ``reason``), ``refuse`` answers ``unclassified`` naming both."""

    estimator: str = "auto"
    refine: bool = False
    alpha: float = 1e-3
    noise: NoiseModel | None = None
    profile: str | None = None
    reach: Reach | None = None
    missed: tuple[MissedPlace, ...] = ()
    close_rivals: str = "name"


@dataclass
class Candidate:
    """One class fitted to every touch: parameters, pose, t per touch, and the fit's
    χ² (weighted squared residuals), degrees of freedom, log-likelihood and BIC."""

    cls: str
    params: dict
    pose: Pose
    t: np.ndarray
    chi2: float
    dof: int
    n_obs: int
    loglik: float = 0.0
    bic: float = math.inf
    p_value: float = 1.0
    consistent: bool = True
    reason: str | None = None
    invariants: dict = field(default_factory=dict)
    uncertainty: dict = field(default_factory=dict)
    worst: str | None = None  # which measurement disagreed most, for the reason
    #: shape parameter → (distance to the 95 % profile-likelihood end below, above) where
    #: recognizer.intervals walked its profile (its two sides may differ)
    profile_sides: dict = field(default_factory=dict)

    def curve(self):
        return CURVES[self.cls](self.params)

    def vector(self) -> np.ndarray:
        """(shape parameters in ``param_names`` order, θ, x, y)."""
        return shape_pose_vector(self.cls, self.params, self.pose)

    def contacts(self) -> list[dict]:
        x, y = self.pose.apply(*self.curve().point(np.asarray(self.t, dtype=float)))
        return [{"t": float(ti), "x": float(xi), "y": float(yi)} for ti, xi, yi in zip(self.t, x, y)]


def shape_pose_vector(cls: str, params: dict, pose: Pose) -> np.ndarray:
    """(shape parameters in ``param_names`` order, θ, x, y): the vector whose covariance a
    refined candidate states (``cov_pose``) and recognizer.next_touch propagates."""
    return np.array([params[n] for n in CURVES[cls].param_names] + [pose.theta, pose.x, pose.y], float)


def _clean(value):
    """JSON-safe copy: floats finite or None (never NaN), arrays as lists."""
    if type(value) is float:  # the common case first
        return value if math.isfinite(value) else None
    if isinstance(value, dict):
        return {str(k): _clean(v) for k, v in value.items()}
    if isinstance(value, (list, tuple, np.ndarray)):
        return [_clean(v) for v in value]
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    if isinstance(value, (int, np.integer)):
        return int(value)
    if isinstance(value, (float, np.floating)):
        return float(value) if math.isfinite(value) else None
    return value


@dataclass(frozen=True)
class Ranked:
    """One class's row of a recognition's ranking: its best fit's χ², degrees of freedom,
    BIC, χ² tail probability, and whether it passed the consistency test."""

    cls: str
    consistent: bool
    chi2: float
    dof: int
    bic: float
    p_value: float

    def to_json(self) -> dict:
        return {"class": self.cls, "consistent": self.consistent, "chi2": self.chi2, "dof": self.dof,
                "bic": self.bic, "p_value": self.p_value}


@dataclass
class Recognition:
    """The recognizer's answer (docs/formats.md, answer); ``ranking`` and ``timing`` are extras."""

    cls: str
    params: dict = field(default_factory=dict)
    pose: Pose | None = None
    contacts: list = field(default_factory=list)
    invariants: dict = field(default_factory=dict)
    uncertainty: dict = field(default_factory=dict)
    reason: str | None = None
    ranking: list[Ranked] = field(default_factory=list)  # every fitted class, best first
    timing: dict = field(default_factory=dict)
    next_touch: dict | None = None  # recognizer.next_touch: where one more touch tells most
    #: classes of the scene not tested, and why (too few touches at distinct places)
    untested: dict = field(default_factory=dict)
    #: consistent richer classes the answer is a limit of (recognizer.classify.also_fits)
    also_fits: list = field(default_factory=list)
    #: shape parameter → [low, high]: its 95 % interval (recognizer.intervals.interval95),
    #: wider on the side where the likelihood falls slower; None where its σ is undetermined
    interval: dict = field(default_factory=dict)
    #: the covariance of (shape parameters in ``param_names`` order, θ, x, y) of a refined
    #: curve answer (``shape_pose_vector``), its diagonal the stated σ's squared (correlations
    #: the refined fit's; not in the JSON answer); None for a line or an unrefined answer
    cov_pose: np.ndarray | None = field(default=None, compare=False)

    def to_json(self) -> dict:
        out = {
            "class": self.cls,
            "params": _clean(self.params) if self.cls != "unclassified" else {},
            "pose": self.pose.to_json() if self.pose is not None else None,
            "contacts": _clean(self.contacts),
            "invariants": _clean(self.invariants),
            "uncertainty": _clean(self.uncertainty),
            "interval": _clean(self.interval),
            "reason": self.reason,
            "next_touch": _clean(self.next_touch),
            "untested": dict(self.untested),
            "also_fits": _clean(self.also_fits),
        }
        out["ranking"] = _clean([r.to_json() for r in self.ranking])
        if self.timing:
            out["timing"] = _clean(self.timing)
        return out
