"""Calibration on the jaw: touch a reference disk with both fingers and collect readings.

:func:`touch_reference` locates the disk placed near a guess with a few face touches,
then runs the touch plan (hand_driver.calibration_plan) with both fingers at once, each
move routed clear of the located disk; :func:`park` opens the fingers. The readings go to
hand_driver.calibration_fit.fit (``tactile calibrate``).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from hand_driver import kinematics as kin
from hand_driver.calibration_fit import CalibrationRefused, ContactModel, Reading, pack_params
from hand_driver.calibration_plan import DEFAULT_PLACEMENTS, PlannedTouch, plan_touches
from hand_driver.config import JawConfig
from hand_driver.cycle import LIMIT_MARGIN_RAD, run_together
from hand_driver.motion import guarded_approach, joint_currents, move_joint_line, move_to
from tactile_common.angles import wrap_angle

#: pre-contact gap (mm) from which every calibration touch approaches, and its travel
APPROACH_GAP_MM = 5.0
APPROACH_TRAVEL_MM = 12.0
#: locating touches start this far (mm) outside the expected disk: the placement may be
#: off by up to this much
LOCATE_GAP_MM = 6.0
#: :func:`default_placements` moves DEFAULT_PLACEMENTS away from the palm in steps of this
#: (mm), at most this far
PLACEMENT_SHIFT_STEP_MM = 5.0
PLACEMENT_SHIFT_MAX_MM = 60.0
#: transit keeps the pads this far (mm) from the located disk (less than APPROACH_GAP_MM)
TRANSIT_CLEARANCE_MM = 4.0


def home_pose(finger) -> np.ndarray:
    """A finger's parking pose: opened outward, clear of the workspace."""
    out = np.array([math.radians(40.0), math.radians(30.0)]) * finger.pad.side_sign * -1.0
    lo = np.array([j.min_rad for j in finger.joints])
    hi = np.array([j.max_rad for j in finger.joints])
    return np.clip(out, lo, hi)


def park(jaw) -> None:
    """Move both fingers to their parking poses (:func:`home_pose`) together."""
    run_together(jaw, {f.name: move_to(jaw, f.name, home_pose(f)) for f in jaw.config.fingers})


def _corner_approach(jaw, finger: str, center, r: float, direction, end: str, q_branch, gap0: float,
                     travel: float):
    """Guarded approach of a pad end toward the disk centre along −direction, from
    ``gap0`` mm outside the disk (nominal geometry); returns the contact's reading (a
    JointState) or None."""
    m = jaw.config.motion
    step = m.approach_step_mm
    f = jaw.config.finger(finger)
    mvec, c = np.asarray(direction, dtype=float), np.asarray(center, dtype=float)

    def solve(gap, q_ref):
        sols = kin.ik_corner(f, c + (r + gap) * mvec, LIMIT_MARGIN_RAD, end=end)
        if not sols:
            raise kin.Unreachable(f"finger {finger}: pad {end} end cannot reach the reference")
        return min(sols, key=lambda q: float(np.sum(wrap_angle(q - q_ref) ** 2)))

    t0 = jaw.robot_time()
    gap_goal = gap0
    state, _ = yield solve(gap_goal, q_branch)
    history: list[float] = []
    while True:
        line = jaw.pad_line(state, finger)
        point = line.distal if end == "distal" else line.proximal
        gap = float(mvec @ (point - c)) - r
        history.append(gap)
        current = jaw.finger_current(state, finger)
        felt = current is not None and current >= m.contact_current_ma
        stalled = len(history) >= 3 and gap - gap_goal >= 1.5 * step and history[-3] - history[-1] < 0.2 * step
        if felt or stalled:
            return state
        elapsed = jaw.robot_time() - t0
        if gap0 - gap_goal >= travel or elapsed > m.max_touch_s:
            return None
        gap_goal = max(gap0 - m.approach_speed_mm_s * elapsed, gap - 2.0 * step, gap0 - travel)
        state, _ = yield solve(gap_goal, jaw.finger_q(state, finger))


def _reading(jaw, state, finger: str, kind: str, placement: int) -> Reading:
    """The calibration reading of a contact: the finger's ticks and its joints' currents (None
    unless every joint senses one, hand_driver.motion.joint_currents) in that one reading."""
    ticks = jaw.finger_ticks(state, finger)
    return Reading(finger, kind, (float(ticks[0]), float(ticks[1])), placement, joint_currents(jaw, state, finger))


def _pre_pose(cfg: JawConfig, t: PlannedTouch, center, r: float, gap: float):
    """Nominal joint angles ``gap`` mm before the planned contact, on its branch."""
    f = cfg.finger(t.finger)
    c = np.asarray(center, dtype=float)
    if t.kind == "face":
        n = kin.unit(t.psi)
        sols = kin.ik_line_solutions(f, t.psi, float(n @ c) - r - gap)
    else:
        pt = c + (r + gap) * np.asarray(t.direction)
        sols = kin.ik_corner(f, pt, end="distal" if t.kind == "corner" else "proximal")
    sols = [q for q in sols if kin.within_limits(f.joints, q)]
    if not sols:
        return None
    return min(sols, key=lambda q: float(np.sum(wrap_angle(q - np.asarray(t.q)) ** 2)))


def _route(guard, finger: str, here, target, home) -> list | None:
    """Joint-space waypoints from ``here`` to ``target`` whose straight segments keep the
    pad clear of the expected disk: direct, or via the parking pose and/or the corners of
    the joint-space box (one joint moved first); None if none is clear."""
    candidates = [[], [home]]
    for a in (here, home):
        candidates += [[np.array([a[0], target[1]])], [np.array([target[0], a[1]])]]
    candidates += [[home, np.array([home[0], target[1]])], [home, np.array([target[0], home[1]])]]
    checked: dict[bytes, bool] = {}  # candidates share segments: test each once

    def clear(a, b) -> bool:
        key = np.concatenate([np.asarray(a, dtype=float), np.asarray(b, dtype=float)]).tobytes()
        if key not in checked:
            checked[key] = guard(finger, a, b)
        return checked[key]

    for via in candidates:
        points = [here] + via + [target]
        if all(clear(a, b) for a, b in zip(points[:-1], points[1:])):
            return via + [target]
    return None


def _finger_touches(jaw, finger: str, plan: list[PlannedTouch], center, r: float, placement: int,
                    guard, out: list[Reading], skipped: list[str], gap: float = APPROACH_GAP_MM,
                    travel: float = APPROACH_TRAVEL_MM):
    """One finger's motion through its planned touches (a generator for run_together).
    The waypoints since the finger last left its parking pose are kept (``trail``): when
    no clear route leads from where it is to the next touch, it retraces them (segments
    already found clear) to park and plans from there; it also retraces them at the end."""
    cfg = jaw.config
    f = cfg.finger(finger)
    home = home_pose(f)
    here = jaw.finger_q(jaw.last_state, finger)
    trail = [here]

    def retrace(move=move_to):
        for q in trail[-2::-1]:
            yield from move(jaw, finger, q)
        return [trail[0]]

    for t in plan:
        pre = _pre_pose(cfg, t, center, r, gap)
        if pre is None:
            skipped.append(f"{finger} {t.kind}: unreachable")
            continue
        route = _route(guard, finger, here, pre, home)
        if route is None and len(trail) > 1:
            trail = yield from retrace()
            here = trail[0]
            route = _route(guard, finger, here, pre, home)
        if route is None:
            skipped.append(f"{finger} {t.kind}: no clear path")
            continue
        done = []
        for q in route:
            if not (yield from move_to(jaw, finger, q)):
                break
            done.append(q)
        homed = [i for i, q in enumerate(done) if q is home]
        trail = [home] + done[homed[-1] + 1:] if homed else trail + done
        if len(done) < len(route):  # blocked on the way (the object is not where expected): back to the
            # last waypoint reached and the way it came to park, skip — a finger left pushing toward an
            # unreached goal stays blocked against the disk at its current limit (a PM42-010 distal
            # joint, 1,461 mA at most, raised its overload error while the other finger touched on)
            skipped.append(f"{finger} {t.kind}: blocked on the way")
            yield from move_joint_line(jaw, finger, trail[-1])
            trail = yield from retrace(move_joint_line)  # on the segments checked clear, not each servo's own profile
            here = trail[0]
            continue
        here = route[-1]
        if t.kind == "face":
            n = kin.unit(t.psi)
            d_pre = float(n @ np.asarray(center)) - r - gap
            try:
                result = yield from guarded_approach(jaw, finger, t.psi, d_pre, travel)
                # the approach ends on the reading it judged a contact, the jaw's last
                state = None if result.contact is None else jaw.last_state
                if state is not None and result.contact.reading != jaw.last_index:
                    raise RuntimeError("the contact's reading is not the jaw's last")
            except kin.Unreachable:
                state = None
        else:
            try:
                state = yield from _corner_approach(jaw, finger, center, r, t.direction,
                                                    "distal" if t.kind == "corner" else "proximal", pre, gap, travel)
            except kin.Unreachable:
                state = None
        if state is None:
            skipped.append(f"{finger} {t.kind}: no contact")
        else:
            out.append(_reading(jaw, state, finger, t.kind, placement))
        yield from move_to(jaw, finger, pre)
    if len(trail) > 1 and not guard(finger, here, home):
        trail = yield from retrace()
        here = trail[0]
    for q in _route(guard, finger, here, home, home) or []:  # direct, or round the disk
        yield from move_to(jaw, finger, q)


def _guard(cfg: JawConfig, center, r: float, extra: float):
    """guard(finger, q_from, q_to): does the straight joint-space move keep the pad ``extra``
    mm clear of a disk of radius ``r`` at ``center`` (sampled every 0.01 rad)?"""
    c = np.asarray(center, dtype=float)

    def guard(finger, q_from, q_to) -> bool:
        q_from, q_to = np.asarray(q_from, dtype=float), np.asarray(q_to, dtype=float)
        n = max(2, math.ceil(float(np.max(np.abs(q_to - q_from))) / 0.01) + 1)
        qs = q_from + np.linspace(0.0, 1.0, n)[:, None] * (q_to - q_from)
        line = kin.finger_pad_line(cfg.finger(finger), qs)
        ab = line.distal - line.proximal
        u = np.clip(np.sum((c - line.proximal) * ab, axis=1) / np.sum(ab * ab, axis=1), 0.0, 1.0)
        dist = np.hypot(*(line.proximal + u[:, None] * ab - c).T)
        return bool(np.all(dist >= r + extra))
    return guard


def _reachable(cfg: JawConfig, guard):
    """accept(finger, q) for :func:`plan_touches`: is there a route (:func:`_route`) from the
    finger's parking pose to approach pose q and back that ``guard`` finds clear?"""
    homes = {f.name: home_pose(f) for f in cfg.fingers}
    return lambda name, q: _route(guard, name, homes[name], q, homes[name]) is not None


def _locate_guard(cfg: JawConfig, guess, r: float):
    """The clearance test of the locating touches' routes: the pads 0.5 mm inside their
    ``LOCATE_GAP_MM`` start outside a disk of radius ``r`` expected at ``guess``."""
    return _guard(cfg, guess, r, LOCATE_GAP_MM - 0.5)


def _locate_options(cfg: JawConfig, reference, guess) -> dict[str, list[PlannedTouch]]:
    """Per finger, the face touches (ψ order) that locate a disk expected at ``guess``
    (:func:`touch_reference`'s step 1): from ``LOCATE_GAP_MM`` outside it, each approach pose
    on a route clear of it from the finger's parking pose."""
    guard = _locate_guard(cfg, guess, float(reference.params["r"]))
    plan = plan_touches(cfg, reference, guess, faces=15, corners=0, gap=LOCATE_GAP_MM,
                        accept=_reachable(cfg, guard))
    return {f.name: sorted((t for t in plan if t.finger == f.name and t.kind == "face"), key=lambda t: t.psi)
            for f in cfg.fingers}


def default_placements(cfg: JawConfig, reference, locate: int = 2) -> list[tuple[float, float]]:
    """Where ``tactile calibrate`` asks for the reference disk when no ``--place`` is given:
    hand_driver.calibration_plan.DEFAULT_PLACEMENTS (chosen for config/jaw.yaml's geometry)
    moved away from the palm (+x) by the least multiple of ``PLACEMENT_SHIFT_STEP_MM`` at which
    every placement leaves the two fingers at least 2·``locate`` locating touches between them
    (:func:`_locate_options`; a finger that reaches none leaves its share to the other). A
    jaw of longer proximal links and shorter pads cannot fold round a disk at (60, 0) mm: the
    P-series jaw with 85 / 62 mm links and 40 mm pads reaches no locating touch there, and was
    told to place a disk where it already lay; moved 10 mm, 4. Raises CalibrationRefused
    when no shift up to ``PLACEMENT_SHIFT_MAX_MM`` does."""
    shift = 0.0
    while shift <= PLACEMENT_SHIFT_MAX_MM:
        places = [(x + shift, y) for x, y in DEFAULT_PLACEMENTS]
        if all(sum(len(v) for v in _locate_options(cfg, reference, p).values()) >= 2 * locate for p in places):
            return places
        shift += PLACEMENT_SHIFT_STEP_MM
    raise CalibrationRefused(f"no placement of the reference disk lets this jaw's pads locate it: "
                             f"{', '.join(f'({x:g}, {y:g})' for x, y in DEFAULT_PLACEMENTS)} mm moved up to "
                             f"{PLACEMENT_SHIFT_MAX_MM:g} mm away from the palm leave fewer than {2 * locate} "
                             f"locating touches at some placement; pass --place X,Y where the pads reach it")


def touch_reference(jaw, reference, guess, placement: int = 0, faces: int = 10, corners: int = 6,
                    locate: int = 2) -> tuple[list[Reading], np.ndarray, list[str]]:
    """Touch one placement of a disk reference with both fingers: ``locate`` face touches
    per finger (a finger that cannot reach enough face orientations leaves its share to the
    other) from LOCATE_GAP_MM outside the expected disk at ``guess`` find it (nominal
    geometry, least squares), then the full plan (:func:`plan_touches`) runs with both
    fingers at once. Returns the readings (locating touches included), the located
    centre and what was skipped."""
    cfg = jaw.config
    r = float(reference.params["r"])
    readings: list[Reading] = []
    skipped: list[str] = []

    # 0. park both fingers (opening them moves the pads away from the workspace)
    park(jaw)
    # 1. locate: the pads start LOCATE_GAP_MM outside the expected disk
    loc_gap, loc_travel = LOCATE_GAP_MM, 2.0 * LOCATE_GAP_MM
    guard = _locate_guard(cfg, guess, r)
    options = _locate_options(cfg, reference, guess)
    if sum(len(v) for v in options.values()) < 3:
        raise CalibrationRefused(f"placement {placement + 1}: this jaw's pads reach {sum(len(v) for v in options.values())} "
                                 f"locating touches of a disk of radius {r:g} mm at ({guess[0]:g}, {guess[1]:g}) mm "
                                 f"from their parking poses (3 needed): place it farther from the palm (--place X,Y)")
    # `locate` per finger; what a finger cannot reach (a disk off to its side) the other takes
    counts = {name: min(len(mine), locate) for name, mine in options.items()}
    for name, mine in options.items():
        spare = locate * len(options) - sum(counts.values())
        counts[name] += min(spare, len(mine) - counts[name])
    by_finger = {}
    for name, mine in options.items():  # the middles of equal parts of the reachable orientations
        n = counts[name]
        by_finger[name] = [mine[min(len(mine) - 1, round((k + 0.5) * len(mine) / n - 0.5))] for k in range(n)]
    run_together(jaw, {name: _finger_touches(jaw, name, items, guess, r, placement, guard, readings, skipped,
                                             gap=loc_gap, travel=loc_travel) for name, items in by_finger.items()})
    faces_found = [rd for rd in readings if rd.kind == "face"]
    if len(faces_found) < 3:
        raise CalibrationRefused(f"placement {placement + 1}: found the reference with only {len(faces_found)} "
                                 f"touches ({'; '.join(sorted(set(skipped))) or 'none skipped'}): no disk of radius "
                                 f"{r:g} mm near ({guess[0]:g}, {guess[1]:g}) mm; place it there (an emulated bus: "
                                 f"tactile sim --scene <the reference> --place {guess[0]:g},{guess[1]:g})")
    model = ContactModel(cfg, reference, [dataclasses.replace(rd, placement=0) for rd in faces_found])
    center = model.pose_start(pack_params(cfg))[:2]
    # 2. the full plan around the located disk
    guard = _guard(cfg, center, r, TRANSIT_CLEARANCE_MM)
    plan = plan_touches(cfg, reference, center, faces=faces, corners=corners, gap=APPROACH_GAP_MM,
                        accept=_reachable(cfg, guard))
    run_together(jaw, {f.name: _finger_touches(jaw, f.name, [t for t in plan if t.finger == f.name], center, r,
                                               placement, guard, readings, skipped) for f in cfg.fingers})
    return readings, center, skipped
