"""The recognizer's place as a pad's face really reaches it: the contact travels along the
answered curve over the roll (tactile_jaw.choose.rolled_reach, next_aim, budget_advice)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from hand_driver import kinematics as kin
from hand_driver.config import load_config
from hand_driver.cycle import LIMIT_MARGIN_RAD
from hand_driver.motion import roll_angles
from recognizer.curves import CURVES, Pose
from recognizer.result import Recognition
from tactile_jaw.choose import JawReach, budget_advice, next_aim, rolled_reach
from tactile_jaw.decide import Why
from tactile_jaw.settings import ExploreSettings

ROOT = Path(__file__).resolve().parents[2]
CONFIG = load_config(ROOT / "config" / "jaw-p.yaml")
SETTINGS = ExploreSettings.from_profile("balanced")
REACH = JawReach(CONFIG, SETTINGS)
LEFT = CONFIG.finger("left")
# P semicubical 134 of bench_explore --finite 20 --anywhere --seed 541 (config/jaw-p.yaml), exact
PARAMS = {"a": 0.3430990217104318, "b": -1.2}
POSE = Pose(2.5972595800326888, 105.5967908714265, -0.2742260143662163)
CURVE = CURVES["semicubical_parabola"](PARAMS)
T = np.linspace(0.87, 4.64, 20001)  # the object's branch
PX, PY = POSE.apply(*CURVE.point(T))
# the left pad's inward normal: the tangent (the direction of travel, away from the cusp) + π/2
PSI = np.unwrap(np.asarray(CURVE.tangent_angle(T), float) + POSE.theta + math.pi / 2)
FELT = Recognition("semicubical_parabola", PARAMS, pose=POSE, contacts=[{"t": 2.0}, {"t": 3.1}])


def _place(psi_deg: float) -> tuple[float, float, float]:
    """(x, y, φ) of the branch where the left pad's normal is ψ."""
    k = int(np.argmin(np.abs(np.remainder(PSI - math.radians(psi_deg) + math.pi, 2 * math.pi) - math.pi)))
    return float(PX[k]), float(PY[k]), float(PSI[k]) - math.pi / 2


def _pad_ends(psi0: float) -> list[float]:
    """Where along the left pad (mm) the exact branch touches it at the two ends of a roll about ψ0."""
    out = []
    for a in roll_angles(psi0, SETTINGS.roll_span_rad, SETTINGS.samples_per_touch)[[0, -1]]:
        x, y, _ = _place(math.degrees(float(a)))
        p = np.array([x, y])
        out += [float(kin.finger_pad_line(LEFT, q).pad_coordinate(p))
                for q in kin.ik_line_solutions(LEFT, float(a), float(kin.unit(float(a)) @ p))
                if kin.within_limits(LEFT.joints, q, LIMIT_MARGIN_RAD)]
    return out


def test_the_place_a_pads_face_rolls_through_is_aimed_at_not_the_one_its_end_meets():
    # the recognizer's place at pad normal −87.3° (log of that run): held there the contact
    # stays on the pad; travelling along the branch (ρ 24 mm) it runs to the pad's proximal
    # end, as the roll aimed there did (contact 0.3–8.7 mm along the pad, not used)
    x, y, phi = _place(-87.3)
    assert REACH.finger(x, y, phi) is not None  # the old promise
    assert min(_pad_ends(phi + math.pi / 2)) < 1.0
    suggested = {"x": x, "y": y, "phi": phi, "gain": 6.0, "why": "tells semicubical_parabola from ellipse"}
    rec = Recognition("semicubical_parabola", PARAMS, pose=POSE, contacts=FELT.contacts, next_touch=suggested)
    aim, stop = next_aim(rec, Why("semicubical_parabola and ellipse both fit", "rival", "ellipse"),
                         (PX[:1], PY[:1]), REACH, CONFIG.fingers, [])
    assert stop is None and aim is not None and aim.finger == "left"
    psi = math.degrees(math.remainder(aim.psi, 2 * math.pi))
    assert -100.0 < psi < -93.0, psi  # toward the felt stretch, as little as the pad's face needs
    assert math.hypot(*(np.array(aim.point) - np.array(_place(psi)[:2]))) < 0.1  # on the branch
    ends = _pad_ends(aim.psi)
    assert ends and all(1.0 < u < LEFT.pad.length_mm - 1.0 for u in ends), ends
    assert "nearest where the recognizer points" in aim.why


def test_a_place_the_pads_face_reaches_is_aimed_at_where_it_is():
    x, y, phi = _place(-110.0)
    got = rolled_reach(FELT, x, y, phi, REACH)
    assert got is not None and got[3].name == "left"
    assert math.hypot(got[0] - x, got[1] - y) < 1e-9 and abs(got[2] - phi) < 1e-12


def test_the_budgets_advice_names_a_move_for_a_place_the_pads_face_does_not_reach():
    # "within a pad's reach: a profile with more touches may decide" was said of the place
    # at −87.3°, where the travelling contact runs off the pad: a move is named instead
    x, y, phi = _place(-87.3)
    wanted = {"x": x, "y": y, "phi": phi, "gain": 6.0, "why": "w"}
    stop = budget_advice(FELT, Why("semicubical_parabola and ellipse both fit", "rival", "ellipse"), None, REACH, 8,
                         anywhere=lambda: wanted)
    assert "within a pad's reach" not in stop and "the most telling touch would roll at" in stop
    x, y, phi = _place(-110.0)
    near = {"x": x, "y": y, "phi": phi, "gain": 6.0, "why": "w"}
    stop = budget_advice(FELT, Why("semicubical_parabola and ellipse both fit", "rival", "ellipse"), None, REACH, 8,
                         anywhere=lambda: near)
    assert "within a pad's reach" in stop and stop.move is None
