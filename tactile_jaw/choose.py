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
(b) otherwise the recognizer's ``next_touch`` (already inside the jaw's reach), unless a
    touch was aimed within ``AIM_AGAIN_MM`` of it, or one aimed within ``EMPTY_AIM_MM`` met
    nothing (then the planner's own choice);
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
from dataclasses import dataclass
from typing import Callable, Sequence

import numpy as np

from recognizer.curves import CURVES
from recognizer.result import Recognition
from recognizer.touches import Reach
from tactile_jaw.decide import VERTEX_SIDE_DEG, Why, vertex_sides
from tactile_jaw.plan import ObjectModel, feasible, nominal_psi
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
#: a stop for want of reach names the smallest move of the object after which a pad rolls where
#: the touch would have to go (:func:`move_for`): a shift on a grid of MOVE_STEP_MM up to MOVE_MAX_MM (random
#: parabolas 6 mm nearer the palm than the example reach only one side of their vertex)
MOVE_STEP_MM = 1.0
MOVE_MAX_MM = 20.0
#: ... else the smallest turn about that place, every MOVE_TURN_STEP_DEG up to
#: MOVE_TURN_MAX_DEG, else a turn and a shift on the coarser grid MOVE_COARSE (mm, deg)
MOVE_TURN_STEP_DEG = 2.5
MOVE_TURN_MAX_DEG = 30.0
MOVE_COARSE = (2.0, 5.0)
#: a shift found is lengthened by this much (mm) when a pad still reaches the place then
MOVE_MARGIN_MM = 2.0


@dataclass(frozen=True)
class Aim:
    """A touch aimed at the boundary point (x, y) mm whose tangent there is ``phi`` (rad, in
    the touches' direction of travel), by ``finger``; ``why`` for people; ``kind`` 'vertex'
    (:func:`vertex_aim`), 'suggested' (the recognizer's ``next_touch``) or 'curve' (where the
    finger's last, unusable roll felt the curved part: tactile_jaw.pipeline.curve_hint)."""

    x: float
    y: float
    phi: float
    finger: str
    why: str
    kind: str = "suggested"

    @property
    def psi(self) -> float:
        """The pad's normal for this touch (the exploration's ψ = φ + π/2)."""
        return self.phi + math.pi / 2

    @property
    def point(self) -> tuple[float, float]:
        return self.x, self.y


#: the run-log events that carry a :class:`Stop`: stopped for want of reach, or the budget spent undecided
STOP_EVENTS = ("stopped_early", "budget_spent")


class Stop(str):
    """Why exploration stops before its budget is spent (for people), with ``move``: the move
    of the object after which a pad rolls where the touch would have to go (:func:`move_for`:
    ``{"dx": mm, "dy": mm, "turn_deg": deg, "about": [x, y]}``, the turn about that place
    first), or None when no small move is known."""

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


class JawReach:
    """Where the jaw's pads can roll (module docstring); the recognizer's ``options.reach``."""

    def __init__(self, config, settings: ExploreSettings):
        ws = config.workspace
        self.config = config
        self.settings = settings
        self.disk = Reach(float(ws.center_mm[0]), float(ws.center_mm[1]), float(ws.radius_mm))
        self._model = ObjectModel(ws.center_mm, ws.radius_mm)  # nothing felt: only its workspace edge is used

    def finger(self, x: float, y: float, phi: float, fingers: Sequence | None = None):
        """The finger (of ``fingers``, default all) that can roll through (x, y) with its pad
        normal at φ + π/2 nearest its zero-angle normal, or None."""
        if not bool(self.disk.contains(x, y)):
            return None
        psi = phi + math.pi / 2
        ok = [f for f in (self.config.fingers if fingers is None else fingers)
              if feasible(f, self._model, psi, self.settings, aim=(x, y))]
        return min(ok, key=lambda f: abs(math.remainder(psi - nominal_psi(f), 2 * math.pi)), default=None)

    def contains(self, px, py, phi=None) -> np.ndarray:
        """Whether a pad can roll through each place (x, y) with tangent φ; without φ, the disk."""
        inside = np.atleast_1d(np.asarray(self.disk.contains(px, py), bool))
        if phi is None:
            return inside
        px, py, phi = (np.broadcast_to(np.atleast_1d(np.asarray(v, float)), inside.shape) for v in (px, py, phi))
        out = inside.copy()
        for i in np.flatnonzero(inside):
            out[i] = self.finger(float(px[i]), float(py[i]), float(phi[i])) is not None
        return out

    def to_json(self) -> dict:
        """The workspace disk (a request file's ``options.reach`` holds only a disk)."""
        return self.disk.to_json()


def vertex_aim(recognition: Recognition, touched: tuple[np.ndarray, np.ndarray], reach: JawReach,
               fingers: Sequence | None = None) -> Aim | None:
    """For a parabola answer felt on one side of its vertex: the touch rolling over
    ``VERTEX_SIDE_DEG`` of tangent turn beyond the vertex on the short side
    (tactile_jaw.decide.vertex_sides), its centre the nearest to VERTEX_SIDE_DEG + a quarter
    roll a pad reaches (every ``VERTEX_AIM_STEP_DEG``, the roll's far end past
    VERTEX_SIDE_DEG); None if no pad reaches any."""
    sides = vertex_sides(recognition, touched)
    short = 0 if sides[0] <= sides[1] else 1
    sign = -1.0 if short == 0 else 1.0
    half = 0.5 * math.degrees(reach.settings.roll_span_rad)
    goal = VERTEX_SIDE_DEG + 0.5 * half
    centres = np.arange(VERTEX_SIDE_DEG - half + 0.5, VERTEX_SIDE_DEG + 2 * half + 1e-9, VERTEX_AIM_STEP_DEG)
    for c in sorted(centres, key=lambda c: abs(c - goal)):
        x, y, phi = _parabola_place(recognition, sign * math.tan(math.radians(c)))
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
             aimed_at: Sequence[tuple[float, float]], vertex_missed: bool = False,
             empty_at: Sequence[tuple[float, float]] = (),
             anywhere: Callable[[], dict | None] | None = None) -> tuple[Aim | None, Stop | None]:
    """(the next touch's aim, or None for the planner's own choice; why no touch within reach
    can help, or None) for an answer that is not decisive because of ``why`` (module
    docstring). ``touched``: the usable touches' sample positions (x, y); ``aimed_at``: the
    points touches were aimed at so far; ``vertex_missed``: a touch aimed beyond the vertex
    fell off the curved part; ``empty_at``: points aimed at where the touch met nothing;
    ``anywhere``: the recognizer's ``next_touch`` anywhere in the workspace (called only
    when none is within the pads' reach, for the reason to say where it would be)."""
    if why.kind == "vertex" and touched is not None:
        aim = None if vertex_missed else vertex_aim(recognition, touched, reach, fingers)
        if aim is not None and not _aimed_near(aim.point, aimed_at):
            return aim, None
        if vertex_missed:  # the richer rival always fits at least as well: only that side decides
            return None, Stop("no touch within the pads' reach can decide: the touch aimed beyond the vertex fell off "
                              "the curved part (the object ends there): move or turn the object so that more of its "
                              "curved part faces a finger")
        if aim is None:
            return None, _place_stop("no touch within the pads' reach can decide: no pad can roll beyond the vertex "
                                     "on that side (near {where})", *vertex_place(recognition, touched), reach)
    suggested = recognition.next_touch
    if suggested is not None:
        f = reach.finger(suggested["x"], suggested["y"], suggested["phi"], fingers)
        if f is not None:
            aim = Aim(float(suggested["x"]), float(suggested["y"]), float(suggested["phi"]), f.name,
                      f"where the recognizer points: {suggested.get('why', '')}")
            skip = _aimed_near(aim.point, aimed_at) or _aimed_near(aim.point, empty_at, EMPTY_AIM_MM)
            return (None if skip else aim), None
    if why.kind == "resolution":  # more touches of this jaw cannot tell them apart (tactile_jaw.decide.inseparable)
        return None, Stop("more touches of this jaw are not expected to tell them apart")
    if why.kind in ("unstable", "unclassified"):
        return None, None  # one more touch anywhere: the planner's
    what = ("narrow the parameters" if why.kind == "imprecise" else "tell the classes apart")
    wanted = anywhere() if anywhere is not None else None
    if wanted is None:
        return None, Stop(f"no touch within the pads' reach is expected to {what}: move or turn the object so that "
                          f"more of its curved part faces a finger")
    return None, _wanted_stop(f"no touch within the pads' reach is expected to {what}", wanted, reach)


def budget_advice(recognition: Recognition, why: Why, touched, reach: JawReach, budget: int,
                  anywhere: Callable[[], dict | None] | None = None) -> Stop:
    """What a person can do when the touch budget is spent and the answer is not decisive:
    for a parabola felt on one side of its vertex, the move that lets a pad roll beyond it
    (:func:`move_advice`); else where the recognizer's ``next_touch`` anywhere in the
    workspace would go, with the move that brings it within a pad's roll, or, when a pad
    already reaches it, a larger budget (the ``accurate`` profile)."""
    spent = f"the touch budget of {budget} is spent"
    if recognition.cls == "parabola" and touched is not None and min(vertex_sides(recognition, touched)) < VERTEX_SIDE_DEG:
        x, y, phi = vertex_place(recognition, touched)
        if reach.finger(x, y, phi) is None:
            return _place_stop(f"{spent} and no pad can roll beyond the parabola's vertex on the side felt less than "
                               f"{VERTEX_SIDE_DEG:g} deg (near {{where}})", x, y, phi, reach)
    wanted = anywhere() if anywhere is not None else None
    if wanted is None:
        return Stop(f"{spent}: a profile with more touches (--profile accurate) may decide")
    if reach.finger(float(wanted["x"]), float(wanted["y"]), float(wanted["phi"])) is not None:
        return Stop(f"{spent}; the most telling touch would roll at ({float(wanted['x']):.0f}, {float(wanted['y']):.0f}) "
                    f"mm, within a pad's reach: a profile with more touches (--profile accurate) may decide")
    return _wanted_stop(spent, wanted, reach)


def _wanted_stop(head: str, wanted: dict, reach: JawReach) -> Stop:
    """``head``, then where the touch ``wanted`` (a ``next_touch``) would roll and the move of
    the object that brings it within a pad's roll (:func:`_place_stop`)."""
    return _place_stop(f"{head}; the most telling touch would roll at {{where}}",
                       float(wanted["x"]), float(wanted["y"]), float(wanted["phi"]), reach)


def _place_stop(message: str, x: float, y: float, phi: float, reach: JawReach) -> Stop:
    """The stop ``message`` (its ``{where}`` the place, :func:`_where`), then the move of the
    object that lets a pad roll through (x, y) with tangent φ (:func:`move_advice`)."""
    advice, move = move_advice(reach, x, y, phi)
    return Stop(f"{message.format(where=_where(x, y, phi))}: {advice}", move)


def move_for(reach: JawReach, x: float, y: float, phi: float, fingers: Sequence | None = None
             ) -> tuple[float, float, float] | None:
    """The smallest move (dx mm, dy mm, turn rad) of the object after which a pad can roll
    through its place now at (x, y) with tangent φ, or None: a shift alone (the place moves
    with the object, its tangent does not turn; grid ``MOVE_STEP_MM`` up to ``MOVE_MAX_MM``),
    else a turn about the place alone (every ``MOVE_TURN_STEP_DEG`` up to
    ``MOVE_TURN_MAX_DEG``), else both (the coarser grid ``MOVE_COARSE``), the smallest first."""
    def shifts(step: float) -> list[tuple[float, float]]:
        k = int(MOVE_MAX_MM // step)
        grid = np.arange(-k, k + 1) * step
        dx, dy = (v.ravel() for v in np.meshgrid(grid, grid))
        norm = np.hypot(dx, dy)
        order = np.argsort(norm, kind="stable")
        return [(float(dx[i]), float(dy[i])) for i in order if norm[i] <= MOVE_MAX_MM + 1e-9]

    def turns(step: float) -> list[float]:
        k = int(MOVE_TURN_MAX_DEG // step)
        return [math.radians(sign * i * step) for i in range(1, k + 1) for sign in (1, -1)]

    moves = ([(dx, dy, 0.0) for dx, dy in shifts(MOVE_STEP_MM)]
             + [(0.0, 0.0, a) for a in turns(MOVE_TURN_STEP_DEG)]
             + [(dx, dy, a) for a in turns(MOVE_COARSE[1]) for dx, dy in shifts(MOVE_COARSE[0])[1:]])
    for dx, dy, a in moves:
        if reach.finger(x + dx, y + dy, phi + a, fingers) is not None:
            return dx, dy, a
    return None


def move_advice(reach: JawReach, x: float, y: float, phi: float, fingers: Sequence | None = None
                ) -> tuple[str, dict | None]:
    """What a person can do so that a pad rolls through the place (x, y) with tangent φ: the
    move of :func:`move_for` in the hand frame's words (x away from the palm, y toward the
    left finger, turns counterclockwise positive) and as :class:`Stop`'s ``move``, or a
    general request (and None) when none is near."""
    move = move_for(reach, x, y, phi, fingers)
    if move is None:
        return (f"no pad reaches it with the object moved up to {MOVE_MAX_MM:g} mm or turned up to "
                f"{MOVE_TURN_MAX_DEG:g} deg: place the object so that more of its curved part faces a finger"), None
    if move == (0.0, 0.0, 0.0):  # within reach, yet its finger gave up there (corners, closing segments)
        return "move or turn the object so that more of its curved part faces a finger", None
    dx, dy, a = move
    grow = (math.hypot(dx, dy) + MOVE_MARGIN_MM) / max(math.hypot(dx, dy), 1e-9)
    if (dx or dy) and reach.finger(x + grow * dx, y + grow * dy, phi + a, fingers) is not None:
        dx, dy = grow * dx, grow * dy  # clear of the reach's edge, which a fitted curve knows only so well
    parts = [f"{abs(v):.0f} mm {(pos if v > 0 else neg)}" for v, pos, neg in
             ((dx, "away from the palm (+x)", "toward the palm (-x)"),
              (dy, "toward the left finger (+y)", "toward the right finger (-y)")) if abs(v) >= 0.5]
    moved = [f"move the object {' and '.join(parts)}"] if parts else []
    if a:
        moved.append(f"turn {'it' if moved else 'the object'} {abs(math.degrees(a)):.0f} deg {'counterclockwise' if a > 0 else 'clockwise'} "
                     f"(hand frame) about that place")
    return (f"{', then '.join(moved)}, and a pad can roll there",
            {"dx": round(dx, 3), "dy": round(dy, 3), "turn_deg": round(math.degrees(a), 3), "about": [x, y]})


def _aimed_near(point, aimed_at, radius: float = AIM_AGAIN_MM) -> bool:
    return any(math.hypot(point[0] - x, point[1] - y) < radius for x, y in aimed_at)
