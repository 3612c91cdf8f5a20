"""Which touch comes next (tactile_jaw.choose): the jaw's reach as the pads really roll,
the touch beyond a parabola's vertex on its short side, the recognizer's suggestion, and
stopping with a reason when nothing within reach can help."""

import json
import math
import re
from pathlib import Path

import numpy as np

from hand_driver.config import load_config
from recognizer.curves import CURVES, Pose
from recognizer.classify import NONE_TESTED_FITS, recognize
from recognizer.result import Ranked, Recognition
from recognizer.touches import parse_request
from tactile_jaw.choose import (MOVE_CLEAR_MM, MOVE_MAX_MM, MOVE_TURN_MAX_DEG, VERTEX_ENDS, VERTEX_OFF, JawReach, Stop,
                                Advice, budget_advice, curvature_at, move_advice, move_for, next_aim, place_goal, vertex_aim, vertex_goal)
from tactile_jaw.decide import NO_CLASS_FITS, VERTEX_SIDE_DEG, Why, refusal_kind, vertex_sides
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
    aim, stop = next_aim(suggesting, _why("vertex"), touched, REACH, fingers, [], vertex_missed=VERTEX_ENDS)
    assert aim is None and "fell off the curved part" in stop and stop.move is None
    aim, stop = next_aim(suggesting, _why("vertex"), touched, REACH, [CONFIG.fingers[1]], [])
    assert aim is None and "no pad can roll beyond the vertex" in stop and "move or turn the object" in stop


def _moved(move, x, y):
    """(x, y) turned by the move's turn about its ``about``, then shifted (tools.bench_explore.moved_object)."""
    a = math.radians(move["turn_deg"])
    ax, ay = move["about"]
    c, s = math.cos(a), math.sin(a)
    x, y = np.asarray(x, float) - ax, np.asarray(y, float) - ay
    return ax + c * x - s * y + move["dx"], ay + s * x + c * y + move["dy"]


def _vertex_region_reached(rec, move, edge_deg, reach=REACH):
    """Whether, the parabola answer ``rec`` moved so, a pad of ``reach`` rolls centred at every
    tangent turn within ±edge_deg of its vertex (every 2.5°: more places than the search asked),
    its contact travelling along the parabola over the roll (κ, κ_s at the place)."""
    curve = CURVES["parabola"](rec.params)
    for c in np.arange(-edge_deg, edge_deg + 1e-9, 2.5):
        t = np.array([math.tan(math.radians(c))])
        x, y = _moved(move, *rec.pose.apply(*curve.point(t)))
        phi = float(curve.tangent_angle(t)[0]) + rec.pose.theta - math.pi + math.radians(move["turn_deg"])
        curvature = (float(curve.kappa(t)[0]), float(curve.kappa_s(t)[0]))
        if reach.finger(float(np.ravel(x)[0]), float(np.ravel(y)[0]), phi, curvature=curvature) is None:
            return False
    return True


def test_a_stop_for_want_of_reach_names_a_move_after_which_a_pad_rolls_across_the_whole_vertex_region():
    # the parabola example 12 mm nearer the palm: 25° past its vertex on the palm side, where the
    # left pad would have to face down and toward +x, no pad rolls
    near = Recognition("parabola", PARABOLA.params, pose=Pose(-math.pi / 2, 93.0, 12.0), uncertainty={"a": 0.05},
                       ranking=PARABOLA.ranking)
    touched = near.pose.apply(*CURVES["parabola"](near.params).point(np.tan(np.radians(np.linspace(-12.0, 47.0, 40)))))
    assert vertex_aim(near, touched, REACH) is None
    edge = VERTEX_SIDE_DEG + 0.25 * math.degrees(SETTINGS.roll_span_rad)
    assert not _vertex_region_reached(near, {"dx": 0.0, "dy": 0.0, "turn_deg": 0.0, "about": [0.0, 0.0]}, edge)
    aim, stop = next_aim(near, _why("vertex"), touched, REACH, list(CONFIG.fingers), [])
    assert aim is None and isinstance(stop, Stop) and stop.move is not None
    move = stop.move
    assert 0 < math.hypot(move["dx"], move["dy"]) <= MOVE_MAX_MM + 2.0 and abs(move["turn_deg"]) <= MOVE_TURN_MAX_DEG
    assert "across its vertex" in stop and ("away from the palm (+x)" in stop if move["dx"] > 0 else "(-x)" in stop)
    assert move["about"] == list(near.pose.apply(0.0, 0.0))  # turned about the vertex
    # moved so, a pad rolls centred anywhere within the region both sides of the vertex, not only the short side
    assert _vertex_region_reached(near, move, edge)
    # and the felt stretch and the region stay inside the workspace disk, clear of the opened jaw
    (cx, cy), radius = CONFIG.workspace.center_mm, CONFIG.workspace.radius_mm
    x, y = _moved(move, *touched)
    assert np.all(np.hypot(x - cx, y - cy) <= radius - MOVE_CLEAR_MM + 1e-9)


def test_a_move_keeps_the_known_boundary_clear_of_the_opened_jaw():
    # a place near the left pad's reach edge, the felt stretch 2 mm inside the workspace disk near the
    # opened left pad (y = 43): the reach-only search moved the object there, across the pad; the goal's
    # move keeps every known point inside the disk (or no farther out than it was)
    (cx, cy), radius = CONFIG.workspace.center_mm, CONFIG.workspace.radius_mm
    x, y, phi = 93.0, 12.0, math.atan2(1.0, -math.tan(math.radians(VERTEX_SIDE_DEG))) - math.pi / 2 - math.pi
    felt = (np.array([110.0, 115.0, 120.0]), np.array([radius - 2.0, radius - 2.5, radius - 4.0]))
    goal = place_goal(x, y, phi, felt)
    dx, dy, turn = move_for(REACH, goal)
    assert REACH.finger(x, y, phi) is None and REACH.finger(x + dx, y + dy, phi + turn) is not None
    mx, my = _moved({"dx": dx, "dy": dy, "turn_deg": math.degrees(turn), "about": [x, y]}, *felt)
    before = np.hypot(felt[0] - cx, felt[1] - cy)
    assert np.all(np.hypot(mx - cx, my - cy) <= np.maximum(radius - MOVE_CLEAR_MM, before) + 1e-9)


def test_move_advice_turns_the_object_when_no_shift_brings_the_tangent_within_reach():
    # a place at the example's vertex whose pad would have to face up and toward +x (ψ = 60°):
    # no shift helps, a turn about the place does, and the words say which way
    x, y, phi = 105.0, 12.0, math.radians(60.0) - math.pi / 2
    goal = place_goal(x, y, phi)
    assert move_for(REACH, goal) is not None
    advice = move_advice(REACH, goal)
    words, move = advice.words, advice.move
    assert advice.kind == "move"
    dx, dy, turn = move["dx"], move["dy"], math.radians(move["turn_deg"])
    assert turn != 0.0 and REACH.finger(x + dx, y + dy, phi + turn) is not None
    assert ("counterclockwise" if turn > 0 else "clockwise") in words
    # within reach already: nothing to move, the general request
    assert move_advice(REACH, place_goal(105.0, 12.0, -math.pi)) == Advice(
        "move or turn the object so that more of its curved part faces a finger", None, "within_reach")


def test_no_move_is_advised_when_no_class_fits():
    # the touches disagree with every class: where they were is not what failed, so the budget's
    # advice names no move, even though the recognizer's next_touch anywhere lies out of reach
    none = Recognition("unclassified", {}, reason="no class of the scene fits: closest class parabola: …",
                       next_touch={"x": 93.0, "y": 12.0, "phi": -math.pi, "gain": 1.0, "why": "w"})
    stop = budget_advice(none, _why("unclassified"), _touched(np.linspace(-47.0, 12.0, 40)), REACH, 8,
                         anywhere=lambda: {"x": 93.0, "y": 12.0, "phi": -math.pi, "gain": 1.0, "why": "w"})
    assert stop.move is None and "no class of the scene fits" in stop and "no move" in stop
    assert refusal_kind(none.reason) == "no class fits"
    assert refusal_kind("not decisive after 4 usable touches: …; move the object 4 mm", {"dx": 4.0}) == "out of reach"


def test_classes_untested_for_too_few_touches_make_no_no_class_fits_refusal():
    # dev seed 83, P-series semicubical 27: 2 of 8 touches clear of the end corners; the parabola
    # (the richest class 2 touches test) fails, ellipse..semicubical were never tested. That is
    # not "no class fits" (no move helps) but too few usable touches: another placement or more
    # touches (saved request: tactile replay --touches on the run's log)
    request = parse_request(json.loads((Path(__file__).parent / "data" / "p_semicubical_two_clear_touches.json")
                                       .read_text()))
    rec = recognize(request)
    assert rec.cls == "unclassified"
    assert set(rec.untested) == {"ellipse", "hyperbola", "cubical_parabola", "semicubical_parabola"}
    assert rec.reason.startswith(NONE_TESTED_FITS) and not rec.reason.startswith(NO_CLASS_FITS)
    assert "parabola" in rec.reason and "needs 3 touches, got 2" in rec.reason
    assert refusal_kind(rec.reason) == "needs another move"
    stop = budget_advice(rec, _why("unclassified"), _touched(np.linspace(-47.0, 12.0, 40)), REACH, 8)
    assert stop.move is None and "no class of the scene fits" not in stop
    assert "semicubical_parabola" in stop and "clear of its corners" in stop
    assert refusal_kind(stop) == "needs another move"


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
    edge = VERTEX_SIDE_DEG + 0.25 * math.degrees(SETTINGS.roll_span_rad)
    assert "across its vertex" in stop and _vertex_region_reached(near, stop.move, edge)
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


def test_a_vertex_roll_that_ran_off_the_pad_is_tried_again_at_the_next_centre():
    """A touch aimed beyond the vertex that did not fall off the curved part (its contact ran
    off the pad's face: P parabola 78 of bench_explore --finite 20 --anywhere --seed 107) is
    aimed again at the next centre a pad reaches, still rolling past VERTEX_SIDE_DEG; once
    every such centre was aimed at, the recognizer's touch (or the stop without one) as before."""
    touched = _touched(np.linspace(-47.0, 12.0, 40))
    fingers = list(CONFIG.fingers)
    first, _ = next_aim(PARABOLA, _why("vertex"), touched, REACH, fingers, [])
    again, stop = next_aim(PARABOLA, _why("vertex"), touched, REACH, fingers, [first.point])
    assert stop is None and again.kind == "vertex" and math.hypot(again.x - first.x, again.y - first.y) > 1.0
    a = PARABOLA.params["a"]
    turns = [math.degrees(math.atan(PARABOLA.pose.inverse(p.x, p.y)[1] / (2 * a))) for p in (first, again)]
    half = 0.5 * math.degrees(SETTINGS.roll_span_rad)
    assert abs(abs(turns[1] - turns[0]) - 2.5) < 1e-6 and min(turns) + half >= VERTEX_SIDE_DEG
    aimed, aim = [], first
    while aim is not None and aim.kind == "vertex":
        aimed.append(aim.point)
        aim, stop = next_aim(PARABOLA, _why("vertex"), touched, REACH, fingers, aimed)
    # PARABOLA suggests no touch: the stop the vertex side aimed at once gave before
    assert aim is None and "move or turn the object" in stop and len(aimed) >= 3


def test_a_move_to_the_telling_touch_also_brings_the_side_an_unrolled_finger_met_within_reach():
    # random X-series ellipse 57 of bench_explore --finite 20 --anywhere --seed 127: the left
    # finger alone rolled (one end: ellipse, semicubical and parabola fit), the right pad met
    # the object only at its proximal end (probe at ψ 90°: the contact 5.3 mm along the pad).
    # The budget's move to the most telling touch alone left the right pad as it was (moved so,
    # refused again); with the right's place it reaches both, and moved so it is answered
    ellipse = Recognition("ellipse", {"a": 19.7, "b": 11.9}, pose=Pose(1.14, 94.0, -13.0),
                          uncertainty={"a": 0.3, "b": 0.2},
                          ranking=[Ranked("ellipse", True, 19.7, 22, 325.7, 0.6),
                                   Ranked("semicubical_parabola", True, 20.1, 22, 326.1, 0.57)])
    wanted = {"x": 87.138, "y": -0.463, "phi": math.radians(-48.0) - math.pi / 2, "gain": 0.3, "why": "w"}
    right = (97.875, -30.442, 1.62295 - math.pi / 2)
    assert REACH.finger(*right) is None and REACH.finger(wanted["x"], wanted["y"], wanted["phi"]) is None
    alone = budget_advice(ellipse, _why("rival"), None, REACH, 8, anywhere=lambda: wanted)
    both = budget_advice(ellipse, _why("rival"), None, REACH, 8, anywhere=lambda: wanted, also=[right])
    assert alone.move is not None and both.move is not None and "met only at its pad's end" in both

    def reached(move, x, y, phi):  # the contact travelling along the answered ellipse over the roll
        mx, my = _moved(move, np.array([x]), np.array([y]))
        return REACH.finger(float(mx[0]), float(my[0]), phi + math.radians(move["turn_deg"]),
                            curvature=curvature_at(ellipse, x, y)) is not None

    assert reached(both.move, wanted["x"], wanted["y"], wanted["phi"]) and reached(both.move, *right)
    assert not reached(alone.move, *right)
    # no move reaches both: the telling touch's alone
    far = (60.0, -30.0, 1.62295 - math.pi / 2)
    assert budget_advice(ellipse, _why("rival"), None, REACH, 8, anywhere=lambda: wanted, also=[far]).move == alone.move


def test_a_vertex_region_no_move_reaches_whole_is_narrowed_so_the_refusal_still_names_a_move():
    # random P parabola 72 of bench_explore --finite 20 --anywhere --seed 157, as its touches fitted it: felt
    # 52° on one side of the vertex, 0° on the other; one pad reaches about 45° of its tangent turn from
    # any placement, so no move up to 20 mm and 30° lets a pad roll centred 29.5° either side (refused
    # naming no move); the region a quarter roll narrower each side is reached after a move
    p_reach = JawReach(load_config(ROOT / "config" / "jaw-p.yaml"), SETTINGS)
    rec = Recognition("parabola", {"a": 10.347}, pose=Pose(-2.1108, 130.480, 9.358), uncertainty={"a": 0.01},
                      ranking=PARABOLA.ranking)
    touched = rec.pose.apply(*CURVES["parabola"](rec.params).point(np.tan(np.radians(np.linspace(-52.0, 0.0, 30)))))
    assert vertex_aim(rec, touched, p_reach) is None
    assert move_for(p_reach, vertex_goal(rec, touched, p_reach)) is None
    aim, stop = next_aim(rec, _why("vertex"), touched, p_reach, list(p_reach.config.fingers), [])
    assert aim is None and stop.move is not None and "no pad can roll beyond the vertex" in stop
    half = 0.5 * math.degrees(SETTINGS.roll_span_rad)
    narrow = float(re.search(r"across its vertex, (\d+) deg either side", stop).group(1))
    # narrower than the widest region, no narrower than each roll's far end a quarter roll past VERTEX_SIDE_DEG
    assert VERTEX_SIDE_DEG - 0.5 * half - 0.5 <= narrow < VERTEX_SIDE_DEG + 0.5 * half - 0.5
    still = {"dx": 0.0, "dy": 0.0, "turn_deg": 0.0, "about": [0.0, 0.0]}
    assert not _vertex_region_reached(rec, still, narrow, p_reach)
    assert _vertex_region_reached(rec, stop.move, narrow, p_reach)
    # a roll aimed beyond the vertex that ran off the curved part without pivoting about a corner
    # (at the edge of its pad's reach) names the move too; one that pivoted (the object ends there) does not
    aim, off = next_aim(rec, _why("vertex"), touched, p_reach, list(p_reach.config.fingers), [],
                        vertex_missed=VERTEX_OFF)
    assert aim is None and off.move == stop.move and "without pivoting about a corner" in off
    aim, ends = next_aim(rec, _why("vertex"), touched, p_reach, list(p_reach.config.fingers), [],
                         vertex_missed=VERTEX_ENDS)
    assert aim is None and ends.move is None and "the object ends there" in ends


def test_the_reach_of_many_places_at_once_is_each_places_own_without_asking_each(monkeypatch):
    # random places in and around the workspace disk, random tangents, both jaws: contains()
    # answers as finger() does place by place, and asks finger() about none of them (before:
    # every place inside the disk, 3.4 of 13.5 s CPU of a live P run, seed 313 rand65)
    rng = np.random.default_rng(5)
    for path in ("jaw.yaml", "jaw-p.yaml"):
        reach = JawReach(load_config(ROOT / "config" / path), SETTINGS)
        c, r = np.array(reach.config.workspace.center_mm), reach.config.workspace.radius_mm
        ang, rad = rng.uniform(0, 2 * np.pi, 400), r * np.sqrt(rng.uniform(0, 1.1, 400))
        px, py, phi = c[0] + rad * np.cos(ang), c[1] + rad * np.sin(ang), rng.uniform(-np.pi, np.pi, 400)
        exact = [bool(reach.disk.contains(x, y)) and reach.finger(x, y, f) is not None for x, y, f in zip(px, py, phi)]
        asked = []
        monkeypatch.setattr(JawReach, "finger", lambda self, *a, **k: asked.append(a))
        assert reach.contains(px, py, phi).tolist() == exact
        assert 40 <= sum(exact) <= 360 and not asked
        monkeypatch.undo()


def test_the_finger_nearest_its_zero_angle_normal_is_asked_first(monkeypatch):
    # the parabola example's vertex facing down: the left pad rolls there, nearest its normal;
    # the right one is not asked (before: both, then the nearer of those that roll)
    import tactile_jaw.choose as choose
    asked = []
    real = choose.feasible
    monkeypatch.setattr(choose, "feasible", lambda f, *a, **k: asked.append(f.name) or real(f, *a, **k))
    assert REACH.finger(105.0, 12.0, -math.pi).name == "left" and asked == ["left"]
    asked.clear()
    assert REACH.finger(105.0, 12.0, -math.pi / 2) is None and sorted(asked) == ["left", "right"]


def test_a_move_says_where_it_was_for_and_which_finger_rolls_there_after_it():
    # the place turns about itself (the goal's ``about``) and shifts with the object: after the move
    # it lies at (x + dx, y + dy) with its tangent turned, and a pad of the named finger rolls there
    from tactile_jaw.choose import moved_places

    x, y, phi = 105.0, 12.0, math.radians(60.0) - math.pi / 2
    move = move_advice(REACH, place_goal(x, y, phi)).move
    (place,) = move["places"]
    turn = math.radians(move["turn_deg"])
    assert (place["x"], place["y"]) == (round(x + move["dx"], 3), round(y + move["dy"], 3))
    assert place["phi"] == round(math.remainder(phi + turn, 2 * math.pi), 5)
    finger = REACH.finger(place["x"], place["y"], place["phi"])
    assert finger is not None and place["finger"] == finger.name
    # a place no pad rolls at (far outside the workspace) names no finger
    assert moved_places(REACH, place_goal(300.0, 300.0, 0.0), 0.0, 0.0, 0.0)[0]["finger"] is None
