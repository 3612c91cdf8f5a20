"""What the run before a move felt of the same object (``tactile explore --moved-as``).

A run after a move of the object (tactile_jaw.explore's ``moved_for``) explores the same
object in another pose. Curvature is the boundary's own, whatever its pose (paper, eq. 1: κ
is a differential invariant), so what the first run measured of it still holds: a usable
rolling touch clear of the corners states its envelope's κ with its deviation σ_κ
(tactile_jaw.envelope.EnvelopeFit), and a line has κ = 0 everywhere. Under a line each such
roll's z = κ / σ_κ is a standard normal draw, independent of the others (each roll's own
readings), so Σ z² over the n rolls is χ²(n): beyond its quantile at ``MODEL_ALPHA`` (the
recognizer's own consistency level, recognizer.classify) the object is no line. A curved part
the first run felt without a usable roll on it (tactile_jaw.pipeline.curved_part: radius ≥
``MOVED_SIGMAS`` σ_ρ, i.e. κ ≥ 10 σ_κ to first order, as z = κ/σ_κ = ρ/σ_ρ) says the same.
A block shows neither: its rolls pivot on corners, never usable (no usable roll in the 40
line objects of bench_explore --finite 20 --anywhere --seed 617, either jaw).

So a second run that reaches only flat faces and corners and would answer `line` from flat
presses refuses instead: the curved part the first run felt was not reached after the move
(X cubical 104 of seed 617, moved as advised: four presses of the closing segment answered
line after the first run's four usable rolls, Σ z² 122 on 4 dof, its limit 18.5). The run logs the first
run's evidence (``FELT_BEFORE_EVENT``), so ``tactile replay`` of the second log answers as
the run did without the first log.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any, Sequence

from scipy import stats

from hand_driver.flat_press import FlatResult
from recognizer.classify import MODEL_ALPHA
from recognizer.result import Recognition
from tactile_jaw.pipeline import FeltTouch, logged_run
from tactile_jaw.settings import ExploreSettings

#: the run-log event a run after a move writes with what the run before felt
FELT_BEFORE_EVENT = "felt_before"
#: the stop of such a refusal: no move is known that brings the curved part back within reach
MOVED_OFF_CURVE = ("no move is named: after the move the pads reached only straight faces and corners of an object "
                   "whose curved part the run before felt; place it as it was before the move, or so that its "
                   "curved part faces a finger")


@dataclass(frozen=True)
class FeltBefore:
    """The curvature the run before the move measured: its usable rolls' count and Σ (κ/σ_κ)²,
    and the curved part it felt without a usable roll (radius and deviation, mm), if any."""

    rolls: int
    chi2: float
    stretch_rho: float | None = None
    stretch_sigma_rho: float | None = None

    @property
    def curved(self) -> bool:
        """Is κ = 0 (a line) refuted: Σ z² beyond χ²(rolls)'s quantile at ``MODEL_ALPHA``, or a
        curved part felt (tactile_jaw.pipeline.curved_part)?"""
        return self.stretch_rho is not None or (self.rolls > 0 and self.chi2 > line_limit(self.rolls))

    def describe(self) -> str:
        """What the run before the move felt, for people."""
        said = []
        if self.rolls:
            said.append(f"{self.rolls} usable roll{'s' if self.rolls > 1 else ''} whose curvature is "
                        f"{math.sqrt(self.chi2 / self.rolls):.1f} of its deviations from zero (RMS; "
                        f"chi2 {self.chi2:.1f} on {self.rolls} dof, a line's limit {line_limit(self.rolls):.1f})")
        if self.stretch_rho is not None:
            said.append(f"a curved part of radius {self.stretch_rho:.1f} ± {self.stretch_sigma_rho:.2g} mm")
        return "; ".join(said)

    def to_event(self) -> dict[str, Any]:
        """The run-log record of this evidence (``FELT_BEFORE_EVENT``)."""
        return {"type": "event", "kind": FELT_BEFORE_EVENT,
                "message": f"before the move the run felt {self.describe() or 'no curvature'}",
                "rolls": self.rolls, "chi2": self.chi2, "stretch_rho": self.stretch_rho,
                "stretch_sigma_rho": self.stretch_sigma_rho}

    @classmethod
    def from_events(cls, events: Sequence[dict]) -> "FeltBefore | None":
        """The evidence a run log's ``FELT_BEFORE_EVENT`` holds, or None (no move before the run)."""
        e = next((e for e in events if e.get("kind") == FELT_BEFORE_EVENT), None)
        if e is None:
            return None
        return cls(int(e["rolls"]), float(e["chi2"]), e.get("stretch_rho"), e.get("stretch_sigma_rho"))


def line_limit(rolls: int) -> float:
    """χ²(rolls)'s upper quantile at ``MODEL_ALPHA``: Σ z² of that many rolls on a line stays below it."""
    return float(stats.chi2.isf(MODEL_ALPHA, rolls))


def roll_z(touch: FeltTouch) -> float:
    """z of a usable roll's envelope κ against zero: κ / σ_κ (σ_κ² the fit's cov[0, 0])."""
    return float(touch.fit.kappa) / math.sqrt(float(touch.fit.cov[0, 0]))


def felt_in(config, contents, settings: ExploreSettings) -> FeltBefore:
    """What a run log's touches (hand_driver.log.read_log's ``contents``, rebuilt with the
    exploration's own checks, tactile_jaw.pipeline.logged_run) felt of the object's curvature:
    its usable rolls clear of the corners, and the curved part it felt."""
    run = logged_run(config, contents, settings)
    rolls = [t for t in run.touches if not isinstance(t.touch, FlatResult) and t.fit is not None]
    curve = run.curve if run.curve is not None and run.curve.fit is not None else None
    return FeltBefore(len(rolls), float(sum(roll_z(t) ** 2 for t in rolls)),
                      None if curve is None else float(curve.fit.rho),
                      None if curve is None else float(curve.fit.sigma_rho))


def not_a_line(recognition: Recognition, before: FeltBefore | None) -> Recognition:
    """``recognition``, unless it answers `line` after a run before the move felt a curved part
    (``before.curved``): then the refusal saying so (the faces pressed are closing segments of
    a curved object, its curved part not reached after the move)."""
    if before is None or recognition.cls != "line" or not before.curved:
        return recognition
    return replace(Recognition("unclassified"), reason=(
        f"the touches after the move met only straight faces and corners, answered line, but the run before the "
        f"move felt {before.describe()}: the object is no line, and its curved part was not reached after the move; "
        f"the faces pressed are its closing segments"))
