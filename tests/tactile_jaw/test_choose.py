"""Which touch comes next (tactile_jaw.choose): the jaw's reach as the pads really roll,
the touch beyond a parabola's vertex on its short side, the recognizer's suggestion, and
stopping with a reason when nothing within reach can help."""

import math
from pathlib import Path

import numpy as np

from hand_driver.config import load_config
from recognizer.curves import CURVES, Pose
from recognizer.result import Ranked, Recognition
from tactile_jaw.choose import (MOVE_MAX_MM, MOVE_STEP_MM, JawReach, Stop, budget_advice, move_advice, move_for, next_aim,
                                vertex_aim)
from tactile_jaw.decide import VERTEX_SIDE_DEG, Why, vertex_sides
from tactile_jaw.plan import ObjectModel, feasible
from tactile_jaw.settings import ExploreSettings

ROOT = Path(__file__).resolve().parents[2]
CONFIG = load_config(ROOT / "config" / "jaw.yaml")
SETTINGS = ExploreSettings.from_profile("balanced")
REACH = JawReach(CONFIG, SETTINGS)
#: the parabola example (config/scenes/parabola.yaml): vertex facing the left finger
PARABOLA = Recognition("parabola", {"a": 8.0}, pose=Pose(-math.pi / 2, 105.0, 12.0), uncertainty={"a": 0.05},
                       ranking=[Ranked("parabola", True, 51.1, 140, 400.0, 0.5),
                                Ranked("ellipse", True, 50.5, 139, 404.0, 0.5)])


def _touched(turns_deg):
    t = np.tan(np.radians(turns_deg))
    return PARABOLA.pose.apply(*CURVES["parabola"](PARABOLA.params).point(t))


def test_the_jaws_reach_depends_on_the_pads_orientation():
    # the parabola example's vertex (105, 12): the left pad rolls there facing down (ψ = −90°,
    # φ = ψ − 90°); no pad can face +x there (ψ = 0), and nothing outside the workspace disk
    x, y = 105.0, 12.0
    assert REACH.contains(x, y, -math.pi).tolist() == [True]
    assert REACH.finger(x, y, -math.pi).name == "left"
    assert REACH.contains(x, y, -math.pi / 2).tolist() == [False]
    assert REACH.contains([x, 110.0 + 46.0], [y, 0.0], [-math.pi, -math.pi]).tolist() == [True, False]
    assert REACH.contains(x, y).tolist() == [True]  # no tangent given: the disk
    model = ObjectModel(CONFIG.workspace.center_mm, CONFIG.workspace.radius_mm)
    assert feasible(CONFIG.fingers[0], model, -math.pi / 2, SETTINGS, aim=(x, y))  # the planner's own test


def test_the_touch_beyond_the_vertex_goes_to_the_short_side_within_reach():
    touched = _touched(np.linspace(-47.0, 12.0, 40))  # 47° on one side, 12° on the other
    aim = vertex_aim(PARABOLA, touched, REACH)
    assert aim is not None and aim.kind == "vertex" and aim.finger == "left"
    # on the answered parabola, on the short (+t) side, rolling past VERTEX_SIDE_DEG
    cx, cy = PARABOLA.pose.inverse(aim.x, aim.y)
    a = PARABOLA.params["a"]
    assert math.isclose(cx, cy**2 / (4 * a), abs_tol=1e-9)
    turn = math.degrees(math.atan(cy / (2 * a)))
    half = 0.5 * math.degrees(SETTINGS.roll_span_rad)
    assert turn > 0 and turn + half >= VERTEX_SIDE_DEG and turn <= VERTEX_SIDE_DEG + 2 * half + 1e-9
    # the pad faces the solid (the focus side): ψ = the tangent − 90°
    tangent = math.atan2(1.0, cy / (2 * a)) + PARABOLA.pose.theta
    assert abs(math.remainder(aim.psi - (tangent - math.pi / 2), 2 * math.pi)) < 1e-9
    assert REACH.finger(aim.x, aim.y, aim.phi).name == "left"
    assert vertex_aim(PARABOLA, touched, REACH, fingers=[CONFIG.fingers[1]]) is None  # the right pad cannot


def _why(kind):
    return Why(f"a {kind} reason", kind)


def test_next_aim_follows_the_reason_and_stops_when_nothing_within_reach_helps():
    touched = _touched(np.linspace(-47.0, 12.0, 40))
    fingers = list(CONFIG.fingers)
    # (a) the vertex side first
    aim, stop = next_aim(PARABOLA, _why("vertex"), touched, REACH, fingers, [])
    assert aim is not None and aim.kind == "vertex" and stop is None
    # (b) the recognizer's suggestion when it is reachable, not twice at the same place
    reachable = {"x": 105.0, "y": 12.0, "phi": -math.pi, "gain": 1.0, "why": "tells parabola from ellipse"}
    suggesting = Recognition("parabola", PARABOLA.params, pose=PARABOLA.pose, next_touch=reachable)
    aim, stop = next_aim(suggesting, _why("rival"), touched, REACH, fingers, [])
    assert (aim.x, aim.y, aim.finger, aim.kind, stop) == (105.0, 12.0, "left", "suggested", None)
    assert next_aim(suggesting, _why("rival"), touched, REACH, fingers, [(105.2, 12.3)]) == (None, None)
    # nor near a place where an aimed touch met nothing (the answered curve goes on where the object does not)
    assert next_aim(suggesting, _why("rival"), touched, REACH, fingers, [], empty_at=[(110.0, 15.0)]) == (None, None)
    assert next_aim(suggesting, _why("rival"), touched, REACH, fingers, [], empty_at=[(125.0, 12.0)])[0] is not None
    # (c) nothing reachable: the planner's touch when the answer only needs checking, else stop
    unreachable = Recognition("parabola", PARABOLA.params, pose=PARABOLA.pose,
                              next_touch={**reachable, "phi": -math.pi / 2})
    assert next_aim(unreachable, _why("unstable"), touched, REACH, fingers, []) == (None, None)
    for kind, what in (("rival", "tell the classes apart"), ("imprecise", "narrow the parameters")):
        aim, stop = next_aim(unreachable, _why(kind), touched, REACH, fingers, [])
        assert aim is None and what in stop and "move or turn the object" in stop
    # the vertex side once missed (the object ends there) or out of every pad's reach: only that
    # side decides (the richer rival always fits at least as well), so exploration stops, saying so
    aim, stop = next_aim(suggesting, _why("vertex"), touched, REACH, fingers, [], vertex_missed=True)
    assert aim is None and "fell off the curved part" in stop
    aim, stop = next_aim(suggesting, _why("vertex"), touched, REACH, [CONFIG.fingers[1]], [])
    assert aim is None and "no pad can roll beyond the vertex" in stop and "move or turn the object" in stop


def test_a_stop_for_want_of_reach_names_the_smallest_move_that_brings_the_place_within_a_pads_roll():
    # the parabola example 12 mm nearer the palm: 25° past its vertex on the palm side, where the
    # left pad would have to face down and toward +x, no pad rolls
    near = Recognition("parabola", PARABOLA.params, pose=Pose(-math.pi / 2, 93.0, 12.0), uncertainty={"a": 0.05},
                       ranking=PARABOLA.ranking)
    touched = near.pose.apply(*CURVES["parabola"](near.params).point(np.tan(np.radians(np.linspace(-12.0, 47.0, 40)))))
    assert vertex_aim(near, touched, REACH) is None
    aim, stop = next_aim(near, _why("vertex"), touched, REACH, list(CONFIG.fingers), [])
    assert aim is None and isinstance(stop, Stop) and stop.move is not None
    move = stop.move
    assert 0 < math.hypot(move["dx"], move["dy"]) <= MOVE_MAX_MM + 2.0 and move["turn_deg"] == 0.0
    assert "away from the palm (+x)" in stop if move["dx"] > 0 else "toward the palm (-x)" in stop
    x, y = move["about"]
    t = -np.tan(np.radians(VERTEX_SIDE_DEG))  # the place: the short (−t) side, toward the palm
    px, py = near.pose.apply(*CURVES["parabola"](near.params).point(np.array([t])))
    assert math.hypot(x - px[0], y - py[0]) < 1e-9
    phi = math.atan2(1.0, t) + near.pose.theta - math.pi  # the pad faces the solid: ψ = tangent − 90°
    assert REACH.finger(x + move["dx"], y + move["dy"], phi) is not None  # moved so, a pad rolls there
    # the shift move_for found is the smallest on its grid: nothing shorter brings it in
    dx, dy, turn = move_for(REACH, x, y, phi)
    assert turn == 0.0 and REACH.finger(x + dx, y + dy, phi) is not None
    k = int(MOVE_MAX_MM // MOVE_STEP_MM)
    grid = np.arange(-k, k + 1) * MOVE_STEP_MM
    shorter = [(a, b) for a in grid for b in grid if math.hypot(a, b) < math.hypot(dx, dy) - 1e-9]
    assert all(REACH.finger(x + a, y + b, phi) is None for a, b in shorter)


def test_move_advice_turns_the_object_when_no_shift_brings_the_tangent_within_reach():
    # a place at the example's vertex whose pad would have to face up and toward +x (ψ = 60°):
    # no shift helps, a turn about the place does, and the words say which way
    x, y, phi = 105.0, 12.0, math.radians(60.0) - math.pi / 2
    assert move_for(REACH, x, y, phi) is not None
    words, move = move_advice(REACH, x, y, phi)
    dx, dy, turn = move["dx"], move["dy"], math.radians(move["turn_deg"])
    assert turn != 0.0 and REACH.finger(x + dx, y + dy, phi + turn) is not None
    assert ("counterclockwise" if turn > 0 else "clockwise") in words
    # within reach already: nothing to move, the general request
    assert move_advice(REACH, 105.0, 12.0, -math.pi) == (
        "move or turn the object so that more of its curved part faces a finger", None)


def test_a_stop_without_a_reachable_suggestion_says_where_the_touch_anywhere_would_go():
    touched = _touched(np.linspace(-47.0, 12.0, 40))
    unreachable = Recognition("parabola", PARABOLA.params, pose=PARABOLA.pose,
                              next_touch={"x": 105.0, "y": 12.0, "phi": -math.pi / 2, "gain": 1.0, "why": "w"})
    wanted = {"x": 93.0, "y": 12.0, "phi": -math.pi, "gain": 1.0, "why": "w"}
    aim, stop = next_aim(unreachable, _why("rival"), touched, REACH, list(CONFIG.fingers), [],
                         anywhere=lambda: wanted)
    assert aim is None and "the most telling touch would roll at (93, 12) mm, pad normal -90 deg" in stop
    assert stop.move is not None and stop.move["about"] == [93.0, 12.0]


def test_when_the_budget_runs_out_undecided_the_reason_says_what_to_do():
    # a parabola felt on one side only, its short side out of reach (12 mm nearer the palm
    # than the example): the move that lets a pad roll beyond the vertex
    near = Recognition("parabola", PARABOLA.params, pose=Pose(-math.pi / 2, 93.0, 12.0), uncertainty={"a": 0.05},
                       ranking=PARABOLA.ranking)
    touched = near.pose.apply(*CURVES["parabola"](near.params).point(np.tan(np.radians(np.linspace(-12.0, 47.0, 40)))))
    stop = budget_advice(near, _why("rival"), touched, REACH, 8)
    assert stop.startswith("the touch budget of 8 is spent") and "beyond the parabola's vertex" in stop
    x, y = stop.move["about"]
    t = -np.tan(np.radians(VERTEX_SIDE_DEG))
    phi = math.atan2(1.0, t) + near.pose.theta - math.pi
    assert REACH.finger(x, y, phi) is None and REACH.finger(x + stop.move["dx"], y + stop.move["dy"], phi) is not None
    # felt on both sides: where the recognizer's touch anywhere would go; within a pad's reach,
    # more touches, else the move
    both = _touched(np.linspace(-40.0, 40.0, 40))
    reachable = {"x": 105.0, "y": 12.0, "phi": -math.pi, "gain": 1.0, "why": "w"}
    stop = budget_advice(PARABOLA, _why("rival"), both, REACH, 8, anywhere=lambda: reachable)
    assert "--profile accurate" in stop and stop.move is None
    stop = budget_advice(PARABOLA, _why("rival"), both, REACH, 8, anywhere=lambda: {**reachable, "x": 93.0})
    assert "the most telling touch would roll at (93, 12) mm" in stop and stop.move is not None
    assert "--profile accurate" in budget_advice(PARABOLA, _why("rival"), both, REACH, 8)


def test_why_carries_its_kind():
    why = Why("parabola parameters not yet within 2 %", "imprecise")
    assert why == "parabola parameters not yet within 2 %" and why.kind == "imprecise"
    assert np.allclose(vertex_sides(PARABOLA, _touched([-30.0, 25.0])), (30.0, 25.0))
