"""What one finger felt can contradict a straight boundary when no touch of it was usable: a
roll whose contact moved along the object over a stretch (tactile_jaw.pipeline.moving_stretch)
and a flat press whose scan rolled on a curve until the contact ran off the pad's end
(tactile_jaw.pipeline.on_pad_face). Either makes the faces the other pad pressed closing
segments (tactile_jaw.pipeline.curved_part), not a line, and a roll's such stretch is where the
finger rolls next (tactile_jaw.pipeline.moving_hint). The logged readings of two runs that
answered `line` for a hyperbola; exact rolls about a block's corners feel neither."""

from __future__ import annotations

import json
import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from hand_driver import kinematics as kin
from hand_driver.config import load_config
from hand_driver.flat_press import FlatResult
from hand_driver.motion import TouchResult
from recognizer.scene import load_scene
from tactile_jaw.pipeline import (CURVE_HINT_SAMPLES, MOVED_RUN_WINDOWS, curve_refusal, curved_part, curved_stretch,
                                  feel, left_out, logged_samples, moving_stretch)
from tests.tactile_jaw.test_envelope_order import FINE, roll
from tests.tactile_jaw.test_flat import _face, _flat

DATA = Path(__file__).parent / "data"
CLASSES = ["line", "circle", "ellipse", "parabola", "hyperbola", "cubical_parabola", "semicubical_parabola"]


def _hyperbola(a: float, theta: float, x: float, y: float):
    """The scene object: a rectangular hyperbola over t in −1.3..1.3, closed by its chord."""
    return load_scene({"classes": CLASSES, "object": {"class": "hyperbola", "extent": [-1.3, 1.3],
                                                      "params": {"a": a, "b": a},
                                                      "pose": {"theta": theta, "x": x, "y": y}}}).object


def _miss(obj, x, y) -> float:
    """The farthest of the points (x, y) from the object's curve (mm)."""
    px, py = obj.pose.apply(*obj.curve().point(np.linspace(*obj.extent, 200001)))
    return max(float(np.min(np.hypot(px - a, py - b))) for a, b in zip(x, y))


def _logged(config, raw: dict, kind=TouchResult, **extra):
    samples = logged_samples(config, raw["finger"], raw["ticks"], raw["psi"])
    return feel(config, kind(raw["finger"], raw["touch"], raw["psi_center"], samples, **extra), 9)


def test_a_roll_whose_contact_moved_on_the_branch_makes_the_faces_closing_segments():
    """P hyperbola 45 (a = b = 9.9 mm): the left pad's roll kept 8 lines on the branch, where ρ
    grows from 24 to 130 mm, then turned about the end corner; its lines' few-µm errors (the
    truth jaw's backlash and zero errors) leave no run of them a polynomial envelope within
    their stated noise, so the roll showed no curve (curve_at None) and the right pad's three
    presses on the chord were answered line. Every three consecutive lines on the branch touch
    a circle of radius 27–96 ± 0.3 mm: the contact moved, the object is no block."""
    config = load_config("config/jaw-p.yaml")
    raw = json.loads((DATA / "p_hyperbola_45_rolls.json").read_text())["rolls"]
    branch, corner = (_logged(config, r, outcome="ok") for r in raw)
    assert branch.off_curve and curved_stretch(config, branch) is None, branch.problem  # session 16's rule finds none
    branch.touch.outcome = corner.touch.outcome = "rejected"  # as the exploration marks them: felt as taken
    stretch = moving_stretch(config, branch)
    assert stretch is not None and len(stretch.contacts.x) >= 5
    obj = _hyperbola(9.913058884762528, -0.9380753485688964, 88.53656810149093, 21.238957381245562)
    # on the branch: a cubic envelope over ρ 27–96 mm places its contacts up to 0.2 mm along the pads
    assert _miss(obj, stretch.contacts.x, stretch.contacts.y) < 0.3
    assert 20.0 < stretch.fit.rho < 130.0 and stretch.fit.rho > 100.0 * stretch.fit.sigma_rho
    assert corner.corner is not None and moving_stretch(config, corner) is None  # a pivot: the contact stayed
    chord = [_flat(_face(5.0, math.radians(36.25), x0=86.5, x1=113.7), "right") for _ in range(3)]
    found = curved_part(config, [*chord, corner, branch])
    assert found is not None and found.finger == "left" and found.touch.touch == 4
    assert "closing segments, not a line" in curve_refusal(found).reason


def test_a_press_scan_that_rolled_on_the_branch_until_the_pad_end_is_a_curve():
    """Mixed jaw (XM430 base joint, PH42 distal), hyperbola 18 (a = b = 12.9 mm): the left
    pad's press turned 69° without seating; its scan rolled on the branch over its first 18
    lines, then the contact ran off the pad's proximal end (contacts −3 mm along it). The
    whole scan failed on that pad end and showed no curve; without the lines past the pad's
    end (and one beside the cut) it is a usable roll of the branch, ρ ≈ 16 mm."""
    p = load_config("config/jaw-p.yaml")
    left, right = p.finger("left"), p.finger("right")
    mixed = replace(p, fingers=tuple(replace(f, joints=(replace(f.joints[0], model="XM430-W350", zero_tick=2048.0),
                                                        f.joints[1])) for f in (left, right)))
    raw = json.loads((DATA / "mixed_hyperbola_18_press.json").read_text())["press"]
    press = _logged(mixed, raw, FlatResult, outcome=raw["outcome"], roles=raw["roles"])
    whole = feel(mixed, TouchResult("left", 6, raw["psi_center"], press.touch.samples, outcome="ok"), 24)
    assert whole.problem is not None and "pad end" in whole.problem and np.min(whole.pad_u) < 0.0
    found = curved_part(mixed, [press])
    assert found is not None and found.problem is None and not isinstance(found.touch, FlatResult)
    obj = _hyperbola(12.907617658694114, -2.1132519479393075, 101.13491685026267, 4.130128557351055)
    assert _miss(obj, found.contacts.x, found.contacts.y) < 0.5
    assert 10.0 < found.fit.rho < 25.0 and len(found.contacts.x) >= 12
    assert np.min(found.pad_u) > 1.0


def _block_rolls(config, ticks: int, rng):
    """The left pad's 18° rolls of 9 lines on a block: about one corner, and across the straight
    segment between two, each joint rounded to a tick of ``ticks`` per turn (the jaw
    ``config``'s resolution, whose noise its fit states)."""
    psis = np.radians(-97.5 + np.linspace(-9.0, 9.0, 9))
    a, b = np.array([96.0, -2.4]), np.array([112.0, -6.0])
    for contact in (lambda psi: a, lambda psi: min((a, b), key=lambda p: math.cos(psi) * p[0] + math.sin(psi) * p[1])):
        q = roll(contact, psis, ticks, rng)
        left = config.finger("left")
        samples = logged_samples(config, "left", np.rint(kin.angles_to_ticks(left.joints, q)), psis)
        yield feel(config, TouchResult("left", 0, float(np.mean(psis)), samples, outcome="ok"), 9)


@pytest.mark.parametrize("jaw, ticks", [("config/jaw-p.yaml", FINE), ("config/jaw.yaml", 4096)], ids=["P", "X"])
def test_rolls_about_a_blocks_corners_show_no_moving_contact(jaw, ticks):
    """A block's rolls: about one corner (the contact stays put), and across a straight
    segment between two corners (the pivot changes between two lines, two triples straddle
    it): no stretch of a moved contact, on either jaw."""
    config = load_config(jaw)
    for seed in range(5):
        for felt in _block_rolls(config, ticks, np.random.default_rng(seed)):
            assert felt.off_curve, felt.problem
            assert moving_stretch(config, felt) is None


def _cubical():
    """The scene object of P cubical 21 (bench_explore --finite 4 --anywhere --follow --seed 191)."""
    return load_scene({"classes": CLASSES, "object": {
        "class": "cubical_parabola", "extent": [-20.953190336259826, 1.7460991946883189],
        "params": {"a": 0.0010495718017393162, "c": -0.5},
        "pose": {"theta": 0.5362685777876406, "x": 112.3054177260003, "y": 31.892028089784176}}}).object


def test_a_roll_off_the_end_corner_onto_the_curve_makes_the_faces_closing_segments():
    """P cubical 21 (closed by three straight segments via (122.7, 17.8) and (103.2, 6.2) mm):
    the left pad's roll at ψ −99…−81° pivoted about the curve's end corner (114.25, 32.04) for
    6 lines, then its last 3 lines moved along the curve: the three-line windows over those
    lines touch circles of ρ 9.1, 127.3, 53.8 ± 0.35 mm, 3 windows where a block's crossing of a
    face moves 2 (the two that straddle the pivot's change, below). The run is short of the smoothness test's
    CURVE_HINT_SAMPLES, yet the curve was felt: the right pad's presses on the closing segment
    (103.2, 6.2)–(122.7, 17.8) are no line. Before, they were answered line (χ² 1.9e-5, every
    other class untested). Since session 34 those 3 windows also aim the finger's next roll on
    past them, away from the corner (tactile_jaw.pipeline.past_stretch): on the curved part,
    the line through the place aimed at within 1.5 mm of the true support line (no hint before)."""
    config = load_config("config/jaw-p.yaml")
    raw = json.loads((DATA / "p_cubical_21_rolls.json").read_text())["rolls"]
    branch, corner = (_logged(config, r, outcome="ok") for r in raw)
    assert branch.off_curve and curved_stretch(config, branch) is None, branch.problem
    assert corner.corner is not None and moving_stretch(config, corner, MOVED_RUN_WINDOWS) is None
    assert moving_stretch(config, branch) is None  # 3 windows: not moving_hint's 5, past_stretch's 3
    stretch = moving_stretch(config, branch, MOVED_RUN_WINDOWS)
    assert stretch is not None and len(stretch.contacts.x) == CURVE_HINT_SAMPLES
    assert left_out(branch, stretch) == (4, 0)  # the pivot's lines below, the stretch up to the roll's end
    obj = _cubical()
    # its lines past the corner's touch the curve: contacts within 0.5 mm of it; the first, a
    # line through the corner (a window's neighbour), lies 1.3 mm past the curve's end
    assert _miss(obj, stretch.contacts.x[1:], stretch.contacts.y[1:]) < 0.5
    assert 9.0 < stretch.fit.rho < 130.0
    x, y, phi = branch.curve_at  # one roll on past the stretch's high-ψ end, away from the corner's lines
    psi = phi + math.pi / 2
    assert psi > max(s.psi for s in branch.touch.samples) + math.radians(8.0)
    ox, oy = obj.outline(20000)
    support = np.cos(psi) * ox + np.sin(psi) * oy
    k = int(np.argmin(support))
    assert abs(math.cos(psi) * x + math.sin(psi) * y - support[k]) < 1.5
    assert 0 < k < 20000 - 1  # the support there is inside the curved part (its first 20000 points), no corner
    press = _flat(_face(6.18, math.atan2(17.77 - 6.18, 122.73 - 103.21), x0=103.21, x1=122.73, below=False), "right")
    found = curved_part(config, [press, press, press, corner, branch])
    assert found is not None and found.finger == "left" and found.touch.touch == 4
    assert "closing segments, not a line" in curve_refusal(found).reason


@pytest.mark.parametrize("jaw, ticks", [("config/jaw-p.yaml", FINE), ("config/jaw.yaml", 4096)], ids=["P", "X"])
@pytest.mark.parametrize("shift_deg", [0.0, 0.5, 1.125, 1.75])
def test_a_roll_across_a_blocks_face_moves_two_windows_at_most(jaw, ticks, shift_deg):
    """A roll across a straight segment between two corners changes its pivot once between two
    lines (or rests one line on both corners), wherever its ψ grid falls on the face's normal:
    only the two windows holding both pivots touch a circle clear of a pivot's (ρ up to the
    segment's length over the roll's step, hundreds of mm), fewer than MOVED_RUN_WINDOWS, so
    no curved part is felt and the presses on the face stay a line."""
    config = load_config(jaw)
    for seed in range(5):
        rng = np.random.default_rng(seed)
        psis = np.radians(-102.7 + shift_deg + np.linspace(-9.0, 9.0, 9))
        a, b = np.array([96.0, -2.4]), np.array([112.0, -6.0])
        q = roll(lambda psi: min((a, b), key=lambda p: math.cos(psi) * p[0] + math.sin(psi) * p[1]), psis, ticks, rng)
        samples = logged_samples(config, "left", np.rint(kin.angles_to_ticks(config.finger("left").joints, q)), psis)
        felt = feel(config, TouchResult("left", 0, float(np.mean(psis)), samples, outcome="ok"), 9)
        assert felt.off_curve, felt.problem
        assert moving_stretch(config, felt, MOVED_RUN_WINDOWS) is None and curved_part(config, [felt]) is None


def test_the_next_roll_goes_on_along_the_branch_past_the_moving_stretch():
    """The same roll (P hyperbola 45): no run of its lines passes every check, yet its contact
    moved along the branch (t 0.67–1.26 of the extent's 1.3, then the end corner), so the
    finger's next roll aims past that stretch away from the corner (tactile_jaw.pipeline.moving_hint,
    ``curve_at``): on the branch, with its tangent, nearer the vertex than any of the stretch's
    contacts. Before, ``curve_at`` was None, the finger rolled about the corner next, retired,
    and the run was refused "closing segments, not a line" with no move; with the aim it is
    answered hyperbola. A pivot about the corner aims nowhere."""
    config = load_config("config/jaw-p.yaml")
    raw = json.loads((DATA / "p_hyperbola_45_rolls.json").read_text())["rolls"]
    branch, corner = (_logged(config, r, outcome="ok") for r in raw)
    assert branch.curve_at is not None and corner.curve_at is None
    x, y, phi = branch.curve_at
    obj = _hyperbola(9.913058884762528, -0.9380753485688964, 88.53656810149093, 21.238957381245562)
    t = np.linspace(*obj.extent, 200001)
    px, py = obj.pose.apply(*obj.curve().point(t))
    i = int(np.argmin(np.hypot(px - x, py - y)))
    assert math.hypot(px[i] - x, py[i] - y) < 0.3  # on the branch (a circle of the stretch's ρ predicts it)
    tangent = math.atan2(py[i + 1] - py[i - 1], px[i + 1] - px[i - 1])
    assert abs(math.remainder(tangent - phi, math.pi)) < math.radians(5.0)
    stretch = moving_stretch(config, branch)
    reached = [float(t[np.argmin(np.hypot(px - a, py - b))]) for a, b in zip(stretch.contacts.x, stretch.contacts.y)]
    assert t[i] < min(reached) < max(reached) < obj.extent[1]  # past the stretch, away from the end corner


def test_a_stretch_leaves_out_the_readings_beside_it_wherever_the_roll_turned():
    """The samples a stretch leaves out below and above its ψ range are counted by the same
    readings (tactile_jaw.pipeline.left_out), so neither the angle's wrap nor µrad between
    commanded and measured ψ decides a side: P cubical 102 moved of bench_explore --finite 20
    --anywhere --seed 463 rolled its left pad at commanded ψ 214.7–232.7°, its stretch's
    contacts at −140.8 … −129.5°, and the old counts (commanded against the contacts' ψ) gave
    (0, 9) where 2 and 1 were left out; the logged hyperbola roll's stretch is a run inside it."""
    config = load_config("config/jaw-p.yaml")
    raw = json.loads((DATA / "p_hyperbola_45_rolls.json").read_text())["rolls"]
    branch = _logged(config, raw[0], outcome="ok")
    stretch = moving_stretch(config, branch)
    psi = sorted(s.psi for s in branch.touch.samples)
    kept = sorted(s.psi for s in stretch.touch.samples)
    first = psi.index(kept[0])
    assert psi[first:first + len(kept)] == kept  # a run of the roll's readings
    assert left_out(branch, stretch) == (first, len(psi) - first - len(kept))
    turned = [math.radians(214.7387 + 2.25 * k) for k in range(9)]
    whole = replace(branch, touch=replace(branch.touch, samples=[replace(s, psi=p) for s, p in
                                                                  zip(branch.touch.samples, turned)]))
    part = replace(stretch, touch=replace(stretch.touch, samples=whole.touch.samples[2:8]))
    assert left_out(whole, part) == (2, 1)
