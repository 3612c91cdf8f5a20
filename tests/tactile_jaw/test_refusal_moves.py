"""Refusals that name a move where the felt geometry gives one (issue 20): the turn that
makes a felt curved part face a finger's first rolls (tactile_jaw.choose.facing_move), and the
advice sought when the rolls end before the budget (tactile_jaw.choose.budget_advice's
``ended``)."""

import math
from pathlib import Path

import numpy as np

from hand_driver.config import load_config
from recognizer.result import Recognition
from tactile_jaw.choose import MOVE_TURN_STEP_DEG, JawReach, _reaches, budget_advice, facing_move, place_goal
from tactile_jaw.decide import Why
from tactile_jaw.plan import nominal_psi
from tactile_jaw.settings import ExploreSettings

ROOT = Path(__file__).resolve().parents[2]
CONFIG = load_config(ROOT / "config" / "jaw-p.yaml")
SETTINGS = ExploreSettings.from_profile("balanced")
REACH = JawReach(CONFIG, SETTINGS)
LEFT = CONFIG.finger("left")


def _goal(psi_deg: float):
    """The middle of the curved stretch calibrated parabola 30 of seed 239's left scan felt."""
    touched = (np.array([101.0, 119.0]), np.array([32.5, 39.8]))
    return place_goal(105.9, 36.3, math.radians(psi_deg) - math.pi / 2, touched)


def test_facing_turn_brings_the_place_to_the_nominal_normal():
    goal = _goal(-63.0)
    assert REACH.finger(105.9, 36.3, goal.places[0][2], [LEFT]) is not None  # reached already
    words, move = facing_move(REACH, goal, LEFT)
    assert (move["dx"], move["dy"]) == (0.0, 0.0) and move["about"] == [105.9, 36.3]
    # -63° turned to within half a turn step of the left pad's nominal normal (-90°)
    assert abs(-63.0 + move["turn_deg"] - math.degrees(nominal_psi(LEFT))) <= MOVE_TURN_STEP_DEG / 2
    assert move["turn_deg"] % MOVE_TURN_STEP_DEG == 0
    assert words.startswith(f"turn the object {abs(move['turn_deg']):.0f} deg clockwise (hand frame) about (106, 36) mm")
    assert _reaches(REACH, goal, 0.0, 0.0, math.radians(move["turn_deg"]), [LEFT])


def test_no_facing_turn_when_it_faces_already():
    assert facing_move(REACH, _goal(math.degrees(nominal_psi(LEFT)) + 1.0), LEFT) is None


def test_rolls_ended_head():
    ended = "no finger has a roll left to make after 2 usable touches"
    stop = budget_advice(Recognition("unclassified"), Why("none fits", "unclassified"), None, REACH, 8, ended=ended)
    assert stop.startswith(ended + " and no class of the scene fits")
    assert "budget" not in stop
