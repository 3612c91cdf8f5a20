"""Replay answers as the exploration does: its answers carry the jaw's calibration note (tactile_jaw.decide.noted),
its refusal for want of usable touches too, not only its answers from final_answer; and a face's presses count
only once felt min_touches times."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
import yaml

from hand_driver.log import RunLog
from tactile_jaw.decide import UNCALIBRATED
from tactile_jaw.settings import ExploreSettings

ROOT = Path(__file__).resolve().parents[2]


@pytest.mark.parametrize("calibrated", [False, True])
def test_replay_of_a_log_without_usable_touches_carries_it_as_the_exploration(tmp_path, tactile_in_process,
                                                                               calibrated):
    """Replay's refusal for want of usable touches (no touch in the log) is noted as its
    answers from final_answer are."""
    config = yaml.safe_load((ROOT / "config" / "jaw-p.yaml").read_text())
    if calibrated:
        config["fingers"][1]["joints"][1]["zero_sigma_deg"] = 4e-4
    log = tmp_path / "run.jsonl"
    with RunLog(log).open(config=config, scene=None, settings=ExploreSettings.from_profile("balanced").to_json()):
        pass
    rc, out, err = tactile_in_process(["replay", str(log), "--json"])
    answer = json.loads(out)
    assert rc == 3 and answer["class"] == "unclassified", err
    assert answer["reason"].startswith("no usable touch in the log (0 touches logged): too few to recognize")
    assert answer["reason"].endswith(UNCALIBRATED) != calibrated


def test_replay_asks_as_many_presses_of_one_face_as_the_exploration(tmp_path, tactile_in_process, monkeypatch):
    """Replay takes a face's flat touches only once felt ``min_touches`` times, as the
    exploration does (both through tactile_jaw.pipeline.logged_run): held-out P line 5 of seed 313,
    refused by its exploration (2 presses seated on one face, min_touches 3), was answered line
    by ``tactile replay`` of its log, which passed no count (1)."""
    import tactile_jaw.pipeline

    asked = []
    real = tactile_jaw.pipeline.recognized_touches

    def spy(usable, fewest=1, curved=False):
        asked.append(fewest)
        return real(usable, fewest, curved)

    monkeypatch.setattr(tactile_jaw.pipeline, "recognized_touches", spy)
    settings = ExploreSettings.from_profile("balanced")
    config = yaml.safe_load((ROOT / "config" / "jaw-p.yaml").read_text())
    log = tmp_path / "run.jsonl"
    with RunLog(log).open(config=config, scene=None, settings=settings.to_json()):
        pass
    rc, _, err = tactile_in_process(["replay", str(log), "--json"])
    assert rc == 3 and asked == [settings.min_touches] and settings.min_touches == 3, err
