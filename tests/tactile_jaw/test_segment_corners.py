"""A roll across a straight closing segment states the segment's end corners
(tactile_jaw.pipeline.crossed_segment, FeltTouch.segment_corners), and the samples another roll
kept on one of them are cleared (clearing_corners, clear_of_corners): on the P-series jaw a roll
that ran onto an end corner no roll had pivoted about kept its last sample there, a µm from the
curve's continuation's tangent, and no class fitted (P semicubical 123 of bench_explore --finite
20 --anywhere --seed 199). Exact quantized rolls on a circle of radius 20 mm whose curved part
ends at a corner E, closed by a segment from E (tests/tactile_jaw/test_fine_corner_clearance.py)."""

import math

import numpy as np
import pytest

from hand_driver import kinematics as kin
from tactile_jaw.pipeline import SEGMENT_CORNER_LINES, clear_of_corners, clearing_corners, feel

from test_fine_corner_clearance import _rolls
from test_pipeline_feel import CENTRE, P_CONFIG, _p_touch

#: the closing segment's length (mm) and its normal's turn (deg) past the curve's end tangent
SEGMENT_MM, SEGMENT_TURN_DEG = 8.0, 10.0


def _segment_roll(end: np.ndarray, samples: int, span_deg: float, before: int):
    """The left pad rolled across the closing segment from the curve's end corner ``end`` (pad
    normal at the curve's end: ``end``'s outward normal less π), ``before`` of its ``samples``
    pad lines on ``end``, the rest on the segment's other corner; that corner too."""
    end_psi = math.atan2(end[1] - CENTRE[1], end[0] - CENTRE[0]) - math.pi
    psi_s = end_psi + math.radians(SEGMENT_TURN_DEG)
    other = end + SEGMENT_MM * np.array([math.sin(psi_s), -math.cos(psi_s)])  # below ψ_s the pad rests on ``end``
    step = math.radians(span_deg) / (samples - 1)
    psis = psi_s + step * (np.arange(samples) - before + 0.5)
    left = P_CONFIG.finger("left")

    def corner(psi):
        normal = np.array([math.cos(psi), math.sin(psi)])
        return min((end, other), key=lambda e: float(normal @ e))

    q = np.array([kin.ik_tangent(left, corner(p), float(p)) for p in psis])
    return feel(P_CONFIG, _p_touch(q), samples), other


@pytest.mark.parametrize("samples, span_deg, kept", [(9, 18.0, 7), (15, 24.0, 13)])
def test_a_segments_end_corner_clears_the_samples_of_a_roll_that_ran_onto_it(samples, span_deg, kept):
    past, _, end = _rolls(samples, span_deg)
    assert past.problem is None, past.problem  # nothing in the roll itself tells
    assert clear_of_corners(P_CONFIG, [past], [past], samples) == ([past], [])  # nor without a corner
    segment, other = _segment_roll(end, 9, 18.0, 4)
    assert segment.problem is not None and "closing segment" in segment.problem, segment.problem
    assert segment.corner is None
    np.testing.assert_allclose(segment.segment_corners, [end, other], atol=0.005)  # P: lines to 0.3 µm
    np.testing.assert_allclose(clearing_corners([past, segment]), [end, other], atol=0.005)
    usable, notes = clear_of_corners(P_CONFIG, [past], [past, segment], samples)
    assert len(notes) == 1 and "of the corner at" in notes[0], notes
    if kept:
        assert len(usable) == 1 and usable[0].contacts.x.size == kept
    else:
        assert usable == []


def test_two_lines_through_a_point_are_no_corner():
    """Two pad lines always meet: a segment crossing whose first run has fewer than
    SEGMENT_CORNER_LINES lines states only the other corner."""
    _, _, end = _rolls(9, 18.0)
    segment, other = _segment_roll(end, 9, 18.0, SEGMENT_CORNER_LINES - 1)
    assert segment.problem is not None and "closing segment" in segment.problem, segment.problem
    np.testing.assert_allclose(segment.segment_corners, [other], atol=0.005)


def test_the_exploration_clears_again_once_a_roll_crosses_a_closing_segment():
    """X line 18 of bench_explore --finite 20 --anywhere --seed 499 (logged): the right pad's
    roll 15 stayed on the end corner of the block's closing segment (its radius 10.6 ± 4.9 mm,
    no corner to the X jaw's ticks) and was used; roll 16 crossed that segment and stated its end
    corner. The exploration's cleared touches (tactile_jaw.explore._clear_of_corners) were
    recomputed only when the usable touches, corners or curve ends grew, so roll 15 stayed
    usable, and the block was refused with its three seated presses unused (fails before session
    32: [roll 15]); now they are recomputed with the segments' corners, and roll 15 goes."""
    import json
    from pathlib import Path

    from hand_driver.config import load_config
    from hand_driver.motion import TouchResult
    from tactile_jaw.explore import _clear_of_corners
    from tactile_jaw.pipeline import logged_samples
    from tactile_jaw.rounds import Exploration
    from tactile_jaw.settings import ExploreSettings

    raw = json.loads((Path(__file__).parent / "data" / "x_line_499_18_rolls.json").read_text())
    config, settings = load_config("config/jaw.yaml"), ExploreSettings.from_profile("balanced")
    corner, crossing = (feel(config, TouchResult(r["finger"], r["touch"], r["psi_center"],
                                                 logged_samples(config, r["finger"], r["ticks"], r["psi"]),
                                                 outcome=r["outcome"]), settings.samples_per_touch)
                        for r in raw["touches"])
    assert corner.problem is None and crossing.segment_corners  # used; the segment's end corner stated
    out = Exploration()
    out.touches, out.used = [corner], [corner]
    said: list[str] = []
    cleared = _clear_of_corners(config, out, settings, lambda event: None, said.append)
    assert cleared() == [corner]
    out.touches.append(crossing)
    assert cleared() == [] and len(said) == 1 and "(135.5, -31.9) mm" in said[0], said
