"""What touches could tell apart (tactile_jaw.separation) and the stopping rule built on it
(tactile_jaw.decide.inseparable, refusal_kind): on exact touches of a cubical parabola's hump
(the shape of random cubical 102 of bench_explore --finite 20 --seed 13, answered parabola
once moved), the expected Δχ² between the parabola and a cubical departing within the
touched stretch is below the decisive 10 at the X-series jaw's noise and far above it at a
P-series jaw's, scaling exactly as the square of the resolution."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pytest

from hand_driver.config import load_config
from recognizer.classify import recognize
from recognizer.curves import CURVES, Pose
from recognizer.profiles import get_profile
from recognizer.result import RecognizeOptions
from recognizer.synth import sample_touch
from recognizer.touches import NoiseModel, Request, SamplesTouch
from tactile_jaw.decide import DECISIVE_CHI2, FINER, REFUSAL_KINDS, inseparable, refusal_kind
from tactile_jaw.separation import (answer_ts, departing_gap, exact_touches, expected_gap, finer_ticks,
                                    jaw_ticks_per_rev, round_up)
from tactile_jaw.settings import phi_sigma

ALL = ("line", "circle", "ellipse", "parabola", "hyperbola", "cubical_parabola", "semicubical_parabola")
X_TICKS, P_TICKS = 4096, 1_003_846
#: the noise the X-series jaw states for a balanced roll (docs/exploration.md#the-stated-noise)
X_NOISE = NoiseModel(phi=phi_sigma(load_config("config/jaw.yaml").fingers[0].joints), pos=0.03, pos_along=0.7)


@dataclass(frozen=True)
class Felt:
    """The one field of tactile_jaw.pipeline.FeltTouch the separation reads."""

    samples: SamplesTouch


def recognizer(noise: NoiseModel):
    """Felt touches → Recognition with the balanced options and ``noise`` (as
    tactile_jaw.pipeline.make_recognizer, ``classes`` a subset)."""
    options = RecognizeOptions(**{**get_profile("balanced", "profile").options(), "noise": noise})

    def run(touches, reach=None, classes=None):
        request = Request(tuple(t.samples for t in touches), None, tuple(classes or ALL), noise, {}, "test")
        return recognize(request, options)

    return run


def scaled(noise: NoiseModel, k: float) -> NoiseModel:
    return NoiseModel(phi=noise.phi * k, pos=noise.pos * k, pos_along=noise.pos_along * k)


def cubical_hump() -> list[Felt]:
    """Four exact 9-sample rolls over the hump of the cubical (t, a t³ + c t), a 0.00056,
    c −0.5 (hump at t −17.2, inflection at 0), on both sides of the hump."""
    curve = CURVES["cubical_parabola"]({"a": 0.00056, "c": -0.5})
    pose = Pose(-0.27, 118.0, -7.6)
    return [Felt(sample_touch(curve, pose, t, 9, 0.7)[0]) for t in (-25.0, -20.5, -15.0, -10.0)]


@pytest.fixture(scope="module")
def hump():
    touches = cubical_hump()
    parabola = recognizer(X_NOISE)(touches, classes=("parabola",))
    assert parabola.cls == "parabola"
    return touches, parabola


def test_a_curve_is_not_told_from_itself_and_gaps_scale_as_the_resolution_squared(hump):
    touches, parabola = hump
    ts = answer_ts(parabola, touches)
    run = recognizer(X_NOISE)
    assert expected_gap(run, touches, "parabola", parabola.params, parabola.pose, ts, "parabola") < 1e-6
    coarse = expected_gap(run, touches, "parabola", parabola.params, parabola.pose, ts, "circle")
    fine = expected_gap(recognizer(scaled(X_NOISE, 0.25)), touches, "parabola", parabola.params, parabola.pose, ts,
                        "circle")
    assert coarse > 1.0 and fine == pytest.approx(16.0 * coarse, rel=0.02)
    # the exact touches lie on the curve: the parabola fits its own exact touches perfectly
    exact = exact_touches(touches, "parabola", parabola.params, parabola.pose, ts)
    assert all(np.allclose(t.samples.phi, s.samples.phi, atol=0.05) for t, s in zip(exact, touches))


def test_a_cubical_departing_within_the_hump_is_told_apart_only_with_finer_angles(hump):
    touches, parabola = hump
    coarse = departing_gap(recognizer(X_NOISE), parabola, touches, "cubical_parabola")
    k = X_TICKS / P_TICKS
    fine = departing_gap(recognizer(scaled(X_NOISE, k)), parabola, touches, "cubical_parabola")
    assert coarse < DECISIVE_CHI2 < fine
    # at the P-series noise the parabola's fit to the departing member is far outside the
    # range the recognizer refines (its invariant-stage fit stands): at least the scaled gap
    assert fine >= 0.95 * coarse / k**2
    half = departing_gap(recognizer(scaled(X_NOISE, 0.5)), parabola, touches, "cubical_parabola")
    assert half == pytest.approx(4.0 * coarse, rel=0.02)
    need = finer_ticks(coarse, X_TICKS, DECISIVE_CHI2)
    assert X_TICKS < need <= P_TICKS and need == pytest.approx(X_TICKS * math.sqrt(DECISIVE_CHI2 / coarse), rel=1e-2)
    assert departing_gap(recognizer(X_NOISE), parabola, touches, "line") is None  # no such member


def test_an_inseparable_limit_answer_is_refused_naming_the_rival_and_the_resolution(hump):
    touches, parabola = hump
    everything = recognizer(X_NOISE)(touches)  # every class fitted: the ranking the rule reads
    answer = type(parabola)("parabola", parabola.params, parabola.pose, parabola.contacts,
                            ranking=everything.ranking)
    why = inseparable(recognizer(X_NOISE), answer, touches, X_TICKS, budget=4)
    assert why is not None and why.kind == "resolution" and why.rival in ("cubical_parabola", "semicubical_parabola")
    assert FINER in why and refusal_kind(why) == "needs finer angles"
    fine = recognizer(scaled(X_NOISE, X_TICKS / P_TICKS))
    assert inseparable(fine, answer, touches, P_TICKS, budget=4) is None


def test_an_answer_that_is_no_limit_is_not_checked(hump):
    touches, parabola = hump
    cubical = recognizer(X_NOISE)(touches, classes=("cubical_parabola", "ellipse"))
    assert cubical.cls in ("cubical_parabola", "ellipse")
    assert inseparable(recognizer(X_NOISE), cubical, touches, X_TICKS, budget=4) is None


def test_a_jaw_resolution_is_its_joints_quantization():
    assert jaw_ticks_per_rev(load_config("config/jaw.yaml")) == X_TICKS
    # PH54 (1,003,846) at the base joints and PH42 (607,500) distal: the one resolution with
    # the same total quantization variance
    expected = 1.0 / math.sqrt(0.5 / 1_003_846**2 + 0.5 / 607_500**2)
    assert jaw_ticks_per_rev(load_config("config/jaw-p.yaml")) == pytest.approx(expected, abs=1)


def test_round_up_and_refusal_kinds():
    assert round_up(24_871.2) == 24_900 and round_up(1_003_846) == 1_010_000 and round_up(12.0) == 12
    assert finer_ticks(10.0, 4096, 10.0) == 4096 and finer_ticks(0.0, 4096, 10.0) is None
    assert finer_ticks(2.5, 4096, 10.0) == 8200  # 8192 up to 3 significant digits
    assert refusal_kind("…; move the object 4 mm away from the palm", {"dx": 4.0, "dy": 0.0}) == "out of reach"
    assert refusal_kind("no pad can roll beyond the vertex on that side") == "out of reach"
    # a refusal naming both a finer jaw and a move: the move, which this jaw can make, counts first
    finer = f"not decisive: cubical_parabola and parabola both fit; {FINER} 8,200 ticks per turn tells them apart"
    assert refusal_kind(finer) == "needs finer angles"
    assert refusal_kind(f"{finer}; turn the object 25 deg counterclockwise", {"dx": 16.0, "dy": -6.0}) == "out of reach"
    assert refusal_kind("only 0 usable touches of 8 tried") == "needs another move"
    assert set(REFUSAL_KINDS) == {"out of reach", "needs finer angles", "needs another move", "no class fits"}
    assert refusal_kind("no class of the scene fits: closest class parabola: …") == "no class fits"
