"""tactile_jaw.envelope._propagate's Jacobian is analytic (the least-squares fit of the support
values differentiated in its pad lines, the lines in the joint angles and the geometry): it is
checked here against central differences of the fit itself, every output (κ, κ_s, ρ at the
middle sample, each contact's x, y, ψ) in every joint angle of every reading, every joint's
offset and every link length and the pad offset, on rolls of a hyperbola's arm at every
degree the order rule weighs, and on a 33-line scan at degree 12 (a flat press's, whose runs
tactile_jaw.pipeline._passing_runs fits by the dozen: the differences took 4n + 1 fits per
degree, 14 min of CPU in one search on P semicubical 126 of finite seed 227); it costs one fit."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from hand_driver import kinematics as kin
from recognizer.scene import load_scene
from tactile_jaw.envelope import JointNoise, _propagate, degrees
from tests.tactile_jaw.test_envelope_order import FINE, LEFT, roll, support_point

H_RAD, H_MM = 1e-7, 1e-4  # steps of the reference differences (their error: ~1e-6 of a row)
HYPERBOLA = load_scene(Path("config/scenes/hyperbola.yaml")).object
NOISE = JointNoise((1e-5, 2e-5), offset_rad=(3e-4, 5e-4), link_mm=(2e-4, 3e-4), pad_mm=5e-4)


def _outputs(finger, q, origin, degree):
    line = kin.finger_pad_line(finger, q)
    c = kin.touch_from_pad_lines(line.psi, line.d, origin=origin, degree=degree)
    m = c.x.size // 2
    return np.concatenate(([1.0 / c.rho[m], -c.rho_psi[m] / c.rho[m] ** 3, c.rho[m]], c.x, c.y, c.psi))


def _moved(finger, which: str, h: float):
    if which == "pad":
        return replace(finger, pad=replace(finger.pad, offset_mm=finger.pad.offset_mm + h))
    k = int(which)
    joints = list(finger.joints)
    joints[k] = replace(joints[k], link_mm=joints[k].link_mm + h)
    return replace(finger, joints=tuple(joints))


def _reference(finger, q, origin, degree, noise: JointNoise) -> np.ndarray:
    """The noise factor by central differences of the fit (the columns _propagate states)."""
    cols = []
    for j in range(q.size):
        dq = np.zeros(q.size)
        dq[j] = H_RAD
        dq = dq.reshape(q.shape)
        cols.append((_outputs(finger, q + dq, origin, degree) - _outputs(finger, q - dq, origin, degree)) / (2 * H_RAD))
    jac = np.stack(cols, axis=1)
    factor = [jac * np.tile(noise.quantization, q.shape[0])]
    factor.append(jac.reshape(jac.shape[0], q.shape[0], 2).sum(axis=1) * np.asarray(noise.offset_rad))
    for which, sigma in (("0", noise.link_mm[0]), ("1", noise.link_mm[1]), ("pad", noise.pad_mm)):
        plus, minus = _moved(finger, which, H_MM), _moved(finger, which, -H_MM)
        cols = (_outputs(plus, q, origin, degree) - _outputs(minus, q, origin, degree)) / (2 * H_MM)
        factor.append(sigma * cols[:, None])
    return np.hstack(factor)


def _check(q, degree):
    line = kin.finger_pad_line(LEFT, q)
    origin = kin.touch_from_pad_lines(line.psi, line.d).origin
    _, factor = _propagate(LEFT, q, origin, degree, NOISE)
    reference = _reference(LEFT, q, origin, degree, NOISE)
    assert factor.shape == reference.shape
    # each output's row to 1e-5 of its largest entry: at a step of 1e-6 rad the differences
    # are off by up to 2e-5 (truncation, ∝ h²), at 1e-7 by ~1e-6 (rounding)
    scale = np.max(np.abs(reference), axis=1, keepdims=True)
    worst = np.max(np.abs(factor - reference) / scale, axis=1)
    assert np.max(worst) < 1e-5, worst
    assert np.all(np.isfinite(factor))


@pytest.mark.parametrize("centre_deg", [-118.0, -67.0])
def test_the_analytic_noise_factor_matches_central_differences_on_a_hyperbola(centre_deg):
    rng = np.random.default_rng(5)
    psis = np.radians(np.linspace(centre_deg - 9.0, centre_deg + 9.0, 11))
    q = roll(lambda p: support_point(HYPERBOLA, p), psis, FINE, rng)
    for degree in degrees(q.shape[0]):
        _check(q, degree)


def test_the_analytic_noise_factor_matches_on_a_long_scan_at_a_high_degree():
    rng = np.random.default_rng(7)
    psis = np.radians(np.linspace(-127.0, -109.0, 33))
    q = roll(lambda p: support_point(HYPERBOLA, p), psis, FINE, rng)
    _check(q, 12)


def test_a_wrong_jacobian_fails_the_check():
    """The check can fail: a factor with one reading's joints swapped is far off."""
    rng = np.random.default_rng(5)
    q = roll(lambda p: support_point(HYPERBOLA, p), np.radians(np.linspace(-127.0, -109.0, 9)), FINE, rng)
    line = kin.finger_pad_line(LEFT, q)
    origin = kin.touch_from_pad_lines(line.psi, line.d).origin
    _, factor = _propagate(LEFT, q, origin, 4, NOISE)
    reference = _reference(LEFT, q, origin, 4, NOISE)
    factor[:, [0, 1]] = factor[:, [1, 0]]
    assert np.max(np.abs(factor - reference)) > 1e-2 * np.max(np.abs(reference))


def test_the_noise_factor_costs_one_fit(monkeypatch):
    """One envelope fit per degree, not one per differenced joint angle (4n + 1 before)."""
    rng = np.random.default_rng(5)
    q = roll(lambda p: support_point(HYPERBOLA, p), np.radians(np.linspace(-127.0, -109.0, 9)), FINE, rng)
    line = kin.finger_pad_line(LEFT, q)
    origin = kin.touch_from_pad_lines(line.psi, line.d).origin
    calls = []
    fit = kin.touch_from_pad_lines
    monkeypatch.setattr(kin, "touch_from_pad_lines", lambda *a, **k: calls.append(1) or fit(*a, **k))
    _propagate(LEFT, q, origin, 4, NOISE)
    assert len(calls) == 1
