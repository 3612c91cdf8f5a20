"""A roll judged a corner only by its radius's deviation is rolled again at the same place over
a wider span (tactile_jaw.explore.wider_again): on the X-series jaw an ellipse's end (ρ = b²/a)
measured over 18° cannot be told from a corner, over 36° it can."""

import json
import math
from pathlib import Path

import numpy as np
import pytest

from hand_driver.config import load_config
from hand_driver.motion import TouchResult
from recognizer.curves import CURVES, Pose
from tactile_jaw.choose import JawReach
from tactile_jaw.explore import wider_again
from tactile_jaw.pipeline import (CORNER_CLEARANCE_MM, WIDER_SPAN, clear_of_corners, corner_in_doubt, feel,
                                  logged_samples, measured_there, on_corner)
from tactile_jaw.settings import ExploreSettings

DATA = Path(__file__).parent / "data" / "x_ellipse_end_rolls.json"
A, B = 18.827261996782514, 11.29635719806951
POSE = Pose(-2.026291734773856, 126.00148026381865, -9.005520852872607)
CONFIG = load_config("config/jaw.yaml")


def _roll(key: str, data: Path = DATA) -> TouchResult:
    """Roll ``key`` of the logged rolls ``data`` (its finger's ticks and commanded ψ) as the run made it."""
    raw = json.loads(data.read_text())["rolls"][key]
    samples = logged_samples(CONFIG, raw["finger"], raw["ticks"], raw["psi"])
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


def _with_rho(felt, rho, sigma_rho=None):
    fit = type(felt.fit)(**{**felt.fit.__dict__, "rho": rho,
                            "sigma_rho": felt.fit.sigma_rho if sigma_rho is None else sigma_rho})
    return type(felt)(**{**felt.__dict__, "fit": fit})


def test_a_radius_under_1_mm_with_a_deviation_of_mm_is_in_doubt(reach):
    """X ellipse 10 of --seed 29 (moved as advised; b²/a = 5.4 mm) measured ρ 0.63 ± 3.78 mm
    at its end over 18°: under CORNER_RADIUS_MM, a sure corner until session 13, yet within
    its deviation of the radius it has. The same roll with ρ 0.5 mm is rolled again wider."""
    felt = _with_rho(feel(CONFIG, _roll("10"), 9), 0.5)
    assert felt.fit.sigma_rho > 3.0 and on_corner(felt.fit) and corner_in_doubt(felt.fit)
    assert wider_again(felt, reach, set()) is not None


def test_a_sure_corner_is_not_rolled_again(reach):
    """A corner whose radius stays a corner's within 2 of its deviations, even for a roll
    WIDER_SPAN times wider (σ_ρ / WIDER_SPAN²), is not rolled again: ρ 0.5 ± 0.2 mm (a
    P-series jaw's corners: σ_ρ of µm), or −6 ± 2.5 mm."""
    felt = feel(CONFIG, _roll("10"), 9)
    for rho, sigma in ((0.5, 0.2), (-6.0, 2.5), (0.0, 0.001)):
        sure = _with_rho(felt, rho, sigma)
        assert on_corner(sure.fit) and not corner_in_doubt(sure.fit)
        assert wider_again(sure, reach, set()) is None
    assert corner_in_doubt(_with_rho(felt, -3.0, 2.5).fit)  # −3 + 2·2.5 ≥ 2·2.5 / 4: a usable bend within reach


def test_a_wider_roll_there_drops_a_corner_in_doubt_and_a_sure_one_stays():
    """The wider roll (usable, its middle contact at the doubtful roll's corner) keeps all of
    its samples when the first roll's corner was in doubt (ρ 0.5 mm of σ 4.1: before session
    13 a sure corner, which trimmed the wider roll's samples near it); a sure corner
    there (ρ 0.05 ± 0.1 mm) still trims them. The rule reads the touches alone (replay too)."""
    first, wider = feel(CONFIG, _roll("10"), 9), feel(CONFIG, _roll("12"), 9)
    assert first.corner is not None and wider.problem is None
    m = len(wider.contacts.x) // 2
    assert np.hypot(wider.contacts.x[m] - first.corner[0], wider.contacts.y[m] - first.corner[1]) < CORNER_CLEARANCE_MM
    doubt = _with_rho(first, 0.5)
    assert measured_there(doubt, [doubt, wider])
    kept, notes = clear_of_corners(CONFIG, [wider], [doubt, wider], 9)
    assert kept == [wider] and notes == []
    sure = _with_rho(first, 0.05, 0.1)  # below its deviation: a corner that clears (CLEARANCE_SIGMAS)
    kept, notes = clear_of_corners(CONFIG, [wider], [sure, wider], 9)
    assert len(notes) == 1 and (not kept or len(kept[0].touch.samples) < len(wider.touch.samples))
