"""``tactile sim`` and ``tactile scan`` as a user runs them."""

import json
import signal
import subprocess
import sys
import time

import pytest

from hand_driver.config import JointConfig
from hand_driver.sim.server import EmulatedBus


def tactile(*args, **kw):
    return subprocess.run([sys.executable, "-m", "tools.cli", *args], capture_output=True, text=True, timeout=60, **kw)


@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGINT])
def test_sim_prints_port_first_and_exits_cleanly_on_signal(sig):
    proc = subprocess.Popen([sys.executable, "-m", "tools.cli", "sim", "--scene", "config/scenes/default.yaml"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        port = proc.stdout.readline().strip()
        assert port.startswith("/dev/")
        out = tactile("scan", "--port", port, "--ids", "1-5", "--json")
        assert out.returncode == 0, out.stderr
        servos = json.loads(out.stdout)["servos"]
        assert [(s["id"], s["model"], s["model_number"]) for s in servos] == [(i, "XM430-W350", 1020) for i in (1, 2, 3, 4)]
        proc.send_signal(sig)
        assert proc.wait(timeout=10) == 0
    finally:
        proc.kill()
        proc.wait()


def test_scan_table_and_errors():
    with EmulatedBus([JointConfig(7, "XC330-M288", 2048, 50.0)]) as sim:
        out = tactile("scan", "--port", sim.port, "--ids", "5-8")
        assert out.returncode == 0
        assert out.stdout.splitlines()[1].split() == ["7", "XC330-M288", "1240", "46", "1000000"]
    out = tactile("scan", "--port", "/dev/no-such-adapter")
    assert out.returncode == 1 and "cannot open serial port /dev/no-such-adapter" in out.stderr
    assert "Traceback" not in out.stderr
    out = tactile("scan", "--port", "/dev/null", "--ids", "3-x")
    assert out.returncode == 2 and "--ids" in out.stderr


def test_bus_vanishing_during_explore_is_one_error_line(jaw_config, tmp_path):
    from recognizer.scene import load_scene

    with EmulatedBus(jaw_config, load_scene("config/scenes/default.yaml")) as sim:
        proc = subprocess.Popen([sys.executable, "-m", "tools.cli", "explore", "--port", sim.port,
                                 "--log", str(tmp_path / "run.jsonl")],
                                stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        try:
            assert "exploring" in proc.stderr.readline() + proc.stderr.readline()
            time.sleep(1.0)
            sim.vanish()
            err = proc.stderr.read()
            assert proc.wait(timeout=30) == 1
        finally:
            proc.kill()
    errors = [line for line in err.splitlines() if not line.startswith("  ")]
    assert len(errors) == 1 and errors[0].startswith("tactile explore: ") and "adapter unplugged?" in errors[0]
    assert "Bus Watchdog" in errors[0]
