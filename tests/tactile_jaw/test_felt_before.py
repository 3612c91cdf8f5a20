"""A `line` after a move whose run before felt curvature is refused (tactile_jaw.felt_before)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import stats

from hand_driver.log import RunLog

from recognizer.classify import MODEL_ALPHA
from recognizer.result import Recognition
from tactile_common.errors import InputError
from tactile_jaw.felt_before import FELT_BEFORE_EVENT, FeltBefore, line_limit, not_a_line, roll_z
from tools.cmd_explore import felt_before_move

LINE = Recognition("line", reason=None)


def test_line_limit_is_chi2_quantile_of_the_rolls_at_the_recognizer_level():
    assert math.isclose(line_limit(4), float(stats.chi2.isf(MODEL_ALPHA, 4)), rel_tol=1e-12)
    assert 18.4 < line_limit(4) < 18.5  # χ²(4) upper 0.1 %


def test_line_after_rolls_that_felt_curvature_is_refused():
    # X cubical 104 of bench_explore --finite 20 --anywhere --follow --seed 617: 4 rolls, Σ z² 122
    refused = not_a_line(LINE, FeltBefore(4, 122.0))
    assert refused.cls == "unclassified"
    assert "not reached after the move" in refused.reason and "122.0 on 4 dof" in refused.reason


def test_line_stands_when_the_rolls_curvature_is_within_a_line_s_noise():
    assert not_a_line(LINE, FeltBefore(4, line_limit(4) - 0.01)) is LINE
    assert not_a_line(LINE, FeltBefore(4, line_limit(4) + 0.01)).cls == "unclassified"
    assert not_a_line(LINE, FeltBefore(0, 0.0)) is LINE  # a block: no usable roll
    assert not_a_line(LINE, None) is LINE  # no move before the run


def test_curved_part_felt_without_a_usable_roll_refuses_a_line():
    assert not_a_line(LINE, FeltBefore(0, 0.0, 15.7, 0.31)).cls == "unclassified"


def test_other_answers_are_untouched():
    circle = Recognition("circle", params={"r": 20.0})
    assert not_a_line(circle, FeltBefore(4, 122.0)) is circle


def test_evidence_round_trips_through_its_log_event():
    before = FeltBefore(3, 40.5, 15.7, 0.31)
    event = before.to_event()
    assert event["kind"] == FELT_BEFORE_EVENT
    assert FeltBefore.from_events([{"kind": "touch_used"}, event]) == before
    assert FeltBefore.from_events([{"kind": "touch_used"}]) is None


class _Fit:
    kappa = 0.05
    cov = np.array([[0.01**2, 0.0], [0.0, 1.0]])


class _Roll:
    fit = _Fit()


def test_roll_z_is_kappa_over_its_deviation():
    assert math.isclose(roll_z(_Roll()), 5.0, rel_tol=1e-12)



def test_moved_as_log_without_settings_is_refused_in_one_line(tmp_path):
    log = tmp_path / "first.jsonl"
    with RunLog(log).open(config={}, scene=None) as out:
        out.write({"type": "event", "kind": "no_face_contact", "message": "nothing met"})
    with pytest.raises(InputError, match="--moved-as"):
        felt_before_move(str(log))
    assert felt_before_move(None) is None


class _Press:
    def __init__(self, face):
        from hand_driver.flat_press import FlatResult

        self.touch = FlatResult("left", 3, face.psi, [], outcome="ok", roles=[])
        self.face = face


def _face(p, q):
    from tactile_jaw.flat import Face

    p, q = np.asarray(p, float), np.asarray(q, float)
    t = (q - p) / np.linalg.norm(q - p)
    psi = math.atan2(-t[0], t[1])  # the normal a quarter turn clockwise of the tangent
    return Face(psi, float(np.array([math.cos(psi), math.sin(psi)]) @ p), p, q)


def test_a_line_from_one_face_s_presses_names_the_face_and_the_stretch_felt():
    from tactile_jaw.flat import face_line

    presses = [_Press(_face((100.0, 10.0), (130.0, 10.0))), _Press(_face((95.0, 10.0), (125.0, 10.0)))]
    said = face_line(Recognition("line", reason="calibrate"), presses)
    assert said.reason.startswith("the line of one straight face the pads pressed flat (pad normal -90.0 deg), "
                                  "felt from (95.0, 10.0) to (130.0, 10.0) mm (35.0 mm)")
    assert said.reason.endswith("; calibrate")
    circle = Recognition("circle")
    assert face_line(circle, presses) is circle
    assert face_line(LINE, []) is LINE
