"""The run log: header, every reading, touch boundaries, durability against a killed writer."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import textwrap
import time
from dataclasses import dataclass

import pytest

from hand_driver.log import RunLog, read_log
from tactile_common.errors import InputError


@dataclass
class _State:
    t_monotonic: float
    ticks: tuple
    current_ma: tuple | None
    moving: tuple | None


def _write_small_log(path):
    with RunLog(path).open(config={"fingers": []}, scene={"name": "s"}, command=["demo"]) as log:
        i0 = log.reading(_State(0.1, (2048, 2049), (1.5, -2.0), (False, True)))
        log.write({"type": "touch_start", "touch": 0, "finger": "left", "psi": 0.5, "reading": i0})
        i1 = log.reading(_State(0.2, (2050, 2051), None, None))
        log.write({"type": "sample", "touch": 0, "finger": "left", "psi": 0.5, "reading": i1})
        log.write({"type": "touch_end", "touch": 0, "finger": "left", "reading": i1, "samples": 1, "outcome": "ok"})
        log.event("no_contact", "right pad met nothing within 30 mm")


def test_log_round_trip(tmp_path):
    path = tmp_path / "run.jsonl"
    _write_small_log(path)
    lines = path.read_text().splitlines()
    assert all(json.loads(line) for line in lines)
    contents = read_log(path)
    assert contents.header["config"] == {"fingers": []}
    assert contents.header["versions"]["python"]
    assert [r["ticks"] for r in contents.readings] == [[2048, 2049], [2050, 2051]]
    assert contents.readings[0]["current_ma"] == [1.5, -2.0]
    assert contents.readings[1]["current_ma"] is None
    (touch,) = contents.touches
    assert touch.finger == "left" and touch.readings == [1] and touch.psi == [0.5] and touch.outcome == "ok"
    assert contents.events[0]["kind"] == "no_contact"
    assert not contents.truncated


def test_exception_inside_log_is_recorded_as_fault(tmp_path):
    path = tmp_path / "run.jsonl"
    with pytest.raises(RuntimeError):
        with RunLog(path).open(config={}, scene=None) as log:
            log.reading(_State(0.0, (1,), None, None))
            raise RuntimeError("bus timeout on id 3")
    contents = read_log(path)
    assert len(contents.readings) == 1
    assert contents.events[-1]["kind"] == "fault" and "bus timeout on id 3" in contents.events[-1]["message"]


def test_cut_last_line_is_dropped_other_damage_is_an_input_error(tmp_path):
    path = tmp_path / "run.jsonl"
    _write_small_log(path)
    text = path.read_text()
    path.write_text(text + '{"type": "reading", "i": 2, "t"')
    contents = read_log(path)
    assert contents.truncated and len(contents.readings) == 2
    lines = text.splitlines()
    lines[2] = "{oops"
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(InputError, match="line 3: not valid JSON"):
        read_log(path)
    path.write_text('{"type": "reading"}\n')
    with pytest.raises(InputError, match="line 1 is not a tactile-jaw-log header"):
        read_log(path)


def test_nan_is_never_written(tmp_path):
    path = tmp_path / "run.jsonl"
    with RunLog(path).open(config={}, scene=None) as log:
        log.reading(_State(float("nan"), (1,), (float("inf"),), None))
    rec = read_log(path).readings[0]
    assert rec["t"] is None and rec["current_ma"] == [None]


def test_sigkill_loses_no_logged_reading(tmp_path):
    """A writer killed without warning leaves every reading it had logged."""
    path = tmp_path / "run.jsonl"
    progress = tmp_path / "progress"
    script = textwrap.dedent(f"""
        import os, time
        import numpy as np
        from hand_driver.bus import JointState
        from hand_driver.log import RunLog
        log = RunLog({str(path)!r}).open(config={{}}, scene=None)
        for i in range(100000):
            log.reading(JointState(time.monotonic(), np.array([i, i]), np.zeros(2), np.zeros(2, bool), np.zeros(2)))
            with open({str(progress)!r} + ".tmp", "w") as f:
                f.write(str(i + 1))
            os.replace({str(progress)!r} + ".tmp", {str(progress)!r})
            time.sleep(0.001)
    """)
    proc = subprocess.Popen([sys.executable, "-c", script])
    try:
        deadline = time.monotonic() + 20
        while time.monotonic() < deadline:
            if progress.exists() and int(progress.read_text()) >= 50:
                break
            time.sleep(0.02)
        proc.send_signal(signal.SIGKILL)
    finally:
        proc.wait()
    logged_before_kill = int(progress.read_text())
    contents = read_log(path)
    assert len(contents.readings) >= logged_before_kill >= 50
    assert [r["ticks"][0] for r in contents.readings] == list(range(len(contents.readings)))
    assert os.path.getsize(path) > 0
