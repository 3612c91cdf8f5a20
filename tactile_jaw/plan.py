"""Where to touch: the object model built from felt pad lines, and the pad orientations
of probes and rolling touches.

Probes (guarded approaches with a short roll from several pad orientations,
:func:`probe_psis`) first locate the boundary; the pad lines of face contacts
(:func:`probe_face_contact`) sample the object's support function, which
:class:`ObjectModel` fits locally to predict tangents. A rolling touch goes to a feasible
orientation (:func:`feasible`) farthest from the finger's earlier touches
(:func:`choose_psi`). docs/exploration.md.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from hand_driver import kinematics as kin
from hand_driver.cycle import LIMIT_MARGIN_RAD
from hand_driver.motion import contact_on_pad, roll_angles
from tactile_common.errors import InputError
from tactile_jaw.pipeline import FeltTouch
from tactile_jaw.settings import ExploreSettings

#: a rolling touch starts this far (mm) outside the predicted tangent line
APPROACH_MARGIN_MM = 10.0
#: a rolling touch's approach runs faster (hand_driver.motion.FREE_SPEED_FACTOR, still
#: guarded) until this far (mm) outside the predicted tangent line; a probe's, whose
#: prediction is an extrapolation from other normals, until APPROACH_MARGIN_MM outside it
FREE_MARGIN_MM = 3.0
#: a planned roll's lines must be reachable this far (mm) beyond the predicted tangent: a
#: guarded approach's goal leads the measured pad by at most two approach steps (1 mm with
#: config/jaw.yaml), so a contact on the line d needs d + 1 mm within the joints' reach, plus
#: 0.5 mm for the prediction's error (hand_driver.motion.guarded_approach). Was 4 mm (what a
#: re-approach may travel, not what it reaches before it stops), which ruled out the last
#: ~10 deg of a finger at full stretch: the hyperbola example's arm toward the palm (left
#: pad normals -65...-56 deg; tests/tactile_jaw/test_plan_reach.py)
PLAN_OVERSHOOT_MM = 1.5
#: rolling touches are planned at pad normals within ± CANDIDATE_SPREAD_DEG of the pad's
#: normal at zero joint angles, every CANDIDATE_STEP_DEG
CANDIDATE_SPREAD_DEG = 75.0
CANDIDATE_STEP_DEG = 2.5
#: planning keeps the predicted contact this fraction of the pad's length from either end
PLAN_PAD_MARGIN = 0.1
#: probes: pad normals (deg) relative to the pad's normal at zero joint angles, samples
#: and span (deg) of each probe's short roll, and the fraction of the pad's length from
#: either end where its contact must lie to count as a face contact
PROBE_OFFSETS_DEG = (-60.0, -40.0, -20.0, 0.0, 20.0, 40.0, 60.0)
PROBE_SAMPLES = 4
PROBE_SPAN_DEG = 6.0
PROBE_PAD_MARGIN = 0.1
#: a finger stops probing once its face contacts span this many degrees of pad normal
#: (20: robot time on the default, circle and ellipse scenes 45.9/68.7/41.3 s against
#: 49.5/70.1/52.0 s with 40, same answers; the touches' own lines extend the model)
PROBE_ENOUGH_DEG = 20.0
#: a finger with a single face contact after the grid probes again this far (deg) either side
PROBE_REFINE_DEG = 10.0
#: the object model predicts a tangent for ψ from felt lines within MODEL_REACH_DEG that
#: span at least MODEL_MIN_SPAN_DEG, the nearest at most MODEL_EXTRAPOLATE_DEG away
MODEL_REACH_DEG = 45.0
MODEL_MIN_SPAN_DEG = 3.0
MODEL_EXTRAPOLATE_DEG = 30.0
#: ... weighting each line by 1 / (1 + (Δψ / MODEL_WEIGHT_DEG)²), Δψ its distance from ψ
MODEL_WEIGHT_DEG = 10.0


class ObjectModel:
    """What the pads felt (module docstring): the in-contact pad lines ψ, d of face
    contacts. The object's support function d(ψ) (the first line of normal ψ that meets
    it) is fitted near ψ by a quadratic; its tangent point is d·n(ψ) + d'(ψ)·n'(ψ)."""

    def __init__(self, center, workspace_radius: float):
        self.workspace_center = np.asarray(center, dtype=float)
        self.workspace_radius = workspace_radius
        self.psi = np.zeros(0)
        self.d = np.zeros(0)

    def add(self, psi, d) -> None:
        """Add felt pad lines (face contacts only)."""
        self.psi = np.concatenate([self.psi, np.atleast_1d(np.asarray(psi, dtype=float))])
        self.d = np.concatenate([self.d, np.atleast_1d(np.asarray(d, dtype=float))])

    def tangent(self, psi: float) -> tuple[float, np.ndarray] | None:
        """The predicted pad line offset d and contact point for a pad with normal ψ, or
        None where nothing was felt within ``MODEL_REACH_DEG`` or the lines there span
        less than ``MODEL_MIN_SPAN_DEG``."""
        delta = np.remainder(self.psi - psi + math.pi, 2 * math.pi) - math.pi
        near = np.abs(delta) <= math.radians(MODEL_REACH_DEG)
        if np.count_nonzero(near) < 2 or np.ptp(delta[near]) < math.radians(MODEL_MIN_SPAN_DEG):
            return None
        if np.min(np.abs(delta[near])) > math.radians(MODEL_EXTRAPOLATE_DEG):
            return None
        deg = 2 if np.ptp(delta[near]) >= math.radians(2 * MODEL_MIN_SPAN_DEG) and np.count_nonzero(near) >= 3 else 1
        weight = 1.0 / (1.0 + (delta[near] / math.radians(MODEL_WEIGHT_DEG)) ** 2)
        coef = np.polynomial.polynomial.polyfit(delta[near], self.d[near], deg, w=weight)
        n = kin.unit(psi)
        dn = np.array([-math.sin(psi), math.cos(psi)])
        return float(coef[0]), coef[0] * n + coef[1] * dn

    def edge(self, psi):
        """Offset of the line with normal ψ tangent to the workspace disk (outside it): a float
        for a float ψ, an array for an array."""
        out = line_offset(psi, self.workspace_center) - self.workspace_radius
        return float(out) if np.ndim(out) == 0 else out


def line_offset(psi, p):
    """n(ψ)·p, the offset d of the line of normal ψ through the point(s) ``p`` (..., 2), ψ
    broadcast against p's leading axes: the same arithmetic for one line as for many."""
    p = np.asarray(p, dtype=float)
    return np.cos(psi) * p[..., 0] + np.sin(psi) * p[..., 1]


def nominal_psi(finger) -> float:
    """The pad's outward normal angle at zero joint angles."""
    return finger.base.angle + finger.pad.side_sign * math.pi / 2


#: a rolled arc's radius of curvature is at most this (mm): a straight stretch's contact runs
#: off any pad over a roll, and this keeps the closed form finite
ARC_RHO_MAX_MM = 1e6


@dataclass(frozen=True)
class RolledArc:
    """A touch aimed at the boundary point (x, y) mm with pad normal ``psi`` (rad) on a curve of
    radius of curvature ``rho`` (mm) there, changing by ``drho`` (mm/rad) per radian of pad normal
    (ρ' = −κ_s/(|κ|κ²), κ and κ_s of eqs. 3–7 at the place: :func:`rolled_arc`). Over a roll
    the contact travels along the curve (tactile_jaw.choose.JawReach.finger): a pad on a
    curve of ρ ~43 mm rolled 18° about a fixed aim met it ~6.8 mm along the pad from where
    a fixed contact would be (calibrated cubical 54 of seed 281)."""

    x: float | np.ndarray
    y: float | np.ndarray
    psi: float | np.ndarray
    rho: float | np.ndarray
    drho: float | np.ndarray = 0.0

    def contact(self, psi) -> np.ndarray:
        """The contact for pad normal ψ: p(ψ) = p₀ − ∫ρ(u) n'(u) du from ψ₀ (n the pad's normal,
        pointing into the object, n' its derivative; ρ(u) = ρ₀ + ρ'(u − ψ₀)), in closed form
        p₀ − ρ₀(n − n₀) − ρ'(Δ n + n' − n'₀), Δ = ψ − ψ₀ taken to [−π, π]. Fields and ψ may be
        arrays of one shape S (many arcs at once): (*S, 2). ρ = ρ' = 0 is a contact that stays at
        (x, y), exactly (a touch aimed at a point)."""
        psi, psi0 = np.asarray(psi, dtype=float), np.asarray(self.psi, dtype=float)
        delta = psi - psi0
        # math.remainder's rounding: Δ itself where |Δ| < π
        delta = delta - 2 * math.pi * np.rint(delta / (2 * math.pi))
        c, s, c0, s0 = np.cos(psi), np.sin(psi), np.cos(psi0), np.sin(psi0)
        # n = (cos, sin), n' = (−sin, cos), component by component
        x = self.x - self.rho * (c - c0) - self.drho * (delta * c + -s - -s0)
        y = self.y - self.rho * (s - s0) - self.drho * (delta * s + c - c0)
        return np.stack([x, y], axis=-1)

    def at(self, i) -> "RolledArc":
        """The arcs ``i`` (an index array) of an arc whose fields are arrays of one shape (a
        float field: the same for every arc)."""
        fields = (np.asarray(v, dtype=float) for v in (self.x, self.y, self.psi, self.rho, self.drho))
        return RolledArc(*(v[i] if v.ndim else np.full(np.shape(i), float(v)) for v in fields))


def rolled_arc(x: float, y: float, psi: float, kappa: float, kappa_s: float) -> RolledArc:
    """The :class:`RolledArc` at (x, y), pad normal ψ, of a curve with curvature κ and κ_s there
    (either sign: the pad rolls on the side the solid is convex; ρ = 1/|κ| at most
    ``ARC_RHO_MAX_MM``, ρ' = dρ/dψ = (dρ/ds)/(dψ/ds) = −κ_s/(|κ|κ²))."""
    if abs(kappa) < 1.0 / ARC_RHO_MAX_MM:
        return RolledArc(x, y, psi, ARC_RHO_MAX_MM)
    return RolledArc(x, y, psi, 1.0 / abs(kappa), -kappa_s / (abs(kappa) * kappa * kappa))


def predicted_tangent(model: ObjectModel, psi: float, aim=None) -> tuple[float, np.ndarray] | None:
    """The pad line offset d and contact point predicted for normal ψ: the object model's
    (:meth:`ObjectModel.tangent`), or, for a touch aimed at a boundary point ``aim`` (the
    recognizer's ``next_touch``, from the curve it fitted to every touch, which knows more
    there than the model's extrapolation), the line of normal ψ through that point (the
    true tangent over a roll of ±Δψ about it is at most ρ·Δψ²/2 nearer), or, for a
    :class:`RolledArc`, through the contact the arc has at ψ (the contact travels over a roll)."""
    if aim is None:
        return model.tangent(psi)
    p = aim.contact(psi) if isinstance(aim, RolledArc) else np.asarray(aim, dtype=float)
    return float(line_offset(psi, p)), p


def retreat_offset(finger, model: ObjectModel, psi: float, aim=None) -> float | None:
    """The farthest-out pad line of normal ψ that the joints reach and that keeps clear of
    the object: the workspace edge's line where reachable, else the first reachable line
    inward in 1 mm steps, at most up to ``APPROACH_MARGIN_MM`` outside the predicted
    tangent (:func:`predicted_tangent`; none inward where nothing is predicted); None if no such line exists. A pad
    turned far from its zero-angle normal cannot stretch out to the workspace edge, yet may
    roll nearer the object (the far arms of open curves)."""
    d = model.edge(psi)
    predicted = predicted_tangent(model, psi, aim)
    limit = d if predicted is None else max(d, predicted[0] - APPROACH_MARGIN_MM)
    out = float(retreat_lines(finger, np.array([psi], float), np.array([d]), np.array([limit]))[0])
    return None if math.isnan(out) else out


def _reached(finger, q: np.ndarray, real: np.ndarray) -> np.ndarray:
    """Whether each line has a joint solution (kinematics.ik_line_angles' q, real) within the
    limits less ``LIMIT_MARGIN_RAD`` (kinematics.ik_line's rule): (2, *S) of the two solutions."""
    return real & kin.within_limits(finger.joints, q, LIMIT_MARGIN_RAD)


def retreat_lines(finger, psi: np.ndarray, start: np.ndarray, limit: np.ndarray) -> np.ndarray:
    """:func:`retreat_offset`'s line for every pad normal ψ at once (1-D arrays): the first line
    from ``start`` (the workspace edge's) inward in 1 mm steps, no farther in than ``limit``,
    that the joints reach; NaN where none is."""
    out = np.full(psi.shape, np.nan)
    if not psi.size:
        return out
    step = np.array(start, dtype=float)
    todo = np.flatnonzero(step <= limit + 1e-9)
    while todo.size:
        hit = np.any(_reached(finger, *kin.ik_line_angles(finger, psi[todo], step[todo])), axis=0)
        out[todo[hit]] = step[todo[hit]]
        todo = todo[~hit]
        step[todo] += 1.0
        todo = todo[step[todo] <= limit[todo] + 1e-9]
    return out


#: a transit between rolling touches keeps APPROACH_MARGIN_MM outside the tangent the felt
#: lines predict (instead of going out to the workspace edge) only at pad normals within the
#: felt lines' span widened by this much (deg) each side, where the prediction interpolates
HUG_EXTEND_DEG = 10.0


def hug_offset(finger, model: ObjectModel, psi: float) -> float | None:
    """The pad line of normal ψ ``APPROACH_MARGIN_MM`` outside the tangent the felt lines
    predict (:meth:`ObjectModel.tangent`, never an aimed point's line, which is no support
    line away from the aim), where ψ lies within the felt span widened by ``HUG_EXTEND_DEG``
    and the joints reach it; else None. A rolling touch's first move already goes to such a
    line unguarded (tactile_jaw.explore), so a transit through them trusts the model no more."""
    if not model.psi.size:
        return None
    lo, hi = float(model.psi.min()), float(model.psi.max())
    mid = 0.5 * (lo + hi)
    off = abs(math.remainder(psi - mid, 2 * math.pi))
    if off > 0.5 * (hi - lo) + math.radians(HUG_EXTEND_DEG):
        return None
    predicted = model.tangent(psi)
    if predicted is None:
        return None
    d = predicted[0] - APPROACH_MARGIN_MM
    try:
        kin.ik_line(finger, psi, d, margin_rad=LIMIT_MARGIN_RAD)
    except kin.Unreachable:
        return None
    return d


def clear_offset(finger, model: ObjectModel, psi: float, d: float | None) -> float | None:
    """A transit's line of normal ψ: ``d``, or farther out where ``d`` lies less than
    ``APPROACH_MARGIN_MM`` outside the tangent the felt lines predict (:meth:`ObjectModel.tangent`;
    an object reaching to within that of the workspace edge) and the joints reach the line that
    far out. Each servo runs its own trapezoidal profile, so on a turn the joints start alike and
    the pad first slides along its normal: from the workspace edge 5.7 mm outside a circle's
    tangent the right pad of random X-series circle 32 of bench_explore --finite 20 --anywhere
    --seed 139 slid back onto the circle at every transit and stayed wedged there (three rolls
    without contact; refused)."""
    predicted = None if d is None else model.tangent(psi)
    if predicted is None or d <= predicted[0] - APPROACH_MARGIN_MM:
        return d
    try:
        kin.ik_line(finger, psi, predicted[0] - APPROACH_MARGIN_MM, margin_rad=LIMIT_MARGIN_RAD)
    except kin.Unreachable:
        return d
    return predicted[0] - APPROACH_MARGIN_MM


def reaches_lines(finger, model: ObjectModel, psi: np.ndarray, d: np.ndarray, p: np.ndarray,
                  pad_margin: float = PLAN_PAD_MARGIN) -> np.ndarray:
    """The reach rule of one roll orientation, for every line at once (1-D arrays ψ, d; p
    (m, 2)): the pad line n(ψ)·x = d through the predicted contact p has a joint solution within
    the limits less ``LIMIT_MARGIN_RAD`` with p on the pad (kinematics.ik_line with its contact),
    and one with p ``pad_margin`` of the pad's length from either end; the line
    ``PLAN_OVERSHOOT_MM`` beyond has one; and a line to retreat to (:func:`retreat_offset`'s,
    from the workspace edge's inward up to ``APPROACH_MARGIN_MM`` outside d, :func:`retreat_lines`)
    has one. :func:`feasible` asks it of one line, the jaw's reach of many
    (tactile_jaw.choose.JawReach): one rule, the same arithmetic."""
    m, length = psi.size, finger.pad.length_mm
    edge = model.edge(psi)
    # the line, the overshoot line and the workspace edge's line, in one pass
    q, real = kin.ik_line_angles(finger, np.concatenate([psi, psi, psi]),
                                 np.concatenate([d, d + PLAN_OVERSHOOT_MM, edge]))
    within = _reached(finger, q, real)
    u = kin.finger_pad_line(finger, q[:, :m]).pad_coordinate(p)
    on = within[:, :m]
    ok = (np.any(on & (u >= 0.0) & (u <= length), axis=0)
          & np.any(on & (u >= pad_margin * length) & (u <= (1 - pad_margin) * length), axis=0)
          & np.any(within[:, m:2 * m], axis=0))
    i = np.flatnonzero(ok & ~np.any(within[:, 2 * m:], axis=0))  # the edge's line out of reach: 1 mm steps inward
    ok[i] = ~np.isnan(retreat_lines(finger, psi[i], edge[i] + 1.0, np.maximum(edge[i], d[i] - APPROACH_MARGIN_MM)))
    return ok


def roll_ends(psi: np.ndarray, settings: ExploreSettings) -> np.ndarray:
    """Both end orientations of the rolls centred on every pad normal of ``psi`` (1-D): every
    roll's first (hand_driver.motion.roll_angles' first), then every roll's last, (2·m,)."""
    first, last = roll_angles(0.0, settings.roll_span_rad, settings.samples_per_touch)[[0, -1]]
    return np.concatenate([psi + first, psi + last])


def feasible(finger, model: ObjectModel, psi: float, settings: ExploreSettings, aim=None,
             pad_margin: float = PLAN_PAD_MARGIN) -> bool:
    """Every roll orientation around ψ has a predicted tangent (:func:`predicted_tangent`)
    that puts the pad on it, with the predicted contact on the pad, inside the joint
    limits, and also ``PLAN_OVERSHOOT_MM`` beyond it; a line to retreat to is reachable
    (:func:`retreat_offset`). The predicted contact keeps ``pad_margin`` of the pad's length
    from either end (:func:`reaches_lines`; with an ``aim``, :func:`feasible_arcs` of one arc)."""
    if aim is None:
        return bool(feasible_many(finger, model, np.array([psi], float), settings, pad_margin)[0])
    arc = aim if isinstance(aim, RolledArc) else RolledArc(float(aim[0]), float(aim[1]), psi, 0.0)
    return bool(feasible_arcs(finger, model, np.array([psi], float), arc.at(np.array([0])), settings, pad_margin)[0])


def feasible_many(finger, model: ObjectModel, psi: np.ndarray, settings: ExploreSettings,
                  pad_margin: float = PLAN_PAD_MARGIN) -> np.ndarray:
    """:func:`feasible` without an aim for rolls centred on every pad normal of ``psi`` (1-D) at
    once: the object model's tangent (:meth:`ObjectModel.tangent`) at both ends of each roll,
    :func:`reaches_lines` of all of them in one pass."""
    ends = roll_ends(psi, settings)
    predicted = [model.tangent(float(a)) for a in ends]
    known = np.array([t is not None for t in predicted], bool)
    ok = known.copy()
    i = np.flatnonzero(known)
    if i.size:
        d = np.array([predicted[k][0] for k in i])
        p = np.array([predicted[k][1] for k in i], float).reshape(-1, 2)
        ok[i] = reaches_lines(finger, model, ends[i], d, p, pad_margin)
    return np.all(ok.reshape(2, -1), axis=0)


def feasible_arcs(finger, model: ObjectModel, psi: np.ndarray, arc: RolledArc, settings: ExploreSettings,
                  pad_margin: float = PLAN_PAD_MARGIN) -> np.ndarray:
    """:func:`feasible` for rolls centred on every pad normal of ``psi`` (1-D) at once, each
    aimed at its arc of ``arc`` (fields arrays of psi's length, or floats: the contact at either
    end of the roll where the arc has it, :meth:`RolledArc.contact`; ρ = 0: at (x, y))."""
    a = roll_ends(psi, settings)
    both = np.concatenate([np.arange(psi.size)] * 2)
    p = arc.at(both).contact(a)
    return np.all(reaches_lines(finger, model, a, line_offset(a, p), p, pad_margin).reshape(2, -1), axis=0)


def within_curve(psi: float, span: float, limits) -> bool:
    """Whether a roll of ``span`` (rad) about ψ keeps short of every limit of the curved part
    (``limits``: (ψ_end, side) pairs, tactile_jaw.explore.curve_limits: the roll's ψ must stay
    below ψ_end for side +1, above it for side −1)."""
    return all(side * math.remainder(end - psi, 2 * math.pi) > 0.5 * span for end, side in limits)


def within_cone(psi: float, span: float, cones) -> bool:
    """Whether a roll of ``span`` (rad) about ψ lies wholly within one of the ``cones`` ((ψ_lo,
    ψ_hi) pairs, ψ_lo ≤ ψ_hi, an arc under 2π: the pad normals at which the finger's support
    lines passed through one corner, tactile_jaw.explore.corner_cones)."""
    for lo, hi in cones:
        start = math.remainder(psi - 0.5 * span - lo, 2 * math.pi)  # from lo to the roll's first orientation
        if 0.0 <= start and start + span <= hi - lo:
            return True
    return False


def passes_end(psi: float, span: float, ends) -> bool:
    """Whether a roll of ``span`` (rad) about ψ turns the pad through both pad normals of one
    of the ``ends`` ((ψ_a, ψ_b) pairs, rad: the last two samples of a touch that stopped with a
    pad end on the object, tactile_jaw.explore.pad_end_normals). With its two joints a finger at
    a given pad normal meets a convex object at one place on its pad, so such a roll meets that
    pad end again. Both normals, not the last alone: a polygon's contact jumps along the pad
    where the pad normal passes a face's normal, and P lines 15 and 18 of bench_explore --finite
    20 --anywhere --seed 499 rolled from between a probe's pair (87…89°, 77…79°, crossing 0.3
    and 0.2 mm along the pad) across a closing segment, 16.4 and 2.1 mm along it."""
    lo = psi - 0.5 * span
    return any(0.0 <= math.remainder(a - lo, 2 * math.pi) <= span and 0.0 <= math.remainder(b - lo, 2 * math.pi) <= span
               for a, b in ends)


def choose_psi(finger, model: ObjectModel, settings: ExploreSettings, used: list[float],
               limits=(), cones=(), ends=()) -> float | None:
    """Next pad orientation for ``finger`` (module docstring), None if none is feasible; a
    roll reaches no pad orientation beyond ``limits`` (:func:`within_curve`), where the
    finger's earlier rolls left the curved part, and none lies wholly within one of the
    ``cones`` (:func:`within_cone`): a convex boundary point's normals form one arc, so a roll
    between two normals at which the pad turned about one corner turns about it again and
    keeps none of its samples (tactile_jaw.pipeline.clear_of_corners). Of the feasible ones,
    the middle one first, else the farthest from the ``used`` ones (none within a candidate
    step of one); in that order, the first that turns through none of the ``ends``
    (:func:`passes_end`: it would meet a pad end again), so that every other choice stays
    what it was without them (leaving them out of the candidates moved the middle one: X line
    10 of seed 499, 39.6 → 45.1 s)."""
    nominal = nominal_psi(finger)
    offsets = np.arange(-CANDIDATE_SPREAD_DEG, CANDIDATE_SPREAD_DEG + 1e-9, CANDIDATE_STEP_DEG)
    cands = [nominal + math.radians(o) for o in offsets]
    cands = [a for a in cands if within_curve(a, settings.roll_span_rad, limits)
             and not within_cone(a, settings.roll_span_rad, cones)]
    ok = [a for a, f in zip(cands, feasible_many(finger, model, np.array(cands, float), settings)) if f]
    if not used:
        order = sorted(range(len(ok)), key=lambda i: abs(i - len(ok) // 2))
    else:  # every feasible orientation a step from the used ones, the farthest first
        gap = [min(abs(a - u) for u in used) for a in ok]
        order = [i for i in sorted(range(len(ok)), key=lambda i: -gap[i])
                 if gap[i] >= math.radians(CANDIDATE_STEP_DEG) - 1e-9]
    return next((ok[i] for i in order if not passes_end(ok[i], settings.roll_span_rad, ends)), None)


def open_pose(config) -> np.ndarray:
    """Joint angles (rad, config order) of the opened jaw: every pad at its normal at zero
    joint angles, on the line tangent to the workspace disk (config ``workspace``) from
    outside; where an exploration starts its probes."""
    ws = config.workspace
    model = ObjectModel(ws.center_mm, ws.radius_mm)
    out = []
    for f in config.fingers:
        psi = nominal_psi(f)
        out.append(kin.ik_line(f, psi, model.edge(psi), margin_rad=LIMIT_MARGIN_RAD))
    return np.concatenate(out)


#: the stretch a probe's pad swept free is taken between its poses this far apart (mm) along
#: its approach (:func:`free_strips`): each step's overlap loses what the pad slid in it
#: (~0.5 mm at each end on the P-series jaw's probes)
FREE_STEP_MM = 1.0

#: how far (mm) from the workspace a refusal still names the object's nearest point
_NEAREST_SEARCH_MM = 10_000.0


def check_in_workspace(obj, config, source: str) -> None:
    """Refuse (one line, before any motion) a scene object none of whose boundary lies in
    the jaw's workspace disk (config ``workspace``): the probes would sweep that disk and
    feel nothing. The line says where the workspace is and where the object's nearest point
    is; the error names ``object.pose`` (tactile_common.yamlfile adds its line)."""
    from hand_driver.sim.boundary import Boundary

    (cx, cy), r = config.workspace.center_mm, config.workspace.radius_mm
    boundary = Boundary(obj)
    if len(boundary.points((cx, cy), r)):
        return
    near = boundary.points((cx, cy), _NEAREST_SEARCH_MM)
    where = "more than 10 m away"
    if len(near):
        d = np.hypot(near[:, 0] - cx, near[:, 1] - cy)
        k = int(np.argmin(d))
        where = f"nearest at ({near[k, 0]:.1f}, {near[k, 1]:.1f}) mm, {d[k] - r:.1f} mm outside it"
    raise InputError(f"{source}: object.pose: the object is outside the jaw's workspace, the disk of radius {r:g} mm "
                     f"about ({cx:g}, {cy:g}) mm in the hand frame (config workspace) ({where}); place it so that its "
                     f"boundary crosses that disk")


def probe_psis(finger, model: ObjectModel) -> list[float]:
    """The probe orientations of a finger: its pad's normal at zero joint angles ±
    ``PROBE_OFFSETS_DEG`` whose workspace-edge line is reachable, nearest that normal first."""
    nominal = nominal_psi(finger)
    out = []
    for o in sorted(PROBE_OFFSETS_DEG, key=abs):
        a = nominal + math.radians(o)
        try:
            kin.ik_line(finger, a, model.edge(a), margin_rad=LIMIT_MARGIN_RAD)
        except kin.Unreachable:
            continue
        out.append(a)
    return out


def probe_face_contact(config, felt: FeltTouch) -> float | None:
    """Where a probe touched along the pad (mm from its proximal end, at its middle sample)
    if it took all ``PROBE_SAMPLES`` and the point its pad lines turned about lies
    ``PROBE_PAD_MARGIN`` of the pad's length from either end (a pad end resting on the
    object turns the pad about that end); else None. The point is the envelope of constant
    radius of curvature (degree 2, kinematics.touch_from_pad_lines), whose uncertain radius
    (~20 mm over 6°) barely moves the middle sample's point. A probe's short roll cannot
    measure the arc length (the pipeline's test for rolling touches): its pad lines, true to
    ±0.05 mm, make the radius of a cubic envelope over 6° uncertain by ~100 mm, and on the
    circle example 8 of 12 face contacts failed that test."""
    touch = felt.touch
    if touch.outcome != "ok" or len(touch.samples) < PROBE_SAMPLES or felt.lines is None:
        return None
    lines = felt.lines
    try:
        c = kin.touch_from_pad_lines(lines.psi, lines.d, degree=2)
    except InputError:
        return None
    taken = np.empty((c.order.size, 2))
    taken[c.order] = np.stack([c.x, c.y], axis=-1)
    u = lines.pad_coordinate(taken)
    length = config.finger(felt.finger).pad.length_mm
    if np.any(u < PROBE_PAD_MARGIN * length) or np.any(u > (1 - PROBE_PAD_MARGIN) * length):
        return None
    return float(u[len(u) // 2])


def _pad_extent(line) -> tuple[float, float]:
    """The pad's ends' coordinates along ``line``'s tangent (−sin ψ, cos ψ), smaller first."""
    t = np.array([-math.sin(float(line.psi)), math.cos(float(line.psi))])
    u = sorted((float(t @ np.asarray(line.proximal)), float(t @ np.asarray(line.distal))))
    return u[0], u[1]


def free_strips(config, probes) -> np.ndarray:
    """Where the probes' pads swept and met nothing (k × 5 rows ψ rad, u_lo, u_hi, d_lo, d_hi
    mm: the points p with d_lo ≤ n(ψ)·p ≤ d_hi and u_lo ≤ t(ψ)·p ≤ u_hi, t = (−sin ψ, cos ψ)).
    Each probe's first approach (tactile_jaw.probing) ran from the workspace edge's line
    along its normal to its first contact, or without one across the disk: the rectangle
    between, across the stretch its pad covered at both ends, was free of the object, and
    so was the finger's own body behind the pad's face at the edge (the pad's offset from
    its links; for the nominal probe, the opened jaw's place). What a move must not carry
    unfelt object into: the opened pads' strips (:func:`opened_strips`)."""
    ws = config.workspace
    model = ObjectModel(ws.center_mm, ws.radius_mm)
    rows = []
    for felt in probes:
        touch = felt.touch
        if not touch.samples and touch.outcome != "no_contact":
            continue  # unreachable, blocked: where its pad went is not known
        finger = config.finger(felt.finger)
        psi = float(touch.samples[0].psi) if touch.samples else float(
            roll_angles(touch.psi_center, math.radians(PROBE_SPAN_DEG), PROBE_SAMPLES)[0])
        edge = model.edge(psi)
        far = touch.samples[0].d if touch.samples else edge + 2.0 * model.workspace_radius
        # the pad slides along its line as the joints carry it in: the swept stretch is taken
        # between pad poses every FREE_STEP_MM of the approach, each the overlap of two
        depths = np.linspace(edge, far, max(2, math.ceil((far - edge) / FREE_STEP_MM) + 1))
        extents = []
        for d in depths:
            try:
                extents.append(_pad_extent(kin.finger_pad_line(
                    finger, kin.ik_line(finger, psi, float(d), margin_rad=LIMIT_MARGIN_RAD))))
            except kin.Unreachable:
                break
        for i in range(len(extents) - 1):
            lo, hi = max(extents[i][0], extents[i + 1][0]), min(extents[i][1], extents[i + 1][1])
            if hi > lo:
                rows.append((psi, lo, hi, edge - finger.pad.offset_mm if i == 0 else depths[i], depths[i + 1]))
    return np.array(rows, float).reshape(-1, 5)


def opened_strips(config, depth_mm: float, behind_mm: float = 0.0) -> np.ndarray:
    """The opened jaw's pads (:func:`open_pose`) as :func:`free_strips` rows: each pad's face
    from ``behind_mm`` behind it to ``depth_mm`` in front."""
    ws = config.workspace
    model = ObjectModel(ws.center_mm, ws.radius_mm)
    rows = []
    for finger in config.fingers:
        psi = nominal_psi(finger)
        edge = model.edge(psi)
        line = kin.finger_pad_line(finger, kin.ik_line(finger, psi, edge, margin_rad=LIMIT_MARGIN_RAD))
        rows.append((psi, *_pad_extent(line), edge - behind_mm, edge + depth_mm))
    return np.array(rows, float)


def rested_ends(config, probes) -> np.ndarray:
    """The pad ends probes rested on (k × 4 rows: the end's point x, y mm and the unit
    direction along the pad beyond it): a probe whose last contact (the crossing of its last
    two pad lines) lies within ``PROBE_PAD_MARGIN`` of the pad's length from an end, or beyond
    it, met the object with that end, and the object goes on past it where no pad swept
    (calibrated random block 1 of bench_explore --finite 10 --anywhere --seed 239: the right
    pad's proximal end on the block's corner, its far corner 14 mm beyond, behind the pad's face)."""
    rows = []
    for felt in probes:
        samples = felt.touch.samples
        if len(samples) < 2:
            continue
        _, u = contact_on_pad(samples)
        length = config.finger(felt.finger).pad.length_mm
        if u is None or PROBE_PAD_MARGIN * length <= u <= (1.0 - PROBE_PAD_MARGIN) * length:
            continue
        line = samples[-1].line
        end, other = (line.proximal, line.distal) if u < 0.5 * length else (line.distal, line.proximal)
        beyond = np.asarray(end, float) - np.asarray(other, float)
        rows.append((*np.asarray(end, float), *(beyond / np.linalg.norm(beyond))))
    return np.array(rows, float).reshape(-1, 4)
