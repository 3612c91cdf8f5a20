"""A flat press whose turn back across the range it scanned is blocked where the finger stands
at its reach (hand_driver.flat_press._press_across), on the emulated bus through the SDK."""

from __future__ import annotations

import math

import numpy as np
import pytest

from hand_driver.cycle import run_together
from hand_driver.flat_press import flat_press
from hand_driver.motion import move_line
from recognizer.scene import load_scene
from tactile_jaw.pipeline import feel

from tests.hand_driver.test_motion_emulated import CONFIG, _edge, emulated_jaw

#: random block 1 of ``bench_explore --finite 20 --anywhere --seed 599`` (development): its
#: 31.2 mm face, outward normal 81.6°, lies 68–99 mm from the palm; a seated left pad (ψ −98.4°)
#: has only its proximal 13.6 mm on it, the rest past the corner (98.5, −3.8) mm
BLOCK_HALF, BLOCK_THETA = 15.596785365955881, -0.14727468204167815
BLOCK = load_scene({"name": "block 1", "classes": ["line"], "object": {
    "class": "line", "params": {}, "pose": {"theta": BLOCK_THETA, "x": 83.10690465345415, "y": -1.5080918517811168},
    "extent": [-BLOCK_HALF, BLOCK_HALF],
    "closure": [[BLOCK_HALF, -12.477428292764705], [-BLOCK_HALF, -12.477428292764705]]}})


def test_a_press_turned_to_its_reach_the_wrong_way_comes_back_along_its_stops():
    """The left pad meets the face's corner 14 mm from its proximal end and lowers its longer
    part (lowering_turn) away from the face until the corner meets its distal end at the
    finger's reach (ψ ≈ −154°); there every turn back toward the seat, 7° the other side of
    the start, is blocked by the object and backing off along its normal is beyond the
    finger: before _press_across the press ended no_seat. Back along its own stops it seats:
    the face's normal within 0.3°, the seated segment's middle on the face within 0.2 mm."""
    psi0, d0 = math.radians(-105.8), -33.0  # the run's start, 10 mm before the face's corner
    with emulated_jaw(scene=BLOCK) as (sim, jaw):
        run_together(jaw, {"left": move_line(jaw, "left", psi0, _edge(psi0))})
        result = run_together(jaw, {"left": flat_press(jaw, "left", 0, psi0, 1, d0, 20.0,
                                                       toward=CONFIG.workspace.center_mm)})["left"]
    assert result.outcome == "ok", result.message
    psis = [math.degrees(s.psi) for s in result.samples]
    assert min(psis) < -140.0  # it did turn the wrong way to the finger's reach first
    felt = feel(CONFIG, result, 9)
    assert felt.problem is None, felt.problem
    assert math.degrees(felt.face.psi) == pytest.approx(math.degrees(BLOCK_THETA) - 90.0, abs=0.3)
    top = np.array([-math.sin(BLOCK_THETA), math.cos(BLOCK_THETA)])
    origin = np.array([83.10690465345415, -1.5080918517811168])
    assert float(top @ (felt.face.middle - origin)) == pytest.approx(0.0, abs=0.2)
