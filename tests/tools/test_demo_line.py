"""tactile demo's truth line for a line object: the answer's canonical line pose (the foot of
the perpendicular, θ with the solid on the right) against the object's nearest straight edge."""

from __future__ import annotations

import math

from recognizer.scene import load_scene
from tools.cmd_demo import line_pose_error

LINE = load_scene("config/scenes/line.yaml").object  # top face y = 10 (the line), block x 80..130, y -10..10


def test_the_top_face_and_a_closing_segment_are_both_found():
    assert line_pose_error({"theta": 0.001, "x": 0.0, "y": 10.02}, LINE) == \
        "no parameters; pose offset 0.02 mm, angle +1.0 mrad from the line"
    # the bottom face, travelled −x with the block on its right, is closing segment 2
    out = line_pose_error({"theta": math.pi, "x": 0.0, "y": -10.05}, LINE)
    assert out == "no parameters; pose offset 0.05 mm, angle +0.0 mrad from closing segment 2"
    # the top face travelled the wrong way (the solid on its left) is no face of the block:
    # nearest is the bottom face, 20 mm away
    assert line_pose_error({"theta": math.pi, "x": 0.0, "y": 10.0}, LINE) == \
        "no parameters; pose offset 20.00 mm, angle +0.0 mrad from closing segment 2"
