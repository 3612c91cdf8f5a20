"""Between two samples of a roll the pad backs off far enough that it keeps clear of the last
contact whichever joint arrives first (hand_driver.motion.uncoordinated_overshoot): each
servo runs its own trapezoidal profile, so on a short move the joint with the shorter way
ends first and the pad leaves the Cartesian path."""

from __future__ import annotations

import math

import numpy as np

from hand_driver import kinematics as kin
from hand_driver.config import load_config
from hand_driver.cycle import LIMIT_MARGIN_RAD
from hand_driver.motion import CORNER_CLEARANCE_MM, ROLL_CLEARANCE_MM, uncoordinated_overshoot

CONFIG = load_config("config/jaw-p.yaml")


class _Jaw:
    """What uncoordinated_overshoot asks of a jaw: its config, the finger's joint angles now
    and inverse kinematics nearest them."""

    def __init__(self, q):
        self.config, self.last_state, self._q = CONFIG, None, np.asarray(q, float)

    def finger_q(self, state, finger):
        return self._q

    def solve(self, finger, psi, d, q_ref):
        sols = [q for q in kin.ik_line_solutions(CONFIG.finger(finger), psi, d)
                if kin.within_limits(CONFIG.finger(finger).joints, q, LIMIT_MARGIN_RAD)]
        return min(sols, key=lambda q: float(np.sum((q - q_ref) ** 2)))


def _kinks(finger, q0, q1):
    """The pad lines where each joint but the last arrives, the joints turning alike."""
    dq = q1 - q0
    return [kin.finger_pad_line(finger, q0 + np.sign(dq) * np.minimum(np.abs(dq), s)) for s in np.sort(np.abs(dq))[:-1]]


def test_the_pad_keeps_clear_of_the_contact_whichever_joint_arrives_first():
    """The left pad in contact at pad normals about −110° (a roll on a random parabola of the
    P-series bench, where 30 of 38 turns stalled): turned 2.25° and backed off the roll's
    1 mm, the base joint's shorter way ends first and that pad line passes beyond the
    contact; with the overshoot added, every such line keeps ``CORNER_CLEARANCE_MM``."""
    f = CONFIG.finger("left")
    crossed = 0
    for psi0_deg in (-111.0, -100.0, -90.0, -80.0):
        for u in (10.0, 26.0, 42.0):  # contact along the pad (mm from its proximal end)
            psi0 = math.radians(psi0_deg)
            q0 = kin.ik_line(f, psi0, 20.0, margin_rad=LIMIT_MARGIN_RAD)
            line0 = kin.finger_pad_line(f, q0)
            pivot = line0.proximal + u * line0.tangent
            jaw = _Jaw(q0)
            psi1 = psi0 + math.radians(2.25)
            d = float(kin.unit(psi1) @ pivot) - ROLL_CLEARANCE_MM
            plain = min(float(line.normal @ pivot) - float(line.d)
                        for line in _kinks(f, q0, jaw.solve("left", psi1, d, q0)))
            crossed += plain < 0.0
            extra = uncoordinated_overshoot(jaw, "left", psi1, d, pivot)
            assert extra >= 0.0
            q1 = jaw.solve("left", psi1, d - extra, q0)
            clear = min(float(line.normal @ pivot) - float(line.d) for line in _kinks(f, q0, q1))
            assert clear >= CORNER_CLEARANCE_MM - 0.05, (psi0_deg, u, clear, extra)
            assert extra <= 10.0
    assert crossed > 0  # the plain 1 mm back-off does let a pad line pass the contact somewhere
