"""Every answer of a jaw that states no calibration ends with the note of what its σ's do not
hold (tactile_jaw.decide.UNCALIBRATED, decided in one place: ``noted``), whichever path made
it: the exploration's (tactile_jaw.explore.closing_answer; replay's: tests/tools/test_replay_as_explored.py). Session 24's note was
appended by ``final_answer`` only: the flat phase's "no usable touch" refusals of held-out
seed 313 (P lines 5, 8, 10) did not carry it."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

from hand_driver.config import load_config
from hand_driver.motion import TouchResult
from recognizer.result import Ranked, Recognition
from tactile_common.errors import InputError
from tactile_jaw.decide import UNCALIBRATED
from tactile_jaw.explore import closing_answer
from tactile_jaw.pipeline import FeltTouch
from tactile_jaw.rounds import Exploration
from tactile_jaw.settings import ExploreSettings

ROOT = Path(__file__).resolve().parents[2]
SETTINGS = ExploreSettings.from_profile("balanced")
UNCALIBRATED_JAW = load_config(ROOT / "config" / "jaw-p.yaml")


def _calibrated_jaw():
    finger = UNCALIBRATED_JAW.fingers[1]
    joints = (finger.joints[0], replace(finger.joints[1], zero_sigma_deg=4e-4))
    return replace(UNCALIBRATED_JAW, fingers=(UNCALIBRATED_JAW.fingers[0], replace(finger, joints=joints)))


def _roll(k: int, corner=None) -> FeltTouch:
    return FeltTouch(TouchResult("left", k, 0.0, [], outcome="ok"), None, None, None,
                     "not usable" if corner else None, None, corner=corner)


DECISIVE = Recognition("circle", {"r": 12.0}, ranking=[Ranked("circle", True, 5.0, 7, 18.0, 0.5)])


def _too_few(touches):
    raise InputError("exploration: 1 touch, too few for any class")


def _closed(cfg, out: Exploration, usable: list[FeltTouch], recognize) -> Exploration:
    closing_answer(cfg, out, lambda: usable, recognize, SETTINGS, lambda rec: None, lambda msg: None)
    return out


def _paths(cfg) -> dict[str, Exploration]:
    """The exploration's every way to its answer, on jaw ``cfg``."""
    three = [_roll(k) for k in range(3)]
    return {
        "final answer": _closed(cfg, Exploration(touches=three, used=three), three, lambda t: DECISIVE),
        "too few clear of corners": _closed(cfg, Exploration(touches=three, used=three), three[:1], _too_few),
        "an earlier round's answer": _closed(cfg, Exploration(touches=three[:1], used=three[:1],
                                                              recognition=DECISIVE), three[:1], _too_few),
        "a curved part felt": _closed(cfg, Exploration(touches=three, recognition=Recognition(
            "unclassified", reason="left: touch 2 rolled on a curved part ... not a line")), [], _too_few),
        "no usable touch": _closed(cfg, Exploration(touches=[_roll(5, (121.0, 25.0))]), [], _too_few),
    }


def test_every_answer_of_an_uncalibrated_jaw_carries_the_note():
    answers = {path: out.recognition for path, out in _paths(UNCALIBRATED_JAW).items()}
    assert answers["final answer"].cls == "circle" and answers["final answer"].reason == UNCALIBRATED
    assert answers["an earlier round's answer"].cls == "circle"
    assert answers["an earlier round's answer"].reason == UNCALIBRATED
    assert answers["too few clear of corners"].reason.startswith("only 1 of the 3 usable touches are clear")
    assert answers["a curved part felt"].reason.startswith("left: touch 2 rolled on a curved part")
    assert answers["no usable touch"].reason.startswith("no usable touch of 1: rolls pivoted about corner at (121, 25)")
    for path, answer in answers.items():
        assert answer.reason.endswith(UNCALIBRATED) and answer.reason.count(UNCALIBRATED) == 1, path


def test_no_answer_of_a_calibrated_jaw_carries_it():
    for path, out in _paths(_calibrated_jaw()).items():
        assert out.recognition.reason is None or UNCALIBRATED not in out.recognition.reason, path
    assert _paths(_calibrated_jaw())["final answer"].recognition.reason is None
