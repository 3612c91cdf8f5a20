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


def test_the_places_on_the_object_as_felt_are_those_short_of_its_pivoted_ends():
    from tactile_jaw.explore import FeltObject
    from tactile_jaw.pipeline import CORNER_CLEARANCE_MM
    from recognizer.touches import Reach

    corners = np.array([_at(T0), _at(T1)])
    answer = _answer()
    ts = np.array([-2.0, 5.5, 3.3, 1.9, 1.5])
    px, py = np.array([_at(t) for t in ts]).T
    assert np.hypot(px[-1] - corners[0, 0], py[-1] - corners[0, 1]) < CORNER_CLEARANCE_MM < np.hypot(
        px[-2] - corners[0, 0], py[-2] - corners[0, 1])
    # past either corner; within the stretch; short of the corner; beside the corner (no samples kept there)
    assert beyond_felt_end(answer, px, py, corners).tolist() == [True, True, False, False, False]
    on = FeltObject(Reach(px[2], py[2], 1000.0), answer, corners)
    assert on.contains(px, py, np.zeros_like(px)).tolist() == [False, False, True, True, False]
    assert FeltObject(Reach(px[2], py[2], 1.0), answer, corners).contains(px, py).tolist() == [False, False, True,
                                                                                        False, False]
    assert beyond_felt_end(answer, float(px[0]), float(py[0]), corners) is True  # a place alone: one bool


def test_a_budget_refusal_asks_for_the_best_touch_on_the_object_when_the_first_lies_past_its_end():
    """Calibrated P cubical 58 of seed 337: the recognizer's place lay past the left pad's end corner, the
    refusal named no move; asked again among the places on the object, it names one a move reaches."""
    from tactile_jaw.choose import JawReach
    from tactile_jaw.explore import FeltObject, past_felt_end
    from tactile_jaw.settings import ExploreSettings
    from tests.tactile_jaw.test_flat import CONFIG_P

    corners = [_at(T0), _at(T1)]
    answer = _answer()
    (x, y), (ox, oy) = _at(-2.0), _at(3.6)
    past = {"x": x, "y": y, "phi": 0.0}
    on_it = {"x": ox, "y": oy, "phi": 0.5}
    reach = JawReach(CONFIG_P, ExploreSettings.from_profile("balanced"))
    asked = []

    def ask(on):
        asked.append(on)
        return on_it if on.contains(np.array([ox, x]), np.array([oy, y])).tolist() == [True, False] else None

    assert past_felt_end(answer, [], lambda: past, reach, 0.3, lambda name: [], corners)() is None
    assert past_felt_end(answer, [], lambda: past, reach, 0.3, lambda name: [], corners, ask)() is on_it
    assert len(asked) == 1 and isinstance(asked[0], FeltObject)
    assert past_felt_end(answer, [], lambda: past, reach, 0.3, lambda name: [], corners, lambda on: None)() is None
