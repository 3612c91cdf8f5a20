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

Where the truth declares no compliance (backlash and zero errors only: every shipped truth
config), the contact force F of a pad is the one that explains its joints' present currents best
(least squares of τ_j = Kt_j·I_j against τ_j = a_j·F, a_j = ((p − J_j) × u)_z the moment arm of a
force along u at the contact p, F ≥ 0; u is the pad's normal where its face touches, the
object's normal where a pad end presses it; kinematics.balanced_force), with each model's torque constant
Kt (hand_driver.control_table); it is judged once per integration span (a lag of one bus
packet), and used for the next (:meth:`ServoErrors.judge_load`): the currents are the servos'
position lag, and only the side of the load matters.

Where it declares compliance (some joint's c or pad's k), the deflection is what a reading
measures, so the load is a **torque balance of one instant** (:meth:`ServoErrors.balance`, at
the end of every span, before the servos publish): a pad touching the object carries the force
F ≥ 0 along u that its servos' drive (each one's lag current, hand_driver.sim.servo) pushes
with, the least-squares F of τ_j = a_j·F against the drive (kinematics.balanced_force), no larger than the weakest joint's
current cap allows; the joints then carry exactly τ_j = a_j·F (the drive's part across a_j is
held by the finger's static friction, as a blocked finger's is), deflect by c·τ_j and the pad
gives k·F, the motors stand where the links and the deflection put them, and each blocked
servo's Present Current is the balance Kt_j·I_j = τ_j (the e-Manual states no gear friction,
so none is added). F, the deflection and the motors' position depend on each other through
the drive (the motor's lead over its trajectory); the balance is their fixed point, a
contraction of ratio c·K + k·K/L² ≈ 0.02 for the servos' 14 A/rad (K ≈ 64 N·m/rad on a PH54):
``BALANCE_ITERATIONS`` settle it far below a tick. So a reading's ticks and currents are of
one instant, and Kt·I explains its deflection to the current's resolution.
"""

from __future__ import annotations

import numpy as np

from hand_driver import kinematics as kin
from hand_driver.config import JawConfig

#: a joint torque below this (N·m) leaves the joint unloaded (its backlash in play)
LOADED_NM = 1e-3
#: a pad this close to the object (mm) touches it
TOUCH_MM = 0.05
#: a contact this close (mm) to an end of the pad is a pad end pressing the object
END_MM = 0.05
#: fixed-point passes of a torque balance (module docstring: each shrinks the force's error
#: by about 50×), and the relative change of the force at which it has settled
BALANCE_ITERATIONS = 12
BALANCE_SETTLED = 1e-12


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
        #: some finger declares a link or pad compliance (kinematics.declares_compliance): the load
        #: is a torque balance of one instant (:meth:`balance`), not judged from the last span's
        #: currents (:meth:`judge_load`)
        self.balanced = any(kin.declares_compliance(f) for f in truth.fingers)

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
            arms = kin.moment_arms(f, q[sl], info.point, _force_direction(contact_world, f, q[sl], info)) / 1000.0
            force[i] = float(kin.balanced_force(arms, self.kt[sl] * np.asarray(cur, dtype=float) / 1000.0))
            torque[sl] = arms * force[i]
            pad_dq[sl] = _pad_give(f, q[sl], self.pad_compliance[i] * force[i])
        self.torque, self.force = torque, force
        self.pad_dq = pad_dq

    def balance(self, contact_world, world, drive) -> tuple[np.ndarray, np.ndarray]:
        """The torque balance of this instant (module docstring) at world angles ``world``, the
        motors' gap as the span's steps left it: ``drive(motor)`` → (each joint's drive torque
        toward its trajectory with its motor at ``motor`` rad, N·m along its angle, NaN without
        current sensing; each joint's largest |torque|, N·m). Sets each pad's force, the joints'
        torques, gaps and the pads' give; returns (the motor angles, each joint's balanced
        torque, N·m, NaN where its finger carries no force: its servos draw their lag current)."""
        q = np.asarray(world, dtype=float)
        infos = contact_world.contact_info(q) if contact_world is not None else [None] * len(self.cfg.fingers)
        play = np.clip(self.gap, -self.half, self.half)  # unloaded, a joint's deflection springs back
        torque, force = np.zeros_like(self.torque), np.zeros_like(self.force)
        gap, pad_dq = play.copy(), np.zeros_like(self.pad_dq)
        balanced = np.full_like(self.torque, np.nan)
        k = 0
        for i, (f, info) in enumerate(zip(self.cfg.fingers, infos)):
            sl = slice(k, k + len(f.joints))
            k += len(f.joints)
            if info is None or not (info.penetrating or info.gap_mm <= TOUCH_MM):
                continue
            arms = kin.moment_arms(f, q[sl], info.point, _force_direction(contact_world, f, q[sl], info)) / 1000.0
            if not np.any(arms):  # the press loads no joint
                continue
            force_i = self.force[i]
            for _ in range(BALANCE_ITERATIONS):
                motor = q.copy()
                motor[sl] += self._loaded_gap(sl, arms * force_i, play[sl]) + _pad_give(
                    f, q[sl], self.pad_compliance[i] * force_i)
                push, cap = (a[sl] for a in drive(motor))
                if np.any(np.isnan(push)):  # a joint senses no current: no balance to read
                    force_i = 0.0
                    break
                bound = min((float(c / abs(a)) for a, c in zip(arms, cap) if a != 0.0), default=0.0)
                new = min(float(kin.balanced_force(arms, push)), bound)
                settled = abs(new - force_i) <= BALANCE_SETTLED * max(new, 1.0)
                force_i = new
                if settled:
                    break
            if force_i <= 0.0:
                continue
            force[i] = force_i
            tau = arms * force_i
            torque[sl] = tau
            pad_dq[sl] = _pad_give(f, q[sl], self.pad_compliance[i] * force[i])
            gap[sl] = self._loaded_gap(sl, tau, play[sl])
            balanced[sl] = tau
        self.torque, self.force, self.gap, self.pad_dq = torque, force, gap, pad_dq
        return q + gap + pad_dq, balanced

    def _loaded_gap(self, sl: slice, tau, play) -> np.ndarray:
        """Motor − link of joints ``sl`` under torques ``tau``: sign(τ)·h + c·τ where loaded,
        ``play`` where not."""
        return np.where(np.abs(tau) > LOADED_NM, np.sign(tau) * self.half[sl] + self.compliance[sl] * tau, play)


def _force_direction(contact_world, finger, q, info) -> np.ndarray:
    """The direction of the force a pad applies at its contact: its normal where its face
    touches, the object's normal (into the object) where a pad end does."""
    normal = kin.finger_pad_line(finger, q).normal
    if END_MM < info.pad_u_mm < finger.pad.length_mm - END_MM:
        return normal
    surface = contact_world.surface_direction(info.point)
    if surface is None:
        return normal
    return surface if float(surface @ normal) >= 0.0 else -surface


def _pad_give(finger, q, depth_mm: float) -> np.ndarray:
    """Joint turns moving the pad line ``depth_mm`` along its normal at the same angle
    (kinematics.give_turns)."""
    return kin.give_turns(finger.base.angle, q, finger.joints[0].link_mm, finger.pad.side_sign, depth_mm)
