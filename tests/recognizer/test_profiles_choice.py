"""recognizer.profiles: the profiles, their validation, the robot-time model, options."""

from __future__ import annotations

import math
from types import SimpleNamespace

import pytest

from tactile_common.errors import InputError
from recognizer.profiles import (DEFAULT_PROFILE, DEFAULT_TIME_MODEL, PROFILES, Profile, get_profile,
                                 resolve_options, robot_time_s)
from recognizer.result import RecognizeOptions


def test_profiles_trade_time_for_accuracy():
    assert set(PROFILES) == {"fast", "balanced", "accurate"} and DEFAULT_PROFILE in PROFILES
    t = {n: robot_time_s(p.touches, p.samples_per_touch, p.roll_span_deg) for n, p in PROFILES.items()}
    assert t["fast"] < t["balanced"] < t["accurate"]
    assert PROFILES["balanced"].refine and PROFILES["accurate"].refine
    # the balanced profile samples about 2 % of a shape's size on a radius L/2
    assert math.isclose(PROFILES["balanced"].spacing(0.5), 0.0196, rel_tol=0.01)


def test_robot_time_model_by_hand():
    """One touch of 9 samples over 18°: approach 10/20 + back-off 10/100 + transfer
    30/100 + 3 settles, then 9 × (0.314/8/3.1416 + 2·0.5/20 + 0.05 + 0.01)."""
    m = DEFAULT_TIME_MODEL
    step = math.radians(18) / 8
    expect = 0.5 + 0.1 + 0.3 + 0.15 + 9 * (step / math.pi + 0.05 + 0.05 + 0.01)
    assert math.isclose(m.touch_s(9, math.radians(18)), expect, rel_tol=1e-12)
    assert math.isclose(robot_time_s(3, 9, 18.0), 3 * expect, rel_tol=1e-12)


@pytest.mark.parametrize("kw,msg", [({"touches": 1}, "touches"), ({"samples_per_touch": 2}, "samples"),
                                    ({"roll_span_deg": 0.0}, "roll_span"), ({"estimator": "spline"}, "estimator"),
                                    ({"alpha": 0.7}, "alpha"), ({"decisive_rel_sigma": 0.0}, "decisive_rel_sigma"),
                                    ({"decisive_rel_sigma": 0.6}, "decisive_rel_sigma"),
                                    ({"target_rel_sigma": 0.0}, "target_rel_sigma"),
                                    ({"target_rel_sigma": 0.03}, "target_rel_sigma")])
def test_profile_validation(kw, msg):
    base = dict(name="x", touches=3, samples_per_touch=9, roll_span_deg=18.0, estimator="auto", refine=True)
    base.update(kw)
    with pytest.raises(InputError, match=msg):
        Profile(**base)


def test_options_resolution():
    assert resolve_options({"refine": True}) == {"refine": True}
    fast = resolve_options({"profile": "fast"})
    assert fast["refine"] is False and fast["estimator"] == "auto" and fast["profile"] == "fast"
    assert resolve_options({"profile": "fast", "refine": True})["refine"] is True
    scene = SimpleNamespace(profile="accurate")
    assert resolve_options({}, scene)["refine"] is True
    assert resolve_options({"profile": "fast"}, scene)["profile"] == "fast"
    RecognizeOptions(**resolve_options({"profile": "balanced"}))  # keywords fit the options type
    with pytest.raises(InputError, match="unknown profile"):
        get_profile("turbo")
