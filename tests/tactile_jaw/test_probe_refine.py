"""The refine pass around a finger's only face contact (tactile_jaw.probing.Probes.next)
leaves out the orientations the finger probed already: the probe sequence of P-series block 8
of bench_explore --finite 20 --anywhere --seed 157 (what each probe found scripted, the queue
logic real), whose right pad probed 100° and 120° twice each before."""

from __future__ import annotations

import math
from pathlib import Path
from types import SimpleNamespace

from hand_driver.config import load_config
from tactile_jaw import probing
from tactile_jaw.plan import ObjectModel

ROOT = Path(__file__).resolve().parents[2]


def _run(monkeypatch, finger: str, face: dict[float, float], end: dict[float, float], rounds: int,
         unreached: frozenset[float] = frozenset(), sampled: bool = False) -> list[float]:
    """The orientations (deg) ``finger`` probes over ``rounds`` rounds, each probe at ψ finding the
    face ``face[ψ]`` mm along the pad, or meeting the object ``end[ψ]`` mm along it (a pad end), or,
    at the ψ in ``unreached``, leaving the joint limits before any sample (``sampled``: after its
    samples)."""
    cfg = load_config(ROOT / "config" / "jaw-p.yaml")
    ws = cfg.workspace
    probes = probing.Probes(cfg, ObjectModel(ws.center_mm, ws.radius_mm))
    for other in probes.queues:
        if other != finger:
            probes.queues[other] = []
    monkeypatch.setattr(probing, "probe_face_contact", lambda config, felt: felt.face)
    monkeypatch.setattr(probing, "pad_contact", lambda felt: felt.end)
    out, seen = SimpleNamespace(probes=[]), []
    for _ in range(rounds):
        upcoming = probes.next()
        if finger not in upcoming:
            break
        psi = upcoming[finger]
        probes.queues[finger].pop(0)
        deg = round(math.degrees(math.remainder(psi, 2 * math.pi)), 6)
        seen.append(deg)
        lost = deg in unreached
        samples = [] if lost and not sampled else [SimpleNamespace(psi_measured=psi, d=50.0)] * 4
        felt = SimpleNamespace(finger=finger, face=face.get(deg), end=face.get(deg, end.get(deg)),
                               touch=SimpleNamespace(samples=samples, psi_center=psi, message=None,
                                                     outcome="unreachable" if lost else "ok"))
        probes.record(felt, out, lambda msg: None)
    return seen


def test_the_refine_pass_does_not_probe_again(monkeypatch):
    # block 8, right pad: 90° and 70° met the object at its proximal end (0.8, 0.3 mm), the turn
    # toward the pad's middle found the face at 110°, and 120°, 100° around it missed the face
    seen = _run(monkeypatch, "right", {110.0: 37.2}, {90.0: 0.8, 70.0: 0.3}, 12)
    assert seen[:5] == [90.0, 70.0, 110.0, 120.0, 100.0]
    assert seen.count(100.0) == 1 and seen.count(120.0) == 1  # before: 100, 120 again after the grid


def test_a_lone_face_contact_is_still_refined(monkeypatch):
    # no turn toward the middle: the pass probes both sides of the only face contact, as before
    seen = _run(monkeypatch, "right", {90.0: 41.0, 80.0: 42.4, 100.0: 42.4}, {}, 12)
    assert seen[-2:] == [80.0, 100.0] and len(seen) == len(set(seen))
