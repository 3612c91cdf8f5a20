"""Which touch comes next while the answer is not decisive (docs/exploration.md#the-next-touch).

:class:`JawReach` is where the jaw can make a rolling touch: a place on the boundary, with
its tangent there, is touchable when some finger can roll its pad through the place over
the profile's whole roll (tactile_jaw.plan.feasible), inside the workspace disk. Handed to
the recognizer as ``options.reach``, it makes the recognizer's ``next_touch`` the most
telling touch the jaw can really make. :func:`next_aim` picks the next touch from the
reason the answer is not decisive (tactile_jaw.decide.Why):

(a) a parabola felt on one side of its vertex only (``vertex``): a roll centred
    ``VERTEX_SIDE_DEG`` of tangent turn beyond the vertex on the short side, the nearest
    such centre a pad reaches (:func:`vertex_aim`). When no pad reaches it, or such a touch
    fell off the curved part (the object ends there), exploration stops: the richer rival
    (ellipse, hyperbola, cubic) always fits at least as well, so only that side can decide;
(b) otherwise the recognizer's ``next_touch`` (inside the jaw's reach with the contact held
    there), or the place nearest it toward the felt stretch where a pad rolls with its contact
    travelling along the answered curve (:func:`rolled_reach`), unless a touch was aimed within
    ``AIM_AGAIN_MM`` of it, or one aimed within ``EMPTY_AIM_MM`` met nothing (then the planner's
    own choice);
(c) nothing reachable helps (no ``next_touch`` and no vertex aim) while the classes or the
    parameters are in doubt: exploration stops with a reason a person can act on rather
    than spend the budget on touches that cannot help. An answer that changed with the last
    touch (``unstable``) needs one more touch anywhere: the planner's.

When it stops for want of reach, the reason says where the touch would have to go (the place
past the vertex, or the recognizer's ``next_touch`` anywhere in the workspace) and how far to
move the object for a pad to roll there (:func:`move_for`, :func:`move_advice`); when the
touch budget runs out undecided, :func:`budget_advice` says the same, or asks for more touches.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Callable, Sequence

import numpy as np

from recognizer.curves import CURVES
from recognizer.result import Recognition
from recognizer.touches import Reach
from tactile_jaw.decide import VERTEX_SIDE_DEG, Why, vertex_sides
from tactile_jaw.plan import (ObjectModel, RolledArc, feasible, feasible_arcs, free_strips, nominal_psi,
                              opened_strips, rested_ends, rolled_arc)
from tactile_jaw.settings import ExploreSettings

#: a suggested next touch this near (mm) one already aimed at is not aimed at again
AIM_AGAIN_MM = 1.0
#: roll centres tried beyond a parabola's vertex on its short side, every this many degrees
#: of tangent turn
VERTEX_AIM_STEP_DEG = 2.5
#: a suggestion this near (mm) a place where a touch aimed before met nothing is not aimed
#: at: the answered curve goes on where the object does not (the far side of a circle fitted
#: to a parabola's touches: the parabola example moved 3 mm sent the right pad there twice)
EMPTY_AIM_MM = 10.0
#: a stop for want of reach names the smallest move of the object (:func:`move_for`) after which
#: a pad rolls through every place the deciding touches need (for a parabola felt on one side
#: of its vertex, the whole vertex region: :func:`vertex_goal`) and the object's known boundary
#: stays inside the workspace disk: shifts every MOVE_STEP_MM up to MOVE_MAX_MM and turns every
#: MOVE_TURN_STEP_DEG up to MOVE_TURN_MAX_DEG, every combination, the smallest first (by how far
#: the known boundary's farthest point travels)
MOVE_STEP_MM = 2.0
MOVE_MAX_MM = 20.0
MOVE_TURN_STEP_DEG = 5.0
MOVE_TURN_MAX_DEG = 30.0
#: a move keeps every point of the object's known boundary (the felt stretch and the places the
#: move is for) this far (mm) inside the workspace disk, or no farther out than it was: the
#: opened jaw's pads and every transit lie on the disk's edge (tactile_jaw.plan.open_pose,
#: tactile_jaw.rounds.transit), so a boundary inside it is clear of them (seed-11 random
#: parabola 23 of session 10, moved as a reach-only search advised, lay across the opened jaw)
MOVE_CLEAR_MM = 3.0
#: a place counts as swept free within this far (mm) beyond a probe's swept stretch along its
#: pad (tactile_jaw.plan.free_strips): the probe at a pad's normal starts half a probe's span
#: (3°) off it, and misses the opened pad's far corners by 0.3 mm (calibrated block 1 of seed 239)
FREE_END_MM = 1.0
#: the search asks the jaw's reach about a place of a candidate move at most this many times (seed-13
#: random parabola 18 on the P-series jaw: a turn of 30° and a (-14, -8) mm shift, found after
#: more than 1,200 questions, 2.3 s more when asked one place at a time)
MOVE_QUERIES = 6000
#: the search asks the jaw's reach about this many candidate moves' places at once at first, twice
#: as many each time after, up to MOVE_BATCH_MAX (:func:`_first_reaching`)
MOVE_BATCH = 16
MOVE_BATCH_MAX = 1024
#: a boundary that goes on unfelt (:attr:`Goal.goes_on`) is followed this far (mm) at a step to
#: where a pad swept free (:meth:`JawReach.go_on_length`)
GO_ON_STEP_MM = 0.5
#: how :func:`move_advice`'s advice begins when every move it found would carry an opened pad
#: where the object goes on unfelt (:meth:`JawReach.opened_clear`)
NOT_CLEAR = "no move found that keeps the pads clear"
#: what :func:`move_advice` asks when a pad already reaches every place, yet its finger gave up there
WITHIN_REACH = "move or turn the object so that more of its curved part faces a finger"
#: a shift found is lengthened by this much (mm) when every place is still reached then
MOVE_MARGIN_MM = 2.0
#: the vertex region a move is for: roll centres at this many places evenly from one side's
#: VERTEX_SIDE_DEG + a quarter roll to the other's (:func:`vertex_goal`)
VERTEX_GOAL_PLACES = 5
#: the vertex regions a move is sought for, widest first (:func:`vertex_goals`): the outermost
#: roll centres this many quarter rolls past VERTEX_SIDE_DEG either side. +1 is where
#: :func:`vertex_aim` aims first; −1 puts a roll's far end a quarter roll past VERTEX_SIDE_DEG,
#: still within the centres vertex_aim tries. One pad rolls over 42–61° of a parabola's tangent
#: turn from one placement (roll centres; the other pad meets only its concave side), so the
#: widest region (59° of centres) is out of every pad's reach for some parabolas wherever they
#: lie: random P parabola 72 of ``bench_explore --finite 20 --anywhere --seed 157`` (a 10.4 mm)
#: had no move up to 90° and 20 mm for it, refused naming none; ±25° is reached turned 30° and
#: moved 20 mm, and followed so it is answered right (15.9 s; ±20.5°'s move, 12 mm: 19.7 s)
VERTEX_GOAL_QUARTERS = (1, 0, -1)


@dataclass(frozen=True)
class Aim:
    """A touch aimed at the boundary point (x, y) mm whose tangent there is ``phi`` (rad, in
    the touches' direction of travel), by ``finger``; ``why`` for people; ``kind`` 'vertex'
    (:func:`vertex_aim`), 'suggested' (the recognizer's ``next_touch``), 'curve' (where the
    finger's last, unusable roll felt the curved part: tactile_jaw.pipeline.curve_hint),
    'wider' (where its last roll was a corner only by its radius's deviation, rolled again
    wider: tactile_jaw.explore.wider_again), 'corner' (beside a usable roll's stretch clear of
    the corner it ran onto, away from it: tactile_jaw.pipeline.clear_side) or 'scan' (where
    a flat press's scan rolled on the curved part: tactile_jaw.explore.scanned_curve) or
    'promised' (where the move a refusal named was for, after it: tactile_jaw.explore.promised_aims)
    or 'felt' (on a curved part felt while no touch was usable, once, before the flat phase:
    tactile_jaw.explore.felt_curve_roll); ``span``: the roll's ψ range (rad) when not the settings'."""

    x: float
    y: float
    phi: float
    finger: str
    why: str
    kind: str = "suggested"
    span: float | None = None

    @property
    def psi(self) -> float:
        """The pad's normal for this touch (the exploration's ψ = φ + π/2)."""
        return self.phi + math.pi / 2

    @property
    def point(self) -> tuple[float, float]:
        return self.x, self.y


#: how a touch aimed beyond a parabola's vertex fell off the curved part (:func:`next_aim`'s
#: ``vertex_missed``): it pivoted about a corner or its approach met nothing, so the object ends
#: there, and no move helps; or it ran off elsewhere, or could not be made, at the edge of its
#: pad's reach, and the vertex move is named — random P parabola 62 of ``bench_explore --finite
#: 20 --anywhere --seed 157`` calibrated against config/jaw-p-truth.yaml: a roll centred 19° past
#: the vertex, where the left pad reaches centres up to 19°, gave pad lines no smooth curve has,
#: 37° short of the object's end (uncalibrated, the same roll was used); P parabola 66 of seed
#: 127: the roll's first line outside the joint limits. Both were refused naming no move.
VERTEX_ENDS, VERTEX_OFF = "ends", "off"

#: the run-log events that carry a :class:`Stop`: stopped for want of reach, or the budget spent undecided
STOP_EVENTS = ("stopped_early", "budget_spent")


@dataclass(frozen=True)
class Advice:
    """What :func:`move_advice` tells a person: its ``words``, the ``move`` (as :class:`Stop`'s;
    None when no small move is known) and its ``kind``: ``"move"``, ``"within_reach"`` (a pad
    already reaches every place: ``WITHIN_REACH``), ``"not_clear"`` (every move found would carry
    an opened pad where the object goes on: ``NOT_CLEAR``) or ``"out_of_reach"``."""

    words: str
    move: dict | None
    kind: str


class Stop(str):
    """Why exploration stops before its budget is spent (for people), with ``move``: the move
    of the object after which a pad rolls where the touch would have to go (:func:`move_for`:
    ``{"dx": mm, "dy": mm, "turn_deg": deg, "about": [x, y]}``, the turn about that place
    first, and ``places``: where it was named for, :func:`moved_places`), or None when no small
    move is known."""

    move: dict | None

    def __new__(cls, message: str, move: dict | None = None) -> "Stop":
        out = super().__new__(cls, message)
        out.move = move
        return out

    def event(self, kind: str) -> dict:
        """The run-log record of this stop (``kind`` one of ``STOP_EVENTS``)."""
        return {"type": "event", "kind": kind, "message": str(self),
                **({"move": self.move} if self.move is not None else {})}


def last_stop(events) -> dict | None:
    """A run log's latest ``STOP_EVENTS`` record (hand_driver.log.read_log's events), or None."""
    return next((e for e in reversed(events) if e.get("kind") in STOP_EVENTS), None)


def _in_strips(points: np.ndarray, strips, end_mm: float = 0.0) -> np.ndarray:
    """Which ``points`` (k × 2, mm) lie in one of the ``strips`` (ψ, u_lo, u_hi, d_lo, d_hi:
    along the pad line of normal ψ from u_lo to u_hi, lengthened ``end_mm`` each way, and
    between the offsets d_lo and d_hi; tactile_jaw.plan.free_strips)."""
    inside = np.zeros(len(points), bool)
    for psi, u_lo, u_hi, d_lo, d_hi in strips:
        n, t = np.array([math.cos(psi), math.sin(psi)]), np.array([-math.sin(psi), math.cos(psi)])
        u, d = points @ t, points @ n
        inside |= (u >= u_lo - end_mm) & (u <= u_hi + end_mm) & (d >= d_lo - 1e-9) & (d <= d_hi + 1e-9)
    return inside


class JawReach:
    """Where the jaw's pads can roll (module docstring); the recognizer's ``options.reach``."""

    def __init__(self, config, settings: ExploreSettings, probes: Sequence = ()):
        ws = config.workspace
        self.config = config
        self.settings = settings
        #: the exploration's probes (tactile_jaw.pipeline.FeltTouch, a list that may still grow):
        #: the pad ends they rested on bound where a move may carry the object
        #: (:meth:`opened_clear`); none, no such bound (a replayed log's recognition)
        self.probes = probes
        #: (how many probes, the free strips, the rested pad ends) as :meth:`opened_clear` last read them
        self._free: tuple[int, np.ndarray, np.ndarray] | None = None
        #: :meth:`go_on_length` of each ray asked, for the same free strips (a move search asks it every turn)
        self._go_on: dict[tuple[float, ...], float] = {}
        self.disk = Reach(float(ws.center_mm[0]), float(ws.center_mm[1]), float(ws.radius_mm))
        self._model = ObjectModel(ws.center_mm, ws.radius_mm)  # nothing felt: only its workspace edge is used

    def finger(self, x: float, y: float, phi: float, fingers: Sequence | None = None,
               curvature: tuple[float, float] | None = None):
        """The finger (of ``fingers``, default all) that can roll through (x, y) with its pad
        normal at φ + π/2 nearest its zero-angle normal, or None. With ``curvature`` (κ, κ_s of
        the curve there, :func:`curvature_at`) the contact travels along the curve over the roll
        (tactile_jaw.plan.RolledArc), else it stays at (x, y)."""
        if not bool(self.disk.contains(x, y)):
            return None
        psi = phi + math.pi / 2
        aim = RolledArc(x, y, psi, 0.0) if curvature is None else rolled_arc(x, y, psi, *curvature)
        # nearest its zero-angle normal first (a stable sort: ties in the given order), the first that rolls
        nearest = sorted(self.config.fingers if fingers is None else fingers,
                         key=lambda f: abs(math.remainder(psi - nominal_psi(f), 2 * math.pi)))
        return next((f for f in nearest if feasible(f, self._model, psi, self.settings, aim=aim)), None)

    def contains(self, px, py, phi=None) -> np.ndarray:
        """Whether a pad can roll through each place (x, y) with tangent φ; without φ, the disk.
        :meth:`finger`'s answer (is not None), every place at once (:meth:`rolls`)."""
        inside = np.atleast_1d(np.asarray(self.disk.contains(px, py), bool))
        if phi is None:
            return inside
        px, py, phi = (np.broadcast_to(np.atleast_1d(np.asarray(v, float)), inside.shape) for v in (px, py, phi))
        return self.rolls(px.ravel(), py.ravel(), phi.ravel()).reshape(inside.shape)

    def rolls(self, px: np.ndarray, py: np.ndarray, phi: np.ndarray, rho=0.0, drho=0.0,
              fingers: Sequence | None = None) -> np.ndarray:
        """Whether :meth:`finger` (of ``fingers``, default all) is not None for each place (1-D
        arrays x, y, φ), every place at once: inside the disk, a pad of some finger rolls through
        it (tactile_jaw.plan.feasible_arcs, the rule and arithmetic :meth:`finger` asks of one
        place), the contact travelling along a :class:`tactile_jaw.plan.RolledArc` of ``rho``,
        ``drho`` (per place, or floats; 0: it stays at the place; :func:`rolled_arc`'s of κ, κ_s)."""
        out = np.asarray(self.disk.contains(px, py), bool).copy()
        idx = np.flatnonzero(out)
        psi = phi[idx] + math.pi / 2
        arc = RolledArc(px[idx], py[idx], psi, *(np.broadcast_to(np.asarray(v, float), px.shape)[idx]
                                                  for v in (rho, drho)))
        ok = np.zeros(idx.size, bool)
        for f in self.config.fingers if fingers is None else fingers:
            todo = np.flatnonzero(~ok)
            ok[todo] = feasible_arcs(f, self._model, psi[todo], arc.at(todo), self.settings)
        out[idx] = ok
        return out

    def opened_clear(self, about, turn: float, shift: np.ndarray, goes_on: Sequence = (),
                     felt: np.ndarray | None = None) -> np.ndarray:
        """For each shift (k × 2) after turning by ``turn`` about ``about``: does the opened
        jaw keep its clearance from where the probes found the object going on unfelt? A pad
        end a probe rested on (tactile_jaw.plan.rested_ends) found the object there, going on
        past the end where no pad swept: the opened pads' places (their face and
        ``MOVE_CLEAR_MM`` before it, tactile_jaw.plan.opened_strips), carried back to where the
        object lies now, must not come within ``MOVE_CLEAR_MM`` of such an end on its far side,
        except where a probe's pad swept free (tactile_jaw.plan.free_strips) or the opened jaw
        stood when the exploration began. Calibrated random block 1 of bench_explore --finite
        10 --anywhere --seed 239 (P-series): the right pad's proximal end rested on its short
        side at (87.9, −39.8) mm; turned 10° about the face its left pad met and moved (6, −4)
        mm, that side came 1.0 mm from the opened right pad's place and its far corner across
        the pad. Space no probe found the object in is not held against a move: session 22's
        check that every such place be swept free (fc55cf9) refused 3 of 4 good moves of seed
        191, and the half-plane past every rested end refused 54 of 76 moves named in sessions
        20–22's held-out logs (those sampled 23–62 mm from the end); this check 3 of 106, all
        blocks whose far side came to an opened pad. ``goes_on`` (rows x, y, bx, by mm: a point
        of the boundary and the unit direction it goes on unfelt, :attr:`Goal.goes_on`): the
        opened pads' places must also keep ``MOVE_CLEAR_MM`` from that ray, up to where it first
        enters a place a pad swept free or the opened jaw stood (or the workspace's diameter,
        :meth:`go_on_length`): P-series block 7 of bench_explore --finite 20 --anywhere --seed
        347, moved 30° and (11, −11) mm for the face its left pad met, lay across the opened
        right pad with that face's unfelt part. ``felt`` (n × 2 mm, :attr:`Goal.felt`): points the
        exploration felt on the object, each kept clear of the opened pads once moved
        (:meth:`felt_near`). True for every shift when no probe rested on a pad end, nothing goes
        on and nothing felt is given."""
        free, ends = self._strips()
        rays = [(np.array(row[:2], float), np.array(row[2:], float), self.go_on_length(row)) for row in goes_on]
        felt = np.empty((0, 2)) if felt is None else np.asarray(felt, float).reshape(-1, 2)
        held = ~self.felt_near(about, turn, shift, felt) if len(felt) else np.ones(len(shift), bool)
        if not len(ends) and not rays:
            return held
        points = np.vstack([_strip_points(*row) for row in opened_strips(self.config, MOVE_CLEAR_MM)])  # m × 2
        c, s = math.cos(turn), math.sin(turn)
        a = np.asarray(about, float)
        # p = R⁻¹(q − a − shift) + a: where each such place is now
        back = (points[None, :, :] - a - np.asarray(shift, float)[:, None, :]) @ np.array([[c, -s], [s, c]]) + a
        beyond = np.zeros(back.shape[:2], bool)
        for ex, ey, bx, by in ends:
            dx, dy = back[..., 0] - ex, back[..., 1] - ey
            beyond |= (dx * bx + dy * by > 0.0) & (np.hypot(dx, dy) <= MOVE_CLEAR_MM)
        for e, b, length in rays:
            u = (back - e) @ b
            beyond |= (u >= 0.0) & (u <= length) & (np.abs((back - e) @ np.array([-b[1], b[0]])) <= MOVE_CLEAR_MM)
        near = back[beyond]  # only these can be refused: the swept strips are asked about them alone
        beyond[beyond] = ~_in_strips(near, free, FREE_END_MM)
        return held & ~np.any(beyond, axis=1)

    def felt_near(self, about, turn: float, shift: np.ndarray, felt: np.ndarray) -> np.ndarray:
        """For each shift (k × 2) after turning by ``turn`` about ``about``: does a point the
        exploration felt on the object (``felt``, n × 2 mm) come nearer an opened pad's face
        (tactile_jaw.plan.opened_strips) than ``MOVE_CLEAR_MM``, or than it is now when nearer, over
        the pad's length and ``MOVE_CLEAR_MM`` past its ends, in front of the face or behind it (up to
        the workspace's diameter)? Semicubical parabola 137 of bench_explore --finite 20 --anywhere
        --follow --seed 571 (P-series): a corner the left pad's rolls turned about lay 2.8 mm before
        the opened left pad; a face's move (15° about the right pad's corner, then (6, 3) mm) carried
        it 4.5 mm behind that pad, and the moved scene overlapped the opened jaw."""
        c, s = math.cos(turn), math.sin(turn)
        a = np.asarray(about, float)
        moved = ((felt - a) @ np.array([[c, s], [-s, c]]) + a)[None, :, :] + np.asarray(shift, float)[:, None, :]
        near = np.zeros(len(shift), bool)
        for psi, u_lo, u_hi, edge, _ in opened_strips(self.config, 0.0):
            n, t = np.array([math.cos(psi), math.sin(psi)]), np.array([-math.sin(psi), math.cos(psi)])
            allowed = np.clip(felt @ n - edge, 0.0, MOVE_CLEAR_MM)  # no nearer than MOVE_CLEAR_MM, or than now
            u, gap = moved @ t, moved @ n - edge
            near |= np.any((u >= u_lo - MOVE_CLEAR_MM) & (u <= u_hi + MOVE_CLEAR_MM) & (gap < allowed[None, :] - 1e-9)
                           & (gap > -2.0 * self.disk.radius), axis=1)
        return near

    def _strips(self) -> tuple[np.ndarray, np.ndarray]:
        """The free strips and the rested pad ends of :meth:`opened_clear`, read once per probe count."""
        if self._free is None or self._free[0] != len(self.probes):
            ends = rested_ends(self.config, self.probes)
            # the opened pads' places are free as the object lies now (the exploration began
            # there), and so is all behind their faces, the fingers' side
            behind = opened_strips(self.config, MOVE_CLEAR_MM, 2.0 * self.disk.radius)
            self._free = (len(self.probes), np.vstack([free_strips(self.config, self.probes), behind]), ends)
            self._go_on = {}
        return self._free[1], self._free[2]

    def go_on_length(self, row) -> float:
        """How far (mm) the boundary may go on unfelt from (x, y) along the unit (bx, by) of
        ``row``: to the first point (every ``GO_ON_STEP_MM``) a probe's pad swept free or the
        opened jaw stood (:meth:`opened_clear`'s free strips, without ``FREE_END_MM``), at most
        the workspace's diameter."""
        free = self._strips()[0]
        key = tuple(float(v) for v in row)
        if key not in self._go_on:
            most = 2.0 * self.disk.radius
            s = np.arange(GO_ON_STEP_MM, most + GO_ON_STEP_MM / 2, GO_ON_STEP_MM)
            swept = _in_strips(np.asarray(key[:2]) + s[:, None] * np.asarray(key[2:]), free)
            self._go_on[key] = float(s[np.argmax(swept)]) if np.any(swept) else most
        return self._go_on[key]

    def to_json(self) -> dict:
        """The workspace disk (a request file's ``options.reach`` holds only a disk)."""
        return self.disk.to_json()


def _strip_points(psi: float, u_lo: float, u_hi: float, d_lo: float, d_hi: float) -> np.ndarray:
    """Points (m × 2) filling a strip (tactile_jaw.plan.free_strips' rows) at most
    ``MOVE_STEP_MM`` apart along it, at its near, middle and far lines."""
    n, t = np.array([math.cos(psi), math.sin(psi)]), np.array([-math.sin(psi), math.cos(psi)])
    u = np.linspace(u_lo, u_hi, int(math.ceil((u_hi - u_lo) / MOVE_STEP_MM)) + 1)
    d = np.linspace(d_lo, d_hi, 3)
    uu, dd = (v.ravel() for v in np.meshgrid(u, d))
    return uu[:, None] * t + dd[:, None] * n


def vertex_aim(recognition: Recognition, touched: tuple[np.ndarray, np.ndarray], reach: JawReach,
               fingers: Sequence | None = None, avoid: Sequence[tuple[float, float]] = ()) -> Aim | None:
    """For a parabola answer felt on one side of its vertex: the touch rolling over
    ``VERTEX_SIDE_DEG`` of tangent turn beyond the vertex on the short side
    (tactile_jaw.decide.vertex_sides), its centre the nearest to VERTEX_SIDE_DEG + a quarter
    roll a pad reaches (every ``VERTEX_AIM_STEP_DEG``, the roll's far end past
    VERTEX_SIDE_DEG) and not within ``AIM_AGAIN_MM`` of a place aimed at before (``avoid``:
    a roll there that ran off the pad's face is tried at the next centre); None if no pad
    reaches any."""
    sides = vertex_sides(recognition, touched)
    short = 0 if sides[0] <= sides[1] else 1
    sign = -1.0 if short == 0 else 1.0
    half = 0.5 * math.degrees(reach.settings.roll_span_rad)
    goal = VERTEX_SIDE_DEG + 0.5 * half
    centres = np.arange(VERTEX_SIDE_DEG - half + 0.5, VERTEX_SIDE_DEG + 2 * half + 1e-9, VERTEX_AIM_STEP_DEG)
    for c in sorted(centres, key=lambda c: abs(c - goal)):
        x, y, phi = _parabola_place(recognition, sign * math.tan(math.radians(c)))
        if _aimed_near((x, y), avoid):
            continue
        f = reach.finger(x, y, phi, fingers)
        if f is not None:
            return Aim(x, y, phi, f.name,
                       f"beyond the parabola's vertex on the side felt only {sides[short]:.0f} deg (a roll centred "
                       f"{c:.1f} deg past it)", "vertex")
    return None


def vertex_place(recognition: Recognition, touched: tuple[np.ndarray, np.ndarray]) -> tuple[float, float, float]:
    """(x, y, φ) of the place ``VERTEX_SIDE_DEG`` past a parabola answer's vertex on its short
    side: where a touch would have to go (for people)."""
    sides = vertex_sides(recognition, touched)
    return _parabola_place(recognition, (-1.0 if sides[0] <= sides[1] else 1.0) * math.tan(math.radians(VERTEX_SIDE_DEG)))


def _parabola_place(recognition: Recognition, t: float) -> tuple[float, float, float]:
    """(x, y, φ) at t on a parabola answer (the canonical (a t², 2a t) placed by its pose), φ
    the tangent a pad touching there has: the pad faces the solid (the focus side), ψ =
    tangent − π/2, so φ = tangent − π."""
    curve = CURVES["parabola"]({"a": recognition.params["a"]})
    x, y = (float(np.ravel(v)[0]) for v in recognition.pose.apply(*curve.point(np.array([t]))))
    phi = float(np.ravel(curve.tangent_angle(np.array([t])))[0]) + recognition.pose.theta - math.pi
    return x, y, float(math.remainder(phi, 2 * math.pi))


def _where(x: float, y: float, phi: float) -> str:
    """A place for people: its position and the pad normal ψ = φ + π/2 a touch there has."""
    return f"({x:.0f}, {y:.0f}) mm, pad normal {math.degrees(math.remainder(phi + math.pi / 2, 2 * math.pi)):.0f} deg"


def next_aim(recognition: Recognition, why: Why, touched, reach: JawReach, fingers: Sequence,
             aimed_at: Sequence[tuple[float, float]], vertex_missed: str | None = None,
             empty_at: Sequence[tuple[float, float]] = (),
             anywhere: Callable[[], dict | None] | None = None,
             also: Sequence[tuple[float, float, float]] = (),
             one_side: Callable[[], bool] | None = None) -> tuple[Aim | None, Stop | None]:
    """(the next touch's aim, or None for the planner's own choice; why no touch within reach
    can help, or None) for an answer that is not decisive because of ``why`` (module
    docstring). ``touched``: the usable touches' sample positions (x, y); ``aimed_at``: the
    points touches were aimed at so far; ``vertex_missed``: a touch aimed beyond the vertex
    fell off the curved part, ``VERTEX_ENDS`` when it pivoted about a corner or met nothing (the
    object ends there), ``VERTEX_OFF`` when it ran off the curved part elsewhere or could not be
    made; ``empty_at``: points aimed at where the touch met nothing;
    ``anywhere``: the recognizer's ``next_touch`` anywhere in the workspace (called only
    when none is within the pads' reach, for the reason to say where it would be); ``also``:
    places a move to that touch should bring within a pad's roll too (:func:`_goal_stop`);
    ``one_side``: whether the rival is beyond the jaw's resolution on the side felt (asked only
    when a stop names a move: then the move for ``also``'s places comes first,
    :func:`other_side_stop`)."""
    if why.kind == "vertex" and touched is not None:
        aim = None if vertex_missed else vertex_aim(recognition, touched, reach, fingers, aimed_at)
        if aim is not None:
            return aim, None
        if not vertex_missed:  # every centre a pad reaches was aimed at already: the recognizer's touch
            aim = vertex_aim(recognition, touched, reach, fingers)
        if vertex_missed == VERTEX_ENDS:  # the richer rival always fits at least as well: only that side decides
            return None, Stop("no touch within the pads' reach can decide: the touch aimed beyond the vertex fell off "
                              "the curved part (the object ends there): move or turn the object so that more of its "
                              "curved part faces a finger")
        if vertex_missed:  # no corner there: the roll ran off at the edge of its pad's reach (module docstring)
            return None, _goal_stop("no touch within the pads' reach can decide: the touch aimed beyond the vertex "
                                    f"(near {_where(*vertex_place(recognition, touched))}) could not be made, or ran "
                                    "off the curved part without pivoting about a corner: it lies at the edge of the "
                                    "pads' reach",
                                    vertex_goals(recognition, touched, reach), reach, recognition=recognition)
        if aim is None:
            return None, _goal_stop("no touch within the pads' reach can decide: no pad can roll beyond the vertex "
                                    f"on that side (near {_where(*vertex_place(recognition, touched))})",
                                    vertex_goals(recognition, touched, reach), reach, recognition=recognition)
    suggested = recognition.next_touch
    if suggested is not None:
        sx, sy = float(suggested["x"]), float(suggested["y"])
        place = rolled_reach(recognition, sx, sy, float(suggested["phi"]), reach, fingers)
        if place is not None:
            x, y, phi, f = place
            where = ("where the recognizer points" if math.hypot(x - sx, y - sy) < AIM_AGAIN_MM else
                     f"nearest where the recognizer points ({sx:.1f}, {sy:.1f}) mm that a pad's face rolls through")
            aim = Aim(x, y, phi, f.name, f"{where}: {suggested.get('why', '')}")
            skip = _aimed_near(aim.point, aimed_at) or _aimed_near(aim.point, empty_at, EMPTY_AIM_MM)
            return (None if skip else aim), None
    if why.kind in ("unstable", "unclassified", "untested"):
        return None, None  # one more touch anywhere: the planner's
    what = ("narrow the parameters" if why.kind == "imprecise" else "tell the classes apart")
    if also and touched is not None and one_side is not None and one_side():
        side = other_side_stop(f"no touch within the pads' reach is expected to {what}", touched, reach, also,
                               recognition)
        if side is not None:
            return None, side
    if why.kind == "resolution":  # more touches of this jaw cannot tell them apart (tactile_jaw.decide.inseparable)
        return None, Stop("more touches of this jaw are not expected to tell them apart")
    wanted = anywhere() if anywhere is not None else None
    if wanted is None:
        return None, Stop(f"no touch within the pads' reach is expected to {what}: move or turn the object so that "
                          f"more of its curved part faces a finger")
    return None, _wanted_stop(f"no touch within the pads' reach is expected to {what}", wanted, reach, touched, also,
                              recognition)


def budget_advice(recognition: Recognition, why: Why, touched, reach: JawReach, budget: int,
                  anywhere: Callable[[], dict | None] | None = None,
                  also: Sequence[tuple[float, float, float]] = (), one_side: bool = False,
                  ended: str | None = None, felt_side: Sequence[tuple[float, float, float]] = ()) -> Stop:
    """What a person can do when the touch budget is spent and the answer is not decisive:
    when the classes tested fail and others were not tested for too few usable touches, another
    placement or more touches; when no class fits (``why.kind`` 'unclassified'), no move (the touches disagree with every
    class wherever they were: seed-11 random parabolas 20 and 23 of session 11's bench were
    advised the move to a ``next_touch`` of such an answer); for a parabola felt on one side of
    its vertex, the move that lets a pad roll across the vertex region (:func:`vertex_goal`,
    :func:`move_advice`); else where the recognizer's ``next_touch`` anywhere in the
    workspace would go, with the move that brings it within a pad's roll, or, when a pad
    already reaches it (its contact travelling along the answered curve, :func:`curvature_at`),
    a larger budget (the ``accurate`` profile); a move to that touch
    brings ``also``'s places within a pad's roll too where it can (:func:`_goal_stop`). With
    ``one_side`` (tactile_jaw.decide.beyond_resolution: the touches where they were cannot tell
    the answer from its rival at this jaw's resolution, however many), the move that brings
    ``also``'s places, the object's other side, within a pad's roll comes first
    (:func:`other_side_stop`); for an open answer, the move to the side felt's unfelt stretch
    (``felt_side``, tactile_jaw.explore.felt_side_places: :func:`felt_side_stop`) instead, when one
    reaches it. ``ended``: why the rolls ended instead, when the budget was not spent
    (no finger has a roll left to make)."""
    spent = f"the touch budget of {budget} is spent" if ended is None else ended
    if one_side and also and touched is not None:
        stop = felt_side_stop(spent, felt_side, touched, reach, recognition) if felt_side else None
        stop = stop if stop is not None else other_side_stop(spent, touched, reach, also, recognition)
        if stop is not None:
            return stop
    if why.kind in ("unclassified", "untested") and recognition.untested:
        # the classes tested failed, the others need more usable touches than the budget gave:
        # the touches met corners or pad ends, so another placement, or more touches, may decide
        untested = ", ".join(recognition.untested)
        return Stop(f"{spent} with too few usable touches to test {untested}: move or turn the object so that more "
                    f"of its curved part, clear of its corners, faces a finger, or use a profile with more touches "
                    f"(--profile accurate)")
    if why.kind == "unclassified":  # the touches disagree with every class: where they were is not what failed
        return Stop(f"{spent} and no class of the scene fits the touches: no move of the object is known to help")
    if recognition.cls == "parabola" and touched is not None and min(vertex_sides(recognition, touched)) < VERTEX_SIDE_DEG:
        x, y, phi = vertex_place(recognition, touched)
        if reach.finger(x, y, phi) is None:
            return _goal_stop(f"{spent} and no pad can roll beyond the parabola's vertex on the side felt less than "
                              f"{VERTEX_SIDE_DEG:g} deg (near {_where(x, y, phi)})",
                              vertex_goals(recognition, touched, reach), reach, recognition=recognition)
    wanted = anywhere() if anywhere is not None else None
    if wanted is None:
        return Stop(f"{spent}: a profile with more touches (--profile accurate) may decide")
    wx, wy = float(wanted["x"]), float(wanted["y"])
    if reach.finger(wx, wy, float(wanted["phi"]), curvature=curvature_at(recognition, wx, wy)) is not None:
        return Stop(f"{spent}; the most telling touch would roll at ({float(wanted['x']):.0f}, {float(wanted['y']):.0f}) "
                    f"mm, within a pad's reach: a profile with more touches (--profile accurate) may decide")
    return _wanted_stop(spent, wanted, reach, touched, also, recognition)


@dataclass(frozen=True)
class Goal:
    """What a move of the object is for: a pad rolling through every place (x, y, φ) of
    ``places`` (mm, rad: the boundary's tangent there, in the touches' direction of travel),
    the boundary's known points ``keep`` (2 × n, mm) kept clear of the opened jaw
    (``MOVE_CLEAR_MM``), turning about ``about``; ``where`` names it for people; ``curvature``
    per place (κ, κ_s) of the answered curve there, or None (:func:`with_curvature`; empty:
    none known): a pad's contact travels along the curve over its roll (:meth:`JawReach.finger`);
    ``goes_on`` rows (x, y, bx, by): a known point where the boundary goes on unfelt along the
    unit (bx, by), whose ray a move keeps clear of the opened jaw (:meth:`JawReach.opened_clear`:
    a straight face past its felt ends, tactile_jaw.flat_phase._face_advice); ``felt`` (n × 2 mm,
    or None): the points the exploration felt on the object, each kept clear of the opened pads
    once moved (:meth:`JawReach.felt_near`; tactile_jaw.flat_phase.felt_points)."""

    places: tuple[tuple[float, float, float], ...]
    keep: np.ndarray
    about: tuple[float, float]
    where: str
    curvature: tuple[tuple[float, float] | None, ...] = ()
    goes_on: tuple[tuple[float, float, float, float], ...] = ()
    felt: np.ndarray | None = None

    def curvature_of(self, j: int) -> tuple[float, float] | None:
        """(κ, κ_s) at place ``j``, or None."""
        return self.curvature[j] if j < len(self.curvature) else None


#: a goal's place this near (mm) the answered curve rolls on it (:func:`curvature_at`)
ON_CURVE_MM = 1.0
#: :func:`curvature_at` starts from the nearest of this many curve points: over a periodic class's
#: period, or over the touched parameters' span widened CURVE_REACH_SPANS times it each side
CURVE_GRID = 2001
CURVE_REACH_SPANS = 4.0


def _curve_t(recognition: Recognition | None, x: float, y: float) -> float | None:
    """The answered curve's parameter t at its point nearest (x, y), or None when there is no
    curved answer or that point is farther than ``ON_CURVE_MM``."""
    if recognition is None or recognition.pose is None or recognition.cls not in CURVES or recognition.cls == "line":
        return None
    curve = CURVES[recognition.cls](recognition.params)
    px, py = (float(np.ravel(v)[0]) for v in recognition.pose.inverse(x, y))
    if curve.t_period is not None:
        grid = np.linspace(*curve.t_period, CURVE_GRID)
    else:
        t = np.array([c["t"] for c in recognition.contacts], float)
        lo, hi = (float(t.min()), float(t.max())) if t.size else (-1.0, 1.0)
        wide = CURVE_REACH_SPANS * max(hi - lo, 1.0)
        grid = np.linspace(lo - wide, hi + wide, CURVE_GRID)
    t = curve.nearest(grid, px, py, 8)
    cx, cy = curve.point(t)
    if not math.hypot(float(cx[0]) - px, float(cy[0]) - py) <= ON_CURVE_MM:
        return None
    return float(np.ravel(t)[0])


def curvature_at(recognition: Recognition | None, x: float, y: float) -> tuple[float, float] | None:
    """(κ, κ_s) (eqs. 3–7) of the answered curve at its point nearest (x, y), or None when there
    is no curved answer or that point is farther than ``ON_CURVE_MM``."""
    t = _curve_t(recognition, x, y)
    if t is None:
        return None
    curve = CURVES[recognition.cls](recognition.params)
    return float(np.ravel(curve.kappa(np.array([t])))[0]), float(np.ravel(curve.kappa_s(np.array([t])))[0])


#: a place whose tangent is this far (deg) from the answered curve's at its nearest point is not on
#: that curve (:func:`rolled_reach`; the recognizer's next_touch lies on it, tangent and all)
ON_CURVE_DEG = 1.0
#: :func:`rolled_reach` tries this many places, evenly in t, from the recognizer's place to the felt stretch
ALONG_STEPS = 40


def rolled_reach(recognition: Recognition, x: float, y: float, phi: float, reach: JawReach,
                 fingers: Sequence | None = None) -> tuple[float, float, float, object] | None:
    """(x, y, φ, finger) of the place nearest (x, y) (tangent φ) on the answered curve, from there
    toward its felt stretch (its contact nearest in t, or the stretch's middle when (x, y) lies
    within it), at which a finger of ``fingers`` rolls its pad with the contact travelling along
    that curve over the roll (:meth:`JawReach.finger` with :func:`curvature_at`; ``ALONG_STEPS``
    places); (x, y) itself with the contact held there when it is not on a curved answer (within
    ``ON_CURVE_MM`` and ``ON_CURVE_DEG``); None when
    no pad rolls there. A place where the recognizer points with the contact held there may be one
    where the travelling contact runs off the pad: P semicubical 134 of bench_explore --finite 20
    --anywhere --seed 541 (config/jaw-p.yaml): the place at pad normal −87.3° (ρ 24 mm) was aimed
    at, and the roll's contact ran 0.3–8.7 mm along the left pad (not used); the pad's face
    reaches the branch up to −95° (ρ 18 mm), where the next roll was used and decided."""
    t0 = _curve_t(recognition, x, y)
    curve = None if t0 is None else CURVES[recognition.cls](recognition.params)
    off = None if t0 is None else math.remainder(
        phi - float(np.ravel(curve.tangent_angle(np.array([t0])))[0]) - recognition.pose.theta, math.pi)
    if off is None or abs(off) > math.radians(ON_CURVE_DEG):  # not a place of the answered curve
        f = reach.finger(x, y, phi, fingers)
        return None if f is None else (x, y, phi, f)
    pose = recognition.pose
    felt = np.array([float(c["t"]) for c in recognition.contacts], float)
    if curve.t_period is not None and felt.size:
        period = curve.t_period[1] - curve.t_period[0]
        gap = (felt - t0 + 0.5 * period) % period - 0.5 * period
        target = t0 + float(gap[np.argmin(np.abs(gap))])
    elif felt.size and not felt.min() <= t0 <= felt.max():
        target = float(felt[np.argmin(np.abs(felt - t0))])
    else:
        target = 0.5 * float(felt.min() + felt.max()) if felt.size else t0
    t = t0 + (target - t0) * np.linspace(0.0, 1.0, ALONG_STEPS + 1)
    px, py = pose.apply(*curve.point(t))
    tangent = np.asarray(curve.tangent_angle(t), float) + pose.theta
    flip = math.pi if abs(math.remainder(phi - float(tangent[0]), 2 * math.pi)) > math.pi / 2 else 0.0
    kappa, kappa_s = np.asarray(curve.kappa(t), float), np.asarray(curve.kappa_s(t), float)
    for k in range(t.size):
        if not (np.isfinite(px[k]) and np.isfinite(py[k]) and np.isfinite(kappa[k]) and np.isfinite(kappa_s[k])):
            continue
        place = float(px[k]), float(py[k]), phi + math.remainder(float(tangent[k]) + flip - phi, 2 * math.pi)
        f = reach.finger(*place, fingers, (float(kappa[k]), float(kappa_s[k])))
        if f is not None:
            return (*place, f)
    return None


def with_curvature(goal: Goal, recognition: Recognition | None) -> Goal:
    """``goal`` with the answered curve's curvature at each of its places (:func:`curvature_at`);
    unchanged without a recognition."""
    if recognition is None:
        return goal
    return replace(goal, curvature=tuple(curvature_at(recognition, x, y) for x, y, _ in goal.places))


def place_goal(x: float, y: float, phi: float, touched=None) -> Goal:
    """The goal of one place (x, y) with tangent φ, turning about it; ``touched`` the felt
    samples' positions (x, y), kept clear of the opened jaw."""
    keep = np.array([[x], [y]]) if touched is None else np.hstack([np.array([[x], [y]]), _thinned(touched)])
    return Goal(((x, y, phi),), keep, (x, y), "there")


def vertex_goal(recognition: Recognition, touched, reach: JawReach, quarters: int = 1) -> Goal:
    """The goal of a parabola answer felt on one side of its vertex: a pad rolling across the
    whole vertex region — roll centres at ``VERTEX_GOAL_PLACES`` places evenly from
    VERTEX_SIDE_DEG + ``quarters`` quarter rolls of tangent turn on one side to the same on the
    other (with 1, each roll's centre a quarter roll past VERTEX_SIDE_DEG, as :func:`vertex_aim`
    aims first; with −1, its far end), not only the short side's place: a move that brings the
    short side within reach can take the long side out of it —, turning about the vertex; kept
    clear of the opened jaw: the felt samples and the answered parabola out to a roll beyond
    that region."""
    half = 0.5 * math.degrees(reach.settings.roll_span_rad)
    edge = VERTEX_SIDE_DEG + 0.5 * half * quarters
    places = tuple(_parabola_place(recognition, math.tan(math.radians(c)))
                   for c in np.linspace(-edge, edge, VERTEX_GOAL_PLACES))
    t = np.tan(np.radians(np.linspace(-edge - half, edge + half, 9)))
    curve = CURVES["parabola"]({"a": recognition.params["a"]})
    arc = np.vstack([np.ravel(v) for v in recognition.pose.apply(*curve.point(t))])
    keep = arc if touched is None else np.hstack([arc, _thinned(touched)])
    vx, vy, _ = _parabola_place(recognition, 0.0)
    return Goal(places, keep, (vx, vy), f"across its vertex, {edge:.0f} deg either side (the vertex near ({vx:.0f}, {vy:.0f}) mm)")


def vertex_goals(recognition: Recognition, touched, reach: JawReach) -> tuple[Goal, ...]:
    """The vertex regions a move is sought for, widest first (``VERTEX_GOAL_QUARTERS``,
    :func:`vertex_goal`): :func:`_goal_stop` names the move for the first one a move reaches."""
    return tuple(vertex_goal(recognition, touched, reach, q) for q in VERTEX_GOAL_QUARTERS)


def _thinned(touched, most: int = 24) -> np.ndarray:
    """At most ``most`` of the felt samples' positions (2 × n), evenly by index."""
    xy = np.vstack([np.ravel(np.asarray(v, float)) for v in touched])
    return xy[:, np.unique(np.linspace(0, xy.shape[1] - 1, min(most, xy.shape[1])).astype(int))]


def _wanted_stop(head: str, wanted: dict, reach: JawReach, touched=None, also=(),
                 recognition: Recognition | None = None) -> Stop:
    """``head``, then where the touch ``wanted`` (a ``next_touch``) would roll and the move of
    the object that brings it within a pad's roll (:func:`_goal_stop`); ``wanted['what']``, if
    given, names the touch (tactile_jaw.explore.past_felt_end)."""
    x, y, phi = float(wanted["x"]), float(wanted["y"]), float(wanted["phi"])
    return _goal_stop(f"{head}; {wanted.get('what', 'the most telling touch')} would roll at {_where(x, y, phi)}",
                      place_goal(x, y, phi, touched), reach, also, recognition)


def _goal_stop(message: str, goal: Goal | Sequence[Goal], reach: JawReach,
               also: Sequence[tuple[float, float, float]] = (), recognition: Recognition | None = None) -> Stop:
    """The stop ``message``, then the move of the object that reaches ``goal`` (:func:`move_advice`)
    and with it the places ``also`` (x, y, φ), where a finger that never rolled met the object,
    when a move reaches them all (:func:`with_places`), else ``goal``'s. (A move for ``also``'s
    places alone was tried: random X-series ellipse 46 of bench_explore --finite 20 --anywhere
    --seed 127, turned 30° and moved 4 mm so, gave no usable roll at all.) Several goals
    (:func:`vertex_goals`, widest first): the advice for the first one a move reaches, or a pad
    already reaches (``WITHIN_REACH``); when none is, the move for ``also``'s places alone
    (:func:`side_goal`) stands in: a closed object's other side decides what one side leaves
    (random X-series ellipse 50 of seed 157: the touch wanted lay at the far end of the major
    axis, which no pad reaches however the object lies; moved as the left pad's place asks,
    turned 5° and moved 3 mm, it is answered ellipse, a −0.31 %); else the first goal's advice.
    Each place rolls on ``recognition``'s curve where it lies on it (:func:`with_curvature`)."""
    goals = (goal,) if isinstance(goal, Goal) else tuple(goal)
    first = None
    for g in goals:
        if also:
            advice = move_advice(reach, with_curvature(with_places(g, also), recognition))
            if advice.move is not None:
                return Stop(f"{message}: {advice.words}", advice.move)
        advice = move_advice(reach, with_curvature(g, recognition))
        if advice.kind in ("move", "within_reach"):
            return Stop(f"{message}: {advice.words}", advice.move)
        first = advice.words if first is None else first
    if also:
        side = move_advice(reach, with_curvature(side_goal(goals[0], also), recognition))
        if side.move is not None:
            return Stop(f"{message}: no pad reaches that touch with the object moved up to {MOVE_MAX_MM:g} mm and "
                        f"turned up to {MOVE_TURN_MAX_DEG:g} deg; {side.words}", side.move)
    return Stop(f"{message}: {first}", None)


def other_side_stop(head: str, touched, reach: JawReach, also: Sequence[tuple[float, float, float]],
                    recognition: Recognition | None = None) -> Stop | None:
    """``head``, then the move after which a pad rolls through ``also``'s places (where a finger
    that never rolled met the object: its other side, :func:`side_goal`), the felt samples
    ``touched`` kept clear of the opened jaw; None when no move reaches them. For an answer the
    rolls of one side cannot tell from its rival at this jaw's resolution: a move to the most
    telling touch brings the same side's rolls again (random X-series ellipse 55 of
    bench_explore --finite 20 --anywhere --seed 199: moved 3 mm and turned 15° for it, refused
    again, ellipse and semicubical within 0.1 in χ²; turned 10° about the left pad's place
    instead, the left pad rolls there and it is answered ellipse, a −0.07 %)."""
    keep = Goal((), _thinned(touched), (0.0, 0.0), "")
    advice = move_advice(reach, with_curvature(side_goal(keep, also), recognition))
    if advice.move is None:
        return None
    return Stop(f"{head}; the rolls on this side cannot tell the classes apart at this jaw's angle resolution, "
                f"the object's other side can: {advice.words}", advice.move)


def felt_side_stop(head: str, felt_side: Sequence[tuple[float, float, float]], touched, reach: JawReach,
                   recognition: Recognition | None = None) -> Stop | None:
    """``head``, then the move after which a pad rolls through the place past the felt stretch's end
    on an open answer's curve and through the felt stretch's other end (``felt_side``:
    tactile_jaw.explore.felt_side_places), or, when no move reaches both, through the first alone;
    the felt samples ``touched`` kept clear of the opened jaw; None when no move reaches it. On a
    branch closed by a chord the object's other side is that chord or an end corner, and the stretch
    that tells an open class from a closed rival is the side felt's own continuation: calibrated P
    semicubicals 60 and 63 of bench_explore --finite 10 --anywhere --calibrate --seed 593 (radii of
    curvature 8–13 mm felt, refused; the semicubical and ellipse part where the radius has grown
    1.6× and more over the felt stretch, docs/exploration.md)."""
    (x, y, phi), rest = felt_side[0], tuple(felt_side[1:])
    keep = np.hstack([np.array([[x], [y]]), _thinned(touched)])
    where = f"on the side felt, past where its rolls reached ({_where(x, y, phi)})"
    goals = [Goal(((x, y, phi), *rest), np.hstack([keep, np.array([(p[0], p[1]) for p in rest], float).T]),
                  (x, y), f"{where} and through the felt stretch's far end")] if rest else []
    goals.append(Goal(((x, y, phi),), keep, (x, y), where))
    for goal in goals:
        advice = move_advice(reach, with_curvature(goal, recognition))
        if advice.move is not None:
            return Stop(f"{head}; the rolls on this side cannot tell the classes apart at this jaw's angle "
                        f"resolution, and the {recognition.cls if recognition is not None else 'curve'} answered "
                        f"goes on past them on this side: {advice.words}", advice.move)
    return None


def side_goal(goal: Goal, also: Sequence[tuple[float, float, float]]) -> Goal:
    """The goal of the places ``also`` alone (x, y, φ: where a finger that never rolled met the
    object, tactile_jaw.explore.unrolled_places), turning about the first, ``goal``'s known
    boundary kept clear of the opened jaw."""
    xy = np.array([(x, y) for x, y, _ in also], float).T
    where = " and ".join(f"({x:.0f}, {y:.0f}) mm" for x, y, _ in also)
    return Goal(tuple(also), np.hstack([np.asarray(goal.keep, float), xy]), (float(xy[0, 0]), float(xy[1, 0])),
                f"through the side of the object near {where}, which the other finger met but has not rolled on")


def with_places(goal: Goal, also: Sequence[tuple[float, float, float]]) -> Goal:
    """``goal`` with the places ``also`` (x, y, φ: where a finger that never rolled met the object,
    tactile_jaw.explore.unrolled_places) to roll through too, kept clear of the opened jaw."""
    xy = np.array([(x, y) for x, y, _ in also], float).T
    where = " and ".join(f"({x:.0f}, {y:.0f}) mm" for x, y, _ in also)
    return Goal(goal.places + tuple(also), np.hstack([np.asarray(goal.keep, float), xy]), goal.about,
                f"{goal.where}, and another through the side of the object near {where}, which the other "
                f"finger met only at its pad's end")


def _moved(goal: Goal, turn: float, shift: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The places' (n × 2) and the kept points' (m × 2) positions after turning by ``turn``
    about ``goal.about``, then shifting by ``shift`` (k × 2): arrays k × n × 2, k × m × 2."""
    c, s = math.cos(turn), math.sin(turn)
    rot = np.array([[c, -s], [s, c]])
    about = np.asarray(goal.about, float)
    places = np.array([(x, y) for x, y, _ in goal.places], float)
    keep = np.asarray(goal.keep, float).T
    turned = [(p - about) @ rot.T + about for p in (places, keep)]
    return tuple(t[None, :, :] + shift[:, None, :] for t in turned)


def move_for(reach: JawReach, goal: Goal, fingers: Sequence | None = None) -> tuple[float, float, float] | None:
    """The smallest move (dx mm, dy mm, turn rad: the turn about ``goal.about`` first) of
    the object after which a pad can roll through every place of ``goal`` (the place turns
    and moves with the object) and every known point of its boundary stays ``MOVE_CLEAR_MM``
    inside the workspace disk (or no farther out than it was): shifts every
    ``MOVE_STEP_MM`` up to ``MOVE_MAX_MM``, turns every ``MOVE_TURN_STEP_DEG`` up to
    ``MOVE_TURN_MAX_DEG``, smallest first by how far the farthest known point travels; None
    when none does within ``MOVE_QUERIES`` questions to the reach."""
    return _move_search(reach, goal, fingers)[0]


def _move_search(reach: JawReach, goal: Goal, fingers,
                 turns: tuple[float, float] | None = None) -> tuple[tuple[float, float, float] | None, list]:
    """:func:`move_for`'s move, and the candidates (turn, shift, places) it passed over only because
    they carry an opened pad where the object goes on (:meth:`JawReach.opened_clear`), in its order;
    ``turns`` (lo, hi rad), if given, the only turns it tries (of its own steps)."""
    k = int(MOVE_MAX_MM // MOVE_STEP_MM)
    grid = np.arange(-k, k + 1) * MOVE_STEP_MM
    shift = np.stack([v.ravel() for v in np.meshgrid(grid, grid)], axis=-1)
    shift = shift[np.hypot(shift[:, 0], shift[:, 1]) <= MOVE_MAX_MM + 1e-9]
    m = int(MOVE_TURN_MAX_DEG // MOVE_TURN_STEP_DEG)
    (cx, cy), radius = (reach.disk.x, reach.disk.y), reach.disk.radius
    here = np.vstack([np.array([(x, y) for x, y, _ in goal.places]), np.asarray(goal.keep, float).T])
    allowed = np.maximum(radius - MOVE_CLEAR_MM, np.hypot(here[:, 0] - cx, here[:, 1] - cy))
    cands, blocked = [], []
    for turn in np.radians(np.arange(-m, m + 1) * MOVE_TURN_STEP_DEG):
        if turns is not None and not turns[0] - 1e-9 <= turn <= turns[1] + 1e-9:
            continue
        places, keep = _moved(goal, float(turn), shift)
        every = np.concatenate([places, keep], axis=1)
        clear = np.all(np.hypot(every[..., 0] - cx, every[..., 1] - cy) <= allowed[None, :] + 1e-9, axis=1)
        opened = reach.opened_clear(goal.about, float(turn), shift, goal.goes_on, goal.felt)
        travel = np.max(np.hypot(*(every - here[None]).transpose(2, 0, 1)), axis=1)
        for i in np.flatnonzero(clear):
            (cands if opened[i] else blocked).append((float(travel[i]), abs(float(turn)), float(turn), shift[i], places[i]))
    cands.sort(key=lambda c: c[:2])
    blocked.sort(key=lambda c: c[:2])
    first = _first_reaching(reach, goal, cands, fingers)
    return (None if first is None else (float(first[3][0]), float(first[3][1]), first[2])), blocked


def _first_reaching(reach: JawReach, goal: Goal, cands: Sequence, fingers):
    """The first of the candidate moves ``cands`` (..., turn, shift, places) after which a pad rolls
    through every place of ``goal``, or None when none does within ``MOVE_QUERIES`` questions: each
    candidate's places asked in turn until one is not rolled through, the place that failed last
    first. A place is asked of a batch of candidates at once (:meth:`JawReach.rolls`, from
    ``MOVE_BATCH`` candidates, doubling), the first time one of the batch asks it."""
    order = list(range(len(goal.places)))
    arcs = []  # each place's arc radius and its rate (rolled_arc's; 0, 0: a contact that stays put)
    for j in order:
        curvature = goal.curvature_of(j)
        arc = RolledArc(0.0, 0.0, 0.0, 0.0) if curvature is None else rolled_arc(0.0, 0.0, 0.0, *curvature)
        arcs.append((arc.rho, arc.drho))
    asked, start, size = 0, 0, MOVE_BATCH
    while start < len(cands):
        batch = cands[start:start + size]
        turn = np.array([c[2] for c in batch])
        places = np.array([c[4] for c in batch])  # batch × n × 2
        rolled: dict[int, np.ndarray] = {}
        for b, cand in enumerate(batch):
            for j in list(order):
                asked += 1
                if j not in rolled:  # this place, for this candidate and the rest of the batch
                    rolled[j] = np.zeros(len(batch), bool)
                    rolled[j][b:] = reach.rolls(places[b:, j, 0], places[b:, j, 1], goal.places[j][2] + turn[b:],
                                                *arcs[j], fingers=fingers)
                if not rolled[j][b]:
                    order.remove(j)
                    order.insert(0, j)
                    break
            else:
                return cand
            if asked >= MOVE_QUERIES:
                return None
        start += size
        size = min(2 * size, MOVE_BATCH_MAX)
    return None


def _reaches(reach: JawReach, goal: Goal, dx: float, dy: float, turn: float, fingers) -> bool:
    """Does a pad roll through every place of ``goal`` after the move, its known points clear?"""
    (cx, cy), radius = (reach.disk.x, reach.disk.y), reach.disk.radius
    places, keep = _moved(goal, turn, np.array([[dx, dy]]))
    here = np.asarray(goal.keep, float).T
    allowed = np.maximum(radius - MOVE_CLEAR_MM, np.hypot(here[:, 0] - cx, here[:, 1] - cy))
    if np.any(np.hypot(keep[0, :, 0] - cx, keep[0, :, 1] - cy) > allowed + 1e-9) \
            or not reach.opened_clear(goal.about, turn, np.array([[dx, dy]]), goal.goes_on, goal.felt)[0]:
        return False
    return all(reach.finger(float(p[0]), float(p[1]), goal.places[j][2] + turn, fingers, goal.curvature_of(j))
               is not None for j, p in enumerate(places[0]))


def move_advice(reach: JawReach, goal: Goal, fingers: Sequence | None = None,
                turns: tuple[float, float] | None = None) -> Advice:
    """What a person can do so that a pad rolls through every place of ``goal``, as an
    :class:`Advice`: the move of :func:`move_for` in the hand frame's words (x away from the
    palm, y toward the left finger, turns counterclockwise positive) and as :class:`Stop`'s
    ``move``, or a general request (and no move) when none is near, saying so when moves were near but each would carry
    an opened pad where the object goes on unfelt (:meth:`JawReach.opened_clear`). ``turns``
    (lo, hi rad): only moves turning the object within them (a flat press's seat,
    tactile_jaw.flat_phase._face_advice)."""
    move, blocked = _move_search(reach, goal, fingers, turns)
    # the search passed over every reaching move only for the opened pads: the candidates it had
    # asked about reach nowhere, so the moves without the probes' bound are those it passed over
    if move is None and _first_reaching(reach, goal, blocked, fingers) is not None:
        felt = goal.felt is not None and len(goal.felt)
        return Advice(f"{NOT_CLEAR}: every move that brings a pad {goal.where} would carry an "
                      f"opened pad where the object goes on unfelt (past a pad end a probe rested on"
                      f"{', or along the face past its felt ends' if goal.goes_on else ''}"
                      f"{', or onto a place a pad felt it' if felt else ''}): place the object so "
                      f"that more of its curved part faces a finger, clear of the opened pads", None, "not_clear")
    if move is None:
        return Advice(f"no pad reaches {goal.where} with the object moved up to {MOVE_MAX_MM:g} mm and turned up "
                      f"to {MOVE_TURN_MAX_DEG:g} deg inside the workspace: place the object so that more of its "
                      f"curved part faces a finger", None, "out_of_reach")
    if move == (0.0, 0.0, 0.0):  # within reach, yet its finger gave up there (corners, closing segments)
        return Advice(WITHIN_REACH, None, "within_reach")
    dx, dy, a = move
    grow = (math.hypot(dx, dy) + MOVE_MARGIN_MM) / max(math.hypot(dx, dy), 1e-9)
    if (dx or dy) and _reaches(reach, goal, grow * dx, grow * dy, a, fingers):
        dx, dy = grow * dx, grow * dy  # clear of the reach's edge, which a fitted curve knows only so well
    words, out = _move_words(goal, dx, dy, a)
    return Advice(words, {**out, "places": moved_places(reach, goal, dx, dy, a, fingers)}, "move")


def moved_places(reach: JawReach, goal: Goal, dx: float, dy: float, turn: float,
                 fingers: Sequence | None = None) -> list[dict]:
    """Where the move (``dx``, ``dy`` mm after ``turn`` rad about ``goal.about``) was named for:
    each place of ``goal`` once the object is moved so (x, y mm, φ rad in the hand frame) and the
    finger that rolls there (None when none does), for :class:`Stop`'s ``move``: the run after
    the move rolls there (tactile_jaw.explore.promised_aims)."""
    places, _ = _moved(goal, turn, np.array([[dx, dy]]))
    out = []
    for j, (x, y) in enumerate(places[0]):
        phi = float(math.remainder(goal.places[j][2] + turn, 2 * math.pi))
        finger = reach.finger(float(x), float(y), phi, fingers, goal.curvature_of(j))
        out.append({"x": round(float(x), 3), "y": round(float(y), 3), "phi": round(phi, 5),
                    "finger": None if finger is None else finger.name})
    return out


def facing_move(reach: JawReach, goal: Goal, finger) -> tuple[str, dict] | None:
    """For a place of ``goal`` a pad of ``finger`` already rolls through, yet whose rolls there
    pivoted about the object's corners: the turn about it (every ``MOVE_TURN_STEP_DEG``, up to
    ``MOVE_TURN_MAX_DEG``) after which the place's normal is the finger's nominal one, where
    its first rolls go (tactile_jaw.plan.nominal_psi), with the pad still rolling through it
    and the known boundary clear of the opened jaw; None when no such turn is (or it is 0).
    Calibrated random parabola 30 of bench_explore --finite 10 --anywhere --seed 239 (P-series):
    the left press's scan rolled over ψ −84…−42° of the curved part while the left rolls at
    −90° and −110° pivoted about its end corner; refused naming no move."""
    x, y, phi = goal.places[0]
    step, most = math.radians(MOVE_TURN_STEP_DEG), math.radians(MOVE_TURN_MAX_DEG)
    turn = math.remainder(nominal_psi(finger) - (phi + math.pi / 2), 2 * math.pi)
    turn = max(-most, min(most, step * round(turn / step)))
    if abs(turn) < 1e-9 or not _reaches(reach, goal, 0.0, 0.0, turn, [finger]):
        return None
    return _move_words(goal, 0.0, 0.0, turn)


def _move_words(goal: Goal, dx: float, dy: float, a: float) -> tuple[str, dict]:
    """The move (dx, dy mm after turning ``a`` rad about ``goal.about``) in the hand frame's
    words, and as :class:`Stop`'s ``move``."""
    parts = [f"{abs(v):.0f} mm {(pos if v > 0 else neg)}" for v, pos, neg in
             ((dx, "away from the palm (+x)", "toward the palm (-x)"),
              (dy, "toward the left finger (+y)", "toward the right finger (-y)")) if abs(v) >= 0.5]
    ax, ay = goal.about
    moved = []
    if a:
        moved.append(f"turn the object {abs(math.degrees(a)):.0f} deg {'counterclockwise' if a > 0 else 'clockwise'} "
                     f"(hand frame) about ({ax:.0f}, {ay:.0f}) mm")
    if parts:
        moved.append(f"{'then move it' if moved else 'move the object'} {' and '.join(parts)}")
    return (f"{', '.join(moved)}, and a pad can roll {goal.where}",
            {"dx": round(dx, 3), "dy": round(dy, 3), "turn_deg": round(math.degrees(a), 3), "about": [ax, ay]})


def _aimed_near(point, aimed_at, radius: float = AIM_AGAIN_MM) -> bool:
    return any(math.hypot(point[0] - x, point[1] - y) < radius for x, y in aimed_at)
