"""A place on the answer's curve past a corner the rolls pivoted about, or off it when such corners
close both ends, is not on the object: no move is advised to it (tactile_jaw.explore.beyond_felt_end; docs/exploration.md)."""

from __future__ import annotations

import numpy as np

from recognizer.curves import CURVES, Pose
from recognizer.result import Recognition
from tactile_jaw.explore import beyond_felt_end

# P semicubical 123 of bench_explore --finite 20 --anywhere --seed 199 (its scene's exact shape and pose)
PARAMS = {"a": 0.34453053266731243, "b": -1.2}
POSE = Pose(-0.7276419070091502, 95.14801076228865, -14.988733905076723)
T0, T1 = 0.8620426111458485, 4.623683096145914  # the object's extent: its curved part's end corners


def _at(t: float) -> tuple[float, float]:
    x, y = POSE.apply(*CURVES["semicubical_parabola"](PARAMS).point(np.array([t])))
    return float(x[0]), float(y[0])


def _answer(cls="semicubical_parabola", params=PARAMS, felt=(2.25, 3.0, 3.8, 4.45)):
    contacts = [{"t": t, "x": _at(t)[0], "y": _at(t)[1]} for t in felt]
    return Recognition(cls, dict(params), POSE, contacts)


def test_a_place_past_a_pivoted_end_corner_is_off_the_object():
    corners = [_at(T0), _at(T1)]  # both ends pivoted about
    answer = _answer()
    assert beyond_felt_end(answer, *_at(-2.0), corners)  # the other branch, past the cusp-side corner (123's place)
    assert beyond_felt_end(answer, *_at(5.5), corners)  # past the far end corner
    assert not beyond_felt_end(answer, *_at(3.3), corners)  # within the felt stretch
    assert not beyond_felt_end(answer, *_at(1.5), corners)  # past the felt stretch, short of the corner: on the object
    assert not beyond_felt_end(answer, *_at(-2.0), [_at(T1)])  # that end not felt: the object may go on
    assert not beyond_felt_end(answer, *_at(-2.0), [])
    x, y = _at(3.3)
    assert beyond_felt_end(answer, x + 40.0, y + 50.0, corners)  # a rival's place: both ends felt, not the object
    assert not beyond_felt_end(answer, x + 40.0, y + 50.0, [_at(T1)])  # one end felt: not judged


def test_a_closed_answer_has_no_ends():
    answer = Recognition("ellipse", {"a": 20.0, "b": 12.0}, POSE,
                         [{"t": t, "x": 0.0, "y": 0.0} for t in (0.1, 0.4, 0.8)])
    assert not beyond_felt_end(answer, 100.0, -20.0, [(100.0, -20.0)])
