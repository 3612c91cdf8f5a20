"""A paced Cartesian move (hand_driver.motion.move_line ``paced``) keeps the pad on its planned
lines where the joints would outrun their servos: the transit of P-series random block 1 of
bench_explore --finite 20 --anywhere --seed 157 (right pad from ψ 123° on the workspace edge,
turning along it to 81.5°) on the emulated P-series jaw. Unpaced, both joints ran at their
profile velocity, alike and opposite: the pad kept ψ 123° and slid 23 mm inside the edge,
onto the corner it had probed."""

from __future__ import annotations

import math

import numpy as np
import pytest

from hand_driver import kinematics as kin
from hand_driver.bus import JointBus
from hand_driver.config import load_config
from hand_driver.cycle import Jaw, LockstepClock, run_together
from hand_driver.motion import joint_steps, move_line, move_to
from hand_driver.sim.server import EmulatedBus
from recognizer.scene import load_scene

CONFIG = load_config("config/jaw-p.yaml")


def _edge(psi: float) -> float:
    ws = CONFIG.workspace
    return math.cos(psi) * ws.center_mm[0] + math.sin(psi) * ws.center_mm[1] - ws.radius_mm


@pytest.mark.parametrize("paced", [True, False])
def test_a_paced_turn_along_the_edge_keeps_the_pad_on_it(paced):
    scene = load_scene({"name": "empty", "classes": ["ellipse"]})
    vias = [math.radians(a) for a in (109.2, 95.3, 81.5)]
    with EmulatedBus(CONFIG, scene, time_scale=0.0) as sim:
        with JointBus(sim.port, CONFIG.bus.baudrate, CONFIG, retries=CONFIG.bus.retries, timeout_s=1.0) as bus:
            bus.set_goal_current(CONFIG.motion.goal_current_ma)
            bus.set_profile_raw(CONFIG.motion.profile_velocity, CONFIG.motion.profile_acceleration)
            jaw = Jaw(bus, CONFIG, None, clock=LockstepClock(sim))
            start = math.radians(123.0)
            q0 = jaw.solve("right", start, _edge(start), np.radians([-11.8, 44.8]))
            assert run_together(jaw, {"right": move_to(jaw, "right", q0)})["right"]
            passed = []

            def watch(motion):
                value = None
                while True:
                    try:
                        goal = motion.send(value)
                    except StopIteration as stop:
                        return stop.value
                    value = yield goal
                    passed.append(jaw.pad_line(value[0], "right"))

            move = move_line(jaw, "right", vias[-1], _edge(vias[-1]), via=[(a, _edge(a)) for a in vias[:-1]],
                             paced=paced)
            assert run_together(jaw, {"right": watch(move)})["right"]
    inside = max(float(p.d) - _edge(float(p.psi)) for p in passed)  # > 0: inside the workspace edge
    if paced:
        assert inside < 2.0  # 1.4: the chords between the edge lines, the servos' ramps
        assert np.all(joint_steps(jaw, "right") > 0)
    else:
        assert inside > 10.0  # 12.3 mm (23 mm onto the block in the bench run)
