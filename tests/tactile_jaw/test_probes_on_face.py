"""A finger whose probes met the object only on the face its presses seated on, or at that face's
supports, is not held to a roll before the flat presses answer (tactile_jaw.explore.probes_on_face,
unrolled_before_flat): X-series lines 1, 4, 9, 19 of bench_explore --finite 20 --anywhere --seed
269 held the right pad, its 3 seated presses done, to a roll of 3.4–4.1 s after them. Probes of
the X-series left pad through whole ticks (tests/tactile_jaw/test_plan_model.py)."""

import math
from types import SimpleNamespace

import numpy as np

from hand_driver import kinematics as kin
from hand_driver.cycle import LIMIT_MARGIN_RAD
from hand_driver.flat_press import SEAT_TOL_MM, FlatResult
from tactile_jaw.explore import OFF_CURVE_RETIRE, probes_on_face, unrolled_before_flat
from tactile_jaw.flat import Face
from tactile_jaw.pipeline import FeltTouch
from tactile_jaw.plan import probe_face_contact
from tactile_jaw.rounds import Exploration

from test_plan_model import CONFIG, _probe, _probe_psis

FACE_PSI = math.radians(-90.0)


def _face_and_corner() -> tuple[Face, np.ndarray]:
    """A 12 mm face of pad normal −90° whose support P lies in the left pad's middle when the pad
    turns 10° below that normal (a probe there pivots about P), its other support Q away from it."""
    left = CONFIG.finger("left")
    psi = FACE_PSI - math.radians(10.0)
    line = kin.finger_pad_line(left, kin.ik_line(left, psi, -20.0, margin_rad=LIMIT_MARGIN_RAD))
    p = line.proximal + 26.0 * line.tangent
    t = np.array([-math.sin(FACE_PSI), math.cos(FACE_PSI)])
    q = p - 12.0 * t  # n(ψ)·(Q − P) = 12 sin(10°) > 0 below the face's normal: P is the support there
    return Face(FACE_PSI, float(kin.unit(FACE_PSI) @ p), p, q), p


def _seated(face: Face) -> FeltTouch:
    return FeltTouch(FlatResult("left", 5, face.psi, [object()] * 9, outcome="ok", roles=[]), None, None, None, None,
                     None, face=face)


def test_probes_about_the_seated_face_s_support_met_that_face():
    face, p = _face_and_corner()
    psis = _probe_psis(math.degrees(FACE_PSI) - 10.0)
    about_p, _ = _probe([p] * len(psis), psis)
    assert probes_on_face(CONFIG, "left", [about_p], [_seated(face)])
    assert not probes_on_face(CONFIG, "left", [about_p], [])  # no seated face: nothing says what they met
    assert not probes_on_face(CONFIG, "right", [about_p], [_seated(face)])  # the other finger's face
    n = kin.unit(float(np.mean(psis)))
    beyond, _ = _probe([p - 2.5 * SEAT_TOL_MM * n] * len(psis), psis)  # boundary 0.5 mm outside the face's corner
    assert probe_face_contact(CONFIG, about_p) is not None and probe_face_contact(CONFIG, beyond) is not None
    assert not probes_on_face(CONFIG, "left", [about_p, beyond], [_seated(face)])


def test_the_flat_presses_do_not_wait_for_a_finger_whose_probes_met_its_seated_face():
    face, p = _face_and_corner()
    psis = _probe_psis(math.degrees(FACE_PSI) - 10.0)
    about_p, _ = _probe([p] * len(psis), psis)
    out = Exploration(probes=[about_p])
    out.touches = [SimpleNamespace(finger="right", touch=SimpleNamespace(samples=[])) for _ in range(4)]
    probes = SimpleNamespace(faces={"left": [float(np.mean(psis))], "right": [1.6]})
    retired = {"left": 0, "right": OFF_CURVE_RETIRE}
    assert unrolled_before_flat(CONFIG, out, probes, retired, lambda f: -1.8) == "left"  # as before: it rolls
    assert unrolled_before_flat(CONFIG, out, probes, retired, lambda f: -1.8, [_seated(face)]) is None
