"""The jaw's bus cycle: robot clocks, the :class:`Jaw` the motions act through, and
:func:`run_together`, which steps one motion per finger in shared cycles.

A motion (hand_driver.motion) is a generator that yields the finger's next goal joint
angles (or ``None`` to hold) and receives each cycle's reading. One cycle is one sync write
of every goal, one sync read of every joint (logged), and a wait of one cycle period,
``motion.approach_step_mm / motion.approach_speed_mm_s`` of robot time, on a
:class:`WallClock` (a real jaw) or a :class:`LockstepClock` (the emulated bus, stepped by
the cycles).
"""

from __future__ import annotations

import math
import time
from typing import Any, Generator

import numpy as np

from hand_driver import kinematics as kin
from hand_driver.bus import WATCHDOG_REARM_FRACTION
from hand_driver.config import JawConfig
from tactile_common.angles import wrap_angle

#: joint-limit margin kept by every goal (rad): 1°
LIMIT_MARGIN_RAD = math.radians(1.0)

Reading = tuple[Any, int]  # (JointState, log index)
Motion = Generator[np.ndarray | None, Reading, Any]


class WallClock:
    """Robot time is wall time × ``time_scale`` (1 for a real jaw; an emulator's time
    scale when it runs on the wall clock); a cycle waits by sleeping."""

    def __init__(self, time_scale: float = 1.0):
        self.time_scale = float(time_scale)
        self._t0 = time.monotonic()
        self._next = self._t0

    def now(self) -> float:
        return (time.monotonic() - self._t0) * self.time_scale

    def wait(self, period_s: float) -> None:
        """Sleep until ``period_s`` robot seconds after the previous wait ended."""
        self._next += period_s / self.time_scale
        now = time.monotonic()
        if self._next > now:
            time.sleep(self._next - now)
        else:
            self._next = now


class LockstepClock:
    """Robot time is an emulated bus's simulated time, advanced only by the cycles:
    the bus runs with ``time_scale=0`` and each wait integrates ``period_s`` of motion
    (hand_driver.sim.server.EmulatedBus.advance). A cycle's write is served before the
    wait, because the cycle's read comes between them. Robot time is exact and the motion the same on any host;
    wall time is only the computation."""

    def __init__(self, sim):
        if sim.time_scale != 0.0:
            raise ValueError("LockstepClock needs an EmulatedBus with time_scale=0")
        self.sim = sim

    def now(self) -> float:
        return float(self.sim.sim_time)

    def wait(self, period_s: float) -> None:
        self.sim.advance(period_s)


class Jaw:
    """The bus, the config, the log and the robot clock, as the motions see them.

    ``bus`` has ``read_state()`` and ``write_goal_ticks(ticks)`` over the config's joints
    in config order (hand_driver.bus.JointBus); ``clock`` a :class:`WallClock` or a
    :class:`LockstepClock`. ``readings_logged_by_bus``: the bus already passes every reading
    to ``log.reading`` (its ``on_reading`` hook), so the jaw only looks up the index."""

    def __init__(self, bus, config: JawConfig, log=None, clock=None, readings_logged_by_bus: bool = False):
        self.bus = bus
        self.config = config
        self.log = log
        self.clock = clock if clock is not None else WallClock()
        self.readings_logged_by_bus = readings_logged_by_bus
        self.slices = config.joint_slices()
        self.period_s = config.motion.approach_step_mm / config.motion.approach_speed_mm_s
        self.readings = 0
        self.last_index = -1
        self._t0 = self.clock.now()
        self._last_io = self._t0  # robot time of the last cycle on the bus (Bus Watchdog)
        state, _ = self.read()
        self.goal_ticks = np.asarray(state.ticks, dtype=np.int64).copy()
        self.last_state = state

    # -- clock ------------------------------------------------------------------------------
    def robot_time(self) -> float:
        """Robot seconds since the jaw was set up."""
        return self.clock.now() - self._t0

    def pace(self) -> None:
        """Wait one cycle period of robot time."""
        self.clock.wait(self.period_s)

    # -- bus --------------------------------------------------------------------------------
    def read(self) -> Reading:
        self._last_io = self.clock.now()
        state = self.bus.read_state()
        self.readings += 1
        if self.log is None:
            i = self.readings - 1
        elif self.readings_logged_by_bus:
            i = self.log.readings - 1
        else:
            i = self.log.reading(state)
        self.last_state, self.last_index = state, i
        return state, i

    def log_index(self) -> int:
        """Index of the last reading taken."""
        return self.last_index

    def set_goal(self, finger: str, q) -> None:
        f = self.config.finger(finger)
        self.goal_ticks[self.slices[finger]] = np.rint(kin.angles_to_ticks(f.joints, q)).astype(np.int64)

    def write_goals(self) -> None:
        """Every goal in one write; after a pause of the host close to the Bus Watchdog's
        time (the servos may have stopped and refuse goals) the watchdog is re-armed first."""
        now = self.clock.now()
        if self.bus.watchdog_ms and now - self._last_io > WATCHDOG_REARM_FRACTION * self.bus.watchdog_ms / 1000.0:
            self.bus.rearm_watchdog()
        self._last_io = now
        self.bus.write_goal_ticks([int(t) for t in self.goal_ticks])

    # -- geometry ---------------------------------------------------------------------------
    def finger_ticks(self, state, finger: str) -> np.ndarray:
        return np.asarray(state.ticks, dtype=float)[self.slices[finger]]

    def finger_q(self, state, finger: str) -> np.ndarray:
        return kin.ticks_to_angles(self.config.finger(finger).joints, self.finger_ticks(state, finger))

    def pad_line(self, state, finger: str) -> kin.PadLine:
        return kin.finger_pad_line_from_ticks(self.config, finger, self.finger_ticks(state, finger))

    def finger_current(self, state, finger: str) -> float | None:
        """Largest |present current| (mA) over the finger's joints; None without sensing."""
        if state.current_ma is None:
            return None
        values = [abs(float(c)) for c in np.asarray(state.current_ma, dtype=object)[self.slices[finger]]
                  if c is not None]
        return max(values) if values else None

    def solve(self, finger: str, psi: float, d: float, q_ref) -> np.ndarray:
        """Joint angles for the pad line (ψ, d) nearest ``q_ref``; kin.Unreachable if none."""
        f = self.config.finger(finger)
        sols = [q for q in kin.ik_line_solutions(f, psi, d) if kin.within_limits(f.joints, q, LIMIT_MARGIN_RAD)]
        if not sols:
            raise kin.Unreachable(f"finger {finger}: pad line psi={math.degrees(psi):.1f} deg, d={d:.1f} mm "
                                  f"is outside the joint limits")
        return min(sols, key=lambda q: float(np.sum(np.square(wrap_angle(q - q_ref)))))


# --------------------------------------------------------------------------------- running


def run_together(jaw: Jaw, motions: dict[str, Motion]) -> dict[str, Any]:
    """Run one motion per finger in shared cycles until all have returned; their
    return values by finger. A fault propagates at once (the bus turns torque off)."""
    results: dict[str, Any] = {}
    active = dict(motions)

    def advance(name: str, value) -> None:
        try:
            goal = active[name].send(value)
        except StopIteration as stop:
            results[name] = stop.value
            del active[name]
            return
        if goal is not None:
            jaw.set_goal(name, goal)

    for name in list(active):
        advance(name, None)
    while active:
        jaw.write_goals()
        reading = jaw.read()
        jaw.pace()
        for name in list(active):
            advance(name, reading)
    return results
