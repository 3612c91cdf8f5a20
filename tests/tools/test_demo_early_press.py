"""`tactile demo` on a block of the P-series jaw (random block 0 of ``bench_explore --finite
10 --anywhere --classes line --config config/jaw-p.yaml --seed 11``, development): a pad's
first-round lines show a seat, so in the second round it presses flat there
(tactile_jaw.flat_phase.early_press) while the other pad rolls again; that press is the face's
first flat touch. Before, both fingers rolled a second time and the presses began after (4
presses after 4 rolls, 46.8 s; then 43.5 s). Until session 13 the right pad pressed closing
segment 2 (its roll crossed it); since a seat may be 0.2 of the pad (its supports, the part of
the pad toward the other however short), the left pad's probe and roll lines show the top face
(27.5 mm, its outward normal at 78.8°) and it presses there first (33.3 s). Three presses of
the face answer (tactile_jaw.decide.repeats_a_face: a fourth repeated its place)."""

from __future__ import annotations

import json
import math

from hand_driver.log import read_log

BLOCK = {"name": "rand0", "classes": ["line", "circle", "ellipse", "parabola", "hyperbola", "cubical_parabola",
                                       "semicubical_parabola"],
         "object": {"class": "line", "params": {},
                    "pose": {"theta": -0.19535577075707344, "x": 121.411672999304, "y": -16.62320220455208},
                    "extent": [-15.744180465992144, 15.744180465992144],
                    "closure": [[15.744180465992144, -12.595344372793715],
                                [-15.744180465992144, -12.595344372793715]]}}


def test_a_finger_whose_roll_crossed_a_face_presses_it_in_the_second_round(tmp_path, demo_answer, tactile_in_process):
    log = tmp_path / "rand0.jsonl"
    answer = demo_answer(BLOCK, tmp_path / "rand0.yaml", log, "config/jaw-p.yaml")
    assert answer["class"] == "line", answer.get("reason")
    # closing segment 2 (the right side, turned): the face the right pad presses
    lines = [json.loads(s) for s in log.read_text().splitlines()]
    starts = [r for r in lines if r["type"] == "touch_start" and r.get("span") != 0.10471975511965978]  # not probes
    first_flat = next(k for k, r in enumerate(starts) if r.get("kind") == "flat")
    # the second round: a press and a roll (touch indices 11 and 12, in whichever order they start)
    assert first_flat in (2, 3) and {starts[2].get("kind"), starts[3].get("kind")} == {None, "flat"}
    assert starts[first_flat]["finger"] == "left" and starts[5 - first_flat]["finger"] == "right"
    used = [e for e in read_log(log).events if e.get("kind") == "touch_used"]
    assert used[0]["touch"] == starts[first_flat]["touch"] and len(used) == 3
    # the answer's line is the face that press seated on (ψ −101.2°: the top face, outward normal at 78.8°)
    assert abs(math.remainder(answer["pose"]["theta"] - (math.radians(-101.19) + math.pi / 2), 2 * math.pi)) < 3e-3
    result = next(r for r in lines if r["type"] == "result")
    assert result["robot_time_s"] < 45.0
    rc, out, err = tactile_in_process(["replay", str(log), "--json"])
    assert rc == 0 and json.loads(out)["class"] == "line"
    assert json.loads(out)["pose"] == answer["pose"]
