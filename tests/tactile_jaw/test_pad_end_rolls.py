"""A finger's roll that ran onto a pad end (outcome ``edge``) marks the pad normal at which it
did (tactile_jaw.explore.pad_end_normals): with its two joints a finger at a given pad normal
meets a convex object at one place on its pad, so the planner chooses no roll through that
normal (tactile_jaw.plan.choose_psi's ``ends``, :func:`tactile_jaw.plan.passes_normal`). P
semicubical 124 of bench_explore --finite 20 --anywhere --seed 499 (session 31): the left pad's
rolls centred on −62.5, −77.5, −81.8 and −70° met its proximal end at −69.25, −75.25, −75.0 and
−74.5°; the planner went back there twice after the first (2.3–4.1 s each) and the budget ran out
before a roll toward the cusp."""

import math

import numpy as np

from hand_driver.motion import Sample, TouchResult
from tactile_jaw.explore import felt_pad_ends, futile_roll, pad_end_normals
from tactile_jaw.pipeline import FeltTouch
from tactile_jaw.plan import ObjectModel, choose_psi, nominal_psi, passes_normal
from tactile_jaw.rounds import Exploration
from tactile_jaw.settings import ExploreSettings

from test_futile_roll import _aim
from test_pipeline_feel import CONFIG, LEFT

SPAN = math.radians(18.0)  # the balanced profile's roll


def _roll(finger: str, touch: int, psi_deg: list[float], outcome: str) -> FeltTouch:
    samples = [Sample(reading=k, psi=math.radians(p), ticks=np.zeros(2, int), line=None, current_ma=None,
                      robot_time=0.0) for k, p in enumerate(psi_deg)]
    result = TouchResult(finger, touch, math.radians(psi_deg[0] + 9.0), samples, outcome=outcome)
    return FeltTouch(result, None, None, None, "a pad end, not the pad's face, touched", None)


def _circle_model() -> ObjectModel:
    """A circle of radius 15 mm before the left pad, its support lines known over ±40°."""
    centre, radius = np.array([110.0, 12.0]), 15.0
    model = ObjectModel(CONFIG.workspace.center_mm, CONFIG.workspace.radius_mm)
    psis = nominal_psi(LEFT) + np.radians(np.arange(-40.0, 40.5, 2.0))
    model.add(psis, [float(np.array([math.cos(p), math.sin(p)]) @ centre) - radius for p in psis])
    return model


def test_the_normals_where_a_fingers_rolls_met_a_pad_end():
    edge = _roll("left", 6, [-71.5, -69.25], "edge")
    ok = _roll("left", 4, [-101.5, -99.25], "ok")
    (touch, psi), = pad_end_normals("left", [ok, edge])
    assert touch == 6 and abs(math.degrees(psi) + 69.25) < 1e-9
    assert pad_end_normals("right", [ok, edge]) == []  # another finger's pad end says nothing of its own
    assert passes_normal(math.radians(-77.5), SPAN, [psi])  # −86.5…−68.5°: through it
    assert not passes_normal(math.radians(-79.0), SPAN, [psi])  # −88…−70°: short of it
    assert passes_normal(math.radians(-61.0), SPAN, [psi])
    assert not passes_normal(math.radians(-59.0), SPAN, [psi])
    # the aimed roll's check (futile_roll) and the planner's read the same normals
    assert futile_roll(_aim("left", -77.5), [edge], SPAN, np.empty((0, 2))) is not None
    assert futile_roll(_aim("left", -79.0), [edge], SPAN, np.empty((0, 2))) is None


def test_the_planner_chooses_no_roll_through_a_pad_end_met():
    model = _circle_model()
    settings = ExploreSettings(touches=8, samples_per_touch=9, roll_span_rad=SPAN)
    used = [nominal_psi(LEFT), nominal_psi(LEFT) - math.radians(25.0)]
    first = choose_psi(LEFT, model, settings, used)
    assert first is not None and first > nominal_psi(LEFT)  # farthest from both: beyond the nominal normal
    end = first + math.radians(3.0)  # an earlier roll met its pad end there: that roll would meet it again
    assert passes_normal(first, SPAN, [end])
    again = choose_psi(LEFT, model, settings, used, ends=[end])
    assert again is not None and not passes_normal(again, SPAN, [end])
    assert math.degrees(again) < math.degrees(end) - 9.0  # short of it, on the side the curve was felt
    # a pad end met at every normal the planner could roll through leaves it none
    every = list(nominal_psi(LEFT) + np.radians(np.arange(-90.0, 90.5, 5.0)))
    assert choose_psi(LEFT, model, settings, [], ends=every) is None


def test_only_a_finger_that_felt_the_curve_keeps_out_of_its_pad_ends():
    """A finger with no usable roll (a line's face, corners only) keeps its rolls as before."""
    out = Exploration()
    edge = _roll("left", 6, [-71.5, -69.25], "edge")
    out.touches.append(edge)
    assert felt_pad_ends("left", out) == []
    used = _roll("left", 4, [-101.5, -99.25], "ok")
    out.touches.append(used)
    out.used.append(used)
    assert [round(math.degrees(p), 2) for p in felt_pad_ends("left", out)] == [-69.25]
    assert felt_pad_ends("right", out) == []
