"""Where a transit cannot retreat along the pad's normal (its edge line out of the joints'
reach) it swings the finger open in joint space to its nominal pose (tactile_jaw.rounds.transit);
that swing goes along the joints' straight path, paced, not to one far goal that each servo
reaches on its own trapezoidal profile: both joints then start alike and the pad slides along
its normal. X-series line 18 of bench_explore --finite 20 --anywhere --seed 139: the right pad,
3 mm off a block's corner after a roll ending at ψ 125.5°, slid 12 mm back onto it and stayed
wedged there, so its flat press met "no contact"."""

from __future__ import annotations

import math

import numpy as np
import pytest

from hand_driver import kinematics as kin
from hand_driver.config import load_config
from tactile_jaw.plan import ObjectModel
from tactile_jaw.rounds import transit

CONFIG = load_config("config/jaw.yaml")
HALF = 19.151051038110438
SCENE = {"name": "line18", "classes": ["line"],
         "object": {"class": "line", "params": {}, "extent": [-HALF, HALF],
                    "closure": [[HALF, -15.32084083048835], [-HALF, -15.32084083048835]],
                    "pose": {"theta": -2.5500108568192132, "x": 124.61518357528242, "y": -24.50651003790156}}}
Q_AFTER_ROLL = np.radians([-26.5, 62.0])  # the right finger 3 mm off the block's corner, pad normal 125.5°


def test_the_swing_open_does_not_slide_the_pad_onto_the_block(opened_jaw, rested_at, peak_current):
    config = CONFIG
    with opened_jaw(config, SCENE) as jaw:
        start = rested_at(jaw, "right", Q_AFTER_ROLL, 125.5)
        ws = config.workspace
        model = ObjectModel(ws.center_mm, ws.radius_mm)
        with pytest.raises(kin.Unreachable):  # the premise: no retreat along its normal to the edge
            jaw.solve("right", float(start.psi), model.edge(float(start.psi)), jaw.finger_q(jaw.last_state, "right"))
        peak, line = peak_current(jaw, "right", transit(jaw, "right", model, math.radians(89.5)))
    assert peak < config.motion.contact_current_ma  # never pressed on the block on the way
    assert math.degrees(float(line.psi)) == pytest.approx(89.5, abs=0.5)
