"""What every phase of the exploration shares: its record (:class:`Exploration`), the
transit that carries a pad between touches (:func:`transit`), and a round of both fingers
run together with its robot time booked (:func:`timed_round`). docs/exploration.md.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from hand_driver import kinematics as kin
from hand_driver.cycle import LIMIT_MARGIN_RAD, Jaw, run_together
from hand_driver.motion import move_line, move_to
from recognizer.result import Recognition
from tactile_jaw.choose import Stop
from tactile_jaw.pipeline import FeltTouch
from tactile_jaw.plan import ObjectModel, clear_offset, hug_offset, nominal_psi, retreat_offset

#: a transit turns along the workspace edge through pad lines at most this many degrees apart
EDGE_TURN_STEP_DEG = 15.0


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
    stopped: Stop | None = None  # why it ended undecided and what to do: stopped early, or its budget spent (tactile_jaw.choose)
    #: where the robot time went (s): probe, rolling-touch and flat-press rounds (each
    #: including its transits), the transits alone (per round the slower finger's), the
    #: final retreat
    time_s: dict[str, float] = field(default_factory=lambda: dict.fromkeys(
        ("probes", "probe_transits", "touches", "touch_transits", "presses", "press_transits", "retreat"), 0.0))

    @property
    def request(self) -> dict[str, Any]:
        """The touches request (docs/formats.md) of the usable touches."""
        return {"touches": [t.to_json() for t in self.used]}


def transit(jaw: Jaw, finger: str, model: ObjectModel, psi_to: float, aim=None, hug: bool = False):
    """Retreat to the workspace edge along the pad normal, then turn along the edge to ψ
    (where the joints cannot reach the edge, along the farthest-out line they reach that
    keeps clear of the object: tactile_jaw.plan.retreat_offset).
    Where the edge is out of the joints' reach along this normal (a pad turned far past its
    nominal direction), the pad retreats as far as it can and the finger swings open in
    joint space to its edge pose at the nominal ψ, and turns from there: without this, one
    such pose made every later transit of the finger fail and spent the touch budget.
    With ``hug`` (between rolling touches) the pad keeps only ``APPROACH_MARGIN_MM`` outside
    the tangent the felt lines predict where they interpolate (tactile_jaw.plan.hug_offset)
    instead of going out to the edge there. The turn is paced so that no joint's goal outruns
    its servo (hand_driver.motion.move_line ``paced``): unpaced, a distal joint asked for more
    than its profile velocity ran alike with the proximal one and the pad slid along its normal
    back onto the object it had just rolled on, wedged there for every later touch (random P
    cubical 109 of bench_explore --finite 20 --anywhere --seed 419)."""
    line = jaw.pad_line(jaw.last_state, finger)
    psi_from = float(line.psi)
    f = jaw.config.finger(finger)
    def out(a: float, d: float | None) -> float | None:  # nearer the object only where hugging may
        h = hug_offset(f, model, a) if hug else None
        return clear_offset(f, model, a, d if h is None or d is None else max(d, h))

    via = [(psi_from, min(float(line.d), out(psi_from, model.edge(psi_from))))]
    try:
        jaw.solve(finger, *via[0], jaw.finger_q(jaw.last_state, finger))
    except kin.Unreachable:
        psi_from = nominal_psi(f)
        q_open = kin.ik_line(f, psi_from, model.edge(psi_from), margin_rad=LIMIT_MARGIN_RAD)
        q0 = jaw.finger_q(jaw.last_state, finger)  # the joints' straight path, paced: each servo's own
        step = math.radians(jaw.config.motion.turn_speed_deg_s) * jaw.period_s  # profile to the far goal
        steps = max(1, math.ceil(float(np.max(np.abs(q_open - q0))) / step))  # starts both joints alike
        for k in range(1, steps):  # and slides the pad along its normal onto the object (X line 18 of seed 139)
            yield q0 + (q_open - q0) * k / steps
        yield from move_to(jaw, finger, q_open)
        via = []
    delta = math.remainder(psi_to - psi_from, 2 * math.pi)
    steps = max(1, math.ceil(abs(math.degrees(delta)) / EDGE_TURN_STEP_DEG))
    for k in range(1, steps + 1):
        a = psi_from + delta * k / steps
        d = out(a, retreat_offset(f, model, a, aim))
        if d is None:
            raise kin.Unreachable(f"finger {finger}: no pad line of psi={math.degrees(a):.1f} deg within the joint "
                                  f"limits keeps clear of the object")
        via.append((a, d))
    yield from move_line(jaw, finger, *via[-1], via=via[:-1], paced=True)


def transit_or_problem(jaw: Jaw, finger: str, model: ObjectModel, psi_to: float,
                       spent: dict[str, float] | None = None, aim=None, hug: bool = False):
    """:func:`transit`; why it could not go on (the path left the joint limits), or None.
    The robot time it took goes to ``spent[finger]``."""
    t0 = jaw.robot_time()
    try:
        yield from transit(jaw, finger, model, psi_to, aim, hug)
    except kin.Unreachable as exc:
        return f"{finger}: transit to psi={math.degrees(psi_to):.1f} deg: {exc}"
    finally:
        if spent is not None:
            spent[finger] = jaw.robot_time() - t0
    return None


def timed_round(jaw: Jaw, plans: dict, spent: dict[str, float], time_s: dict[str, float], total: str,
                transits: str):
    """:func:`run_together` of one round, its robot time added to ``time_s[total]`` and the
    slower finger's transit to ``time_s[transits]``."""
    t0 = jaw.robot_time()
    results = run_together(jaw, plans)
    time_s[total] += jaw.robot_time() - t0
    time_s[transits] += max(spent.values(), default=0.0)
    return results
