"""A probe turned as far as or farther from the pad's nominal normal, on the same side, than one
whose transit or approach left the joint limits before meeting the object is not made
(tactile_jaw.probing.Probes): the probe sequences of P-series lines 19 and 3 of bench_explore
--finite 20 --anywhere --seed 541 (what each probe found scripted, the queue logic real)."""

from __future__ import annotations

from tests.tactile_jaw.test_probe_refine import _run


def test_no_probe_farther_out_than_one_that_left_the_joint_limits(monkeypatch):
    # line 19, right pad: 90° on the face, 70° out of reach, 110° its distal end; before, 50° and 30°
    # were tried and left the joint limits too (0.5 + 0.3 s, and their rounds), then the refine pass
    seen = _run(monkeypatch, "right", {90.0: 21.2, 80.0: 24.7, 100.0: 20.0}, {110.0: 51.9}, 12,
                frozenset({70.0, 50.0, 30.0}))
    assert seen == [90.0, 70.0, 110.0, 80.0, 100.0]


def test_a_probe_nearer_the_nominal_normal_is_still_made(monkeypatch):
    # line 3, right pad: 70° on the face, 50° out of reach: 30° is not made, the refine pass's 60°
    # (nearer the nominal normal than 50°) and 80° still are; the other side is untouched
    seen = _run(monkeypatch, "right", {70.0: 25.1, 80.0: 19.0}, {90.0: 52.6, 110.0: 51.8}, 12,
                frozenset({50.0, 60.0}))
    assert seen == [90.0, 70.0, 110.0, 50.0, 60.0, 80.0]


def test_a_probe_that_met_the_object_first_rules_out_nothing(monkeypatch):
    # 70° out of reach only after its samples (the probe's short roll, not its approach): 50° and 30° still made
    seen = _run(monkeypatch, "right", {90.0: 21.2}, {}, 12, frozenset({70.0}), sampled=True)
    assert seen[:5] == [90.0, 70.0, 110.0, 50.0, 30.0]
