"""The flat-press phase (docs/exploration.md#lines-flat-presses): when the rolling touches
found no curved part, every finger presses its pad flat on the face before it
(hand_driver.flat_press), round after round, until the recognizer's answer on one face's
flat touches (tactile_jaw.flat) is decisive.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import Any, Sequence

import numpy as np

from hand_driver import kinematics as kin
from hand_driver.cycle import Jaw
from hand_driver.flat_press import (FACE_MIN_FRACTION, FLAT_MAX_TURN_DEG, FLAT_STEP_DEG, SEAT_TOL_MM,
                                     SPLIT_APART, FlatResult, _run, clear_of_pad_ends, face_normal, flat_press,
                                     lowering_turn, seat_split)
from hand_driver.motion import TouchResult, uncoordinated_overshoot
from recognizer.result import Recognition
from tactile_jaw.decide import RecognizeTouches, decide
from tactile_jaw.choose import (MOVE_TURN_MAX_DEG, Goal, JawReach, Stop, facing_move,
                                move_advice, place_goal)
from tactile_jaw.flat import (BULGED_PRESSES, FACE_MISS_MM, bulged, curved_faces, face_groups, recognized_touches,
                              same_face_rad)
from tactile_jaw.pipeline import FeltTouch, curve_refusal, curved_part, feel, left_out
from tactile_jaw.plan import PROBE_PAD_MARGIN, ObjectModel, nominal_psi, retreat_offset
from tactile_jaw.rounds import Exploration, timed_round, transit_or_problem
from tactile_jaw.settings import ExploreSettings

#: a finger's first flat press starts at its pad's nominal normal (the press turns toward
#: the seat from there, hand_driver.flat_press); a later one FLAT_RESTART_STEPS turn steps
#: before the face's normal it found, from FLAT_RESTART_MM outside it; at most
#: settings.min_touches + FLAT_SPARE rounds; a finger stops after FLAT_TRIES presses whose
#: seat missed the tolerance (one miss can be the encoders' rounding: a seated press of the
#: line example moved 3 mm stopped 0.22 mm off, over the 0.2 mm tolerance; the retry starts
#: half a step further on, other stops, other roundings), or after one that found no seat.
#: The rolling touches give way to flat presses once FLAT_AFTER_TOUCHES of them were
#: tried and none was usable (every one on a corner, a pad end or across a face: the line
#: example turned −5° spent 8 rolling touches, 54 s of robot time, before). A later press
#: starts whole steps farther out where the finger's last seated press, started so, could not
#: tell the lines on that side near the seat (:func:`restart_steps`)
FLAT_RESTART_STEPS = 2.5
#: ... a press started this many steps or fewer from where the next one starts, and a line of it
#: this much nearer the seat than the next press's third stop, are taken for the same (a stop lies
#: nearer its own grid point than the next, half a step off either way: :func:`restart_steps`)
RESTART_MATCH_STEPS = 0.25
FLAT_RESTART_MM = 3.0
FLAT_SPARE = 2
FLAT_TRIES = 2
FLAT_AFTER_TOUCHES = 4
#: a flat press that has not found its seat after this much robot time (s) gives up: on
#: the random blocks of bench_explore --finite 8 --anywhere --seed 11 (both jaws) every
#: press that seated found its seat within 7.9 s (2.5–3.2 s from a known seat), and those
#: that did not took 9–44 s each (one turned 70°, its approaches up to 1.5 s apart), a
#: round lasting as long as its slowest press
FLAT_MAX_S = 12.0
#: a first press beside the other finger's probes or rolls that walks (no face seated, no seat
#: its lines show: :func:`beside_press`) gives up sooner: it holds up the other finger's motion of
#: its round (0.4–3 s). Of the 51 first presses made beside before any usable touch in
#: bench_explore --finite 20 --anywhere --follow --classes line, P seeds 571 and 541, X seed 571,
#: the 46 that seated did so within 7.1 s of their start (transit included); 4 walked 12.0–14.6 s
#: to FLAT_MAX_S and found none while the other pad waited (docs/exploration.md, session 34). A walk
#: so given up is no miss: it is not made beside again, and the flat phase walks again (FLAT_MAX_S,
#: stopped once another pad seats), so no seat the longer walk would have found is lost
FLAT_BESIDE_S = 8.0
#: two rolls whose lines pass through points this close (mm) turned about one corner
#: (:func:`sliding_face`); the X-series rolls about one corner of seed 139's block 18 met it
#: within 0.3 mm, the P-series slides of its block 8 passed through points 4–7 mm apart
PIVOT_AGAIN_MM = 1.0
#: a first press, from the pad's nominal normal, seats a face whose seat lies at most this far
#: (deg) from that normal: it turns FLAT_MAX_TURN_DEG at most, three steps past the seat (its Q
#: lines). A move named for a face leaves the seat there (:func:`_face_advice`): line 17 of
#: bench_explore --finite 20 --seed 283 (near the palm, its long face 79° from the right pad's
#: normal) was moved with the seat 59° from it (P-series): no seat within FLAT_MAX_S, refused again
SEATED_TURN_DEG = FLAT_MAX_TURN_DEG - 3 * FLAT_STEP_DEG


def _felt_stop(out: Exploration, finger: str, psi: float, length_mm: float,
               toward: np.ndarray) -> tuple[float, float, int] | None:
    """Where ``finger``'s first flat press starts, as (ψ, d, first turn ±1), or None: the
    in-contact sample (probes and rolling touches so far) whose orientation is nearest
    ``psi`` (the pad's nominal normal) — a guarded approach at that ψ stops there again, so
    the press starts from just outside it instead of the workspace edge — or, when that
    normal lies among ≥ 3 of the finger's lines through one corner on the pad (more than
    SEAT_TOL_MM from either end: not a pad end resting on the object; lines whose corner lies
    off that part of the pad, at either end of the run through it, are left out: X line 18 of bench_explore --finite 20
    --anywhere --seed 439, whose left pad's probe at −70° met its rolls' corner with the
    proximal end, 0.14 mm along the pad, and whose first press walked 9 scan steps from −91°
    to its seat at −121.9°), FLAT_RESTART_STEPS
    before the end of those lines' ψ range the press would walk to, turning that way first,
    at the stop those lines give there. Every normal between two of a corner's pad normals
    is its normal too (its normal cone is one arc), so a press from ``psi`` pivots about that
    corner, lowering the part of the pad hand_driver.flat_press.lowering_turn names
    (``toward``: the workspace centre, as the press turns), step by step through the known
    range; from 2.5 steps before its end the press still has three lines through the corner,
    the seat's first support, and goes on as it would have. Not when that skips less than a
    step. P line 2 of bench_explore --finite 20 --anywhere --seed 313: the left pad's lines
    passed through one corner from −113° to −27°, its first press walked from −91° to its
    seat at −115° (7 scan steps, 4.8 s); from −105.5°, 1 step, 2.8 s (docs/exploration.md).
    Else, when that nearest stop rested on a pad end (:func:`_end_turns`), the press lowers the
    whole pad about it and walks that way: it starts at the farthest stop beyond that rested on
    a pad end lowering the same way, each stop on the way one (no seat there), turning that way
    first. P line 14 of bench_explore --finite 20 --anywhere --seed 439: the left pad's probes
    at −90° and −110° rested on its proximal end, its first press walked from −91° to its seat
    at −119.5° (8 scan steps, 6.0 s); from −113°, 2 steps, 4.4 s."""
    samples = [s for t in (*out.probes, *out.touches) if t.touch.finger == finger
               and not isinstance(t.touch, FlatResult) for s in t.touch.samples]
    if not samples:
        return None
    samples.sort(key=lambda s: math.remainder(float(s.line.psi) - psi, 2 * math.pi))
    rel = [math.remainder(float(s.line.psi) - psi, 2 * math.pi) for s in samples]
    lines = [s.line for s in samples]
    step = math.radians(FLAT_STEP_DEG)
    for i in range(len(lines)):
        n, corner, _ = _run(lines, i, 1, SEAT_TOL_MM)
        if n < 3 or not rel[i] - 0.5 * step <= 0.0 <= rel[i + n - 1] + 0.5 * step:
            continue
        # the corner on the pad: lines with a pad end on it or past it say nothing of its normals, left out at the run's ends
        inner = [j for j in range(i, i + n) if clear_of_pad_ends(lines[j], corner, length_mm)]
        if (len(inner) < 3 or inner[-1] - inner[0] + 1 != len(inner)
                or not rel[inner[0]] - 0.5 * step <= 0.0 <= rel[inner[-1]] + 0.5 * step):
            break  # a pad end resting on the object among them, or at the normal: its lines say nothing of a corner's normals
        i, n = inner[0], len(inner)
        turn = lowering_turn(lines[min(range(i, i + n), key=lambda j: abs(rel[j]))], corner, length_mm, toward)
        if turn is None:
            break
        start = rel[i + n - 1 if turn == 1 else i] - turn * FLAT_RESTART_STEPS * step
        if turn * start < step:
            break
        return psi + start, float(kin.unit(psi + start) @ corner), turn
    s = min(samples, key=lambda s: abs(math.remainder(s.psi - psi, 2 * math.pi)))
    turns = _end_turns(out, finger, length_mm, toward)
    turn = turns.get(id(s))
    if turn is not None:  # s rests on a pad end: on past every stop beyond that rests on one lowering the same way
        offset = {id(x): math.remainder(x.psi - s.psi, 2 * math.pi) for x in samples}
        last = s
        for x in sorted((x for x in samples if turn * offset[id(x)] > 0), key=lambda x: turn * offset[id(x)]):
            if turns.get(id(x)) != turn:
                break
            last = x
        if turn * offset[id(last)] >= step:
            return float(last.psi), float(last.line.d), turn
    return float(s.psi), float(s.line.d), 1


def _end_turns(out: Exploration, finger: str, length_mm: float, toward: np.ndarray) -> dict[int, int]:
    """Per sample (by id) of ``finger``'s probes and rolling touches that met the object only at
    a pad end — every two neighbouring pad lines of the touch crossing within PROBE_PAD_MARGIN
    of the pad's length of one end (a pad end resting on the object, or a corner under it, as
    tactile_jaw.plan.probe_face_contact tells a face contact from it) — the turn that lowers
    the pad about where its line crosses its neighbour's (hand_driver.flat_press.lowering_turn,
    as a flat press turns there: the whole pad). A corner under the pad's middle is
    :func:`_felt_stop`'s normal cone instead."""
    turns: dict[int, int] = {}
    margin = PROBE_PAD_MARGIN * length_mm
    for t in (*out.probes, *out.touches):
        samples = t.touch.samples
        if t.touch.finger != finger or isinstance(t.touch, FlatResult) or len(samples) < 2:
            continue
        points = [kin.crossing(a.line, b.line) for a, b in zip(samples, samples[1:])]
        if any(x is None or margin < float(a.line.pad_coordinate(x)) < length_mm - margin
               for a, x in zip(samples, points)):
            continue
        for k, a in enumerate(samples):
            turn = lowering_turn(a.line, points[min(k, len(points) - 1)], length_mm, toward)
            if turn is not None:
                turns[id(a)] = turn
    return turns


def _felt_seat(out: Exploration, finger: str, length_mm: float, psi: float) -> tuple[float, np.ndarray, np.ndarray] | None:
    """(ψ, P, Q) of the seat the pad lines of ``finger``'s probes and rolling touches so far
    already show, or None: sorted by ψ (about ``psi``, the pad's nominal normal) they are
    support lines of what the pad reaches, and where three pass through one support and
    three through another at least FACE_MIN_FRACTION of the pad apart
    (hand_driver.flat_press.seat_split: a roll across a closing segment, or rolls that
    pivoted about both corners of one face), the pad lies flat at the normal of the two.
    The press starts there as a later press starts at its face: the walk to the seat from
    the pad's nominal normal (up to 60°, 3° a step) is left out."""
    samples = [s for t in (*out.probes, *out.touches) if t.touch.finger == finger for s in t.touch.samples]
    samples.sort(key=lambda s: math.remainder(float(s.line.psi) - psi, 2 * math.pi))
    lines = [s.line for s in samples]
    found = seat_split(lines, length_mm) if len(lines) >= 6 else None
    if found is None or np.linalg.norm(found[2] - found[1]) < FACE_MIN_FRACTION * length_mm:
        return None
    _, p, q = found
    normal = face_normal(p, q, lines[0].normal)
    return math.atan2(normal[1], normal[0]), p, q


def guard_done(cfg, out: Exploration, pressed: Sequence[FeltTouch], settings: ExploreSettings) -> str | None:
    """Why the closing-segment guard has nothing left to look for once one face's presses
    answer, or None. The guard rolls the other fingers to see whether their side holds a
    curved part, of which the pressed face would be the closing segment (a curved object's
    one straight face). It is done when one finger's seated presses of ``pressed`` already
    make the flat phase's answer (``settings.min_touches`` on one face, none stopped short
    of its supports once: :func:`_bulge_pending`) and every other finger met with its own
    probes and rolls a second straight face (:func:`straight_side`) more than SPLIT_APART ·
    SEAT_TOL_MM off the pressed face's line at both supports: a finite curved object closed
    by one straight segment has no second, and the lines of a curve, of a radius its rolls
    tell from 0, meet no two corners. One closed by several segments (the cubical example's
    three) may show two straight faces, both closing segments: then the second face proves
    only that the other finger's lines so far met no curved part — a roll of it that turned
    past a corner onto a curved part would not pass through P or Q and would keep the guard,
    and any touch that felt one refuses the line (flat_phase._curve_felt) — not that no curved
    part lies beyond a corner at normals its rolls did not reach. The demo of such a block turned
    −90° (its curved part facing +x, out of both pads' reach: tests/tactile_jaw/test_guard_done.py)
    ends here and answers line with and without this stop, in the same robot time. P line 19 of bench_explore --finite 20 --anywhere --follow --seed 571: the
    right pad's third press answered at 16.2 s, the left then probed and rolled across the
    block's far face until 23.4 s (docs/exploration.md, session 34)."""
    state = _booked(cfg, pressed)
    answer = recognized_touches(state.flat, settings.min_touches)
    if len(answer) < settings.min_touches or _bulge_pending(state, out.touches):
        return None
    face = answer[0].face
    sides = []
    for f in cfg.fingers:
        if f.name == answer[0].finger:
            continue
        side = straight_side(out, f.name, f.pad.length_mm, nominal_psi(f))
        if side is None or min(abs(float(face.normal @ x) - face.d) for x in side) <= SPLIT_APART * SEAT_TOL_MM:
            return None
        sides.append(f"the {f.name} pad's lines met a straight face from ({side[0][0]:.1f}, {side[0][1]:.1f}) to "
                     f"({side[1][0]:.1f}, {side[1][1]:.1f}) mm and nothing else")
    return (f"the {answer[0].finger} pad's {len(answer)} presses on one face answer, and "
            + "; ".join(sides) + ": no curved part left to guard against")


def straight_side(out: Exploration, finger: str, length_mm: float, psi: float) -> tuple[np.ndarray, np.ndarray] | None:
    """The straight face (its supports P, Q) that ``finger``'s probes and rolls met, when they
    met nothing else, or None: their lines show a seat (:func:`_felt_seat`: three lines through
    each of two points at least FACE_MIN_FRACTION of the pad apart, the pad flat between), every
    roll felt no stretch of a curved part (tactile_jaw.pipeline: ``curve_at``) and every one
    that did not stop on a pad end fell on a corner or across a closing segment (``off_curve``:
    its radius of curvature told from 0 at the jaw's noise), and every line met on the pad's
    face passes within SEAT_TOL_MM of P or Q. A pad end resting on the object (outcome
    ``edge``) tells no support line: its lines are left out."""
    seat = _felt_seat(out, finger, length_mm, psi)
    if seat is None:
        return None
    _, p, q = seat
    rolls = [t for t in out.touches if t.finger == finger and not isinstance(t.touch, FlatResult)]
    if any(t.curve_at is not None or (t.touch.samples and t.touch.outcome != "edge" and not t.off_curve)
           for t in rolls):
        return None
    met = [t for t in (*out.probes, *rolls) if t.finger == finger and t.touch.samples and t.touch.outcome != "edge"]
    for t in met:
        for s in t.touch.samples:
            n, d = kin.unit(float(s.line.psi)), float(s.line.d)
            if min(abs(float(n @ p) - d), abs(float(n @ q) - d)) > SEAT_TOL_MM:
                return None
    return p, q


def restart_steps(press: FlatResult, face_psi: float, side: int, restart: float = FLAT_RESTART_STEPS) -> float:
    """How many FLAT_STEP_DEG turn steps before the normal ``face_psi`` of the face it seated on
    a finger's next press there starts, from ``side`` (+1: below the normal) as before, after its
    seated ``press``, which started ``restart`` steps before it: when ``press`` started there (within
    RESTART_MATCH_STEPS), ``restart`` plus the whole steps that put the third stop on that side more than
    RESTART_MATCH_STEPS beyond every line of ``press`` on that side that lay between its two supports'
    runs (role ``scan``: it fitted neither, hand_driver.flat_press.seat_split); else ``restart``.
    The same pad on the same face, started and turned alike, rests the same way at each stop, so such
    a stop is no support's again, and the press turned through the seat in whole steps, then back past
    its start for the missing third line and forth again. P line 2 of bench_explore --finite 20
    --anywhere --seed 599 (a face's second support a pad end sliding on past its corner): the line
    half a step from the seat fitted neither support in each of its three presses, each turned 12°
    back and 15° forth, 4.0 s a press where the others took 2.5 s. A press started elsewhere (from the
    pad's nominal normal: its stops on another grid, the pad resting otherwise) tells nothing of it:
    seed 599's first presses had such lines 0.04–0.69 steps from the seat, and the later presses from
    FLAT_RESTART_STEPS had none; nor does a press without lines through both supports."""
    if side not in (1, -1):
        raise ValueError(f"side must be +1 or -1, not {side!r}")
    step = math.radians(FLAT_STEP_DEG)
    supported = [k for k, role in enumerate(press.roles) if role in ("P", "Q")]
    started = -side * math.remainder(press.psi_center - face_psi, 2 * math.pi) / step
    if {press.roles[k] for k in supported} != {"P", "Q"} or abs(started - restart) > RESTART_MATCH_STEPS:
        return restart
    offsets = [math.remainder(float(s.line.psi) - face_psi, 2 * math.pi) / step for s in press.samples]
    low, high = sorted((max(offsets[k] for k in supported if press.roles[k] == r),
                        min(offsets[k] for k in supported if press.roles[k] == r)) for r in ("P", "Q"))
    between = [-side * x for x, role in zip(offsets, press.roles)
               if role == "scan" and low[0] < x < high[1] and -side * x > 0.0]
    if not between:
        return restart
    return restart + max(0, math.floor(max(between) - (restart - 2.0) + RESTART_MATCH_STEPS) + 1)


def _timed_out(max_s: float) -> str:
    """Why a press gave up after ``max_s`` without a seat (its message; :func:`_flat_plan`)."""
    return f"no seat found within {max_s:g} s"


def _flat_plan(jaw: Jaw, finger: str, model: ObjectModel, face, misses: int, touch_index: int, emit,
               spent: dict[str, float], felt: tuple[float, float, int] | None = None, seated: set[str] | None = None,
               seat: tuple[float, np.ndarray, np.ndarray] | None = None, side: int = 1,
               max_s: float = FLAT_MAX_S, restart: float = FLAT_RESTART_STEPS):
    """One flat press of ``finger``: the first at the pad's nominal normal (after a transit)
    from the workspace edge, or — ``felt``, an earlier stop (ψ, d) near that normal and the
    way to turn first (:func:`_felt_stop`) — at that ψ from FLAT_RESTART_MM outside that stop
    (1.4 s less of guarded approach on the line example) — or ``seat``, one the rolls already show (:func:`_felt_seat`), as a later press
    starts at its face; a later one close to the ``face`` it seated on (module constants;
    ``restart`` steps before its normal: :func:`restart_steps`),
    on the ``side`` of it (+1: below its normal, turning up; −1: above) the finger's first
    seated press came from (the other side may lie beyond a joint limit); after
    ``misses`` presses that did not seat, from the edge, half a step further on each. While
    it seeks its seat it gives up once another finger's press of the same round is added to
    ``seated`` (pressed at its seat), in the cycle it is added, mid-turn or mid-approach:
    one face's touches make the answer, or after
    ``max_s`` of robot time without a seat (then its ``seek_limit_s``; :meth:`_Faces.book`). Returns the
    FlatResult (or a TouchResult if the transit could not go on)."""
    step = math.radians(FLAT_STEP_DEG)
    f = jaw.config.finger(finger)
    if face is None and seat is not None and misses == 0:  # a seat the rolls showed (_felt_seat): as a later press
        start = seat[0] - FLAT_RESTART_STEPS * step
        felt = (start, min(float(kin.unit(start) @ seat[1]), float(kin.unit(start) @ seat[2])), 1)  # where it stops there
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
        start = face.psi - side * (restart + 0.5 * misses) * step
        n = kin.unit(start)
        d_start = min(float(n @ face.p), float(n @ face.q)) - FLAT_RESTART_MM
        # each joint runs its own profile: from the seat the base joint's turn ends first and
        # pressed the pad onto the face's corner on the way (random block 18 of bench_explore
        # --finite 20 --anywhere --seed 139, P-series: stuck there, "no contact"); start as
        # far out as keeps both supports clear wherever a joint arrives first
        extra = max(uncoordinated_overshoot(jaw, finger, start, d_start, s) for s in (face.p, face.q))
        d_start -= extra
        travel = 2.0 * FLAT_RESTART_MM + extra
    seated = set() if seated is None else seated
    t0 = jaw.robot_time()

    def seated_other() -> str | None:
        others = sorted(seated - {finger})
        return f"the {others[0]} pad seated on a face" if others else None

    timed_out = False  # give_up ended the seek at max_s (the press stops as soon as it gives a reason)

    def give_up() -> str | None:
        nonlocal timed_out
        other = seated_other()
        timed_out = other is None and jaw.robot_time() - t0 > max_s
        return other or (_timed_out(max_s) if timed_out else None)

    first_turn = side if face is not None else felt[2] if felt is not None and misses == 0 else 1
    result = yield from flat_press(jaw, finger, touch_index, start, first_turn, d_start, travel,
                                   toward=model.workspace_center, on_event=emit, give_up=give_up,
                                   interrupt=seated_other, face=None if face is None else (face.p, face.q))
    if result.outcome == "ok":
        seated.add(finger)
    if timed_out:
        result.seek_limit_s = max_s
    return result


def _curve_felt(cfg, settings: ExploreSettings, out: Exploration, emit, say, checked: set[int]) -> bool:
    """Did a touch so far roll on a curved part (tactile_jaw.pipeline.curved_part: a press's
    scan, or a roll's stretch beside the corner it crossed)? Then the faces are closing
    segments: the exploration stops, refused (``out.recognition``), and says what would help
    (``out.stopped``, :func:`curve_stop`). ``checked``: the touches (their ``id``) found no
    curve before, not felt again (a press's scan of 30 lines is felt on every run of its
    lines: seconds of CPU a round); updated."""
    # a bulged press is counted again, its scan not felt again: it shows a curved part only
    # with another (flat.bulged_presses)
    new = [t for t in out.touches if id(t) not in checked or bulged(t)]
    curve = curved_part(cfg, new, checked)
    if curve is None:
        checked.update(id(t) for t in new)
        return False
    out.used, out.recognition = [], curve_refusal(curve)
    out.stopped = curve_stop(cfg, settings, curve, next(t for t in new if t.touch.touch == curve.touch.touch),
                             out.probes)
    emit(out.stopped.event("stopped_early"))
    say(f"{out.recognition.reason}; {out.stopped}")
    return True


def curve_stop(cfg, settings: ExploreSettings, curve: FeltTouch, felt: FeltTouch,
               probes: Sequence[FeltTouch] = ()) -> Stop:
    """What would help once ``curve`` (tactile_jaw.pipeline.curved_part), a stretch of the
    touch ``felt``, rolled on a curved part that no usable touch measured: where ``felt``
    left that part at one end of its ψ range more than at the other (a roll run onto a
    corner or closing segment: more of its samples left out on that side), the move of the
    object after which a pad rolls on from the stretch's other end through a roll's span of
    tangent (a roll centred half a span past that end, placed ρ·span/2 on along the
    stretch's direction of travel), away from the corner (tactile_jaw.choose.move_advice);
    else (a press's scan, or a stretch cut on both sides) a pad clear of the corners there;
    for presses whose seats bulged (tactile_jaw.flat.bulged_presses), the move after which a
    pad rolls across the middle of their supports with the seat's tangent. ``probes``: the
    exploration's, whose rested pad ends bound every move (tactile_jaw.choose.JawReach.opened_clear)."""
    reach = JawReach(cfg, settings, probes)
    if isinstance(curve.touch, FlatResult):
        x, y = (float(v) for v in curve.face.middle)
        where = f"the curved part the {curve.finger} pad pressed near ({x:.1f}, {y:.1f}) mm"
        goal = place_goal(x, y, curve.face.psi - math.pi / 2, np.stack([curve.face.p, curve.face.q], axis=1))
        advice = move_advice(reach, replace(goal, where=where), [cfg.finger(curve.finger)])
        return Stop(f"{advice.words} ({where}; the rolls there met its corners)" if advice.kind == "within_reach"
                    else advice.words, advice.move)
    c, m = curve.contacts, len(curve.contacts.x) // 2
    psi = np.asarray(c.psi, dtype=float)
    low, high = left_out(felt, curve)  # samples left out below and above the stretch's ψ range
    near = f"felt near ({c.x[m]:.1f}, {c.y[m]:.1f}) mm"
    if low == high:  # a roll centred on the stretch, the pad through its middle with its tangent
        finger = cfg.finger(felt.finger)
        goal = replace(place_goal(float(c.x[m]), float(c.y[m]), float(psi[m]) - math.pi / 2, (c.x, c.y)),
                       where=f"on its curved part, {near}")
        advice = move_advice(reach, goal, [finger])
        if advice.kind == "within_reach":  # reached there, yet its rolls met the corners
            facing = facing_move(reach, goal, finger)
            if facing is not None:
                return Stop(f"{facing[0]}, facing the {felt.finger} pad's first rolls", facing[1])
            return Stop(f"the {felt.finger} pad reaches its curved part, {near}, and no turn up to "
                        f"{MOVE_TURN_MAX_DEG:g} deg makes it face that pad's first rolls: move or turn the object so "
                        f"that more of its curved part, clear of its corners, faces a finger")
        return Stop(advice.words, advice.move)
    end = -1 if low > high else 0  # on past the end away from where the roll left the curved part
    way = 1.0 if low > high else -1.0  # ψ (and the tangent) grow toward the contacts' last
    back = end - int(way)  # the contact before the end, toward the stretch's other end
    step = np.array([c.x[end] - c.x[back], c.y[end] - c.y[back]])
    along = step / max(float(np.linalg.norm(step)), 1e-9)
    half = 0.5 * settings.roll_span_rad
    x, y = np.array([c.x[end], c.y[end]]) + along * float(curve.fit.rho) * half
    phi = float(psi[end]) + way * half - math.pi / 2
    goal = Goal(((float(x), float(y), phi),), np.array([c.x, c.y], dtype=float), (float(c.x[m]), float(c.y[m])),
                f"on along its curved part, {near}, past the end of that stretch away from the corner "
                f"{felt.finger} roll {felt.touch.touch} ran onto")
    advice = move_advice(reach, goal)
    return Stop(advice.words, advice.move)


def early_press(jaw: Jaw, finger: str, model: ObjectModel, out: Exploration, touch_index: int, emit,
                spent: dict[str, float]):
    """The flat press ``finger`` makes instead of its second rolling touch, or None: after a
    first round of rolls of which none was usable, a finger whose probe and roll lines
    already show a seat (:func:`_felt_seat`: its roll crossed a face, or pivoted about both
    its corners) presses there, in the same round as the other finger's second roll
    (tactile_jaw.explore). The other finger's roll still looks for a curved part (the
    guard the second round of rolls is for), and this press's scan is one too
    (tactile_jaw.pipeline.curved_part); should a roll find a curved part, the press is
    not recognized (tactile_jaw.flat.recognized_touches). It gives up only after
    ``FLAT_MAX_S`` without a seat."""
    f = jaw.config.finger(finger)
    seat = _felt_seat(out, finger, f.pad.length_mm, nominal_psi(f))
    if seat is None:
        return None
    return _flat_plan(jaw, finger, model, None, 0, touch_index, emit, spent, None, set(), seat)


def beside_press(jaw: Jaw, finger: str, model: ObjectModel, out: Exploration, pressed: Sequence[FeltTouch],
                 settings: ExploreSettings, touch_index: int, emit, spent: dict[str, float], seat_only: bool = False):
    """The flat press a finger with no roll to make (retired after its rolls fell on corners or
    closing segments, no orientation to roll at, a face seated already, or its probes done:
    tactile_jaw.explore) makes in a round in which another finger still probes or rolls, or
    None: its first at a seat its lines show (:func:`_felt_seat`) or from its nominal normal,
    later ones on the face it seated on, as the flat phase would make them (``pressed``:
    every press made during the rolls, booked as :func:`flat_presses` books them); None once
    it has ``settings.min_touches`` seated presses or stopped for misses (``FLAT_TRIES``), and
    after a press that missed while it has no face (a retry beside the other pad's roll ran 12.4 s
    without a seat on X-series block 3 of seed 107; the flat phase stops one once another pad
    seats), and with ``seat_only`` when it has neither a face nor a seat its lines show (a press
    beside probes, tactile_jaw.probing: a walk from the nominal normal, 4–12 s, would hold up
    rounds of 1.5–2.5 s). A walk (no face, no seat) gives up after ``FLAT_BESIDE_S`` without a
    seat, not ``FLAT_MAX_S``, and is not made beside again (:class:`_Faces` ``walked``): P line 4 of
    bench_explore --finite 20 --anywhere --follow --seed 571, the left pad walked 12.1 s without a
    seat beside the right's one 1.0 s probe.
    The flat phase counts these presses first and decides on them before pressing more: the
    presses the block's answer needs run while the other finger still looks for a curved part,
    which it did alone before (bench_explore --finite 20 --anywhere --seed 107, P-series: random
    blocks whose one finger retired after two rolls on one corner while the other probed for
    4–7 s more, its pad idle). Should a curved part be felt, no press is recognized
    (tactile_jaw.flat.recognized_touches; tactile_jaw.pipeline.curved_part)."""
    state = _booked(jaw.config, pressed)
    if finger not in state.active or sum(t.finger == finger for t in state.flat) >= settings.min_touches:
        return None
    f = jaw.config.finger(finger)
    seat = _felt_seat(out, finger, f.pad.length_mm, nominal_psi(f))
    if state.faces[finger] is None and (state.misses[finger] or (seat is None and (seat_only or finger in state.walked))):
        return None  # a retry, or a walk again, is the flat phase's, which stops it once another pad seats
    walk = state.faces[finger] is None and seat is None  # from its nominal normal: bounded by FLAT_BESIDE_S
    return _flat_plan(jaw, finger, model, state.faces[finger], state.misses[finger], touch_index, emit, spent,
                      _felt_stop(out, finger, nominal_psi(f), f.pad.length_mm, model.workspace_center), set(), seat,
                      state.sides[finger], FLAT_BESIDE_S if walk else FLAT_MAX_S,
                      state.restarts.get(finger, FLAT_RESTART_STEPS))


def _booked(cfg, pressed: Sequence[FeltTouch], emit=None, say=None) -> "_Faces":
    """Each finger's flat-press state after the presses ``pressed`` (:class:`_Faces`)."""
    names = [f.name for f in cfg.fingers]
    state = _Faces(dict.fromkeys(names), dict.fromkeys(names, 0), dict.fromkeys(names, 1), list(names))
    for felt in pressed:
        state.book(felt.finger, felt, set(), emit or (lambda rec: None), say or (lambda msg: None))
    return state


@dataclass
class _Faces:
    """Each finger's flat-press state: the face it seated on, its presses that missed, the
    side of its face its first seated press came from, the seated presses so far, the fingers
    whose walk beside gave up after FLAT_BESIDE_S (no miss: the flat phase walks again), and how
    many turn steps before its face's normal its next press starts (:func:`restart_steps`)."""

    faces: dict[str, Any]
    misses: dict[str, int]
    sides: dict[str, int]
    active: list[str]
    flat: list[FeltTouch] = field(default_factory=list)
    walked: set[str] = field(default_factory=set)
    restarts: dict[str, float] = field(default_factory=dict)

    def book(self, name: str, felt: FeltTouch, seated: set[str], emit, say) -> None:
        """Count ``name``'s press ``felt`` (``seated``: the fingers whose press of the same
        round seated), log it and say it."""
        if felt.problem is None:
            if self.faces[name] is None:
                self.sides[name] = 1 if math.remainder(felt.face.psi - felt.touch.psi_center, 2 * math.pi) >= 0 else -1
            self.faces[name] = felt.face
            self.restarts[name] = restart_steps(felt.touch, felt.face.psi, self.sides[name],
                                                self.restarts.get(name, FLAT_RESTART_STEPS))
            self.flat.append(felt)
            emit({"type": "event", "kind": "touch_used", "message": f"{name}: flat press {felt.touch.touch} seated",
                  "touch": felt.touch.touch, "samples": felt.to_json()})
            say(f"flat press ({name}): seated on a face at psi {math.degrees(felt.face.psi):.2f} deg over "
                f"{felt.face.length:.1f} mm")
            return
        # retried: a press whose seat missed the tolerance (the encoders' rounding), a
        # later press on a face found (half a step further on), one stopped for another
        # finger's seat (should that seat not be a face); not: a first press that
        # found no seat (turned its range, ran out of time, met nothing)
        outcome = felt.touch.outcome
        for_other = outcome == "stopped" and bool(seated - {name})
        if outcome == "stopped" and felt.touch.seek_limit_s == FLAT_BESIDE_S:
            self.walked.add(name)  # a walk beside cut short (FLAT_BESIDE_S): the flat phase walks again
            for_other = True
        retry = outcome in ("ok", "rejected") or self.faces[name] is not None
        self.misses[name] += 0 if for_other else 1 if retry else FLAT_TRIES
        if self.misses[name] >= FLAT_TRIES and name in self.active:
            self.active.remove(name)
        if felt.touch.outcome == "ok":
            felt.touch.outcome = "rejected"
        emit({"type": "event", "kind": "touch_rejected", "message": felt.problem, "touch": felt.touch.touch})
        say(f"flat press ({name}): not used: {felt.problem}")


def flat_presses(jaw: Jaw, settings: ExploreSettings, model: ObjectModel, out: Exploration,
                 recognize_touches: RecognizeTouches, emit, say, index: int,
                 pressed: Sequence[FeltTouch] = (), checked: set[int] | None = None) -> None:
    """Every finger presses its pad flat on the face before it, round after round, until
    the recognizer's answer on one face's flat touches (tactile_jaw.flat.recognized_touches)
    is decisive; a finger stops after FLAT_TRIES presses that did not seat. ``pressed``:
    the presses made during the probes and rolls (:func:`early_press`, :func:`beside_press`,
    already in ``out.touches``), counted first and decided on before any more; ``checked``:
    the touches (their ``id``) whose scans were found to roll on no curve already. ``out.used``
    ends as those touches."""
    cfg = jaw.config
    say("no rolling touch was usable: pressing the pads flat on the faces before them")
    state = _booked(cfg, pressed, emit, say)
    checked = set() if checked is None else checked  # touches whose scans rolled on no curve (_curve_felt)
    if state.flat and (_curve_felt(cfg, settings, out, emit, say, checked)
                       or (not _bulge_pending(state, out.touches)
                           and _decided(out, state.flat, settings, recognize_touches, say))):
        return  # the presses made during the rolls decide (or a curve was felt)
    for _ in range(max(FLAT_SPARE, settings.min_touches + FLAT_SPARE - len(pressed))):
        pending = _bulge_pending(state, out.touches)
        if any(state.faces.values()):  # one face's touches make the answer: a finger without one stops,
            # unless its press bulged once: it presses again first
            state.active = [name for name in state.active if state.faces[name] is not None or name in pending]
        if not state.active or _curve_felt(cfg, settings, out, emit, say, checked):
            break
        spent: dict[str, float] = {}
        seated: set[str] = set()
        plans = {name: _flat_plan(jaw, name, model, state.faces[name], state.misses[name], index + k, emit, spent,
                                  _felt_stop(out, name, nominal_psi(cfg.finger(name)), cfg.finger(name).pad.length_mm,
                                             model.workspace_center),
                                  set() if name in pending else seated,  # not stopped by another pad's seat
                                  _felt_seat(out, name, cfg.finger(name).pad.length_mm, nominal_psi(cfg.finger(name))),
                                  state.sides[name], restart=state.restarts.get(name, FLAT_RESTART_STEPS))
                 for k, name in enumerate(state.active)}
        index += len(plans)
        out.rounds += 1
        results = timed_round(jaw, plans, spent, out.time_s, "touches", "touch_transits")
        for name in plans:
            felt = feel(cfg, results[name], settings.samples_per_touch)
            out.touches.append(felt)
            state.book(name, felt, seated, emit, say)
        if _curve_felt(cfg, settings, out, emit, say, checked):
            break
        pending = _bulge_pending(state, out.touches)
        if pending:
            say(f"a flat press of the {' and '.join(sorted(pending))} pad stopped short of its supports once: it "
                f"presses again before one face is answered")
            continue
        if _decided(out, state.flat, settings, recognize_touches, say):
            return
    if out.stopped is None:  # undecided, no curve felt: where a face was felt, the move after which a pad presses it
        out.stopped = short_face_stop(cfg, settings, out, len(state.flat))
        if out.stopped is not None:
            emit(out.stopped.event("stopped_early"))
            say(str(out.stopped))


def short_face_stop(cfg, settings: ExploreSettings, out: Exploration, seated: int = 0,
                    head: str | None = None) -> Stop | None:
    """When the flat presses end undecided (``seated`` of them seated; ``head``, the message's
    start, says so unless given: tactile_jaw.explore.closing_answer asks it of rolls that left too few usable touches
    clear of the corners, no press made): the longest face a
    press found — a seated press's supports, else what its lines show
    (the path one pad end of its lines slid along, :func:`_slid_path`, else
    hand_driver.flat_press.seat_split without the FACE_MIN_FRACTION bound: a face lying
    mostly beyond the pad's end, whose supports are that end and one corner) — and the move
    of the object after which that pad rolls through both its supports with its tangent
    (tactile_jaw.choose.move_advice): that face, under the pad and clear of its joint limits,
    then seats. None if no press found one. Random block 3 of bench_explore --finite 4
    --anywhere --seed 11: both pads met faces of 14.6 mm mostly beyond their proximal ends (the
    right over 9.1 mm), its other faces 71° from the pads' normals; block 1 of --finite 10
    --seed 17: the right pad seated once on a face of 12.7 mm 33° from its normal, its later
    presses ran into its joint limits. Both were refused before with no move named. When none of
    these, nor a corner's face (:func:`_corner_stop`), gives a move: the longest path a pad end
    slid along in part of a press (:func:`_slid_path` with ``part``; session 32)."""
    best = None
    presses = [(t, sorted((smp.line for smp in t.touch.samples), key=lambda ln: float(ln.psi))) for t in out.touches
               if isinstance(t.touch, FlatResult) and len(t.touch.samples) >= 6]
    for t, lines in presses:
        length_mm = cfg.finger(t.finger).pad.length_mm
        toward = t.touch.samples[-1].line.normal
        if t.face is not None:
            found = (None, t.face.p, t.face.q)
        else:  # the path a pad end slid along is the face; the crossings of its lines lie off the object
            slid = _slid_path(lines, length_mm)
            found = seat_split(lines, length_mm) if slid is None else (None, slid[0], slid[1])
            toward = toward if slid is None else slid[2]
        if found is not None and (best is None or np.linalg.norm(found[2] - found[1]) > best[0]):
            best = (float(np.linalg.norm(found[2] - found[1])), t.finger, found[1], found[2], toward)
    for f in cfg.fingers:  # ... or one a pad end slid along during the rolls
        slid = sliding_face([t for t in out.touches if t.finger == f.name and t.lines is not None
                             and not isinstance(t.touch, FlatResult)], f.pad.length_mm)
        if slid is not None and (best is None or slid[0] > best[0]):
            best = (slid[0], f.name, *slid[1:])
    head = head or ("no flat press seated" if not seated else
                    f"{seated} flat press{'es' if seated > 1 else ''} seated, fewer than the answer needs on one face")
    if best is None:
        corner = _corner_stop(cfg, settings, out, head)
        if corner is not None:
            return corner
        for t, lines in presses:  # ... else the path a pad end slid along in part of a press
            slid = _slid_path(lines, cfg.finger(t.finger).pad.length_mm, part=True)
            if slid is not None and (best is None or np.linalg.norm(slid[1] - slid[0]) > best[0]):
                best = (float(np.linalg.norm(slid[1] - slid[0])), t.finger, *slid)
    if best is None:
        return None
    length, finger, p, q, toward = best
    advice, move, mid, psi = _face_advice(cfg, settings, out, finger, p, q, toward)
    short = length < FACE_MIN_FRACTION * cfg.finger(finger).pad.length_mm
    return Stop(f"{head}; the {finger} pad met a face near ({mid[0]:.0f}, {mid[1]:.0f}) mm, pad normal "
                f"{math.degrees(psi):.0f} deg, over {length:.1f} mm of the pad"
                + (f" (a seat needs {FACE_MIN_FRACTION:g} of it)" if short else "") + f": {advice}", move)


def _face_advice(cfg, settings: ExploreSettings, out: Exploration, finger: str, p: np.ndarray, q: np.ndarray,
                 toward: np.ndarray, reach: JawReach | None = None,
                 corner: bool = False) -> tuple[str, dict | None, np.ndarray, float]:
    """The move after which the pad of ``finger`` rolls through the face PQ's ends and middle
    with its tangent (the pad's normal along ``toward``: tactile_jaw.choose.move_advice) and its
    first press seats there (the seat within ``SEATED_TURN_DEG`` of the pad's nominal normal:
    else the same search over only the turns that leave it so, shifts included, or no move), as
    (advice, move, the face's middle, the seated pad's normal ψ); ``out``'s probes bound the move
    (tactile_jaw.choose.JawReach.opened_clear; ``reach``, if given, holds them), and so does the
    face itself: it goes on unfelt past Q, and past P unless P is the ``corner`` a pad turned
    about (``Goal.goes_on``: the opened pads keep clear of its line there)."""
    normal = face_normal(p, q, toward)
    psi = math.atan2(normal[1], normal[0])
    mid = 0.5 * (p + q)
    along = (q - p) / max(float(np.linalg.norm(q - p)), 1e-9)
    goes_on = ((*map(float, q), *map(float, along)),) + (() if corner else ((*map(float, p), *map(float, -along)),))
    goal = Goal(tuple((float(x), float(y), psi - math.pi / 2) for x, y in (p, mid, q)), np.stack([p, q], axis=1),
                (float(mid[0]), float(mid[1])), "across that face", goes_on=goes_on, felt=felt_points(out))
    f = cfg.finger(finger)
    reach = reach or JawReach(cfg, settings, out.probes)
    found = move_advice(reach, goal, [f])
    advice, move = found.words, found.move

    def off(move: dict | None) -> float:  # the seat's angle from the pad's nominal normal after ``move``
        turn = 0.0 if move is None else math.radians(move["turn_deg"])
        return abs(math.degrees(math.remainder(psi + turn - nominal_psi(f), 2 * math.pi)))

    if found.kind in ("move", "within_reach") and off(move) > SEATED_TURN_DEG:
        # the same search, over the turns that leave the seat within SEATED_TURN_DEG of the normal
        facing, most = math.remainder(nominal_psi(f) - psi, 2 * math.pi), math.radians(SEATED_TURN_DEG)
        seated = move_advice(reach, goal, [f], (facing - most, facing + most))
        if seated.kind in ("move", "not_clear"):
            advice, move = seated.words, seated.move
        elif off(None) > SEATED_TURN_DEG:
            way = "counterclockwise" if facing > 0 else "clockwise"
            advice, move = (f"that face's seat lies {off(None):.0f} deg from the {finger} pad's nominal normal, past the "
                            f"{SEATED_TURN_DEG:g} deg a flat press seats from there: turn the object at least "
                            f"{off(None) - SEATED_TURN_DEG:.0f} deg {way} (hand frame) about ({mid[0]:.0f}, "
                            f"{mid[1]:.0f}) mm, so that the face faces the {finger} finger"), None
        else:  # the moves that reach it turn the seat away
            advice, move = (f"each move found that brings the {finger} pad across that face turns its seat past the "
                            f"{SEATED_TURN_DEG:g} deg from the pad's nominal normal a flat press seats from: place the "
                            f"object so that the face faces the {finger} finger inside the workspace"), None
    return advice, move, mid, psi


def felt_points(out: Exploration) -> np.ndarray:
    """The points (n × 2 mm) the exploration felt on the object, which a move carries and the
    opened pads must keep clear of (tactile_jaw.choose.JawReach.felt_near): every probe's and
    touch's corner a run of its lines turned about (``pivot``), the closing segment's corners it
    rolled across, a seated press's supports, and a usable touch's contacts. Not a roll's
    ``corner`` without a pivot, nor an unusable roll's contacts: crossings of lines that need not
    pass through one point may lie off the object (P line 1 of bench_explore --finite 4 --anywhere
    --seed 191: the left rolls' "corners" at (111.3, 26.1) and (106.8, 27.9) mm lay 21 and 25 mm
    from the block, 0.8 mm off their own pad lines)."""
    points = []
    for t in (*out.probes, *out.touches):
        points += [] if t.pivot is None else [t.pivot[0]]
        points += list(t.segment_corners) + ([] if t.face is None else [t.face.p, t.face.q])
        if t.samples is not None and t.contacts is not None:
            points += list(zip(t.contacts.x, t.contacts.y))
    return np.array([np.asarray(c, float)[:2] for c in points], float).reshape(-1, 2)


def _corner_stop(cfg, settings: ExploreSettings, out: Exploration, head: str) -> Stop | None:
    """When no press found a face: the first face beside a corner a pad turned about
    (:func:`corner_faces`, every finger's, the longest felt first) for which a move seats that
    pad (:func:`_face_advice`), as the stop naming it; None if there is none."""
    found = []
    for f in cfg.fingers:
        samples = [s for t in (*out.probes, *out.touches) if t.touch.finger == f.name for s in t.touch.samples]
        samples.sort(key=lambda s: math.remainder(float(s.line.psi) - nominal_psi(f), 2 * math.pi))
        found += [(face, f.name) for face in corner_faces([s.line for s in samples], f.pad.length_mm)]
    reach = JawReach(cfg, settings, out.probes)  # one for every face: the opened pads' bound read once
    for (felt, p, q, toward), finger in sorted(found, key=lambda c: -c[0][0]):
        advice, move, _, psi = _face_advice(cfg, settings, out, finger, p, q, toward, reach, corner=True)
        if move is not None:
            seen = f"met its face with a pad end {felt:.1f} mm from it" if felt > 0 else "turned on as far as it reached"
            return Stop(f"{head}; the {finger} pad turned about a corner at ({p[0]:.0f}, {p[1]:.0f}) mm and "
                        f"{seen}, short of lying on the face at pad normal {math.degrees(psi):.0f} deg: {advice}", move)
    return None


def _slid_path(lines: Sequence[kin.PadLine], length_mm: float, tol_mm: float = SEAT_TOL_MM,
               part: bool = False) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
    """(P, Q, toward): the ends of the straight path one pad end of every line of an unseated
    press (``lines``, in order of ψ) slid along, within ``tol_mm``, over at least
    FACE_MIN_FRACTION of the pad (an end turning about a corner under the pad bows out by more:
    :func:`sliding_face`), and the way from the pad into the face (from the other end: the
    lines' normals, up to 98° off the face's there, say nothing), or None. X line 17 of
    bench_explore --finite 20 --seed 283: the right press's proximal end slid 11.7 mm along the
    block's long face (within 0.04 mm) as the pad turned 48–146°, its lines crossing 1.8 mm
    inside the block and 4.3 mm outside it, where seat_split put a face of 6.5 mm at pad normal
    98° and the move named for it. ``part``: the longest such path of a run of the lines, each
    crossing the one before nearer that end than the other (the end the pad touched with), none
    through a corner three lines pass through more than FACE_MIN_FRACTION of the pad from
    either end (a pad turned about it touches nothing with its ends, and as the approaches slide
    the pad over that corner an end may move straight). X line 7 of --finite 20 --anywhere
    --seed 499: the left press's proximal end slid 10.8 mm along the block's long face (within
    0.05 mm) as the pad turned from −105.5° toward its seat at −156°, then the pad turned on to
    −165.5° about the face's far corner 21–37 mm along it, its end off the face (and straight
    within 0.2 mm over 12.5 mm): no path of every line, no move named (docs/exploration.md).
    Nor a path of every line when all of them pass (within ``tol_mm``) through one corner more than
    FACE_MIN_FRACTION of the pad from either end: held-out P cubical 113 of --finite 20 --anywhere
    --follow --seed 571, the left press's 8 lines through the corner its rolls pivoted about,
    40.7 → 15.4 mm along the pad, its proximal end straight over 26.4 mm 15 mm and more off the
    object: taken for the longest face, it hid the right pad's seated one, and no move was named."""
    lines = list(lines)
    margin = FACE_MIN_FRACTION * length_mm
    pivoted = [False] * len(lines)  # lines through a corner under the pad's middle part
    near: dict[str, list[bool]] = {}  # per end: each line crossed the one before nearer it (part only)
    if part:
        crossed = [None] + [kin.crossing(a, b) for a, b in zip(lines, lines[1:])]
        proximal = [x is not None and float(ln.pad_coordinate(x)) < 0.5 * length_mm for ln, x in zip(lines, crossed)]
        near = {"proximal": proximal, "distal": [x is not None and not p for x, p in zip(crossed, proximal)]}
        for i in range(len(lines)):
            n, corner, _ = _run(lines, i, 1, tol_mm)
            for j in range(i, i + n if n >= 3 else i):
                pivoted[j] = pivoted[j] or margin < float(lines[j].pad_coordinate(corner)) < length_mm - margin
    else:
        n, corner, _ = _run(lines, 0, 1, tol_mm)
        if n == len(lines) and all(margin < float(ln.pad_coordinate(corner)) < length_mm - margin for ln in lines):
            return None  # every line through one corner under the pad's middle part: the pad turned about it
    best = None
    for end in ("proximal", "distal"):
        points = [np.asarray(getattr(ln, end), dtype=float) for ln in lines]
        for i in range(len(points) if part else min(1, len(points))):
            for j in range(i + 1, len(points)) if part else (len(points) - 1,):
                path = kin.straight_line(points[i:j + 1])
                if path.worst > tol_mm or (part and (pivoted[i] or pivoted[j] or not near[end][j])):
                    break
                span = float(np.ptp(path.u))
                if span >= margin and (best is None or (part and span > best[0])):  # every line: the first end
                    best = (span, end, i, j + 1, path)
    if best is None:
        return None
    _, end, i, j, path = best
    other = "distal" if end == "proximal" else "proximal"
    toward = np.mean([np.asarray(getattr(ln, end), float) - np.asarray(getattr(ln, other), float)
                      for ln in lines[i:j]], axis=0)
    return *path.ends, toward


def sliding_face(rolls: Sequence[FeltTouch], length_mm: float,
                 tol_mm: float = SEAT_TOL_MM) -> tuple[float, np.ndarray, np.ndarray, np.ndarray] | None:
    """The longest face a pad end slid along in a finger's rolls (``rolls``: felt rolling
    touches, their pad lines and envelope fits), as (its length felt, its ends P and Q, the pad's
    normal toward it), or None: a roll whose lines' envelope bends the way no convex boundary's
    tangents do (radius of curvature below 0 by 3 σ: a roll on a curve near the pad's end moves
    that end along a nearly straight path too — 54 of the 140 P-series logs of seed 139, circles
    among them, had such ends — and a corner's radius is 0), the
    same end of every line of that roll within ``tol_mm`` of one straight line, slid along it by
    more than SPLIT_APART · ``tol_mm``, and that end of every line of the finger's rolls within
    ``tol_mm`` of it spanning at least FACE_MIN_FRACTION of the pad (an end turning about a
    corner under the pad moves on a circle of at most the pad's length: over that span it bows
    out by more than the tolerance), from a roll whose lines do not pass through a point
    another roll's lines pass through (within ``PIVOT_AGAIN_MM``): the lines of a roll resting
    on a sliding end may pass within 0.02 mm of one point off the object, a different one each
    roll, while the rolls about one corner all pass through it, and their ends may lie on a
    straight line too (the X-series right pad about the corner of random block 18 of seed
    139: within 0.03 mm over 10.6 mm, off the object). Random block 8 of bench_explore --finite 20 --anywhere
    --seed 139 (P-series, near the palm): no press seated, the right pad's proximal end slid
    12.5 mm along a face 69° from its nominal normal over three rolls (tactile_jaw.pipeline
    .slid_end), while the move named came from a press's scan that split at two points
    5.7 mm apart inside the block. A roll whose end's points lie on one line within the pad
    lines' own deviations (``slid``, tactile_jaw.pipeline.slid_end: fine encoders only, µm, where
    a roll on a circle bends the end's path by 18–280 µm and an end turning about a corner under
    the pad by its sagitta) counts whatever its envelope and pivots: P-series line 16 of --seed
    173, near the palm, whose left pad's proximal end slid 1–3 mm along a face in two rolls
    (envelope radius +14.3, +3.0 mm, their lines within 1 mm of points other rolls' lines pass
    through, beside the face's corner), was refused naming no move."""
    best = None
    lines = [t.lines for t in rolls]
    pivots = [_pivot(ln, tol_mm) if np.asarray(ln.psi).size >= 3 else None for ln in lines]
    concave = [t.fit is not None and t.fit.rho + 3.0 * t.fit.sigma_rho < 0.0 for t in rolls]
    for end in ("proximal", "distal"):
        every = [np.asarray(getattr(ln, end), dtype=float).reshape(-1, 2) for ln in lines]
        pool = np.concatenate(every) if every else np.empty((0, 2))
        for i, (pts, ln) in enumerate(zip(every, lines)):
            pivoted = pivots[i] is not None and any(
                o is not None and j != i and np.linalg.norm(o - pivots[i]) <= PIVOT_AGAIN_MM for j, o in enumerate(pivots))
            if len(pts) < 3 or not ((concave[i] and not pivoted) or rolls[i].slid == end):
                continue  # its lines pass through a point another roll's pass through (a corner), and its
                # end's path is straight only within the tolerance
            path = kin.straight_line(pts)
            if path.worst > tol_mm or float(np.ptp(path.u)) <= SPLIT_APART * tol_mm:
                continue
            centre, along = path.centre, path.along
            on = pool[np.abs((pool - centre) @ path.across) <= tol_mm]
            u = (on - centre) @ along
            length = float(np.ptp(u))
            if length >= FACE_MIN_FRACTION * length_mm and (best is None or length > best[0]):
                toward = np.asarray(ln.normal, dtype=float).reshape(-1, 2)[0]
                best = (length, centre + float(np.min(u)) * along, centre + float(np.max(u)) * along, toward)
    return best


def corner_faces(lines: Sequence[kin.PadLine], length_mm: float,
                 tol_mm: float = SEAT_TOL_MM) -> list[tuple[float, np.ndarray, np.ndarray, np.ndarray]]:
    """The faces beside the corner a finger's pad turned about most, from its pad lines in
    order of ψ (probes, rolls, presses): the longest run of ≥ 3 lines through one point P
    (hand_driver.flat_press._run), and past either end of it, as (how far from P a pad end
    felt the face, P, Q, the pad's normal toward it): the lines there that miss P by more
    than ``tol_mm``, each resting on one pad end E (the end whose chord PE no pad stop cuts:
    P and E both on the convex object, a pad stopped across the chord would have met it),
    those ends on one straight line through P within ``tol_mm``: Q the farthest; with no
    such end, the face along the run's last line over the part of the pad that turning on
    lowers (0 felt). Q lies at least FACE_MIN_FRACTION of the pad from P (what a seat
    needs); a face that neither felt nor the pad's part reaches is left out. A pad turned
    about a corner toward a face it cannot lie on — the face's line beyond the finger's reach,
    or the pad placed along it past the face — meets that face with a pad end at most: no
    seat, whose supports need three lines each (hand_driver.flat_press.seat_split).
    Held-out blocks 5, 12 and 14 of bench_explore --finite 20 --anywhere --seed 269 (x
    118–133 mm, a corner toward each pad, every face 42–55° from a pad's nominal normal):
    block 12's left pad end slid 19 mm along a face whose line lies 5 mm past the left
    finger's reach; block 5's left pad turned about its corner to pad normal −138.25°, 0.35°
    past the face's seat, where the finger's reach ends (its next part step, from 3 mm out,
    beyond it); refused naming no move before."""
    runs = [_run(lines, i, -1, tol_mm)[0] for i in range(len(lines))]
    if not runs or max(runs) < 3:
        return []
    hi = max(range(len(runs)), key=lambda i: (runs[i], i))
    lo = hi - runs[hi] + 1
    p = _run(lines, hi, -1, tol_mm)[1]
    out = []
    for edge, beyond, turn in ((lines[hi], lines[hi + 1:], 1), (lines[lo], lines[:lo][::-1], -1)):
        ends: list[np.ndarray] = []
        for ln in beyond:
            if abs(float(ln.normal @ p - ln.d)) <= tol_mm:
                continue  # through the corner still
            touched = [e for e in (np.asarray(ln.proximal, float), np.asarray(ln.distal, float))
                       if not any(_cuts(m, p, e, tol_mm) for m in lines)]
            if len(touched) != 1:
                break  # neither end or either: no face to tell
            if ends and kin.straight_line([*ends, touched[0]], through=p).worst > tol_mm:
                break  # off the straight line the nearer ends lie on: past the face
            ends.append(touched[0])
        felt = max((float(np.linalg.norm(e - p)) for e in ends), default=0.0)
        t, n = np.asarray(edge.tangent, float), np.asarray(edge.normal, float)
        # turning on by ``turn`` about P lowers the pad part on this side of it (hand_driver.flat_press.lowering_turn)
        side = turn * (1.0 if float(np.array([-t[1], t[0]]) @ n) > 0 else -1.0)
        u = float(edge.pad_coordinate(p))
        part = length_mm - u if side > 0 else u
        along = (max(ends, key=lambda e: float(np.linalg.norm(e - p))) - p) / felt if ends else side * t
        if max(felt, part) >= FACE_MIN_FRACTION * length_mm:
            out.append((felt, p, p + max(felt, FACE_MIN_FRACTION * length_mm) * along, n))
    return out


def _cuts(line: kin.PadLine, a: np.ndarray, b: np.ndarray, tol_mm: float) -> bool:
    """Does the pad of ``line`` lie more than ``tol_mm`` inside the chord from ``a`` to ``b``
    somewhere along it (a point of the chord under the pad, on the pad's side of its line)?"""
    t, n = np.asarray(line.tangent, float), np.asarray(line.normal, float)
    ua, ub = (float(t @ (x - line.proximal)) for x in (a, b))
    length = float(np.linalg.norm(np.asarray(line.distal) - np.asarray(line.proximal)))
    lo, hi = sorted(((0.0 - ua) / (ub - ua), (length - ua) / (ub - ua))) if abs(ub - ua) > 1e-9 else \
        ((0.0, 1.0) if 0.0 <= ua <= length else (1.0, 0.0))
    lo, hi = max(lo, 0.0), min(hi, 1.0)
    return lo <= hi and min(float(n @ (a + s * (b - a)) - line.d) for s in (lo, hi)) < -tol_mm


def _pivot(lines: kin.PadLine, tol_mm: float) -> np.ndarray | None:
    """The point more than half a roll's consecutive lines pass within ``tol_mm`` of, or None."""
    seq = [lines.at(i) for i in range(np.asarray(lines.psi).size)]
    runs = [_run(seq, i, 1, tol_mm) for i in range(len(seq))]
    n, p, _ = max(runs, key=lambda r: r[0])
    return p if n > len(seq) // 2 else None


def _bulge_pending(state: "_Faces", touches: Sequence[FeltTouch]) -> set[str]:
    """The fingers still pressing (``state.active``) with no face seated whose presses of
    ``touches`` bulged (tactile_jaw.flat.bulged) fewer than ``BULGED_PRESSES`` times but at
    least once: their boundary may be a curved part (one bulge can be the encoders' rounding,
    two are a curve: tactile_jaw.flat.bulged_presses), so no face is answered `line` before
    they press again. The hyperbola example on a P-series jaw with 90/60 mm links and 44 mm
    pads: the left pad's first press stopped +0.23 mm short, its second was stopped by the
    right pad's seat and the left dropped (no face), and the right's three presses on the
    closing segment were answered `line`."""
    return {name for name in state.active if state.faces[name] is None
            and 0 < sum(t.finger == name and bulged(t) for t in touches) < BULGED_PRESSES}


def _decided(out: Exploration, flat: list[FeltTouch], settings: ExploreSettings, recognize_touches: RecognizeTouches,
             say) -> bool:
    """Recognize one face's flat touches so far (tactile_jaw.flat.recognized_touches) into
    ``out``; True once the answer is decisive."""
    out.used = recognized_touches(flat, settings.min_touches)
    for n, miss in curved_faces(flat):
        say(f"{n} flat presses of one face stopped {miss:+.2f} mm short of their supports on average "
            f"(at most {FACE_MISS_MM:g}): a gentle curve, not a face; not recognized as a line")
    if len(out.used) < settings.min_touches:
        return False
    recognition, why = decide(recognize_touches, out.used, settings)
    out.recognition = recognition
    out.answers.append(recognition.cls)
    say(f"after {len(out.used)} flat touches of one face: {recognition.cls}"
        + ("" if why is None else f", not decisive: {why}"))
    return why is None


def _seated_apart(seated: Sequence[FeltTouch]) -> str:
    """Why flat presses that seated made no answer: their faces (tactile_jaw.flat.face_groups)
    are too many, each felt too few times — on a short face the pad's angles scatter more
    than one face's presses may (tactile_jaw.flat.same_face_rad: by the faces' lengths). Held-out
    X line 7 of seed 241 (session 22, a fixed 0.57° then): 4 presses seated on an 11 mm face at
    ψ −63.4, −62.7, −63.3, −62.3°, two faces of 2, and the refusal said only that 1 press found
    no seat."""
    groups = face_groups(seated)
    if len(groups) == 1:
        return f"{len(seated)} flat press{'es' if len(seated) > 1 else ''} seated on one face, too few for an answer"
    psi = [math.degrees(t.face.psi) for t in seated]
    short = min((t.face for t in seated), key=lambda f: f.length)
    return (f"{len(seated)} flat presses seated, on {len(groups)} faces by their angles (pad normal {min(psi):.1f} to "
            f"{max(psi):.1f} deg; one face's presses agree within {math.degrees(same_face_rad(short, short)):.1f} deg), "
            f"none felt often enough: over {short.length:.1f} mm of the pad the seats' angles scatter more than that")


def unusable_refusal(out: Exploration) -> tuple[Recognition, Stop]:
    """The refusal of an exploration with too few usable touches to ask the recognizer
    (``out.used`` of ``out.touches``, rolled or pressed) and no curved part felt: what the touches met — the corners rolls
    pivoted about (``PIVOT_AGAIN_MM`` apart), presses that found no seat, approaches that met
    nothing — and what would help: ``out.stopped`` when a face's move was named
    (:func:`short_face_stop`), else why no move is named: no touch felt a curved part or a face
    to aim one at, only the corners, between which the boundary that was not felt lies.
    Random P semicubical 134 of bench_explore --finite 20 --anywhere --seed 227 (6 touches:
    rolls about corners at (109, 44) and (95, 14) mm, two presses without a seat) ended with
    no recognition, no reason and no move."""
    corners: list[tuple[float, float]] = []
    for t in out.touches:
        if t.corner is not None and all(math.hypot(t.corner[0] - x, t.corner[1] - y) > PIVOT_AGAIN_MM
                                        for x, y in corners):
            corners.append((float(t.corner[0]), float(t.corner[1])))
    unseated = sum(isinstance(t.touch, FlatResult) and t.face is None for t in out.touches)
    empty = sum(not t.touch.samples for t in out.touches)
    at = " and ".join(f"({x:.0f}, {y:.0f}) mm" for x, y in corners)
    met = [f"rolls pivoted about corner{'s' if len(corners) > 1 else ''} at {at}"] if corners else []
    seated = [t for t in out.touches if isinstance(t.touch, FlatResult) and t.problem is None and t.face is not None]
    if seated and not out.used:
        met.append(_seated_apart(seated))
    met += [f"{unseated} flat press{'es' if unseated > 1 else ''} found no seat"] if unseated else []
    met += [f"{empty} took no contact sample (out of the joints' reach, or nothing met)"] if empty else []
    used = len(out.used)  # usable, yet fewer than any class needs
    head = f"only {used} usable of {len(out.touches)} touches, too few to recognize" if used else \
        f"no usable touch of {len(out.touches)}"
    reason = (head + (f": {'; '.join(met)}" if met else "")
              + " (the log's touch_rejected events say why each)")
    if out.stopped is not None:
        return Recognition("unclassified", reason=reason), out.stopped
    if corners:
        stop = Stop(f"no move is named: no touch felt a curved part or a face to aim one at, only corners; place "
                    f"the object so that its boundary {'between' if len(corners) > 1 else 'beside'} {at}, "
                    f"clear of {'them' if len(corners) > 1 else 'it'}, faces a finger")
    else:
        stop = Stop("no move is named: no touch felt a curved part, a face or a corner to aim one at; place the "
                    "object so that its boundary faces a finger inside the workspace")
    return Recognition("unclassified", reason=reason), stop
