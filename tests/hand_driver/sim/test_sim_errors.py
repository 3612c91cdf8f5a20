"""The errors a truth jaw declares, against exact geometry: backlash as a dead band that shows
when a joint's load reverses, link compliance under the joint torque, pad compliance under the
contact force; none declared, none simulated (hand_driver.sim.errors)."""

import dataclasses
import math

import numpy as np
import pytest

from hand_driver import kinematics as kin
from hand_driver.bus import JointBus
from hand_driver.config import load_config
from hand_driver.sim.server import EmulatedBus
from recognizer.curves import Pose
from recognizer.scene import SceneObject
from tactile_jaw.plan import open_pose

NOMINAL = load_config("config/jaw-p.yaml")
DISK = SceneObject("circle", {"r": 20.0}, Pose(0.0, 112.0, 6.0), "left")
HALF_DEG = 0.05  # half of the e-Manual's 0.1° band


def declared(cfg, backlash_deg=0.0, compliance=0.0, pad=0.0):
    fingers = tuple(dataclasses.replace(
        f, joints=tuple(dataclasses.replace(j, backlash_deg=backlash_deg, compliance_deg_per_nm=compliance)
                        for j in f.joints),
        pad=dataclasses.replace(f.pad, compliance_mm_per_n=pad)) for f in cfg.fingers)
    return dataclasses.replace(cfg, fingers=fingers)


def press_left(truth, goal_current_ma=300.0, settle_s=2.0, step_s=0.05, every=None):
    """The left pad closed onto the disk (its base joint commanded 20° toward it from the open
    pose: it touches after about 9.5°) at ``goal_current_ma``, the emulator stepped ``step_s`` at
    a time; returns (reading angles, link angles, emulator, reading). ``every(reading angles, link
    angles, emulator, reading)`` is called after each step."""
    cfg = NOMINAL
    q_open = open_pose(cfg)
    start = np.rint(kin.angles_to_ticks(cfg.joints, q_open)).astype(int)
    sim = EmulatedBus(cfg, scene=DISK, truth_config=truth, time_scale=0.0, initial_ticks=start.tolist())
    bus = JointBus(sim.port, 1_000_000, cfg, timeout_s=0.5, watchdog_ms=0, handle_signals=False)
    bus.open()
    try:
        bus.set_goal_current(goal_current_ma)
        goal = kin.angles_to_ticks(cfg.joints, q_open + np.radians([-20.0, 0.0, 0.0, 0.0]))
        bus.write_goal_ticks(np.rint(goal))
        for _ in range(int(round(settle_s / step_s))):
            sim.step(step_s)
            if every is not None:
                state = bus.read_state()
                every(kin.ticks_to_angles(cfg.joints, state.ticks), sim.link_angles(), sim, state)
        state = bus.read_state()
        reading = kin.ticks_to_angles(cfg.joints, state.ticks)
        return reading, sim.link_angles(), sim, state
    finally:
        bus.close()
        sim.stop()


def gap_to_disk(finger, q) -> float:
    """Distance from the disk's centre to the pad line, less the radius (0: tangent)."""
    line = kin.finger_pad_line(finger, q)
    return float(line.normal @ np.array([DISK.pose.x, DISK.pose.y]) - line.d) - DISK.params["r"]


def exact_arms(finger, q) -> np.ndarray:
    """Moment arms (m) of the pad's normal force at its exact tangent point on the disk."""
    line = kin.finger_pad_line(finger, q)
    point = np.array([DISK.pose.x, DISK.pose.y]) - DISK.params["r"] * line.normal
    return kin.moment_arms(finger, q, point, line.normal) / 1000.0


def test_none_declared_means_none():
    sim = EmulatedBus(NOMINAL, scene=DISK, time_scale=0.0)
    try:
        assert sim.errors is None
    finally:
        sim.stop()
    reading, link, _, _ = press_left(NOMINAL)
    left = NOMINAL.finger("left")
    assert np.allclose(reading, link, atol=2 * math.pi / kin.resolutions(NOMINAL.joints).min())
    # the pad rests on the disk: within a tick of tangent
    assert abs(gap_to_disk(left, link[:2])) < 2e-3


def test_backlash_bears_on_the_side_of_each_joints_load():
    truth = declared(NOMINAL, backlash_deg=2 * HALF_DEG)
    reading, link, sim, state = press_left(truth)
    left = NOMINAL.finger("left")
    assert sim.errors.force[0] > 1.0
    assert abs(gap_to_disk(left, link[:2])) < 2e-3  # the links touch the disk exactly
    arms = exact_arms(left, link[:2])
    tick = 2 * math.pi / kin.resolutions(NOMINAL.joints)[:2]
    h = math.radians(HALF_DEG)
    # each motor (encoder) leads its link by half the band, toward the side its torque pushes;
    # zero_tick is the link's zero under the working load, so the reading is the motor less w·h
    motor = reading[:2] + kin.working_loads(left) * h
    assert np.allclose(motor - link[:2], np.sign(arms) * h, atol=tick.max())
    # a press of the pad's face loads both joints the working way: the reading is the link
    assert np.all(np.sign(arms) == kin.working_loads(left))
    assert np.allclose(reading[:2], link[:2], atol=tick.max())
    assert np.allclose(kin.load_offsets(left, np.sign(arms)), 0.0)


def test_backlash_is_a_dead_band_when_the_motion_reverses():
    truth = declared(NOMINAL, backlash_deg=2 * HALF_DEG)
    cfg = NOMINAL
    q0 = open_pose(cfg)
    sim = EmulatedBus(cfg, truth_config=truth, time_scale=0.0,
                      initial_ticks=np.rint(kin.angles_to_ticks(cfg.joints, q0)).astype(int).tolist())
    try:
        with JointBus(sim.port, 1_000_000, cfg, timeout_s=0.5, watchdog_ms=0, handle_signals=False) as bus:
            w = kin.working_loads(cfg.finger("left"))[0] * math.radians(HALF_DEG)

            def move_to(deg):  # (motor, link) angles of the left base joint
                bus.write_goal_ticks(np.rint(kin.angles_to_ticks(cfg.joints, q0 + np.radians([deg, 0, 0, 0]))))
                for _ in range(20):
                    sim.step(0.05)
                return kin.ticks_to_angles(cfg.joints, bus.read_state().ticks)[0] + w, sim.link_angles()[0]

            m1, l1 = move_to(1.0)  # driven up: the motor leads by half the band
            assert m1 - l1 == pytest.approx(math.radians(HALF_DEG), abs=1e-5)
            m2, l2 = move_to(1.0 - 1.5 * HALF_DEG)  # back by less than the band: the link stays
            assert l2 == pytest.approx(l1, abs=1e-9) and m2 == pytest.approx(m1 - math.radians(1.5 * HALF_DEG), abs=1e-5)
            m3, l3 = move_to(0.5)  # back beyond it: the link follows, the motor now lags by half
            assert l3 - m3 == pytest.approx(math.radians(HALF_DEG), abs=1e-5)
            assert l1 - l3 == pytest.approx(math.radians(0.5 - 2 * HALF_DEG), abs=1e-5)
    finally:
        sim.stop()


def test_link_compliance_deflects_by_the_joint_torque():
    compliance = 0.2  # deg per N·m
    truth = declared(NOMINAL, compliance=compliance)
    reading, link, sim, state = press_left(truth, goal_current_ma=300.0)
    left = NOMINAL.finger("left")
    assert abs(gap_to_disk(left, link[:2])) < 2e-3
    arms = exact_arms(left, link[:2])
    # the contact force that explains the currents the driver reads (each joint's Kt)
    kt = np.array([j.spec.torque_nm_per_a for j in left.joints])
    direction = np.array([j.direction for j in left.joints])
    torque = kt * direction * state.current_ma[:2] / 1000.0
    force = max(0.0, float(arms @ torque) / float(arms @ arms))
    assert force > 1.0
    deflection = np.radians(compliance) * arms * force
    tick = 2 * math.pi / kin.resolutions(NOMINAL.joints)[:2]
    assert np.allclose(reading[:2] - link[:2], deflection, atol=3 * tick.max() + 0.02 * np.abs(deflection).max())


def test_declared_compliance_reads_one_instants_torque_balance():
    """A pad pressed on a fixed face (the disk), with backlash, link and pad compliance declared:
    every reading in contact, from the first, is one instant's torque balance. Its currents are
    the contact force's torques, Kt_j·I_j = a_j·F (a_j the exact moment arms at the tangent point)
    within the current's resolution; its encoders lead the links by sign(τ)·h + c·τ with τ = Kt·I,
    within a tick; the nominal pad line lies k·F inside the disk. (Before: the currents were the
    servos' position lag, (300, −14) mA against a balance of (270, 117), and the deflection was
    that of the previous packet's currents, 8–15 ticks off.)"""
    c_deg, k, half = 0.02, 0.002, HALF_DEG
    truth = declared(NOMINAL, backlash_deg=2 * half, compliance=c_deg, pad=k)
    left = NOMINAL.finger("left")
    kt = np.array([j.spec.torque_nm_per_a for j in left.joints])
    direction = np.array([j.direction for j in left.joints])
    resolution = kt * np.array([j.spec.current_unit_ma for j in left.joints]) / 1000.0  # N·m per current unit
    tick = 2 * math.pi / kin.resolutions(NOMINAL.joints)[:2]
    forces = []

    def check(reading, link, sim, state):
        if sim.errors.force[0] <= 0.0:
            return
        arms = exact_arms(left, link[:2])
        torque = kt * direction * np.asarray(state.current_ma[:2], dtype=float) / 1000.0
        force = float(arms @ torque) / float(arms @ arms)
        forces.append(force)
        assert np.all(np.abs(torque - arms * force) <= resolution)
        motor = reading[:2] + kin.working_loads(left) * math.radians(half)
        lead = np.sign(arms) * math.radians(half) + math.radians(c_deg) * torque
        assert np.all(np.abs(motor - link[:2] - lead) <= tick + math.radians(c_deg) * resolution)
        assert gap_to_disk(left, link[:2]) == pytest.approx(-k * force, abs=1e-4)

    press_left(truth, settle_s=0.6, step_s=0.02, every=check)
    assert len(forces) >= 5 and max(forces) > 5.0  # pressed, at several forces on the way up


def test_pad_compliance_puts_the_pad_line_into_the_object_by_the_give():
    k = 0.01  # mm per N
    truth = declared(NOMINAL, pad=k)
    reading, link, sim, state = press_left(truth, goal_current_ma=600.0)
    left = NOMINAL.finger("left")
    force = float(sim.errors.force[0])
    assert force > 2.0
    # no joint error declared: the encoders are the links; the nominal pad line is k·F inside the disk
    assert np.allclose(reading, link, atol=1e-5)
    assert gap_to_disk(left, link[:2]) == pytest.approx(-k * force, abs=2e-3)
    # at the angle the pad would have without the give (the give moves the line along its normal)
    rigid = sim.errors.world_angles(link)
    assert gap_to_disk(left, rigid[:2]) == pytest.approx(0.0, abs=2e-3)
    assert kin.finger_pad_line(left, rigid[:2]).psi == pytest.approx(float(kin.finger_pad_line(left, link[:2]).psi),
                                                                      abs=1e-9)


def test_truth_config_declares_the_e_manual_backlash_and_a_zero_error_per_joint(tmp_path):
    from hand_driver.config import config_to_mapping, declares_errors, dump_config

    truth = load_config("config/jaw-p-truth.yaml")
    assert declares_errors(truth) and not declares_errors(NOMINAL)
    for j, n in zip(truth.joints, NOMINAL.joints):
        assert j.model == n.model and j.backlash_deg == j.spec.backlash_deg == 0.1
        assert 0.05 <= abs(j.zero_tick - n.zero_tick) * 360.0 / j.ticks_per_rev <= 0.15
    # declared errors round-trip; a config without them is written as before
    dump_config(truth, tmp_path / "t.yaml")
    assert load_config(tmp_path / "t.yaml") == truth
    assert all("backlash_deg" not in j for f in config_to_mapping(NOMINAL)["fingers"] for j in f["joints"])
