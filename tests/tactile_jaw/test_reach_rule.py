"""One reach rule for one place and for many (tactile_jaw.plan.reaches_lines): plan.feasible,
JawReach.finger, JawReach.contains and the move search give the answers of the rule written out
place by place in plain math here (the pre-session-26 plan.feasible, kinematics.ik_line_solutions
and RolledArc.contact), and the move search asks no place by place (session 26)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import tactile_jaw.choose as choose
from hand_driver import kinematics as kin
from hand_driver.config import load_config
from hand_driver.cycle import LIMIT_MARGIN_RAD
from hand_driver.motion import roll_angles
from tactile_common.angles import wrap_angle
from tactile_jaw.choose import Goal, JawReach, move_for, place_goal
from tactile_jaw.plan import (APPROACH_MARGIN_MM, PLAN_OVERSHOOT_MM, PLAN_PAD_MARGIN, ObjectModel, RolledArc,
                              feasible, feasible_many, nominal_psi, rolled_arc)
from tactile_jaw.settings import ExploreSettings

ROOT = Path(__file__).resolve().parents[2]
JAWS = {name: load_config(ROOT / "config" / name) for name in ("jaw.yaml", "jaw-p.yaml")}


def _ik(finger, psi: float, d: float) -> list[np.ndarray]:
    """Both joint solutions of the line n(ψ)·p = d, math only (the rule's definition)."""
    j1 = finger.joints[0]
    c = (d - finger.pad.offset_mm - (math.cos(psi) * finger.base.x + math.sin(psi) * finger.base.y)) / j1.link_mm
    if abs(c) > 1.0:
        return []
    a2 = psi - finger.pad.side_sign * math.pi / 2
    return [np.array([wrap_angle(a1 - finger.base.angle), wrap_angle(a2 - a1)])
            for a1 in (psi + math.acos(c), psi - math.acos(c))]


def _reached(finger, psi: float, d: float) -> list[np.ndarray]:
    return [q for q in _ik(finger, psi, d) if kin.within_limits(finger.joints, q, LIMIT_MARGIN_RAD)]


def _contact(x, y, psi0, rho, drho, psi) -> np.ndarray:
    delta = math.remainder(psi - psi0, 2 * math.pi)
    n, n0 = np.array([math.cos(psi), math.sin(psi)]), np.array([math.cos(psi0), math.sin(psi0)])
    dn, dn0 = np.array([-math.sin(psi), math.cos(psi)]), np.array([-math.sin(psi0), math.cos(psi0)])
    return np.array([x, y]) - rho * (n - n0) - drho * (delta * n + dn - dn0)


def _aimed(x, y, psi, rho=0.0, drho=0.0):
    """The predicted line (d, contact) of a roll aimed at (x, y) on an arc, at pad normal a."""
    def at(a):
        p = _contact(x, y, psi, rho, drho, a)
        return math.cos(a) * p[0] + math.sin(a) * p[1], p
    return at


def _rolls(finger, config, settings, psi, at) -> bool:
    """The reach rule of one roll centred on ψ, written out: at both ends a of the roll the
    predicted line ``at(a)`` (d, contact) has a solution within the limits with the contact 10 %
    of the pad from either end, the line 1.5 mm beyond has one, and so has a line from the
    workspace edge's inward in 1 mm steps up to 10 mm outside d."""
    (cx, cy), r = config.workspace.center_mm, config.workspace.radius_mm
    length = finger.pad.length_mm
    for a in roll_angles(psi, settings.roll_span_rad, settings.samples_per_touch)[[0, -1]]:
        a = float(a)
        if at(a) is None:
            return False
        d, p = at(a)
        u = [float(kin.finger_pad_line(finger, q).pad_coordinate(p)) for q in _reached(finger, a, d)]
        if not any(PLAN_PAD_MARGIN * length <= v <= (1 - PLAN_PAD_MARGIN) * length for v in u):
            return False
        if not _reached(finger, a, d + PLAN_OVERSHOOT_MM):
            return False
        step = math.cos(a) * cx + math.sin(a) * cy - r
        limit = max(step, d - APPROACH_MARGIN_MM)
        while step <= limit + 1e-9 and not _reached(finger, a, step):
            step += 1.0
        if step > limit + 1e-9:
            return False
    return True


def _places(config, rng, n):
    c, r = np.array(config.workspace.center_mm), config.workspace.radius_mm
    ang, rad = rng.uniform(0, 2 * np.pi, n), r * np.sqrt(rng.uniform(0, 1.2, n))
    # tangents about as a finger's pad meets them (either finger), and any at all
    facing = np.array([nominal_psi(config.fingers[k]) for k in rng.integers(0, 2, n)]) - math.pi / 2
    phi = np.where(rng.uniform(0, 1, n) < 0.7, facing + np.radians(rng.uniform(-70, 70, n)), rng.uniform(-np.pi, np.pi, n))
    return c[0] + rad * np.cos(ang), c[1] + rad * np.sin(ang), phi


@pytest.mark.parametrize("name", sorted(JAWS))
def test_the_reach_of_one_place_and_of_many_is_the_rule_written_out(name):
    # random places in and around the workspace disk, random tangents and curvatures: finger()
    # (one place, with and without a rolled arc) and contains() (all at once) answer as the rule
    config = JAWS[name]
    rng = np.random.default_rng(26)
    for profile in ("fast", "accurate"):
        settings = ExploreSettings.from_profile(profile)
        reach = JawReach(config, settings)
        px, py, phi = _places(config, rng, 100)
        kappa = rng.choice([-1.0, 1.0], px.size) * 10 ** rng.uniform(-1.7, -0.5, px.size)
        kappa_s = rng.normal(0, 1, px.size) * kappa ** 2
        inside = [bool(reach.disk.contains(x, y)) for x, y in zip(px, py)]
        plain, curved = [], []
        for k, (x, y, f) in enumerate(zip(px, py, phi)):
            psi = float(f) + math.pi / 2
            arc = rolled_arc(float(x), float(y), psi, float(kappa[k]), float(kappa_s[k]))
            plain.append(inside[k] and any(_rolls(g, config, settings, psi, _aimed(float(x), float(y), psi))
                                           for g in config.fingers))
            curved.append(inside[k] and any(_rolls(g, config, settings, psi,
                                                   _aimed(float(x), float(y), psi, arc.rho, arc.drho))
                                            for g in config.fingers))
            assert (reach.finger(float(x), float(y), float(f)) is not None) == plain[-1]
            assert (reach.finger(float(x), float(y), float(f), curvature=(kappa[k], kappa_s[k])) is not None) == curved[-1]
        assert reach.contains(px, py, phi).tolist() == plain
        assert 10 <= sum(plain) <= 90 and 5 <= sum(curved) and plain != curved


def test_the_planners_own_rolls_are_the_rule_with_the_object_models_tangents():
    # feasible() without an aim, one orientation and many (choose_psi's), on an exact circle's lines
    config = JAWS["jaw-p.yaml"]
    settings = ExploreSettings.from_profile("balanced")
    model = ObjectModel(config.workspace.center_mm, config.workspace.radius_mm)
    grid = np.radians(np.arange(-150.0, 150.0, 4.0))  # nothing felt toward the palm: no tangent there
    centre, radius = np.array([112.0, 4.0]), 18.0
    model.add(grid, np.cos(grid) * centre[0] + np.sin(grid) * centre[1] - radius)
    for finger in config.fingers:
        psis = np.radians(np.arange(-180.0, 180.0, 2.5))
        many = feasible_many(finger, model, psis, settings)
        for psi, got in zip(psis, many):
            want = _rolls(finger, config, settings, float(psi), model.tangent)
            assert got == want == feasible(finger, model, float(psi), settings)
        assert 5 <= np.count_nonzero(many) <= psis.size - 5


def test_an_aim_at_a_point_is_an_arc_of_no_radius():
    arc = RolledArc(np.array([3.0, -7.5]), np.array([1.25, 2.0]), np.array([0.3, -2.0]), 0.0)
    for a in (0.1, 0.5, -2.9):
        assert np.array_equal(arc.contact(np.array([a, a])), np.array([[3.0, 1.25], [-7.5, 2.0]]))


def _first_reaching_place_by_place(reach, goal, cands):
    """The move search's rule asked place by place (before session 26)."""
    order, asked = list(range(len(goal.places))), 0
    for cand in cands:
        for j in list(order):
            asked += 1
            x, y = cand[4][j]
            if reach.finger(float(x), float(y), goal.places[j][2] + cand[2], None, goal.curvature_of(j)) is None:
                order.remove(j)
                order.insert(0, j)
                break
        else:
            return cand
        if asked >= choose.MOVE_QUERIES:
            return None
    return None


def test_the_move_search_asks_many_places_at_once_and_finds_the_same_move(monkeypatch):
    # goals of one place, of a place on a curve and of three places, both jaws: the first reaching
    # candidate is the place-by-place search's, with no question to finger()
    cases = [("jaw.yaml", place_goal(105.0, 12.0, math.radians(60.0) - math.pi / 2)),
             ("jaw-p.yaml", Goal(((118.0, -20.0, 0.4),), np.array([[118.0], [-20.0]]), (118.0, -20.0), "w",
                                 ((0.05, 0.001),))),
             ("jaw-p.yaml", Goal(tuple((100.0 + 8 * k, 25.0 + 3 * k, -2.6 + 0.2 * k) for k in range(3)),
                                 np.array([[100.0, 108.0, 116.0], [25.0, 28.0, 31.0]]), (100.0, 25.0), "w",
                                 ((0.03, -0.0005), None, (-0.02, 0.0))))]
    real = choose._first_reaching
    for name, goal in cases:
        reach = JawReach(JAWS[name], ExploreSettings.from_profile("balanced"))
        seen = []
        monkeypatch.setattr(choose, "_first_reaching", lambda *a: seen.append(a[2]) or real(*a))
        monkeypatch.setattr(JawReach, "finger", lambda *a, **k: pytest.fail("asked finger() place by place"))
        move = move_for(reach, goal)
        monkeypatch.undo()
        want = _first_reaching_place_by_place(reach, goal, seen[0])
        assert move is not None and want is not None
        assert move == (float(want[3][0]), float(want[3][1]), want[2])
