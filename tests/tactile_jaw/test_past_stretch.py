"""A roll that ran onto an end corner at one end and felt a hyperbola's arm at the other, with
no passing run at either end (ρ falls several times within the roll): its next roll goes on
past the stretch the contact moved along, away from the corner (tactile_jaw.pipeline.past_stretch),
not back over the same roll."""

import json
import math
from pathlib import Path

import numpy as np

from hand_driver.config import load_config
from hand_driver.motion import TouchResult
from recognizer.curves import CURVES, Pose
from tactile_jaw.pipeline import feel, logged_samples

DATA = Path(__file__).parent / "data" / "p_hyperbola_94_roll_off_corner.json"
# the scene of hyperbola 94 of bench_explore --finite 20 --anywhere --seed 571 (config/jaw-p.yaml)
A = 9.328426320772627
POSE = Pose(2.096353178797445, 121.3976000563663, -13.118346014807903)
EXTENT = (-1.3, 1.3)


def _roll():
    raw = json.loads(DATA.read_text())
    config = load_config("config/jaw-p.yaml")
    samples = logged_samples(config, raw["finger"], raw["ticks"], raw["psi"])
    return config, TouchResult(raw["finger"], 5, raw["psi_center"], samples, outcome="ok")


def _support(psi: float) -> float:
    """The exact object's support line offset at pad normal ψ: min over its boundary of n·p
    (the arm, and its end corners that close it)."""
    x, y = POSE.apply(*CURVES["hyperbola"]({"a": A, "b": A}).point(np.linspace(*EXTENT, 200001)))
    return float(np.min(math.cos(psi) * x + math.sin(psi) * y))


def test_the_next_roll_goes_on_past_the_arm_felt_away_from_the_corner():
    """P hyperbola 94 (a = b = 9.33 mm), the right pad's roll at ψ 73.5–91.5°: its first three
    lines pass through the end corner (98.5, −5.2) mm, the other six touch the arm (ρ 124 →
    23 mm). The only run passing every check drops two lines at each end, and its middle was
    rolled again: the same roll, and the run was refused. The next roll now starts one step
    past the last line the contact moved along (ψ 89.25°: at the roll's last, 91.5°, away from
    the corner; before, its first reading lay 9° lower, inside the roll), and the line of its middle normal through the place aimed at lies within 2 mm of the true
    arm's support line there (the approach starts 10 mm outside it)."""
    config, touch = _roll()
    felt = feel(config, touch, len(touch.samples))
    assert felt.problem is not None and felt.off_curve and felt.curve_at is not None
    x, y, phi = felt.curve_at
    psi = phi + math.pi / 2
    step = float(np.median(np.diff([s.psi for s in touch.samples])))
    first = psi - 4 * step  # the planned roll's first reading (9 readings, its middle the fifth)
    last = max(s.psi for s in touch.samples)
    assert abs(first - last) < 0.1 * step  # from the roll's last line (on the arm, beside no window) on
    assert abs(math.cos(psi) * x + math.sin(psi) * y - _support(psi)) < 2.0
