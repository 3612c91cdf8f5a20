"""`tactile demo` end to end (emulated bus, real SDK), its log, `tactile replay`, a killed run."""

from __future__ import annotations

import json
import time

import pytest

from hand_driver.log import read_log
from recognizer.scene import load_scene
from tools.cmd_demo import truth_lines

TRUTH = load_scene("config/scenes/default.yaml").object


@pytest.fixture(scope="module")
def demo(tmp_path_factory, tactile_in_process):
    d = tmp_path_factory.mktemp("demo")
    log, png = d / "demo.jsonl", d / "demo.png"
    t0 = time.monotonic()
    rc, out, err = tactile_in_process(["demo", "--json", "--log", str(log), "--plot", str(png)])
    return {"rc": rc, "out": out, "err": err, "log": log, "png": png, "wall": time.monotonic() - t0}


def _without_timing(rec: dict) -> dict:
    return {k: v for k, v in rec.items() if k != "timing"}


def test_demo_recognizes_the_default_ellipse(demo):
    assert demo["rc"] == 0, demo["err"]
    rec = json.loads(demo["out"])  # stdout is exactly one answer object (docs/formats.md)
    assert rec["class"] == "ellipse"
    for k, v in TRUTH.params.items():  # measured: a +0.21 %, b +0.08 %
        assert rec["params"][k] == pytest.approx(v, rel=0.015)
    assert rec["pose"]["x"] == pytest.approx(TRUTH.pose.x, abs=0.5)
    assert rec["pose"]["y"] == pytest.approx(TRUTH.pose.y, abs=0.5)
    assert math_mod_pi(rec["pose"]["theta"] - TRUTH.pose.theta) < 0.02
    assert len(rec["contacts"]) >= 3
    assert "touch 1 (" in demo["err"]  # progress went to stderr
    assert demo["png"].read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def math_mod_pi(a: float) -> float:
    """|a| modulo π (an ellipse is the same after a half turn)."""
    import math

    return abs(math.remainder(a, math.pi))


def test_demo_log_has_header_readings_touches_and_result(demo):
    contents = read_log(demo["log"])
    h = contents.header
    assert h["config"]["fingers"][0]["name"] == "left" and h["scene"]["object"]["class"] == "ellipse"
    assert h["versions"]["dynamixel-sdk"] and h["start_time"]
    assert len(contents.readings) > 100 and not contents.truncated
    assert contents.verified and contents.cut is None and contents.integrity().startswith("whole: ")
    t = [r["t"] for r in contents.readings]
    assert all(b >= a for a, b in zip(t, t[1:]))  # monotonic timestamps
    assert contents.touches and all(x.outcome is not None for x in contents.touches)
    assert _without_timing(contents.result["recognition"]) == _without_timing(json.loads(demo["out"]))
    assert contents.result["robot_time_s"] > 0


def test_replay_reproduces_the_demo(demo, tactile_in_process):
    rc, out, err = tactile_in_process(["replay", str(demo["log"]), "--json"])
    assert rc == 0, err
    assert _without_timing(json.loads(out)) == _without_timing(json.loads(demo["out"]))
    rc, out, _ = tactile_in_process(["replay", str(demo["log"])])
    assert rc == 0 and out.startswith("recognized: ellipse")


def test_replay_touches_recognize_the_same(demo, tmp_path, tactile_in_process):
    """The request replay --touches writes carries the run's options: tactile recognize on it
    answers what replay answered (class and parameters)."""
    req = tmp_path / "touches.json"
    rc, out, err = tactile_in_process(["replay", str(demo["log"]), "--json", "--touches", str(req)])
    assert rc == 0, err
    replayed = json.loads(out)
    assert json.loads(req.read_text())["options"]["profile"] == "balanced"
    rc, out, err = tactile_in_process(["recognize", str(req)])
    assert rc == 0, err
    answer = json.loads(out)
    assert answer["class"] == replayed["class"] == "ellipse"
    assert answer["params"] == pytest.approx(replayed["params"], rel=1e-12)


def test_replay_touches_pools_each_set_once(demo, tmp_path, tactile_in_process, monkeypatch):
    """``replay --touches`` writes the touches the answer pools (the recognizer's own pooling,
    tactile_jaw.pipeline.make_recognizer's ``run.pooled``): no set of touches is pooled twice."""
    import tactile_jaw.curvature_pool as curvature_pool
    import tactile_jaw.pipeline as pipeline

    calls = []
    pooled = curvature_pool.pooled

    def counted(touches):
        calls.append(tuple(id(t) for t in touches))
        return pooled(touches)

    monkeypatch.setattr(pipeline, "pooled", counted)
    monkeypatch.setattr(curvature_pool, "pooled", counted)
    rc, _, err = tactile_in_process(["replay", str(demo["log"]), "--json", "--touches", str(tmp_path / "t.json")])
    assert rc == 0, err
    assert calls and len(set(calls)) == len(calls)


def test_truth_lines_report_relative_error(demo):
    lines = truth_lines(json.loads(demo["out"]), TRUTH)
    assert lines[0].startswith("true:       ellipse a=28.000 b=17.000")
    assert "a +" in lines[1] or "a -" in lines[1]


def test_replay_of_a_bad_log_is_one_line_exit_2(tmp_path, tactile_in_process):
    bad = tmp_path / "bad.jsonl"
    bad.write_text('{"type": "reading"}\n')
    rc, out, err = tactile_in_process(["replay", str(bad)])
    assert rc == 2 and err.count("\n") == 1 and "header" in err


def test_killed_demo_leaves_a_valid_log(tmp_path, tactile_in_process, killed_demo):
    log = tmp_path / "killed.jsonl"
    killed_demo(log, timeout_s=30)
    contents = read_log(log)  # a cut last line is tolerated, nothing else is wrong
    assert len(contents.readings) >= 60
    assert [r["i"] for r in contents.readings] == list(range(len(contents.readings)))
    rc, _, err = tactile_in_process(["replay", str(log)])
    assert rc in (0, 3) and "Traceback" not in err  # recognized, or refused: too few touches yet


def test_explore_without_an_adapter_is_one_line_exit_1(tmp_path, tactile_in_process):
    log = tmp_path / "none.jsonl"
    rc, out, err = tactile_in_process(["explore", "--port", str(tmp_path / "no-such-tty"), "--log", str(log)])
    assert rc == 1 and err.count("\n") == 1 and "no-such-tty" in err
    contents = read_log(log)  # the header was written before the port was opened
    assert contents.readings == [] and contents.events[-1]["kind"] == "fault"
