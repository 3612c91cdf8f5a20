"""What a new user met first (issue: runs a lab can open, and the rough edges): one clock
rule, exit codes a script can use, the parser naming its subcommand, a silent bus's hint,
refusals and lines printed in the scene's convention."""

from __future__ import annotations

import math

import pytest

from hand_driver.bus import BusTimeout, clock_rate
from hand_driver.config import load_config
from hand_driver.sim.server import EmulatedBus
from recognizer.scene import load_scene
from tactile_common.errors import InputError
from tools import cli
from tools.cmd_demo import truth_lines
from tools.cmd_explore import REAL_TIME_TOLERANCE, bus_time_scale, describe

CFG = load_config("config/jaw.yaml")


def test_exit_codes_are_the_documented_ones():
    assert (cli.EXIT_RECOGNIZED, cli.EXIT_FAULT, cli.EXIT_BAD_INPUT, cli.EXIT_REFUSED) == (0, 1, 2, 3)
    readme = open("README.md").read()
    for code, meaning in ((0, "recognized"), (1, "bus or hardware fault"), (2, "bad input"), (3, "refused")):
        assert f"{code} {meaning}" in readme


@pytest.mark.parametrize("argv, line", [
    (["demo", "--bogus"], "tactile demo: unrecognized arguments: --bogus\n"),
    (["replay", "x.jsonl", "--nope", "1"], "tactile replay: unrecognized arguments: --nope 1\n"),
    (["--bogus"], "tactile: unrecognized arguments: --bogus\n")])
def test_unrecognized_arguments_name_the_subcommand(argv, line, capsys):
    with pytest.raises(SystemExit) as exit_:
        cli.main(argv)
    assert exit_.value.code == 2 and capsys.readouterr().err == line


@pytest.mark.parametrize("scale", [1.0, 5.0])
def test_explore_learns_the_buses_time_scale(scale):
    """The emulator on the wall clock at ``scale`` (tactile sim --time-scale): measured from
    servo 1's Realtime Tick to within the tolerance, and a --time-scale that disagrees is
    refused with one line naming what to pass."""
    said = []
    with EmulatedBus(CFG, None, time_scale=scale) as sim:
        measured = clock_rate(sim.port, CFG.bus.baudrate, CFG.joints[0])
        assert measured.rate == pytest.approx(scale, rel=REAL_TIME_TOLERANCE)  # measured: within 1-2 %
        learned = bus_time_scale(CFG, sim.port, said.append)
        assert learned == (1.0 if scale == 1.0 else pytest.approx(scale, rel=REAL_TIME_TOLERANCE))
        assert bool(said) == (scale != 1.0)
        wrong = 1.0 if scale != 1.0 else 5.0
        with pytest.raises(InputError, match=rf"--time-scale {wrong:g} but the bus on .* runs .*: pass "
                                             rf"--time-scale .* or leave the option out"):
            bus_time_scale(CFG, sim.port, said.append, given=wrong)
        assert bus_time_scale(CFG, sim.port, said.append, given=scale) == scale


def test_a_silent_bus_says_to_scan_other_baud_rates():
    with EmulatedBus(CFG, None, time_scale=1.0) as sim:
        with pytest.raises(BusTimeout) as info:
            clock_rate(sim.port, 57600, CFG.joints[0])
    text = str(info.value)
    assert "no status packet (timeout)" in text and "57600 baud" in text
    assert f"tactile scan --port {sim.port} --baud " in text and "\n" not in text


def test_a_refusal_is_not_a_wrong_class():
    truth = load_scene("config/scenes/hyperbola.yaml").object
    lines = truth_lines({"class": "unclassified", "reason": "r"}, truth)
    assert lines[0].startswith("true:       hyperbola")
    assert lines[1] == "error:      no answer to compare: refused (the truth is hyperbola)"


def test_a_line_is_printed_in_the_scenes_convention():
    """The canonical line answer (foot of the perpendicular from the hand origin, here at
    x = 0) is printed at its point nearest the scene's pose, beside that pose."""
    truth = load_scene("config/scenes/line.yaml").object  # top face y = 10, pose x = 105
    answer = {"class": "line", "params": {}, "pose": {"theta": 0.0002, "x": -0.002, "y": 9.97}, "reason": None}
    shown = describe(answer, (truth.pose.x, truth.pose.y))
    x = float(shown.split(" x=")[1].split(" mm")[0])
    y = float(shown.split(" y=")[1].split(" mm")[0])
    assert x == pytest.approx(105.0, abs=0.01) and y == pytest.approx(9.97 + 105.0 * math.tan(0.0002), abs=0.01)
    assert "nearest the scene's pose" in shown
    assert "foot of the perpendicular" in describe(answer)


def test_the_log_header_records_the_port_the_run_used(default_demo):
    """The config's bus.port is /dev/ttyUSB0; the demo ran on the emulator's pseudo-terminal,
    and its log (like explore's with --port) says which."""
    from hand_driver.log import read_log

    port = read_log(default_demo["log"]).header["config"]["bus"]["port"]
    assert CFG.bus.port == "/dev/ttyUSB0" and port.startswith("/dev/pts/")
