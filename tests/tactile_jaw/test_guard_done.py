"""The closing-segment guard ends with the presses once the other finger met a second straight
face and nothing else (tactile_jaw.flat_phase.guard_done, straight_side): exact support lines of
a block's far face, of a hyperbola's curved part and of its end beside a closing-segment corner."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np

from hand_driver import kinematics as kin
from hand_driver.flat_press import FlatResult
from hand_driver.config import load_config
from tactile_jaw.flat import Face
from tactile_jaw.flat_phase import guard_done, straight_side
from tactile_jaw.settings import ExploreSettings

PAD_MM = 52.0
A, B = np.array([92.0, 21.0]), np.array([134.0, 24.0])  # a block's far face (P line 19 of seed 571's)


def _line(psi_deg: float, boundary: np.ndarray) -> kin.PadLine:
    """The exact support line of pad normal ψ on the points ``boundary`` (the object below it), the
    contact at the pad's middle."""
    psi = math.radians(psi_deg)
    n = kin.unit(psi)
    c = boundary[int(np.argmin(boundary @ n))]
    t = np.array([-n[1], n[0]])
    proximal = c - 0.5 * PAD_MM * t
    return kin.PadLine(np.float64(psi), np.float64(n @ c), n, t, proximal, proximal + PAD_MM * t, proximal - 5 * t)


def _touch(name: str, psis, boundary, **felt):
    samples = [SimpleNamespace(line=_line(p, boundary), psi=math.radians(p)) for p in psis]
    touch = SimpleNamespace(finger=name, samples=samples, outcome="ok")
    return SimpleNamespace(finger=name, touch=touch, off_curve=True, curve_at=None, **felt)


def _block(a=A, b=B, depth=20.0) -> np.ndarray:
    corners = [a, b, b - [0, depth], a - [0, depth]]
    return np.concatenate([np.linspace(p, q, 400) for p, q in zip(corners, corners[1:] + corners[:1])])


def _hyperbola(a=20.0, b=12.0, t_end=1.3, vertex=(110.0, 25.0)) -> np.ndarray:
    """A finite hyperbola (x = a cosh t, y = b sinh t) turned so its vertex faces the left pad
    (ψ −90°), closed by its chord: the curve sampled 0.005 mm apart, and the chord."""
    t = np.linspace(-t_end, t_end, 40001)
    x, y = a * np.cosh(t), b * np.sinh(t)
    arc = np.stack([y, -x], axis=1) + [vertex[0], vertex[1] + a]
    return np.concatenate([arc, np.linspace(arc[-1], arc[0], 400)])


def _roll(centre_deg: float) -> list[float]:
    return [centre_deg + 2.25 * k for k in range(-4, 5)]


def _probe(centre_deg: float) -> list[float]:
    return [centre_deg - 3.0, centre_deg - 1.0, centre_deg + 1.0, centre_deg + 3.0]


def _out(boundary, probes=(-110.0, -100.0, -90.0), rolls=(-86.0,)):
    return SimpleNamespace(probes=[_touch("left", _probe(p), boundary) for p in probes],
                           touches=[_touch("left", _roll(r), boundary) for r in rolls])


def test_a_blocks_far_face_is_a_straight_side():
    side = straight_side(_out(_block()), "left", PAD_MM, math.radians(-90.0))
    assert side is not None
    p, q = sorted(side, key=lambda x: x[0])
    assert np.linalg.norm(p - A) < 0.05 and np.linalg.norm(q - B) < 0.05


def test_a_hyperbolas_curved_part_is_no_straight_side():
    # the same probes and roll on the vertex (ρ = b²/a = 7.2 mm) and on an arm near its end corner
    assert straight_side(_out(_hyperbola()), "left", PAD_MM, math.radians(-90.0)) is None
    arm = _hyperbola()
    end = arm[40000]  # the arc's end at t = 1.3, a corner of the closing chord
    lines = [_line(p, arm) for p in _roll(-140.0)]
    on_corner = [abs(float(ln.normal @ end) - float(ln.d)) < 1e-3 for ln in lines]
    assert any(on_corner) and not all(on_corner)  # the roll turns from the arm onto its end corner
    out = SimpleNamespace(probes=[], touches=[_touch("left", _roll(-140.0), arm), _touch("left", _roll(-130.0), arm)])
    assert straight_side(out, "left", PAD_MM, math.radians(-90.0)) is None


def test_a_roll_that_felt_a_curved_stretch_or_was_usable_is_no_straight_side():
    out = _out(_block())
    out.touches[0].curve_at = (110.0, 22.0, 0.0)
    assert straight_side(out, "left", PAD_MM, math.radians(-90.0)) is None
    out = _out(_block())
    out.touches[0].off_curve = False
    assert straight_side(out, "left", PAD_MM, math.radians(-90.0)) is None


def _presses(face: Face, n: int = 3):
    presses = []
    for k in range(n):
        touch = FlatResult("right", 20 + k, face.psi, [], outcome="ok")
        presses.append(SimpleNamespace(finger="right", touch=touch, problem=None, face=face, to_json=lambda: {}))
    return presses


def _face(p, q, psi_deg) -> Face:
    psi = math.radians(psi_deg)
    return Face(psi, float(kin.unit(psi) @ np.asarray(p)), np.asarray(p, float), np.asarray(q, float))


def test_the_guard_ends_with_the_presses_only_beside_a_second_straight_face():
    cfg = load_config("config/jaw-p.yaml")
    settings = ExploreSettings.from_profile("balanced")
    block = _block()
    out = _out(block)
    bottom = _face(A - [0, 20], B - [0, 20], 90.0 + math.degrees(math.atan2(3.0, 42.0)))
    out.touches += _presses(bottom)
    why = guard_done(cfg, out, out.touches[1:], settings)
    assert why is not None and "straight face" in why
    assert guard_done(cfg, out, out.touches[1:3], settings) is None  # two presses: no answer yet
    # the right pad pressed the face the left met: the chord of a curved object, no second face
    same = _face(B, A, -90.0 + math.degrees(math.atan2(3.0, 42.0)))
    out = _out(block)
    out.touches += _presses(same)
    assert guard_done(cfg, out, out.touches[1:], settings) is None
    # a left pad on a hyperbola's vertex: no straight side, the guard goes on
    out = _out(_hyperbola())
    out.touches += _presses(bottom)
    assert guard_done(cfg, out, out.touches[1:], settings) is None


def _cubical_block(k: float = 1.5, at=(118.3472, -16.5)) -> np.ndarray:
    """config/scenes/cubical_parabola.yaml's object scaled k times ((t, a t³ + c t), a = 0.0008 / k²,
    c = −0.5, t in [−24k, 2k], closed by three segments through (2k, −20k) and (−24k, −20k)), turned
    −90° so its curved part faces +x, away from both pads, and its two side faces (closing segments)
    face them: sampled 0.01 mm apart."""
    a, c = 0.0008 / k**2, -0.5
    t = np.linspace(-24.0 * k, 2.0 * k, 2601)
    arc = np.stack([t, a * t**3 + c * t], axis=1)
    corners = [arc[-1], np.array([2.0 * k, -20.0 * k]), np.array([-24.0 * k, -20.0 * k]), arc[0]]
    canonical = np.concatenate([arc, *(np.linspace(p, q, 3001) for p, q in zip(corners, corners[1:]))])
    return np.stack([canonical[:, 1], -canonical[:, 0]], axis=1) + at  # turned −90°, moved


def test_a_second_straight_face_beside_a_curve_beyond_its_corner():
    """A cubical block closed by three segments (the bench's cubical objects are): the right pad's
    presses seat on one side face, the left's lines met the other side face and the corner (119.8,
    19.5) mm where the curved part begins (its normal cone 41.4°–90°: rolls at pad normals −100°,
    −115° as tactile demo --config config/jaw-p.yaml ran it). Two straight faces prove no polygon
    here; the guard ends there (the demo's answer, line, is the same without it: no pad reaches
    the curved part's normals below 41.4°). A roll turned past the corner's cone meets the curve,
    a line through neither support: the guard goes on."""
    cfg = load_config("config/jaw-p.yaml")
    settings = ExploreSettings.from_profile("balanced")
    block = _cubical_block()
    corner = np.array([118.3472 + 0.0008 / 1.5**2 * (-36.0) ** 3 + 18.0, 19.5])
    out = _out(block, probes=(-100.0, -90.0, -80.0), rolls=(-100.0, -115.0))
    side = straight_side(out, "left", PAD_MM, math.radians(-90.0))
    assert side is not None and min(np.linalg.norm(x - corner) for x in side) < 0.05
    right_face = _face((88.35, -19.5), (116.86, -19.5), 90.0)
    out.touches += _presses(right_face)
    why = guard_done(cfg, out, out.touches[2:], settings)
    assert why is not None and "straight face" in why
    out = _out(block, probes=(-100.0, -90.0, -80.0), rolls=(-100.0, -115.0, -150.0))
    out.touches += _presses(right_face)
    assert guard_done(cfg, out, out.touches[3:], settings) is None
