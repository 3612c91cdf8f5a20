"""`tactile demo` on a block of the P-series jaw whose left pad, its probes done, has a seat in
its probe lines while the right pad still probes (random block 6 of ``bench_explore --finite 20
--anywhere --seed 107 --config config/jaw-p.yaml``): the left pad presses there in the probe
rounds (tactile_jaw.probing.probe_boundary's ``beside``, tactile_jaw.flat_phase.beside_press),
and its three presses are done before the right pad's one roll ends, so the flat phase answers
at once: 20.1 s of robot time (26.8 s before session 14, when the left pad waited 6 s for the
right's probes, then 2 s for its roll, before pressing; 18.7 s before session 29 paced the
transits' turns to the servos' profile velocity, hand_driver.motion.move_line ``paced``). The answer is one of the block's faces."""

from __future__ import annotations

import math

import numpy as np

from hand_driver.log import read_log

EXTENT, HEIGHT = 25.964615901821787, 20.771692721457427
POSE = {"theta": -0.24913256582154464, "x": 114.95449115948823, "y": 13.383562588680403}
BLOCK = {"name": "block6", "classes": ["line", "circle", "ellipse", "parabola", "hyperbola", "cubical_parabola",
                                        "semicubical_parabola"],
         "object": {"class": "line", "params": {}, "pose": POSE, "extent": [-EXTENT, EXTENT],
                    "closure": [[EXTENT, -HEIGHT], [-EXTENT, -HEIGHT]]}}


def _faces() -> list[tuple[np.ndarray, np.ndarray]]:
    """The block's four faces (hand frame, mm), each as its two corners."""
    c, s = math.cos(POSE["theta"]), math.sin(POSE["theta"])
    canonical = [(-EXTENT, 0.0), (EXTENT, 0.0), (EXTENT, -HEIGHT), (-EXTENT, -HEIGHT)]
    corners = [np.array([POSE["x"] + c * u - s * v, POSE["y"] + s * u + c * v]) for u, v in canonical]
    return [(corners[k], corners[(k + 1) % 4]) for k in range(4)]


def test_a_finger_done_probing_presses_at_the_seat_its_probes_show(tmp_path, demo_answer):
    log = tmp_path / "block6.jsonl"
    answer = demo_answer(BLOCK, tmp_path / "block6.yaml", log, config="config/jaw-p.yaml")
    assert answer["class"] == "line", answer.get("reason")
    pose = answer["pose"]
    direction = np.array([math.cos(pose["theta"]), math.sin(pose["theta"])])
    normal = np.array([-direction[1], direction[0]])
    on = [p for p, q in _faces() if abs(float(normal @ (q - p))) / np.linalg.norm(q - p) < 5e-3
          and max(abs(float(normal @ (r - np.array([pose["x"], pose["y"]])))) for r in (p, q)) < 0.3]
    assert len(on) == 1  # the answer's line runs along one face of the block
    contents = read_log(log)
    first_roll = min(t.touch for t in contents.touches if t.kind != "flat" and len(t.psi) > 4)
    presses = [t for t in contents.touches if t.kind == "flat"]
    assert len(presses) == 3 and {t.finger for t in presses} == {"left"}
    assert presses[0].touch < first_roll  # pressed in the probe rounds, before any rolling touch
    assert contents.result["robot_time_s"] < 21.0


ELLIPSE = {"name": "ellipse8", "classes": BLOCK["classes"],
           "object": {"class": "ellipse", "params": {"a": 25.890036012863142, "b": 15.534021607717886},
                      "pose": {"theta": -2.5860319961987375, "x": 126.64129144073003, "y": -6.5181860358871475}}}


def test_a_finger_with_no_roll_does_not_walk_to_a_seat_before_any_roll(tmp_path, demo_answer):
    """Random ellipse 8 of ``bench_explore --finite 3 --anywhere --seed 13 --config
    config/jaw-p.yaml``: the left pad has no orientation to roll at before the right pad's first
    roll, and its lines show no seat. A walk from its nominal normal there (4–12 s) held up the
    round of the right pad's first roll, which was usable: 22.9 s instead of 12.5. A finger
    presses from its nominal normal only once a roll found no curved part (tactile_jaw.explore)."""
    log = tmp_path / "ellipse8.jsonl"
    answer = demo_answer(ELLIPSE, tmp_path / "ellipse8.yaml", log, config="config/jaw-p.yaml")
    assert answer["class"] == "ellipse", answer.get("reason")
    assert abs(answer["params"]["a"] / ELLIPSE["object"]["params"]["a"] - 1) < 0.01
    contents = read_log(log)
    assert not [t for t in contents.touches if t.kind == "flat"]
    assert contents.result["robot_time_s"] < 14.0
