"""A guarded approach over a stretch the caller knows to be free runs faster, and still stops
on contact with the same force where the object turns out nearer than expected
(hand_driver.motion.guarded_approach's ``free_mm``), on both servo families; such a contact,
met at speed, is taken again at the normal speed, so it reads as the slow approach's does
even on jaws with backlash (the probes approach this way all the way)."""

from __future__ import annotations

import contextlib
import math

import pytest

from hand_driver.bus import JointBus
from hand_driver.config import load_config
from hand_driver.cycle import Jaw, LockstepClock, run_together
from hand_driver.motion import FREE_SPEED_FACTOR, guarded_approach, move_line
from hand_driver.sim.server import EmulatedBus
from recognizer.scene import load_scene

SCENE = load_scene("config/scenes/default.yaml")  # ellipse a=28, b=17, theta=0.3 at (110, 0)


@contextlib.contextmanager
def _left_pad_above_ellipse(config_path: str):
    """The left pad at the workspace edge, facing down onto the ellipse's top: (jaw, emulator,
    config, ψ, the edge's offset along ψ)."""
    config = load_config(config_path)
    ws = config.workspace
    psi = -math.pi / 2
    edge = math.cos(psi) * ws.center_mm[0] + math.sin(psi) * ws.center_mm[1] - ws.radius_mm
    with EmulatedBus(config, SCENE, time_scale=0.0) as sim:
        with JointBus(sim.port, config.bus.baudrate, config, retries=config.bus.retries, timeout_s=1.0) as bus:
            if config.fingers[0].joints[0].spec.guard_mode in config.fingers[0].joints[0].spec.current_capped_modes:
                bus.set_goal_current(config.motion.goal_current_ma)
            bus.set_profile_raw(config.motion.profile_velocity, config.motion.profile_acceleration)
            jaw = Jaw(bus, config, None, clock=LockstepClock(sim))
            assert run_together(jaw, {"left": move_line(jaw, "left", psi, edge)})["left"]
            yield jaw, sim, config, psi, edge


def _approach(config_path: str, free_mm: float):
    """The left pad's approach onto the ellipse's top from the workspace edge: the contact,
    and the robot time of the approach alone."""
    with _left_pad_above_ellipse(config_path) as (jaw, sim, config, psi, edge):
        t0 = sim.sim_time
        result = run_together(jaw, {"left": guarded_approach(jaw, "left", psi, edge, 45.0, free_mm)})["left"]
        return result, sim.sim_time - t0, config.motion.goal_current_ma


def _readings_at_speed(config_path: str, free_mm: float):
    """Every reading of the fast stretch up to the first contact (current and pad offset),
    by stepping the approach by hand: (the peak current of any joint, that cycle's offset)."""
    peak = 0.0
    with _left_pad_above_ellipse(config_path) as (jaw, sim, config, psi, edge):
        motion = guarded_approach(jaw, "left", psi, edge, 45.0, free_mm)
        goal = motion.send(None)
        try:
            while True:
                if goal is not None:
                    jaw.set_goal("left", goal)
                jaw.write_goals()
                reading = jaw.read()
                jaw.pace()
                peak = max(peak, jaw.finger_current(reading[0], "left") or 0.0)
                goal = motion.send(reading)
        except StopIteration as stop:
            return stop.value, peak, config.motion.goal_current_ma


@pytest.mark.parametrize("config_path", ["config/jaw.yaml", "config/jaw-p.yaml", "config/jaw-truth.yaml",
                                         "config/jaw-p-truth.yaml"])
def test_free_stretch_is_faster_and_a_nearer_object_still_stops_the_pad_as_gently(config_path):
    slow, t_slow, cap = _approach(config_path, 0.0)
    # the caller believed the whole 45 mm free: the object (26 mm in) is met at the fast speed,
    # the goal leading the pad by up to FREE_SPEED_FACTOR times the normal two steps, then
    # taken again from backoff_mm out at the normal speed
    fast, t_fast, _ = _approach(config_path, 45.0)
    assert slow.contact is not None and fast.contact is not None
    assert {slow.reason, fast.reason} <= {"current", "stall"}
    # the same contact line, on the truth jaws with backlash too (taken at speed it read 0.07
    # and 0.12 mm off there; taken again: measured 0.0008 mm on the P truth jaw, 0 elsewhere)
    assert fast.contact.d == pytest.approx(slow.contact.d, abs=0.005)
    assert fast.contact.current_ma <= cap
    # well under the normal speed's time (measured 1.14-1.16 -> 0.72-0.80 s)
    assert t_fast < 0.75 * t_slow, (t_fast, t_slow, FREE_SPEED_FACTOR)


@pytest.mark.parametrize("config_path", ["config/jaw.yaml", "config/jaw-p.yaml"])
def test_every_cycle_at_speed_stays_under_the_goal_current(config_path):
    # every reading of the approach, the fast stretch's first contact included (measured
    # 213 mA on the X jaw, 186 mA on the P jaw), under the goal current that caps the force
    result, peak, cap = _readings_at_speed(config_path, 45.0)
    assert result.contact is not None
    assert 0.0 < peak <= cap, (peak, cap)
