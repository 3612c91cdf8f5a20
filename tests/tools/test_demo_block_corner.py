"""`tactile demo` on a block turned 13.5° (random block 17 of ``bench_explore --finite 20
--seed 13``): the right pad's one usable rolling touch lies beside the corner its other
touches pivoted about, and is dropped by the corner clearance (6 of its 9 samples within
2 mm). With no rolling touch left clear of the corners the pads press flat on the faces:
the answer is the line of the face, not a refusal. (Before, the flat presses ran only when
no rolling touch was usable at all, and this block was refused.) Since the left pad presses
during the rolls (tactile_jaw.flat_phase.early_press: its probe lines show the seat, and the
right pad's first two rolls found no usable touch), the right pad's roll beside the corner is
no longer made. Since a finger with no roll to make presses beside the other's rolls
(tactile_jaw.flat_phase.beside_press: the left pad, its probes on pad ends and a corner, has no
orientation to roll at), the left pad's first press runs in the round of the right pad's first
roll and its three presses are done while the right pad still rolls: 19.2 s of robot time,
21.6 s before, when they began with the right pad's third roll."""

from __future__ import annotations

import math

from hand_driver.log import read_log

BLOCK = {"name": "block17", "classes": ["line", "circle", "ellipse", "parabola", "hyperbola", "cubical_parabola",
                                         "semicubical_parabola"],
         "object": {"class": "line", "params": {},
                    "pose": {"theta": -0.2363024378608834, "x": 102.13024615431051, "y": 12.662769393302662},
                    "extent": [-32.804347512122064, 32.804347512122064],
                    "closure": [[32.804347512122064, -26.243478009697654],
                                [-32.804347512122064, -26.243478009697654]]}}


def test_a_block_whose_rolling_touch_sits_at_a_corner_is_pressed_flat(tmp_path, demo_answer):
    log = tmp_path / "block17.jsonl"
    answer = demo_answer(BLOCK, tmp_path / "block17.yaml", log)
    assert answer["class"] == "line", answer.get("reason")
    # the top face: the line through the block's pose at its angle, the solid on its right
    pose, truth = answer["pose"], BLOCK["object"]["pose"]
    assert abs(math.remainder(pose["theta"] - truth["theta"], 2 * math.pi)) < 5e-3
    offset = -math.sin(truth["theta"]) * (pose["x"] - truth["x"]) + math.cos(truth["theta"]) * (pose["y"] - truth["y"])
    assert abs(offset) < 0.3
    contents = read_log(log)
    first_press = next(t for t in contents.touches if t.kind == "flat")
    assert first_press.finger == "left"
    rolls_after = [t for t in contents.touches if t.kind != "flat" and t.touch > first_press.touch]
    assert [t.finger for t in rolls_after] == ["right"] * 3  # the right pad rolled on beside the left's presses
    assert contents.result["robot_time_s"] < 20.0
