"""A probe or roll that stopped with a pad end on the object (outcome ``edge``) marks the two pad
normals of its last samples (tactile_jaw.explore.pad_end_normals): with its two joints a finger
at a given pad normal meets a convex object at one place on its pad, so a roll of that finger
through both normals meets that pad end again (tactile_jaw.plan.passes_end), and the planner
(tactile_jaw.plan.choose_psi), an aimed touch and a touch on (tactile_jaw.explore.futile_roll)
make none. Two cases of bench_explore --finite 20 --anywhere --follow --seed 499 on the P jaw:
line 12, whose right pad's probes at 87–89° and 79–81° rested on its distal end and whose four
rolls through those normals met it (7.5 s after the left's presses had answered); semicubical
124, whose left pad's roll met its proximal end at −71.5…−69.25° and whose planner's roll about
−77.5° met it again (refused for want of budget)."""

import json
import math
from pathlib import Path

import numpy as np
import pytest

from hand_driver.config import load_config
from hand_driver.motion import Sample, TouchResult
from tactile_jaw.explore import futile_roll, pad_end_normals
from tactile_jaw.pipeline import FeltTouch, feel, logged_samples
from tactile_jaw.plan import PROBE_SAMPLES, ObjectModel, choose_psi, nominal_psi, passes_end, probe_face_contact
from tactile_jaw.settings import ExploreSettings

from test_futile_roll import _aim
from test_pipeline_feel import CONFIG, LEFT

P_CONFIG = load_config("config/jaw-p.yaml")
PROBES = Path(__file__).parent / "data" / "p_line_pad_end_probes.json"
SPAN = math.radians(18.0)  # the balanced profile's roll
SETTINGS = ExploreSettings(touches=8, samples_per_touch=9, roll_span_rad=SPAN)
NO_CORNERS = np.empty((0, 2))


def _line_probes() -> dict[str, FeltTouch]:
    """Line 12's logged probes of the right finger (their ticks, commanded ψ and outcome), felt."""
    raw = json.loads(PROBES.read_text())["probes"]
    out = {}
    for key, t in raw.items():
        samples = logged_samples(P_CONFIG, t["finger"], t["ticks"], t["psi"])
        touch = TouchResult(t["finger"], int(key), t["psi_center"], samples, outcome=t["outcome"])
        out[key] = feel(P_CONFIG, touch, PROBE_SAMPLES, curve_checks=False)
    return out


def _roll(finger: str, touch: int, psi_deg: list[float], outcome: str) -> FeltTouch:
    samples = [Sample(reading=k, psi=math.radians(p), ticks=np.zeros(2, int), line=None, current_ma=None,
                      robot_time=0.0) for k, p in enumerate(psi_deg)]
    result = TouchResult(finger, touch, math.radians(psi_deg[0] + 9.0), samples, outcome=outcome)
    return FeltTouch(result, None, None, None, "a pad end, not the pad's face, touched", None)


def _degrees(ends) -> list[tuple]:
    return [(e[0], *(round(math.degrees(v), 6) for v in e[1:])) for e in ends]


def _pairs(ends) -> list[tuple[float, float]]:
    return [(a, b) for _, a, b in ends]


def test_the_pad_end_normals_of_a_fingers_probes_and_rolls():
    probes = list(_line_probes().values())
    assert _degrees(pad_end_normals("right", probes)) == [(1, 87.0, 89.0), (11, 79.0, 81.0)]
    assert pad_end_normals("left", probes) == []  # another finger's pad ends are not its own
    edge, ok = _roll("left", 6, [-71.5, -69.25], "edge"), _roll("left", 4, [-101.5, -99.25], "ok")
    assert _degrees(pad_end_normals("left", [ok, edge])) == [(6, -71.5, -69.25)]  # the semicubical's roll


def test_a_roll_passes_a_pad_end_only_through_both_its_normals():
    line = [(math.radians(87.0), math.radians(89.0)), (math.radians(79.0), math.radians(81.0))]
    for centre in (82.5, 92.5, 77.5, 72.5):  # line 12's rolls: all four met the distal end
        assert passes_end(math.radians(centre), SPAN, line)
    # lines 15 and 18 rolled from 88.5° (between a probe's 87 and 89°) across a closing segment, clear of
    # that end: a polygon's contact jumps along the pad where the normal passes a face's; a roll ending
    # at 86.5° stops short of it
    assert not passes_end(math.radians(97.5), SPAN, line[:1])
    assert not passes_end(math.radians(77.5), SPAN, line[:1])
    semicubical = [(math.radians(-71.5), math.radians(-69.25))]
    assert passes_end(math.radians(-77.5), SPAN, semicubical)  # −86.5…−68.5°: the roll that met it again
    assert not passes_end(math.radians(-79.0), SPAN, semicubical)  # −88…−70°: short of its last normal
    assert not passes_end(math.radians(-61.0), SPAN, semicubical)  # −70…−52°: from between them
    across = [(math.radians(178.0), math.radians(-178.0))]  # across the half turn
    assert passes_end(math.radians(180.0), SPAN, across)
    assert not passes_end(math.radians(-171.0), SPAN, across)


def test_a_touch_on_reads_the_same_pad_ends():
    edge = _roll("left", 6, [-71.5, -69.25], "edge")
    why = futile_roll(_aim("left", -77.5), [edge], SPAN, NO_CORNERS)
    assert why is not None and "-71.5…-69.2 deg" in why
    assert futile_roll(_aim("left", -79.0), [edge], SPAN, NO_CORNERS) is None
    probe = _line_probes()["1"]  # a probe's pad end counts as a roll's
    assert futile_roll(_aim("right", 82.5), [probe], SPAN, NO_CORNERS) is not None
    assert futile_roll(_aim("right", 97.5), [probe], SPAN, NO_CORNERS) is None


def test_the_planner_rolls_through_no_line_probes_pad_end():
    """Line 12: the model from the face contact of probe 3 (70°, 9.2 mm along the pad); the
    planner's roll without the pad ends is the run's first, 82.5°, through both; with them, none."""
    probes = _line_probes()
    face = probes["3"]
    assert probe_face_contact(P_CONFIG, face) == pytest.approx(9.2, abs=0.1)  # the premise
    ws = P_CONFIG.workspace
    model = ObjectModel(ws.center_mm, ws.radius_mm)
    model.add([s.psi_measured for s in face.touch.samples], [s.d for s in face.touch.samples])
    right = P_CONFIG.finger("right")
    ends = _pairs(pad_end_normals("right", list(probes.values())))
    before = choose_psi(right, model, SETTINGS, [])
    assert math.degrees(before) == pytest.approx(82.5)
    assert passes_end(before, SPAN, ends)
    assert choose_psi(right, model, SETTINGS, [], ends=ends) is None  # every roll the model predicts passes one


def _circle_model() -> ObjectModel:
    """A circle of radius 15 mm before the left pad, its support lines known over ±40°."""
    centre, radius = np.array([110.0, 12.0]), 15.0
    model = ObjectModel(CONFIG.workspace.center_mm, CONFIG.workspace.radius_mm)
    psis = nominal_psi(LEFT) + np.radians(np.arange(-40.0, 40.5, 2.0))
    model.add(psis, [float(np.array([math.cos(p), math.sin(p)]) @ centre) - radius for p in psis])
    return model


def test_the_planner_keeps_its_order_past_a_pad_end():
    model = _circle_model()
    used = [nominal_psi(LEFT), nominal_psi(LEFT) - math.radians(25.0)]
    first = choose_psi(LEFT, model, SETTINGS, used)
    assert first is not None and first > nominal_psi(LEFT)  # farthest from both: beyond the nominal normal
    end = (first + math.radians(2.0), first + math.radians(4.0))  # a roll met its pad end there
    assert passes_end(first, SPAN, [end])
    again = choose_psi(LEFT, model, SETTINGS, used, ends=[end])
    assert again is not None and not passes_end(again, SPAN, [end])
    # a pad end no first choice passes leaves the middle one: left out of the candidates, the
    # orientations through it would move the middle (X line 10 of seed 499)
    middle = choose_psi(LEFT, model, SETTINGS, [])
    aside = (middle + math.radians(12.0), middle + math.radians(14.0))
    assert not passes_end(middle, SPAN, [aside])
    assert choose_psi(LEFT, model, SETTINGS, [], ends=[aside]) == middle
    # a pad end met at every normal the planner could roll through leaves it none
    every = [(a, a + math.radians(2.0)) for a in nominal_psi(LEFT) + np.radians(np.arange(-90.0, 90.5, 5.0))]
    assert choose_psi(LEFT, model, SETTINGS, [], ends=every) is None
