"""Shared fixtures: real config objects (never stand-ins) and the emulated servo bus."""

from __future__ import annotations

import math
from contextlib import contextmanager

import numpy as np
import pytest

from hand_driver import kinematics as kin
from hand_driver.bus import JointBus
from hand_driver.config import JawConfig, JointConfig, load_config
from hand_driver.cycle import Jaw, LockstepClock, run_together
from hand_driver.motion import move_to
from hand_driver.sim.server import EmulatedBus
from recognizer.scene import load_scene
from tactile_jaw.plan import open_pose


def _joint(id: int, model: str = "XM430-W350", zero_tick: float = 2048.0, direction: int = 1,
           min_deg: float = -90.0, max_deg: float = 90.0, current_limit_ma: float = 1000.0,
           link_mm: float = 50.0) -> JointConfig:
    return JointConfig(id=id, model=model, zero_tick=zero_tick, link_mm=link_mm, direction=direction,
                       min_deg=min_deg, max_deg=max_deg, current_limit_ma=current_limit_ma)


@pytest.fixture(scope="session")
def make_joint():
    """A JointConfig with defaults for what a test does not care about (link 50 mm, ±90°)."""
    return _joint


@pytest.fixture(scope="session")
def bus_joints() -> tuple[JointConfig, ...]:
    """Three servos of two models: id 1 XM430 (±90°), id 2 XM430 turning the other way
    (−45°..30°), id 3 XC330-T288 about tick 1500 (ticks 1000..2000)."""
    return (_joint(1, current_limit_ma=500.0),
            _joint(2, direction=-1, min_deg=-45.0, max_deg=30.0, current_limit_ma=500.0),
            _joint(3, "XC330-T288", zero_tick=1500.0, min_deg=-500 * 360 / 4096, max_deg=500 * 360 / 4096,
                   current_limit_ma=400.0))


@pytest.fixture
def sim(bus_joints):
    """The emulated bus of ``bus_joints`` in real time, stopped after the test."""
    with EmulatedBus(bus_joints) as s:
        yield s


@pytest.fixture(scope="session")
def jaw_config() -> JawConfig:
    """The repository's jaw config (config/jaw.yaml)."""
    return load_config("config/jaw.yaml")


@pytest.fixture
def opened_jaw():
    """``with opened_jaw(config, scene) as jaw``: the emulated jaw ``config`` in lockstep
    (no real time), its fingers at the opened pose (tactile_jaw.plan.open_pose) beside the
    scene mapping's object, Goal Current and the profile set from ``config.motion`` as the
    exploration sets them."""
    @contextmanager
    def opened(config: JawConfig, scene: dict):
        ticks = np.rint(kin.angles_to_ticks(config.joints, open_pose(config))).astype(int).tolist()
        with EmulatedBus(config, load_scene(scene), time_scale=0.0, initial_ticks=ticks) as sim:
            with JointBus(sim.port, config.bus.baudrate, config, retries=config.bus.retries, timeout_s=1.0) as bus:
                bus.set_goal_current(config.motion.goal_current_ma)
                bus.set_profile_raw(config.motion.profile_velocity, config.motion.profile_acceleration)
                yield Jaw(bus, config, None, clock=LockstepClock(sim))
    return opened


@pytest.fixture
def peak_current():
    """``run(jaw, finger, motion) -> (peak, line)``: ``motion`` (a generator of joint goals for
    tactile_jaw.rounds / hand_driver.cycle.run_together) run to its end for ``finger``, with the
    largest |current| (mA) the finger drew on the way and its pad line where it ended."""
    def run(jaw, finger: str, motion):
        peak = 0.0

        def watched():
            nonlocal peak
            goal = next(motion)
            try:
                while True:
                    state, i = yield goal
                    peak = max(peak, abs(jaw.finger_current(state, finger) or 0.0))
                    goal = motion.send((state, i))
            except StopIteration as stop:
                return stop.value
        run_together(jaw, {finger: watched()})
        return peak, jaw.pad_line(jaw.last_state, finger)
    return run


@pytest.fixture
def rested_at():
    """``rest(jaw, finger, q, psi_deg) -> line``: ``finger`` moved to joint angles ``q`` (reached),
    its pad normal within 0.3° of ``psi_deg`` and drawing less than the contact current there
    (the premise of a transit test: the pad off the object), its pad line returned."""
    def rest(jaw, finger: str, q, psi_deg: float):
        assert run_together(jaw, {finger: move_to(jaw, finger, q)})[finger]
        line = jaw.pad_line(jaw.last_state, finger)
        assert math.degrees(float(line.psi)) == pytest.approx(psi_deg, abs=0.3)
        assert (jaw.finger_current(jaw.last_state, finger) or 0.0) < jaw.config.motion.contact_current_ma
        return line
    return rest
