"""The errors a real servo puts between its encoder and its link, as the truth jaw declares them.

A DYNAMIXEL-P counts its pulses on the motor side of its gear, so what it reads is the motor's
angle m, not the link's angle ℓ; an X-series servo's encoder is on its output shaft, but its
gear train, horn and link still yield. The emulator simulates, per joint and pad, only what
the truth config declares (hand_driver.config: none declared, none simulated):

- **backlash** ``backlash_deg`` = 2h, a dead band between motor and link: unloaded, the link
  moves only when the motor drives it across the band (a play operator: m − ℓ stays in
  [−h, h] and changes only where it reaches its ends); loaded by a contact, the gear's teeth
  bear on the side the joint's torque τ pushes: m − ℓ = sign(τ)·h. So a joint whose load
  reverses reads 2h differently at the same link angle;
- **link compliance** ``compliance_deg_per_nm`` = c: the link and gear deflect by c·τ under
  the joint torque, m − ℓ = sign(τ)·h + c·τ;
- **pad compliance** ``pad.compliance_mm_per_n`` = k: the pad's face yields by δ = k·F under
  the contact force F, so the finger stands δ further in along the pad's normal than a rigid
  pad would (the links turn by Δℓ, Δℓ1 = δ / (L1 · n·e1⊥), Δℓ2 = −Δℓ1: the pad line moves δ
  along n at the same angle ψ);
- a **zero error** is the truth config's ``zero_tick`` differing from the nominal one (the
  emulator's encoder angles are the truth's).

The contact force F of a pad is the one that explains its joints' present currents best
(least squares of τ_j = Kt_j·I_j against τ_j = a_j·F, a_j = ((p − J_j) × n)_z the moment arm of a
force along the pad's normal n at the contact p, F ≥ 0), with each model's torque constant
Kt (hand_driver.control_table); it is judged once per integration span (a lag of one bus
packet), and used for the next.
"""

from __future__ import annotations

import math

import numpy as np

from hand_driver import kinematics as kin
from hand_driver.config import JawConfig

#: a joint torque below this (N·m) leaves the joint unloaded (its backlash in play)
LOADED_NM = 1e-3
#: a pad this close to the object (mm) touches it
TOUCH_MM = 0.05
#: a pad cannot be moved along its normal at a fixed angle when the base link is within
#: this of parallel to it (n·e1⊥ below it): its compliance is then not applied
SINGULAR_COS = 0.05


class ServoErrors:
    """The declared errors' state: per joint the encoder's lead over the link (rad), per pad
    its contact force; angles in config joint order, rad, the truth's."""

    def __init__(self, truth: JawConfig):
        joints = truth.joints
        self.cfg = truth
        self.half = np.radians([j.backlash_deg for j in joints]) / 2.0
        self.compliance = np.radians([j.compliance_deg_per_nm for j in joints])  # rad per N·m
        self.kt = np.array([j.spec.torque_nm_per_a for j in joints])
        self.pad_compliance = np.array([f.pad.compliance_mm_per_n for f in truth.fingers])
        n = len(joints)
        self.gap = np.zeros(n)  # motor − link (backlash and compliance)
        self.pad_dq = np.zeros(n)  # link − rigid-pad configuration (pad compliance)
        self.torque = np.zeros(n)  # the contact's load on each joint (N·m, counter-clockwise +)
        self.force = np.zeros(len(truth.fingers))  # each pad's contact force (N)

    def world_angles(self, motor) -> np.ndarray:
        """The configuration the contact world sees (a rigid pad at its nominal offset) for
        motor angles ``motor`` in the present state."""
        return np.asarray(motor, dtype=float) - self.gap - self.pad_dq

    def target(self, world_from, motor_to) -> tuple[np.ndarray, np.ndarray]:
        """(world angles the motors drive toward, the gap they keep) for motor angles
        ``motor_to``: loaded joints bear on their load's side, unloaded ones play."""
        link_from = np.asarray(world_from, dtype=float) + self.pad_dq
        motor_to = np.asarray(motor_to, dtype=float)
        loaded = np.abs(self.torque) > LOADED_NM
        play = np.clip(motor_to - link_from, -self.half, self.half)
        gap = np.where(loaded, np.sign(self.torque) * self.half + self.compliance * self.torque, play)
        return motor_to - gap - self.pad_dq, gap

    def settle(self, world, gap) -> np.ndarray:
        """Keep ``gap``; the motor angles at world angles ``world``."""
        self.gap = np.asarray(gap, dtype=float)
        return np.asarray(world, dtype=float) + self.gap + self.pad_dq

    def judge_load(self, contact_world, world, currents_ma) -> None:
        """Each pad's contact force from its joints' present currents (mA, each along its
        joint's angle; None: no sensing), and from it the joints' load and the pads' give,
        at world angles ``world`` (the next span uses them)."""
        q = np.asarray(world, dtype=float)
        infos = contact_world.contact_info(q) if contact_world is not None else [None] * len(self.cfg.fingers)
        torque, pad_dq, force = np.zeros_like(self.torque), np.zeros_like(self.pad_dq), np.zeros_like(self.force)
        k = 0
        for i, (f, info) in enumerate(zip(self.cfg.fingers, infos)):
            sl = slice(k, k + len(f.joints))
            k += len(f.joints)
            cur = currents_ma[sl]
            if info is None or not (info.penetrating or info.gap_mm <= TOUCH_MM) or any(c is None for c in cur):
                continue
            arms = kin.moment_arms(f, q[sl], info.point, kin.finger_pad_line(f, q[sl]).normal) / 1000.0  # m
            measured = self.kt[sl] * np.asarray(cur, dtype=float) / 1000.0
            norm = float(arms @ arms)
            force[i] = max(0.0, float(arms @ measured) / norm) if norm > 0 else 0.0
            torque[sl] = arms * force[i]
            pad_dq[sl] = _pad_give(f, q[sl], self.pad_compliance[i] * force[i])
        self.torque, self.force = torque, force
        self.pad_dq = pad_dq


def _pad_give(finger, q, depth_mm: float) -> np.ndarray:
    """Joint turns moving the pad line ``depth_mm`` along its normal at the same angle."""
    if depth_mm <= 0.0:
        return np.zeros(2)
    a1 = finger.base.angle + q[0]
    a2 = a1 + q[1]
    side = finger.pad.side_sign
    n = np.array([-side * math.sin(a2), side * math.cos(a2)])
    reach = finger.joints[0].link_mm * float(n @ np.array([-math.sin(a1), math.cos(a1)]))
    if abs(reach) < SINGULAR_COS * finger.joints[0].link_mm:
        return np.zeros(2)
    turn = depth_mm / reach
    return np.array([turn, -turn])
