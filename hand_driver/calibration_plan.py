"""Calibration touch plan: where each finger touches a reference disk (pure geometry).

For each finger, face touches spread over its reachable pad orientations on both
inverse-kinematics branches and corner/heel touches spread around the reachable arc
(why both kinds: hand_driver.calibration_fit). :func:`synthesize` turns a plan into the
readings a jaw of known geometry would produce (tests and benchmarks).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from hand_driver import kinematics as kin
from hand_driver.calibration_fit import Reading
from hand_driver.config import JawConfig
from tactile_common.angles import wrap_angle
from tactile_common.errors import InputError

#: suggested placements of the reference disk (hand frame, mm). A base joint's zero tick
#: is fixed only through the disk centre's distance from each base (trilateration by the
#: two fingers), and that distance trades against the proximal ``link_mm``, which face
#: touches separate only through the spread of cos(q2) over the touches. Disks straight
#: ahead give each finger a narrow q2 range (base zero ticks to ~0.6 tick standard error
#: with (60,0), (85,±10)); a disk off to each side makes the finger on that side fold, and
#: (60,0), (85,0), (70,±30) give ~0.25 tick with the same number of touches (Fisher
#: information of the default plan, confirmed on the emulated bus).
DEFAULT_PLACEMENTS = ((60.0, 0.0), (85.0, 0.0), (65.0, 30.0), (65.0, -30.0))

#: a corner touch needs the pad to leave the object at least this steeply (rad)
CORNER_TILT_RAD = math.radians(20.0)


@dataclass(frozen=True)
class PlannedTouch:
    """Where to touch: ``face`` at pad normal angle ``psi``, or ``corner`` at ``point``
    approached along ``-direction`` (the reference's outward normal there); ``q`` is the
    nominal contact configuration (rad), which fixes the inverse-kinematics branch."""

    finger: str
    kind: str
    psi: float
    point: tuple[float, float]
    direction: tuple[float, float]
    q: tuple[float, float]


def plan_touches(cfg: JawConfig, reference, center, faces: int = 14, corners: int = 8,
                 margin_rad: float = math.radians(3.0), clearance_mm: float = 2.0,
                 gap: float = 3.0, accept=None) -> list[PlannedTouch]:
    """The calibration touch plan on a disk of the reference's radius centred at ``center``
    (the expected position). Per finger and inverse-kinematics branch: ``faces`` pad
    orientations evenly over the reachable range (contact ≥ 3 mm inside the pad), and
    ``corners`` contacts of each pad end ('corner': the fingertip end, 'heel': the
    proximal end) evenly over the reachable arc, with the pad leaving the disk by ≥ 20°.
    Only configurations whose links clear the disk by ``clearance_mm`` are used (the
    links are not modelled by the emulator, but they are real), only contacts whose
    approach pose ``gap`` mm outside the disk is inside the joint limits too, and, with
    ``accept(finger, q_approach) -> bool``, only approach poses it accepts (a clear path)."""
    if reference.cls != "circle":
        raise InputError("the calibration touch plan needs a disk reference (class circle)")
    r = float(reference.params["r"])
    c = np.asarray(center, dtype=float)
    plan: list[PlannedTouch] = []
    grid = np.linspace(-np.pi, np.pi, 181)[:-1]  # 2° steps
    for f in cfg.fingers:
        def clear(q) -> bool:
            line = kin.finger_pad_line(f, q)
            base = np.array([f.base.x, f.base.y])
            tip = line.joint2 + f.joints[1].link_mm * line.tangent
            return (_segment_distance(c, base, line.joint2) >= r + clearance_mm
                    and _segment_distance(c, line.joint2, tip) >= r + clearance_mm)

        face_ok = []
        for psi in grid:
            n = kin.unit(psi)
            pt = c - r * n
            pre = [q for q in kin.ik_line_solutions(f, psi, float(n @ c) - r - gap)
                   if kin.within_limits(f.joints, q, margin_rad)]
            for q in kin.ik_line_solutions(f, psi, float(n @ c) - r):
                u = float(kin.finger_pad_line(f, q).pad_coordinate(pt))
                if kin.within_limits(f.joints, q, margin_rad) and 3.0 <= u <= f.pad.length_mm - 3.0 and clear(q):
                    near = [p for p in pre if np.sum(wrap_angle(p - q) ** 2) < 0.25]
                    if near:
                        face_ok.append((psi, q, pt, near[0]))
        plan += _spread(f.name, "face", face_ok, faces, lambda it: (it[0], (-math.cos(it[0]), -math.sin(it[0]))),
                        None if accept is None else lambda it, name=f.name: accept(name, it[3]))
        for kind, end, sign in (("corner", "distal", -1.0), ("heel", "proximal", 1.0)):
            ok = []
            for beta in grid:
                m = kin.unit(beta)
                pt = c + r * m
                pre = kin.ik_corner(f, c + (r + gap) * m, margin_rad, end=end)
                for q in kin.ik_corner(f, pt, margin_rad, end=end):
                    line = kin.finger_pad_line(f, q)
                    if float(sign * line.tangent @ m) >= math.sin(CORNER_TILT_RAD) and clear(q):
                        near = [p for p in pre if np.sum(wrap_angle(p - q) ** 2) < 0.25]
                        if near:
                            ok.append((beta, q, pt, near[0]))
            plan += _spread(f.name, kind, ok, corners, lambda it: (float("nan"), (math.cos(it[0]), math.sin(it[0]))),
                            None if accept is None else lambda it, name=f.name: accept(name, it[3]))
    return plan


def _segment_distance(p, a, b) -> float:
    ab = b - a
    t = float(np.clip((p - a) @ ab / max(float(ab @ ab), 1e-300), 0.0, 1.0))
    return float(np.hypot(*(p - a - t * ab)))


def _spread(finger: str, kind: str, items: list, count: int, meta, accept=None) -> list[PlannedTouch]:
    """``count`` items evenly over the sorted angle range, per IK branch (sign of q2); with
    ``accept(item) -> bool`` each pick moves to the nearest accepted item not yet taken."""
    out = []
    for branch in (1.0, -1.0):
        sel = sorted((it for it in items if math.copysign(1.0, it[1][1]) == branch), key=lambda it: it[0])
        if len(sel) < 2:
            continue
        taken: set[int] = set()
        for i in np.unique(np.round(np.linspace(0, len(sel) - 1, count)).astype(int)):
            order = sorted(range(len(sel)), key=lambda k: abs(k - i))[:max(3, len(sel) // count)]
            pick = next((k for k in order if k not in taken and (accept is None or accept(sel[k]))), None)
            if pick is None:
                continue
            taken.add(pick)
            q, pt = sel[pick][1], sel[pick][2]
            psi, direction = meta(sel[pick])
            out.append(PlannedTouch(finger, kind, float(psi), (float(pt[0]), float(pt[1])), direction,
                                    (float(q[0]), float(q[1]))))
    return out


def synthesize(truth: JawConfig, reference, nominal_plan: list[PlannedTouch], quantize: bool = True,
               placement: int = 0, forces_n=None) -> list[Reading]:
    """Readings a jaw with geometry ``truth`` would produce for a plan (tests and
    benchmarks): the exact truth contact configuration on the same IK branch (face touches
    whose tangent point falls off the truth pad are left out: a pad end would touch), as ticks
    of the truth zero ticks, each encoder leading its link by half the truth's declared
    backlash toward its load (the sign of the moment arm of the pressing force: along the pad's
    normal, or toward the disk's centre for a pad end; zero_tick is the zero under the working
    load, kinematics.load_offsets), rounded to whole ticks as the encoders do (unless
    quantize=False). With ``forces_n`` (one per planned touch, N) each touch presses with that
    force F and its reading carries its joints' currents, the torque balance Kt·I = τ_j = a_j·F
    rounded to each model's current unit (hand_driver.sim.errors): the pad's face gives k·F (its
    links turned to put its line k·F further in at the same angle, kinematics.give_turns) and each
    encoder leads its link by c·τ_j more."""
    out = []
    r = float(reference.params["r"])
    c = np.array([reference.pose.x, reference.pose.y])
    for k, t in enumerate(nominal_plan):
        f = truth.finger(t.finger)
        force = None if forces_n is None else float(forces_n[k])
        if t.kind == "face":
            n = kin.unit(t.psi)
            sols = kin.ik_line_solutions(f, t.psi, float(n @ c) - r)
        else:
            pt = c + r * np.asarray(t.direction)
            sols = kin.ik_corner(f, pt, margin_rad=-math.pi, end="distal" if t.kind == "corner" else "proximal")
        if not sols:
            continue
        q = min(sols, key=lambda s: float(np.sum(wrap_angle(s - np.asarray(t.q)) ** 2)))
        line = kin.finger_pad_line(f, q)
        if t.kind == "face":  # the tangent point off the truth pad: a pad end would touch instead
            point, direction = c - r * line.normal, line.normal
            if not 0.0 <= float(line.pad_coordinate(point)) <= f.pad.length_mm:
                continue
        else:
            point = line.distal if t.kind == "corner" else line.proximal
            direction = (c - point) / r
        arms = kin.moment_arms(f, q, point, direction)
        lead = kin.load_offsets(f, np.sign(arms))
        currents = None
        if force is not None:  # the pad's give turns the links (kinematics.give_turns), the torques lead the motors
            torque = arms / 1000.0 * force
            q = q + kin.give_turns(f.base.angle, q, f.joints[0].link_mm, f.pad.side_sign,
                                   f.pad.compliance_mm_per_n * force)
            lead = lead + np.radians([j.compliance_deg_per_nm for j in f.joints]) * torque
            currents = tuple(_balance_current(j, tau) for j, tau in zip(f.joints, torque))
        ticks = kin.angles_to_ticks(f.joints, q + lead)
        if quantize:
            ticks = np.rint(ticks)
        out.append(Reading(t.finger, t.kind, (float(ticks[0]), float(ticks[1])), placement, currents))
    return out


def _balance_current(joint, torque_nm: float) -> float:
    """The Present Current (mA, as the bus reads it) of a blocked joint balancing ``torque_nm``
    along its angle: τ/Kt, signed by the joint's direction, in whole units of its model."""
    unit = joint.spec.current_unit_ma
    return float(np.rint(torque_nm / joint.spec.torque_nm_per_a * 1000.0 * joint.direction / unit) * unit)
