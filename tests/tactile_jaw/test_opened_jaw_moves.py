"""A move the advice names must not carry an opened pad past a pad end a probe rested on,
where the object goes on unfelt (tactile_jaw.plan.rested_ends, JawReach.opened_clear):
calibrated random block 1 of bench_explore --finite 10 --anywhere --seed 239 (P-series),
whose far corner, never felt, lay 14 mm beyond the right pad's proximal end that rested on
the near corner; the move named for the face its left pad met (turn 10° about (79, −10) mm,
then (6, −4) mm) put that corner across the opened right pad."""

import math
from pathlib import Path

import numpy as np

from hand_driver import kinematics as kin
from hand_driver.config import load_config
from hand_driver.cycle import LIMIT_MARGIN_RAD
from hand_driver.motion import Sample, TouchResult
from tactile_jaw.choose import MOVE_CLEAR_MM, NOT_CLEAR, Goal, JawReach, move_advice, move_for
from tactile_jaw.pipeline import FeltTouch
from tactile_jaw.plan import opened_strips, rested_ends
from tactile_jaw.settings import ExploreSettings

ROOT = Path(__file__).resolve().parents[2]
CONFIG = load_config(ROOT / "config" / "jaw-p.yaml")
SETTINGS = ExploreSettings.from_profile("balanced")
#: the block's corners in the hand frame (its scene: a 34.3 × 13.7 mm block at (87.0, −20.9) mm,
#: turned −62.1°); the third, (82.9, −42.4) mm, is the far corner no probe felt
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


def _line_at_contact(name: str, psi: float):
    """The pad line at ``psi`` moved from the workspace edge along its normal until it first
    meets the block across the pad's stretch (0.02 mm steps)."""
    finger = CONFIG.finger(name)
    n, pts = np.array([math.cos(psi), math.sin(psi)]), _boundary()
    d = float(n @ np.asarray(CONFIG.workspace.center_mm)) - CONFIG.workspace.radius_mm
    while True:
        line = kin.finger_pad_line(finger, kin.ik_line(finger, psi, d, margin_rad=LIMIT_MARGIN_RAD))
        u = line.pad_coordinate(pts)
        on = (u >= 0.0) & (u <= finger.pad.length_mm)
        if np.any(pts[on] @ n <= d):
            return line
        d += 0.02


def _probe(name: str, psi_deg: float) -> FeltTouch:
    """A probe's last two samples on the exact block, 2° apart ending at ``psi_deg``."""
    samples = [Sample(reading=i, psi=math.radians(a), ticks=np.zeros(2), line=_line_at_contact(name, math.radians(a)),
                      current_ma=None, robot_time=0.0) for i, a in enumerate((psi_deg - 2.0, psi_deg))]
    return FeltTouch(TouchResult(name, 0, math.radians(psi_deg), samples), None, None, None, None, None)


#: the left pad at −92…−90° rests its proximal end on the block's long side beside the corner
#: (79, −5.7) mm, the right pad at 98–100° on the edge beside the near corner (95, −36) mm
PROBES = [_probe("left", -90.0), _probe("right", 100.0), _probe("right", 115.0)]


def test_the_probes_rested_their_pad_ends_on_the_block_corners():
    """Both probes met the block with their pad's proximal end (their last lines cross 0.0
    and 4.7 mm from it, within PROBE_PAD_MARGIN of the 52 mm pad): each end is on the block's
    boundary within the approach's step, and beyond it is away from the pad's distal end; a
    probe of one sample, or one whose lines cross mid-pad, says nothing."""
    ends = rested_ends(CONFIG, PROBES)
    assert ends.shape == (3, 4)
    for (ex, ey, bx, by), probe in zip(ends, PROBES):
        assert np.min(np.hypot(*(_boundary(0.01) - (ex, ey)).T)) < 0.05
        line = probe.touch.samples[-1].line
        away = np.asarray(line.proximal) - np.asarray(line.distal)
        assert np.dot((bx, by), away / np.linalg.norm(away)) > 1.0 - 1e-9  # past the proximal end
    assert rested_ends(CONFIG, [_probe("right", 90.0)]).shape == (0, 4)  # lines crossing 5.6 mm in
    one = FeltTouch(TouchResult("right", 0, 0.0, PROBES[1].touch.samples[:1]), None, None, None, None, None)
    assert rested_ends(CONFIG, [one]).shape == (0, 4)


def test_the_advised_move_is_refused_and_moves_clear_of_the_rested_ends_are_kept():
    """Moved as advised before, the far corner lies on the opened right pad: refused. Not
    moving, or moving 2 mm toward the left finger (away from the right pad), is kept, and so
    is every move without probes (nothing known)."""
    opened = opened_strips(CONFIG, MOVE_CLEAR_MM, CONFIG.finger("right").pad.offset_mm)
    c, s = math.cos(ADVISED[2]), math.sin(ADVISED[2])
    corner = (CORNERS[2] - ABOUT) @ np.array([[c, s], [-s, c]]) + ABOUT + ADVISED[:2]
    psi, u_lo, u_hi, d_lo, d_hi = opened[1]
    n, t = np.array([math.cos(psi), math.sin(psi)]), np.array([-math.sin(psi), math.cos(psi)])
    assert u_lo <= corner @ t <= u_hi and d_lo <= corner @ n <= d_hi  # the far corner on the opened right pad
    reach = JawReach(CONFIG, SETTINGS, PROBES)
    dx, dy, turn = ADVISED
    assert not reach.opened_clear(ABOUT, turn, np.array([[dx, dy]]))[0]
    assert list(reach.opened_clear(ABOUT, 0.0, np.array([[0.0, 0.0], [0.0, 2.0]]))) == [True, True]
    assert JawReach(CONFIG, SETTINGS).opened_clear(ABOUT, turn, np.array([[dx, dy]]))[0]


def test_the_move_named_with_the_probes_keeps_its_clearance_from_the_rested_ends():
    """The move named for the face the left pad met (5.2 mm of it, pad normal −83°, about
    (79, −10) mm, as short_face_stop's goal): without the probes, a move whose opened right
    pad comes within MOVE_CLEAR_MM of the rested ends' far side (the block across it); with
    them another move, clear of them. What no probe found (the far corner) is not known: the
    block may still reach the pad (here it does), only a found end's clearance is kept."""
    psi = math.radians(-83.0)
    t = np.array([math.cos(psi - math.pi / 2), math.sin(psi - math.pi / 2)])
    p, mid, q = (np.asarray(ABOUT) + k * 2.6 * t for k in (-1, 0, 1))
    goal = Goal(tuple((float(x), float(y), psi - math.pi / 2) for x, y in (p, mid, q)), np.stack([p, q], axis=1),
                ABOUT, "across that face")
    left = [CONFIG.finger("left")]
    reach = JawReach(CONFIG, SETTINGS, PROBES)

    def clear(move) -> bool:
        return bool(reach.opened_clear(move["about"], math.radians(move["turn_deg"]),
                                       np.array([[move["dx"], move["dy"]]]))[0])

    before = move_advice(JawReach(CONFIG, SETTINGS), goal, left).move
    assert before is not None and not clear(before)
    move = move_advice(reach, goal, left).move
    assert move is not None and move != before and clear(move)


def _face_goal(psi_deg: float) -> Goal:
    """The goal across the face the left pad met (as above), its pad normal at ``psi_deg``."""
    psi = math.radians(psi_deg)
    t = np.array([math.cos(psi - math.pi / 2), math.sin(psi - math.pi / 2)])
    p, mid, q = (np.asarray(ABOUT) + k * 2.6 * t for k in (-1, 0, 1))
    return Goal(tuple((float(x), float(y), psi - math.pi / 2) for x, y in (p, mid, q)), np.stack([p, q], axis=1),
                ABOUT, "across that face")


def _questions(monkeypatch) -> list:
    """A counter of the places put to any JawReach: one per ``finger`` call, one per place of a
    ``rolls`` call (the move search asks a batch of candidates at once)."""
    calls = [0]
    finger, rolls = JawReach.finger, JawReach.rolls

    def counted(self, *args, **kwargs):
        calls[0] += 1
        return finger(self, *args, **kwargs)

    def counted_rolls(self, px, *args, **kwargs):
        calls[0] += len(px)
        return rolls(self, px, *args, **kwargs)

    monkeypatch.setattr(JawReach, "finger", counted)
    monkeypatch.setattr(JawReach, "rolls", counted_rolls)
    return calls


def test_a_refusal_without_a_move_asks_each_candidate_once(monkeypatch):
    """No pad reaches the face turned away from the left finger (normal 97°): the advice says
    so, and asks the reach no more than one search over every candidate move does (the probe-free
    search): the candidates the search with the probes asked about reach nowhere, so only those
    it passed over for the opened pads are asked again (before: the whole search again without
    the probes, 5,030 questions against 2,754, 1.5 s → 0.85 s of CPU)."""
    calls = _questions(monkeypatch)
    goal, left = _face_goal(97.0), [CONFIG.finger("left")]
    assert move_for(JawReach(CONFIG, SETTINGS), goal, left) is None
    unbound = calls[0]
    calls[0] = 0
    advice = move_advice(JawReach(CONFIG, SETTINGS, PROBES), goal, left)
    assert advice.kind == "out_of_reach" and advice.move is None
    assert advice.words.startswith("no pad reaches across that face")
    assert 0 < calls[0] <= unbound


def test_moves_barred_only_by_the_opened_pads_are_named_so(monkeypatch):
    """Where the opened pads bar every move (each shift refused while probes rested on pad ends)
    yet one reaches without them, the refusal says so, from the one search's record."""
    bar = JawReach.opened_clear
    monkeypatch.setattr(JawReach, "opened_clear", lambda self, *args: bar(self, *args) & (len(self.probes) == 0))
    advice = move_advice(JawReach(CONFIG, SETTINGS, PROBES), _face_goal(-83.0), [CONFIG.finger("left")])
    assert advice.kind == "not_clear" and advice.move is None
    assert advice.words.startswith(f"{NOT_CLEAR}: every move that brings a pad across that face would carry "
                                            f"an opened pad")
    free = move_advice(JawReach(CONFIG, SETTINGS), _face_goal(-83.0), [CONFIG.finger("left")]).move
    assert free is not None
