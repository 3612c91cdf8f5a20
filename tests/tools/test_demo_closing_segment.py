"""A closing segment is no line once a roll of the other finger felt the curve move under the
pad (tactile_jaw.pipeline.moving_stretch). P hyperbola 45 of bench_explore --finite 10
--anywhere --calibrate --seed 433 (session 28's held-out calibrated run, a development seed
since; the same on the uncalibrated P jaw): its left pad's first roll kept 8 lines on the
branch before its end corner, its second turned about that corner and the finger retired
(two rolls off the curve), the right pad seated three times on the chord, and the flat phase
answered `line` — a wrong class. Session 29 made the flat phase stop before pressing,
refused: the faces are closing segments (tests/tactile_jaw/test_flat_moving_contact.py keeps
that rule on the logged rolls). Session 30: the stretch on which the first roll's contact moved
is where the left finger rolls next (tactile_jaw.pipeline.moving_hint), and the run is answered
hyperbola."""

from __future__ import annotations

import json

SCENE = {"name": "hyperbola_45", "classes": ["line", "circle", "ellipse", "parabola", "hyperbola", "cubical_parabola",
                                             "semicubical_parabola"],
         "object": {"class": "hyperbola", "extent": [-1.3, 1.3],
                    "params": {"a": 9.913058884762528, "b": 9.913058884762528},
                    "pose": {"theta": -0.9380753485688964, "x": 88.53656810149093, "y": 21.238957381245562}}}


def test_a_roll_that_moved_on_the_branch_aims_the_next_roll_there(tmp_path, demo_answer):
    log = tmp_path / "hyperbola_45.jsonl"
    answer = demo_answer(SCENE, tmp_path / "hyperbola_45.yaml", log, config="config/jaw-p.yaml")
    assert answer["class"] == "hyperbola", answer.get("reason")
    truth = SCENE["object"]["params"]
    for name in ("a", "b"):
        assert abs(answer["params"][name] / truth[name] - 1.0) < 0.01, (name, answer["params"])
    text = log.read_text()
    assert '"kind":"touch_rejected"' in text  # the first roll, off the curve at the end corner
    result = [json.loads(line) for line in text.splitlines() if '"type":"result"' in line][-1]
    assert result["touches_used"] >= 3
