"""A move the advice names must keep every point the exploration felt on the object clear of
the opened pads (tactile_jaw.choose.JawReach.felt_near, tactile_jaw.flat_phase.felt_points):
semicubical parabola 137 of bench_explore --finite 20 --anywhere --follow --seed 571 (P-series),
whose rolls turned about corners at (110.0, 42.2) and (92.4, 3.1) mm; the move named for the
face beside the right pad's corner (15° about (88, 6) mm, then (6, 3) mm) carried the corner
the left pad felt 4.5 mm behind the opened left pad, and the moved scene overlapped the opened jaw."""

import math
from pathlib import Path
from types import SimpleNamespace

import numpy as np

from hand_driver.config import load_config
from hand_driver.sim.physics import ContactWorld
from recognizer.scene import load_scene
from tactile_jaw.choose import MOVE_CLEAR_MM, JawReach
from tactile_jaw.flat_phase import _face_advice, felt_points
from tactile_jaw.plan import open_pose
from tactile_jaw.settings import ExploreSettings
from tools.bench_explore import moved_object

ROOT = Path(__file__).resolve().parents[2]
CONFIG = load_config(ROOT / "config" / "jaw-p.yaml")
SETTINGS = ExploreSettings.from_profile("balanced")
#: the exact object (its scene rand137.yaml)
OBJECT = {"class": "semicubical_parabola", "params": {"a": 0.24959042121710726, "b": -1.2},
          "pose": {"theta": 0.7351295784198584, "x": 90.53672892574549, "y": 3.052078711197818},
          "extent": [1.1899495122917934, 6.382456475019619]}
#: the corners its rolls turned about (the left pad's 2.8 mm before the opened left pad)
CORNERS = ((110.015, 42.247), (92.44, 3.05))
#: the face beside the right pad's corner short_face_stop named: P (the corner), Q, the pad's normal
FACE = (np.array([92.518, 3.033]), np.array([83.651, 8.467]), np.array([0.5225, 0.8526]))


def _felt(corners) -> SimpleNamespace:
    """An exploration whose rolls turned about ``corners`` (nothing else felt)."""
    touches = [SimpleNamespace(corner=c, pivot=(np.asarray(c), 0.01 * np.eye(2)), segment_corners=(), face=None,
                               samples=None, contacts=None) for c in corners]
    return SimpleNamespace(probes=[], touches=touches)


def _overlaps(move: dict) -> bool:
    """Does the exact object, moved as ``move`` says, overlap the opened jaw's pads (tactile demo's check)?"""
    obj = load_scene({"name": "m", "classes": ["semicubical_parabola"], "object": moved_object(OBJECT, move)}).object
    return ContactWorld(CONFIG, obj).penetrates(open_pose(CONFIG))


def test_the_face_move_keeps_the_felt_corners_clear_of_the_opened_pads():
    """Knowing only the face, the move found carries the left pad's corner across the opened left
    pad (the held-out run's advice); knowing both corners, the move keeps it MOVE_CLEAR_MM before
    that pad and the moved object clear of the opened jaw (fails before session 33: no felt points)."""
    assert not _overlaps({"dx": 0.0, "dy": 0.0, "turn_deg": 0.0, "about": [0.0, 0.0]})
    p, q, toward = FACE
    _, blind, _, _ = _face_advice(CONFIG, SETTINGS, _felt(CORNERS[1:]), "right", p, q, toward, corner=True)
    assert blind is not None and _overlaps(blind)
    _, move, _, _ = _face_advice(CONFIG, SETTINGS, _felt(CORNERS), "right", p, q, toward, corner=True)
    assert move is not None and not _overlaps(move)
    a, turn = np.asarray(move["about"]), math.radians(move["turn_deg"])
    rot = np.array([[math.cos(turn), -math.sin(turn)], [math.sin(turn), math.cos(turn)]])
    corner = rot @ (np.asarray(CORNERS[0]) - a) + a + np.array([move["dx"], move["dy"]])
    assert corner[1] <= 45.0 - MOVE_CLEAR_MM + 1e-6  # the opened left pad's face lies at y = 45 mm


def test_felt_near_holds_each_point_clear_or_no_nearer_than_now():
    """The opened left pad's face at y = 45 mm over x 91.9–143.9 mm: a felt point 2.8 mm before
    it may stay (no nearer than now) but not come 1 mm nearer or pass behind the pad; a point
    5.9 mm short of the pad's end is free; one from inside stops MOVE_CLEAR_MM short."""
    reach = JawReach(CONFIG, SETTINGS)
    near = reach.felt_near((110.0, 0.0), 0.0, np.array([[0.0, 0.0], [0.0, 1.0], [0.0, 6.0], [-24.0, 6.0]]),
                           np.array([[110.0, 42.2]]))
    assert list(near) == [False, True, True, False]  # x 86 mm: 5.9 mm short of the pad's end
    inside = reach.felt_near((110.0, 0.0), 0.0, np.array([[0.0, 3.5], [0.0, 1.5]]), np.array([[120.0, 39.0]]))
    assert list(inside) == [True, False]  # 2.5 and 4.5 mm before the face
    assert felt_points(_felt(CORNERS)).shape == (2, 2)
