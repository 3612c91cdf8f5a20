"""Rolls kept on the curved part away from the object's end corners: a usable roll that ran
onto the end corner, dropped for too few samples clear of it, is rolled again beside its clear
stretch (tactile_jaw.pipeline.clear_side), and no planned roll reaches past where a finger's
rolls left the curve (tactile_jaw.explore.curve_limits, tactile_jaw.plan.within_curve)."""

import math

import numpy as np

from tactile_jaw.explore import curve_limits
from tactile_jaw.pipeline import CORNER_CLEARANCE_MM, clear_of_corners, clear_side, clearing_corners, feel
from tactile_jaw.plan import within_curve

from test_pipeline_feel import CONFIG, _arc_then_corner, quantized_touch

SAMPLES = 9
SPAN = math.radians(18.0)
CENTRE_PSI = math.radians(-80.0)


def _rolls():
    """A 9-sample roll on a circle of radius 20 whose last 3 readings pivot about the curve's end
    corner (as tests/tactile_jaw/test_pipeline_feel.py), a roll on that corner, and the contact
    function of the object."""
    step = SPAN / (SAMPLES - 1)
    contact, end = _arc_then_corner(CENTRE_PSI + math.pi + step * (SAMPLES // 2 - 3 + 0.5))
    psis = CENTRE_PSI + np.linspace(-0.5, 0.5, SAMPLES) * SPAN
    past = feel(CONFIG, quantized_touch(contact, psis), SAMPLES)
    on_corner = feel(CONFIG, quantized_touch(lambda psi: end, psis + math.radians(22.0)), SAMPLES)
    return past, on_corner, contact, end


def test_a_roll_dropped_at_the_corner_is_rolled_again_beside_its_clear_stretch():
    """The dropped roll keeps 5 of 9 samples clear of the corner (7 needed). The roll
    clear_side names touches the circle (its tangent line predicted within 0.3 mm, its contact
    within 1.5 mm along the pad, the X-series contacts' deviation at a roll's ends), every one
    of its contacts at least CORNER_CLEARANCE_MM from the corner, and it is usable and kept
    whole by the corner check; the same roll centred on the clear stretch is not."""
    past, on_corner, contact, end = _rolls()
    corners = clearing_corners([past, on_corner])
    assert clear_of_corners(CONFIG, [past], [past, on_corner], SAMPLES)[0] == []
    x, y, phi = clear_side(past, corners, SPAN, SAMPLES)
    psi = phi + math.pi / 2
    assert abs(np.array([math.cos(psi), math.sin(psi)]) @ (contact(psi) - (x, y))) < 0.3
    assert np.hypot(*(contact(psi) - (x, y))) < 1.5
    again = feel(CONFIG, quantized_touch(contact, psi + np.linspace(-0.5, 0.5, SAMPLES) * SPAN), SAMPLES)
    assert again.problem is None, again.problem
    assert np.min(np.hypot(again.contacts.x - end[0], again.contacts.y - end[1])) >= CORNER_CLEARANCE_MM
    kept, notes = clear_of_corners(CONFIG, [again], [past, on_corner, again], SAMPLES)
    assert kept == [again] and notes == []
    clear = past.contacts.psi[np.hypot(past.contacts.x - end[0], past.contacts.y - end[1]) >= CORNER_CLEARANCE_MM]
    centred = float(np.mean(clear)) + np.linspace(-0.5, 0.5, SAMPLES) * SPAN
    on_clear = feel(CONFIG, quantized_touch(contact, centred), SAMPLES)
    assert clear_of_corners(CONFIG, [on_clear], [past, on_corner, on_clear], SAMPLES)[0] == []


def test_no_corner_or_a_roll_clear_of_it_gives_no_place():
    past, on_corner, contact, end = _rolls()
    assert clear_side(past, np.zeros((0, 2)), SPAN, SAMPLES) is None
    far = np.array([[end[0] + 30.0, end[1]]])
    assert clear_side(past, far, SPAN, SAMPLES) is None


def test_planned_rolls_keep_short_of_where_the_finger_left_the_curve():
    """The finger felt the circle below the corner's pad orientations and the corner above:
    a roll reaching the corner's orientations, or beyond them, is out; one below is in; the
    other finger, which felt nothing, has no limits."""
    past, on_corner, contact, end = _rolls()
    limits = curve_limits("left", [past, on_corner], clearing_corners([past, on_corner]))
    assert limits and all(side > 0 for _, side in limits)
    assert not within_curve(CENTRE_PSI, SPAN, limits)  # the roll that ran onto the corner
    assert not within_curve(CENTRE_PSI + math.radians(22.0), SPAN, limits)  # the corner
    assert within_curve(CENTRE_PSI - math.radians(12.0), SPAN, limits)
    assert within_curve(CENTRE_PSI - math.radians(12.0) + 2 * math.pi, SPAN, limits)  # ψ's branch does not matter
    assert curve_limits("right", [past, on_corner], clearing_corners([past, on_corner])) == []
    assert curve_limits("left", [on_corner], clearing_corners([on_corner])) == []  # no curve felt: no limits
