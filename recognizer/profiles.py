"""Speed/accuracy profiles and the robot-time model they are compared with.

A profile says how much to touch and how hard to compute:

- ``touches``: touches per exploration (contacts on the boundary);
- ``samples_per_touch``: samples of one local rolling move (the contact is the middle one);
- ``roll_span_deg``: total pad rotation of one rolling move; the samples are
  ``roll_span / (samples − 1)`` apart in tangent angle (on a boundary of radius of
  curvature ρ that is ``ρ · roll_span/(samples − 1)`` mm of arc);
- ``estimator``: recognizer.estimate method for κ, κ_s;
- ``refine``: least squares over every sample after the invariants (recognizer.refine);
- ``alpha``: false-rejection rate of each χ² consistency test;
- ``decisive_rel_sigma``: an exploration answers only once every shape parameter's standard
  deviation is at most this fraction of its magnitude (tactile_jaw.decide.imprecision);
- ``target_rel_sigma``: a decisive exploration still touches on, within its touch budget,
  while a shape parameter's standard deviation exceeds this fraction of its magnitude, and
  answers at ``decisive_rel_sigma`` once no touch is left (tactile_jaw.explore).

The numbers come from ``tactile bench`` (docs/bench/bench.md): see docs/estimation.md
("Profiles") for which to pick.

Robot time (:class:`TimeModel`, :func:`robot_time_s`): per touch a guarded approach and a
back-off, a transfer to the next touch, and one small guarded rolling move per sample;
every move pays a settle time. Defaults: finger joints at profile velocity 0.5 rev/s
(3.14 rad/s), guarded pad speed 20 mm/s, free pad speed 100 mm/s, approach 10 mm,
back-off 10 mm, transfer 30 mm, per-sample re-approach 0.5 mm in and out, settle 50 ms
per move, 10 ms to read the joints.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Mapping

from recognizer.estimate import METHODS
from tactile_common.errors import InputError


@dataclass(frozen=True)
class Profile:
    """One speed/accuracy trade (see module docstring)."""

    name: str
    touches: int
    samples_per_touch: int
    roll_span_deg: float
    estimator: str
    refine: bool
    alpha: float = 1e-3
    decisive_rel_sigma: float = 0.02
    target_rel_sigma: float = 0.01

    def __post_init__(self) -> None:
        where = f"profile {self.name!r}"
        if self.touches < 2:
            raise InputError(f"{where}: touches must be >= 2, got {self.touches}")
        if self.samples_per_touch < 3:
            raise InputError(f"{where}: samples_per_touch must be >= 3, got {self.samples_per_touch}")
        if not 0.0 < self.roll_span_deg <= 90.0:
            raise InputError(f"{where}: roll_span_deg must be in (0, 90], got {self.roll_span_deg}")
        if self.estimator not in METHODS:
            raise InputError(f"{where}: estimator must be one of {', '.join(METHODS)}, got {self.estimator!r}")
        if not 0.0 < self.alpha < 0.5:
            raise InputError(f"{where}: alpha must be in (0, 0.5), got {self.alpha}")
        if not 0.0 < self.decisive_rel_sigma <= 0.5:
            raise InputError(f"{where}: decisive_rel_sigma must be in (0, 0.5], got {self.decisive_rel_sigma}")
        if not 0.0 < self.target_rel_sigma <= self.decisive_rel_sigma:
            raise InputError(f"{where}: target_rel_sigma must be in (0, decisive_rel_sigma = "
                             f"{self.decisive_rel_sigma}], got {self.target_rel_sigma}")

    @property
    def step_rad(self) -> float:
        """Pad rotation between two samples."""
        return math.radians(self.roll_span_deg) / (self.samples_per_touch - 1)

    def spacing(self, radius_mm: float) -> float:
        """Arc length between samples on a boundary of radius of curvature ``radius_mm``."""
        return self.step_rad * radius_mm

    def options(self) -> dict:
        """The recognizer options this profile sets (RecognizeOptions keywords)."""
        return {"estimator": self.estimator, "refine": self.refine, "alpha": self.alpha, "profile": self.name}

    def to_json(self) -> dict:
        return {"name": self.name, "touches": self.touches, "samples_per_touch": self.samples_per_touch,
                "roll_span_deg": self.roll_span_deg, "estimator": self.estimator, "refine": self.refine,
                "alpha": self.alpha}


@dataclass(frozen=True)
class TimeModel:
    """Robot-time model of an exploration (see module docstring); speeds in rad/s, mm/s."""

    joint_speed: float = 0.5 * 2 * math.pi
    guarded_speed: float = 20.0
    free_speed: float = 100.0
    approach_mm: float = 10.0
    backoff_mm: float = 10.0
    transfer_mm: float = 30.0
    sample_reapproach_mm: float = 0.5
    settle_s: float = 0.05
    read_s: float = 0.01

    def touch_s(self, samples: int, roll_span_rad: float) -> float:
        """One touch: approach, rolling samples, back-off, transfer."""
        fixed = (self.approach_mm / self.guarded_speed + self.backoff_mm / self.free_speed
                 + self.transfer_mm / self.free_speed + 3 * self.settle_s)
        step = roll_span_rad / max(samples - 1, 1)
        per_sample = (step / self.joint_speed + 2 * self.sample_reapproach_mm / self.guarded_speed
                      + self.settle_s + self.read_s)
        return fixed + samples * per_sample


DEFAULT_TIME_MODEL = TimeModel()


def robot_time_s(touches: int, samples: int, roll_span_deg: float, model: TimeModel = DEFAULT_TIME_MODEL) -> float:
    """Modelled robot time (s) of an exploration."""
    return touches * model.touch_s(samples, math.radians(roll_span_deg))


PROFILES: dict[str, Profile] = {
    p.name: p
    for p in (
        Profile("fast", touches=3, samples_per_touch=5, roll_span_deg=12.0, estimator="auto", refine=False,
                decisive_rel_sigma=0.05, target_rel_sigma=0.05),
        Profile("balanced", touches=3, samples_per_touch=9, roll_span_deg=18.0, estimator="auto", refine=True),
        Profile("accurate", touches=5, samples_per_touch=15, roll_span_deg=24.0, estimator="auto", refine=True),
    )
}
DEFAULT_PROFILE = "balanced"


def get_profile(name: str, where: str = "profile") -> Profile:
    """The named profile, or a one-line InputError naming the allowed ones."""
    if name not in PROFILES:
        raise InputError(f"{where}: unknown profile {name!r}; allowed: {', '.join(PROFILES)}")
    return PROFILES[name]


def resolve_options(options: Mapping[str, Any] | None = None, scene: Any = None, default: str | None = None) -> dict:
    """RecognizeOptions keywords for a request: its ``options.profile`` (else the scene's
    ``profile``, else ``default``) sets estimator, refine and alpha; keys given explicitly
    in ``options`` override the profile's. Without any profile the options pass through
    unchanged."""
    options = dict(options or {})
    name = options.get("profile") or getattr(scene, "profile", None) or default
    if name is None:
        return options
    where = "options.profile" if options.get("profile") else "scene profile" if getattr(scene, "profile", None) else "profile"
    out = get_profile(name, where).options()
    out.update({k: v for k, v in options.items() if k != "profile"})
    return out
