"""One load-direction model (kinematics.moment_arms) for the emulator's backlash, the
calibration and the exploration's touches, and what a touch states for it
(tactile_jaw.pipeline.touch_loads, tactile_jaw.envelope.joint_noise): a joint whose load keeps
a known direction over a touch is read with its backlash taken out and states only its
calibrated zero's standard error; one whose load is not known to stay one way states its half
band. Checked against exact geometry: rolls on a circle read through encoders that lead their
links by the band's half on the side of each joint's load, as the emulator's gears do."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from hand_driver import kinematics as kin
from hand_driver.config import load_config
from tactile_jaw.envelope import joint_noise
from tactile_jaw.pipeline import LOAD_KNOWN_ARM_MM, feel, touch_loads
from tests.tactile_jaw.test_envelope_order import touch as read_at  # the same jaw's geometry and ticks: a touch read at joint angles

BAND_DEG = 0.1
ZERO_SIGMA_DEG = 0.0004
NOMINAL = load_config("config/jaw-p.yaml")
CONFIG = replace(NOMINAL, fingers=tuple(
    replace(f, joints=tuple(replace(j, backlash_deg=BAND_DEG, zero_sigma_deg=ZERO_SIGMA_DEG) for j in f.joints))
    for f in NOMINAL.fingers))
LEFT = CONFIG.finger("left")


def test_moment_arms_closed_form_and_vectorized():
    """Along the pad's normal (the default direction) at u mm along the distal link from its
    joint: distal arm side·u, proximal side·(L1·cos q2 + u); rows of a stack equal single calls."""
    rng = np.random.default_rng(4)
    for finger in CONFIG.fingers:
        q = np.stack([rng.uniform(-1.5, 1.5, 30), rng.uniform(-2.8, 2.8, 30)], axis=-1)
        line = kin.finger_pad_line(finger, q)
        u = rng.uniform(13.0, 65.0, 30)  # along the distal link (the pad spans 13..65 mm)
        p = line.distal - (finger.joints[1].link_mm - u)[:, None] * line.tangent
        arms = kin.moment_arms(finger, q, p)
        side = finger.pad.side_sign
        assert np.allclose(arms[:, 1], side * u, atol=1e-9)
        assert np.allclose(arms[:, 0], side * (finger.joints[0].link_mm * np.cos(q[:, 1]) + u), atol=1e-9)
        for i in range(0, 30, 7):
            assert np.allclose(kin.moment_arms(finger, q[i], p[i], line.normal[i]), arms[i], atol=1e-12)


def circle_roll(q2: float, pad_u: float, r: float = 15.0, span_deg: float = 16.0, n: int = 9):
    """The left pad rolling on a circle of radius ``r`` it first touches ``pad_u`` mm from its
    proximal end with its distal joint at ``q2``: true link angles (n, 2) and the circle's centre."""
    q0 = np.array([0.3, q2])
    line = kin.finger_pad_line(LEFT, q0)
    contact = line.proximal + pad_u * line.tangent
    centre = contact + r * line.normal  # the pad presses along its normal into the object
    psis = float(line.psi) + np.radians(np.linspace(-span_deg / 2, span_deg / 2, n))
    q = []
    for psi in psis:
        n_psi = kin.unit(psi)
        q_i = kin.ik_tangent(LEFT, centre - r * n_psi, float(psi), pad_u=pad_u)
        q.append(q_i)
    return np.array(q), centre


def read_through_gears(q_link):
    """The touch the encoders report: each joint's link angle plus (s − w)·h (its gear bears
    on its load's side s; zero_tick holds the working load w), every joint rounded to a tick."""
    s = np.sign(kin.moment_arms(LEFT, q_link, _contacts(q_link)))
    assert np.all(s == s[0]), "the true load must keep its direction over the roll"
    return read_at(q_link + kin.load_offsets(LEFT, s)), s[0]



_CENTRE = {}


def _contacts(q_link):
    line = kin.finger_pad_line(LEFT, q_link)
    c = _CENTRE["c"]
    return c - _CENTRE["r"] * line.normal


@pytest.mark.parametrize("q2, pad_u", [(0.9, 26.0), (2.1, 10.0)])
def test_a_known_load_is_taken_out_and_only_the_zero_error_is_stated(q2, pad_u):
    """Under its working load (q2 = 0.9) no joint is offset; folded (q2 = 2.1, contact 23 mm
    along the distal link) the base joint bears against it, reads a whole band (0.1°) off,
    and is read back: the contacts lie on the true circle within their stated deviations, and
    the stated offset σ is the zero's standard error alone."""
    q_link, centre = circle_roll(q2, pad_u)
    _CENTRE.update(c=centre, r=15.0)
    touch, s = read_through_gears(q_link)
    w = kin.working_loads(LEFT)
    q_enc = kin.ticks_to_angles(LEFT.joints, np.array([x.ticks for x in touch.samples]))
    loads = touch_loads(LEFT, q_enc, kin.finger_pad_line(LEFT, q_enc))
    assert loads.known == (True, True) and loads.reversed is None
    assert np.allclose(loads.offsets, kin.load_offsets(LEFT, s)), (loads.offsets, s)
    against = s != w
    assert list(against) == ([True, False] if q2 > 2 else [False, False])
    assert np.allclose(joint_noise(LEFT, loads.known).offset_rad, math.radians(ZERO_SIGMA_DEG))
    felt = feel(CONFIG, touch, len(touch.samples))
    assert felt.problem is None, felt.problem
    c = felt.contacts
    radial = np.hypot(c.x - centre[0], c.y - centre[1]) - 15.0
    assert np.max(np.abs(radial / felt.fit.sigma_across)) < 4.0, radial
    if against[0]:  # not taken out, the same readings miss the circle by the band's lever
        raw = feel(replace(CONFIG, fingers=(replace(LEFT, joints=tuple(replace(j, backlash_deg=0.0)
                                                                         for j in LEFT.joints)),
                                            CONFIG.fingers[1])), touch, len(touch.samples))
        miss = np.hypot(raw.contacts.x - centre[0], raw.contacts.y - centre[1]) - 15.0
        assert np.max(np.abs(miss)) > 20 * np.max(np.abs(radial)) and np.max(np.abs(miss)) > 0.02


def test_a_load_near_a_joints_line_of_action_states_its_half_band():
    """Short rolls on a small circle with the finger folded so that the base joint's arm is
    near 0: one whose arm keeps its sign within LOAD_KNOWN_ARM_MM of 0 is not known to rest on
    either side of its band (not offset; its stated offset √(z² + (b/2)²)); one whose arm
    changes sign reversed, and feel refuses it."""
    near, crossing = None, None
    for pad_u in np.arange(5.0, 30.0, 0.25):
        q, centre = circle_roll(1.9, float(pad_u), r=1.0, span_deg=1.0)
        line = kin.finger_pad_line(LEFT, q)
        arms = kin.moment_arms(LEFT, q, centre - 1.0 * line.normal)[:, 0]
        if np.all(np.abs(arms) < LOAD_KNOWN_ARM_MM) and (np.all(arms > 0) or np.all(arms < 0)):
            near = near or (q, line)
        if np.any(arms > 0) and np.any(arms < 0):
            crossing = crossing or (q, centre)
    assert near is not None and crossing is not None
    loads = touch_loads(LEFT, *near)
    assert loads.known == (False, True) and loads.reversed is None
    assert not np.any(loads.offsets[:, 0]) and np.all(loads.offsets[:, 1] == 0.0)  # distal: working load
    noise = joint_noise(LEFT, loads.known)
    assert noise.offset_rad[0] == pytest.approx(math.radians(math.hypot(ZERO_SIGMA_DEG, BAND_DEG / 2)))
    assert noise.offset_rad[1] == pytest.approx(math.radians(ZERO_SIGMA_DEG))
    q, centre = crossing
    line = kin.finger_pad_line(LEFT, q)
    assert touch_loads(LEFT, q, line).reversed == 0
    touch = read_at(q)
    felt = feel(CONFIG, touch, len(touch.samples))
    assert felt.problem is not None and "reversed" in felt.problem
    # without backlash declared, every joint is known and never offset
    plain = NOMINAL.finger("left")
    loads = touch_loads(plain, *near)
    assert loads.known == (True, True) and not np.any(loads.offsets)
