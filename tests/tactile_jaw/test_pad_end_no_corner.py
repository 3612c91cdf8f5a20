"""A roll whose radius of curvature is negative by many of its deviations turned about no point
(tactile_jaw.pipeline.clears_around): it is not used, and it clears no samples of the usable
rolls around it. X ellipse 57 of bench_explore --finite 20 --anywhere --seed 157 (development
seed since session 17; a 21.8, b 13.1: ρ = b²/a = 7.9 mm at the end the left pad rolled on):
the wider roll where an 18° roll was in doubt measured ρ −8.70 ± 1.01 mm, was taken for a sure
corner, and trimmed the left pad's two usable rolls; the object was refused."""

from pathlib import Path

import pytest

from hand_driver.config import load_config
from tactile_jaw.pipeline import (CORNER_RADIUS_MM, CORNER_SIGMAS, clear_of_corners, clearing_corners, clears_around,
                                  feel, on_corner)
from tests.tactile_jaw.test_wider_roll import _roll

DATA = Path(__file__).parent / "data" / "x_ellipse57_end_rolls.json"
CONFIG = load_config("config/jaw.yaml")


@pytest.fixture(scope="module")
def felt():
    return {k: feel(CONFIG, _roll(k, DATA), 9) for k in ("6", "8", "12")}


def test_the_wide_roll_is_no_curve_and_no_corner(felt):
    wide = felt["12"]
    assert wide.problem is not None and on_corner(wide.fit)  # still not used
    assert wide.fit.rho < -(CORNER_RADIUS_MM + CORNER_SIGMAS * wide.fit.sigma_rho)  # −8.7 ± 1.0 mm
    assert not clears_around(wide.fit)
    assert clearing_corners(list(felt.values())).shape == (0, 2)


def test_the_usable_rolls_are_kept_whole(felt):
    usable = [felt["6"], felt["8"]]
    assert all(t.problem is None for t in usable)
    kept, notes = clear_of_corners(CONFIG, usable, list(felt.values()), 9)
    assert notes == [] and kept == usable


def test_a_corner_near_zero_from_below_still_clears(felt):
    """The rule's other side: a pivot's radius scatters about 0 (a corner at −0.5 ± 1.0 mm,
    or −0.05 ± 0.02 mm on fine encoders) and still clears around it."""
    fit = felt["12"].fit
    for rho, sigma in ((-0.5, 1.0), (-0.05, 0.02), (-2.5, 1.0)):
        assert clears_around(fit.__class__(**{**fit.__dict__, "rho": rho, "sigma_rho": sigma}))
