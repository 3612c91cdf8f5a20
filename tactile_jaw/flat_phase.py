"""The flat-press phase (docs/exploration.md#lines-flat-presses): when the rolling touches
found no curved part, every finger presses its pad flat on the face before it
(hand_driver.flat_press), round after round, until the recognizer's answer on one face's
flat touches (tactile_jaw.flat) is decisive.
"""

from __future__ import annotations

import math

from hand_driver import kinematics as kin
from hand_driver.cycle import Jaw
from hand_driver.flat_press import FLAT_STEP_DEG, flat_press
from hand_driver.motion import TouchResult
from tactile_jaw.decide import RecognizeTouches, decide
from tactile_jaw.choose import Stop
from tactile_jaw.flat import FACE_MISS_MM, curved_faces, recognized_touches
from tactile_jaw.pipeline import FeltTouch, curve_refusal, curved_part, feel
from tactile_jaw.plan import ObjectModel, nominal_psi, retreat_offset
from tactile_jaw.rounds import Exploration, timed_round, transit_or_problem
from tactile_jaw.settings import ExploreSettings

#: a finger's first flat press starts at its pad's nominal normal (the press turns toward
#: the seat from there, hand_driver.flat_press); a later one FLAT_RESTART_STEPS turn steps
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
        problem = yield from transit_or_problem(jaw, finger, model, start, spent)
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
        n = kin.unit(start)
        d_start = min(float(n @ face.p), float(n @ face.q)) - FLAT_RESTART_MM
        travel = 2.0 * FLAT_RESTART_MM
    return (yield from flat_press(jaw, finger, touch_index, start, 1, d_start, travel, toward=model.workspace_center,
                                  on_event=emit))


def _curve_felt(cfg, out: Exploration, emit, say) -> bool:
    """Did a touch so far roll on a curved part (tactile_jaw.pipeline.curved_part)? Then the
    faces are closing segments: the exploration stops, refused (``out.recognition``), and
    says what would help (``out.stopped``)."""
    curve = curved_part(cfg, out.touches)
    if curve is None:
        return False
    out.used, out.recognition = [], curve_refusal(curve)
    c, m = curve.contacts, len(curve.contacts.x) // 2
    out.stopped = Stop(f"move or turn the object so that its curved part, felt near ({c.x[m]:.1f}, {c.y[m]:.1f}) mm, "
                       f"faces a pad clear of the object's corners")
    emit(out.stopped.event("stopped_early"))
    say(f"{out.recognition.reason}; {out.stopped}")
    return True


def flat_presses(jaw: Jaw, settings: ExploreSettings, model: ObjectModel, out: Exploration,
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
        if not active or _curve_felt(cfg, out, emit, say):
            break
        spent: dict[str, float] = {}
        plans = {name: _flat_plan(jaw, name, model, faces[name], misses[name], index + k, emit, spent,
                                  _felt_stop(out, name, nominal_psi(cfg.finger(name))))
                 for k, name in enumerate(active)}
        index += len(plans)
        out.rounds += 1
        results = timed_round(jaw, plans, spent, out.time_s, "touches", "touch_transits")
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
        if _curve_felt(cfg, out, emit, say):
            break
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
