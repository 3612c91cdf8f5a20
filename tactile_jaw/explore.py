"""Exploration: rolling touches with both fingers at once until the recognizer is sure.

Probes first locate the boundary (tactile_jaw.plan). Each round, every finger makes one
rolling touch (hand_driver.motion.rolling_touch) in the same bus cycles, at the
orientation tactile_jaw.plan.choose_psi picks, starting ``APPROACH_MARGIN_MM`` outside the
predicted tangent. Between touches a pad retreats to the workspace edge and turns along
it (:func:`transit`). Every touch is felt once (tactile_jaw.pipeline.feel).

After every round with at least ``settings.min_touches`` usable touches the recognizer
runs on all of them; exploration stops as soon as its answer is decisive
(tactile_jaw.decide), when the touch budget is spent, or when no touch within the pads'
reach can help (tactile_jaw.choose). While it is not decisive, the next touch of the finger
that can reach it goes where tactile_jaw.choose.next_aim points (beyond a parabola's vertex
on its short side, else the recognizer's ``next_touch`` within the jaw's reach; the other
finger's where the planner picks). Once it ends, the answer on the usable touches is the
class if decisive, else ``unclassified`` with the reason. docs/exploration.md.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Callable

import numpy as np

from hand_driver import kinematics as kin
from hand_driver.cycle import LIMIT_MARGIN_RAD, Jaw, run_together
from hand_driver.flat_press import FLAT_STEP_DEG, flat_press
from hand_driver.motion import TouchResult, move_line, move_to, roll_angles, rolling_touch
from recognizer.result import Recognition
from tactile_common.errors import InputError
from tactile_jaw.choose import Aim, JawReach, next_aim
from tactile_jaw.decide import RecognizeTouches, decide, final_answer, sample_positions
from tactile_jaw.flat import FACE_MISS_MM, curved_faces, recognized_touches
from tactile_jaw.pipeline import FeltTouch, clear_of_corners, feel, too_few_clear
from tactile_jaw.plan import (
    APPROACH_MARGIN_MM,
    PROBE_ENOUGH_DEG,
    PROBE_REFINE_DEG,
    PROBE_SAMPLES,
    PROBE_SPAN_DEG,
    ObjectModel,
    choose_psi,
    nominal_psi,
    predicted_tangent,
    probe_face_contact,
    probe_psis,
    retreat_offset,
)
from tactile_jaw.settings import ExploreSettings

#: a finger whose last this many touches fell on corners or closing segments stops touching:
#: its side of the object is not the curved part, and the touch budget goes to the others
OFF_CURVE_RETIRE = 2
#: a transit turns along the workspace edge through pad lines at most this many degrees apart
EDGE_TURN_STEP_DEG = 15.0
#: flat presses (docs/exploration.md#lines-flat-presses), when no rolling touch was usable:
#: a finger's first one starts at its pad's nominal normal (the press turns toward the
#: seat from there, hand_driver.flat_press); a later one FLAT_RESTART_STEPS turn steps
#: before the face's normal it found, from FLAT_RESTART_MM outside it; at most
#: settings.min_touches + FLAT_SPARE rounds; a finger stops after FLAT_TRIES presses that
#: did not seat (one miss can be the encoders' rounding: a seated press of the line
#: example moved 3 mm stopped 0.22 mm off, over the 0.2 mm tolerance; the retry starts
#: half a step further on, other stops, other roundings).
#: The rolling touches give way to flat presses once FLAT_AFTER_TOUCHES of them were
#: tried and none was usable (every one on a corner, a pad end or across a face: the line
#: example turned −5° spent 8 rolling touches, 54 s of robot time, before)
FLAT_RESTART_STEPS = 2.5
FLAT_RESTART_MM = 3.0
FLAT_SPARE = 2
FLAT_TRIES = 2
FLAT_AFTER_TOUCHES = 4


@dataclass
class Exploration:
    """What an exploration did and found."""

    probes: list[FeltTouch] = field(default_factory=list)  # every probe, in order
    touches: list[FeltTouch] = field(default_factory=list)  # every touch attempted, in order
    used: list[FeltTouch] = field(default_factory=list)  # the usable touches, recognized
    recognition: Recognition | None = None
    rounds: int = 0
    robot_time_s: float = 0.0
    answers: list[str] = field(default_factory=list)  # class after each recognition
    stopped: str | None = None  # why exploration stopped before its budget was spent (tactile_jaw.choose)
    #: where the robot time went (s): probe and touch rounds (each including its transits),
    #: the transits alone (per round the slower finger's), the final retreat
    time_s: dict[str, float] = field(default_factory=lambda: dict.fromkeys(
        ("probes", "probe_transits", "touches", "touch_transits", "retreat"), 0.0))

    @property
    def request(self) -> dict[str, Any]:
        """The touches request (docs/formats.md) of the usable touches."""
        return {"touches": [t.to_json() for t in self.used]}



def transit(jaw: Jaw, finger: str, model: ObjectModel, psi_to: float, aim=None):
    """Retreat to the workspace edge along the pad normal, then turn along the edge to ψ
    (where the joints cannot reach the edge, along the farthest-out line they reach that
    keeps clear of the object: tactile_jaw.plan.retreat_offset).
    Where the edge is out of the joints' reach along this normal (a pad turned far past its
    nominal direction), the pad retreats as far as it can and the finger swings open in
    joint space to its edge pose at the nominal ψ, and turns from there: without this, one
    such pose made every later transit of the finger fail and spent the touch budget."""
    line = jaw.pad_line(jaw.last_state, finger)
    psi_from = float(line.psi)
    f = jaw.config.finger(finger)
    via = [(psi_from, min(float(line.d), model.edge(psi_from)))]
    try:
        jaw.solve(finger, *via[0], jaw.finger_q(jaw.last_state, finger))
    except kin.Unreachable:
        psi_from = nominal_psi(f)
        q_open = kin.ik_line(f, psi_from, model.edge(psi_from), margin_rad=LIMIT_MARGIN_RAD)
        yield from move_to(jaw, finger, q_open)
        via = []
    delta = math.remainder(psi_to - psi_from, 2 * math.pi)
    steps = max(1, math.ceil(abs(math.degrees(delta)) / EDGE_TURN_STEP_DEG))
    for k in range(1, steps + 1):
        a = psi_from + delta * k / steps
        d = retreat_offset(f, model, a, aim)
        if d is None:
            raise kin.Unreachable(f"finger {finger}: no pad line of psi={math.degrees(a):.1f} deg within the joint "
                                  f"limits keeps clear of the object")
        via.append((a, d))
    yield from move_line(jaw, finger, *via[-1], via=via[:-1])


def _transit_or_problem(jaw: Jaw, finger: str, model: ObjectModel, psi_to: float,
                        spent: dict[str, float] | None = None, aim=None):
    """:func:`transit`; why it could not go on (the path left the joint limits), or None.
    The robot time it took goes to ``spent[finger]``."""
    t0 = jaw.robot_time()
    try:
        yield from transit(jaw, finger, model, psi_to, aim)
    except kin.Unreachable as exc:
        return f"{finger}: transit to psi={math.degrees(psi_to):.1f} deg: {exc}"
    finally:
        if spent is not None:
            spent[finger] = jaw.robot_time() - t0
    return None


def _touch_plan(jaw: Jaw, finger: str, model: ObjectModel, psi: float, settings: ExploreSettings,
                touch_index: int, emit, spent: dict[str, float], aim=None):
    """Transit, then one rolling touch around ψ from ``APPROACH_MARGIN_MM`` outside the
    predicted tangent line (tactile_jaw.plan.predicted_tangent, ``aim`` a boundary point the
    touch is aimed at); returns the TouchResult."""
    start = float(roll_angles(psi, settings.roll_span_rad, settings.samples_per_touch)[0])
    problem = yield from _transit_or_problem(jaw, finger, model, start, spent, aim)
    if problem is not None:
        return TouchResult(finger, touch_index, psi, outcome="unreachable", message=problem)
    d_pred, _ = predicted_tangent(model, start, aim)
    d_start = max(retreat_offset(jaw.config.finger(finger), model, start, aim), d_pred - APPROACH_MARGIN_MM)
    travel = d_pred + APPROACH_MARGIN_MM - d_start
    return (yield from rolling_touch(jaw, finger, touch_index, psi, settings.roll_span_rad,
                                     settings.samples_per_touch, d_start, travel, on_event=emit))


def _probe_plan(jaw: Jaw, finger: str, model: ObjectModel, psi: float, touch_index: int, emit,
                spent: dict[str, float]):
    """Transit, then a short rolling touch (``PROBE_SAMPLES`` over ``PROBE_SPAN_DEG``) from
    the workspace edge across the whole workspace disk; returns the TouchResult."""
    span = math.radians(PROBE_SPAN_DEG)
    start = float(roll_angles(psi, span, PROBE_SAMPLES)[0])
    problem = yield from _transit_or_problem(jaw, finger, model, start, spent)
    if problem is not None:
        return TouchResult(finger, touch_index, psi, outcome="unreachable", message=problem)
    return (yield from rolling_touch(jaw, finger, touch_index, psi, span, PROBE_SAMPLES, model.edge(start),
                                     2.0 * model.workspace_radius, on_event=emit))


def _memo(recognize_touches: RecognizeTouches) -> RecognizeTouches:
    """``recognize_touches`` remembering its answers by the touches' identities."""
    seen: dict[tuple[int, ...], Any] = {}

    def run(touches):
        key = tuple(id(t) for t in touches)
        if key not in seen:
            seen[key] = recognize_touches(touches)
        return seen[key]

    return run


def _clear_of_corners(cfg, out: Exploration, settings: ExploreSettings, emit, say) -> Callable[[], list[FeltTouch]]:
    """The usable touches so far without their samples at the corners the touches so far
    pivoted about (tactile_jaw.pipeline.clear_of_corners; recomputed when either list grows),
    each change logged once (event ``touch_trimmed``)."""
    state: dict[str, Any] = {"key": None, "usable": [], "said": set()}

    def run() -> list[FeltTouch]:
        key = (len(out.used), sum(t.corner is not None for t in out.touches))
        if key != state["key"]:
            state["key"] = key
            state["usable"], notes = clear_of_corners(cfg, out.used, out.touches, settings.samples_per_touch)
            for note in notes:
                if note not in state["said"]:
                    state["said"].add(note)
                    emit({"type": "event", "kind": "touch_trimmed", "message": note})
                    say(note)
        return state["usable"]

    return run


def _spent(out: Exploration) -> int:
    """Touches that count against the budget: all but those that fell on a corner or across
    a closing segment of a finite object (a finger retires after OFF_CURVE_RETIRE in a row,
    so these stay few); the touches on the curved part are what the budget is for."""
    return sum(not t.off_curve for t in out.touches)


def _timed(jaw: Jaw, plans: dict, spent: dict[str, float], time_s: dict[str, float], total: str, transits: str):
    """:func:`run_together` of one round, its robot time added to ``time_s[total]`` and the
    slower finger's transit to ``time_s[transits]``."""
    t0 = jaw.robot_time()
    results = run_together(jaw, plans)
    time_s[total] += jaw.robot_time() - t0
    time_s[transits] += max(spent.values(), default=0.0)
    return results


def _felt_stop(out: Exploration, finger: str, psi: float) -> tuple[float, float] | None:
    """(ψ, d) of the in-contact sample of ``finger`` (probes and rolling touches so far)
    whose orientation is nearest ``psi``, or None: a guarded approach at that ψ stops there
    again, so a flat press can start from just outside it instead of the workspace edge."""
    samples = [s for t in (*out.probes, *out.touches) if t.touch.finger == finger for s in t.touch.samples]
    if not samples:
        return None
    s = min(samples, key=lambda s: abs(math.remainder(s.psi - psi, 2 * math.pi)))
    return float(s.psi), float(s.line.d)


def _flat_plan(jaw: Jaw, finger: str, model: ObjectModel, face, misses: int, touch_index: int, emit,
               spent: dict[str, float], felt: tuple[float, float] | None = None):
    """One flat press of ``finger``: the first at the pad's nominal normal (after a transit)
    from the workspace edge, or — ``felt``, an earlier stop (ψ, d) near that normal — at that
    ψ from FLAT_RESTART_MM outside that stop (1.4 s less of guarded approach on the line
    example); a later one close to the ``face`` it seated on (module constants); after
    ``misses`` presses that did not seat, from the edge, half a step further on each.
    Returns the FlatResult (or a TouchResult if the transit could not go on)."""
    step = math.radians(FLAT_STEP_DEG)
    f = jaw.config.finger(finger)
    if face is None:
        start = felt[0] if felt is not None and misses == 0 else nominal_psi(f) + 0.5 * misses * step
        problem = yield from _transit_or_problem(jaw, finger, model, start, spent)
        if problem is not None:
            return TouchResult(finger, touch_index, start, outcome="unreachable", message=problem)
        d_start = retreat_offset(f, model, start)
        if d_start is None:
            return TouchResult(finger, touch_index, start, outcome="unreachable",
                               message=f"{finger}: no pad line of psi={math.degrees(start):.1f} deg keeps clear of the object")
        travel = 2.0 * model.workspace_radius
        if felt is not None and misses == 0:
            d_start = max(d_start, felt[1] - FLAT_RESTART_MM)
            travel = felt[1] + FLAT_RESTART_MM - d_start
    else:
        spent[finger] = 0.0
        start = face.psi - (FLAT_RESTART_STEPS + 0.5 * misses) * step
        n = np.array([math.cos(start), math.sin(start)])
        d_start = min(float(n @ face.p), float(n @ face.q)) - FLAT_RESTART_MM
        travel = 2.0 * FLAT_RESTART_MM
    return (yield from flat_press(jaw, finger, touch_index, start, 1, d_start, travel, toward=model.workspace_center,
                                  on_event=emit))


def _flat_presses(jaw: Jaw, settings: ExploreSettings, model: ObjectModel, out: Exploration,
                  recognize_touches: RecognizeTouches, emit, say, index: int) -> None:
    """Every finger presses its pad flat on the face before it, round after round, until
    the recognizer's answer on one face's flat touches (tactile_jaw.flat.recognized_touches)
    is decisive; a finger stops after FLAT_TRIES presses that did not seat. ``out.used``
    ends as those touches."""
    cfg = jaw.config
    faces = {f.name: None for f in cfg.fingers}
    misses = {f.name: 0 for f in cfg.fingers}
    active = [f.name for f in cfg.fingers]
    flat: list[FeltTouch] = []
    say("no rolling touch was usable: pressing the pads flat on the faces before them")
    for _ in range(settings.min_touches + FLAT_SPARE):
        if not active:
            break
        spent: dict[str, float] = {}
        plans = {name: _flat_plan(jaw, name, model, faces[name], misses[name], index + k, emit, spent,
                                  _felt_stop(out, name, nominal_psi(cfg.finger(name))))
                 for k, name in enumerate(active)}
        index += len(plans)
        out.rounds += 1
        results = _timed(jaw, plans, spent, out.time_s, "touches", "touch_transits")
        for name in plans:
            felt = feel(cfg, results[name], settings.samples_per_touch)
            out.touches.append(felt)
            if felt.problem is None:
                faces[name] = felt.face
                flat.append(felt)
                emit({"type": "event", "kind": "touch_used", "message": f"{name}: flat press {felt.touch.touch} seated",
                      "touch": felt.touch.touch, "samples": felt.to_json()})
                say(f"flat press ({name}): seated on a face at psi {math.degrees(felt.face.psi):.2f} deg over "
                    f"{felt.face.length:.1f} mm")
            else:
                misses[name] += 1
                if misses[name] >= FLAT_TRIES:
                    active.remove(name)
                if felt.touch.outcome == "ok":
                    felt.touch.outcome = "rejected"
                emit({"type": "event", "kind": "touch_rejected", "message": felt.problem, "touch": felt.touch.touch})
                say(f"flat press ({name}): not used: {felt.problem}")
        out.used = recognized_touches(flat, settings.min_touches)
        for n, miss in curved_faces(flat):
            say(f"{n} flat presses of one face stopped {miss:+.2f} mm short of their supports on average "
                f"(at most {FACE_MISS_MM:g}): a gentle curve, not a face; not recognized as a line")
        if len(out.used) >= settings.min_touches:
            recognition, why = decide(recognize_touches, out.used, settings)
            out.recognition = recognition
            out.answers.append(recognition.cls)
            say(f"after {len(out.used)} flat touches of one face: {recognition.cls}"
                + ("" if why is None else f", not decisive: {why}"))
            if why is None:
                break


def explore(jaw: Jaw, settings: ExploreSettings, recognize_touches: RecognizeTouches,
            emit: Callable[[dict], None] | None = None,
            progress: Callable[[str], None] | None = None) -> Exploration:
    """Explore with both fingers (module docstring). ``recognize_touches`` maps a list of
    usable felt touches to a Recognition (tactile_jaw.pipeline.make_recognizer); ``emit``
    receives log records; ``progress`` one-line messages for people."""
    emit = emit or (lambda rec: None)
    say = progress or (lambda msg: None)
    recognize_touches = _memo(recognize_touches)
    cfg = jaw.config
    ws = cfg.workspace
    model = ObjectModel(ws.center_mm, ws.radius_mm)
    out = Exploration()
    t0 = jaw.robot_time()
    index = 0
    queues = {f.name: probe_psis(f, model) for f in cfg.fingers}
    faces: dict[str, list[float]] = {f.name: [] for f in cfg.fingers}
    refined = False
    while True:
        if not any(queues.values()):
            if refined:
                break
            refined = True  # one more pass: around a finger's only face contact, PROBE_REFINE_DEG either side
            queues = {f.name: [faces[f.name][0] + math.radians(sign * PROBE_REFINE_DEG) for sign in (-1, 1)]
                      if len(faces[f.name]) == 1 else [] for f in cfg.fingers}
            if not any(queues.values()):
                break
        plans, spent = {}, {}
        for name, queue in queues.items():
            if queue:
                plans[name] = _probe_plan(jaw, name, model, queue.pop(0), index + len(plans), emit, spent)
        results = _timed(jaw, plans, spent, out.time_s, "probes", "probe_transits")
        for name in plans:
            felt = feel(cfg, results[name], PROBE_SAMPLES, curve_checks=False)
            probe = felt.touch
            out.probes.append(felt)
            index += 1
            u = probe_face_contact(cfg, felt)
            if u is not None:
                model.add([s.psi_measured for s in probe.samples], [s.d for s in probe.samples])
                faces[name].append(probe.psi_center)
                if np.ptp(faces[name]) >= math.radians(PROBE_ENOUGH_DEG) - 1e-9:
                    queues[name] = []  # enough felt to plan this finger's touches
            say(f"probe {len(out.probes)}: {name} at psi {math.degrees(probe.psi_center):.1f} deg: "
                + (f"pad face {u:.1f} mm from its proximal end" if u is not None else
                   probe.message or f"{len(probe.samples)} samples, not on the pad's face"))
    used: dict[str, list[float]] = {f.name: [] for f in cfg.fingers}
    off_curve: dict[str, int] = {f.name: 0 for f in cfg.fingers}  # the finger's latest touches off the curve
    reach = JawReach(cfg, settings)
    aim: Aim | None = None  # where the next touch goes while the answer is not decisive (tactile_jaw.choose)
    aimed_at: list[tuple[float, float]] = []
    vertex_missed = False  # a touch aimed beyond a parabola's vertex fell off the curved part
    empty_at: list[tuple[float, float]] = []  # points aimed at where the touch met nothing
    cleared = _clear_of_corners(cfg, out, settings, emit, say)
    while _spent(out) < settings.touches:
        if not cleared() and len(out.touches) >= FLAT_AFTER_TOUCHES:
            say(f"none of {len(out.touches)} rolling touches was usable clear of the corners: no curved part "
                f"within reach of the pads")
            break
        plans, spent, aimed = {}, {}, None
        budget = settings.touches - _spent(out)
        active = [f for f in cfg.fingers if off_curve[f.name] < OFF_CURVE_RETIRE][:budget]
        for f in active:
            point = None
            if aim is not None and f.name == aim.finger:
                psi, point, aimed = aim.psi, aim.point, aim
                aimed_at.append(point)
                say(f"{f.name}: next touch at ({aim.x:.1f}, {aim.y:.1f}) mm, pad normal "
                    f"{math.degrees(math.remainder(psi, 2 * math.pi)):.1f} deg, "
                    f"{aim.why}")
            else:
                psi = choose_psi(f, model, settings, used[f.name])
            if psi is None:
                message = (f"{f.name}: no untouched pad orientation left for which the felt lines predict a "
                           f"{math.degrees(settings.roll_span_rad):g} deg roll on the pad's face")
                emit({"type": "event", "kind": "no_orientation", "message": message})
                say(message)
                continue
            used[f.name].append(psi)
            plans[f.name] = _touch_plan(jaw, f.name, model, psi, settings, index + len(plans), emit, spent, point)
        if not plans:
            break
        index += len(plans)
        out.rounds += 1
        results = _timed(jaw, plans, spent, out.time_s, "touches", "touch_transits")
        for name in plans:
            felt = feel(cfg, results[name], settings.samples_per_touch)
            touch, problem = felt.touch, felt.problem
            out.touches.append(felt)
            off_curve[name] = off_curve[name] + 1 if felt.off_curve else 0
            if off_curve[name] == OFF_CURVE_RETIRE:
                message = (f"{name}: its last {OFF_CURVE_RETIRE} touches fell on corners or closing segments: "
                           f"no more touches with this finger")
                emit({"type": "event", "kind": "finger_retired", "message": message})
                say(message)
            if problem is None:
                out.used.append(felt)
                model.add([s.psi_measured for s in touch.samples], [s.d for s in touch.samples])
                emit({"type": "event", "kind": "touch_used", "message": f"{name}: touch {touch.touch} used",
                      "touch": touch.touch, "samples": felt.to_json()})
            else:
                if touch.outcome == "ok":
                    touch.outcome = "rejected"
                emit({"type": "event", "kind": "touch_rejected", "message": problem, "touch": touch.touch})
            say(f"touch {len(out.touches)} ({_spent(out)}/{settings.touches} of the budget): {name} at psi {math.degrees(touch.psi_center):.1f} deg, "
                f"{len(touch.samples)} samples, {'used' if problem is None else 'not used: ' + problem}")
            if aimed is not None and name == aimed.finger and problem is not None:
                vertex_missed |= aimed.kind == "vertex"
                if not touch.samples:
                    empty_at.append(aimed.point)  # the object is not where the answered curve goes on
        usable = cleared()
        if len(usable) >= settings.min_touches:
            recognition, why = decide(recognize_touches, usable, settings)
            out.recognition = recognition
            out.answers.append(recognition.cls)
            say(f"after {len(usable)} touches: {recognition.cls}" + ("" if why is None else f", not decisive: {why}"))
            if why is None:
                break
            active = [f for f in cfg.fingers if off_curve[f.name] < OFF_CURVE_RETIRE]
            aim, out.stopped = next_aim(recognition, why, sample_positions(usable), reach, active, aimed_at,
                                        vertex_missed, empty_at)
            if out.stopped is not None:
                emit({"type": "event", "kind": "stopped_early", "message": out.stopped})
                say(f"stopping after {len(usable)} usable touches: {out.stopped}")
                break
    if not cleared():  # no curved part felt (clear of the corners): the faces, by flat presses
        _flat_presses(jaw, settings, model, out, recognize_touches, emit, say, index)
    here = {f.name: float(jaw.pad_line(jaw.last_state, f.name).psi) for f in cfg.fingers}
    t_retreat = jaw.robot_time()
    run_together(jaw, {name: _transit_or_problem(jaw, name, model, psi) for name, psi in here.items()})  # to the edge
    out.time_s["retreat"] = jaw.robot_time() - t_retreat
    if not model.psi.size:
        message = (f"no probe of {len(out.probes)} found a contact on a pad's face: within reach of the pads the "
                   f"object offers no boundary they can roll on (flat, concave, or felt only by a pad end)")
        emit({"type": "event", "kind": "no_face_contact", "message": message})
        say(message)
    if out.used:
        usable = cleared()
        try:  # the answer on every usable touch, a refusal unless decisive
            out.recognition = final_answer(recognize_touches, usable, settings, out.stopped)
            out.answers.append(out.recognition.cls)
        except InputError as exc:
            emit({"type": "event", "kind": "too_few_touches", "message": str(exc)})
            if len(usable) < len(out.used):  # an earlier round's answer was on touches since cleared
                out.recognition = too_few_clear(usable, len(out.used), exc)
        out.used = usable
    out.robot_time_s = jaw.robot_time() - t0
    return out
