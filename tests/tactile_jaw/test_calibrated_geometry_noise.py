"""What a calibration leaves uncertain in a finger's geometry enters each touch's stated noise
(tactile_jaw.envelope.joint_noise, _propagate): a calibrated pad offset or link length is off
by the same amount over a touch, one column of the touch's noise factor each. Checked against
exact geometry: a pad offset moves every contact along its pad's normal by the offset's error
(the envelope of the pad lines moves parallel to itself), so a sample's deviation across its
pad line grows to √(σ_q² + σ_pad²); a base link longer by h moves the distal joint, and so every
pad line, by h along the base link, so every contact by h·(e1·n) across its line. On the
P-series jaw (config/jaw-p.yaml calibrated against config/jaw-p-truth.yaml, bench_explore's
calibration, dev seed 11) both pads came out 0.6–0.7 µm off, 3–7 times a sample's deviation
across its line (0.1–0.27 µm), and were stated nowhere."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from hand_driver import kinematics as kin
from hand_driver.config import dump_config, load_config
from hand_driver.units import rad_per_tick
from recognizer.scene import load_scene
from tactile_jaw.envelope import JointNoise, fit_envelope, joint_noise
from tests.tactile_jaw.test_envelope_order import FINE, LEFT, roll, support_point

TICKS = tuple(float(rad_per_tick(t)) for t in kin.resolutions(LEFT.joints))
HYPERBOLA = load_scene(Path("config/scenes/hyperbola.yaml")).object


def _fit(noise: JointNoise, centre_deg: float = -118.0):
    rng = np.random.default_rng(3)
    psis = np.radians(np.linspace(centre_deg - 9.0, centre_deg + 9.0, 9))
    q = roll(lambda p: support_point(HYPERBOLA, p), psis, FINE, rng)
    return fit_envelope(LEFT, q, kin.finger_pad_line(LEFT, q), noise=noise), q


@pytest.mark.parametrize("centre_deg", [-118.0, -67.0])
def test_a_pad_offsets_uncertainty_moves_every_contact_across_its_line(centre_deg):
    plain, _ = _fit(JointNoise(TICKS), centre_deg)
    sigma = 0.0005  # mm, a calibrated pad offset's spread on the P-series jaw
    fit, _ = _fit(JointNoise(TICKS, pad_mm=sigma), centre_deg)
    assert fit.noise_factor.shape[1] == plain.noise_factor.shape[1] + 1
    np.testing.assert_allclose(fit.sigma_across**2 - plain.sigma_across**2, sigma**2, rtol=1e-4)
    np.testing.assert_allclose(fit.sigma_along, plain.sigma_along, rtol=1e-4)  # nothing along the line
    # the parallel curve: ρ moves by the offset, κ by κ²·σ (a relative 1e-5 here), κ_s by 3κκ_s·σ
    k, ks = fit.kappa, fit.kappa_s
    added = np.diag(fit.cov - plain.cov)
    np.testing.assert_allclose(added, [(k * k * sigma) ** 2, (3.0 * k * ks * sigma) ** 2], rtol=1e-2, atol=1e-22)


def test_a_base_links_uncertainty_moves_every_contact_along_that_link():
    plain, q = _fit(JointNoise(TICKS))
    sigma = 0.0004
    fit, _ = _fit(JointNoise(TICKS, link_mm=(sigma, 0.0)))
    order = fit.contacts.order
    a1 = LEFT.base.angle + q[order, 0]
    normal = np.stack([np.cos(fit.contacts.psi), np.sin(fit.contacts.psi)], axis=-1)
    shift = sigma * (np.cos(a1) * normal[:, 0] + np.sin(a1) * normal[:, 1])  # h·(e1·n)
    np.testing.assert_allclose(fit.sigma_across**2 - plain.sigma_across**2, shift**2, rtol=1e-3, atol=1e-14)


def test_a_calibrated_config_states_its_geometry_and_reads_back(tmp_path):
    """joint_noise takes the calibrated config's ``link_sigma_mm`` and ``pad.offset_sigma_mm``;
    the config writes and reads them back (none written for an uncalibrated config)."""
    cfg = load_config("config/jaw-p.yaml")
    assert joint_noise(cfg.finger("left")) == JointNoise(joint_noise(cfg.finger("left")).tick_rad)
    calibrated = replace(cfg, fingers=tuple(
        replace(f, joints=tuple(replace(j, link_sigma_mm=0.0002 * (i + 1)) for i, j in enumerate(f.joints)),
                pad=replace(f.pad, offset_sigma_mm=0.0005)) for f in cfg.fingers))
    noise = joint_noise(calibrated.finger("right"))
    assert noise.link_mm == pytest.approx((0.0002, 0.0004)) and noise.pad_mm == pytest.approx(0.0005)
    out = tmp_path / "calibrated.yaml"
    dump_config(calibrated, out, source="config/jaw-p.yaml")
    assert load_config(out) == calibrated
    text = out.read_text()
    assert "offset_sigma_mm: 0.0005" in text and "link_sigma_mm" in text
    dump_config(cfg, tmp_path / "plain.yaml")
    assert "sigma" not in (tmp_path / "plain.yaml").read_text()
