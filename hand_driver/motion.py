"""Guarded touches and rolling moves: the motions a finger runs, one bus cycle at a time.

A motion is a generator that yields the finger's next goal joint angles (or ``None`` to
hold) and receives each cycle's reading; hand_driver.cycle.run_together steps one motion
per finger in shared cycles, both fingers at once.

Pad lines follow hand_driver.kinematics: the pad's outward normal has angle ψ and the
pad lies on ``n(ψ)·p = d``; moving the pad in (toward the object) increases d. Every move
is Cartesian (:func:`move_line`): the pad line is interpolated and each step is put on the
pad by inverse kinematics, the solution nearest the present joint angles.

- **Guarded approach** (:func:`guarded_approach`): the pad keeps orientation ψ and
  advances along n at ``approach_speed_mm_s`` of robot time, the goal never more than two
  ``approach_step_mm`` ahead of the measured pad, until a joint of the finger reads
  ``|current| ≥ contact_current_ma`` or the pad stalls (goal ≥ 1.5 steps ahead, no
  progress over two cycles). In current-based position mode the goal current caps the
  pressing force. That reading is the sample (the object holds the pad at the contact);
  no contact within ``travel`` is a result, not an error.
- **Rolling touch** (:func:`rolling_touch`): ψ steps through ``ψ0 ± span/2``; between
  samples the pad backs off ``ROLL_CLEARANCE_MM``, turns about the last contact estimate
  and re-approaches (a blocked turn is retried ``backoff_mm`` further out); a contact at a
  pad end or a pad that does not turn ends the touch; after the last sample the pad backs
  off ``backoff_mm``. The in-contact pad lines give the contacts by their envelope
  (hand_driver.kinematics.touch_from_pad_lines).
- **Flat press** (hand_driver.flat_press, docs/driver.md#flat-press): on a straight face,
  where a pad cannot roll, guarded approaches turned in steps toward where the pad would
  lie flat until its lines rest on two supports of the face, then presses there; built
  from these motions.
- Both fingers run these at once in the same cycles: each finger's contact is judged on
  its own joints' currents and motion only.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable, Sequence

import numpy as np

from hand_driver import kinematics as kin
from hand_driver.cycle import Jaw, Motion
from hand_driver.units import velocity_to_rad_s

#: between the samples of a rolling touch the pad backs off this far (mm) before it turns;
#: the turn about the last contact estimate opens a gap of only ~R·Δψ²/2 (< 0.1 mm for
#: R = 50 mm, Δψ = 2°), so 1 mm clears it with margin and keeps re-approaches short
ROLL_CLEARANCE_MM = 1.0
#: ... and keeps at least this far (mm) from the last contact whichever joint arrives first
#: (:func:`uncoordinated_overshoot`)
CORNER_CLEARANCE_MM = 0.5
#: a contact this close (mm) to either end of the pad is a pad end resting on the
#: object, not a tangent contact of the pad's face
EDGE_MARGIN_MM = 1.0
#: a goal is "reached" when every joint of the finger is within this angle of it (rad): 3
#: ticks of an X-series encoder, about 750 of a PH54's; each joint compares in its own ticks
REACHED_RAD = math.radians(0.27)
#: a joint that moved less than this (rad) over a cycle stands still: 1 X-series tick
STILL_RAD = math.radians(0.09)
#: over the part of a guarded approach the caller knows to be free (``free_mm``: the felt
#: lines put the object farther), the goal advances this many times ``approach_speed_mm_s``
#: and may lead the measured pad by this many times two ``approach_step_mm``, never past the
#: end of that part (the lead, not the speed setting, is what lets the servos run); every
#: cycle is still guarded by the same contact test. An object met inside it after all is
#: pressed with a lead of at most 3 mm: 213 mA instead of 113 mA on the X jaw, 186 instead of
#: 112 on the P jaw, under the 300 mA goal current (tests/hand_driver/test_approach_free.py)
FREE_SPEED_FACTOR = 3.0


# --------------------------------------------------------------------------------- motions


@dataclass
class Sample:
    """One in-contact reading of a guarded approach."""

    reading: int
    psi: float  # commanded pad normal angle (rad)
    ticks: np.ndarray  # the finger's ticks at contact
    line: kin.PadLine  # the pad at contact, from those ticks
    current_ma: float | None
    robot_time: float
    #: each joint's Present Current (mA as read, signed) at contact: what the joints' torques and the
    #: pad's force are read from (kinematics.joint_torques); None where a joint senses none
    joint_current_ma: tuple[float, ...] | None = None

    @property
    def psi_measured(self) -> float:
        """The pad's outward normal angle at contact (rad)."""
        return float(self.line.psi)

    @property
    def d(self) -> float:
        """The measured pad line's offset (mm)."""
        return float(self.line.d)


@dataclass
class ApproachResult:
    contact: Sample | None
    travel_mm: float
    reason: str  # "current", "stall", "no_contact", "timeout"; "blocked": the pad did not turn


def joint_currents(jaw: Jaw, state, finger: str) -> tuple[float, ...] | None:
    """The finger's joints' Present Currents (mA, signed) in ``state``; None unless every one senses it."""
    if state.current_ma is None:
        return None
    values = np.asarray(state.current_ma, dtype=object)[jaw.slices[finger]]
    return None if any(v is None for v in values) else tuple(float(v) for v in values)


def move_to(jaw: Jaw, finger: str, q_goal, max_cycles: int = 200) -> Motion:
    """Go to joint angles ``q_goal`` and wait until reached (or no progress for 3 cycles,
    or ``max_cycles``); returns True when reached."""
    f = jaw.config.finger(finger)
    target = np.rint(kin.angles_to_ticks(f.joints, q_goal))
    per_rad = kin.resolutions(f.joints) / (2.0 * math.pi)  # ticks per rad of each joint
    reached, still_ticks = REACHED_RAD * per_rad, STILL_RAD * per_rad
    state, _ = yield np.asarray(q_goal, dtype=float)
    still, last = 0, jaw.finger_ticks(state, finger)
    for _ in range(max_cycles):
        ticks = jaw.finger_ticks(state, finger)
        if np.all(np.abs(ticks - target) <= reached):
            return True
        moved = not np.all(np.abs(ticks - last) <= still_ticks)
        still = 0 if moved else still + 1
        if still >= 3:
            return False
        last = ticks
        state, _ = yield None
    return False


def move_joint_line(jaw: Jaw, finger: str, q_goal) -> Motion:
    """Go to joint angles ``q_goal`` along the straight joint-space segment from where the
    finger is: one goal per cycle, no joint's step more than its servo turns in a cycle at the
    profile velocity (:func:`joint_cycle_turns`), every joint arriving together; then
    :func:`move_to`. A bare :func:`move_to` lets each servo run its own profile, so a distal
    joint's 150° swing ends long after the base joint's 18° turn and the pad sweeps another
    path than the straight segment a clearance test checked (the calibration's routes round the
    reference disk: a jaw of 85 / 62 mm links swept its pad into the disk on the way back to
    its parking pose). Returns True when reached."""
    q0 = np.asarray(jaw.finger_q(jaw.last_state, finger), dtype=float)
    delta = np.asarray(q_goal, dtype=float) - q0
    turns = joint_cycle_turns(jaw, finger)
    steps = 1 if turns is None else max(1, math.ceil(float(np.max(np.abs(delta) / turns))))
    for k in range(1, steps):
        yield q0 + delta * (k / steps)
    return (yield from move_to(jaw, finger, q_goal))


def joint_cycle_turns(jaw: Jaw, finger: str) -> np.ndarray | None:
    """What each joint of ``finger`` turns in one cycle (rad) at the config's
    ``motion.profile_velocity`` (in each joint's model's unit); None when it is 0 (no limit)."""
    raw = jaw.config.motion.profile_velocity
    if raw <= 0:
        return None
    joints = jaw.config.finger(finger).joints
    return np.array([float(velocity_to_rad_s(raw, j.spec)) for j in joints]) * jaw.period_s


#: a paced :func:`move_line` places its steps anew at most this many times (each time along what
#: its steps asked, the inverse kinematics being nonlinear)
PACE_ROUNDS = 4


def _line_goals(jaw: Jaw, finger: str, q, center, psi0: float, shift0: float, turn: float, shift1: float,
                fractions: np.ndarray) -> list[np.ndarray]:
    """The joint goals at ``fractions`` (increasing, in (0, 1]) of the way from the pad line
    (ψ0, shift0) to (ψ0 + turn, shift1), shifts measured from ``center`` (:func:`move_line`),
    each nearest the one before."""
    goals = []
    for f in fractions:
        a = psi0 + turn * f
        q = jaw.solve(finger, a, shift0 + (shift1 - shift0) * f + float(kin.unit(a) @ center), q)
        goals.append(q)
    return goals


def _paced_fractions(fractions: np.ndarray, need: np.ndarray) -> np.ndarray:
    """Fractions of a move (increasing, in (0, 1]) whose steps each ask about one cycle, from the
    cycles ``need`` each step between ``fractions`` asks (its fastest joint's turn over what its
    servo turns in a cycle, or the set Cartesian speed's share): ⌈Σ need⌉ steps, at least one more
    than before, placed evenly along the need accumulated over the move (linear within each step).
    A step split only in whole parts asks 1.3 cycles' turn in two cycles; over a P-series transit's
    turn that is ~0.2 s of robot time (docs/exploration.md, session 30)."""
    total = np.concatenate([[0.0], np.cumsum(need)])
    count = max(math.ceil(total[-1] - 1e-9), len(fractions) + 1)
    return np.interp(total[-1] * np.arange(1, count + 1) / count, total, np.concatenate([[0.0], fractions]))


def move_line(jaw: Jaw, finger: str, psi: float, d: float, *, via: Sequence[tuple[float, float]] = (),
              shift_mm_s: float | None = None, turn_deg_s: float | None = None, paced: bool = False) -> Motion:
    """Put the pad on the line (ψ, d) by a coordinated Cartesian move, through the pad
    lines ``via`` (ψ, d) in turn without stopping: the pad line is interpolated from where
    it is, turning about the pad's middle at ``turn_deg_s`` and shifting at ``shift_mm_s``
    (default: the config's ``motion.turn_speed_deg_s``, ``motion.move_speed_mm_s``) per
    second of robot time (a straight joint-space move would sweep the pad off the path
    between the two lines); then :func:`move_to` the final goal. ``paced``: the steps are
    placed anew, more of them, until no joint's goal moves more in a cycle than its servo turns
    at the profile velocity (:func:`joint_cycle_turns`), each step asking about one cycle of its
    fastest joint or of the set speeds (:func:`_paced_fractions`): a goal that outruns its servo is reached on
    the servo's own profile, the joints turning alike, and the pad leaves the path (slides
    along its normal). Returns True when reached."""
    m = jaw.config.motion
    max_turn = math.radians(turn_deg_s if turn_deg_s is not None else m.turn_speed_deg_s) * jaw.period_s
    max_shift = (shift_mm_s if shift_mm_s is not None else m.move_speed_mm_s) * jaw.period_s
    most = joint_cycle_turns(jaw, finger) if paced else None
    line = jaw.pad_line(jaw.last_state, finger)
    center = 0.5 * (line.proximal + line.distal)
    psi0 = float(line.psi)
    shift0 = float(line.d) - float(line.normal @ center)  # 0: the pad's middle is on its line
    q = jaw.finger_q(jaw.last_state, finger)
    lines = [*via, (psi, d)]
    for i, (psi1, d1) in enumerate(lines):
        turn = math.remainder(psi1 - psi0, 2 * math.pi)
        shift1 = d1 - float(kin.unit(psi1) @ center)
        cartesian = max(abs(turn) / max_turn, abs(shift1 - shift0) / max_shift)  # cycles at the set speeds
        steps = max(1, math.ceil(cartesian))
        fractions = np.arange(1, steps + 1) / steps
        goals = _line_goals(jaw, finger, q, center, psi0, shift0, turn, shift1, fractions)
        for _ in range(PACE_ROUNDS if most is not None else 0):
            joint = np.max(np.abs(np.diff(np.vstack([q, *goals]), axis=0)) / most, axis=1)  # per step
            if np.all(joint <= 1.0):
                break
            need = np.maximum(joint, cartesian * np.diff(np.concatenate([[0.0], fractions])))
            fractions = _paced_fractions(fractions, need)
            goals = _line_goals(jaw, finger, q, center, psi0, shift0, turn, shift1, fractions)
        steps = len(goals)
        for k, goal in enumerate(goals, start=1):
            if k < steps or i < len(lines) - 1:
                yield goal
        q = goals[-1]
        psi0, shift0 = psi0 + turn, shift1
    return (yield from move_to(jaw, finger, q))


def guarded_approach(jaw: Jaw, finger: str, psi: float, d_start: float, travel_mm: float,
                     free_mm: float = 0.0) -> Motion:
    """Advance the pad along its normal from line (ψ, d_start) until contact or
    ``travel_mm``; returns an :class:`ApproachResult` (module docstring). The first goal is
    already one step in (the pad is on its start line). Over the first ``free_mm`` the goal
    advances ``FREE_SPEED_FACTOR`` times faster, guarded as everywhere else."""
    m = jaw.config.motion
    step = m.approach_step_mm
    free_mm = min(max(free_mm, 0.0), travel_mm)
    t_free = free_mm / (FREE_SPEED_FACTOR * m.approach_speed_mm_s)
    n = kin.unit(psi)
    t0 = jaw.robot_time() - jaw.period_s
    d_meas = float(n @ jaw.pad_line(jaw.last_state, finger).distal)
    d_goal = min(d_start + step, d_meas + 2.0 * step, d_start + travel_mm)
    state, i = yield jaw.solve(finger, psi, d_goal, jaw.finger_q(jaw.last_state, finger))
    history: list[float] = []
    while True:
        line = jaw.pad_line(state, finger)
        d_meas = float(n @ line.distal)  # the pad's offset along the commanded normal
        elapsed = jaw.robot_time() - t0
        history.append(d_meas)
        current = jaw.finger_current(state, finger)
        stalled = (len(history) >= 3 and d_goal - d_meas >= 1.5 * step
                   and history[-1] - history[-3] < 0.2 * step)
        felt = current is not None and current >= m.contact_current_ma
        if (felt or stalled) and d_meas - d_start < free_mm:
            # met inside the free stretch, at up to FREE_SPEED_FACTOR times the speed:
            # pressed harder, the joints' gears loaded otherwise than at the normal speed
            # (with backlash the contact read up to 0.12 mm off), so the sample is taken
            # again: backed off ``backoff_mm`` and approached at the normal speed (from
            # ROLL_CLEARANCE_MM the P-series ellipse example's probes read other ticks
            # than a slow approach, by 1–2, and it was refused, χ² p 0.0005)
            back = d_meas - m.backoff_mm
            yield from move_line(jaw, finger, psi, back)
            again = yield from guarded_approach(jaw, finger, psi, back, 2.0 * m.backoff_mm + 3.0 * ROLL_CLEARANCE_MM)
            return ApproachResult(again.contact, again.travel_mm + back - d_start, again.reason)
        if felt or stalled:
            sample = Sample(reading=i, psi=psi, ticks=jaw.finger_ticks(state, finger), line=line,
                            current_ma=current, robot_time=jaw.robot_time(),
                            joint_current_ma=joint_currents(jaw, state, finger))
            return ApproachResult(sample, d_meas - d_start, "current" if felt else "stall")
        if d_goal - d_start >= travel_mm:
            return ApproachResult(None, d_meas - d_start, "no_contact")
        if elapsed > m.max_touch_s:
            return ApproachResult(None, d_meas - d_start, "timeout")
        # the goal moves at approach_speed in robot time, never more than two steps ahead of
        # the measured pad; over the first free_mm FREE_SPEED_FACTOR times faster and as many
        # times that lead, never past free_mm (two steps hold the pad near 22 mm/s)
        advance = (FREE_SPEED_FACTOR * m.approach_speed_mm_s * elapsed if elapsed <= t_free
                   else free_mm + m.approach_speed_mm_s * (elapsed - t_free))
        lead = max(d_meas + 2.0 * step, min(d_meas + 2.0 * FREE_SPEED_FACTOR * step, d_start + free_mm))
        d_goal = min(d_start + advance, lead, d_start + travel_mm)
        state, i = yield jaw.solve(finger, psi, d_goal, jaw.finger_q(state, finger))


@dataclass
class TouchResult:
    """One rolling touch of one finger: the in-contact samples, in the order taken."""

    finger: str
    touch: int
    psi_center: float
    samples: list[Sample] = field(default_factory=list)
    outcome: str = "ok"  # ok | no_contact | timeout | blocked | edge | unreachable
    message: str = ""


def roll_angles(psi_center: float, span_rad: float, samples: int) -> np.ndarray:
    """The pad orientations of a rolling touch, increasing."""
    return psi_center + np.linspace(-0.5 * span_rad, 0.5 * span_rad, samples)


def turn_to(jaw: Jaw, finger: str, psi: float, d_from: float) -> Motion:
    """Move the pad (backed off its contact) to the line (ψ, ``d_from``); when the object
    was in the way of the turn, back off ``motion.backoff_mm`` further and turn again.
    Returns the offset the pad reached ψ at."""
    if not (yield from move_line(jaw, finger, psi, d_from)):
        here = jaw.pad_line(jaw.last_state, finger)
        yield from move_line(jaw, finger, float(here.psi), float(here.d) - jaw.config.motion.backoff_mm)
        d_from -= jaw.config.motion.backoff_mm
        yield from move_line(jaw, finger, psi, d_from)
    return d_from


def rolling_touch(jaw: Jaw, finger: str, touch: int, psi_center: float, span_rad: float, samples: int,
                  d_start: float, travel_mm: float, on_event: Callable[[dict], None] | None = None,
                  free_mm: float = 0.0) -> Motion:
    """A guarded approach at the first orientation (its first ``free_mm`` faster:
    :func:`guarded_approach`), then one re-approach per further orientation (module
    docstring); ends backed off from the object."""
    m = jaw.config.motion
    emit = on_event or (lambda rec: None)
    result = TouchResult(finger, touch, psi_center)
    angles = roll_angles(psi_center, span_rad, samples)
    emit({"type": "touch_start", "touch": touch, "finger": finger, "psi": float(psi_center),
          "span": float(span_rad), "samples": int(samples), "reading": jaw.log_index()})
    try:
        yield from move_line(jaw, finger, float(angles[0]), d_start)
        reach = travel_mm
        d_from = d_start
        for k, psi in enumerate(angles):
            psi = float(psi)
            approach = yield from guarded_approach(jaw, finger, psi, d_from, reach, free_mm if k == 0 else 0.0)
            turned = (approach.contact is None or k == 0 or abs(math.remainder(
                approach.contact.psi_measured - result.samples[-1].psi_measured, 2 * math.pi))
                >= 0.5 * abs(psi - result.samples[-1].psi))
            if not turned:
                approach = ApproachResult(None, approach.travel_mm, "blocked")
            if approach.contact is None:
                result.outcome = approach.reason
                result.message = {
                    "no_contact": f"{finger}: no contact within {reach:.1f} mm at psi={math.degrees(psi):.1f} deg",
                    "timeout": f"{finger}: an approach took longer than {m.max_touch_s:g} s",
                    "blocked": f"{finger}: stopped short of psi={math.degrees(psi):.1f} deg (the object was in the way)",
                }[approach.reason]
                break
            result.samples.append(approach.contact)
            emit({"type": "sample", "touch": touch, "finger": finger, "psi": psi,
                  "reading": approach.contact.reading, "by": approach.reason})
            if k == len(angles) - 1:
                break
            pivot, u = contact_on_pad(result.samples)
            length = jaw.config.finger(finger).pad.length_mm
            if u is not None and not EDGE_MARGIN_MM <= u <= length - EDGE_MARGIN_MM:
                result.outcome = "edge"
                result.message = (f"{finger}: the contact is {u:.1f} mm along a {length:g} mm pad: "
                                  f"a pad end, not the pad's face, touched")
                break
            # off the contact and turned to the next orientation in one move
            psi = float(angles[k + 1])
            unsure = 0.5 * length if u is None else 0.0
            clearance = ROLL_CLEARANCE_MM + unsure * abs(psi - result.samples[-1].psi)
            clearance += uncoordinated_overshoot(jaw, finger, psi, float(kin.unit(psi) @ pivot) - clearance, pivot)
            planned = float(kin.unit(psi) @ pivot) - clearance
            d_from = yield from turn_to(jaw, finger, psi, planned)
            reach = 2.0 * clearance + 3.0 * ROLL_CLEARANCE_MM + (planned - d_from)
        if result.samples and result.outcome in ("ok", "edge"):  # the pad is in contact: back off
            last = result.samples[-1]
            yield from move_line(jaw, finger, last.psi, last.d - m.backoff_mm)
    except kin.Unreachable as exc:
        result.outcome, result.message = "unreachable", str(exc)
    emit({"type": "touch_end", "touch": touch, "finger": finger, "reading": jaw.log_index(),
          "samples": len(result.samples), "outcome": result.outcome})
    return result


def uncoordinated_overshoot(jaw: Jaw, finger: str, psi: float, d: float, pivot: np.ndarray) -> float:
    """How much farther (mm) than the line (ψ, d) the pad must back off so that it keeps
    ``CORNER_CLEARANCE_MM`` from the object's last contact ``pivot`` on the way there. Each
    servo runs its own trapezoidal profile, every joint with the same acceleration and speed
    limits, so on a short move they turn alike until the one with the shorter way arrives:
    between two samples of a roll on the P-series jaw the base joint's −0.9° ended before the
    distal joint's +3.1° and pressed the pad into the object; the move stalled, backed off
    ``backoff_mm`` and turned again (30 of 38 turns of one finger, 0.46 s a sample instead
    of 0.20 s). The pad is checked where each joint arrives; 0 when none comes nearer the
    contact than that."""
    f = jaw.config.finger(finger)
    q0 = jaw.finger_q(jaw.last_state, finger)
    extra = 0.0
    for _ in range(3):  # the goal moves out with the clearance; the kinks' reach settles in a step or two
        try:
            q1 = jaw.solve(finger, psi, d - extra, q0)
        except kin.Unreachable:
            return extra
        dq = q1 - q0
        worst = -math.inf
        for s in np.sort(np.abs(dq))[:-1]:  # where each joint but the last arrives
            line = kin.finger_pad_line(f, q0 + np.sign(dq) * np.minimum(np.abs(dq), s))
            worst = max(worst, float(line.d) - float(line.normal @ pivot))
        need = worst + CORNER_CLEARANCE_MM  # that pad line's clearance short of CORNER_CLEARANCE_MM
        if need <= 1e-3:
            return extra
        extra += need
    return extra


def contact_on_pad(samples: list[Sample]) -> tuple[np.ndarray, float | None]:
    """Where the pad last touched and its coordinate along the pad (mm from the proximal
    end), from a touch's samples so far: the intersection of the last two pad lines (their envelope point), or the pad's
    middle and None after a single sample."""
    last = samples[-1].line
    mid = 0.5 * (last.proximal + last.distal)
    if len(samples) < 2:
        return mid, None
    p = kin.crossing(last, samples[-2].line)
    if p is None:
        return mid, None
    return p, float(last.pad_coordinate(p))
