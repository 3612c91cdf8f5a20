"""A finger whose probes met no face but whose pad lines already show a seat presses there
instead of probing on (tactile_jaw.probing.probe_boundary): P-series line 0 of bench_explore
--finite 20 --anywhere --seed 313, whose right pad probed 90° and 70° (corners), then 50°,
110° and 30° (pad ends) before its press seated at 105°, 21.9 s; pressing once its lines
showed the seat, 18.1 s. What each probe finds is scripted, the round logic real."""

from __future__ import annotations

import math
from pathlib import Path
from types import SimpleNamespace

from hand_driver.config import load_config
from tactile_jaw import probing
from tactile_jaw.plan import ObjectModel
from tactile_jaw.rounds import Exploration

ROOT = Path(__file__).resolve().parents[2]


def _run(monkeypatch, face: dict[str, set[float]], seat_after: dict[str, int]) -> list[tuple[str, str, float]]:
    """Every motion of the probe phase as (finger, "probe" or "press", ψ in degrees of a
    probe): each probe at ψ meets the pad's face where ``face[finger]`` holds ψ, a corner
    elsewhere; a finger's lines show a seat once it made ``seat_after[finger]`` probes (the
    ``beside`` callback, tactile_jaw.explore's press_beside, then has a press for it)."""
    cfg = load_config(ROOT / "config" / "jaw-p.yaml")
    ws = cfg.workspace
    done: list[tuple[str, str, float]] = []
    probed = {f.name: 0 for f in cfg.fingers}

    def plan(jaw, finger, model, psi, touch_index, emit, spent):
        return ("probe", finger, round(math.degrees(math.remainder(psi, 2 * math.pi)), 6))

    def felt_of(config, result, samples, curve_checks):
        _, finger, deg = result
        probed[finger] += 1
        samples = [SimpleNamespace(psi_measured=math.radians(deg), d=50.0)] * 4
        return SimpleNamespace(finger=finger, face=20.0 if deg in face.get(finger, ()) else None, end=None,
                               touch=SimpleNamespace(samples=samples, psi_center=math.radians(deg), message=None,
                                                     outcome="ok"))

    def beside(finger, touch_index=None, spent=None, result=None):
        if result is not None:
            return None
        return ("press", finger, 0.0) if probed[finger] >= seat_after.get(finger, 99) else None

    def rounds(jaw, plans, spent, time_s, total, transits):
        done.extend(plans.values())
        return dict(plans)

    monkeypatch.setattr(probing, "_probe_plan", plan)
    monkeypatch.setattr(probing, "feel", felt_of)
    monkeypatch.setattr(probing, "timed_round", rounds)
    monkeypatch.setattr(probing, "probe_face_contact", lambda config, felt: felt.face)
    monkeypatch.setattr(probing, "pad_contact", lambda felt: felt.end)
    jaw = SimpleNamespace(config=cfg)
    probing.probe_boundary(jaw, ObjectModel(ws.center_mm, ws.radius_mm), Exploration(), lambda rec: None,
                           lambda msg: None, beside)
    return [(finger, kind, deg) for kind, finger, deg in done]


def test_a_seat_the_probe_lines_show_is_pressed_instead_of_probing_on(monkeypatch):
    # the right pad's two probes met corners and its lines show a seat: it presses in round 3, and
    # its probes left (three on the block above) are not made
    done = _run(monkeypatch, {}, {"right": 2})
    right = [(kind, deg) for finger, kind, deg in done if finger == "right"]
    assert [kind for kind, _ in right[:3]] == ["probe", "probe", "press"]
    assert sum(kind == "probe" for kind, _ in right) == 2  # before: every probe of its queue, then the press


def test_a_finger_with_a_face_contact_probes_on(monkeypatch):
    # a face contact means a boundary the pad can roll on: its probes go on as before, seat or not
    done = _run(monkeypatch, {"right": {90.0}}, {"right": 1})
    right = [kind for finger, kind, _ in done if finger == "right"]
    assert right[:2] == ["probe", "probe"]
