"""``tactile calibrate`` over ``tactile sim`` ports, as a lab rehearses it: one emulated bus per
placement, each started with ``--place`` at the placement calibrate expects
(docs/kinematics.md#tactile-calibrate). The whole calibration takes a minute of wall time, so
the test checks the two ends a user meets: the disk is where ``--place`` puts it, and a bus
whose disk is not at the expected placement is refused with a line that says how to put it
there (before: "found the reference with only 0 touches", nothing more)."""

import subprocess
import sys

import pytest
import yaml

from recognizer.scene import load_scene
from tactile_common.errors import InputError
from tools.cmd_sim import placed

DISK = load_scene("config/scenes/calibration.yaml").object


def tactile(*args, **kw):
    return subprocess.run([sys.executable, "-m", "tools.cli", *args], capture_output=True, text=True, timeout=120, **kw)


def test_place_moves_the_scene_object():
    moved = placed(DISK, "85,-3.5")
    assert (moved.pose.x, moved.pose.y, moved.pose.theta) == (85.0, -3.5, DISK.pose.theta)
    assert moved.params == DISK.params and moved.cls == "circle"
    assert placed(DISK, "70,0,90").pose.theta == pytest.approx(1.5707963267948966)
    for bad in ("85", "a,b", "1,2,3,4", "nan,0"):
        with pytest.raises(InputError, match="--place"):
            placed(DISK, bad)


def test_sim_place_is_checked_against_the_workspace():
    out = tactile("sim", "--scene", "config/scenes/calibration.yaml", "--place", "400,0")
    assert out.returncode == 2 and "workspace" in out.stderr and "Traceback" not in out.stderr


def patient_config(tmp_path):
    """config/jaw-p.yaml with a bus that waits for a loaded host: the emulator runs at 4× the wall
    clock, so its 100 ms Bus Watchdog is 25 ms of wall time and a test machine busy with other
    processes may not schedule the driver that often (the watchdog would stop the servos)."""
    with open("config/jaw-p.yaml") as f:
        raw = yaml.safe_load(f)
    raw["bus"].update(timeout_s=0.5, watchdog_ms=2000)
    path = tmp_path / "jaw-p-patient.yaml"
    path.write_text(yaml.safe_dump(raw))
    return str(path)


def test_calibrate_on_a_bus_whose_disk_is_elsewhere_says_how_to_place_it(tmp_path):
    config = patient_config(tmp_path)
    proc = subprocess.Popen([sys.executable, "-m", "tools.cli", "sim", "--config", config,
                             "--truth-config", "config/jaw-p-truth.yaml", "--scene", "config/scenes/calibration.yaml",
                             "--time-scale", "4"], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        port = proc.stdout.readline().strip()
        out = tactile("calibrate", "--config", config, "--port", port, "--place", "85,0",
                      "--faces", "2", "--corners", "0", "--out", str(tmp_path / "c.yaml"))
        assert out.returncode == 2, out.stderr
        line = out.stderr.strip().splitlines()[-1]
        assert "placement 1: found the reference with only 0 touches" in line, line
        assert "no disk of radius 20 mm near (85, 0) mm" in line and "--place 85,0" in line, line
        assert not (tmp_path / "c.yaml").exists()
    finally:
        proc.terminate()
        proc.wait(timeout=30)
