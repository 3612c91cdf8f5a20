"""A roll whose pad normals all lie between two at which the finger's rolls turned about one
corner turns about that corner again (the normals of a convex boundary point form one arc) and
keeps none of its samples: the planner does not choose it (tactile_jaw.explore.corner_cones,
tactile_jaw.plan.within_cone / choose_psi). X-series lines of bench_explore --finite 20
--anywhere --seed 269: the left pad's guard rolls at ψ −110° turned about the corner its rolls at
−95° and −122.5° had turned about (blocks 1, 4, 19: 5 s each). Exact rolls quantized to the
P-series jaw's ticks (an X-series roll on a corner measures a radius of a few mm ± 4 mm: a corner
only clearing_corners trusts counts, tactile_jaw.pipeline.sure_corner)."""

import json
import math
from pathlib import Path

import numpy as np
import pytest

from hand_driver import kinematics as kin
from hand_driver.config import load_config
from hand_driver.motion import TouchResult
from tactile_jaw.explore import corner_cones, probe_normals
from tactile_jaw.pipeline import feel, logged_samples
from tactile_jaw.plan import PROBE_SAMPLES, ObjectModel, choose_psi, nominal_psi, within_cone
from tactile_jaw.settings import ExploreSettings

from test_pipeline_feel import CONFIG, LEFT, P_CONFIG, _p_touch

SAMPLES = 9
LINE = Path(__file__).parent / "data" / "x_line_corner_rolls.json"
X_CONFIG = load_config("config/jaw.yaml")
SPAN = math.radians(18.0)
CORNER = np.array([112.0, 14.0])


def _logged(raw: dict, key: str) -> TouchResult:
    """A logged touch of the X-series jaw (its ticks and commanded ψ), as the exploration had it."""
    samples = logged_samples(X_CONFIG, raw["finger"], raw["ticks"], raw["psi"])
    return TouchResult(raw["finger"], int(key), raw["psi_center"], samples, outcome="ok")


def _roll_about(point, centre_deg: float):
    """The left pad's 18° roll about ``point`` centred on pad normal ``centre_deg``, felt."""
    psis = math.radians(centre_deg) + np.linspace(-0.5, 0.5, SAMPLES) * SPAN
    left = P_CONFIG.finger("left")
    return feel(P_CONFIG, _p_touch(np.array([kin.ik_tangent(left, point, float(p)) for p in psis])), SAMPLES)


def test_rolls_about_one_corner_bound_the_normals_it_turns_about():
    low, high = _roll_about(CORNER, -100.0), _roll_about(CORNER, -80.0)
    assert low.corner is not None and high.corner is not None  # the premise: both judged a corner
    (lo, hi), = corner_cones("left", [low, high])
    assert math.degrees(lo) == pytest.approx(-109.0, abs=0.01)
    assert math.degrees(hi) == pytest.approx(-71.0, abs=0.01)
    assert within_cone(math.radians(-90.0), SPAN, [(lo, hi)])
    assert not within_cone(math.radians(-75.0), SPAN, [(lo, hi)])  # 4° past the last normal felt there
    between = _roll_about(CORNER, -90.0)  # what that roll would be: about the same corner, nothing measured
    assert between.corner is not None and math.dist(between.corner, CORNER) < 0.01
    assert corner_cones("right", [low, high]) == []  # another finger's rolls bound none of its own


def test_rolls_about_two_corners_bound_each_its_own_normals():
    other = CORNER + np.array([6.0, 0.0])
    rolls = [_roll_about(CORNER, -100.0), _roll_about(other, -70.0), _roll_about(CORNER, -85.0)]
    cones = sorted(corner_cones("left", rolls))
    assert [tuple(round(math.degrees(v)) for v in c) for c in cones] == [(-109, -76), (-79, -61)]
    assert not within_cone(math.radians(-80.0), SPAN, cones)  # straddles both: it may roll between them


def test_a_cone_across_the_half_turn():
    cone = (math.radians(170.0), math.radians(200.0))
    assert within_cone(math.radians(-175.0), SPAN, [cone])
    assert not within_cone(math.radians(-165.0), SPAN, [cone])


def test_the_planner_chooses_no_roll_within_a_cone():
    """A circle of radius 15 mm before the left pad: the planner has rolls to make; with every
    orientation it could roll at within one corner's normals, none."""
    centre, radius = np.array([110.0, 12.0]), 15.0
    model = ObjectModel(CONFIG.workspace.center_mm, CONFIG.workspace.radius_mm)
    psis = nominal_psi(LEFT) + np.radians(np.arange(-40.0, 40.5, 2.0))
    model.add(psis, [float(np.array([math.cos(p), math.sin(p)]) @ centre) - radius for p in psis])
    settings = ExploreSettings(touches=8, samples_per_touch=SAMPLES, roll_span_rad=SPAN)
    psi = choose_psi(LEFT, model, settings, [])
    assert psi is not None
    assert choose_psi(LEFT, model, settings, [], cones=[(psi - SPAN, psi + SPAN)]) != psi
    wide = (nominal_psi(LEFT) - math.radians(100.0), nominal_psi(LEFT) + math.radians(100.0))
    assert choose_psi(LEFT, model, settings, [], cones=[wide]) is None


def test_probes_through_a_rolls_corner_widen_its_normals():
    """X line 8 of bench_explore --finite 20 --anywhere --seed 463: the left pad's roll over 36°
    (touch 7) turned about a corner from ψ −100.5 to −64.5°; its probes at −113…−67° (touches
    0, 2, 4) passed within 0.14 mm of that corner, 37–48 mm along the pad: support lines there,
    so its normals reach −113°, and the roll at −92.5° (−101.5…−83.5°), which turned about it
    again (2.5 s), is not chosen. A point 1 mm off (across the pad) is on none of their lines."""
    raw = json.loads(LINE.read_text())
    rolls = [feel(X_CONFIG, _logged(raw["rolls"][k], k), SAMPLES) for k in ("6", "7")]
    probes = [feel(X_CONFIG, _logged(raw["probes"][k], k), PROBE_SAMPLES, curve_checks=False) for k in ("0", "2", "4")]
    (lo, hi), = corner_cones("left", rolls)
    assert math.degrees(lo) == pytest.approx(-100.5, abs=0.05) and math.degrees(hi) == pytest.approx(-64.5, abs=0.05)
    assert not within_cone(math.radians(-92.5), SPAN, [(lo, hi)])
    (lo, hi), = corner_cones("left", rolls, probes)
    assert math.degrees(lo) == pytest.approx(-113.0, abs=0.05) and math.degrees(hi) == pytest.approx(-64.5, abs=0.05)
    assert within_cone(math.radians(-92.5), SPAN, [(lo, hi)])
    assert corner_cones("right", rolls, probes) == []
    assert len(probe_normals("left", probes, [rolls[1].corner])) == 12
    assert len(probe_normals("left", probes, [np.asarray(rolls[1].corner) + [0.0, 1.0]])) == 0
    assert len(probe_normals("right", probes, [rolls[1].corner])) == 0
