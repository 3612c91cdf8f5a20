"""``tactile sim`` and ``tactile scan`` as a user runs them.

The emulator runs in another process on a host shared with the other tests: the tests wait
for what they need (the log's first readings, every servo listed) within bounded, generous
deadlines instead of sleeping a fixed time or expecting the SDK's 34 ms status timeout to
be met by a starved emulator."""

import json
import signal
import subprocess
import sys
import time
from dataclasses import replace

import pytest

from hand_driver.config import JointConfig, dump_config
from hand_driver.sim.server import EmulatedBus
from recognizer.scene import load_scene


def tactile(*args, **kw):
    return subprocess.run([sys.executable, "-m", "tools.cli", *args], capture_output=True, text=True, timeout=60, **kw)


def scan(port, ids, want, *flags, scans=3):
    """``tactile scan`` until it lists ``want`` servos (at most ``scans`` scans): a servo
    that is there but answered late on a loaded host is scanned again, one that is never
    listed fails the test. Returns the last scan's output."""
    for _ in range(scans):
        out = tactile("scan", "--port", port, "--ids", ids, *flags)
        assert out.returncode == 0, out.stderr
        listed = len(json.loads(out.stdout)["servos"]) if "--json" in flags else len(out.stdout.splitlines()) - 1
        if listed >= want:
            break
    return out


def wait_for_readings(log, n, proc, deadline_s=60.0):
    """Wait until the run log holds ``n`` joint readings (the bus is open and cycling);
    fails at once, with its errors, if ``proc`` ends first."""
    deadline = time.monotonic() + deadline_s
    while time.monotonic() < deadline:
        if log.exists() and log.read_text().count('"type":"reading"') >= n:
            return
        if proc.poll() is not None:
            raise AssertionError(f"the run ended (exit {proc.returncode}) before {n} readings: {proc.stderr.read()}")
        time.sleep(0.05)
    raise AssertionError(f"{log}: fewer than {n} readings after {deadline_s:g} s")


@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGINT])
def test_sim_prints_port_first_and_exits_cleanly_on_signal(sig):
    proc = subprocess.Popen([sys.executable, "-m", "tools.cli", "sim", "--scene", "config/scenes/default.yaml"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        port = proc.stdout.readline().strip()
        assert port.startswith("/dev/")
        servos = json.loads(scan(port, "1-5", 4, "--json").stdout)["servos"]
        assert [(s["id"], s["model"], s["model_number"]) for s in servos] == [(i, "XM430-W350", 1020) for i in (1, 2, 3, 4)]
        proc.send_signal(sig)
        assert proc.wait(timeout=30) == 0
    finally:
        proc.kill()
        proc.wait()


def test_sim_of_the_p_series_jaw_scans_as_p_series_servos():
    proc = subprocess.Popen([sys.executable, "-m", "tools.cli", "sim", "--config", "config/jaw-p.yaml"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        port = proc.stdout.readline().strip()
        servos = json.loads(scan(port, "1-5", 4, "--json").stdout)["servos"]
        assert [(s["id"], s["model"], s["model_number"]) for s in servos] == [
            (1, "PH54-100-S500-R", 2010), (2, "PH42-020-S300-R", 2000), (3, "PH54-100-S500-R", 2010),
            (4, "PH42-020-S300-R", 2000)]
        table = scan(port, "1-2", 2).stdout.splitlines()
        assert table[1].split() == ["1", "PH54-100-S500-R", "2010", "46", "1000000"]
        proc.send_signal(signal.SIGTERM)
        assert proc.wait(timeout=30) == 0
    finally:
        proc.kill()
        proc.wait()


def test_scan_table_and_errors():
    with EmulatedBus([JointConfig(7, "XC330-M288", 2048, 50.0)]) as sim:
        out = scan(sim.port, "5-8", 1)
        assert out.stdout.splitlines()[1].split() == ["7", "XC330-M288", "1240", "46", "1000000"]
    out = tactile("scan", "--port", "/dev/no-such-adapter")
    assert out.returncode == 1 and "cannot open serial port /dev/no-such-adapter" in out.stderr
    assert "Traceback" not in out.stderr
    out = tactile("scan", "--port", "/dev/null", "--ids", "3-x")
    assert out.returncode == 2 and "--ids" in out.stderr


def test_bus_vanishing_during_explore_is_one_error_line(jaw_config, tmp_path):
    # the jaw's own config but a status timeout a starved emulator meets (the config's 50 ms
    # is for hardware): the run must end on the vanished adapter, not on a late answer
    config = tmp_path / "jaw.yaml"
    dump_config(replace(jaw_config, bus=replace(jaw_config.bus, timeout_s=1.0)), config)
    with EmulatedBus(jaw_config, load_scene("config/scenes/default.yaml")) as sim:
        proc = subprocess.Popen([sys.executable, "-m", "tools.cli", "explore", "--port", sim.port, "--config", str(config),
                                 "--log", str(tmp_path / "run.jsonl")],
                                stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        try:
            assert "exploring" in proc.stderr.readline() + proc.stderr.readline()
            wait_for_readings(tmp_path / "run.jsonl", 20, proc)  # the bus is open, its watchdog armed
            sim.vanish()
            err = proc.stderr.read()
            assert proc.wait(timeout=30) == 1
        finally:
            proc.kill()
    errors = [line for line in err.splitlines() if not line.startswith("  ")]
    assert len(errors) == 1 and errors[0].startswith("tactile explore: ") and "adapter unplugged?" in errors[0]
    assert "Bus Watchdog" in errors[0]
