"""What the touches could tell apart: the expected Δχ² between two curves on the places
the jaw touched (docs/exploration.md#what-the-touches-can-tell-apart).

A recognition's χ² says how well each class fits the touches taken; it does not say whether
those touches *could* have told two classes apart. That is the χ² a class reaches on exact
touches of another curve at the same places, with the same stated noise (each touch's
noise factor and κ covariance kept): the noncentrality of the likelihood-ratio test between
them. :func:`expected_gap` computes it by recognizing such exact touches; the stopping rule
(tactile_jaw.decide) uses it on the members of a richer class that depart from the answer
within the touched stretch (:func:`departing_gap`), and the refusal's finer-angle advice
(:func:`finer_ticks`) on two fitted rivals. Every stated deviation is the encoders'
quantization propagated (tactile_jaw.envelope), so it scales as one tick: at N ticks per
turn instead of N₀ the expected Δχ² is (N / N₀)² times larger.
"""

from __future__ import annotations

import math
from dataclasses import replace
from typing import Any, Callable, Sequence

import numpy as np

from recognizer.curves import CURVES, Pose
from recognizer.nested import NESTED_FROM, nested_candidates
from recognizer.result import Candidate, Recognition
from recognizer.touches import SamplesTouch
from tactile_common.angles import wrap_angle

__all__ = ["DEPART_FRACTION", "PROJECT_STEPS", "answer_ts", "exact_touches", "expected_gap", "departing_gap",
           "finer_ticks", "round_up", "is_rolling", "jaw_ticks_per_rev"]

#: the richer member a limit answer is held against departs from it (its inflection, cusp
#: or far vertex) at this fraction of the touched stretch's half-width across the answer's
#: axis (recognizer.nested's fraction): 1, the departure at the edge of what was touched,
#: a member of the richer class whose own shape shows inside the touched stretch
DEPART_FRACTION = 1.0
#: Newton steps projecting a sample onto a curve from its touch's contact (samples lie
#: within ~15 mm of it)
PROJECT_STEPS = 40

#: felt touches → Recognition, fitting only ``classes`` when given (tactile_jaw.pipeline.make_recognizer)
RecognizeTouches = Callable[..., Recognition]


def is_rolling(touches: Sequence[Any]) -> bool:
    """Every touch a rolling one with samples (not a flat press's contact)."""
    return bool(touches) and all(isinstance(getattr(t, "samples", None), SamplesTouch) for t in touches)


def answer_ts(recognition: Recognition, touches: Sequence[Any]) -> list[np.ndarray] | None:
    """Every sample's parameter t on the answer's curve (per touch; each projected from its
    touch's contact t), or None when the answer has no contacts for these touches."""
    if recognition.pose is None or len(recognition.contacts) != len(touches):
        return None
    curve = CURVES[recognition.cls](recognition.params)
    out = []
    for t, contact in zip(touches, recognition.contacts):
        s = t.samples
        cx, cy = recognition.pose.inverse(np.asarray(s.x, float), np.asarray(s.y, float))
        ts = curve.project(np.full(len(s.x), float(contact["t"])), cx, cy, PROJECT_STEPS)
        if not np.all(np.isfinite(ts)):
            return None
        out.append(ts)
    return out


def exact_touches(touches: Sequence[Any], cls: str, params: dict, pose: Pose, ts: Sequence[np.ndarray]) -> list:
    """``touches`` (felt touches with samples) with every sample moved onto the curve
    (``cls``, ``params``, ``pose``) at parameters ``ts`` (per touch): position, tangent angle
    in the touch's direction of travel, and κ, κ_s at its contact sample; the noise factor,
    κ covariance and everything else the touch states kept."""
    curve = CURVES[cls](params)
    out = []
    for t, tt in zip(touches, ts):
        s = t.samples
        px, py = curve.point(tt)
        hx, hy = pose.apply(px, py)
        phi = np.asarray(curve.tangent_angle(tt), float) + pose.theta
        flip = abs(wrap_angle(float(phi[len(phi) // 2] - s.phi[len(s.phi) // 2]))) > math.pi / 2
        phi = phi + (math.pi if flip else 0.0)
        phi = phi + np.round((np.asarray(s.phi, float) - phi) / (2 * math.pi)) * 2 * math.pi  # the touch's branch
        curvature = s.curvature
        if curvature is not None:
            m = s.contact_index
            kappa = float(np.asarray(curve.kappa(tt[m:m + 1]))[0]) * (-1.0 if flip else 1.0)
            curvature = (kappa, float(np.asarray(curve.kappa_s(tt[m:m + 1]))[0]), curvature[2])
        exact = replace(s, x=np.asarray(hx, float), y=np.asarray(hy, float), phi=phi, curvature=curvature)
        out.append(replace(t, samples=exact))
    return out


def expected_gap(recognize_touches: RecognizeTouches, touches: Sequence[Any], cls: str, params: dict, pose: Pose,
                 ts: Sequence[np.ndarray], against: str) -> float:
    """The χ² class ``against`` reaches on exact touches of the curve (``cls``, ``params``,
    ``pose``) at parameters ``ts``, with the touches' stated noise: the Δχ² by which these
    touches would set that curve apart from ``against`` (inf: ``against`` not fitted)."""
    rec = recognize_touches(exact_touches(touches, cls, params, pose, ts), classes=(against,))
    row = next((r for r in rec.ranking if r.cls == against), None)
    return float(row.chi2) if row is not None and math.isfinite(row.chi2) else math.inf


def departing_gap(recognize_touches: RecognizeTouches, recognition: Recognition, touches: Sequence[Any],
                  rival: str) -> float | None:
    """The smallest expected Δχ² (:func:`expected_gap`) between the answer and a member of
    the richer class ``rival`` that departs from it at ``DEPART_FRACTION`` of the touched
    stretch (recognizer.nested: tangent at the answer's vertex with its curvature, its
    inflection, cusp or far vertex that far out; a cubic family bending either way). None
    when the pair has no such members (only a limit class's richer classes do) or the
    touches are not rolling ones."""
    if rival not in NESTED_FROM.get(recognition.cls, ()) or not is_rolling(touches):
        return None
    ts = answer_ts(recognition, touches)
    if ts is None:
        return None
    limit = Candidate(recognition.cls, dict(recognition.params), recognition.pose, np.concatenate(ts), 0.0, 0, 0)
    sizes = np.cumsum([len(t) for t in ts])[:-1]
    gaps = []
    for member in nested_candidates(limit, rival, (DEPART_FRACTION,)):
        member_ts = np.split(np.asarray(member.t, float), sizes)
        if not all(np.all(np.isfinite(t)) for t in member_ts):
            continue
        gaps.append(expected_gap(recognize_touches, touches, rival, member.params, member.pose, member_ts,
                                 recognition.cls))
    return min(gaps) if gaps else None


def finer_ticks(gap: float, ticks: int, needed: float) -> int | None:
    """The encoder resolution (ticks per turn) at which an expected Δχ² of ``gap`` at
    ``ticks`` grows to ``needed`` (every stated deviation is one tick's quantization: Δχ²
    scales as the square of the resolution), rounded up to 3 significant digits (``ticks``
    itself when the gap is already enough); None when the gap is 0 or not finite (no
    resolution tells them apart)."""
    if not (math.isfinite(gap) and gap > 0.0):
        return None
    if gap >= needed:
        return ticks
    return round_up(ticks * math.sqrt(needed / gap))


def round_up(value: float, digits: int = 3) -> int:
    """``value`` rounded up to ``digits`` significant digits (a resolution to state)."""
    step = 10 ** max(int(math.floor(math.log10(value))) - digits + 1, 0)
    return int(math.ceil(value / step) * step)


def jaw_ticks_per_rev(config) -> int:
    """The encoder resolution (ticks per turn) of the jaw ``config``'s joints: what the
    stated noise of its touches is one tick of. A jaw mixing models (config/jaw-p.yaml:
    1,003,846 at the base joints, 607,500 at the distal ones) counts as the one resolution
    N that gives every joint's quantization the same total variance (tactile_jaw.settings.
    phi_sigma): 1/N² the mean of 1/N_j²."""
    inv2 = [1.0 / float(j.ticks_per_rev) ** 2 for f in config.fingers for j in f.joints]
    return int(round(1.0 / math.sqrt(sum(inv2) / len(inv2))))
