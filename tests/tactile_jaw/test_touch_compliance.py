"""tactile_jaw.pipeline.touch_compliance and tactile_jaw.envelope.joint_noise: a roll of the
P-series jaw's left pad on an exact circle, its readings made by a jaw that yields (each link
c·τ behind its encoder, the pad's face k·F in: kinematics.compliance_turns) and carrying the
joints' Present Currents quantized to the P-series' 1 mA: felt with the compliance the config
declares, the contacts are on the circle within their stated deviation; felt as rigid, they
are not; a compliance known to its standard error only is stated in the deviations."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from hand_driver import kinematics as kin
from hand_driver.config import dump_config, load_config
from hand_driver.motion import Sample, TouchResult
from tactile_jaw.pipeline import feel

RIGID = load_config("config/jaw-p.yaml")
CENTRE, RADIUS = np.array([115.0, 0.0]), 20.0
C_DEG_PER_NM, K_MM_PER_N = 0.02, 0.002  # config/jaw-p.yaml's jaw at the first round's synthetic truth


def yielding(cfg, c: float, k: float, c_sigma: float = 0.0, k_sigma: float = 0.0):
    """``cfg`` whose left finger's joints declare compliance c (°/N·m) and pad give k (mm/N)."""
    f = cfg.finger("left")
    joints = tuple(dataclasses.replace(j, compliance_deg_per_nm=c, compliance_sigma_deg_per_nm=c_sigma)
                   for j in f.joints)
    pad = dataclasses.replace(f.pad, compliance_mm_per_n=k, compliance_sigma_mm_per_n=k_sigma)
    left = dataclasses.replace(f, joints=joints, pad=pad)
    return dataclasses.replace(cfg, fingers=tuple(left if g.name == "left" else g for g in cfg.fingers))


TRUTH = yielding(RIGID, C_DEG_PER_NM, K_MM_PER_N)


def pressed_roll(psis, forces, currents: bool = True) -> tuple[TouchResult, np.ndarray]:
    """The left pad rolled on the circle at normals ``psis``, pressing with ``forces`` (N): the
    touch as TRUTH's jaw reads it (ticks rounded, currents to 1 mA) and the true contacts."""
    f = TRUTH.finger("left")
    samples, points = [], []
    for i, (psi, force) in enumerate(zip(psis, forces)):
        point = CENTRE - RADIUS * kin.unit(psi)
        q_link = kin.ik_tangent(f, point, psi)
        torques = kin.moment_arms(f, q_link, point) / 1000.0 * force
        q_enc = q_link
        for _ in range(6):  # the encoders' angles whose links, less the compliance, are q_link
            q_enc = q_link + kin.compliance_turns(f, q_enc, torques, force)
        ticks = np.rint(kin.angles_to_ticks(f.joints, q_enc))
        sign = np.array([j.direction for j in f.joints], dtype=float)
        kt = np.array([j.spec.torque_nm_per_a for j in f.joints])
        amps = tuple(float(a) for a in np.rint(1000.0 * torques / (kt * sign))) if currents else None
        samples.append(Sample(reading=i, psi=float(psi), ticks=ticks,
                              line=kin.finger_pad_line_from_ticks(RIGID, "left", ticks), current_ma=None,
                              robot_time=0.0, joint_current_ma=amps))
        points.append(point)
    return TouchResult("left", 0, float(np.mean(psis)), samples, outcome="ok"), np.array(points)


PSIS = math.radians(-90.0) + np.linspace(-1.0, 1.0, 9) * math.radians(12.0)
FORCES = np.linspace(1.0, 4.0, 9)


def contact_z(cfg) -> np.ndarray:
    """Each felt contact's distance from the circle in its stated deviation across the pad."""
    touch, _ = pressed_roll(PSIS, FORCES)
    felt = feel(cfg, touch, len(PSIS))
    assert felt.problem is None, felt.problem
    off = np.hypot(felt.contacts.x - CENTRE[0], felt.contacts.y - CENTRE[1]) - RADIUS
    return off / felt.fit.sigma_across


def test_declared_compliance_is_taken_out():
    assert np.max(np.abs(contact_z(TRUTH))) < 3.0


def test_rigid_reading_of_a_yielding_jaw_is_off():
    assert np.max(np.abs(contact_z(RIGID))) > 10.0


def test_compliance_standard_error_is_stated():
    """c 20 % high: outside the deviations unless its standard error is stated."""
    high = 1.2 * C_DEG_PER_NM
    assert np.max(np.abs(contact_z(yielding(RIGID, high, K_MM_PER_N)))) > 3.0
    assert np.max(np.abs(contact_z(yielding(RIGID, high, K_MM_PER_N, c_sigma=0.2 * C_DEG_PER_NM)))) < 3.0


def test_give_is_k_times_force_along_the_normal():
    f = TRUTH.finger("left")
    q = kin.ik_tangent(f, CENTRE - RADIUS * kin.unit(PSIS[0]), PSIS[0])
    bare = dataclasses.replace(f, joints=tuple(dataclasses.replace(j, compliance_deg_per_nm=0.0) for j in f.joints))
    before, after = kin.finger_pad_line(f, q), kin.finger_pad_line(f, q - kin.compliance_turns(bare, q, (0.0, 0.0), 3.0))
    assert after.psi == pytest.approx(before.psi, abs=1e-12)
    assert before.d - after.d == pytest.approx(3.0 * K_MM_PER_N, rel=1e-4)  # first order in the turn


def test_compliance_sigmas_are_written_and_read(tmp_path):
    cfg = yielding(RIGID, C_DEG_PER_NM, K_MM_PER_N, c_sigma=0.0015, k_sigma=1e-5)
    dump_config(cfg, tmp_path / "c.yaml", source="config/jaw-p.yaml", header="test")
    back = load_config(tmp_path / "c.yaml").finger("left")
    assert [j.compliance_sigma_deg_per_nm for j in back.joints] == [0.0015, 0.0015]
    assert back.pad.compliance_sigma_mm_per_n == 1e-5


def test_readings_without_currents_are_refused():
    touch, _ = pressed_roll(PSIS, FORCES, currents=False)
    felt = feel(TRUTH, touch, len(PSIS))
    assert felt.problem is not None and "currents" in felt.problem
