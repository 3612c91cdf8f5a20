"""A run after a move a refusal named rolls first where that move was for (tactile_jaw.explore.promised_aims;
``tactile explore --moved-as``, tools.cmd_explore.moved_for; docs/exploration.md)."""

from __future__ import annotations

import pytest

from hand_driver.log import RunLog
from tactile_common.errors import InputError
from tactile_jaw.choose import Stop
from tactile_jaw.explore import promised_aims
from tests.tactile_jaw.test_choose import CONFIG
from tools.cmd_explore import moved_for

PLACES = [{"x": 101.855, "y": -32.529, "phi": 0.05216, "finger": "right"},  # X ellipse 40 of seed 283's move
          {"x": 120.0, "y": 10.0, "phi": 3.0, "finger": None},  # no finger rolls there
          {"x": 110.0, "y": -20.0, "phi": 0.5, "finger": "right"},  # a second place of one finger: its first only
          {"x": 99.0, "y": 20.0, "phi": -3.0, "finger": "thumb"}]  # no such finger on this jaw


def test_each_finger_named_rolls_first_at_its_first_place():
    aims = promised_aims(PLACES, CONFIG)
    assert set(aims) == {"right"}
    right = aims["right"]
    assert (right.x, right.y, right.phi, right.finger, right.kind) == (101.855, -32.529, 0.05216, "right", "promised")
    assert promised_aims([], CONFIG) == {}


def test_moved_as_reads_where_the_logged_refusal_s_move_was_for(tmp_path):
    log = tmp_path / "first.jsonl"
    with RunLog(log).open(config={}, scene=None) as out:
        out.write(Stop("the touch budget of 8 is spent; move it", {"dx": 4.0, "dy": 0.0, "turn_deg": 0.0,
                                                                   "about": [97.9, -32.5], "places": PLACES})
                  .event("budget_spent"))
    assert moved_for(str(log)) == PLACES
    assert moved_for(None) == []
    none = tmp_path / "none.jsonl"
    with RunLog(none).open(config={}, scene=None) as out:
        out.write(Stop("the touch budget of 8 is spent: no class fits").event("budget_spent"))
    with pytest.raises(InputError, match="named no move"):
        moved_for(str(none))
