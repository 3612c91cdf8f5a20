"""A first press's turn skips what the finger's earlier contacts already show
(hand_driver.flat_press.past_known): where the pad pivots about one support and earlier pad
lines farther that way pass through the same support, every approach between pivots about it
again (a boundary point's normal cone is an arc). Checked on exact stops (the emulator's
penetration test, bisected) of the line example's block turned 25°, and on exact tangents
of a circle, where nothing is skipped."""

import math

import numpy as np
import pytest

from hand_driver import kinematics as kin
from hand_driver.flat_press import FLAT_STEP_DEG, KNOWN_TOL_MM, face_normal, past_known
from hand_driver.sim.physics import ContactWorld
from tests.hand_driver.test_flat_press import CONFIG, _block_turned, _stop, _walk

STEP = math.radians(FLAT_STEP_DEG)


def _probe_lines(world, finger, centre_deg: float) -> list[kin.PadLine]:
    """A probe's four exact stops over 6° about ``centre_deg`` (tactile_jaw.plan's probes)."""
    return [_stop(world, finger, math.radians(centre_deg + off)) for off in (-3.0, -1.0, 1.0, 3.0)]


def test_a_walk_about_one_corner_skips_what_a_probe_showed():
    """The block turned 25°: from −90° the left pad pivots about the face's corner until it
    seats at −65°; a probe at −80° (lines −83…−77°) pivoted about the same corner, so the walk
    turns about it to −78°, the last step within the probe's lines, and seats on the same
    supports with one approach fewer (without the probe's lines: every 3° step)."""
    finger = CONFIG.finger("left")
    world = ContactWorld(CONFIG, _block_turned(25.0).object)
    psi0 = -math.pi / 2
    known = _probe_lines(world, finger, -80.0)
    plain, plain_lines = _walk(world, finger, psi0)
    found, lines = _walk(world, finger, psi0, known)
    assert plain is not None and found is not None
    turned = sorted(round(math.degrees(psi0 + k * STEP), 6) for k in lines)
    assert turned == sorted(round(math.degrees(psi0 + k * STEP), 6) for k in plain_lines if k * 3.0 - 90.0 != -81.0)
    assert len(lines) == len(plain_lines) - 1  # −81° (between the probe's lines) is not approached
    for a, b in zip(found[1:], plain[1:]):
        assert np.allclose(a, b, atol=1e-6)  # the same two supports
    n = face_normal(found[1], found[2], lines[max(lines)].normal)
    assert math.atan2(n[1], n[0]) == pytest.approx(psi0 + math.radians(25.0), abs=5e-3)


def test_lines_of_another_support_or_off_the_pad_are_not_followed():
    """Known lines through another point, or through the pivot only beyond the pad's end,
    leave the step as it was."""
    finger = CONFIG.finger("left")
    world = ContactWorld(CONFIG, _block_turned(25.0).object)
    psi0 = -math.pi / 2
    walk = [_stop(world, finger, psi0 + k * STEP) for k in (0, 1, 2)]
    x = kin.nearest_point(np.array([ln.normal for ln in walk]), np.array([float(ln.d) for ln in walk]))
    far = _probe_lines(world, finger, -80.0)
    shifted = [kin.PadLine(psi=ln.psi, d=ln.d + 3.0 * KNOWN_TOL_MM, normal=ln.normal, tangent=ln.tangent,
                           proximal=ln.proximal + 3.0 * KNOWN_TOL_MM * ln.normal,
                           distal=ln.distal + 3.0 * KNOWN_TOL_MM * ln.normal, joint2=ln.joint2) for ln in far]
    assert past_known(3.0, [0.0, 1.0, 2.0], walk, shifted, psi0, lambda k: True) == (3.0, None)
    beyond = [kin.PadLine(psi=ln.psi, d=ln.d, normal=ln.normal, tangent=ln.tangent,
                          proximal=x + 1.0 * ln.tangent, distal=x + 53.0 * ln.tangent, joint2=ln.joint2)
              for ln in far]  # the same lines, the pad moved along them past the pivot
    assert past_known(3.0, [0.0, 1.0, 2.0], walk, beyond, psi0, lambda k: True) == (3.0, None)
    k, pivot = past_known(3.0, [0.0, 1.0, 2.0], walk, far, psi0, lambda k: True)
    assert k == 4.0 and np.allclose(pivot, x, atol=KNOWN_TOL_MM)  # −78°, the last step within the lines


def test_tangents_of_a_circle_are_no_pivot():
    """A pad turning on a circle of radius 40 mm: its last three lines pass through no one point
    within KNOWN_TOL_MM, and lines tangent farther on are no reason to skip."""
    centre, r = np.array([110.0, 0.0]), 40.0

    def tangent(deg):
        a = math.radians(deg)
        n = np.array([math.cos(a), math.sin(a)])
        t = np.array([-n[1], n[0]])
        touch = centre - r * n
        return kin.PadLine(psi=np.float64(a), d=np.float64(n @ touch), normal=n, tangent=t,
                           proximal=touch - 26.0 * t, distal=touch + 26.0 * t, joint2=touch - 40.0 * t)

    psi0 = math.radians(-90.0)
    walk = [tangent(-90.0 + 3.0 * k) for k in (0, 1, 2)]
    known = [tangent(a) for a in (-83.0, -81.0, -79.0, -77.0)]
    assert past_known(3.0, [0.0, 1.0, 2.0], walk, known, psi0, lambda k: True) == (3.0, None)
