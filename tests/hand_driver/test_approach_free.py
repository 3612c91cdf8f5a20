"""A guarded approach over a stretch the caller knows to be free runs faster, and still stops
on contact with the same force where the object turns out nearer than expected
(hand_driver.motion.guarded_approach's ``free_mm``), on both servo families."""

from __future__ import annotations

import math

import pytest

from hand_driver.bus import JointBus
from hand_driver.config import load_config
from hand_driver.cycle import Jaw, LockstepClock, run_together
from hand_driver.motion import FREE_SPEED_FACTOR, guarded_approach, move_line
from hand_driver.sim.server import EmulatedBus
from recognizer.scene import load_scene

SCENE = load_scene("config/scenes/default.yaml")  # ellipse a=28, b=17, theta=0.3 at (110, 0)


def _approach(config_path: str, free_mm: float):
    """The left pad faces down onto the ellipse's top from the workspace edge: the contact,
    and the robot time of the approach alone."""
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
            t0 = sim.sim_time
            result = run_together(jaw, {"left": guarded_approach(jaw, "left", psi, edge, 45.0, free_mm)})["left"]
            return result, sim.sim_time - t0, config.motion.goal_current_ma


@pytest.mark.parametrize("config_path", ["config/jaw.yaml", "config/jaw-p.yaml"])
def test_free_stretch_is_faster_and_a_nearer_object_still_stops_the_pad_as_gently(config_path):
    slow, t_slow, cap = _approach(config_path, 0.0)
    # the caller believed the whole 45 mm free: the object (26 mm in) is met at the fast speed,
    # the goal leading the pad by up to FREE_SPEED_FACTOR times the normal two steps
    fast, t_fast, _ = _approach(config_path, 45.0)
    assert slow.contact is not None and fast.contact is not None
    assert {slow.reason, fast.reason} <= {"current", "stall"}
    # the same contact line (the encoders' rounding apart), pressed within the goal current
    # (measured: 113 -> 213 mA on the X jaw, 112 -> 186 mA on the P jaw, cap 300 mA)
    assert fast.contact.d == pytest.approx(slow.contact.d, abs=0.05)
    assert fast.contact.current_ma <= cap
    # well under the normal speed's time (measured 1.16 -> 0.46 s on both jaws)
    assert t_fast < 0.75 * t_slow, (t_fast, t_slow, FREE_SPEED_FACTOR)
