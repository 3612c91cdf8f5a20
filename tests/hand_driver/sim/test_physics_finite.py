"""Contact physics of finite objects (docs/formats.md, scene) against exact geometry: a pad pressed
flat onto a closing segment lies on the segment's line, a tilted pad stops with its end on
it, a pad pressed onto a corner at any orientation of the corner's normal cone stops with
its line through the corner (rolling on a corner pivots about it), the curve counts only
over its extent, and the inside test agrees with the outline."""

from __future__ import annotations

import math

import numpy as np
import pytest
from matplotlib.path import Path as MplPath

from hand_driver import kinematics as kin
from hand_driver.config import load_config
from hand_driver.sim.boundary import Boundary
from hand_driver.sim.physics import ContactWorld
from recognizer.scene import load_scene

CFG = load_config("config/jaw.yaml")
LEFT = CFG.finger("left")
RIGHT_PARK = np.array([-1.3, -0.9])


def _object(raw: dict):
    return load_scene({"object": raw}).object


# a box 80 x 20 mm: its bottom face is the line, its top face (y = 18 in the hand frame) a
# closing segment longer than the pad
BOX = _object({"class": "line", "extent": [-40.0, 40.0], "closure": [[40.0, 20.0], [-40.0, 20.0]],
               "pose": {"theta": 0.0, "x": 105.0, "y": -2.0}})
# a parabolic plate, vertex down: its chord is the top face (y = 18), shorter than the pad,
# between the corners P(1.2) = (105, 18) and P(-1.2) = (133.8, 18)
A, T1 = 6.0, 1.2
PLATE = _object({"class": "parabola", "params": {"a": A}, "extent": [-T1, T1],
                 "pose": {"theta": math.pi / 2, "x": 105.0 + 2 * A * T1, "y": 18.0 - A * T1 * T1}})


def _press(world: ContactWorld, psi: float, point, depth: float = 5.0) -> np.ndarray:
    """Push the left pad, normal at ψ, from 2 ``depth`` mm outside ``point`` to ``depth`` mm
    inside it along a straight joint-space step; the joint angles where it stopped."""
    n = np.array([math.cos(psi), math.sin(psi)])
    p = np.asarray(point, dtype=float)
    q_out = kin.ik_line(LEFT, psi, float(n @ p) - 2 * depth, contact=p - 2 * depth * n)
    q_in = kin.ik_line(LEFT, psi, float(n @ p) + depth, contact=p + depth * n)
    q_from, q_to = np.r_[q_out, RIGHT_PARK], np.r_[q_in, RIGHT_PARK]
    assert not world.penetrates(q_from) and world.penetrates(q_to, [0])
    q = world.constrain(q_from, q_to)
    assert not world.penetrates(q)
    assert world.penetrates(q + 1e-5 * (q_to - q_from), [0])  # pressed against it, no gap
    return q


def test_pad_pressed_flat_on_a_closing_segment_lies_on_it():
    world = ContactWorld(CFG, BOX)
    q = _press(world, -math.pi / 2, (105.0, 18.0))
    line = kin.finger_pad_line(LEFT, q[:2])
    assert float(line.d) == pytest.approx(-18.0, abs=1e-4)  # the pad's line is the face's line y = 18
    for end in (line.proximal, line.distal):  # the whole pad is on the face
        assert float(end[1]) == pytest.approx(18.0, abs=1e-4) and 65.0 < float(end[0]) < 145.0


@pytest.mark.parametrize("tilt", [0.08, -0.15])
def test_tilted_pad_stops_with_its_end_on_a_closing_segment(tilt):
    world = ContactWorld(CFG, BOX)
    q = _press(world, -math.pi / 2 + tilt, (105.0, 18.0))
    line = kin.finger_pad_line(LEFT, q[:2])
    low = min((line.proximal, line.distal), key=lambda e: float(e[1]))
    assert float(low[1]) == pytest.approx(18.0, abs=1e-4)  # the lower pad end rests on the face
    assert 65.0 < float(low[0]) < 145.0


@pytest.mark.parametrize("psi_deg", [-85.0, -75.0, -65.0, -55.0])
def test_pad_on_a_corner_pivots_about_it(psi_deg):
    """P(t1) of the plate, between the chord (outward normal +y) and the curve (outward
    normal at 129.8° + 90°): every pad normal ψ in (−90°, 39.8°) stops with n(ψ)·c = d."""
    corner = np.array([105.0, 18.0])
    assert np.allclose(Boundary(PLATE).corners[0], corner)
    world = ContactWorld(CFG, PLATE)
    psi = math.radians(psi_deg)
    q = _press(world, psi, corner)
    line = kin.finger_pad_line(LEFT, q[:2])
    n = np.array([math.cos(psi), math.sin(psi)])
    assert float(line.d) == pytest.approx(float(n @ corner), abs=1e-4)  # the pad's line through the corner
    assert 0.0 < float(line.pad_coordinate(corner)) < LEFT.pad.length_mm
    near = {c.finger: c for c in world.contact_info(q)}["left"]
    assert near.gap_mm < 1e-3 and np.allclose(near.point, corner, atol=0.06)


@pytest.mark.parametrize("t, blocked", [(0.6, True), (2.0, False)])
def test_curve_blocks_only_over_its_extent(t, blocked):
    """The plate posed with its curve's point P(t) at (105, 18), outward normal +y: a pad
    coming down stops tangent there for t = 0.6; for t = 2.0, beyond the extent [-1.2, 1.2],
    nothing is there (the corner P(1.2) is 1.7 mm below) and the whole 1 mm step is free."""
    phi = math.atan2(1.0, t)  # the parabola's tangent angle; its solid is on the right
    theta = -phi  # tangent along +x, solid below
    c, s = math.cos(theta), math.sin(theta)
    u, v = A * t * t, 2 * A * t
    obj = _object({"class": "parabola", "params": {"a": A}, "extent": [-T1, T1],
                   "pose": {"theta": theta, "x": 105.0 - (c * u - s * v), "y": 18.0 - (s * u + c * v)}})
    world = ContactWorld(CFG, obj)
    q_out = kin.ik_tangent(LEFT, (105.0, 28.0), -math.pi / 2)
    q_in = kin.ik_tangent(LEFT, (105.0, 17.0), -math.pi / 2)
    q_from, q_to = np.r_[q_out, RIGHT_PARK], np.r_[q_in, RIGHT_PARK]
    q = world.constrain(q_from, q_to)
    d = float(kin.finger_pad_line(LEFT, q[:2]).d)
    if blocked:
        assert d == pytest.approx(-18.0, abs=1e-4) and world.penetrates(q_to)
    else:
        assert np.array_equal(q, q_to) and not world.penetrates(q_to)


@pytest.mark.parametrize("raw", [
    {"class": "parabola", "params": {"a": 8.0}, "extent": [-1.4, 1.4], "closure": [[40.0, 30.0], [40.0, -30.0]]},
    {"class": "hyperbola", "params": {"a": 15.0, "b": 20.0}, "extent": [-1.0, 1.0], "closure": [[0.0, 0.0]]},
    {"class": "cubical_parabola", "params": {"a": 0.002, "c": 0.3}, "extent": [-20.0, 15.0],
     "closure": [[15.0, -40.0], [-20.0, -40.0]]},
    {"class": "semicubical_parabola", "params": {"a": 0.5, "b": 0.2}, "extent": [-4.0, 5.0]},
])
def test_inside_agrees_with_the_outline(raw):
    obj = _object({**raw, "pose": {"theta": 0.4, "x": 100.0, "y": -5.0}})
    b = Boundary(obj)
    x, y = obj.outline(samples=20001)
    outline = np.stack([x, y], axis=-1)
    rng = np.random.default_rng(3)
    lo, hi = outline.min(axis=0) - 5.0, outline.max(axis=0) + 5.0
    pts = rng.uniform(lo, hi, size=(600, 2))
    far = np.array([np.min(np.hypot(*(outline - p).T)) > 0.05 for p in pts])
    expect = MplPath(outline).contains_points(pts[far])
    got = np.array([b.inside(*p) for p in pts[far]])
    assert far.sum() > 500 and 50 < expect.sum() < 550
    assert np.array_equal(got, expect)


def test_closed_form_roots_agree_with_numpy():
    """The crossings' cubic solver (closed form, Newton-polished, numpy fallback) finds the
    same real simple roots as numpy's companion matrix on random, also ill-scaled, cubics."""
    from hand_driver.sim.boundary import _real_roots

    rng = np.random.default_rng(5)
    checked = 0
    for _ in range(3000):
        c = [float(rng.choice([-1.0, 1.0]) * 10 ** rng.uniform(-8, 3)) for _ in range(4)]
        if rng.uniform() < 0.5:
            c[int(rng.integers(1, 4))] = 0.0
        r = np.roots(c)
        tol = 1e-12 * np.maximum(1.0, np.abs(r.real))
        if np.any((np.abs(r.imag) > tol) & (np.abs(r.imag) < 1e6 * tol)):
            continue  # a near-double root: whether it is real is a matter of rounding
        real = np.sort(r[np.abs(r.imag) <= tol].real)
        if len(real) > 1 and np.min(np.diff(real)) < 1e-6 * max(1.0, float(np.max(np.abs(real)))):
            continue
        mine = np.sort(_real_roots(c))
        assert len(mine) == len(real) and np.allclose(mine, real, rtol=1e-9, atol=1e-12), c
        checked += 1
    assert checked > 2500
