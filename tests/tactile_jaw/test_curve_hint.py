"""A roll that felt the curved part and then ran onto the object's end corner, too short to
trim to a usable touch: where it felt the curve (tactile_jaw.pipeline.curve_hint), so the
exploration aims the finger's next roll there instead of retiring it."""

import json
from pathlib import Path

import numpy as np
import pytest

from hand_driver.config import load_config
from hand_driver.motion import TouchResult
from recognizer.curves import CURVES, Pose
from tactile_jaw.pipeline import CURVE_HINT_SAMPLES, feel, logged_samples
from tactile_jaw.settings import MIN_SAMPLES_PER_TOUCH

DATA = Path(__file__).parent / "data" / "p_cubical_roll_to_corner.json"
TRUTH = ("cubical_parabola", {"a": 0.0009383107856381567, "c": -0.5}, Pose(0.3100936184668761, 112.69721198297934,
                                                                            12.34287536994391))


def _logged_roll(data=DATA):
    raw = json.loads(data.read_text())
    config = load_config("config/jaw-p.yaml")
    samples = logged_samples(config, raw["finger"], raw["ticks"], raw["psi"])
    return config, TouchResult(raw["finger"], 4, raw["psi_center"], samples, outcome="ok")


def test_roll_onto_the_end_corner_notes_where_it_felt_the_curve():
    """P-series jaw, random cubical 30 of bench_explore --finite 6 --anywhere --seed 17
    (development seed): its left pad's first roll went from ρ 17 mm toward the inflection
    (ρ 620 mm) and onto the end corner; 6 of its 9 samples pass every check, one fewer than
    a touch needs. Its fingers then fell on corners, were retired, and flat presses on the
    closing segment answered line. The roll now says where it felt the curve: a point of
    the cubical within 0.05 mm, with its tangent within 0.02 rad (predicted one roll on past
    the stretch, along the circle of its radius of curvature: 0.010 rad off where ρ grows
    toward the inflection), on the side away from the samples the roll lost (its low ψ)."""
    config, touch = _logged_roll()
    felt = feel(config, touch, len(touch.samples))
    assert felt.problem is not None and felt.off_curve
    assert CURVE_HINT_SAMPLES < MIN_SAMPLES_PER_TOUCH
    x, y, phi = felt.curve_at
    cls, params, pose = TRUTH
    curve = CURVES[cls](params)
    t = np.linspace(-22.2, 1.85, 200001)
    px, py = pose.apply(*curve.point(t))
    k = int(np.argmin(np.hypot(px - x, py - y)))
    assert np.hypot(px[k] - x, py[k] - y) < 0.05
    tangent = float(curve.tangent_angle(t[k])) + pose.theta
    assert abs(np.remainder(phi - tangent + np.pi / 2, np.pi) - np.pi / 2) < 0.02
    assert phi + np.pi / 2 > max(s.psi for s in touch.samples) - 0.5 * (touch.samples[-1].psi - touch.samples[0].psi)


def test_a_roll_that_lost_one_end_is_followed_past_the_other():
    """P-series jaw, random cubical 117 of bench_explore --finite 20 --anywhere --seed 157
    (development seed): the right pad's roll over ψ 73.5–91.5° began on the end corner beside
    the inflection, where ρ grows without bound. Five samples pass every check dropping 2 at
    each end, or 3 and 1, or 4 and 0: only the low end is lost in every way. The roll's middle
    was rolled again (the same roll: refused, naming no move); now the next roll goes on past
    the high end (its middle beyond the roll's), at a point of the cubical within 0.5 mm, and
    the stretch felt keeps that end, so a refusal names the move on past it."""
    from tactile_jaw.pipeline import curved_stretch

    config, touch = _logged_roll(DATA.with_name("p_cubical_roll_onto_inflection.json"))
    felt = feel(config, touch, len(touch.samples))
    assert felt.problem is not None and felt.off_curve and felt.curve_at is not None
    x, y, phi = felt.curve_at
    psi = np.array([s.psi for s in touch.samples])
    assert phi + np.pi / 2 > psi.max()
    stretch = curved_stretch(config, felt)
    assert stretch.contacts.psi.max() == pytest.approx(psi.max(), abs=1e-3)
    assert stretch.contacts.psi.min() > psi.min() + 0.05
    curve = CURVES["cubical_parabola"]({"a": 0.0005389292807981494, "c": -0.5})
    px, py = Pose(-2.948510620823335, 97.23699782543376, 4.53610048876182).apply(
        *curve.point(np.linspace(-29.24087371530389, 2.4367394762753243, 200001)))
    assert float(np.min(np.hypot(px - x, py - y))) < 0.5


def test_a_usable_roll_has_no_hint():
    config, touch = _logged_roll()
    rest = TouchResult(touch.finger, touch.touch, touch.psi_center, touch.samples[3:], outcome="ok")
    felt = feel(config, rest, len(rest.samples))
    assert felt.problem is None and felt.curve_at is None


def test_a_roll_aimed_where_the_curve_was_felt_is_followed_once():
    """The same roll off the curved part with a hint, again and again (random parabola 11 of
    bench_explore --finite 3 --anywhere --follow --seed 17 on the P-series jaw, moved as
    advised: 236 touches): a hinted roll that runs off again counts toward retiring its
    finger and is not followed."""
    from types import SimpleNamespace

    from tactile_jaw.explore import OFF_CURVE_RETIRE, off_curve_count

    hinted_off = SimpleNamespace(off_curve=True, curve_at=(1.0, 2.0, 0.3))
    count, follow = off_curve_count(0, hinted_off, hinted=False)
    assert (count, follow) == (0, True)  # first time: aim there
    for _ in range(OFF_CURVE_RETIRE):
        count, follow = off_curve_count(count, hinted_off, hinted=True)
        assert not follow
    assert count == OFF_CURVE_RETIRE
    assert off_curve_count(1, SimpleNamespace(off_curve=False, curve_at=None), hinted=True) == (0, False)
    assert off_curve_count(1, SimpleNamespace(off_curve=True, curve_at=None), hinted=False) == (2, False)
