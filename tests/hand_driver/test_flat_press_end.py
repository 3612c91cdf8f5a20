"""A face that runs on past the pad's end: beyond the seat the pad rests on its own end,
which slides along the face as the pad turns (hand_driver.flat_press.end_support,
sliding_fill). Checked on exact stops (the emulator's penetration test, bisected) of random
block 6 of bench_explore --finite 20 --anywhere --seed 127 (a development seed), whose top
face is turned 46.5° from the left pad's nominal normal and 9 mm of it lie beyond the pad's
distal end when the pad lies flat: refused before on both jaws (the press turned its 60°
without a seat)."""

import math

import numpy as np
import pytest

from hand_driver.flat_press import SEAT_TOL_MM, better_support, face_normal
from hand_driver.sim.physics import ContactWorld
from recognizer.scene import load_scene
from tests.hand_driver.test_flat_press import CONFIG, _walk

THETA, X, Y, E, H = -0.8120495610835197, 112.39000494513441, 3.073523858515601, 17.897354858513534, 14.317883886810828
BLOCK = load_scene({"name": "rand6", "classes": ["line"], "object": {
    "class": "line", "params": {}, "pose": {"theta": THETA, "x": X, "y": Y},
    "extent": [-E, E], "closure": [[E, -H], [-E, -H]]}}).object
#: the top face's corners and the seated left pad's normal (−n of the face's outward normal)
CORNERS = [np.array([X, Y]) + t * np.array([math.cos(THETA), math.sin(THETA)]) for t in (E, -E)]
SEAT_PSI = THETA - math.pi / 2


def test_a_face_past_the_pad_end_seats_on_the_sliding_end():
    """The walk from the left pad's nominal normal seats: one support the face's corner
    under the pad, the other the pad's distal end (on the face, short of its far corner),
    the face's normal within 0.05° of the truth (the lines resting on the sliding end pass
    through no one point: whole steps alone never seated)."""
    finger = CONFIG.finger("left")
    found, lines = _walk(ContactWorld(CONFIG, BLOCK), finger, -math.pi / 2)
    assert found is not None
    groups, p, q = found
    n = face_normal(p, q, lines[min(lines)].normal)
    assert math.atan2(n[1], n[0]) == pytest.approx(SEAT_PSI, abs=math.radians(0.05))
    top = np.array([-math.sin(THETA), math.cos(THETA)])
    for s in (p, q):  # both supports on the face's line
        assert float(top @ (s - CORNERS[0])) == pytest.approx(0.0, abs=SEAT_TOL_MM)
    corner = min(CORNERS, key=lambda c: min(np.linalg.norm(p - c), np.linalg.norm(q - c)))
    assert min(np.linalg.norm(p - corner), np.linalg.norm(q - corner)) < 0.1  # one support the corner
    ends = [ln.distal for ln in lines.values()]
    assert min(float(np.linalg.norm(e - s)) for e in ends for s in (p, q)) < 1e-9  # the other a pad end
    assert any(k != round(k) for k in lines)  # approaches between whole steps were made


def test_the_better_support():
    """A pad turned about a corner near its end slides along its line, and near the seat its
    end lies within the tolerance of the face's line too: the corner, through which its lines
    pass (better than the ends lie on a line), stays the support, and so does a point within
    END_SUPPORT_MM of the end; the end wins when its fit is better and the point farther (lines
    resting on a sliding end passed within 0.05 mm of a point 11 mm inside the pad), or when
    fewer than 3 lines pass through a point."""
    corner = (3, np.array([100.0, 10.0]), 0.01)
    assert better_support(corner, None) is corner
    assert better_support(corner, (3, np.array([100.0, 13.0]), 0.0)) is corner  # 3 mm: that end is the corner
    far_end = (3, np.array([100.0, 21.0]), 0.0)
    assert better_support(corner, far_end) is far_end
    exact = (3, corner[1], 0.0)
    assert better_support(exact, (3, far_end[1], 0.01)) is exact
    assert better_support((2, corner[1], 0.0), far_end) is far_end
