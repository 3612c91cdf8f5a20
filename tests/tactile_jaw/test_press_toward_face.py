"""A later flat press on a face already found (tactile_jaw.flat_phase._flat_plan) turns its pad
toward that face: where it starts, 2.5 steps off the face's normal, the pad rests on the face's
corner under its middle, and the part it lowers is the one over the face, not the one toward the
workspace centre. P line 7 of ``bench_explore --finite 20 --anywhere --seed 241`` (development
since session 22): the left pad seated on the block's short face (13.2 mm, pad normal −63.9°),
and each of its four later presses first turned 60° the other way, 10.7–11.0 s a press where a
press on a known face takes 2.4–2.8 s."""

from __future__ import annotations

import math

import numpy as np
import pytest

from hand_driver import kinematics as kin
from hand_driver.bus import JointBus
from hand_driver.config import load_config
from hand_driver.cycle import Jaw, LockstepClock, run_together
from hand_driver.sim.server import EmulatedBus
from recognizer.scene import load_scene
from tactile_jaw.flat import Face
from tactile_jaw.flat_phase import _flat_plan
from tactile_jaw.plan import ObjectModel, open_pose

CONFIG = load_config("config/jaw-p.yaml")
HALF = 16.49224526166952
SCENE = {"name": "rand7", "classes": ["line"],
         "object": {"class": "line", "params": {}, "extent": [-HALF, HALF],
                    "closure": [[HALF, -0.8 * HALF], [-HALF, -0.8 * HALF]],
                    "pose": {"theta": -1.115558683016686, "x": 95.8050403436292, "y": -17.688485049833172}}}


def _short_face() -> Face:
    """The block's closing side the left pad seated on, from the exact scene: the corners
    (−h, −0.8h) and (−h, 0) in the object's frame, the pad's normal into the object."""
    pose = load_scene(SCENE).object.pose
    p, q = (np.array(pose.apply(-HALF, y), dtype=float) for y in (-0.8 * HALF, 0.0))
    t = (q - p) / np.linalg.norm(q - p)
    psi = math.atan2(t[1], t[0]) - math.pi / 2
    return Face(psi, float(kin.unit(psi) @ p), p, q)


def test_a_later_press_turns_toward_the_face_it_found():
    face = _short_face()
    assert math.degrees(face.psi) == pytest.approx(-63.9, abs=0.1)  # the premise: the face of the log
    finger = CONFIG.finger("left")
    backed = kin.ik_line(finger, face.psi, face.d - CONFIG.motion.backoff_mm)  # where its last seated press left it
    q = open_pose(CONFIG)
    q[:2] = backed  # the right finger open, the left one backed off its face
    ticks = np.rint(kin.angles_to_ticks(CONFIG.joints, q)).astype(int).tolist()
    with EmulatedBus(CONFIG, load_scene(SCENE), time_scale=0.0, initial_ticks=ticks) as sim:
        with JointBus(sim.port, CONFIG.bus.baudrate, CONFIG, retries=CONFIG.bus.retries, timeout_s=1.0) as bus:
            bus.set_goal_current(CONFIG.motion.goal_current_ma)
            bus.set_profile_raw(CONFIG.motion.profile_velocity, CONFIG.motion.profile_acceleration)
            jaw = Jaw(bus, CONFIG, None, clock=LockstepClock(sim))
            ws = CONFIG.workspace
            t0 = jaw.robot_time()
            plan = _flat_plan(jaw, "left", ObjectModel(ws.center_mm, ws.radius_mm), face, 0, 0, lambda rec: None,
                              {}, side=1)
            result = run_together(jaw, {"left": plan})["left"]
            elapsed = jaw.robot_time() - t0
    assert result.outcome == "ok"
    seats = [s for s, role in zip(result.samples, result.roles) if role == "seat"]
    assert len(seats) == 3
    for s in seats:  # pressed flat on that face: stopped where its corners stop a pad of that normal
        n = kin.unit(float(s.psi))
        assert math.degrees(abs(math.remainder(float(s.psi) - face.psi, 2 * math.pi))) < 2.0  # a 13 mm face: its seat from a pad end
        assert float(s.d) == pytest.approx(min(float(n @ face.p), float(n @ face.q)), abs=0.3)
    # never turned away from it: no stop before where it started (2.5 steps of 3 deg before the face's
    # normal), none more than 4 steps past it
    turns = [math.degrees(math.remainder(float(s.psi) - face.psi, 2 * math.pi)) for s in result.samples]
    assert -7.6 < min(turns) and max(turns) < 12.0
    assert elapsed < 4.0  # 10.7-11.0 s a press before


class _Samples:
    """A seated press's samples touch, as the log records it (not read here)."""

    @staticmethod
    def to_json() -> dict:
        return {}


def _seated(k: int, psi_deg: float):
    from hand_driver.flat_press import FlatResult
    from tactile_jaw.pipeline import FeltTouch

    psi = math.radians(psi_deg)
    t = np.array([-math.sin(psi), math.cos(psi)])
    mid = np.array([82.5, -5.6])
    face = Face(psi, float(kin.unit(psi) @ mid), mid - 6.6 * t, mid + 6.6 * t)
    return FeltTouch(FlatResult("left", k, psi - math.radians(7.5), [object()] * 9, outcome="ok", roles=[]), None,
                     None, None, None, _Samples(), face=face)


def test_every_later_press_starts_from_the_first_seated_face():
    """P line 7 of seed 241 with the presses turning toward their face: its short face seats
    through a pad end's support up to 1.4° off its normal, and each press starting from the last
    one's face walked the seats −63.1 → −61.5°, no three on one face (refused)."""
    from tactile_jaw.flat_phase import _booked

    presses = [_seated(11, -63.1), _seated(13, -62.4), _seated(15, -61.8)]
    state = _booked(CONFIG, presses)
    assert state.faces["left"] is presses[0].face  # the reference of every later press
    assert state.faces["right"] is None and len(state.flat) == 3 and state.sides["left"] == 1
