"""How much an exploration touches: :class:`ExploreSettings`, from a recognizer profile,
and the per-sample noise the exploration states in its requests (docs/exploration.md)."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

from hand_driver.units import rad_per_tick
from recognizer.profiles import get_profile

#: a touch cut short (out of reach or contact) is still used with this many samples
#: (with all of them when fewer were planned)
MIN_SAMPLES_PER_TOUCH = 7


def phi_sigma(joints) -> float:
    """Deviation of a pad's angle ψ (and of a sample's tangent angle φ = ψ − π/2): ψ = β + q1 +
    q2, each joint quantized to a tick of its model (uniform, σ = tick/√12), so σ_φ =
    √(Σ_j tick_j²/12) (X-series: √2·(2π/4,096)/√12 = 6.3e-4 rad). The samples' position
    deviations come from each touch's own envelope fit (tactile_jaw.pipeline.stated_noise;
    docs/exploration.md#the-stated-noise)."""
    return math.sqrt(sum(float(rad_per_tick(j.ticks_per_rev)) ** 2 for j in joints) / 12.0)

#: what a run log's header ``settings.noise`` says when the noise was stated from the touches
#: (older logs hold the fixed noise mapping their run stated, and replay with it)
NOISE_FROM_TOUCHES = "per-touch"


@dataclass(frozen=True)
class ExploreSettings:
    """How much to touch: a budget of touches (both fingers together, rejected ones
    included), samples per rolling touch, the roll's total span, the fewest usable
    touches before recognizing, and the recognizer options."""

    touches: int
    samples_per_touch: int
    roll_span_rad: float
    min_touches: int = 3
    profile: str | None = None
    recognize: dict[str, Any] = field(default_factory=dict)  # RecognizeOptions keywords

    @classmethod
    def from_profile(cls, name: str) -> "ExploreSettings":
        """Settings of a recognizer.profiles profile, run as ``tactile bench`` measured it:
        its samples per touch and roll span, a budget of twice its touches plus two, its
        recognizer options. (Short rolls recognize on the jaw because each touch hands the
        recognizer its envelope's κ, κ_s with their covariance: tactile_jaw.pipeline.)"""
        p = get_profile(name, "--profile")
        return cls(touches=2 * p.touches + 2, samples_per_touch=p.samples_per_touch,
                   roll_span_rad=math.radians(p.roll_span_deg), min_touches=p.touches, profile=p.name,
                   recognize=p.options())

    def to_json(self) -> dict[str, Any]:
        return {"touches": self.touches, "samples_per_touch": self.samples_per_touch,
                "roll_span_deg": math.degrees(self.roll_span_rad), "min_touches": self.min_touches,
                "profile": self.profile, "recognize": self.recognize}

    @classmethod
    def from_json(cls, obj: dict[str, Any]) -> "ExploreSettings":
        return cls(touches=int(obj["touches"]), samples_per_touch=int(obj["samples_per_touch"]),
                   roll_span_rad=math.radians(float(obj["roll_span_deg"])), min_touches=int(obj["min_touches"]),
                   profile=obj.get("profile"), recognize=dict(obj.get("recognize") or {}))
