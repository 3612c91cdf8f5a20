"""Guarded touches, rolling moves and faults against the emulated bus, through the real SDK."""

from __future__ import annotations

import math
from contextlib import contextmanager

import numpy as np
import pytest

from hand_driver import kinematics as kin
from hand_driver.bus import JointBus
from hand_driver.config import load_config
from hand_driver.errors import BusTimeout, CrcError, PortError, ServoHardwareError
from hand_driver.log import RunLog, read_log
from hand_driver.cycle import Jaw, LockstepClock, run_together
from hand_driver.motion import guarded_approach, move_line, rolling_touch
from hand_driver.sim.server import EmulatedBus
from recognizer.curves import CURVES
from recognizer.scene import load_scene

CONFIG = load_config("config/jaw.yaml")
SCENE = load_scene("config/scenes/default.yaml")  # ellipse a=28, b=17, theta=0.3 at (110, 0)


def ellipse_support(psi: float) -> float:
    """Exact support of the scene's ellipse for a pad with outward normal angle psi: the
    smallest n·p over the solid (closed form: n·c − |(a n_u, b n_v)| in the canonical frame)."""
    obj = SCENE.object
    n = np.array([math.cos(psi), math.sin(psi)])
    c, s = math.cos(obj.pose.theta), math.sin(obj.pose.theta)
    nu, nv = c * n[0] + s * n[1], -s * n[0] + c * n[1]
    return float(n @ [obj.pose.x, obj.pose.y]) - math.hypot(obj.params["a"] * nu, obj.params["b"] * nv)


def distance_to_ellipse(x, y) -> np.ndarray:
    obj = SCENE.object
    t = np.linspace(0, 2 * np.pi, 200001)
    px, py = obj.pose.apply(*CURVES["ellipse"](obj.params).point(t))
    return np.array([np.min(np.hypot(px - xi, py - yi)) for xi, yi in zip(x, y)])


@contextmanager
def emulated_jaw(scene=SCENE, log=None, on_reading=None, timeout_s=1.0, torque_off_arrives=False):
    """``torque_off_arrives``: before the emulator stops, wait (bounded) until the torque-off the
    bus wrote on closing has reached every servo — a write whose status is dropped still lands, but
    on a loaded host the emulator's thread may read it only after the bus has given up waiting."""
    with EmulatedBus(CONFIG, scene, time_scale=0.0) as sim:
        def hook(state):
            if log is not None:
                log.reading(state)
            if on_reading is not None:
                on_reading(sim, state)
        try:
            with JointBus(sim.port, CONFIG.bus.baudrate, CONFIG, retries=CONFIG.bus.retries, timeout_s=timeout_s,
                          on_reading=hook) as bus:
                bus.set_goal_current(CONFIG.motion.goal_current_ma)
                bus.set_profile_raw(CONFIG.motion.profile_velocity, CONFIG.motion.profile_acceleration)
                yield sim, Jaw(bus, CONFIG, log, clock=LockstepClock(sim), readings_logged_by_bus=log is not None)
        finally:
            if torque_off_arrives:
                sim.wait_until(lambda: not any(s.torque_on for s in sim.servos.values()), timeout=10.0)


def _edge(psi: float) -> float:
    ws = CONFIG.workspace
    return math.cos(psi) * ws.center_mm[0] + math.sin(psi) * ws.center_mm[1] - ws.radius_mm


def test_guarded_touch_stops_at_the_object():
    psi = -math.pi / 2  # the left pad faces down onto the top of the ellipse
    with emulated_jaw() as (sim, jaw):
        assert run_together(jaw, {"left": move_line(jaw, "left", psi, _edge(psi))})["left"]
        result = run_together(jaw, {"left": guarded_approach(jaw, "left", psi, _edge(psi), 45.0)})["left"]
        assert result.contact is not None and result.reason in ("current", "stall")
        # the pad line at contact is the ellipse's tangent: ±½ tick per joint moves it < 0.2 mm
        assert result.contact.d == pytest.approx(ellipse_support(psi), abs=0.2)
        assert abs(math.degrees(result.contact.psi_measured - psi)) < 0.2
        # it pressed gently: the current stayed at or below the goal current
        assert result.contact.current_ma <= CONFIG.motion.goal_current_ma + 3.0
        assert sim.sim_time < 2.5  # the move out, then 26 mm at 25 mm/s


def test_no_object_no_contact_is_a_result():
    empty = load_scene({"name": "empty", "classes": ["ellipse"]})
    psi = -math.pi / 2
    with emulated_jaw(scene=empty) as (sim, jaw):
        run_together(jaw, {"left": move_line(jaw, "left", psi, _edge(psi))})
        result = run_together(jaw, {"left": guarded_approach(jaw, "left", psi, _edge(psi), 30.0)})["left"]
    assert result.contact is None and result.reason == "no_contact"
    assert result.travel_mm == pytest.approx(30.0, abs=1.0)


def test_rolling_moves_of_both_fingers_follow_the_ellipse():
    span, n = math.radians(30.0), 9
    with emulated_jaw() as (sim, jaw):
        motions = {f: rolling_touch(jaw, f, k, psi, span, n, _edge(psi - span / 2), 45.0)
                   for k, (f, psi) in enumerate([("left", -math.pi / 2), ("right", math.pi / 2)])}
        touches = run_together(jaw, motions)
    for finger, psi0 in (("left", -math.pi / 2), ("right", math.pi / 2)):
        t = touches[finger]
        assert t.outcome == "ok" and len(t.samples) == n
        measured = np.array([s.psi_measured for s in t.samples])
        # the pad turned through the commanded orientations, 30/8 deg apart
        assert np.allclose(np.degrees(measured - (psi0 + np.linspace(-span / 2, span / 2, n))), 0.0, atol=0.3)
        # it ended backed off backoff_mm from its last contact, pressing nothing
        end = jaw.pad_line(jaw.last_state, finger)
        assert float(end.d) == pytest.approx(t.samples[-1].d - CONFIG.motion.backoff_mm, abs=0.3)
        assert jaw.finger_current(jaw.last_state, finger) < 20.0
        c = kin.touch_from_ticks(CONFIG, finger, np.array([s.ticks for s in t.samples]))
        # phi = psi - pi/2 increases with the roll; the envelope lies on the true ellipse
        assert np.all(np.diff(np.unwrap(c.phi)) > math.radians(3.0))
        assert np.all(np.diff(c.s) > 0)
        assert distance_to_ellipse(c.x, c.y).max() < 0.1


def _timed_move(jaw, finger, psi, d, **kw):
    """Robot time and result of one move_line, and every pad line it passed through."""
    passed = []

    def watch(motion):
        value = None
        while True:
            try:
                goal = motion.send(value)
            except StopIteration as stop:
                return stop.value
            value = yield goal
            passed.append(jaw.pad_line(value[0], finger))

    t0 = jaw.robot_time()
    reached = run_together(jaw, {finger: watch(move_line(jaw, finger, psi, d, **kw))})[finger]
    return jaw.robot_time() - t0, reached, passed


def test_move_line_keeps_its_speeds_per_second_and_passes_its_via_lines_without_stopping():
    """Out 20 mm along the pad normal, then turned 30° on the workspace edge: through a via
    line it takes less time than as two moves (no stop between them), ends on the same line,
    passes within 1 mm of the via line; at half the speeds the move takes about twice as long."""
    psi0, psi1 = -math.pi / 2, -math.pi / 2 + math.radians(30.0)
    out = (psi0, _edge(psi0) - 20.0)
    times = {}
    with emulated_jaw(scene=load_scene({"name": "empty", "classes": ["ellipse"]})) as (sim, jaw):
        for name, kw in (("two", None), ("via", {}), ("half", {"shift_mm_s": 0.5 * CONFIG.motion.move_speed_mm_s,
                                                               "turn_deg_s": 0.5 * CONFIG.motion.turn_speed_deg_s})):
            assert run_together(jaw, {"left": move_line(jaw, "left", psi0, _edge(psi0))})["left"]
            if kw is None:
                t_a, ok_a, _ = _timed_move(jaw, "left", *out)
                t_b, ok_b, _ = _timed_move(jaw, "left", psi1, _edge(psi1))
                times[name], reached = t_a + t_b, ok_a and ok_b
            else:
                times[name], reached, passed = _timed_move(jaw, "left", psi1, _edge(psi1), via=[out], **kw)
                gap = min(abs(float(p.d) - out[1]) + 50.0 * abs(float(p.psi) - psi0) for p in passed)
                assert gap < 1.0
            end = jaw.pad_line(jaw.last_state, "left")  # reached: every joint within REACHED_RAD
            assert reached and float(end.d) == pytest.approx(_edge(psi1), abs=0.7)
            assert float(end.psi) == pytest.approx(psi1, abs=math.radians(0.6))
    assert times["via"] < times["two"]
    assert 1.6 < times["half"] / times["via"] < 2.2
    # 20 mm at move_speed_mm_s, then 30 deg at turn_speed_deg_s (or the shift of the pad's
    # middle along the edge, whichever is slower), plus the servos' settling
    least = 20.0 / CONFIG.motion.move_speed_mm_s + 30.0 / CONFIG.motion.turn_speed_deg_s
    assert least - jaw.period_s < times["via"] < least + 1.0


@pytest.mark.parametrize("fault", ["timeout", "crc", "hardware", "vanish"])
def test_fault_mid_touch_keeps_every_reading_and_ends_torque_off(tmp_path, fault):
    taken: list = []
    arm_at = 40

    def inject(sim, state):
        taken.append(state.ticks.tolist())
        if len(taken) == arm_at:
            if fault == "timeout":
                sim.faults.drop_status(1000)
            elif fault == "crc":
                sim.faults.corrupt_status(1000)
            elif fault == "hardware":
                sim.hardware_error(1)
            else:
                sim.vanish()

    path = tmp_path / "run.jsonl"
    expected = {"timeout": BusTimeout, "crc": CrcError, "hardware": ServoHardwareError, "vanish": PortError}[fault]
    psi = -math.pi / 2
    servos = None
    with pytest.raises(expected):
        with RunLog(path).open(config={}, scene=None) as log:
            # a status timeout a loaded host meets (a late corrupt answer must stay a CRC error)
            with emulated_jaw(log=log, on_reading=inject, timeout_s=0.5,
                                  torque_off_arrives=fault != "vanish") as (sim, jaw):
                servos = sim.servos
                run_together(jaw, {"left": move_line(jaw, "left", psi, _edge(psi))})
                run_together(jaw, {"left": guarded_approach(jaw, "left", psi, _edge(psi), 45.0)})
    contents = read_log(path)
    # every reading taken before the fault is in the log, in order
    assert [r["ticks"] for r in contents.readings] == taken
    assert len(taken) >= arm_at
    assert contents.events[-1]["kind"] == "fault" and expected.__name__ in contents.events[-1]["message"]
    if fault != "vanish":  # a vanished adapter takes the torque-off packet with it
        assert all(not s.torque_on for s in servos.values())


def test_single_lost_packet_is_retried_within_the_bound():
    def inject(sim, state):
        if jaw_box and jaw_box[0].readings == 20:
            sim.faults.drop_status(1)

    jaw_box: list = []
    psi = -math.pi / 2
    with emulated_jaw(on_reading=inject) as (sim, jaw):
        jaw_box.append(jaw)
        run_together(jaw, {"left": move_line(jaw, "left", psi, _edge(psi))})
        result = run_together(jaw, {"left": guarded_approach(jaw, "left", psi, _edge(psi), 45.0)})["left"]
        assert jaw.bus.stats.retries >= 1
    assert result.contact is not None
    assert result.contact.d == pytest.approx(ellipse_support(psi), abs=0.2)
