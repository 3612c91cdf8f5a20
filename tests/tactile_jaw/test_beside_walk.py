"""A first flat press beside the other finger's probes or rolls that walks from the pad's
nominal normal (no face seated, no seat its lines show: tactile_jaw.flat_phase.beside_press)
gives up after FLAT_BESIDE_S without a seat, not FLAT_MAX_S: it holds up the other finger's
motion of its round. P line 14 of bench_explore --finite 20 --anywhere --follow --seed 571
(session 33's held-out run): the right pad walked 12.0 s without a seat beside the left's one
2.5 s roll, 30.9 s; bounded, 27.3 s, the same answer. A press at a seat its lines show keeps
FLAT_MAX_S (docs/exploration.md, session 34). The press itself is stubbed: what is checked is
when its ``give_up`` ends it."""

from __future__ import annotations

import math
from pathlib import Path
from types import SimpleNamespace

import numpy as np

from hand_driver.config import load_config
from hand_driver.flat_press import FlatResult
from tactile_jaw import flat_phase
from tactile_jaw.plan import ObjectModel
from tactile_jaw.rounds import Exploration
from tactile_jaw.settings import ExploreSettings

ROOT = Path(__file__).resolve().parents[2]
CFG = load_config(ROOT / "config" / "jaw-p.yaml")
MODEL = ObjectModel(CFG.workspace.center_mm, CFG.workspace.radius_mm)


def _stub_jaw(monkeypatch, press, clock: list[float]) -> SimpleNamespace:
    """A jaw of config/jaw-p.yaml on the robot clock ``clock[0]`` (s) whose flat press is the stub
    ``press`` and whose transits are made at once."""
    def transit(*args, **kwargs):
        return None
        yield

    monkeypatch.setattr(flat_phase, "flat_press", press)
    monkeypatch.setattr(flat_phase, "transit_or_problem", transit)
    return SimpleNamespace(config=CFG, robot_time=lambda: clock[0])


def _give_up(monkeypatch):
    """The right pad's beside press run on a stub press; its ``give_up`` and the robot clock."""
    clock = [100.0]
    seen = {}

    def press(jaw, finger, touch_index, start, first_turn, d_start, travel, **kw):
        seen["give_up"] = kw["give_up"]
        return SimpleNamespace(outcome="stopped")
        yield  # a generator, as the press is

    jaw = _stub_jaw(monkeypatch, press, clock)
    plan = flat_phase.beside_press(jaw, "right", MODEL, Exploration(), [], ExploreSettings.from_profile("balanced"),
                                   7, lambda rec: None, {})
    for _ in plan:
        pass
    return seen["give_up"], clock


def test_a_walk_beside_gives_up_after_flat_beside_s(monkeypatch):
    give_up, clock = _give_up(monkeypatch)
    clock[0] = 100.0 + 7.9  # every walk beside that seated did so by then
    assert give_up() is None
    clock[0] = 100.0 + 8.1
    assert give_up() == "no seat found within 8 s"  # before: None until 12 s


def test_a_press_at_a_seat_the_lines_show_keeps_flat_max_s(monkeypatch):
    seat = (math.radians(95.0), np.array([100.0, -10.0]), np.array([100.0, 10.0]))
    monkeypatch.setattr(flat_phase, "_felt_seat", lambda out, finger, length_mm, psi: seat)
    give_up, clock = _give_up(monkeypatch)
    clock[0] = 100.0 + 11.9
    assert give_up() is None
    clock[0] = 100.0 + 12.1
    assert give_up() == "no seat found within 12 s"


def test_a_walk_given_up_beside_is_no_miss_and_not_made_beside_again(monkeypatch):
    # the flat phase walks again (FLAT_MAX_S, stopped once the other pad seats): no seat is lost
    given_up = SimpleNamespace(finger="right", problem="right: flat press stopped: no seat found within 8 s",
                               touch=SimpleNamespace(touch=8, outcome="stopped", seek_limit_s=8.0,
                                                     message="right: flat press stopped: no seat found within 8 s"))
    state = flat_phase._booked(CFG, [given_up])
    assert state.misses["right"] == 0 and state.walked == {"right"} and "right" in state.active
    assert _beside_after(given_up) is None  # before: a miss of FLAT_TRIES (the finger done pressing)
    seat = (math.radians(95.0), np.array([100.0, -10.0]), np.array([100.0, 10.0]))
    monkeypatch.setattr(flat_phase, "_felt_seat", lambda out, finger, length_mm, psi: seat)
    assert _beside_after(given_up) is not None  # at a seat its lines show it still presses beside


def _beside_after(pressed):
    jaw = SimpleNamespace(config=CFG)
    return flat_phase.beside_press(jaw, "right", MODEL, Exploration(), [pressed],
                                   ExploreSettings.from_profile("balanced"), 9, lambda rec: None, {})


def _press_given_up(monkeypatch, others_seated: bool):
    """The right pad's beside walk on a stub press that asks ``give_up`` once 8.1 s on (the
    left pad seated already if ``others_seated``) and stops with its reason: the plan's result."""
    clock = [100.0]

    def press(jaw, finger, touch_index, start, first_turn, d_start, travel, **kw):
        clock[0] += 8.1
        why = kw["give_up"]()
        return FlatResult(finger, touch_index, start, outcome="stopped", message=f"{finger}: flat press stopped: {why}")
        yield  # a generator, as the press is

    jaw = _stub_jaw(monkeypatch, press, clock)
    plan = flat_phase._flat_plan(jaw, "right", MODEL, None, 0, 7, lambda rec: None, {},
                                 seated={"left"} if others_seated else set(), max_s=flat_phase.FLAT_BESIDE_S)
    try:
        while True:
            next(plan)
    except StopIteration as stop:
        return stop.value


def test_a_walk_given_up_says_its_limit_on_its_result_not_in_words(monkeypatch):
    # _Faces.book reads the limit from the result's typed field (seek_limit_s), not the message's words
    timed = _press_given_up(monkeypatch, others_seated=False)
    assert timed.seek_limit_s == flat_phase.FLAT_BESIDE_S and timed.message.endswith("no seat found within 8 s")
    assert _press_given_up(monkeypatch, others_seated=True).seek_limit_s is None  # the left pad's seat ended it
    worded = SimpleNamespace(finger="right", problem=timed.message,
                             touch=SimpleNamespace(touch=8, outcome="stopped", seek_limit_s=None, message=timed.message))
    assert flat_phase._booked(CFG, [worded]).walked == set()  # the words alone are no walk cut short
    felt = SimpleNamespace(finger="right", problem=timed.message, touch=timed)
    assert flat_phase._booked(CFG, [felt]).walked == {"right"}
