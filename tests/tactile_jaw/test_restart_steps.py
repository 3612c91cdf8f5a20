"""Where a later flat press on a seated face starts (tactile_jaw.flat_phase.restart_steps): a
stop of the last seated press, started as the next one will be, that fitted neither support on
the side the presses come from moves the start out by whole steps, so the press turns through
the seat once; none, or a press started elsewhere, and it starts where it did."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from hand_driver.flat_press import FLAT_STEP_DEG, FlatResult
from recognizer.touches import ContactTouch
from tactile_jaw.flat import Face
from tactile_jaw.flat_phase import FLAT_RESTART_STEPS, _booked, restart_steps
from tactile_jaw.pipeline import FeltTouch

from hand_driver.config import load_config

FACE_PSI = math.radians(-136.7)
STEP = math.radians(FLAT_STEP_DEG)


def _press(offsets_roles: list[tuple[float, str]], finger: str = "left") -> FlatResult:
    """A seated press whose stops lie ``offset`` steps from FACE_PSI with their roles."""
    samples = [SimpleNamespace(line=SimpleNamespace(psi=FACE_PSI + k * STEP)) for k, _ in offsets_roles]
    return FlatResult(finger, 8, FACE_PSI + offsets_roles[0][0] * STEP, samples, outcome="ok",
                      roles=[role for _, role in offsets_roles])


#: the press of P line 2 of bench_explore --finite 20 --anywhere --seed 599 (P jaw), in the order
#: taken, from 2.5 steps above the normal: the stop half a step above it fitted neither support
SLID = [(2.5, "Q"), (1.5, "Q"), (0.49, "scan"), (-0.51, "P"), (3.49, "Q"), (-1.51, "P"), (-0.76, "P"),
        (-0.03, "seat"), (0.0, "seat"), (0.03, "seat")]
#: a clean press from 2.5 steps below: three stops through each support, the seat between
CLEAN = [(-2.5, "P"), (-1.5, "P"), (-0.5, "P"), (0.5, "Q"), (1.5, "Q"), (2.5, "Q"),
         (0.0, "seat"), (-0.03, "seat"), (0.03, "seat")]


def test_a_stop_between_the_supports_on_the_start_side_moves_the_start_out():
    """From above (side −1) the third stop at 2.5 steps lands half a step from the seat, where the
    last press's stop (0.49) fitted neither support: one step farther out, its third stop at 1.5."""
    assert restart_steps(_press(SLID), FACE_PSI, -1) == FLAT_RESTART_STEPS + 1
    assert FLAT_RESTART_STEPS - 2 < 0.49 + 0.25 < FLAT_RESTART_STEPS + 1 - 2


def test_a_stop_between_the_supports_on_the_other_side_leaves_the_start():
    """The same press, had the presses come from below: the undecided stop lies beyond the seat,
    where the press goes on turning anyway."""
    assert restart_steps(_press(SLID), FACE_PSI, 1) == FLAT_RESTART_STEPS


def test_a_clean_press_leaves_the_start():
    assert restart_steps(_press(CLEAN), FACE_PSI, 1) == FLAT_RESTART_STEPS
    assert restart_steps(_press(CLEAN), FACE_PSI, -1) == FLAT_RESTART_STEPS


def test_a_stop_at_the_seat_fitting_both_leaves_the_start():
    """A stop a hundredth of a step from the seat (through both supports) is no stop the press's
    third line comes near: 0.5 steps away."""
    near = CLEAN[:3] + [(-0.01, "scan")] + CLEAN[3:]
    assert restart_steps(_press(near), FACE_PSI, 1) == FLAT_RESTART_STEPS


def test_scan_stops_beyond_the_supports_are_not_between():
    """Stops of the walk to the seat far out on the start side fitted neither support, being
    far from it: not between the supports' runs, they move nothing."""
    walk = CLEAN + [(-8.0, "scan"), (-7.0, "scan"), (-6.0, "scan")]
    assert restart_steps(_press(walk), FACE_PSI, 1) == FLAT_RESTART_STEPS


def test_a_stop_further_in_moves_the_start_out_further():
    """Stops fitting neither support up to 1.3 steps from the seat: the third stop must lie at
    2.5 steps, FLAT_RESTART_STEPS + 2."""
    wide = [(2.5, "Q"), (1.3, "scan"), (0.5, "scan"), (-0.5, "scan"), (-1.5, "P"), (-2.5, "P"), (-3.5, "P"),
            (3.5, "Q"), (4.5, "Q")]
    assert restart_steps(_press(wide), FACE_PSI, -1) == FLAT_RESTART_STEPS + 2


def test_a_press_started_elsewhere_tells_nothing():
    """A first press from the pad's nominal normal, 3.57 steps below the seat (P line 19 of seed
    599): its stop 0.57 steps below fitted neither support, and the later presses from 2.5 steps
    had their third stop there 0.5 steps below, through its support; their stops lie on another
    grid, the pad resting otherwise."""
    nominal = [(-3.57, "P"), (-2.57, "P"), (-1.57, "P"), (-0.57, "scan"), (0.43, "Q"), (1.43, "Q"), (0.68, "Q"),
               (0.0, "seat"), (-0.03, "seat"), (0.03, "seat")]
    assert restart_steps(_press(nominal), FACE_PSI, 1) == FLAT_RESTART_STEPS


def test_a_press_started_farther_out_keeps_its_start():
    """Started 3.5 steps out, its stop half a step from the seat between the supports: the third
    stop (1.5 steps) lies beyond it, the start stays."""
    out = [(3.5, "Q"), (2.5, "Q"), (1.5, "Q"), (0.5, "scan"), (-0.5, "P"), (-1.5, "P"), (-2.5, "P"),
           (0.0, "seat"), (-0.03, "seat"), (0.03, "seat")]
    assert restart_steps(_press(out), FACE_PSI, -1, FLAT_RESTART_STEPS + 1) == FLAT_RESTART_STEPS + 1


def test_bad_input_is_refused_and_a_press_without_both_supports_tells_nothing():
    with pytest.raises(ValueError, match="side"):
        restart_steps(_press(CLEAN), FACE_PSI, 0)
    assert restart_steps(_press([(k, "P") for k, _ in CLEAN]), FACE_PSI, 1) == FLAT_RESTART_STEPS


def test_the_booked_press_sets_the_next_start():
    """Booking the seated press (the flat phase's state) records where the finger's next press
    on that face starts; the side is the one its first seated press came from (above: −1)."""
    cfg = load_config("config/jaw-p.yaml")
    press = _press(SLID)
    face = Face(FACE_PSI, 0.0, np.zeros(2), np.array([-math.sin(FACE_PSI), math.cos(FACE_PSI)]) * 20.0)
    contact = ContactTouch(float(face.middle[0]), float(face.middle[1]), face.phi, 0.0, 0.0, np.eye(2) * 1e-6)
    felt = FeltTouch(press, None, None, None, None, contact, face=face)
    state = _booked(cfg, [felt])
    assert state.sides["left"] == -1
    assert state.restarts == {"left": FLAT_RESTART_STEPS + 1}
