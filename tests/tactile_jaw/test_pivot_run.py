"""A roll that ran off the curved part onto its end corner states that corner from the run of
its lines that turned about it (tactile_jaw.pipeline.pivot_run, FeltTouch.pivot), and the
sample another roll kept on it is cleared (on_pivots, clear_of_corners), not its samples beside
it on the curve: on the
P-series jaw such a roll is rough (neither a corner nor a segment crossing), so no corner was
stated, a usable roll kept its last sample 0.74 mm past the corner, and the answer was the
other branch's semicubical with σ's of 0.1 % (calibrated P semicubical 69 of bench_explore
--finite 10 --anywhere --seed 281). Exact quantized rolls on a circle of radius 20 mm whose
curved part ends at a corner E (tests/tactile_jaw/test_fine_corner_clearance.py)."""

import math

import numpy as np
import pytest

from hand_driver import kinematics as kin
from tactile_jaw.pipeline import clear_of_corners, clearing_corners, feel, on_pivots, pivot_run

from test_fine_corner_clearance import R, _rolls
from test_pipeline_feel import CENTRE, CONFIG, P_CONFIG, _arc_then_corner, _p_touch, quantized_touch


def _ran_onto_end(samples: int, span_deg: float, on_arc: int):
    """The left pad's roll whose first ``on_arc`` lines touch the arc and the rest pivot about
    the end corner, the usable roll of the same span that kept its last sample past that corner,
    and the corner."""
    past, _, end = _rolls(samples, span_deg)
    theta_end = math.atan2(end[1] - CENTRE[1], end[0] - CENTRE[0])
    contact, _ = _arc_then_corner(theta_end, R)
    step = math.radians(span_deg) / (samples - 1)
    psis = theta_end - math.pi + step * (np.arange(samples) - on_arc + 0.5)
    left = P_CONFIG.finger("left")
    ran = feel(P_CONFIG, _p_touch(np.array([kin.ik_tangent(left, contact(p), float(p)) for p in psis])), samples)
    return ran, past, end


@pytest.mark.parametrize("samples, span_deg, on_arc", [(9, 18.0, 3), (9, 18.0, 4), (15, 24.0, 4)])
def test_a_roll_that_ran_onto_the_end_corner_clears_the_sample_on_it(samples, span_deg, on_arc):
    ran, past, end = _ran_onto_end(samples, span_deg, on_arc)
    assert ran.problem is not None and "no smooth curve's tangents" in ran.problem, ran.problem
    assert ran.corner is None and ran.fit.rho > 2.0  # neither a corner roll nor a segment crossing
    assert not clearing_corners([past, ran]).size  # nothing cleared the 2 mm around it
    point, cov = ran.pivot
    assert math.hypot(point[0] - end[0], point[1] - end[1]) < 0.005  # P: lines to 0.3 µm
    assert 0.0 < math.sqrt(max(np.linalg.eigvalsh(cov))) < 0.005
    # the usable roll's last line rests on the corner; its others touch the arc (≥ 15 µm from it)
    np.testing.assert_array_equal(on_pivots(past, [ran.pivot]), np.arange(samples) == samples - 1)
    usable, notes = clear_of_corners(P_CONFIG, [past], [past, ran], samples)
    assert len(notes) == 1 and "pad line through the corner" in notes[0] and "used without them" in notes[0], notes
    assert len(usable) == 1 and usable[0].contacts.x.size == samples - 1
    off = np.abs(np.hypot(usable[0].contacts.x - CENTRE[0], usable[0].contacts.y - CENTRE[1]) - R)
    assert np.max(off) < 0.5e-3  # every sample left on the arc


def test_tangents_of_a_curve_turn_about_no_point():
    """A usable roll on the arc (P: radius 20 mm measured to 0.01 mm) has no run of lines
    through one point, and neither has a coarse (X-series) roll on a circle of radius 3 mm,
    whose three lines meet within their noise (0.05 mm) but whose radius cannot be told from
    a corner's at 2 σ."""
    past, _, _ = _rolls(9, 18.0)
    assert pivot_run(past.lines, past.contacts, past.fit.line_sigma) is None
    r = 3.0
    psis = math.radians(-80.0) + np.linspace(-0.5, 0.5, 9) * math.radians(18.0)
    coarse = feel(CONFIG, quantized_touch(lambda psi: CENTRE - r * np.array([math.cos(psi), math.sin(psi)]), psis), 9,
                  curve_checks=True)
    assert coarse.fit is not None and np.max(coarse.fit.line_sigma) > 0.01
    assert pivot_run(coarse.lines, coarse.contacts, coarse.fit.line_sigma) is None
