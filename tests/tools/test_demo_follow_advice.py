"""`tactile demo` on a parabola placed 8 mm nearer the palm than the example and turned 14°
(random parabola 61 of ``bench_explore --finite 20 --seed 13``): no pad can roll beyond its
vertex on the palm side, so the exploration stops and refuses, naming the move of the object
after which a pad rolls across its vertex region (tactile_jaw.choose.move_advice). Moved so, as a person
following the advice would, the same object is recognized: the advice is one that works."""

from __future__ import annotations

import math

from hand_driver.log import read_log
from tools.bench_explore import moved_object

P_JAW = "config/jaw-p.yaml"
PARABOLA = {"name": "parabola61", "classes": ["line", "circle", "ellipse", "parabola", "hyperbola",
                                              "cubical_parabola", "semicubical_parabola"],
            "object": {"class": "parabola", "params": {"a": 8.839390478834567}, "extent": [-1.5, 1.5],
                       "pose": {"theta": -1.3191263801765232, "x": 97.34762312807575, "y": 15.139191865655976}}}


def test_a_refusal_for_want_of_reach_names_a_move_that_makes_the_object_recognizable(tmp_path, demo_answer):
    # on the P-series jaw: the X-series jaw cannot tell a parabola from a semicubical whose
    # cusp lies at the touched stretch's edge (tactile_jaw.decide.inseparable) wherever it is
    scene, log = tmp_path / "parabola61.yaml", tmp_path / "parabola61.jsonl"
    answer = demo_answer(PARABOLA, scene, log, config=P_JAW)
    assert answer["class"] == "unclassified" and "no pad can roll beyond the vertex" in answer["reason"]
    assert "a pad can roll across its vertex" in answer["reason"]
    move = next(e for e in read_log(log).events if e.get("kind") == "stopped_early")["move"]
    assert math.hypot(move["dx"], move["dy"]) <= 22.0 and abs(move["turn_deg"]) <= 30.0
    assert (move["dx"], move["dy"], move["turn_deg"]) != (0.0, 0.0, 0.0)
    answer = demo_answer({**PARABOLA, "object": moved_object(PARABOLA["object"], move)}, scene, config=P_JAW)
    assert answer["class"] == "parabola", answer.get("reason")
    assert abs(answer["params"]["a"] / PARABOLA["object"]["params"]["a"] - 1.0) < 0.02
