"""The Bus Watchdog through the driver: armed on open, fed by every cycle, stopping the jaw
when its host is killed, cleared by the next open, re-armed after a pause of the host."""

from __future__ import annotations

import logging
import subprocess
import sys
import textwrap
import time

import numpy as np
import pytest

from hand_driver.bus import JointBus
from hand_driver.config import load_config
from hand_driver.cycle import Jaw, LockstepClock, run_together
from hand_driver.motion import move_to
from hand_driver.sim.server import EmulatedBus

#: the host process: arms the watchdog on open, moves servo 1 slowly toward tick 3000 and
#: keeps cycling (read, write) every 20 ms, printing the position, until it is killed
HOST = textwrap.dedent("""
    import sys, time
    from hand_driver.bus import JointBus
    from hand_driver.config import JointConfig
    joint = JointConfig(1, "XM430-W350", 2048, 50.0)
    with JointBus(sys.argv[1], 1_000_000, [joint], timeout_s=0.5, watchdog_ms=100) as bus:
        bus.set_profile_raw(20, 0)  # 4.6 rev/min: about 3 s to tick 3000
        while True:
            bus.write_goal_ticks([3000])
            print(int(bus.read_state().ticks[0]), flush=True)
            time.sleep(0.02)
""")


def test_open_arms_every_servo_and_close_disarms(bus_joints):
    # simulated time stands still (time_scale 0): the test's own pauses cannot expire it
    with EmulatedBus(bus_joints, time_scale=0.0) as sim:
        with JointBus(sim.port, 1_000_000, bus_joints, timeout_s=0.25) as bus:
            sim.wait_idle()
            assert bus.watchdog_ms == 100
            assert [s.get("bus_watchdog") for s in sim.servos.values()] == [5, 5, 5]  # 5 × 20 ms
        assert sim.wait_until(lambda: [(s.get("bus_watchdog"), s.torque_on) for s in sim.servos.values()]
                              == [(0, False)] * 3)


def test_killed_host_stops_the_jaw_and_the_next_open_clears_it(make_joint, caplog):
    joint = make_joint(1)
    with EmulatedBus([joint]) as sim:
        host = subprocess.Popen([sys.executable, "-c", HOST, sim.port], stdout=subprocess.PIPE, text=True)
        try:
            deadline = time.monotonic() + 60.0
            while int(host.stdout.readline() or 0) < 2048 + 150:  # moving
                assert time.monotonic() < deadline and host.poll() is None, "the host never got the servo moving"
            host.kill()
            t_kill = sim.now()
            host.wait(timeout=10)
        finally:
            host.kill()
        time.sleep(0.5)
        sim.advance_to_now()
        s = sim.servos[1]
        assert s.watchdog_tripped_at is not None
        assert s.watchdog_tripped_at - s.last_rx == pytest.approx(0.1, abs=1e-9)  # 100 ms after the last packet
        assert s.watchdog_tripped_at - t_kill < 0.1 + 0.05  # a packet may still be in the pty at the kill
        stopped = s.pos
        assert 2048 + 150 < stopped < 2900 and s.torque_on and s.get("bus_watchdog") == -1
        time.sleep(0.3)
        sim.advance_to_now()
        assert s.pos == stopped  # holds there
        with caplog.at_level(logging.WARNING, logger="hand_driver.bus"):
            with JointBus(sim.port, 1_000_000, [joint], timeout_s=0.5) as bus:
                assert "Bus Watchdog had stopped it" in caplog.text
                sim.wait_idle()
                assert s.get("bus_watchdog") == 5
                bus.set_profile_raw(0, 0)
                bus.write_goal_ticks([2100])
                deadline = time.monotonic() + 5.0
                while abs(int(bus.read_state().ticks[0]) - 2100) > 1 and time.monotonic() < deadline:
                    time.sleep(0.02)
                assert abs(int(bus.read_state().ticks[0]) - 2100) <= 1


def test_the_jaw_rearms_the_watchdog_after_a_pause_of_the_host():
    cfg = load_config("config/jaw.yaml")
    with EmulatedBus(cfg, time_scale=0.0) as sim, \
            JointBus(sim.port, cfg.bus.baudrate, cfg, timeout_s=1.0, handle_signals=False) as bus:
        jaw = Jaw(bus, cfg, clock=LockstepClock(sim))
        finger = cfg.fingers[0]
        q0 = jaw.finger_q(jaw.last_state, finger.name)
        sim.advance(1.0)  # the host thinks for 1 s (a recognition): every servo's watchdog expires
        assert all(s.get("bus_watchdog") == -1 for s in sim.servos.values())
        goal = q0 + np.radians([5.0, 5.0])
        reached = run_together(jaw, {finger.name: move_to(jaw, finger.name, goal)})
        assert reached == {finger.name: True}
        assert all(s.get("bus_watchdog") == 5 for s in sim.servos.values())


def test_watchdog_time_is_a_config_key(tmp_path):
    text = open("config/jaw.yaml").read().replace("watchdog_ms: 100", "watchdog_ms: 260")
    (tmp_path / "jaw.yaml").write_text(text)
    cfg = load_config(tmp_path / "jaw.yaml")
    assert cfg.bus.watchdog_ms == 260
    with EmulatedBus(cfg, time_scale=0.0) as sim, JointBus.for_config(cfg, sim.port, timeout_s=0.5, handle_signals=False):
        sim.wait_idle()
        assert [s.get("bus_watchdog") for s in sim.servos.values()] == [13] * 4  # 260 ms / 20 ms
    (tmp_path / "bad.yaml").write_text(text.replace("260", "250"))
    with pytest.raises(Exception, match="watchdog_ms: 250 is not a multiple of 20 ms"):
        load_config(tmp_path / "bad.yaml")


def test_default_watchdog_stretches_to_two_slow_cycles_but_an_explicit_one_must_fit():
    from hand_driver.config import parse_config
    from tactile_common.yamlfile import read_yaml

    raw = read_yaml("config/jaw.yaml", "jaw config")
    raw["motion"]["approach_speed_mm_s"] = 2.0  # 0.5 mm steps: a 250 ms cycle
    with pytest.raises(Exception, match="bus.watchdog_ms: 100 ms is less than two motion cycles"):
        parse_config(raw)
    del raw["bus"]["watchdog_ms"]
    assert parse_config(raw).bus.watchdog_ms == 500
