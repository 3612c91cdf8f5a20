"""A move named for a face keeps the opened pads clear of where that face goes on unfelt
(tactile_jaw.choose.Goal.goes_on, JawReach.opened_clear, JawReach.go_on_length): P-series line 7
of bench_explore --finite 20 --anywhere --seed 347, whose face the left pad met over 13.6 mm,
was moved as session 27 advised (30° and (11, −11) mm) across the opened right pad."""

import json
import math
from pathlib import Path

import numpy as np
import pytest

from hand_driver.config import load_config
from hand_driver.flat_press import FlatResult
from hand_driver.motion import TouchResult
from hand_driver.sim.boundary import Boundary
from hand_driver.sim.physics import ContactWorld
from recognizer.scene import load_scene
from tactile_jaw.choose import MOVE_CLEAR_MM, JawReach
from tactile_jaw.flat_phase import short_face_stop
from tactile_jaw.pipeline import feel, logged_samples
from tactile_jaw.plan import open_pose, opened_strips
from tactile_jaw.rounds import Exploration
from tactile_jaw.settings import ExploreSettings
from tools.bench_explore import moved_object

ROOT = Path(__file__).resolve().parents[2]
CONFIG = load_config(ROOT / "config" / "jaw-p.yaml")
SETTINGS = ExploreSettings.from_profile("balanced")
RAW = json.loads((Path(__file__).parent / "data" / "p_line_347_7_touches.json").read_text())


def _felt(row):
    samples = logged_samples(CONFIG, row["finger"], row["ticks"], row["psi"]) if row["ticks"] else []
    if row["kind"] == "flat":
        touch = FlatResult(row["finger"], row["touch"], row["psi_center"], samples, outcome=row["outcome"],
                           roles=row["roles"])
    else:
        touch = TouchResult(row["finger"], row["touch"], row["psi_center"], samples, outcome=row["outcome"])
    return feel(CONFIG, touch, SETTINGS.samples_per_touch)


def _pads_gap(obj) -> float:
    """The least distance (mm) from the object's boundary to the opened pads' faces (negative: across one)."""
    (cx, cy), r = CONFIG.workspace.center_mm, CONFIG.workspace.radius_mm
    pts = Boundary(load_scene({"name": "b", "classes": ["line"], "object": obj}).object).points((cx, cy), 4 * r)
    gap = math.inf
    for psi, u_lo, u_hi, d, _ in opened_strips(CONFIG, 0.0):
        n, t = np.array([math.cos(psi), math.sin(psi)]), np.array([-math.sin(psi), math.cos(psi)])
        u = np.clip(pts @ t, u_lo, u_hi)
        gap = min(gap, float(np.min(np.hypot(pts @ t - u, pts @ n - d) * np.sign(pts @ n - d + 1e-12))))
    return gap


def test_the_move_named_for_the_face_keeps_the_block_off_the_opened_jaw():
    """The run's touches give the same face (pad normal −166°, 13.6 mm); the move named now
    (fails before: 30° and (11, −11) mm, the block's unfelt far side across the opened right
    pad) leaves the moved block clear of the opened jaw (the emulator's check of a scene:
    ContactWorld.penetrates at the opened pose) by at least MOVE_CLEAR_MM."""
    out = Exploration()
    out.probes = [_felt(r) for r in RAW["probes"]]
    out.touches = [_felt(r) for r in RAW["touches"]]
    stop = short_face_stop(CONFIG, SETTINGS, out)
    assert stop is not None and "pad normal -166 deg, over 13.6 mm" in stop and stop.move is not None
    old = {"dx": 11.414, "dy": -11.414, "turn_deg": 30.0, "about": stop.move["about"]}
    q_open = open_pose(CONFIG)
    for move, across in ((old, True), (stop.move, False)):
        obj = moved_object(RAW["truth"], move)
        world = ContactWorld(CONFIG, load_scene({"name": "b", "classes": ["line"], "object": obj}).object)
        assert world.penetrates(q_open) == across
        assert (_pads_gap(obj) < 0.0) == across
    assert _pads_gap(moved_object(RAW["truth"], stop.move)) >= MOVE_CLEAR_MM


def test_a_face_goes_on_to_where_a_pad_swept_free():
    """From the workspace's centre (110, 0) mm toward the left finger, the opened left pad's
    place (its face at y = 45 mm, and MOVE_CLEAR_MM before it) is the first free point: 42 mm;
    toward the palm nothing swept: the workspace's diameter, 90 mm. An opened pad carried
    within MOVE_CLEAR_MM of such a ray is refused, one beside it kept; with no ray, no probe
    rested on a pad end: every move kept."""
    reach = JawReach(CONFIG, SETTINGS)
    assert reach.go_on_length((110.0, 0.0, 0.0, 1.0)) == pytest.approx(45.0 - MOVE_CLEAR_MM)
    assert reach.go_on_length((110.0, 0.0, -1.0, 0.0)) == pytest.approx(90.0)
    # the opened right pad's face at y = −45 mm, x 91.9–143.9 mm, its place 3 mm before it: the
    # object moved 8 mm toward it carries that place back to y −37…−34 mm, where a ray toward +x
    # from (60, −35) mm runs (refused) and one from (60, −25) mm runs 9 mm beside (kept); unmoved,
    # the place is where the opened jaw stood (kept); a ray from (60, −47) mm ends where it meets
    # the free space behind that pad, the finger's side
    toward, still = np.array([[0.0, -8.0]]), np.zeros((1, 2))
    assert not reach.opened_clear((0.0, 0.0), 0.0, toward, ((60.0, -35.0, 1.0, 0.0),))[0]
    assert reach.opened_clear((0.0, 0.0), 0.0, toward, ((60.0, -25.0, 1.0, 0.0),))[0]
    assert reach.opened_clear((0.0, 0.0), 0.0, still, ((60.0, -35.0, 1.0, 0.0),))[0]
    assert reach.opened_clear((0.0, 0.0), 0.0, toward)[0]
    assert reach.go_on_length((60.0, -47.0, 1.0, 0.0)) == pytest.approx(32.0)
