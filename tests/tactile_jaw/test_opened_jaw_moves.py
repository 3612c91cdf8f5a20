"""A move the advice names must not carry what the probes never swept in front of an opened
pad (tactile_jaw.plan.free_strips, tactile_jaw.choose.JawReach.opened_clear): calibrated
random block 1 of bench_explore --finite 10 --anywhere --seed 239 (P-series), whose far
corner, never felt, lay beyond the right pad's proximal end; the move named for the face its
left pad met (turn 10° about (79, −10) mm, then (6, −4) mm) put that corner across the opened
right pad."""

import math
from pathlib import Path

import numpy as np

from hand_driver import kinematics as kin
from hand_driver.config import load_config
from hand_driver.cycle import LIMIT_MARGIN_RAD
from hand_driver.motion import Sample, TouchResult
from tactile_jaw.choose import MOVE_CLEAR_MM, Goal, JawReach, move_advice
from tactile_jaw.pipeline import FeltTouch
from tactile_jaw.plan import free_strips, opened_strips
from tactile_jaw.settings import ExploreSettings

ROOT = Path(__file__).resolve().parents[2]
CONFIG = load_config(ROOT / "config" / "jaw-p.yaml")
SETTINGS = ExploreSettings.from_profile("balanced")
#: the block's corners in the hand frame (its scene: a 34.3 × 13.7 mm block at (87.0, −20.9) mm,
#: turned −62.1°); the last, (82.9, −42.4) mm, is the far corner no probe felt
CORNERS = np.array([[79.0, -5.7], [95.0, -36.0], [82.9, -42.4], [66.9, -12.1]])
ABOUT = (78.95, -10.10)
ADVISED = (6.0, -4.0, math.radians(10.0))  # the move named before (rand1.log's stopped_early)


def _boundary(step: float = 0.1) -> np.ndarray:
    """Points every ``step`` mm along the block's boundary."""
    out = []
    for a, b in zip(CORNERS, np.roll(CORNERS, -1, axis=0)):
        k = int(np.linalg.norm(b - a) / step) + 1
        out.append(a + np.linspace(0.0, 1.0, k)[:, None] * (b - a))
    return np.vstack(out)


def _probe(name: str, psi: float) -> FeltTouch:
    """A probe's first contact on the exact block: the pad from the workspace edge along its
    normal ψ until the first boundary point across the pad's stretch (in 0.05 mm steps)."""
    finger = CONFIG.finger(name)
    n, pts = np.array([math.cos(psi), math.sin(psi)]), _boundary()
    d = float(n @ np.asarray(CONFIG.workspace.center_mm)) - CONFIG.workspace.radius_mm
    while True:
        line = kin.finger_pad_line(finger, kin.ik_line(finger, psi, d, margin_rad=LIMIT_MARGIN_RAD))
        u = line.pad_coordinate(pts)
        on = (u >= 0.0) & (u <= finger.pad.length_mm)
        if np.any(pts[on] @ n <= d):
            break
        d += 0.05
    sample = Sample(reading=0, psi=psi, ticks=np.zeros(2), line=line, current_ma=None, robot_time=0.0)
    return FeltTouch(TouchResult(name, 0, psi + math.radians(3.0), [sample]), None, None, None, None, None)


PROBES = [_probe("left", math.radians(-93.0)), _probe("right", math.radians(87.0))]


def _moved(points: np.ndarray, dx: float, dy: float, turn: float) -> np.ndarray:
    c, s = math.cos(turn), math.sin(turn)
    a = np.asarray(ABOUT)
    return (points - a) @ np.array([[c, s], [-s, c]]) + a + np.array([dx, dy])


def _in_strips(points: np.ndarray, strips: np.ndarray) -> np.ndarray:
    inside = np.zeros(len(points), bool)
    for psi, u_lo, u_hi, d_lo, d_hi in strips:
        u = points @ np.array([-math.sin(psi), math.cos(psi)])
        d = points @ np.array([math.cos(psi), math.sin(psi)])
        inside |= (u >= u_lo) & (u <= u_hi) & (d >= d_lo) & (d <= d_hi)
    return inside


def test_the_probes_swept_free_up_to_their_contacts():
    """Every strip a probe swept holds no point of the block; the right pad's first one met
    the block 8 mm in (the gap the opened right pad had)."""
    strips = free_strips(CONFIG, PROBES)
    short = strips - np.array([0.0, 0.0, 0.0, 0.0, 0.05])  # the contact itself, within _probe's step
    assert len(strips) > 20 and not np.any(_in_strips(_boundary(), short))
    right = strips[np.isclose(strips[:, 0], math.radians(87.0))]
    gap = right[:, 4].max() - (right[:, 3].min() + CONFIG.finger("right").pad.offset_mm)
    assert 7.0 < gap < 9.0


def test_the_advised_move_put_the_unfelt_corner_on_the_opened_pad_and_is_refused():
    """Moved as advised before, the far corner lies in front of the opened right pad (within
    MOVE_CLEAR_MM of its face): the check refuses that move, and keeps the object where it is."""
    opened = opened_strips(CONFIG, MOVE_CLEAR_MM, CONFIG.finger("right").pad.offset_mm)  # on or before a pad
    assert _in_strips(_moved(CORNERS[2:3], *ADVISED), opened).all()
    assert not _in_strips(CORNERS, opened).any()
    reach = JawReach(CONFIG, SETTINGS, PROBES)
    dx, dy, turn = ADVISED
    assert list(reach.opened_clear(ABOUT, turn, np.array([[dx, dy], [0.0, 0.0]]))) == [False, False]
    assert reach.opened_clear(ABOUT, 0.0, np.array([[0.0, 0.0]]))[0]
    # straight away from the right pad, within the left pad's gap: nothing unswept comes before a pad
    assert reach.opened_clear(ABOUT, 0.0, np.array([[0.0, 2.0]]))[0]
    assert JawReach(CONFIG, SETTINGS).opened_clear(ABOUT, turn, np.array([[dx, dy]]))[0]  # no probes, no bound


def test_every_named_move_keeps_the_block_off_the_opened_pads():
    """The move named for the face the left pad met (5.2 mm of it, pad normal −83°, about
    (79, −10) mm, as short_face_stop's goal): without the probes it is the move that put the
    corner on the right pad; with them none is, and the advice says why."""
    psi = math.radians(-83.0)
    t = np.array([math.cos(psi - math.pi / 2), math.sin(psi - math.pi / 2)])
    p, mid, q = (np.asarray(ABOUT) + k * 2.6 * t for k in (-1, 0, 1))
    goal = Goal(tuple((float(x), float(y), psi - math.pi / 2) for x, y in (p, mid, q)), np.stack([p, q], axis=1),
                ABOUT, "across that face")
    left = [CONFIG.finger("left")]
    _, before = move_advice(JawReach(CONFIG, SETTINGS), goal, left)
    assert before is not None
    moved = _moved(CORNERS, before["dx"], before["dy"], math.radians(before["turn_deg"]))
    assert _in_strips(moved, opened_strips(CONFIG, MOVE_CLEAR_MM, 8.0)).any()  # across the opened right pad
    advice, move = move_advice(JawReach(CONFIG, SETTINGS, PROBES), goal, left)
    if move is None:
        assert advice.startswith("every move that brings a pad across that face would carry what the probes did not "
                                 "sweep free in front of an opened pad")
    else:
        moved = _moved(_boundary(), move["dx"], move["dy"], math.radians(move["turn_deg"]))
        assert not _in_strips(moved, opened_strips(CONFIG, MOVE_CLEAR_MM, 8.0)).any()
