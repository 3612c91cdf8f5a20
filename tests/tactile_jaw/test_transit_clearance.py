"""A transit keeps ``APPROACH_MARGIN_MM`` outside the tangent the felt lines predict where the
joints reach that far out, also where the workspace edge lies nearer the object
(tactile_jaw.plan.clear_offset): on a turn each servo runs its own trapezoidal profile, so
the pad first slides along its normal, and from the edge 5.4 mm outside a circle's tangent
the right pad of random X-series circle 32 (bench_explore --finite 20 --anywhere --seed 139)
slid back onto the circle and stayed wedged there through three rolls."""

from __future__ import annotations

import math

import numpy as np
import pytest

from hand_driver import kinematics as kin
from hand_driver.config import load_config
from hand_driver.cycle import run_together
from hand_driver.motion import move_line
from tactile_jaw.plan import APPROACH_MARGIN_MM, ObjectModel, clear_offset
from tactile_jaw.rounds import transit

CONFIG = load_config("config/jaw.yaml")
RIGHT = CONFIG.finger("right")
CENTER, R = np.array([107.50661934962459, -13.738532446248882]), 27.544977882572233  # circle 32 of seed 139
SCENE = {"name": "circle32", "classes": ["circle"],
         "object": {"class": "circle", "params": {"r": R},
                    "pose": {"theta": -2.6623050321770654, "x": float(CENTER[0]), "y": float(CENTER[1])}}}


def _support(psi: float) -> float:
    """The circle's support line offset for a pad of outward normal ψ: n·c − r."""
    return float(kin.unit(psi) @ CENTER) - R


def _model() -> ObjectModel:
    """What the right finger's two probes felt (4 lines over 6° at ψ 90° and 110°)."""
    ws = CONFIG.workspace
    model = ObjectModel(ws.center_mm, ws.radius_mm)
    psis = np.radians(np.concatenate([np.linspace(87.0, 93.0, 4), np.linspace(107.0, 113.0, 4)]))
    model.add(psis, [_support(p) for p in psis])
    return model


def test_the_line_keeps_the_margin_where_the_edge_is_nearer_the_object():
    model = _model()
    for deg in (80.0, 90.0, 112.5):
        psi = math.radians(deg)
        edge = model.edge(psi)
        assert 0.0 < _support(psi) - edge < APPROACH_MARGIN_MM  # the circle reaches to within the margin of the edge
        assert clear_offset(RIGHT, model, psi, edge) == pytest.approx(_support(psi) - APPROACH_MARGIN_MM, abs=0.3)
    # a line already the margin out, nothing predicted, or no line: unchanged
    far = _support(math.radians(90.0)) - 2.0 * APPROACH_MARGIN_MM
    assert clear_offset(RIGHT, model, math.radians(90.0), far) == far
    ws = CONFIG.workspace
    assert clear_offset(RIGHT, ObjectModel(ws.center_mm, ws.radius_mm), math.radians(90.0), -45.0) == -45.0
    assert clear_offset(RIGHT, model, math.radians(90.0), None) is None


def test_a_transit_from_beside_the_circle_turns_without_meeting_it(opened_jaw, peak_current):
    config = CONFIG
    model = _model()
    psi_from, psi_to = math.radians(112.9), math.radians(78.5)
    with opened_jaw(config, SCENE) as jaw:
        # backed off 2.9 mm after a probe at ψ 113°, as in the run
        assert run_together(jaw, {"right": move_line(jaw, "right", psi_from, _support(psi_from) - 2.9,
                                                     via=[(psi_from, model.edge(psi_from))])})["right"]
        peak, line = peak_current(jaw, "right", transit(jaw, "right", model, psi_to, hug=True))
    assert peak < config.motion.contact_current_ma  # never pressed on the circle on the way
    assert math.degrees(float(line.psi)) == pytest.approx(78.5, abs=0.5)  # and arrived (wedged at 112.4° before)
