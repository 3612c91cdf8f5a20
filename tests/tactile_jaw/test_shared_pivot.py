"""A usable roll whose pad lines pass through a corner that the same finger's lines of its
other touches (probes, rejected rolls) pass through over a wider spread of pad normals rests on
that corner, not on the curve (tactile_jaw.pipeline.on_shared_pivots, clear_of_corners): within
one 18° roll the X-series jaw cannot tell a pivot from an arc of radius ~18 mm, over the finger's
lines together it can (X cubical 106 of bench_explore --finite 20 --anywhere --seed 617, moved
as advised: two such left rolls were used and the answer was ellipse). Exact geometry, each
reading rounded to whole ticks: an arc of radius 80 mm about CENTRE ending at a corner E; and,
for the alternative, circles."""

import json
import math
from pathlib import Path

import numpy as np
import pytest

from hand_driver import kinematics as kin
from hand_driver.motion import Sample, TouchResult
from tactile_jaw.pipeline import clear_of_corners, feel, logged_samples, on_shared_pivots

from test_pipeline_feel import CENTRE, CONFIG, P_CONFIG, _arc_then_corner

STEP = math.radians(18.0) / 8  # a 9-sample roll over 18°
PSI_END = math.radians(-80.0)  # the pad normal at the arc's end: past it the pad turns about E


def _touch(config, contact, psis, number: int) -> TouchResult:
    """The left pad on the object's tangent lines of normals ``psis`` through ``contact(ψ)``,
    each reading's joints rounded to whole ticks."""
    left = config.finger("left")
    samples = []
    for i, psi in enumerate(psis):
        ticks = np.rint(kin.angles_to_ticks(left.joints, kin.ik_tangent(left, contact(psi), float(psi))))
        line = kin.finger_pad_line_from_ticks(config, "left", ticks)
        samples.append(Sample(reading=i, psi=float(line.psi), ticks=ticks, line=line, current_ma=None, robot_time=0.0))
    return TouchResult("left", number, float(np.mean(psis)), samples, outcome="ok")


def _finger_touches(config, contact, roll_psis, way: float = 1.0):
    """The roll at ``roll_psis``, and the finger's probes beyond it (4 lines over 6° each, from
    6° and 24° past the roll's end, its last ψ for ``way`` +1, its first for −1: 48° in all); a
    probe is never judged a corner itself."""
    roll = feel(config, _touch(config, contact, roll_psis, 1), 9)
    end = roll_psis[-1] if way > 0 else roll_psis[0]
    probes = [feel(config, _touch(config, contact, end + way * np.radians(start + 2.0 * np.arange(4)), k), 9)
              for k, start in ((2, 6.0), (3, 24.0))]
    return roll, [roll, *probes]


def test_a_roll_that_passes_for_a_curve_on_a_corner_is_left_out():
    """X-series: 3 lines on the arc, 6 about E, usable as a curve of radius ~18 mm; with the
    probes' lines (48° in all) the 6 rest on E, and the roll is dropped (it was kept before)."""
    contact, end = _arc_then_corner(PSI_END + math.pi, 80.0)
    roll_psis = PSI_END + STEP * (np.arange(9) - 2.5)
    roll, felt = _finger_touches(CONFIG, contact, roll_psis)
    assert roll.problem is None and roll.fit.rho > 2.0 * roll.fit.sigma_rho  # nothing in the roll itself tells
    on, pivot = on_shared_pivots(CONFIG, roll, felt)
    assert pivot is not None and math.dist(pivot.point, end) < 0.1
    # E's lines; the arc's within 3.4° of E miss it by R(1 − cos δ) ≤ 0.14 mm, within 3.3 σ: X cannot tell
    assert on[3:].all() and not on[0]
    assert pivot.chi2_rho - pivot.chi2 > 100.0 and pivot.span_rad > math.radians(40.0)
    usable, notes = clear_of_corners(CONFIG, [roll], felt, 9)
    assert not usable and len(notes) == 1 and "not used" in notes[0] and "pass through over" in notes[0], notes


def test_one_roll_alone_states_no_shared_corner():
    """The same roll without the finger's other touches: its lines spread no wider than its own."""
    contact, _ = _arc_then_corner(PSI_END + math.pi, 80.0)
    roll, _ = _finger_touches(CONFIG, contact, PSI_END + STEP * (np.arange(9) - 2.5))
    on, pivot = on_shared_pivots(CONFIG, roll, [roll])
    assert pivot is None and not on.any()


def test_a_corner_only_the_roll_s_end_passes_through_is_not_this_rule_s():
    """P-series: a usable roll on an arc of radius 20 mm whose last line rests on E, the probes'
    lines through E beyond it. The roll states its radius at its middle contact, 7 steps from E
    (the radius may shrink toward its end, as at a hyperbola's vertex): it says nothing of the
    curve at E, and the rule leaves the roll alone (its end sample is cleared by the 2 mm
    clearance of E where a roll pivoted about it, tactile_jaw.pipeline.clear_of_corners)."""
    contact, _ = _arc_then_corner(PSI_END + math.pi, 20.0)
    roll, felt = _finger_touches(P_CONFIG, contact, PSI_END + STEP * (np.arange(9) - 7.5))
    assert roll.problem is None, roll.problem
    on, pivot = on_shared_pivots(P_CONFIG, roll, felt)
    assert pivot is None and not on.any()


@pytest.mark.parametrize("config, radius", [(CONFIG, 20.0), (P_CONFIG, 3.0)])
def test_tangents_of_a_tight_circle_share_no_corner(config, radius):
    """The roll and the finger's probes on a circle (X: 20 mm, which its 18° roll measures as a
    curve, ±3–4 mm; P: 3 mm): over 48° its tangents miss any one point by about ρ(1 − cos 24°),
    1.7 and 0.26 mm, far beyond their noise (X ~0.06 mm, P ~0.3 µm)."""
    circle = lambda psi: CENTRE - radius * kin.unit(float(psi))  # noqa: E731  (the contact of normal ψ)
    roll, felt = _finger_touches(config, circle, PSI_END + STEP * (np.arange(9) - 4.0), way=-1.0)
    assert roll.problem is None, roll.problem
    on, pivot = on_shared_pivots(config, roll, felt)
    assert pivot is None and not on.any()
    assert clear_of_corners(config, [roll], felt, 9) == ([roll], [])


def test_the_moved_x_cubical_s_left_rolls_on_the_block_corner_are_left_out():
    """X cubical 106 of finite seed 617 moved as advised (data: the left finger's logged probes
    and rolls): rolls 4 and 6 pass as curves (ρ 33.9 ± 4.8 and 20.5 ± 4.7 mm) but 7 and 8 of
    their 9 lines pass through the block's closing corner, as do the probes' and the rejected
    rolls' lines, 44° of normals in all: both are left out (the answer was ellipse with them)."""
    data = json.loads((Path(__file__).parent / "data" / "x_cubical_106_moved_left.json").read_text())
    felt = [feel(CONFIG, TouchResult(r["finger"], r["touch"], r["psi_center"],
                                     logged_samples(CONFIG, r["finger"], r["ticks"], r["psi"]), outcome=r["outcome"]), 9)
            for r in data["rolls"]]
    usable = [t for t in felt if t.problem is None]
    assert [t.touch.touch for t in usable] == [4, 6]
    for t, corner_lines in zip(usable, (7, 8)):
        on, pivot = on_shared_pivots(CONFIG, t, felt)
        assert pivot is not None and math.dist(pivot.point, data["corner"]) < 0.1
        assert int(on.sum()) == corner_lines and pivot.span_rad > math.radians(40.0)
    kept, notes = clear_of_corners(CONFIG, usable, felt, 9)
    assert kept == [] and len(notes) == 2 and all("not used" in n and "pass through over" in n for n in notes)
