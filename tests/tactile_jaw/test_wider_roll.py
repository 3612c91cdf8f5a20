"""A roll judged a corner only by its radius's deviation is rolled again at the same place over
a wider span (tactile_jaw.explore.wider_again): on the X-series jaw an ellipse's end (ρ = b²/a)
measured over 18° cannot be told from a corner, over 36° it can."""

import json
import math
from pathlib import Path

import numpy as np
import pytest

from hand_driver import kinematics as kin
from hand_driver.config import load_config
from hand_driver.motion import Sample, TouchResult
from recognizer.curves import CURVES, Pose
from tactile_jaw.choose import JawReach
from tactile_jaw.explore import wider_again
from tactile_jaw.pipeline import WIDER_SPAN, corner_in_doubt, feel, on_corner
from tactile_jaw.settings import ExploreSettings

DATA = Path(__file__).parent / "data" / "x_ellipse_end_rolls.json"
A, B = 18.827261996782514, 11.29635719806951
POSE = Pose(-2.026291734773856, 126.00148026381865, -9.005520852872607)
CONFIG = load_config("config/jaw.yaml")


def _roll(key: str) -> TouchResult:
    raw = json.loads(DATA.read_text())["rolls"][key]
    ticks = np.array(raw["ticks"], dtype=float)
    lines = kin.finger_pad_line_from_ticks(CONFIG, raw["finger"], ticks)
    samples = [Sample(reading=k, psi=psi, ticks=ticks[k], line=lines.at(k), current_ma=None, robot_time=0.0)
               for k, psi in enumerate(raw["psi"])]
    return TouchResult(raw["finger"], int(key), raw["psi_center"], samples, outcome="ok")


@pytest.fixture(scope="module")
def reach():
    return JawReach(CONFIG, ExploreSettings.from_profile("balanced"))


def test_an_ellipse_end_rolled_over_18_degrees_is_rolled_again_wider(reach):
    """X ellipse 10 of bench_explore --finite 4 --anywhere --seed 83 (development seed; a 18.8,
    b 11.3: ρ 6.8 mm at its ends). Its fingers' 18° rolls at both ends were judged corners
    (ρ 5.2 ± 4.1 mm), both fingers were retired and the object was refused 'needs another
    move'. Such a roll now gets an aim at the point it turned about, rolled twice as wide."""
    felt = feel(CONFIG, _roll("10"), 9)
    assert felt.off_curve and on_corner(felt.fit) and corner_in_doubt(felt.fit)
    aim = wider_again(felt, reach, set())
    assert aim is not None and aim.kind == "wider" and aim.finger == felt.finger
    assert np.hypot(aim.x - felt.corner[0], aim.y - felt.corner[1]) == 0.0
    assert abs(aim.psi - felt.touch.psi_center) < 1e-12
    assert wider_again(felt, reach, {felt.touch.touch}) is None  # a wider roll is not rolled wider again


def test_the_wider_roll_is_usable_and_its_curvature_is_the_ellipse_end(reach):
    """The roll again there over 36° passes every check; its κ agrees with the ellipse's at
    the contact within 3 of its stated σ (ρ 6.8 mm, a curvature no corner has)."""
    touch = _roll("12")
    felt = feel(CONFIG, touch, 9)
    assert felt.problem is None and not corner_in_doubt(felt.fit)
    assert wider_again(felt, reach, set()) is None
    ellipse = CURVES["ellipse"]({"a": A, "b": B})
    t = np.linspace(-math.pi, math.pi, 200001)
    px, py = POSE.apply(*ellipse.point(t))
    c = felt.contacts
    m = len(c.x) // 2
    k = int(np.argmin(np.hypot(px - c.x[m], py - c.y[m])))
    assert np.hypot(px[k] - c.x[m], py[k] - c.y[m]) < 0.3
    kappa = abs(float(ellipse.kappa(t[k])))
    assert abs(abs(felt.fit.kappa) - kappa) < 3.0 * math.sqrt(felt.fit.cov[0, 0])
    assert 1.0 / kappa < 8.0  # the tight end, not a flank
    assert WIDER_SPAN * 0.314 < np.ptp(felt.contacts.psi) + 0.05


def test_a_sure_corner_is_not_rolled_again(reach):
    """ρ below CORNER_RADIUS_MM is a corner whatever its deviation: no wider roll."""
    felt = feel(CONFIG, _roll("10"), 9)
    sure = type(felt.fit)(**{**felt.fit.__dict__, "rho": 0.5})
    assert on_corner(sure) and not corner_in_doubt(sure)
    assert wider_again(type(felt)(**{**felt.__dict__, "fit": sure}), reach, set()) is None
