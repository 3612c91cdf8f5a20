"""A probe turned as far as or farther from the pad's nominal normal, on the same side, than one
whose transit or approach left the joint limits before meeting the object is not made
(tactile_jaw.probing.Probes): the probe sequences of P-series lines 19 and 3 of bench_explore
--finite 20 --anywhere --seed 541 (what each probe found scripted, the queue logic real)."""

from __future__ import annotations

import math
from pathlib import Path
from types import SimpleNamespace

from hand_driver.config import load_config
from tactile_jaw import probing
from tactile_jaw.plan import ObjectModel

ROOT = Path(__file__).resolve().parents[2]


def _run(monkeypatch, finger: str, face: dict[float, float], end: dict[float, float], unreached: set[float],
         rounds: int, sampled: bool = False) -> list[float]:
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


def test_no_probe_farther_out_than_one_that_left_the_joint_limits(monkeypatch):
    # line 19, right pad: 90° on the face, 70° out of reach, 110° its distal end; before, 50° and 30°
    # were tried and left the joint limits too (0.5 + 0.3 s, and their rounds), then the refine pass
    seen = _run(monkeypatch, "right", {90.0: 21.2, 80.0: 24.7, 100.0: 20.0}, {110.0: 51.9}, {70.0, 50.0, 30.0}, 12)
    assert seen == [90.0, 70.0, 110.0, 80.0, 100.0]


def test_a_probe_nearer_the_nominal_normal_is_still_made(monkeypatch):
    # line 3, right pad: 70° on the face, 50° out of reach: 30° is not made, the refine pass's 60°
    # (nearer the nominal normal than 50°) and 80° still are; the other side is untouched
    seen = _run(monkeypatch, "right", {70.0: 25.1, 80.0: 19.0}, {90.0: 52.6, 110.0: 51.8}, {50.0, 60.0}, 12)
    assert seen == [90.0, 70.0, 110.0, 50.0, 60.0, 80.0]


def test_a_probe_that_met_the_object_first_rules_out_nothing(monkeypatch):
    # 70° out of reach only after its samples (the probe's short roll, not its approach): 50° and 30° still made
    seen = _run(monkeypatch, "right", {90.0: 21.2}, {}, {70.0}, 12, sampled=True)
    assert seen[:5] == [90.0, 70.0, 110.0, 50.0, 30.0]
