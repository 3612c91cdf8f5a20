"""recognizer.nested: a richer class started next to its limit class's fit lies on the
limit's curve over the touched stretch (to about NEAR_LIMIT of its sagitta), and the
recognizer's richer classes, so started, never fit a parabola's or a circle's touches
worse than the limit does (docs/recognition.md#nested-starts)."""

from __future__ import annotations

import numpy as np
import pytest

from recognizer.classify import recognize
from recognizer.curves import CURVES, Pose
from recognizer.nested import NEAR_LIMIT, NESTED_FROM, nested_candidates
from recognizer.result import Candidate, RecognizeOptions
from recognizer.synth import SynthNoise, sample_touch
from recognizer.touches import NoiseModel, Request
from tactile_common.angles import wrap_angle

PARABOLA = Candidate("parabola", {"a": 6.0}, Pose(0.4, 120.0, -5.0), np.array([-1.2, -0.4, 0.5, 1.3]), 0.0, 1, 1)
CIRCLE = Candidate("circle", {"r": 18.0}, Pose(0.0, 110.0, 3.0), np.array([-2.0, -1.5, -1.0]), 0.0, 1, 1)


def _points(c: Candidate):
    curve = CURVES[c.cls](c.params)
    x, y = c.pose.apply(*curve.point(np.asarray(c.t, float)))
    return np.stack([x, y], axis=-1), np.asarray(curve.tangent_angle(np.asarray(c.t, float)), float) + c.pose.theta


@pytest.mark.parametrize("limit, cls", [(PARABOLA, r) for r in NESTED_FROM["parabola"]] + [(CIRCLE, "ellipse")])
def test_a_nested_start_lies_on_the_limits_curve(limit, cls):
    """Each start's contacts are the limit's, within its fraction of the touched stretch's
    sagitta (parabola: y²/(4a) at the farthest contact, 6.3 mm here, measured: at most a
    third of it; circle: r, an ellipse of a = (1 + fraction) r), and its tangents there the limit's (mod π: a start may run the
    other way) within the fraction (rad)."""
    p0, phi0 = _points(limit)
    y = 2.0 * limit.params["a"] * np.asarray(limit.t) if limit.cls == "parabola" else None
    scale = float(np.max(np.abs(y)) ** 2 / (4.0 * limit.params["a"])) if y is not None else limit.params["r"]
    for fraction in (0.1, *NEAR_LIMIT):
        starts = nested_candidates(limit, cls, (fraction,))
        assert starts and all(s.cls == cls for s in starts)
        for s in starts:
            p, phi = _points(s)
            assert np.max(np.hypot(*(p - p0).T)) < (0.5 if y is not None else 1.0) * fraction * scale
            turn = np.abs(wrap_angle(2.0 * (phi - phi0))) / 2.0  # mod π
            assert np.max(turn) < fraction


def test_no_nested_start_for_a_class_that_is_no_limit():
    assert nested_candidates(PARABOLA, "circle") == [] and nested_candidates(CIRCLE, "parabola") == []


def _request(cls: str, params: dict, ts, seed: int = 5) -> Request:
    rng = np.random.default_rng(seed)
    curve, pose = CURVES[cls](params), Pose(0.3, 115.0, 4.0)
    noise = SynthNoise(phi=1e-3, pos=0.02)
    touches = tuple(sample_touch(curve, pose, t, 9, 0.6, noise=noise, rng=rng)[0] for t in ts)
    return Request(touches, None, ("parabola", "ellipse", "hyperbola", "cubical_parabola", "semicubical_parabola",
                                   "circle"), NoiseModel(phi=1e-3, pos=0.02))


@pytest.mark.parametrize("cls, params, ts, limit", [
    ("parabola", {"a": 7.0}, (-0.9, -0.3, 0.35, 0.95), "parabola"),
    ("circle", {"r": 20.0}, (-0.6, 0.1, 0.8), "circle"),
])
def test_richer_classes_reach_the_limits_chi2(cls, params, ts, limit):
    """On a limit's touches every richer class fits at least as well as the limit, to
    within 1 % of its χ² (+0.05): LM from the nested start, capped at recognizer.refine's
    evaluations, need not reach the limit's optimum exactly."""
    request = _request(cls, params, ts)
    rec = recognize(request, RecognizeOptions(refine=True, noise=request.noise))
    chi2 = {r.cls: r.chi2 for r in rec.ranking}
    for richer in NESTED_FROM[limit]:
        assert chi2[richer] <= 1.01 * chi2[limit] + 0.05, (richer, chi2)
