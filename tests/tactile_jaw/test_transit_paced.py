"""A transit's turn along the pad lines keeps clear of the object (tactile_jaw.rounds.transit):
its Cartesian steps are paced so that no joint's goal outruns its servo's profile velocity
(hand_driver.motion.move_line, ``paced``). Unpaced, the P-series right finger after a roll
ending at ψ 121.5° beside a cubical's end asked its distal joint for ~2.2° a cycle per 1° of
pad turn, beyond the 2.75° a cycle its servo turns: both joints ran at that speed, alike and
opposite, the pad kept ψ and slid 10 mm along its normal back onto the object and stayed
wedged there, so every later roll of that finger met "no contact" (random P cubical 109 of
bench_explore --finite 20 --anywhere --seed 419: refused, no move named)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from hand_driver.bus import JointBus
from hand_driver.config import load_config
from hand_driver.cycle import Jaw, LockstepClock, run_together
from hand_driver.motion import _paced_fractions, joint_cycle_turns, move_to
from hand_driver.sim.server import EmulatedBus
from recognizer.curves import CURVES
from recognizer.scene import load_scene
from tactile_jaw.plan import ObjectModel
from tactile_jaw.rounds import transit

CONFIG = load_config("config/jaw-p.yaml")
PARAMS = {"a": 0.00100193324609733, "c": -0.5}
EXTENT = (-21.44553284690972, 1.7871277372424768)
POSE = {"theta": -3.009447528518562, "x": 94.40755315368767, "y": -36.32016640189216}
SCENE = {"name": "cubical109", "classes": ["cubical_parabola"],
         "object": {"class": "cubical_parabola", "params": PARAMS, "extent": list(EXTENT),
                    "closure": [[EXTENT[1], -17.871277372424768], [EXTENT[0], -17.871277372424768]],
                    "pose": POSE}}
Q_AFTER_ROLL = np.radians([-25.88, 57.38])  # the right pad backed off its roll's end, normal 121.5°
FELT_PSI = np.radians(np.arange(103.5, 121.6, 2.25))  # that roll's pad normals


def _support(psi: np.ndarray) -> np.ndarray:
    """The first pad line of each normal ψ that meets the exact curve (n(ψ)·p = d, min over p)."""
    x, y = CURVES["cubical_parabola"](PARAMS).point(np.linspace(*EXTENT, 4001))
    c, s = math.cos(POSE["theta"]), math.sin(POSE["theta"])
    px, py = POSE["x"] + c * x - s * y, POSE["y"] + s * x + c * y
    return np.min(np.cos(psi)[:, None] * px[None] + np.sin(psi)[:, None] * py[None], axis=1)


def test_the_joints_are_paced_at_the_profile_velocity():
    """2290 × 0.01 rev/min = 137.4 °/s, 20 ms a cycle: 2.75° a cycle for each P-series joint."""
    with EmulatedBus(CONFIG, load_scene(SCENE), time_scale=0.0) as sim:
        with JointBus(sim.port, CONFIG.bus.baudrate, CONFIG, retries=CONFIG.bus.retries, timeout_s=1.0) as bus:
            jaw = Jaw(bus, CONFIG, None, clock=LockstepClock(sim))
            turns = joint_cycle_turns(jaw, "right")
    assert np.degrees(turns) == pytest.approx([2.748, 2.748], abs=1e-3)


def test_the_turn_after_a_roll_does_not_slide_the_pad_back_onto_the_object(opened_jaw, rested_at, peak_current):
    config = CONFIG
    with opened_jaw(config, SCENE) as jaw:
        start = rested_at(jaw, "right", Q_AFTER_ROLL, 121.5)
        ws = config.workspace
        model = ObjectModel(ws.center_mm, ws.radius_mm)
        model.add(FELT_PSI, _support(FELT_PSI))
        assert float(start.d) < model.tangent(float(start.psi))[0] - 2.0  # the premise: clear of it
        peak, line = peak_current(jaw, "right", transit(jaw, "right", model, math.radians(66.0), hug=True))
    assert peak < config.motion.contact_current_ma  # never pressed on the object on the way
    assert math.degrees(float(line.psi)) == pytest.approx(66.0, abs=0.5)


def test_the_paced_turn_asks_each_cycle_for_about_what_the_servos_turn(opened_jaw):
    """A paced step that asked 1.3 cycles' turn of its fastest joint was split in two halves
    (0.65 each); now the turn's steps are spread along what each asks (motion._paced_fractions):
    the same path and the same limit, the transit to ψ 66° in 41 goals instead of 56 (the distal
    joint's 97.6° of path at 2.75° a cycle alone take 35.5)."""
    with opened_jaw(CONFIG, SCENE) as jaw:
        assert run_together(jaw, {"right": move_to(jaw, "right", Q_AFTER_ROLL)})["right"]
        ws = CONFIG.workspace
        model = ObjectModel(ws.center_mm, ws.radius_mm)
        model.add(FELT_PSI, _support(FELT_PSI))
        most = joint_cycle_turns(jaw, "right")
        goals: list[np.ndarray] = []

        def recorded(motion):
            goal = next(motion)
            try:
                while True:
                    if goal is not None:
                        goals.append(np.asarray(goal, dtype=float))
                    goal = motion.send((yield goal))
            except StopIteration as stop:
                return stop.value
        run_together(jaw, {"right": recorded(transit(jaw, "right", model, math.radians(66.0), hug=True))})
        line = jaw.pad_line(jaw.last_state, "right")
    assert math.degrees(float(line.psi)) == pytest.approx(66.0, abs=0.5)
    steps = np.abs(np.diff(np.array(goals), axis=0)) / most
    assert np.max(steps) <= 1.0 + 1e-6  # no joint's goal outruns its servo
    assert len(goals) <= 45


def test_paced_steps_are_spread_along_what_each_asks():
    """Three steps asking 1.3 cycles each: four even steps (not six halves); a step asking 2
    and one asking 0.5: three steps, the first two inside the first step's half of the move."""
    assert _paced_fractions(np.array([1 / 3, 2 / 3, 1.0]), np.array([1.3, 1.3, 1.3])) == pytest.approx(
        [0.25, 0.5, 0.75, 1.0])
    assert _paced_fractions(np.array([0.5, 1.0]), np.array([2.0, 0.5])) == pytest.approx(
        [0.5 * 2.5 / 6, 0.5 * 5 / 6, 1.0])
