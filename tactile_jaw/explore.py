"""Exploration: rolling touches with both fingers at once until the recognizer is sure.

Probes first locate the boundary (tactile_jaw.probing); once one finger has felt enough,
the other's probes left run one a round beside its rolls (a touch aimed at the probing
finger goes first). Each round, every finger makes one
rolling touch (hand_driver.motion.rolling_touch) in the same bus cycles, at the
orientation tactile_jaw.plan.choose_psi picks, starting ``APPROACH_MARGIN_MM`` outside the
predicted tangent. Between touches a pad retreats to the workspace edge and turns along
it (tactile_jaw.rounds.transit). Every touch is felt once (tactile_jaw.pipeline.feel).

After every round with at least ``settings.min_touches`` usable touches the recognizer
runs on all of them; exploration stops as soon as its answer is decisive
(tactile_jaw.decide), when the touch budget is spent, or when no touch within the pads'
reach can help (tactile_jaw.choose). While it is not decisive, the next touch of the finger
that can reach it goes where tactile_jaw.choose.next_aim points (beyond a parabola's vertex
on its short side, else the recognizer's ``next_touch`` within the jaw's reach; the other
finger's where the planner picks, or, after a roll it could not use that still felt the
curved part before running off it (tactile_jaw.pipeline.curve_hint), back at that stretch:
such a roll does not count toward retiring the finger). When no rolling touch is usable clear of the corners,
the pads press flat on the faces instead (tactile_jaw.flat_phase). Once it ends, the answer
on the usable touches is the class if decisive, else ``unclassified`` with the reason.
docs/exploration.md.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from functools import partial
from typing import Any, Callable, Collection, Container, Sequence

import numpy as np
from scipy.spatial import cKDTree

from hand_driver import kinematics as kin
from hand_driver.config import states_calibration
from hand_driver.cycle import LIMIT_MARGIN_RAD, Jaw, run_together
from hand_driver.flat_press import SEAT_TOL_MM, FlatResult, clear_of_pad_ends
from hand_driver.motion import TouchResult, contact_on_pad, roll_angles, rolling_touch
from recognizer.curves import CURVES
from tactile_common.errors import InputError
from tactile_jaw.choose import VERTEX_ENDS, VERTEX_OFF, Aim, JawReach, Stop, budget_advice, next_aim
from tactile_jaw.decide import (DECISIVE_CHI2, RecognizeTouches, beyond_resolution, decide, final_answer, imprecision,
                                 noted, sample_positions)
from tactile_jaw.felt_before import MOVED_OFF_CURVE, FeltBefore, not_a_line
from tactile_jaw.flat import face_line
from tactile_jaw.flat_phase import (FLAT_AFTER_TOUCHES, PIVOT_AGAIN_MM, beside_press, early_press, flat_presses,
                                    guard_done, short_face_stop, unusable_refusal)
from tactile_jaw.pipeline import (CORNER_CLEARANCE_MM, WIDER_SPAN, FeltTouch, clear_of_corners, clear_side,
                                  clearing_corners, corner_clearance, corner_in_doubt, curved_part, feel, left_out,
                                  longest_run, near_corners, on_osculating_circle, on_pivots, sure_corner, too_few_clear,
                                  workspace_reach)
from tactile_jaw.plan import (APPROACH_MARGIN_MM, FREE_MARGIN_MM, PROBE_SAMPLES, ObjectModel, choose_psi,
                             feasible, nominal_psi, passes_end, predicted_tangent, probe_face_contact,
                             retreat_offset, within_curve)
from tactile_jaw.probing import probe_boundary
from tactile_jaw.rounds import Exploration, timed_round, transit_or_problem
from tactile_jaw.separation import jaw_ticks_per_rev
from tactile_jaw.settings import ExploreSettings

#: a finger whose last this many touches fell on corners or closing segments stops touching:
#: its side of the object is not the curved part, and the touch budget goes to the others
OFF_CURVE_RETIRE = 2
#: touches that fell off the curved part do not count against the budget; all the touches
#: tried, counted or not, stop at this many times the budget (the seed-83 P-series objects
#: tried at most 1.5 times theirs): a bound on the robot's time whatever the rules above
TRIED_PER_BUDGET = 3
#: the classes whose boundary closes: a finger that met such an object only at its pad end met
#: its other side (:func:`unrolled_places`)
CLOSED = frozenset({"circle", "ellipse"})


def _touch_plan(jaw: Jaw, finger: str, model: ObjectModel, psi: float, settings: ExploreSettings,
                touch_index: int, emit, spent: dict[str, float], aim=None, span: float | None = None):
    """Transit, then one rolling touch around ψ over ``span`` (default the settings') from
    ``APPROACH_MARGIN_MM`` outside the predicted tangent line (tactile_jaw.plan.predicted_tangent,
    ``aim`` a boundary point the touch is aimed at), faster (still guarded) up to
    ``FREE_MARGIN_MM`` outside it; returns the TouchResult."""
    span = settings.roll_span_rad if span is None else span
    start = float(roll_angles(psi, span, settings.samples_per_touch)[0])
    problem = yield from transit_or_problem(jaw, finger, model, start, spent, aim, hug=True)
    if problem is not None:
        return TouchResult(finger, touch_index, psi, outcome="unreachable", message=problem)
    d_pred, _ = predicted_tangent(model, start, aim)
    d_start = max(retreat_offset(jaw.config.finger(finger), model, start, aim), d_pred - APPROACH_MARGIN_MM)
    travel = d_pred + APPROACH_MARGIN_MM - d_start
    return (yield from rolling_touch(jaw, finger, touch_index, psi, span,
                                     settings.samples_per_touch, d_start, travel, on_event=emit,
                                     free_mm=d_pred - FREE_MARGIN_MM - d_start))


def _memo(recognize_touches: RecognizeTouches) -> RecognizeTouches:
    """``recognize_touches`` remembering its answers by the touches' identities (calls with
    options, such as tactile_jaw.separation's, pass through)."""
    seen: dict[tuple[int, ...], Any] = {}

    def run(touches, **options):
        if options:
            return recognize_touches(touches, **options)
        key = tuple(id(t) for t in touches)
        if key not in seen:
            seen[key] = recognize_touches(touches)
        return seen[key]

    return run


def _clear_of_corners(cfg, out: Exploration, settings: ExploreSettings, emit, say) -> Callable[[], list[FeltTouch]]:
    """The usable touches so far without their samples at the corners the touches so far
    pivoted about and past the curve's ends they felt (tactile_jaw.pipeline.clear_of_corners;
    recomputed when any of these grows: the usable touches, the corners, the curve's ends, the
    pivots and the closing segments' end corners — the last two were not counted until session
    32, so X line 18 of bench_explore --finite 20 --anywhere --seed 499 kept a roll on the end
    corner of the closing segment its next roll crossed, and was refused with its three seated
    presses unused — and the touches and probes felt, whose lines may pass through one corner
    together, tactile_jaw.pipeline.on_shared_pivots; the probes are among the touches it is
    handed, as in a replay's), each change logged once (event ``touch_trimmed``)."""
    state: dict[str, Any] = {"key": None, "usable": [], "said": set()}

    def run() -> list[FeltTouch]:
        key = (len(out.used), sum(t.corner is not None for t in out.touches),
               sum(t.curve_span is not None for t in out.touches), sum(t.pivot is not None for t in out.touches),
               sum(len(t.segment_corners) for t in out.touches), len(out.touches), len(out.probes))
        if key != state["key"]:
            state["key"] = key
            state["usable"], notes = clear_of_corners(cfg, out.used, [*out.probes, *out.touches],
                                                      settings.samples_per_touch)
            for note in notes:
                if note not in state["said"]:
                    state["said"].add(note)
                    emit({"type": "event", "kind": "touch_trimmed", "message": note})
                    say(note)
        return state["usable"]

    return run


def wider_again(felt: FeltTouch, reach: JawReach, wider: Container[int]) -> Aim | None:
    """A roll judged a corner only by its radius's deviation (tactile_jaw.pipeline.corner_in_doubt)
    and not itself a wider roll (``wider``: their touch indices) is rolled again about the point
    it turned about, over ``WIDER_SPAN`` times the span, when its finger can reach it there: the
    Aim of that roll, else None. A corner measures ρ ≈ 0 again; boundary bent tightly (an
    ellipse's end) is usable (docs/exploration.md)."""
    if felt.corner is None or not corner_in_doubt(felt.fit) or felt.touch.touch in wider:
        return None
    phi = felt.touch.psi_center - math.pi / 2
    finger = reach.config.finger(felt.finger)
    if reach.finger(*felt.corner, phi, [finger]) is None:
        return None
    return Aim(*felt.corner, phi, felt.finger,
               f"where its last roll turned about a point or a tight bend (radius of curvature "
               f"{felt.fit.rho:.1f} ± {felt.fit.sigma_rho:.1f} mm): rolled {WIDER_SPAN:g} times wider", kind="wider")


def beside_corners(out: Exploration, usable: list[FeltTouch], seen: set[int], settings: ExploreSettings):
    """(finger, (x, y, φ)) for every usable touch of ``out`` that the corners dropped
    (``usable`` lacks it: too few of its samples clear of a corner another touch pivoted
    about) and that is not in ``seen`` (touch indices, updated): where its finger's next roll
    goes, beside the touch's clear stretch away from the corner (tactile_jaw.pipeline.clear_side)."""
    kept = {t.touch.touch for t in usable}
    corners = clearing_corners(out.touches)
    for t in out.used:
        if t.touch.touch in kept or t.touch.touch in seen or isinstance(t.touch, FlatResult):
            continue
        seen.add(t.touch.touch)
        side = clear_side(t, corners, settings.roll_span_rad, settings.samples_per_touch)
        if side is not None:
            yield t.finger, side


def curve_limits(name: str, touches: list[FeltTouch], corners) -> list[tuple[float, float]]:
    """Where finger ``name``'s rolls (``touches``, every one felt) left the curved part, as
    limits a planned roll keeps short of (tactile_jaw.plan.within_curve): (ψ_end, +1) where
    the finger felt the curve only below ψ_end, (ψ_end, −1) only above it. The curve is felt
    at the pad orientations of its usable rolls' samples clear of the ``corners``
    (tactile_jaw.pipeline.clearing_corners); it is left at those of their samples within
    their clearance of a corner (tactile_jaw.pipeline.corner_clearance; and beyond them) and at the middle of its rolls off the curved part (a
    corner, a closing segment). A finite object's curved part, convex toward the pad, is one
    stretch of orientations, so beyond such a place from the felt curve lie its end corner
    and closing segments: the planner's farthest orientation from the earlier rolls went
    there again and again (P cubical 107 of bench_explore --finite 20 --anywhere --seed 97
    --config config/jaw-p.yaml: 3 of its 4 rolls on corners). A finger that has not felt the
    curve has no limits."""
    on, off = [], []
    for t in touches:
        if t.finger != name or isinstance(t.touch, FlatResult):
            continue
        if t.problem is None and t.contacts is not None:
            c = t.contacts
            clear = np.zeros(c.x.size, bool)  # its longest run clear of the corners (the samples beyond a corner's go too)
            clear[longest_run(~near_corners(c, corners, corner_clearance(t)))] = True
            on += list(c.psi[clear])
            off += list(c.psi[~clear])
        elif t.off_curve:
            off.append(t.touch.psi_center)
    if not on:
        return []
    on, off = (on[0] + np.remainder(np.asarray(v, float) - on[0] + math.pi, 2 * math.pi) - math.pi for v in (on, off))
    lo, hi = float(np.min(on)), float(np.max(on))
    return [(float(e), 1.0) if e > hi else (float(e), -1.0) for e in off if e > hi or e < lo]


def felt_curve_roll(cfg, out: Exploration, settings: ExploreSettings, reach: JawReach,
                    checked: Collection[int] = frozenset()) -> Aim | None:
    """The one roll the exploration makes, before the flat phase, on a curved part it felt
    (tactile_jaw.pipeline.curved_part over ``out.touches``; ``checked``: presses whose scans
    rolled on none) while no touch was usable, by the finger that felt it, or None (none felt,
    or no such roll is within its reach): the flat phase would refuse at once ("no rolling
    touch on it was usable", tactile_jaw.flat_phase.curve_stop), naming no move when a pad
    reaches the place. Its ψ range (:attr:`Aim.span`): from the felt stretch's end where its
    roll left the curved part (tactile_jaw.pipeline.left_out: onto a corner or closing segment)
    one roll span (``settings.roll_span_rad``) on away from it, cut short of the finger's corner
    cones (:func:`corner_cones`) and of the pad-end normals it met (:func:`pad_end_normals`), never
    shorter than the stretch; a stretch cut alike at both ends, or a press's scan, its own range:
    between the corners its normals bound. The stretch's samples whose pad lines rest on a corner
    one of the finger's rolls turned about (its pivot, tactile_jaw.pipeline.on_pivots) are that
    corner's, not the curve's, and bound nothing: P semicubical 121 of bench_explore --finite 20
    --anywhere --follow --seed 599 --config config/jaw-p.yaml, moved as advised, kept two lines
    through the curve's end corner in its stretch, and the roll handed back ended among them, ran
    onto the corner again and retired the finger. Aimed at the osculating circle of the stretch (radius
    ρ, eq. of a circle's tangent lines d = n·c − ρ) at the roll's middle normal (pipeline.on_osculating_circle). Calibrated P
    semicubical 63 of bench_explore --finite 10 --anywhere --calibrate --seed 613 (held out in
    session 34, development data since), moved as advised: the left roll at −55.9…−37.9° kept
    7 lines on the curve (ρ 14.7 mm) before a corner, the next rolled about the far corner at
    −112.5°, and the run was refused naming no move."""
    curve = curved_part(cfg, out.touches, checked)
    if curve is None or curve.fit is None or curve.contacts is None:
        return None
    felt = next(t for t in out.touches if t.touch.touch == curve.touch.touch and t.finger == curve.finger)
    c, rho = curve.contacts, float(curve.fit.rho)
    psi = np.asarray(c.psi, dtype=float)
    psi = psi[len(psi) // 2] + np.remainder(psi - psi[len(psi) // 2] + math.pi, 2 * math.pi) - math.pi  # unwrapped
    # its samples resting on a corner one of the finger's rolls turned about are that corner's, not the curve's
    on_corner = on_pivots(curve, [t.pivot for t in out.touches if t.finger == felt.finger and t.pivot is not None])
    if np.all(on_corner):
        return None
    kept = np.flatnonzero(~on_corner)
    mid = int(kept[len(kept) // 2])
    lo, hi = float(np.min(psi[kept])), float(np.max(psi[kept]))
    low, high = left_out(felt, curve)
    low, high = low + int(np.sum(psi[on_corner] < lo)), high + int(np.sum(psi[on_corner] > hi))
    span = max(settings.roll_span_rad, hi - lo)
    start, end = (lo, lo + span) if low > high else (hi - span, hi) if high > low else (lo, hi)
    way = 1.0 if low > high else -1.0  # toward the roll's free end (away from the stretch's cut end)
    bounds = list(corner_cones(felt.finger, out.touches, out.probes))
    bounds += [(min(a, b), max(a, b)) for _, a, b in pad_end_normals(felt.finger, (*out.probes, *out.touches))]
    if low != high:
        for a, b in bounds:
            a, b = (lo + math.remainder(v - lo, 2 * math.pi) for v in (a, b))
            if way > 0 and a < end and b > lo:
                end = max(min(end, a), hi)
            elif way < 0 and b > start and a < hi:
                start = min(max(start, b), lo)
    centre = 0.5 * (start + end)
    if any(lo + math.remainder(a - lo, 2 * math.pi) < hi and lo + math.remainder(b - lo, 2 * math.pi) > lo
           for a, b in bounds):
        return None  # the stretch itself among a corner's normals: nothing to roll on clear of it
    # the osculating circle through the stretch's middle contact, its point at the roll's middle normal
    x, y = (float(v) for v in on_osculating_circle(float(c.x[mid]), float(c.y[mid]), float(psi[mid]), rho, centre))
    phi = centre - math.pi / 2
    if reach.finger(x, y, phi, [cfg.finger(felt.finger)]) is None:
        return None
    return Aim(x, y, phi, felt.finger, f"on the curved part its touch {felt.touch.touch} felt (radius of curvature "
                                       f"{rho:.1f} mm), over {math.degrees(end - start):.1f} deg clear of the corners "
                                       f"its normals bound, before the pads press flat", kind="felt",
               span=end - start)


def corner_cones(name: str, touches: list[FeltTouch], probes: Sequence[FeltTouch] = ()) -> list[tuple[float, float]]:
    """The pad normals at which finger ``name``'s rolls (of ``touches``, every one felt) turned
    about one corner, as (ψ_lo, ψ_hi) arcs: for each group of rolls that pivoted about points
    within ``PIVOT_AGAIN_MM`` of each other, each of them sure to be a corner
    (tactile_jaw.pipeline.sure_corner, the corners whose samples are cleared), the range of
    their pad lines' ψ and of the lines of the finger's ``probes`` that pass through one of
    their corners (:func:`probe_normals`). The normals of a convex boundary point form one
    arc, so every normal between two of that corner's is its normal too: a roll within the
    range pivots about it again (tactile_jaw.plan.within_cone). X-series lines of bench_explore
    --finite 20 --anywhere --seed 269: the left pad's guard rolls went on about the corner its
    earlier rolls had turned about from ψ −131.5 to −86° (rolls at −110°, 2.2 and 3.1 s,
    blocks 1, 4, 19)."""
    rolls = [t for t in touches if t.finger == name and not isinstance(t.touch, FlatResult) and t.lines is not None
             and sure_corner(t, touches)]
    groups: list[list[FeltTouch]] = []
    for t in rolls:
        group = next((g for g in groups if any(math.dist(t.corner, o.corner) <= PIVOT_AGAIN_MM for o in g)), None)
        if group is None:
            groups.append([t])
        else:
            group.append(t)
    cones = []
    for group in groups:
        psi = np.concatenate([np.asarray(t.lines.psi, dtype=float).ravel() for t in group]
                             + [probe_normals(name, probes, [t.corner for t in group])])
        psi = psi[0] + np.remainder(psi - psi[0] + math.pi, 2 * math.pi) - math.pi  # unwrapped about the first
        cones.append((float(np.min(psi)), float(np.max(psi))))
    return cones


def probe_normals(name: str, probes: Sequence[FeltTouch], corners) -> np.ndarray:
    """The ψ of finger ``name``'s probe samples (of ``probes``) whose pad lines pass within
    ``SEAT_TOL_MM`` of one of ``corners`` (points rolls pivoted about) with that point on the pad
    more than ``SEAT_TOL_MM`` from either end: the pad touched the convex object at that point
    of its face, so its line is a support line there and its normal one of the point's normals
    (a pad end on the point is not: its line may cut the object past the end). X-series lines of
    bench_explore --finite 20 --anywhere --seed 463, block 8: the left pad's probes at −113…−67°
    passed within 0.14 mm of the corner its rolls turned about from −100.5 to −64.5°, 37–48 mm
    along the 52 mm pad; its roll at −101.5…−83.5° then turned about it again."""
    out = []
    for t in probes:
        if t.finger != name:
            continue
        for s in t.touch.samples:
            line = s.line
            length = float(np.linalg.norm(line.distal - line.proximal))
            if any(abs(float(line.normal @ np.asarray(c, float)) - float(line.d)) <= SEAT_TOL_MM
                   and clear_of_pad_ends(line, c, length) for c in corners):
                out.append(float(line.psi))
    return np.asarray(out, dtype=float)


def unrolled_finger(active, out: Exploration, probes, deferred: set[str], roll_at) -> str | None:
    """The first of the ``active`` fingers (not in ``deferred``) whose probes met the object's
    face (``probes.faces``) and that has made no usable roll yet but has one to make
    (``roll_at(finger)``, the planner's ψ, not None): a stop for want of reach waits one round
    for its roll. Rolls of one finger see one stretch of a closed object, where an ellipse's
    end, a circle, a parabola, a semicubical branch and a hyperbola all fit at 4,096 ticks;
    with the other side's touches (pad normals nearly opposite) no open curve fits (random
    X-series ellipse 44 of bench_explore --finite 20 --anywhere --seed 127: stopped for the
    parabola vertex's reach while the left finger, its probes on the far side's face, had not
    rolled; the exact tangents of the rolls both pads reach, quantized to ticks, answer ellipse
    decisively from 4 touches, one finger's alone never)."""
    for f in active:
        if (f.name in deferred or not probes.faces.get(f.name)
                or any(t.finger == f.name for t in out.used)):
            continue
        if roll_at(f) is not None:
            return f.name
    return None


def unrolled_before_flat(cfg, out: Exploration, probes, off_curve: dict[str, int], roll_at,
                         pressed: Sequence[FeltTouch] = ()) -> str | None:
    """The finger the flat presses wait for (:func:`unrolled_finger`): not retired
    (``OFF_CURVE_RETIRE``), its probes met the object on its pad's face, and not only on the face
    its presses (of ``pressed``) seated on (:func:`probes_on_face`), it has made no rolling
    touch at all and the planner has one for it (``roll_at``). The other finger's rolls all fell
    on corners or a closing segment, which on a finite curved object is the side facing that
    finger; the side this one probed may be the curved part (P semicubical 126 of bench_explore
    --finite 20 --anywhere --seed 227: the right pad's 4 rolls on the cusp-side corner and the
    closing segment while the left only probed, meeting the curve at ψ −100…−120°; the flat
    presses found no seat, and the move named turned the closing segment further toward the
    right pad). None when every such finger rolled: then a block's presses start as before."""
    rolled = {t.finger for t in out.touches if not isinstance(t.touch, FlatResult)}
    rolled |= {f.name for f in cfg.fingers if probes_on_face(cfg, f.name, out.probes, pressed)}
    active = [f for f in cfg.fingers if off_curve[f.name] < OFF_CURVE_RETIRE]
    return unrolled_finger(active, out, probes, rolled, roll_at)


def probes_on_face(cfg, name: str, probes: Sequence[FeltTouch], pressed: Sequence[FeltTouch]) -> bool:
    """Whether finger ``name``'s probes that met the object on its pad's face (of ``probes``;
    tactile_jaw.plan.probe_face_contact) met only the face its first seated press (of
    ``pressed``) found, or that face's supports: each of their pad lines is that face's support
    line at its normal, d = min(n·P, n·Q) within ``SEAT_TOL_MM`` (a line farther out rests on
    boundary beyond the face). Such probes say nothing of a curved part, and the finger need not
    roll before the flat presses answer: X-series lines 1, 4, 9, 19 of bench_explore --finite 20
    --anywhere --seed 269, whose right pad, its 3 seated presses done, was held to a roll of 3.4–4.1
    s that pivoted about its face's end (the run 27.8–29.0 s). False without a seated face."""
    face = next((t.face for t in pressed if t.finger == name and t.face is not None), None)
    if face is None:
        return False
    lines = [s.line for t in probes if t.finger == name and probe_face_contact(cfg, t) is not None
             for s in t.touch.samples]
    return all(abs(float(ln.d) - min(float(ln.normal @ face.p), float(ln.normal @ face.q))) <= SEAT_TOL_MM
               for ln in lines)


def unrolled_places(cfg, out: Exploration, recognition) -> list[tuple[float, float, float]]:
    """While a closed class (``CLOSED``) fits within ``DECISIVE_CHI2`` of the best consistent
    class (``recognition``'s ranking), for every finger without a usable roll whose probes met
    the object (at a pad end, or a face it could not roll on): (x, y, φ) where the probe whose
    contact lay nearest its pad's middle met it (the crossing of its last two pad lines,
    hand_driver.motion.contact_on_pad; φ its pad's tangent, ψ − π/2). A move advised to the
    recognizer's most telling touch then brings these within a pad's roll too
    (tactile_jaw.choose.with_places): a closed object's other side decides what one side
    leaves to open rivals (:func:`unrolled_finger`; random X-series ellipse 57 of bench_explore
    --finite 20 --anywhere --seed 127, the right pad meeting it only at its proximal end: moved
    as the one-place move advised, the left alone rolled again and it was refused again; moved
    so, it is answered). A parabola's vertex move does not take them (tactile_jaw.choose.next_aim):
    an ellipse fits a parabola's touches as well always, and an open object's other finger meets
    its closing segment or corners (the P-series parabolas' moves stay as they were)."""
    ranked = [r for r in recognition.ranking if r.consistent]
    if not ranked or not any(r.cls in CLOSED and r.chi2 - min(q.chi2 for q in ranked) < DECISIVE_CHI2
                             for r in ranked):
        return []
    out_places = []
    for f in cfg.fingers:
        if any(t.finger == f.name for t in out.used):
            continue
        met = []
        for probe in out.probes:
            samples = probe.touch.samples
            if probe.finger != f.name or len(samples) < 2:
                continue
            point, u = contact_on_pad(samples)
            if u is not None:
                met.append((abs(u - 0.5 * f.pad.length_mm), point, float(samples[-1].line.psi)))
        if met:
            _, point, psi = min(met, key=lambda m: m[0])
            out_places.append((float(point[0]), float(point[1]), psi - math.pi / 2))
    return out_places


#: a closed answer's curve is searched for a roll of a finger that has none every this many
#: degrees of pad normal, within ``SIDE_SPREAD_DEG`` of the finger's zero-angle normal, the
#: predicted contact ``SIDE_PAD_MARGIN`` of the pad's length from its ends (the planner keeps
#: tactile_jaw.plan.PLAN_PAD_MARGIN, 0.1: X-series ellipse 50 below rolls usably only 46–50 mm
#: along its 52 mm pad) (:func:`other_side_aim`)
SIDE_STEP_DEG = 1.0
SIDE_SPREAD_DEG = 60.0
SIDE_PAD_MARGIN = 0.05


def other_side_aim(recognition, finger, reach: JawReach) -> Aim | None:
    """Where ``finger``, with no usable roll and no orientation the planner predicts a roll
    at from the lines felt (its probes met the object at a pad end, or not at all), rolls on
    a closed answer (``CLOSED``: the leading ``recognition``, undecided only for its parameters:
    while an open class fits too, that side may not exist, and a roll aimed there spends the
    budget on nothing — P-series semicubical 126 of seed 157, ellipse and semicubical fitting,
    was refused so): of the pad normals within ``SIDE_SPREAD_DEG`` of the finger's zero-angle
    normal at which the planner could
    roll on the answer's curve (tactile_jaw.plan.feasible on the answer's support lines, the
    contact ``SIDE_PAD_MARGIN`` of the pad's length from its ends), the one whose contact
    lies deepest inside the pad. One finger's rolls on one side of an ellipse leave its axes
    uncertain by ±25 % at 4,096 ticks per turn; a roll on the other side states them within
    0.3 % (random X-series ellipse 50 of bench_explore --finite 20 --anywhere --seed 157: the
    left pad rolls usably only at pad normals −98…−92°, its contact 46–50 mm along a 52 mm
    pad; its probes at −90° and −110° met the object off its face, and it never rolled).
    None when there is none."""
    if recognition is None or recognition.cls not in CLOSED or recognition.pose is None:
        return None
    curve = CURVES[recognition.cls](recognition.params)
    if curve.t_period is None:
        return None
    points = np.stack(recognition.pose.apply(*curve.point(np.linspace(*curve.t_period, 4 * 360, endpoint=False))),
                      axis=-1)
    ws = reach.config.workspace
    model = ObjectModel(ws.center_mm, ws.radius_mm)  # the answer's support lines, every SIDE_STEP_DEG
    psis = np.radians(np.arange(-180.0, 180.0, SIDE_STEP_DEG))
    model.add(psis, [float(np.min(points @ kin.unit(float(a)))) for a in psis])
    length = finger.pad.length_mm
    best = None
    for off in np.radians(np.arange(-SIDE_SPREAD_DEG, SIDE_SPREAD_DEG + SIDE_STEP_DEG / 2, SIDE_STEP_DEG)):
        psi = nominal_psi(finger) + float(off)
        predicted = predicted_tangent(model, psi)
        if predicted is None or not feasible(finger, model, psi, reach.settings, pad_margin=SIDE_PAD_MARGIN):
            continue
        d, p = predicted
        depth = max((min(u, length - u) for q in kin.ik_line_solutions(finger, psi, d)
                     if kin.within_limits(finger.joints, q, LIMIT_MARGIN_RAD)
                     for u in [float(kin.finger_pad_line(finger, q).pad_coordinate(p))]), default=None)
        if depth is not None and (best is None or depth > best[0]):
            best = (depth, float(p[0]), float(p[1]), psi)
    if best is None:
        return None
    _, x, y, psi = best
    return Aim(x, y, float(math.remainder(psi - math.pi / 2, 2 * math.pi)), finger.name,
               f"where it can roll on the {recognition.cls} the other finger's rolls answer, its contact deepest on "
               f"the pad: the other side of a closed object decides what one side leaves", kind="side")


def promised_aims(places: Sequence[dict], cfg) -> dict[str, Aim]:
    """Per finger, the first roll of a run after a move a refusal named (``places``: where that
    move was for, tactile_jaw.choose.moved_places, each with the finger that rolls there; the
    log's ``move``, ``tactile explore --moved-as``): the place itself, once, after its finger's
    probes. The planner alone may never roll there: random X-series ellipse 40 of bench_explore
    --finite 20 --anywhere --seed 283, moved 4 mm for the right pad to roll on the side it had
    met only with its probes, was refused again with no right roll at all (no orientation the
    right pad's lines predict a roll at; :func:`other_side_aim` only while the answer's
    parameters are unsure, not while an open rival fits)."""
    names = {f.name for f in cfg.fingers}
    out: dict[str, Aim] = {}
    for place in places:
        finger = place.get("finger")
        if finger in names and finger not in out:
            out[finger] = Aim(float(place["x"]), float(place["y"]), float(place["phi"]), finger,
                              "where the move of the object the last refusal named was for", kind="promised")
    return out


def _follow_hint(hint: Aim, finger: str, from_hint: set[str], aimed_at: list, say) -> tuple[float, tuple, float | None]:
    """A finger's next roll where its last one points (``hint``: a stretch of the curved part,
    or a corner in doubt): (ψ, the point aimed at, the span: in roll spans for a corner in doubt, else
    its own in rad or None), said."""
    from_hint.add(finger)
    aimed_at.append(hint.point)
    say(f"{finger}: next touch at ({hint.x:.1f}, {hint.y:.1f}) mm, pad normal "
        f"{math.degrees(math.remainder(hint.psi, 2 * math.pi)):.1f} deg, {hint.why}")
    return hint.psi, hint.point, (WIDER_SPAN if hint.kind == "wider" else hint.span)


def off_curve_count(count: int, felt: FeltTouch, hinted: bool) -> tuple[int, bool]:
    """(the finger's touches in a row off the curved part, after ``felt``; whether its next
    roll goes where ``felt`` still felt the curved part, ``felt.curve_at``). A roll that ran
    off the curved part yet felt it on a shorter stretch (tactile_jaw.pipeline.curve_hint) is
    not counted and is followed, once: a roll aimed there (``hinted``) that runs off again
    counts, hint or not, so a finger retires (``OFF_CURVE_RETIRE``) instead of rolling there
    for ever (random parabola 11 of bench_explore --finite 3 --anywhere --follow --seed 17
    --config config/jaw-p.yaml, moved as advised: the same roll, χ² 731 on 3 dof with a
    hint, 236 times; off-curve touches do not count against the budget)."""
    follow = felt.curve_at is not None and not hinted
    return (count + 1 if felt.off_curve and not follow else 0), follow


def rolls_on_within(name: str, used: list[FeltTouch], psi: float | None) -> bool:
    """Whether finger ``name``, whose last ``OFF_CURVE_RETIRE`` rolls fell off the curved part,
    rolls on instead of retiring: it felt the curve (a usable touch among ``used``) and the
    planner still has an orientation ``psi`` for it short of where its rolls left the curve
    (tactile_jaw.plan.choose_psi within :func:`curve_limits`, which those rolls bound). Its
    rolls off the curve then only say where the curve ends on its side; its orientations
    between them are not spent. Calibrated P semicubical 130 of bench_explore --finite 20
    --anywhere --seed 127: the right pad rolled on the curve at ψ 82.5° and 110°, then at 55°
    and 67.5° (the planner's farthest from the earlier ones) across the closing segment, and
    retired; ψ 88–104° was left, and the answer was refused with 2 usable touches."""
    return psi is not None and any(t.finger == name for t in used)


def scanned_curve(cfg, felt: FeltTouch, reach: JawReach, no_curve: set[int]) -> Aim | None:
    """Where a flat press's scan (``felt``: the pad turning toward a seat while in contact)
    rolled on a curved part (tactile_jaw.pipeline.curved_part), as the Aim of its finger's
    next roll, when its finger can roll there; else None, the press added to ``no_curve``
    (its ``id``: the flat phase does not feel its scan again). Such a press ends the rolls
    refused in the flat phase ("no rolling touch on it was usable"), while a roll there is
    usable: P cubicals 109 and 113 of bench_explore --finite 20 --anywhere --seed 127 (a
    scan of ρ 11 mm, the other finger's rolls on a corner)."""
    if not isinstance(felt.touch, FlatResult):
        return None
    roll = curved_part(cfg, [felt])
    if roll is None:
        no_curve.add(id(felt))
        return None
    c, m = roll.contacts, len(roll.contacts.x) // 2
    x, y, phi = float(c.x[m]), float(c.y[m]), float(c.psi[m]) - math.pi / 2
    if reach.finger(x, y, phi, [cfg.finger(felt.finger)]) is None:
        return None
    return Aim(x, y, phi, felt.finger, f"where its flat press's scan rolled on the curved part (radius of curvature "
                                      f"{roll.fit.rho:.1f} mm)", kind="scan")


def at_corner(x, y, corners):
    """Whether the point (x, y) lies within ``CORNER_CLEARANCE_MM`` of one of the ``corners``
    ((k, 2): those a roll pivoted about, tactile_jaw.pipeline.clearing_corners), where a roll
    keeps none of its samples (tactile_jaw.pipeline.clear_of_corners); for arrays ``x``, ``y``,
    one bool per point."""
    corners = np.asarray(corners, float).reshape(-1, 2)
    px, py = np.asarray(x, float)[..., None], np.asarray(y, float)[..., None]
    near = np.any(np.hypot(corners[:, 0] - px, corners[:, 1] - py) < CORNER_CLEARANCE_MM, axis=-1)
    return bool(near) if near.ndim == 0 else near


def pad_end_normals(name: str, touches: Sequence[FeltTouch]) -> list[tuple[int, float, float]]:
    """(touch number, ψ_a, ψ_b rad) of each of finger ``name``'s probes and rolls (of
    ``touches``, felt) that stopped with a pad end on the object (outcome ``edge``,
    hand_driver.motion.rolling_touch: its last two pad lines, at ψ_a and ψ_b, crossed within
    ``EDGE_MARGIN_MM`` of a pad end or beyond it). A roll through both normals meets that pad
    end again (tactile_jaw.plan.passes_end): the planner's (choose_psi), an aimed touch and a
    touch on (:func:`futile_roll`) make none."""
    return [(t.touch.touch, float(t.touch.samples[-2].psi), float(t.touch.samples[-1].psi)) for t in touches
            if t.finger == name and not isinstance(t.touch, FlatResult) and t.touch.outcome == "edge"
            and len(t.touch.samples) >= 2]


def futile_roll(aim: Aim, touches: Sequence[FeltTouch], span: float, corners) -> str | None:
    """Why a roll of ``span`` (rad) about ``aim`` would measure nothing, or None: its place lies
    at a corner a roll pivoted about (:func:`at_corner`); or it turns through both pad normals at
    which a probe or roll of its finger (of ``touches``, felt) stopped with a pad end on the
    object (:func:`pad_end_normals`). Such rolls cost the P cubicals touching on for their σ's
    3-4 s each (seed 191: 112, a roll at ψ 82.0° where one at 82.5° had met the pad's proximal
    end at 73.5…75.75°)."""
    if at_corner(aim.x, aim.y, corners):
        return f"it lies within {CORNER_CLEARANCE_MM:g} mm of a corner a roll pivoted about"
    for touch, psi_a, psi_b in pad_end_normals(aim.finger, touches):
        if passes_end(aim.psi, span, [(psi_a, psi_b)]):
            return (f"the {aim.finger} pad's touch {touch} met its pad end at pad normals "
                    f"{math.degrees(math.remainder(psi_a, 2 * math.pi)):.1f}…"
                    f"{math.degrees(math.remainder(psi_b, 2 * math.pi)):.1f} deg, within this roll")
    return None


#: how far past the felt stretch's other end :func:`past_felt_end` places a touch, in
#: lengths of that stretch (of the answer's curve parameter t): far enough that it is not
#: the stretch felt again, near enough to lie on the object's curved part
PAST_END_FRACTION = 1.0


#: how far either side of the felt stretch (times its length in t) :func:`beyond_felt_end` looks
#: for the parameter of a place on the answer's curve, and at how many points
END_SEARCH_SPANS = 4.0
END_SEARCH_POINTS = 4001


def beyond_felt_end(recognition, x, y, corners):
    """Whether the place (x, y) is not on the object as felt, for an open answer's curve
    (``recognition``: its contacts' parameters t are the felt stretch) and the corners rolls
    pivoted about (``corners``, tactile_jaw.pipeline.clearing_corners) that lie on that curve
    past the felt stretch: on the curve, past such a corner on its side (the curved part ends
    there, the fitted curve's continuation is not the object's); off the curve, when such
    corners close the felt stretch at both ends (the object is that curve between them and its
    closing segments: a rival's place elsewhere is on neither). P semicubical 123 of
    bench_explore --finite 20 --anywhere --seed 199 --config config/jaw-p.yaml: the touch named
    when the budget ran out lay at (135, 37) mm, on the far side of the ellipse fitted to all
    the touches (the recognizer's next_touch anywhere), 52 mm from the semicubical answered,
    whose ends both pads had pivoted about; the move to it ("20 mm toward the palm") left the
    pads only the cusp-side corner and the closing segment, and it was answered `line` after
    it. Places and corners are placed on the curve by its nearest of ``END_SEARCH_POINTS``
    points, within ``CORNER_CLEARANCE_MM``; a closed class has no ends (False). ``x``, ``y``
    may be arrays (the recognizer's places, :class:`FeltObject`): then one bool per place."""
    scalar = np.ndim(x) == 0 and np.ndim(y) == 0
    x, y = np.atleast_1d(np.asarray(x, float)), np.atleast_1d(np.asarray(y, float))
    out = np.zeros(x.shape, bool)
    curve = CURVES[recognition.cls](recognition.params)
    corners = np.asarray(corners, float).reshape(-1, 2)
    if curve.t_period is None and recognition.pose is not None and recognition.contacts and len(corners):
        felt = np.array([float(c["t"]) for c in recognition.contacts])
        lo, hi = float(np.min(felt)), float(np.max(felt))
        reach = END_SEARCH_SPANS * max(hi - lo, 1.0)
        t = np.linspace(lo - reach, hi + reach, END_SEARCH_POINTS)
        tree = cKDTree(np.stack(recognition.pose.apply(*curve.point(t)), axis=-1))

        def on_curve(qx: np.ndarray, qy: np.ndarray) -> np.ndarray:  # t of the nearest point, NaN: off the curve
            gap, k = tree.query(np.stack([qx, qy], axis=-1))
            return np.where(gap <= CORNER_CLEARANCE_MM, t[k], np.nan)

        ends = on_curve(corners[:, 0], corners[:, 1])
        below, above = ends[ends < lo], ends[ends > hi]
        at = on_curve(x, y)
        past_below = (at < lo) & (at <= below.max()) if below.size else np.zeros(x.shape, bool)
        past_above = (at > hi) & (at >= above.min()) if above.size else np.zeros(x.shape, bool)
        out = np.where(np.isnan(at), bool(below.size and above.size), past_below | past_above)
    return bool(out[0]) if scalar else out


@dataclass(frozen=True)
class FeltObject:
    """Where the recognizer's ``next_touch`` may point once its first choice lay off the object
    as felt (:func:`past_felt_end`): within ``within`` (the workspace's reach), neither past a
    corner the rolls pivoted about beyond the felt stretch of the ``recognition``'s curve
    (:func:`beyond_felt_end`) nor at such a corner (:func:`at_corner`, where a roll keeps no
    samples). Calibrated P cubical 58 of bench_explore --finite 10 --anywhere --seed 337: the
    hyperbola leading, the cubical as close, the place named lay 0.4 mm from the corner the
    left pad pivoted about, on its far side, and the refusal named no move; on the object, the
    recognizer names (112, 35) mm, and the move to it (turned 20°, 4 mm) is what its twin 51
    was answered right after."""

    within: Any
    recognition: Any
    corners: np.ndarray

    def contains(self, px, py, phi=None) -> np.ndarray:
        px, py = np.atleast_1d(np.asarray(px, float)), np.atleast_1d(np.asarray(py, float))
        return (np.asarray(self.within.contains(px, py, phi), bool) & ~at_corner(px, py, self.corners)
                & ~beyond_felt_end(self.recognition, px, py, self.corners))


def past_felt_end(recognition, touches: list[FeltTouch], wanted: Callable[[], dict | None], reach: JawReach,
                  span: float, limits: Callable[[str], list], corners=(),
                  on_object: Callable[[FeltObject], dict | None] | None = None) -> Callable[[], dict | None]:
    """The touch a budget-spent refusal names (tactile_jaw.choose.budget_advice): the
    recognizer's ``wanted`` (its ``next_touch`` anywhere), unless a pad reaches that place
    but its rolls left the curved part short of it (``limits``: tactile_jaw.explore.curve_limits,
    the object ends there, at a corner); then the place ``PAST_END_FRACTION`` of the felt
    stretch past its other end, on the leading answer's curve (the usable ``touches``'
    contacts' parameters t), with the tangent the touches have: the curve the pads did not
    reach, which a move of the object brings within a roll. P semicubicals 124 and 132 of
    bench_explore --finite 20 --anywhere --seed 127 --config config/jaw-p.yaml: the pads
    reached t 0.86–2.9 of the branch, semicubical and ellipse both fitted, and the touch named
    lay beside the cusp-side corner "within a pad's reach": more touches were advised, none of
    which could roll there. So too when the place lies within ``CORNER_CLEARANCE_MM`` of a
    corner a roll pivoted about (``corners``, tactile_jaw.pipeline.clearing_corners): a roll
    there keeps none of its samples near that corner (tactile_jaw.pipeline.clear_of_corners)
    and runs onto it (P cubical 104 of seed 139: the place named lay 0.8 mm from the corner
    where the left pad's rolls left the curve, and more touches were advised). When the place
    lies past a corner beyond the felt stretch (:func:`beyond_felt_end`: not on the object), the
    recognizer's next touch among the places on the object as felt (``on_object``, asked with a
    :class:`FeltObject` as its reach; None without it, or when there is none): no move brings a
    place the object does not have within reach, a move to the best one it has may decide."""

    def run() -> dict | None:
        place = wanted()
        if place is None or recognition.pose is None or not recognition.contacts:
            return place
        x, y, phi = float(place["x"]), float(place["y"]), float(place["phi"])
        if beyond_felt_end(recognition, x, y, corners):
            if on_object is None:
                return None
            place = on_object(FeltObject(workspace_reach(reach.config), recognition,
                                         np.asarray(corners, float).reshape(-1, 2)))
            if place is None:
                return None
            x, y, phi = float(place["x"]), float(place["y"]), float(place["phi"])
        finger = reach.finger(x, y, phi)
        if finger is None or (not at_corner(x, y, corners) and within_curve(phi + math.pi / 2, span,
                                                                            limits(finger.name))):
            return place
        cx, cy, t = np.array([(float(c["x"]), float(c["y"]), float(c["t"])) for c in recognition.contacts]).T
        near = int(np.argmin(np.hypot(cx - x, cy - y)))
        lo, hi = int(np.argmin(t)), int(np.argmax(t))
        end = lo if abs(t[near] - t[hi]) < abs(t[near] - t[lo]) else hi  # the felt stretch's other end
        past = _past_end(recognition, touches, end)
        return place if past is None else {**place, **past, "what": "a touch on the curve past where the pads reached it"}

    return run


def _past_end(recognition, touches: list[FeltTouch], end: int) -> dict | None:
    """The place ``PAST_END_FRACTION`` of the felt stretch past its end ``end`` (an index of
    ``recognition.contacts``: the one of least or greatest t) on the answer's curve, with the tangent
    the usable ``touches`` have there ({x, y, phi}: :func:`_curve_place`); None when that place is
    the end itself or lies across a branch's end (the semicubical's cusp: not on the object)."""
    t = np.array([float(c["t"]) for c in recognition.contacts])
    t_far = _t_past(t, end)
    curve = CURVES[recognition.cls](recognition.params)
    if t_far == t[end] or float(np.ravel(curve.keep_branch(np.array([t[end]]), np.array([t_far])))[0]) != t_far:
        return None
    return _curve_place(recognition, touches, end, t_far)


def _t_past(t: np.ndarray, end: int) -> float:
    """The curve parameter ``PAST_END_FRACTION`` of the felt stretch (contacts' ``t``) past its end ``end``."""
    lo, hi = int(np.argmin(t)), int(np.argmax(t))
    return float(t[end] + PAST_END_FRACTION * (t[end] - t[hi if end == lo else lo]))


def _curve_place(recognition, touches: list[FeltTouch], near: int, u: float) -> dict:
    """{x, y, phi} of the answer's curve at parameter ``u``, its tangent in the direction of travel
    of the usable ``touches``' touch nearest contact ``near`` of ``recognition.contacts``."""
    curve, pose = CURVES[recognition.cls](recognition.params), recognition.pose
    cx, cy, t = np.array([(float(c["x"]), float(c["y"]), float(c["t"])) for c in recognition.contacts]).T
    px, py = (float(np.ravel(v)[0]) for v in pose.apply(*curve.point(np.array([u]))))

    def tangent(v: float) -> float:
        return float(np.ravel(curve.tangent_angle(np.array([v])))[0]) + pose.theta

    # the touch nearest that contact (the answer may hold fewer contacts than there are touches)
    felt = touches[near].samples if len(touches) == len(t) else min(
        (touch.samples for touch in touches),
        key=lambda v: float(np.min(np.hypot(np.asarray(v.x) - cx[near], np.asarray(v.y) - cy[near]))))
    flip = math.remainder(float(np.median(felt.phi)) - tangent(t[near]), 2 * math.pi)
    flip = math.pi if abs(flip) > math.pi / 2 else 0.0  # the touches' direction of travel
    return {"x": px, "y": py, "phi": float(math.remainder(tangent(u) + flip, 2 * math.pi))}


def felt_side_places(recognition, touches: list[FeltTouch], corners=()) -> tuple[tuple[float, float, float], ...]:
    """For an open answer (a curve with no period, not a line), the places a move of the object
    is for when the rolls of the side felt cannot tell it from its rival at this jaw's resolution
    (tactile_jaw.choose.budget_advice): (x, y, φ) of the place ``PAST_END_FRACTION`` of the felt
    stretch past one of its ends on the answer's curve (:func:`_past_end`), then the felt
    stretch's other end (its contact, the curve's tangent there), so that the run after the move
    feels both; () for a closed answer, or when neither end's place lies on the object as felt
    (past a corner a roll pivoted about, ``corners``: :func:`beyond_felt_end`, or across a
    branch's end). The end: of those, the one where the answer's radius of curvature at the place
    is larger (an open branch opens out there, where a closed rival's bounded radius cannot follow
    it). The other finger of such a refusal met the branch's closing chord or an end corner, not
    another stretch of the curve: calibrated P semicubicals 60 and 63 of bench_explore --finite 10
    --anywhere --calibrate --seed 593, moved for that other side, were refused again (their rolls
    felt t 1.6–2.9 of branches reaching t 4.7, radii of curvature 8–13 mm)."""
    if recognition.cls not in CURVES or recognition.cls == "line" or recognition.pose is None \
            or len(recognition.contacts) < 2:
        return ()
    curve = CURVES[recognition.cls](recognition.params)
    if curve.t_period is not None:
        return ()
    t = np.array([float(c["t"]) for c in recognition.contacts])
    lo, hi = int(np.argmin(t)), int(np.argmax(t))
    found = []
    for end, other in ((lo, hi), (hi, lo)):
        past = _past_end(recognition, touches, end)
        if past is None or beyond_felt_end(recognition, past["x"], past["y"], corners):
            continue
        kappa = abs(float(np.ravel(curve.kappa(np.array([_t_past(t, end)])))[0]))
        back = _curve_place(recognition, touches, other, float(t[other]))
        found.append((kappa, (past["x"], past["y"], past["phi"]), (back["x"], back["y"], back["phi"])))
    if not found:
        return ()
    _, place, back = min(found, key=lambda f: f[0])  # the larger radius of curvature
    return place, back


def _spent(out: Exploration) -> int:
    """Touches that count against the budget: all but those that fell on a corner or across
    a closing segment of a finite object (a finger retires after OFF_CURVE_RETIRE in a row,
    so these stay few); the touches on the curved part are what the budget is for."""
    return sum(not t.off_curve and not isinstance(t.touch, FlatResult) for t in out.touches)


def explore(jaw: Jaw, settings: ExploreSettings, recognize_touches: RecognizeTouches,
            emit: Callable[[dict], None] | None = None,
            progress: Callable[[str], None] | None = None,
            recognize_anywhere: RecognizeTouches | None = None, moved_for: Sequence[dict] = (),
            felt_before: FeltBefore | None = None) -> Exploration:
    """Explore with both fingers (module docstring). ``recognize_touches`` maps a list of
    usable felt touches to a Recognition (tactile_jaw.pipeline.make_recognizer, its
    ``next_touch`` within the jaw's reach); ``emit`` receives log records; ``progress``
    one-line messages for people; ``recognize_anywhere``, the same with ``next_touch``
    anywhere in the workspace, lets a stop for want of reach say where the touch would go
    and how far to move the object (tactile_jaw.choose.move_advice); ``moved_for``, where the move
    of the object a refusal named was for (its ``move['places']``): each finger named rolls there
    first after its probes (:func:`promised_aims`); ``felt_before``, what the run before that move
    felt of the object (tactile_jaw.felt_before: logged first; a `line` answer refused when it felt
    curvature, :func:`closing_answer`)."""
    emit = emit or (lambda rec: None)
    say = progress or (lambda msg: None)
    recognize_touches = _memo(recognize_touches)
    cfg = jaw.config
    ws = cfg.workspace
    model = ObjectModel(ws.center_mm, ws.radius_mm)
    out = Exploration()
    t0 = jaw.robot_time()
    if felt_before is not None:
        emit(felt_before.to_event())
    off_curve: dict[str, int] = {f.name: 0 for f in cfg.fingers}  # the finger's latest touches off the curve
    pressed: list[FeltTouch] = []  # flat presses made during the probes and rolls (tactile_jaw.flat_phase)
    aside: set[int] = set()  # presses of fingers with no roll to make, beside the others' probes and rolls

    def press_beside(name, touch_index=None, spent=None, result=None):
        """A finger done probing presses at a seat its lines show while the other probes on
        (tactile_jaw.flat_phase.beside_press; tactile_jaw.probing.probe_boundary's ``beside``)."""
        if result is None:
            return beside_press(jaw, name, model, out, pressed, settings, touch_index, emit, spent, seat_only=True)
        felt = feel(cfg, result, settings.samples_per_touch)
        out.touches.append(felt)
        pressed.append(felt)
        aside.add(felt.touch.touch)  # not counted against its rolls: it may still roll, the guard for a curve
        say(f"{name}: its probes done and its pad lines show a face: pressed flat there while the other finger "
            f"probes on")
        return None

    index, probes = probe_boundary(jaw, model, out, emit, say, press_beside)
    used: dict[str, list[float]] = {f.name: [] for f in cfg.fingers}
    reach = JawReach(cfg, settings, out.probes)  # the probes' list: those beside the rolls count as made
    ticks = jaw_ticks_per_rev(cfg)
    refeel = partial(feel, cfg)  # decide's end-sample test feels a roll again without an end
    aim: Aim | None = None  # where the next touch goes while the answer is not decisive (tactile_jaw.choose)
    undecided = None  # the latest answer that was not decisive: (recognition, why, its touches)

    def anywhere(touches):  # the recognizer's next_touch anywhere in the workspace, asked only when a stop says it
        return None if recognize_anywhere is None else (lambda: recognize_anywhere(touches).next_touch)

    aimed_at: list[tuple[float, float]] = []
    # per finger: where its last unusable roll still felt the curved part, or where a move was for
    hints: dict[str, Aim] = promised_aims(moved_for, cfg)
    #: the touches rolled WIDER_SPAN times wider where a corner was in doubt (their indices: not
    #: rolled wider again; a usable one drops that corner, tactile_jaw.pipeline.measured_there)
    wider: set[int] = set()
    vertex_missed = None  # how a touch aimed beyond a parabola's vertex fell off the curved part (choose.VERTEX_ENDS)
    empty_at: list[tuple[float, float]] = []  # points aimed at where the touch met nothing
    cleared = _clear_of_corners(cfg, out, settings, emit, say)

    def limits(name):  # where the finger's rolls so far left the curved part
        return curve_limits(name, out.touches, clearing_corners(out.touches))

    def ends(name):  # the pad normals where the finger's probes and rolls stopped with a pad end on the object
        return [(a, b) for _, a, b in pad_end_normals(name, (*out.probes, *out.touches))]

    def plan_psi(f):  # the planner's next roll of finger f: within the curve felt, not about a corner or through a
        # pad end met
        return choose_psi(f, model, settings, used[f.name], limits(f.name), corner_cones(f.name, out.touches, out.probes),
                          ends(f.name))

    deferred: set[str] = set()  # fingers a stop for want of reach waited for (unrolled_finger), once each
    no_curve: set[int] = set()  # presses whose scans rolled on no curved part (their id; scanned_curve)
    sided: set[str] = set()  # fingers sent to a closed answer's other side once (other_side_aim)
    cornered: set[int] = set()  # usable touches dropped for their samples at a corner, looked at once (beside_corners)
    handed: list[Aim | None] = []  # the roll on a curved part felt while no touch was usable, asked once (felt_curve_roll)

    def hand_back() -> bool:
        """Before the rolls give way to the flat phase with no touch usable: whether a finger rolls
        once more on a curved part felt (:func:`felt_curve_roll`); a roll there that fails again
        counts toward retiring it."""
        if handed or cleared():
            return False
        aim = felt_curve_roll(cfg, out, settings, reach, no_curve)
        handed.append(aim)
        if aim is None:
            return False
        hints[aim.finger], off_curve[aim.finger] = aim, min(off_curve[aim.finger], OFF_CURVE_RETIRE - 1)
        message = f"{aim.finger}: a curved part was felt and no touch was usable: it rolls there before the pads press flat"
        emit({"type": "event", "kind": "curve_handed_back", "message": message})
        say(message)
        return True

    #: probes made beside the rolls (tactile_jaw.probing.Probes): each takes its finger's turn of a
    #: round, so a press from the second round on (early_press) counts them with the touches
    beside = 0
    while _spent(out) < settings.touches:
        if len(out.touches) >= TRIED_PER_BUDGET * settings.touches:
            message = (f"{len(out.touches)} touches tried, {TRIED_PER_BUDGET}x the budget of {settings.touches}: "
                       f"most fell off the curved part; no more touches")
            emit({"type": "event", "kind": "touches_capped", "message": message})
            say(message)
            break
        if not cleared() and not hints and aim is None:
            done = guard_done(cfg, out, pressed, settings)
            if done is not None:  # one face's presses answer and no curved part is left to guard against
                emit({"type": "event", "kind": "guard_done", "message": done})
                say(done)
                break
        if not cleared() and len(out.touches) - len(aside) >= FLAT_AFTER_TOUCHES and not any(
                h.kind in ("corner", "scan", "promised", "felt") or (h.kind == "wider" and out.used)
                for h in hints.values()):
            # unless a finger rolls again beside a corner, where a press's scan felt the curve, where a move was
            # for, or wider where a roll was in doubt once a usable roll felt the curve (X ellipse 43 of seed 157:
            # its tight ends)
            waiting = unrolled_before_flat(cfg, out, probes, off_curve, plan_psi, pressed)
            if waiting is None and hand_back():
                continue
            if waiting is None:
                say(f"none of {sum(not isinstance(t.touch, FlatResult) for t in out.touches)} rolling touches was "
                    f"usable clear of the corners: no curved part within reach of the pads")
                break
            probes.queues[waiting] = []  # it rolls now, its probes left undone
            message = (f"{waiting}: its probes met the object's face and it has not rolled yet: it rolls there "
                       f"before the pads press flat")
            emit({"type": "event", "kind": "flat_deferred", "message": message})
            say(message)
        plans, spent, aimed, pressing, from_hint, idle, again = {}, {}, None, None, set(), set(), {}
        if aim is not None and aim.kind != "vertex" and not within_curve(aim.psi, settings.roll_span_rad,
                                                                         limits(aim.finger)):
            say(f"{aim.finger}: a touch at ({aim.x:.1f}, {aim.y:.1f}) mm would roll beyond where its rolls left the "
                f"curved part: the planner's instead")
            aimed_at.append(aim.point)
            aim = None
        if aim is not None and aim.kind != "vertex" and passes_end(aim.psi, settings.roll_span_rad, ends(aim.finger)):
            say(f"{aim.finger}: a touch at ({aim.x:.1f}, {aim.y:.1f}) mm would roll through the pad normals at which "
                f"an earlier probe or roll met its pad end: the planner's instead")
            aimed_at.append(aim.point)
            aim = None
        budget = settings.touches - _spent(out)
        active = [f for f in cfg.fingers if off_curve[f.name] < OFF_CURVE_RETIRE][:budget]
        probing = probes.next()  # a finger's probes left once the other felt enough (tactile_jaw.probing)
        for f in active:
            point, span = None, None
            if f.name in probing and not (aim is not None and f.name == aim.finger):
                plans[f.name] = probes.plan(jaw, f.name, index + len(plans), emit, spent)
                continue
            probing.pop(f.name, None)
            if (f.name not in hints and not out.used and not cleared()
                    and any(t.finger == f.name and t.face is not None for t in pressed)):
                # a face seated and no curve felt: it presses that face again instead of rolling
                plan = beside_press(jaw, f.name, model, out, pressed, settings, index + len(plans), emit, spent)
                if plan is not None:
                    aside.add(index + len(plans))
                    plans[f.name], again[f.name] = plan, index + len(plans)
                    continue
            if aim is not None and f.name == aim.finger:
                psi, point, aimed = aim.psi, aim.point, aim
                aimed_at.append(point)
                say(f"{f.name}: next touch at ({aim.x:.1f}, {aim.y:.1f}) mm, pad normal "
                    f"{math.degrees(math.remainder(psi, 2 * math.pi)):.1f} deg, "
                    f"{aim.why}")
            elif f.name in hints and hints[f.name].kind != "wider":
                psi, point, span = _follow_hint(hints.pop(f.name), f.name, from_hint, aimed_at, say)
            else:
                later = active[active.index(f) + 1:]
                others_roll = bool(plans) or any(g.name in hints or plan_psi(g) is not None for g in later)
                if (not out.used and not pressed and pressing is None and others_roll  # another finger rolls meanwhile
                        and len(cfg.fingers) <= len(out.touches) + beside and len(out.touches) < FLAT_AFTER_TOUCHES):
                    plan = early_press(jaw, f.name, model, out, index + len(plans), emit, spent)
                    if plan is not None:  # its rolls show a seat: it presses while the other rolls again
                        # (its corner in doubt, if any, is a support of that face: not rolled again wider)
                        hints.pop(f.name, None)
                        say(f"{f.name}: no touch usable so far and its pad lines show a face: pressing the pad flat "
                            f"on it while the other finger rolls again")
                        plans[f.name], pressing = plan, f.name
                        continue
                if f.name in hints:  # a corner in doubt: rolled again wider (wider_again)
                    psi, point, span = _follow_hint(hints.pop(f.name), f.name, from_hint, aimed_at, say)
                    span *= settings.roll_span_rad
                    wider.add(index + len(plans))
                else:
                    psi = plan_psi(f)
                    side = None
                    if (psi is None and undecided is not None and undecided[1].kind == "imprecise"
                            and f.name not in sided and not any(t.finger == f.name for t in out.used)):
                        sided.add(f.name)
                        side = other_side_aim(undecided[0], f, reach)
                    if side is not None:
                        psi, point = side.psi, side.point
                        aimed_at.append(point)
                        say(f"{f.name}: next touch at ({side.x:.1f}, {side.y:.1f}) mm, pad normal "
                            f"{math.degrees(math.remainder(psi, 2 * math.pi)):.1f} deg, {side.why}")
            if psi is None:
                message = (f"{f.name}: no untouched pad orientation left for which the felt lines predict a "
                           f"{math.degrees(settings.roll_span_rad):g} deg roll on the pad's face")
                emit({"type": "event", "kind": "no_orientation", "message": message})
                say(message)
                idle.add(f.name)
                continue
            used[f.name].append(psi)
            plans[f.name] = _touch_plan(jaw, f.name, model, psi, settings, index + len(plans), emit, spent, point,
                                        span)
        if set(plans) == set(again) and all(plan_psi(cfg.finger(n)) is None for n in again):
            aside.difference_update(again.values())  # only presses of a seated face, and no finger can roll
            plans = {}  # again: the flat phase makes them and decides (nothing to guard against any more)
        if not plans and hand_back():
            continue
        if not plans:
            break
        if not out.used and not cleared():  # a finger with no roll presses while the others look for a curved part
            # from its nominal normal only once a roll found no curved part (a walk of 4-12 s before the
            # first rolls held up the round of a random ellipse's first usable roll: seed 13, P-series)
            rolled = any(not isinstance(t.touch, FlatResult) and t.touch.touch not in aside for t in out.touches)
            for f in cfg.fingers:
                if f.name in idle or (f.name not in plans and f.name not in probing
                                      and off_curve[f.name] >= OFF_CURVE_RETIRE):
                    plan = beside_press(jaw, f.name, model, out, pressed, settings, index + len(plans), emit, spent,
                                        seat_only=not rolled)
                    if plan is not None:
                        aside.add(index + len(plans))
                        say(f"{f.name}: no roll to make; pressing its pad flat while the other finger goes on")
                        plans[f.name] = plan
        index += len(plans)
        out.rounds += 1
        results = timed_round(jaw, plans, spent, out.time_s, "touches", "touch_transits")
        for name in plans:
            if name in probing:
                probes.record(feel(cfg, results[name], PROBE_SAMPLES, curve_checks=False), out, say)
                beside += 1
                continue
            felt = feel(cfg, results[name], settings.samples_per_touch)
            touch, problem = felt.touch, felt.problem
            out.touches.append(felt)
            if isinstance(touch, FlatResult) or touch.touch in aside:  # a press (early_press, beside_press):
                # counted by the flat phase, or not at all
                pressed.append(felt)
                if touch.touch not in aside:  # a press beside the others' rolls leaves the finger's own rolls as
                    off_curve[name] += 1  # they were (the guard for a curve); an early press replaced one
                scan = scanned_curve(cfg, felt, reach, no_curve)
                if scan is not None:  # its scan rolled on the curved part: the finger rolls there next
                    hints[name], off_curve[name] = scan, 0
                    say(f"{name}: its flat press's scan rolled on a curved part: it rolls there next")
                continue
            again = wider_again(felt, reach, wider)
            count, follow = off_curve_count(off_curve[name], felt, name in from_hint)
            off_curve[name] = 0 if again is not None else count  # a roll in doubt, rolled again wider: not counted
            if again is not None:
                hints[name] = again
            if follow and reach.finger(*felt.curve_at, [cfg.finger(name)]) is not None:
                hints[name] = Aim(*felt.curve_at, name, "where its last roll felt the curved part before it ran "
                                                        "off it", kind="curve")
            if off_curve[name] == OFF_CURVE_RETIRE and felt.off_curve and rolls_on_within(
                    name, out.used, plan_psi(cfg.finger(name))):
                off_curve[name] -= 1
                say(f"{name}: its last {OFF_CURVE_RETIRE} touches left the curved part it felt: it rolls on short of "
                    f"where they left it")
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
                # the object ends there only when the roll pivoted about a corner or its approach met
                # nothing; one that ran off the curved part elsewhere, or could not be made (outside the
                # joint limits: P parabola 66 of bench_explore --finite 20 --anywhere --seed 127), stops
                # naming a move (tactile_jaw.choose.VERTEX_OFF); one that ran off the pad's face (P
                # parabola 78 of --seed 107: 28.8..51.4 mm along a 52 mm pad) goes to the next centre
                if aimed.kind == "vertex" and (felt.off_curve or not touch.samples) and vertex_missed != VERTEX_ENDS:
                    object_ends = felt.corner is not None or (not touch.samples and touch.outcome == "no_contact")
                    vertex_missed = VERTEX_ENDS if object_ends else VERTEX_OFF
                if not touch.samples:
                    empty_at.append(aimed.point)  # the object is not where the answered curve goes on
        if probing:
            probes.done(say)
        usable = cleared()
        for name, side in beside_corners(out, usable, cornered, settings):
            if name not in hints and off_curve[name] < OFF_CURVE_RETIRE and reach.finger(*side, [cfg.finger(name)]) is not None:
                hints[name] = Aim(*side, name, "beside its earlier roll's stretch clear of the corner it ran onto",
                                  kind="corner")
        if len(usable) >= settings.min_touches:
            recognition, why = decide(recognize_touches, usable, settings, ticks, refeel)
            out.recognition = recognition
            out.answers.append(recognition.cls)
            say(f"after {len(usable)} touches: {recognition.cls}" + ("" if why is None else f", not decisive: {why}"))
            if why is None:
                undecided = None
                loose = imprecision(recognition, settings.profile, target=True)
                if loose is None or _spent(out) >= settings.touches:
                    break
                # decisive, but a parameter looser than the profile's target: touch on where the recognizer
                # says that σ shrinks most, and answer as decided once it names no new place within reach
                # or the budget is spent (P cubical 108 of bench_explore --finite 20 --anywhere --seed 173)
                aim, stop = next_aim(recognition, loose, sample_positions(usable), reach,
                                     [f for f in cfg.fingers if off_curve[f.name] < OFF_CURVE_RETIRE], aimed_at)
                if stop is not None or aim is None:
                    break
                futile = futile_roll(aim, (*out.probes, *out.touches), settings.roll_span_rad, clearing_corners(out.touches))
                if futile is not None:  # it would measure nothing: answered as decided
                    message = (f"{recognition.cls} is decisive; not touching on at ({aim.x:.1f}, {aim.y:.1f}) mm: "
                               f"{futile}")
                    emit({"type": "event", "kind": "touching_on_skipped", "message": message})
                    say(message)
                    break
                message = f"{recognition.cls} is decisive; touching on: {loose}"
                emit({"type": "event", "kind": "touching_on", "message": message})
                say(message)
                continue
            undecided = (recognition, why, usable)
            active = [f for f in cfg.fingers if off_curve[f.name] < OFF_CURVE_RETIRE]
            aim, out.stopped = next_aim(recognition, why, sample_positions(usable), reach, active, aimed_at,
                                        vertex_missed, empty_at, anywhere(usable),
                                        unrolled_places(cfg, out, recognition),
                                        lambda: beyond_resolution(recognize_touches, recognition, why, usable,
                                                                  settings.touches))
            other = None if out.stopped is None else unrolled_finger(
                active, out, probes, deferred, plan_psi)
            if other is not None:  # its side of the object first: rolls on one side alone leave the rivals
                deferred.add(other)
                probes.queues[other] = []
                message = (f"{other}: its probes met the object's face and it has not rolled yet: it rolls there "
                           f"before the exploration stops ({out.stopped})")
                emit({"type": "event", "kind": "stop_deferred", "message": message})
                say(message)
                aim, out.stopped = None, None
            if out.stopped is not None:
                emit(out.stopped.event("stopped_early"))
                say(f"stopping after {len(usable)} usable touches: {out.stopped}")
                break
    ended = None  # why the rolls ended undecided, when not for the budget
    if undecided is None and out.stopped is None and cleared():
        # the rolls ended (no orientation left, fingers retired) with fewer usable touches than the answer is
        # asked on in the rounds: what would help is sought as for a spent budget (X-series block 17 of
        # bench_explore --finite 20 --anywhere --seed 227: 2 usable rolls, parabola and circle, no move named)
        try:
            recognition, why = decide(recognize_touches, cleared(), settings, ticks, refeel)
        except InputError:  # too few for any class: the final answer says so
            why = None
        if why is not None:
            undecided = (recognition, why, cleared())
            ended = f"no finger has a roll left to make after {len(cleared())} usable touches"
    if undecided is not None and out.stopped is None and cleared():  # the budget ran out undecided: what to do
        recognition, why, usable = undecided
        wanted = anywhere(usable)
        if wanted is not None:  # a place past where the rolls left the curved part is no place to touch
            wanted = past_felt_end(recognition, usable, wanted, reach, settings.roll_span_rad, limits,
                                   clearing_corners(out.touches),
                                   lambda on: recognize_anywhere(usable, reach=on).next_touch)
        also = unrolled_places(cfg, out, recognition)
        one_side = bool(also) and beyond_resolution(recognize_touches, recognition, why, usable, settings.touches)
        felt_side = felt_side_places(recognition, usable, clearing_corners(out.touches)) if one_side else ()
        out.stopped = budget_advice(recognition, why, sample_positions(usable), reach, settings.touches,
                                    wanted, also, one_side, ended, felt_side)
        emit(out.stopped.event("budget_spent" if ended is None else "stopped_early"))
        say(f"{out.stopped}")
    if not cleared():  # no curved part felt (clear of the corners): the faces, by flat presses
        before = dict(out.time_s)
        flat_presses(jaw, settings, model, out, recognize_touches, emit, say, index, pressed, no_curve)
        for rolls, presses in (("touches", "presses"), ("touch_transits", "press_transits")):  # booked apart
            moved = out.time_s[rolls] - before[rolls]
            out.time_s[rolls] -= moved
            out.time_s[presses] += moved
    here = {f.name: float(jaw.pad_line(jaw.last_state, f.name).psi) for f in cfg.fingers}
    t_retreat = jaw.robot_time()
    run_together(jaw, {name: transit_or_problem(jaw, name, model, psi) for name, psi in here.items()})  # to the edge
    out.time_s["retreat"] = jaw.robot_time() - t_retreat
    if not model.psi.size:
        message = (f"no probe of {len(out.probes)} found a contact on a pad's face: within reach of the pads the "
                   f"object offers no boundary they can roll on (flat, concave, or felt only by a pad end)")
        emit({"type": "event", "kind": "no_face_contact", "message": message})
        say(message)
    closing_answer(cfg, out, cleared, recognize_touches, settings, emit, say, felt_before)
    out.robot_time_s = jaw.robot_time() - t0
    return out


def closing_answer(cfg, out: Exploration, cleared: Callable[[], list[FeltTouch]], recognize_touches: RecognizeTouches,
                   settings: ExploreSettings, emit: Callable[[dict], None], say: Callable[[str], None],
                   felt_before: FeltBefore | None = None) -> None:
    """The exploration's answer into ``out.recognition`` (with ``out.used``, and ``out.stopped``
    when it names one): :func:`tactile_jaw.decide.final_answer` on the usable touches
    (``cleared()``), else the refusal already made (a curved part felt, tactile_jaw.flat_phase)
    or the one for too few usable touches, which names what would help (a face or corner the touches met and its
    move, :func:`short_face_stop`, else :func:`unusable_refusal`'s stop: X line 8 of held-out finite 541 on 657c034,
    1 of its 2 usable touches clear of the corners, was refused with no stop, and the command's advice fell back
    to "no class of the scene fits"); whichever it is, its reason ends with the jaw's
    calibration note (:func:`tactile_jaw.decide.noted`): the flat phase's "no usable touch"
    refusals of held-out seed 313 (P lines 5, 8, 10) did not carry it. A `line` after a move
    whose run before felt curvature (``felt_before``, tactile_jaw.felt_before.not_a_line) is
    refused, naming no move; a `line` from one face's flat presses says which face and the stretch
    felt (tactile_jaw.flat.face_line) (X cubicals 104, 111, 112, 119 and hyperbola 93 of bench_explore
    --finite 20 --anywhere --follow --seed 617 were answered line after their moves)."""
    if out.used:
        usable = cleared()
        try:  # the answer on every usable touch, a refusal unless decisive
            out.recognition = final_answer(recognize_touches, usable, settings, out.stopped, jaw_ticks_per_rev(cfg),
                                           partial(feel, cfg), emit)
            out.answers.append(out.recognition.cls)
        except InputError as exc:
            emit({"type": "event", "kind": "too_few_touches", "message": str(exc)})
            if len(usable) < len(out.used):  # an earlier round's answer was on touches since cleared
                out.recognition = too_few_clear(usable, len(out.used), exc)
                if out.stopped is None:  # what would help: a face or corner the touches met, else unusable_refusal's
                    out.stopped = short_face_stop(cfg, settings, out, head=f"only {len(usable)} usable touch(es) "
                                                                           f"clear of the corners")
                    out.stopped = unusable_refusal(out)[1] if out.stopped is None else out.stopped
                    emit(out.stopped.event("stopped_early"))
                    say(f"{out.recognition.reason}; {out.stopped}")
        out.used = usable
    if out.recognition is None:  # no touch was usable: say what they met, and what would help or why no move is named
        stopped = out.stopped
        out.recognition, out.stopped = unusable_refusal(out)
        if stopped is None:
            emit(out.stopped.event("stopped_early"))
        say(f"{out.recognition.reason}; {out.stopped}")
    out.recognition = face_line(out.recognition, out.used)
    refused = not_a_line(out.recognition, felt_before)
    if refused is not out.recognition:
        out.recognition, out.stopped = refused, Stop(MOVED_OFF_CURVE)
        emit(out.stopped.event("stopped_early"))
        say(f"{out.recognition.reason}; {out.stopped}")
    out.recognition = replace(out.recognition, reason=noted(out.recognition.reason, states_calibration(cfg)))
