"""The order rule on a finger whose joints are of different models (tactile_jaw.envelope.choose_degree,
JointNoise.order_test): exact circle rolls, each joint rounded to its own model's tick, take the
degree a finger of two coarse or two fine joints takes (docs/exploration.md#the-stated-noise)."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from hand_driver import kinematics as kin
from hand_driver.config import load_config
from tactile_jaw.envelope import JointNoise, fit_envelope

P_LEFT = load_config("config/jaw-p.yaml").finger("left")
X_LEFT = load_config("config/jaw.yaml").finger("left")
#: config/jaw-p.yaml's left finger with an XM430-W350 (4,096 ticks per turn) at its base joint and
#: its PH42-020-S300-R (607,500) at the distal one
MIXED_LEFT = replace(P_LEFT, joints=(replace(P_LEFT.joints[0], model="XM430-W350", zero_tick=2048.0),
                                     P_LEFT.joints[1]))
CENTRE, RADIUS = np.array([110.0, 0.0]), 20.0  # config/scenes/circle.yaml's circle


def chosen_degrees(finger, rolls: int = 12) -> list[int]:
    """The order rule's degree on exact 18° rolls of 9 readings on the circle (centres −110°…−70°),
    each joint rounded to its model's tick at a random encoder phase."""
    rng = np.random.default_rng(7)
    step = 2.0 * math.pi / kin.resolutions(finger.joints)
    out = []
    for _ in range(rolls):
        psis = math.radians(rng.uniform(-110.0, -70.0)) + np.radians(np.linspace(-9.0, 9.0, 9))
        q = np.array([kin.ik_tangent(finger, CENTRE - RADIUS * np.array([math.cos(p), math.sin(p)]), float(p))
                      for p in psis])
        phase = rng.uniform(0.0, 1.0, 2) * step
        q = np.round((q - phase) / step) * step + phase
        out.append(fit_envelope(finger, q, kin.finger_pad_line(finger, q)).contacts.degree)
    return out


@pytest.mark.parametrize("finger", [X_LEFT, P_LEFT, MIXED_LEFT], ids=["X", "P", "mixed"])
def test_circle_rolls_take_the_cubic(finger):
    """A circle's support function about its centre of curvature is a constant: no roll's readings
    show a term above the cubic beyond their noise; the mixed finger took degree 4–5 on every roll
    before its test weighed the fine joint at the coarse one's tick (40 of 40 at 5 or 4; X 37 of
    40 at 3, P 39 of 40)."""
    degrees = chosen_degrees(finger)
    assert sum(d == 3 for d in degrees) >= 10, degrees


def test_order_test_noise_floors_every_joint_at_the_coarsest_tick():
    noise = JointNoise((2.0 * math.pi / 4096, 2.0 * math.pi / 607_500), (1e-4, 0.0), (0.1, 0.0), 0.05)
    tested = noise.order_test()
    assert tested.tick_rad == pytest.approx((2.0 * math.pi / 4096,) * 2, rel=1e-15)
    assert (tested.offset_rad, tested.link_mm, tested.pad_mm) == (noise.offset_rad, noise.link_mm, noise.pad_mm)
    same = JointNoise((1e-3, 1e-3))
    assert same.order_test() == same


def test_the_p_series_jaw_keeps_its_order_test():
    """PH54 and PH42 (1,003,846 and 607,500 ticks per turn): the coarser one's second-order
    part (SECOND_ORDER_PER_RAD × tick², 9e-9 rad) lies far below the finer one's tick (6.3e-6):
    no floor, the order rule as before (tests/tactile_jaw/test_at_orientation.py's P roll)."""
    noise = JointNoise((2.0 * math.pi / 1_003_846, 2.0 * math.pi / 607_500))
    assert noise.order_test() is noise
