"""A roll's samples past where another roll of its finger left the curved part, and the
κ_s of a roll too short for its finger's degree comparison (tactile_jaw.pipeline.clear_of_corners,
curve_ends; tactile_jaw.curvature_pool.unseen): the right pad's rolls of P cubical 105 of
bench_explore --finite 20 --anywhere --seed 157 --config config/jaw-p.yaml, as logged, refused
"no class fits" (κ_s at one touch 5.1 σ off, the refined fit's p 6.8e-4)."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from hand_driver.config import load_config
from hand_driver.motion import TouchResult
from recognizer.curves import CURVES, Pose
from tactile_jaw.curvature_pool import pooled
from tactile_jaw.pipeline import clear_of_corners, curve_ends, feel, logged_samples, make_recognizer
from tactile_jaw.settings import ExploreSettings

DATA = Path(__file__).parent / "data" / "p_cubical_105_rolls.json"
RAW = json.loads(DATA.read_text())
TRUTH = RAW["truth"]
CURVE = CURVES[TRUTH["class"]](TRUTH["params"])
POSE = Pose(**TRUTH["pose"])


@pytest.fixture(scope="module")
def felt():
    """Every logged roll felt as the exploration felt it: {touch index: FeltTouch}."""
    config = load_config("config/jaw-p.yaml")
    out = {}
    for t in RAW["touches"]:
        samples = logged_samples(config, t["finger"], t["ticks"], t["psi"])
        out[t["touch"]] = feel(config, TouchResult(t["finger"], t["touch"], t["psi_center"], samples, outcome="ok"), 9)
    return config, out


def _end_normal_deg() -> float:
    """The pad normal ψ at which a pad meets the curve's end P(t0) (the end tangent's)."""
    t0 = TRUTH["extent"][0]
    phi = float(CURVE.tangent_angle(np.array([t0]))[0]) + POSE.theta
    return math.degrees(math.remainder(phi - math.pi / 2, 2 * math.pi))


def test_a_roll_that_crossed_the_end_says_where_the_curve_ends(felt):
    config, touches = felt
    crossed = touches[15]
    assert crossed.problem is not None and crossed.off_curve
    (edge, x, y, way), = curve_ends([crossed])["right"]
    assert way == 1  # it kept its low ψ and lost its high ψ: the curve ends above
    assert abs(math.degrees(edge) - _end_normal_deg()) < 0.5  # the truth 126.0°, its last kept 126.2°


def test_a_usable_rolls_sample_past_that_end_is_left_out(felt):
    """Roll 11 passes every check, yet its last sample lies 0.5° past the end tangent (its
    contact 0.14 mm from the end corner): left out, its 8 others kept; the rolls short of the
    end keep every sample."""
    config, touches = felt
    usable = [touches[k] for k in (7, 11, 13, 17, 20)]
    assert all(t.problem is None for t in usable)
    assert math.degrees(float(touches[11].contacts.psi[-1])) > _end_normal_deg() + 0.3
    kept, notes = clear_of_corners(config, usable, list(touches.values()), 9)
    sizes = {t.touch.touch: t.contacts.x.size for t in kept}
    assert sizes == {7: 9, 11: 8, 13: 9, 17: 8, 20: 9}
    assert math.degrees(float(max(t.contacts.psi[-1] for t in kept))) < _end_normal_deg()
    assert len(notes) == 1 and "touch 11" in notes[0]


def _true_kappa_s(x: float, y: float) -> float:
    t = np.linspace(*TRUTH["extent"], 200001)
    px, py = POSE.apply(*CURVE.point(t))
    return float(CURVE.kappa_s(t[int(np.argmin(np.hypot(px - x, py - y)))]))


def test_a_short_rolls_kappa_s_takes_its_fingers_pooled_truncation(felt):
    """Roll 17 kept 8 of its 9 readings (one read off its commanded angle), too few for the
    quintic its finger's other rolls compare the cubic with; its own quartic hardly moves κ_s
    (−3.26e-3 → −3.34e-3), the truth is −3.81e-3: z 4.1 as stated. With the finger's pooled
    bias of the cubic against the quintic it is within 1 σ."""
    config, touches = felt
    usable = [touches[k] for k in (7, 11, 13, 17, 20)]
    short = touches[17]
    assert short.contacts.x.size == 8 and short.fit.kappa_degree == 3
    c = short.contacts
    truth = _true_kappa_s(c.x[4], c.y[4])
    _, kappa_s, cov = short.samples.curvature
    assert abs(kappa_s - truth) / math.sqrt(cov[1, 1]) > 3.5
    _, kappa_s, cov = pooled(usable)[3].samples.curvature
    assert abs(kappa_s - truth) / math.sqrt(cov[1, 1]) < 1.0


def test_the_rolls_answer_the_cubical(felt):
    """Without roll 11's sample past the end the refined fit is consistent: cubical, a and c
    within 2 % (refused "no class fits" before)."""
    config, touches = felt
    usable, _ = clear_of_corners(config, [touches[k] for k in (7, 11, 13, 17, 20)], list(touches.values()), 9)
    scene = {"name": "p cubical 105", "classes": ["line", "circle", "ellipse", "parabola", "hyperbola",
                                                  "cubical_parabola", "semicubical_parabola"]}
    settings = ExploreSettings.from_json({"touches": 8, "samples_per_touch": 9, "roll_span_deg": 18.0, "min_touches": 3,
                                          "profile": "balanced", "recognize": {"estimator": "auto", "refine": True,
                                                                               "alpha": 0.001, "profile": "balanced"}})
    answer = make_recognizer(scene, settings)(usable)  # the run's settings (its log's header)
    assert answer.cls == "cubical_parabola", answer.reason
    for k, v in TRUTH["params"].items():
        assert answer.params[k] == pytest.approx(v, rel=0.02)
