"""A finger that has not rolled: the stop for want of reach waits for it, and a move brings its side
within reach (tactile_jaw.explore.unrolled_finger, unrolled_places; docs/exploration.md)."""

from __future__ import annotations

import math
from pathlib import Path
from types import SimpleNamespace

import numpy as np

from hand_driver import kinematics as kin
from hand_driver.config import load_config
from hand_driver.motion import Sample, contact_on_pad
from recognizer.result import Ranked, Recognition
from tactile_jaw.explore import unrolled_finger, unrolled_places
from tactile_jaw.rounds import Exploration

ROOT = Path(__file__).resolve().parents[2]
CONFIG = load_config(ROOT / "config" / "jaw.yaml")


def _felt(finger: str):
    return SimpleNamespace(finger=finger)


def test_a_stop_waits_once_for_a_finger_whose_probes_met_a_face_and_that_has_not_rolled():
    left, right = CONFIG.finger("left"), CONFIG.finger("right")
    out = Exploration()
    out.used = [_felt("right"), _felt("right")]
    probes = SimpleNamespace(faces={"left": [-1.9, -2.1], "right": [1.6]})
    rolls = lambda f: -1.7  # noqa: E731 - the planner has a roll for it
    assert unrolled_finger([left, right], out, probes, set(), rolls) == "left"
    assert unrolled_finger([left, right], out, probes, {"left"}, rolls) is None  # once
    assert unrolled_finger([left, right], out, probes, set(), lambda f: None) is None  # no roll to make
    assert unrolled_finger([right], out, probes, set(), rolls) is None  # retired
    out.used.append(_felt("left"))
    assert unrolled_finger([left, right], out, probes, set(), rolls) is None  # it rolled
    assert unrolled_finger([left, right], Exploration(), SimpleNamespace(faces={"left": [], "right": []}), set(),
                           rolls) is None  # no face met


def _probe(finger: str, psi: float, point, u: float):
    """A probe of ``finger`` whose last two pad lines (normals ψ − 3° and ψ) pass through ``point``
    (the solution with the point nearest ``u`` mm along the pad)."""
    f = CONFIG.finger(finger)
    samples = []
    for i, a in enumerate((psi - math.radians(3.0), psi)):
        q = kin.ik_line(f, a, float(kin.unit(a) @ np.asarray(point, float)), contact=np.asarray(point, float), pad_u=u)
        ticks = kin.angles_to_ticks(f.joints, q)
        samples.append(Sample(reading=i, psi=a, ticks=ticks, line=kin.finger_pad_line_from_ticks(CONFIG, finger, ticks),
                              current_ma=None, robot_time=0.0))
    return SimpleNamespace(finger=finger, touch=SimpleNamespace(samples=samples))


def _answer(*ranked):
    return Recognition(ranked[0][0], {}, ranking=[Ranked(c, True, chi2, 20, 0.0, 0.5) for c, chi2 in ranked])


def test_the_side_an_unrolled_finger_met_is_a_place_while_a_closed_class_fits():
    out = Exploration()
    out.used = [_felt("left")]
    out.probes = [_probe("right", math.radians(90.0), (100.0, -25.0), 1.0),
                  _probe("right", math.radians(100.0), (105.0, -20.0), 20.0),
                  _probe("left", math.radians(-90.0), (100.0, 25.0), 20.0)]
    ellipse_close = _answer(("semicubical_parabola", 7.4), ("ellipse", 7.6))
    places = unrolled_places(CONFIG, out, ellipse_close)
    assert len(places) == 1  # the right finger's, not the left's (it rolled)
    point, u = contact_on_pad(out.probes[1].touch.samples)  # the contact nearest the pad's middle
    psi = float(out.probes[1].touch.samples[-1].line.psi)
    first = contact_on_pad(out.probes[0].touch.samples)[1]
    assert abs(u - 26.0) < abs(first - 26.0) and np.hypot(point[0] - 105.0, point[1] + 20.0) < 0.1
    np.testing.assert_allclose(places[0], (point[0], point[1], psi - math.pi / 2), atol=1e-9)
    # open classes only, or the closed one ruled out by the data: no place
    assert unrolled_places(CONFIG, out, _answer(("parabola", 7.4), ("hyperbola", 7.6))) == []
    assert unrolled_places(CONFIG, out, _answer(("semicubical_parabola", 7.4), ("ellipse", 30.0))) == []


def _roll(finger: str):
    return SimpleNamespace(finger=finger, touch=SimpleNamespace(samples=[]))


def test_the_flat_presses_wait_for_a_finger_that_only_probed_the_object_s_face():
    # P semicubical 126 of bench_explore --finite 20 --anywhere --seed 227: the right pad's 4 rolls
    # fell on the cusp-side corner and the closing segment (retired), the left only probed, on the curve
    from tactile_jaw.explore import OFF_CURVE_RETIRE, unrolled_before_flat

    out = Exploration()
    out.touches = [_roll("right") for _ in range(4)]
    probes = SimpleNamespace(faces={"left": [-2.1, -1.7], "right": [1.6]})
    retired = {"left": 0, "right": OFF_CURVE_RETIRE}
    rolls = lambda f: -1.8  # noqa: E731 - the planner has a roll for it
    assert unrolled_before_flat(CONFIG, out, probes, retired, rolls) == "left"
    assert unrolled_before_flat(CONFIG, out, probes, retired, lambda f: None) is None  # no roll to make
    assert unrolled_before_flat(CONFIG, out, probes, {"left": OFF_CURVE_RETIRE, "right": OFF_CURVE_RETIRE},
                                rolls) is None  # retired too
    assert unrolled_before_flat(CONFIG, out, SimpleNamespace(faces={"left": [], "right": [1.6]}), retired,
                                rolls) is None  # its probes met no face: nothing to roll on
    out.touches.append(_roll("left"))
    assert unrolled_before_flat(CONFIG, out, probes, retired, rolls) is None  # it rolled once: a block's presses start
