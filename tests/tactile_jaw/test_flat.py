"""Flat touches as the recognizer's input: the stated flatness against exact arcs, one
face's touches recognized as a line with all seven classes candidates, faces never mixed,
rolling touches first."""

from __future__ import annotations

import math
from dataclasses import replace
from types import SimpleNamespace

import numpy as np
import pytest

from hand_driver.flat_press import SEAT_TOL_MM, FlatResult
from hand_driver.motion import TouchResult
from recognizer.touches import ContactTouch
from tactile_common.yamlfile import read_yaml
from tactile_jaw.decide import decide
from tactile_jaw.flat import (
    FACE_MISS_MM,
    FLAT_NOISE,
    Face,
    curved_faces,
    face_groups,
    flat_curvature_sd,
    recognized_touches,
    same_face,
)
from tactile_jaw.pipeline import FeltTouch, make_recognizer
from tactile_jaw.settings import ExploreSettings

from hand_driver.config import load_config

SCENE = read_yaml("config/scenes/line.yaml", "scene")  # all seven classes; the line y = 10, solid below
CONFIG_P = load_config("config/jaw-p.yaml")


def _flat(face: Face, finger: str = "left") -> FeltTouch:
    sk, sks = flat_curvature_sd(face.length)
    contact = ContactTouch(float(face.middle[0]), float(face.middle[1]), face.phi, 0.0, 0.0, np.diag([sk**2, sks**2]))
    return FeltTouch(FlatResult(finger, 0, face.psi), None, None, None, None, contact, face=face)


def _face(y: float, angle: float, x0: float = 90.0, x1: float = 130.0, below: bool = True) -> Face:
    """A face along the line through (x0, y) at ``angle`` to +x, the solid below it (the
    pad's normal pointing into it)."""
    t = np.array([math.cos(angle), math.sin(angle)])
    p, q = np.array([x0, y]), np.array([x0, y]) + (x1 - x0) * t
    n = np.array([t[1], -t[0]]) if below else np.array([-t[1], t[0]])
    return Face(math.atan2(n[1], n[0]), float(n @ p), p, q)


@pytest.mark.parametrize("length", [15.0, 40.0, 52.0])
def test_stated_flatness_covers_every_arc_that_seats(length):
    """An arc through both supports that bulges SEAT_TOL_MM from its chord (the most a seat
    allows) has κ = 8 g / (ℓ² + 4 g²) exactly: within the stated ±√3 σ_κ."""
    g = SEAT_TOL_MM
    radius = (length**2 / 4 + g**2) / (2 * g)  # chord ℓ, sagitta g
    sk, sks = flat_curvature_sd(length)
    assert 1.0 / radius <= math.sqrt(3.0) * sk <= 1.01 / radius
    assert sks == pytest.approx(2 * math.sqrt(3.0) * sk / length)


def test_one_face_of_flat_touches_is_a_line_with_its_pose():
    rng = np.random.default_rng(3)
    settings = ExploreSettings.from_profile("balanced")
    touches = [_flat(_face(10.0 + rng.normal(0, 0.07), rng.normal(0, 2.5e-3))) for _ in range(4)]
    recognize = make_recognizer(SCENE, settings)
    recognition, why = decide(recognize, touches, settings)
    assert recognition.cls == "line" and why is None
    pose = recognition.pose
    # canonical pose: the solid at canonical y < 0 is the block below the face: theta ≈ 0
    assert abs(math.remainder(pose.theta, 2 * math.pi)) < 0.01
    assert pose.y + 110.0 * math.tan(pose.theta) == pytest.approx(10.0, abs=0.2)  # at the face's middle
    assert FLAT_NOISE["phi"] > 2.5e-3


def test_faces_are_never_mixed_and_rolling_touches_come_first():
    top = [_flat(_face(10.0, 0.0)), _flat(_face(10.05, 1e-3))]
    bottom = [_flat(_face(-10.0, math.pi, x0=130.0, x1=90.0), "right") for _ in range(3)]
    assert same_face(top[0].face, top[1].face) and not same_face(top[0].face, bottom[0].face)
    groups = face_groups(top + bottom)
    assert [len(g) for g in groups] == [2, 3]
    assert recognized_touches(top + bottom) == bottom  # the face felt most often
    assert recognized_touches(bottom[:2] + top) == bottom[:2]  # a tie: the first felt
    rolling = FeltTouch(TouchResult("left", 1, 0.0), None, None, None, None, None)
    assert recognized_touches(top + [rolling]) == [rolling]


def test_a_face_whose_presses_stop_short_on_average_is_a_gentle_curve():
    """Each press passed the seat test (|mean| ≤ SEAT_TOL_MM), but over the face's presses
    they stopped FACE_MISS_MM or more short of their supports on average (an arc's bulge
    stays, a flat face's rounding averages out): not recognized; the other face is."""
    def flat(y, miss, finger="left", **kw):
        return _flat(replace(_face(y, 0.0, **kw), miss=miss), finger)

    arc = [flat(10.0, m) for m in (0.19, 0.12, 0.17, 0.16)]  # mean 0.16
    face = [flat(-10.0, m, "right", x0=130.0, x1=90.0, below=False) for m in (0.14, -0.05, 0.13)]
    assert curved_faces(arc + face) == [(4, pytest.approx(0.16))]
    assert recognized_touches(arc + face) == face
    assert recognized_touches(arc) == []
    assert recognized_touches(arc + face, fewest=3) == face and recognized_touches(arc + face[:2], fewest=3) == []
    assert FACE_MISS_MM < SEAT_TOL_MM


def _press_scan(contact, psis, outcome: str = "no_seat") -> FeltTouch:
    """A flat press of the P-series jaw's left pad whose scan turned through ``psis`` (in that
    order) on the tangent lines through ``contact(ψ)``, each joint read to its tick."""
    from tactile_jaw.pipeline import feel
    from tests.tactile_jaw.test_envelope_order import FINE, roll, touch

    q = roll(contact, psis, FINE, np.random.default_rng(2))
    press = touch(q)
    flat = FlatResult("left", 8, float(psis[0]), press.samples, outcome=outcome, roles=["scan"] * len(psis))
    return feel(CONFIG_P, flat, 9)


def test_a_press_that_rolled_on_a_curved_part_makes_its_faces_closing_segments():
    """A flat press whose pad turned 54° (zigzag, as hand_driver.flat_press scans) on the
    hyperbola example's branch without seating rolled on a curved part: then no face's presses
    are a line (the i20 seed-29 hyperbola 27 was answered line from its chord; now refused,
    naming the radius felt). Turned about a block's corner instead, it felt no curve, and the
    line stays."""
    from recognizer.scene import load_scene
    from tactile_jaw.pipeline import curve_refusal, curved_part
    from tests.tactile_jaw.test_envelope_order import support_point

    obj = load_scene("config/scenes/hyperbola.yaml").object
    zigzag = math.radians(-90.0) + np.radians([0, 3, -3, 6, -6, 9, -9, 12, -12, 15, -15, 18, -18, 21, -21, 24, -24, 27])
    branch = _press_scan(lambda p: support_point(obj, p), zigzag)
    corner = _press_scan(lambda p: np.array([100.0, 2.0]), zigzag)
    chord = [_flat(_face(-10.0, math.pi, x0=130.0, x1=90.0), "right") for _ in range(3)]
    found = curved_part(CONFIG_P, [corner, branch, *chord])
    assert found is not None and found.finger == "left"
    assert 14.0 <= found.fit.rho <= 40.0  # the branch's radius of curvature there (14 mm at the vertex)
    assert "closing segments, not a line" in curve_refusal(found).reason
    assert recognized_touches(chord, curved=True) == [] and recognized_touches(chord) == chord
    assert curved_part(CONFIG_P, [corner, *chord]) is None


def test_the_same_face_tolerance_and_stated_angle_noise_follow_the_face_length():
    """tactile_jaw.flat.face_phi_sd: a face's angle from supports ℓ apart, each fixed to
    SUPPORT_SD_MM, scatters √2·SUPPORT_SD_MM/ℓ (9.0 mrad at 11 mm), FLAT_NOISE's φ for long
    faces; two 11 mm faces 1.06° apart (held-out X line 7 of seed 241's presses) are one face,
    two 40 mm faces so far apart are not (0.57° as before); a request of flat touches on 11 mm
    faces states that σ_φ (tactile_jaw.pipeline.stated_noise)."""
    from tactile_jaw.flat import SUPPORT_SD_MM, face_phi_sd
    from tactile_jaw.pipeline import stated_noise
    assert face_phi_sd(11.0) == pytest.approx(math.sqrt(2.0) * SUPPORT_SD_MM / 11.0) and face_phi_sd(11.0) > 8.5e-3
    assert face_phi_sd(40.0) == FLAT_NOISE["phi"]

    def face(psi_deg: float, length: float):
        psi = math.radians(psi_deg)
        t = np.array([-math.sin(psi), math.cos(psi)])
        mid = np.array([110.0, 10.0])
        return Face(psi, float(np.array([math.cos(psi), math.sin(psi)]) @ mid), mid - 0.5 * length * t,
                    mid + 0.5 * length * t)

    assert same_face(face(-90.0, 11.0), face(-88.94, 11.0)) and not same_face(face(-90.0, 11.0), face(-87.5, 11.0))
    assert not same_face(face(-90.0, 40.0), face(-88.94, 40.0)) and same_face(face(-90.0, 40.0), face(-89.5, 40.0))
    short = [SimpleNamespace(touch=FlatResult("left", k, -math.pi / 2, [], outcome="ok", roles=[]),
                             face=face(-90.0, 11.0)) for k in range(3)]
    assert stated_noise(short).phi == pytest.approx(face_phi_sd(11.0))
