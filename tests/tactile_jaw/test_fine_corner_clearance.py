"""A corner measured by fine encoders clears the samples around it (tactile_jaw.pipeline.
clears_around): on the P-series jaw a roll that began on the curve's end and pivoted about its
end corner measures a radius of curvature of a tenth of a millimetre, many of its deviations
from 0 (so the coarse rule ρ < σ_ρ did not count it), and a roll that ran onto that corner kept
its last sample off the curve. Exact quantized rolls on a circle of radius 20 mm whose curved
part ends at a corner (tests/tactile_jaw/test_pipeline_feel.py)."""

import math

import numpy as np
import pytest

from hand_driver import kinematics as kin
from tactile_jaw.pipeline import (CLEARANCE_SIGMAS, CORNER_CLEARANCE_MM, CORNER_RADIUS_MM, clear_of_corners,
                                  clearing_corners, clears_around, corner_clearance, feel)

from test_pipeline_feel import CENTRE, CONFIG, P_CONFIG, _arc_then_corner, _p_touch, quantized_touch

R = 20.0
CENTRE_PSI = math.radians(-80.0)


def _rolls(samples: int, span_deg: float):
    """A roll on the circle whose last reading is past the curve's end (it pivots about the end
    corner), a roll whose first reading is on the arc and the rest pivot about that corner,
    and the corner."""
    left = P_CONFIG.finger("left")
    span = math.radians(span_deg)
    step = span / (samples - 1)
    theta_end = CENTRE_PSI + math.pi + step * (samples // 2 - 1 + 0.5)
    contact, end = _arc_then_corner(theta_end, R)

    def touch(psis):
        return _p_touch(np.array([kin.ik_tangent(left, contact(p), float(p)) for p in psis]))

    past = feel(P_CONFIG, touch(CENTRE_PSI + np.linspace(-0.5, 0.5, samples) * span), samples)
    pivot = feel(P_CONFIG, touch(theta_end - math.pi + step * (np.arange(samples) - 0.5)), samples)
    return past, pivot, end


def _off_circle_um(c) -> np.ndarray:
    return 1000.0 * np.abs(np.hypot(c.x - CENTRE[0], c.y - CENTRE[1]) - R)


@pytest.mark.parametrize("samples, span_deg, kept", [(9, 18.0, 7), (15, 24.0, 13)])
def test_a_fine_corner_clears_the_samples_of_a_roll_that_ran_onto_it(samples, span_deg, kept):
    past, pivot, end = _rolls(samples, span_deg)
    assert past.problem is None, past.problem  # nothing in the roll itself tells
    off = _off_circle_um(past.contacts)
    assert off[-1] > 1.0 and off[-1] > 5 * np.max(off[:-1])  # its last contact off the curve (P: 0.1-0.4 µm noise)
    assert pivot.corner is not None and math.hypot(pivot.corner[0] - end[0], pivot.corner[1] - end[1]) < 0.01
    rho, sigma = pivot.fit.rho, pivot.fit.sigma_rho
    assert CLEARANCE_SIGMAS * sigma < rho < CORNER_RADIUS_MM / 5  # told from 0, yet no curve's radius
    assert clears_around(pivot.fit)
    np.testing.assert_allclose(clearing_corners([past, pivot]), [pivot.corner])
    usable, notes = clear_of_corners(P_CONFIG, [past], [past, pivot], samples)
    clearance = corner_clearance(past)  # one step's arc on these fine lines (0.6-0.8 mm), not 2 mm
    assert 0.5 < clearance < CORNER_CLEARANCE_MM
    assert len(notes) == 1 and f"within {clearance:.2g} mm of the corner" in notes[0], notes
    if kept:
        assert len(usable) == 1 and usable[0].contacts.x.size == kept
        assert np.max(_off_circle_um(usable[0].contacts)) < 0.5
    else:
        assert usable == []


def test_a_coarse_hump_still_clears_nothing():
    """The rule's other side: a radius told from 0 but not below CORNER_RADIUS_MM by its
    deviation (an X-series hump measured as a corner, ρ 6.5 ± 3.6 mm; a fine roll at 0.9 ±
    0.2 mm) clears nothing."""
    _, pivot, _ = _rolls(9, 18.0)
    for rho, sigma in ((6.5, 3.6), (0.9, 0.2)):
        fit = pivot.fit.__class__(**{**pivot.fit.__dict__, "rho": rho, "sigma_rho": sigma})
        assert not clears_around(fit)


def test_the_clearance_is_the_arc_the_lines_leave_in_doubt():
    """corner_clearance: on P-series lines (0.2 µm) one sample step's arc ρΔψ, within which the
    envelope fit places a pivoting sample's contact (0.2 mm from the corner here), every sample
    beyond it on the circle; on X-series lines (σ ≈ 0.05 mm) the 2 mm measured there, √(2σρ)
    being larger."""
    past, _, end = _rolls(9, 18.0)
    clearance = corner_clearance(past)
    assert clearance == pytest.approx(R * math.radians(18.0) / 8, rel=0.02)
    gaps = np.hypot(past.contacts.x - end[0], past.contacts.y - end[1])
    assert np.all(_off_circle_um(past.contacts)[gaps >= clearance] < 0.5)
    assert _off_circle_um(past.contacts)[np.argmin(gaps)] > 1.0 and np.min(gaps) < clearance
    psis = CENTRE_PSI + np.linspace(-0.5, 0.5, 9) * math.radians(18.0)
    contact, _ = _arc_then_corner(CENTRE_PSI + math.pi + math.radians(18.0) / 8 * 1.5, R)
    coarse = feel(CONFIG, quantized_touch(contact, psis), 9)
    assert coarse.problem is None, coarse.problem
    assert corner_clearance(coarse) == CORNER_CLEARANCE_MM
