"""A finger's lone face contact with a probe that met the object off the pad's face within
PROBE_ENOUGH_DEG of it is probed around next (tactile_jaw.probing.Probes._narrow), not after
the rest of its grid, and never twice: the probe sequences of P-series blocks 11 and 8 of
bench_explore --finite 20 --anywhere --seed 157 (what each probe found scripted, the queue
logic real)."""

from __future__ import annotations

import math
from pathlib import Path
from types import SimpleNamespace

import pytest

from hand_driver.config import load_config
from tactile_jaw import probing
from tactile_jaw.plan import ObjectModel

ROOT = Path(__file__).resolve().parents[2]


def _run(monkeypatch, finger: str, found: dict[float, float | None], rounds: int) -> list[float]:
    """The orientations (deg) ``finger`` probes over ``rounds`` rounds, each probe finding
    ``found[ψ]``: the face contact (mm along the pad) or None (met the object at a pad end)."""
    cfg = load_config(ROOT / "config" / "jaw-p.yaml")
    ws = cfg.workspace
    probes = probing.Probes(cfg, ObjectModel(ws.center_mm, ws.radius_mm))
    for other in probes.queues:
        if other != finger:
            probes.queues[other] = []
    monkeypatch.setattr(probing, "probe_face_contact", lambda config, felt: felt.face)
    monkeypatch.setattr(probing, "pad_contact", lambda felt: None)
    out, seen = SimpleNamespace(probes=[]), []
    for _ in range(rounds):
        upcoming = probes.next()
        if finger not in upcoming:
            break
        psi = upcoming[finger]
        probes.queues[finger].pop(0)
        deg = round(math.degrees(math.remainder(psi, 2 * math.pi)), 6)
        seen.append(deg)
        samples = [SimpleNamespace(psi_measured=psi, d=50.0)] * 4
        felt = SimpleNamespace(finger=finger, face=found.get(deg),
                               touch=SimpleNamespace(samples=samples, psi_center=psi, message=None))
        probes.record(felt, out, lambda msg: None)
    return seen


def test_a_lone_face_contact_between_misses_is_probed_around_next(monkeypatch):
    # block 11 (right pad): 90° on the face, 70° at its proximal end, 110° off the face; 80° and
    # 100° on the face
    seen = _run(monkeypatch, "right", {90.0: 41.0, 80.0: 42.4, 100.0: 42.4}, 8)
    assert seen == [90.0, 70.0, 110.0, 80.0, 100.0]  # before: 90, 70, 110, 50, 30, then 80, 100
    # done: the face contacts span PROBE_ENOUGH_DEG


def test_a_miss_on_one_side_probes_the_other_side_first(monkeypatch):
    # the grid's probe on the other side makes the span alone: one probe, not the refining two
    seen = _run(monkeypatch, "right", {70.0: 30.0, 90.0: 26.0}, 8)
    assert seen == [90.0, 70.0]
    seen = _run(monkeypatch, "right", {90.0: 26.0, 110.0: 30.0}, 8)
    assert seen == [90.0, 70.0, 110.0]


def test_the_refine_is_not_repeated(monkeypatch):
    # block 8 (right pad): 110° on the face only, between misses; before, 100° and 120° were probed twice
    seen = _run(monkeypatch, "right", {110.0: 37.2}, 12)
    assert seen.count(100.0) == 1 and seen.count(120.0) == 1
    assert seen.index(100.0) <= 4 and seen.index(120.0) <= 4


def test_a_face_contact_without_a_near_miss_keeps_the_grid_order(monkeypatch):
    # a curved part: 90° and 70° both on the face span PROBE_ENOUGH_DEG after two probes, as before
    assert _run(monkeypatch, "right", {90.0: 26.0, 70.0: 30.0}, 8) == [90.0, 70.0]
