"""Replay's answers carry the jaw's calibration note as the exploration's do (tactile_jaw.decide.noted):
its refusal for want of usable touches too, not only its answers from final_answer."""

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
