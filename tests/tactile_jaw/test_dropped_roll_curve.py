"""A roll that felt a curved part refuses the line whatever dropped it later
(tactile_jaw.pipeline.curved_part): a usable roll whose samples beside a corner another touch
pivoted about leave too few (tactile_jaw.pipeline.clear_of_corners) still moved its contact
along the boundary while the pad turned, which no pivot does (tactile_jaw.pipeline.moving_stretch);
a pivot that passes as a usable roll at 4,096 ticks shows no such stretch."""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from hand_driver import kinematics as kin
from hand_driver.config import load_config
from hand_driver.motion import TouchResult
from recognizer.scene import load_scene
from tactile_jaw.pipeline import (MOVED_SIGMAS, clear_of_corners, corner_clearance, curve_refusal, curved_part, feel,
                                  logged_samples)
from tests.tactile_jaw.test_envelope_order import roll

DATA = Path(__file__).parent / "data" / "p_cubical_turned_dropped_rolls.json"
CLASSES = ["line", "circle", "ellipse", "parabola", "hyperbola", "cubical_parabola", "semicubical_parabola"]
# the cubical example scaled 1.5x, turned -75 deg, placed at (112, -8) mm: about 19 deg of its curve within the left pad's reach
OBJECT = {"class": "cubical_parabola", "extent": [-36.0, 3.0], "closure": [[3.0, -30.0], [-36.0, -30.0]],
          "params": {"a": 0.00035555555555555557, "c": -0.5},
          "pose": {"theta": -1.3089969389957472, "x": 109.84440290705568, "y": -25.65964747702768}}


def _rolls(config):
    rolls = json.loads(DATA.read_text())["rolls"]
    return [feel(config, TouchResult(r["finger"], r["touch"], r["psi_center"],
                                     logged_samples(config, r["finger"], r["ticks"], r["psi"]), outcome=r["outcome"]), 9)
            for r in rolls]


def test_a_usable_roll_dropped_beside_a_corner_refuses_the_line():
    """P-series jaw: the left roll 4 pivoted about the closing segment's corner (101.9, 9.5) mm,
    the left roll 6 (7 samples) was usable, then dropped while a fixed 2 mm cleared around that
    corner: one of its samples lies 1.0 mm from it and 6 are too few. Every one of its contacts
    lies on the cubical within 0.2 µm, and its fine lines leave in doubt only one step's arc
    about the corner (pipeline.corner_clearance, 0.95 mm), so it is now kept whole. Whatever
    drops such a roll, curved_part still finds it: its contact moved along the curve while the pad turned: its
    three-line windows touch circles ρ ≥ 10 σ_ρ, and the stretch's contacts lie on the cubical
    within 0.5 mm. The right pad's presses on the closing segment were answered line; now that
    roll is the curve felt, and the answer is the refusal naming it."""
    config = load_config("config/jaw-p.yaml")
    felt = _rolls(config)
    dropped = next(t for t in felt if t.touch.touch == 6)
    assert dropped.problem is None and not dropped.off_curve and dropped.curve_at is None
    kept, notes = clear_of_corners(config, [dropped], felt, 9)
    assert kept == [dropped] and notes == []
    assert 0.9 < corner_clearance(dropped) < 1.0
    curve = curved_part(config, felt)
    assert curve is not None and curve.finger == "left" and curve.touch.touch == 6
    assert curve.fit.rho >= MOVED_SIGMAS * curve.fit.sigma_rho
    obj = load_scene({"classes": CLASSES, "object": OBJECT}).object
    px, py = obj.pose.apply(*obj.curve().point(np.linspace(*obj.extent, 200001)))
    miss = max(float(np.min(np.hypot(px - x, py - y))) for x, y in zip(curve.contacts.x, curve.contacts.y))
    assert miss < 0.5
    refusal = curve_refusal(curve)
    assert refusal.cls == "unclassified" and "closing segments, not a line" in refusal.reason


@pytest.mark.parametrize("seed, span_deg", [(67, 9.0), (283, 6.0), (299, 9.0)])
def test_a_pivot_that_passes_as_a_usable_roll_on_the_x_jaw_feels_no_curve(seed, span_deg):
    """X-series jaw (4,096 ticks): the left pad's 9 lines through one corner over ±``span_deg``
    (random corner near (95–110, ±8) mm, random ψ and encoder phase) pass :func:`feel` as a
    usable roll, ρ 6.7–17.6 ± 3.3–8.2 mm (3 of 300 such rolls): no three-line window of them
    touches a circle ρ ≥ 10 σ_ρ, so curved_part finds no curve and a block's line stays."""
    config = load_config("config/jaw.yaml")
    rng = np.random.default_rng(seed)
    rng.choice([6.0, 9.0])  # the draw order of the search that found these rolls
    psis = np.radians(rng.uniform(-110, -80) + np.linspace(-span_deg, span_deg, 9))
    corner = np.array([rng.uniform(95, 110), rng.uniform(-8, 8)])
    q = roll(lambda psi: corner, psis, 4096, rng)
    samples = logged_samples(config, "left", np.rint(kin.angles_to_ticks(config.finger("left").joints, q)), psis)
    felt = feel(config, TouchResult("left", 0, float(np.mean(psis)), samples, outcome="ok"), 9)
    assert felt.problem is None and abs(felt.fit.rho) < 20.0 and not math.isnan(felt.fit.sigma_rho)
    assert curved_part(config, [felt]) is None
