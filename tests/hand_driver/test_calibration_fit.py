"""Calibration fit on synthetic readings: exact contacts of a perturbed 'truth' jaw on a
disk, quantized to ticks; recovery, residuals, and refusals."""

from __future__ import annotations

import dataclasses
import functools
import json
from pathlib import Path

import numpy as np
import pytest

from hand_driver import calibration_fit as cal
from hand_driver import calibration_plan as cp
from hand_driver import kinematics as kin
from hand_driver.config import load_config, perturbed as perturbed_config
from recognizer.curves import Pose
from recognizer.scene import SceneObject, load_scene

CFG = load_config("config/jaw.yaml")
DISK = SceneObject("circle", {"r": 20.0}, Pose(0.0, 0.0, 0.0), "left")


def perturbed(seed: int):
    rng = np.random.default_rng(seed)
    return perturbed_config(CFG, rng), rng


@functools.cache
def plan_at(x: float, y: float) -> tuple:
    return tuple(cp.plan_touches(CFG, DISK, (x, y), faces=10, corners=6))


def readings_for(truth, rng, placements=cp.DEFAULT_PLACEMENTS, kinds=("face", "corner", "heel")):
    """Synthetic readings of the nominal plan; each disk is off its expected place by ±3 mm."""
    out = []
    for k, (x, y) in enumerate(placements):
        disk = dataclasses.replace(DISK, pose=Pose(0.0, x + rng.uniform(-3, 3), y + rng.uniform(-3, 3)))
        plan = [t for t in plan_at(x, y) if t.kind in kinds]
        out += cp.synthesize(truth, disk, plan, placement=k)
    return out


@pytest.mark.parametrize("seed", [1, 2])
def test_fit_recovers_truth_within_a_tick_and_a_tenth_of_a_mm(seed):
    truth, rng = perturbed(seed)
    result = cal.fit(CFG, DISK, readings_for(truth, rng))
    err = cal.pack_params(result.config) - cal.pack_params(truth)
    for e, d in zip(result.estimates, err):
        limit = 1.0 if e.kind == "zero_tick" else 0.1
        assert abs(d) <= limit, f"{e.name}: error {d:+.3f}, se {e.se:.3f}"
        assert abs(d) <= 4.0 * e.se + 1e-9  # the reported uncertainty is honest
    assert result.rms_before_mm > 10 * result.rms_after_mm
    assert result.rms_after_mm < 0.06  # quantization only
    assert len(result.reference_poses) == len(cp.DEFAULT_PLACEMENTS)


def test_exact_readings_give_exact_parameters():
    truth, rng = perturbed(3)
    readings = []
    for k, (x, y) in enumerate(cp.DEFAULT_PLACEMENTS):
        disk = dataclasses.replace(DISK, pose=Pose(0.0, x + 1.0, y - 1.0))
        readings += cp.synthesize(truth, disk, list(plan_at(x, y)), quantize=False, placement=k)
    result = cal.fit(CFG, DISK, readings)
    assert cal.pack_params(result.config) == pytest.approx(cal.pack_params(truth), abs=1e-5)
    assert result.rms_after_mm < 1e-6


def test_face_touches_alone_cannot_see_the_distal_links():
    truth, rng = perturbed(4)
    with pytest.raises(cal.CalibrationRefused, match=r"joint[24]\.link_mm.*corner touches"):
        cal.fit(CFG, DISK, readings_for(truth, rng, kinds=("face",)))


def test_one_finger_cannot_fix_its_base_joint_zero():
    """A finger turning about its base with the disk: the same readings (a symmetry)."""
    truth, rng = perturbed(5)
    readings = [r for r in readings_for(truth, rng, placements=cp.DEFAULT_PLACEMENTS[:1]) if r.finger == "left"]
    with pytest.raises(cal.CalibrationRefused, match="cannot determine|only to"):
        cal.fit(CFG, DISK, readings)


def test_too_few_readings_refused():
    truth, rng = perturbed(6)
    with pytest.raises(cal.CalibrationRefused, match="unknowns") as info:
        cal.fit(CFG, DISK, readings_for(truth, rng)[:8])
    assert "\n" not in str(info.value)


def test_pad_end_contacts_reported_as_face_touches_are_reclassified():
    """A face approach whose tangent point lies off the pad makes the pad end touch (the
    pad line then cuts the disk: residual ≫ quantization). Mislabel three end contacts as
    'face': the screen must find them all, and the fit must be as good as with labels."""
    truth, rng = perturbed(7)
    readings = readings_for(truth, rng)
    ends = [i for i, r in enumerate(readings) if r.kind in ("corner", "heel")][:6:2]
    wrong = [dataclasses.replace(r, kind="face") if i in ends else r for i, r in enumerate(readings)]
    result = cal.fit(CFG, DISK, wrong)
    assert result.n_reclassified == 3 and result.n_dropped == 0
    reference = cal.fit(CFG, DISK, readings)
    assert cal.pack_params(result.config) == pytest.approx(cal.pack_params(reference.config), abs=1e-6)


def test_a_reading_no_contact_explains_is_dropped():
    truth, rng = perturbed(8)
    readings = readings_for(truth, rng)
    bad = readings[5]
    readings[5] = dataclasses.replace(bad, ticks=(bad.ticks[0] + 30.0, bad.ticks[1]))
    result = cal.fit(CFG, DISK, readings)
    assert result.n_dropped == 1 and result.n_readings == len(readings) - 1
    err = cal.pack_params(result.config) - cal.pack_params(truth)
    for e, d in zip(result.estimates, err):
        assert abs(d) <= (1.0 if e.kind == "zero_tick" else 0.1), f"{e.name}: error {d:+.3f}"


def test_backlash_fit_on_exact_p_series_readings():
    """Exact, quantized readings of config/jaw-p-truth.yaml (0.1° band, zero errors of 0.06–0.12°),
    each encoder half a band off its link toward the touch's load (calibration_plan.synthesize):
    the backlash fit recovers every band within 0.005° and every zero under the working load
    within 3 ticks (0.001°) (the plain fit's bias: tests/tools/test_calibration_emulated.py)."""
    nominal, truth = load_config("config/jaw-p.yaml"), load_config("config/jaw-p-truth.yaml")
    rng = np.random.default_rng(1)
    readings = []
    for k, (x, y) in enumerate(cp.DEFAULT_PLACEMENTS):
        disk = dataclasses.replace(DISK, pose=Pose(0.0, x + rng.uniform(-3, 3), y + rng.uniform(-3, 3)))
        readings += cp.synthesize(truth, disk, cp.plan_touches(nominal, DISK, (x, y), faces=6, corners=4),
                                  placement=k)
    result = cal.fit(nominal, DISK, readings, backlash=True)
    assert all(band for *_, band in result.loads) and result.n_dropped == 0
    for j, got in zip(truth.joints, result.config.joints):
        assert abs(got.zero_tick - j.zero_tick) <= 3.0 and abs(got.backlash_deg - j.backlash_deg) <= 0.005


def test_backlash_is_modelled_by_default_where_a_model_states_a_band():
    # DYNAMIXEL-P: 0.1° = 279 PH54 ticks; XM430: 0.25°, under 3 of its ticks, still biases the fit
    assert cal.backlash_matters(load_config("config/jaw-p.yaml"))
    assert cal.backlash_matters(load_config("config/jaw.yaml"))


def _x_readings(truth, seed: int):
    rng = np.random.default_rng(seed)
    readings = []
    for k, (x, y) in enumerate(cp.DEFAULT_PLACEMENTS):
        disk = dataclasses.replace(DISK, pose=Pose(0.0, x + rng.uniform(-3, 3), y + rng.uniform(-3, 3)))
        readings += cp.synthesize(truth, disk, plan_at(x, y), placement=k)
    return readings


@pytest.mark.parametrize("band", [0.25, 0.12])
def test_x_series_calibration_covers_the_truth_under_its_backlash(band):
    """config/jaw-truth.yaml (the XM430's band, zero errors of 0.06–0.12°), its band as stated
    (0.25°) or half of it: the default fit (the stated band modelled: the readings' loads, each
    distal band, which 2–6 readings against the working load cannot fix, held to the stated
    0.25° ± 0.125°) has every zero tick, link and pad offset within 3 standard errors of the
    truth. Without the band the links came out 4–6 standard errors off (10–13 in this plan)."""
    truth = load_config("config/jaw-truth.yaml")
    truth = dataclasses.replace(truth, fingers=tuple(
        dataclasses.replace(f, joints=tuple(dataclasses.replace(j, backlash_deg=band) for j in f.joints))
        for f in truth.fingers))
    result = cal.fit(CFG, DISK, _x_readings(truth, 1), backlash=cal.backlash_matters(CFG))
    err = cal.pack_params(result.config) - cal.pack_params(truth)
    for e, d in zip(result.estimates, err):
        assert abs(d) <= 3.0 * e.se, f"{e.name}: error {d:+.3f}, se {e.se:.3f}"
    bands = [e for e in result.estimates if e.kind == "backlash_deg"]
    assert len(bands) == 4 and all(e.se <= 0.5 * 0.25 + 1e-9 for e in bands)


def test_zero_sigma_holds_the_spread_over_placements():
    """``zero_sigma_deg`` (what the exploration states as a joint's offset over a touch) is the
    larger of a zero tick's standard error and its jackknife spread over the placements
    (calibration_fit._placement_spread): the spread is computed (4 placements), of the order
    of the standard error on quantized readings, and raising it is what the config holds.
    A placement whose disk sat elsewhere than its readings say (one placement's readings
    synthesized 0.05 mm off the radius: a systematic no quantization model covers) makes the
    spread, not the standard error, cover the zero ticks' error, and the same for the links'
    ``link_sigma_mm`` and the pads' ``offset_sigma_mm``."""
    truth, rng = perturbed(3)
    readings = readings_for(truth, rng)
    result = cal.fit(CFG, DISK, readings)
    se = {e.name: e.se for e in result.estimates}
    sigma = {f"{f.name}.joint{j.id}.zero_tick": j.zero_sigma_deg * j.ticks_per_rev / 360.0
             for f in result.config.fingers for j in f.joints}
    for name, s in sigma.items():
        assert s >= se[name] - 1e-12 and s < 6.0 * se[name], (name, s, se[name])
    assert any(s > se[name] * 1.0001 for name, s in sigma.items())  # the spread was used somewhere
    skewed = [r for r in readings if r.placement != 2]
    disk = dataclasses.replace(DISK, params={"r": 20.05}, pose=Pose(0.0, 65.0, 30.0))
    skewed += cp.synthesize(truth, disk, list(plan_at(65.0, 30.0)), placement=2)
    off = cal.fit(CFG, DISK, skewed, tolerances={"zero_tick": 99.0, "link_mm": 99.0, "offset_mm": 99.0})
    err = cal.pack_params(off.config) - cal.pack_params(truth)
    zeros = [(e, d) for e, d in zip(off.estimates, err) if e.kind == "zero_tick"]
    stated = {f"{f.name}.joint{j.id}.zero_tick": j.zero_sigma_deg * j.ticks_per_rev / 360.0
              for f in off.config.fingers for j in f.joints}
    assert max(abs(d) / e.se for e, d in zeros) > 3.0  # the standard errors miss the systematic
    assert all(abs(d) <= 3.0 * stated[e.name] for e, d in zeros), [(e.name, d, stated[e.name]) for e, d in zeros]
    # the links and pads the same way (what the exploration states for them: envelope.joint_noise)
    geometry = {f"{f.name}.joint{j.id}.link_mm": j.link_sigma_mm for f in off.config.fingers for j in f.joints}
    geometry.update({f"{f.name}.pad.offset_mm": f.pad.offset_sigma_mm for f in off.config.fingers})
    fitted = [(e, d) for e, d in zip(off.estimates, err) if e.kind in ("link_mm", "offset_mm")]
    assert max(abs(d) / e.se for e, d in fitted) > 3.0  # the standard errors miss here too (4.0 on the right pad)
    assert all(geometry[e.name] >= e.se - 1e-15 for e, _ in fitted)
    assert all(abs(d) <= 3.0 * geometry[e.name] for e, d in fitted), [(e.name, d, geometry[e.name]) for e, d in fitted]
    two = cal.fit(CFG, DISK, [r for r in readings if r.placement < 2],
                  tolerances={"zero_tick": 99.0, "link_mm": 99.0, "offset_mm": 99.0})
    for f in two.config.fingers:
        for j in f.joints:  # two placements: no spread, the standard error alone
            e = next(e for e in two.estimates if e.name == f"{f.name}.joint{j.id}.zero_tick")
            assert j.zero_sigma_deg == pytest.approx(e.se * 360.0 / j.ticks_per_rev)
            link = next(e for e in two.estimates if e.name == f"{f.name}.joint{j.id}.link_mm")
            assert j.link_sigma_mm == pytest.approx(link.se)



def test_a_parameter_few_readings_fix_carries_their_scatter():
    """calibration_fit.standard_errors on a linear fit whose columns are its parameters: 130
    readings of unit σ fix a, 4 more fix b (a + b) but scatter 10× wider. The pooled χ²/dof
    held b to ~1.2 (its true deviation 10/√4 = 5); the leave-one-out sandwich gives it, and
    leaves a at its quantization-model value where its readings are as modelled."""
    rng = np.random.default_rng(3)
    jac = np.zeros((134, 2))
    jac[:, 0] = 1.0
    jac[130:, 1] = 1.0
    noise = np.concatenate([rng.normal(0.0, 1.0, 130), rng.normal(0.0, 10.0, 4)])
    fun = noise - jac @ np.linalg.lstsq(jac, noise, rcond=None)[0]
    u, s, vt = np.linalg.svd(jac, full_matrices=False)
    se = cal.standard_errors(u, s, vt, fun, 0)
    assert se[0] == pytest.approx(1.0 / np.sqrt(130), rel=0.25)
    assert 2.5 < se[1] < 10.0
    pooled = np.sqrt(float(fun @ fun) / 132 * (1.0 / 4 + 1.0 / 130))
    assert pooled < 2.0  # what the pooled variance factor said


@functools.cache
def _p_readings_1006() -> tuple:
    path = Path(__file__).parent / "data" / "p_calibration_1006.json"
    return tuple(cal.Reading(f, kind, (t1, t2), pl) for f, kind, pl, t1, t2 in json.loads(path.read_text())["readings"])


def test_emulated_p_calibration_states_what_its_readings_leave():
    """The emulated bus's readings of calibration-only seed 1006 (config/jaw-p.yaml against
    config/jaw-p-truth.yaml, bench_explore's calibration): pad-end touches the fit judges
    loaded against a joint's working load read the gear on its working side (a pad end's force
    is not known to lie along the disk's normal), and what the screen keeps of them left χ²/dof
    17: the pooled standard errors put zero ticks 6.1, pads 4.1, bands 4.0 of them off the
    truth. Each parameter's standard error now carries the scatter of the readings that fix it:
    every one within 3 of the truth."""
    nominal, truth = load_config("config/jaw-p.yaml"), load_config("config/jaw-p-truth.yaml")
    disk = load_scene("config/scenes/calibration.yaml").object
    loose = {"zero_tick": 99.0, "link_mm": 99.0, "offset_mm": 99.0, "backlash_deg": 99.0}
    result = cal.fit(nominal, disk, list(_p_readings_1006()), tolerances=loose, backlash=True)
    bands = tuple(k for k, (*_, fitted) in enumerate(result.loads) if fitted)
    assert len(bands) == 4
    err = cal.pack_params(result.config, bands) - cal.pack_params(truth, bands)
    for e, d in zip(result.estimates, err):
        assert abs(d) <= 3.0 * e.se, f"{e.name}: error {d:+.4g}, se {e.se:.3g}"


def test_readings_the_contact_model_does_not_explain_do_not_pull_the_screen():
    """The emulated bus's readings of development seed 563 (bench_explore --calibrate, the same
    calibration as 1006's): 10 of 132 lie 5–80 µm off the truth geometry (a face touch whose
    tangent point lies off its pad, heels, faces), every other within 0.5 µm. Screened on a plain
    fit, worst first, they pulled it and good readings were dropped in their place: zero ticks
    +13.1 and +17.8 off, pads +13.6 and +14.2 µm (3.0 standard errors), pad σ 9 µm, rms 0.71 µm.
    Screened on a robust fit (``ROBUST_Z``): every zero within 1 tick, every pad within 1 µm."""
    nominal, truth = load_config("config/jaw-p.yaml"), load_config("config/jaw-p-truth.yaml")
    disk = load_scene("config/scenes/calibration.yaml").object
    path = Path(__file__).parent / "data" / "p_calibration_563.json"
    readings = [cal.Reading(f, kind, (t1, t2), pl) for f, kind, pl, t1, t2 in json.loads(path.read_text())["readings"]]
    loose = {"zero_tick": 99.0, "link_mm": 99.0, "offset_mm": 99.0, "backlash_deg": 99.0}
    result = cal.fit(nominal, disk, readings, tolerances=loose, backlash=True)
    bands = tuple(k for k, (*_, fitted) in enumerate(result.loads) if fitted)
    err = cal.pack_params(result.config, bands) - cal.pack_params(truth, bands)
    for e, d in zip(result.estimates, err):
        assert abs(d) <= 3.0 * e.se, f"{e.name}: error {d:+.4g}, se {e.se:.3g}"
        if e.kind == "zero_tick":
            assert abs(d) <= 1.0, f"{e.name}: {d:+.2f} ticks"
        if e.kind == "offset_mm":
            assert abs(d) <= 1e-3, f"{e.name}: {d * 1e3:+.2f} µm"
    assert all(f.pad.offset_sigma_mm <= 2e-3 for f in result.config.fingers)
    assert result.rms_after_mm < 3e-4 and result.n_readings >= 120


def _yielding_p_readings(compliance_deg_per_nm: float, compliance_mm_per_n: float) -> tuple:
    """Synthetic readings (calibration_plan.synthesize with forces) of the P-series jaw with
    config/jaw-p-truth.yaml's zero errors, no backlash, and the given compliance of every joint
    and pad: 3 face and 2 pad-end touches per finger, branch and the first two default placements
    (fewer than the placements' jackknife needs: not run, the test's CPU ~1 s), each pressed
    with 3–30 N; the truth and the readings, which carry their joints' balance currents."""
    nominal = load_config("config/jaw-p.yaml")
    truth = load_config("config/jaw-p-truth.yaml")
    truth = dataclasses.replace(truth, fingers=tuple(dataclasses.replace(
        f, joints=tuple(dataclasses.replace(j, backlash_deg=0.0, compliance_deg_per_nm=compliance_deg_per_nm)
                        for j in f.joints),
        pad=dataclasses.replace(f.pad, compliance_mm_per_n=compliance_mm_per_n)) for f in truth.fingers))
    rng = np.random.default_rng(1)
    readings = []
    for k, (x, y) in enumerate(cp.DEFAULT_PLACEMENTS[:2]):
        disk = dataclasses.replace(DISK, pose=Pose(0.0, x + rng.uniform(-3, 3), y + rng.uniform(-3, 3)))
        plan = cp.plan_touches(nominal, DISK, (x, y), faces=3, corners=2)
        readings += cp.synthesize(truth, disk, plan, placement=k, forces_n=rng.uniform(3.0, 30.0, len(plan)))
    return nominal, truth, readings


def test_the_fits_yielding_pad_lines_are_the_explorations():
    """One model of a yielding jaw (kinematics.yield_turns): the fit's pad lines of readings with
    their joints' torques and force (ContactModel.lines, 7 columns) are where the exploration puts
    the pad of a jaw with those parameters (its encoders' angles less kinematics.compliance_turns),
    to 1e-12 (mm, rad) on random readings of both fingers, 0.02°/N·m and 0.002 mm/N."""
    truth = load_config("config/jaw-p-truth.yaml")
    truth = dataclasses.replace(truth, fingers=tuple(dataclasses.replace(
        f, joints=tuple(dataclasses.replace(j, backlash_deg=0.0, compliance_deg_per_nm=0.02) for j in f.joints),
        pad=dataclasses.replace(f.pad, compliance_mm_per_n=0.002)) for f in truth.fingers))
    model = cal.ContactModel(truth, DISK, [], compliance=True)
    v = cal.pack_params(truth, compliance=True)
    rng = np.random.default_rng(3)
    for fi, f in enumerate(truth.fingers):
        ticks = kin.angles_to_ticks(f.joints, rng.uniform(-0.6, 0.6, (40, 2)))
        torques, force = rng.uniform(-3.0, 3.0, (40, 2)), rng.uniform(0.0, 30.0, 40)
        fitted = model.lines(v, fi, np.hstack([ticks, np.zeros((40, 2)), torques, force[:, None]]))
        q = kin.ticks_to_angles(f.joints, ticks)
        explored = kin.finger_pad_line(f, q - kin.compliance_turns(f, q, torques, force))
        assert np.max(np.abs(kin.compliance_turns(f, q, torques, force))) > 1e-3  # yields measurably
        assert np.allclose(fitted.psi, explored.psi, rtol=0.0, atol=1e-12)
        assert np.allclose(fitted.d, explored.d, rtol=0.0, atol=1e-12)


def test_compliance_is_fitted_from_each_readings_own_currents():
    """A jaw whose links yield 0.02°/N·m and pads 0.002 mm/N (3–30 N presses: 8–140 µm of give,
    up to 70 µm of link deflection at the pad, where a reading's quantization σ is 0.1–0.3 µm):
    each reading's link angles are its encoders' less c·τ and its pad k·F behind its line, τ = Kt·I
    and F from its own currents. The fit keeps 47 of 48 readings and puts every parameter, c and k
    included, within 3 standard errors of the truth (1.3 at worst; on all four placements 85 of 88) (the rigid fit of such readings left 66 of 88
    out and the kept ones up to 127 standard errors off)."""
    nominal, truth, readings = _yielding_p_readings(0.02, 0.002)
    assert all(r.current_ma is not None for r in readings)
    result = cal.fit(nominal, DISK, readings)
    assert result.n_dropped <= 3
    err = cal.pack_params(result.config, compliance=True) - cal.pack_params(truth, compliance=True)
    assert [e.kind for e in result.estimates][-6:] == ["compliance_deg_per_nm"] * 4 + ["compliance_mm_per_n"] * 2
    for e, d in zip(result.estimates, err):
        assert abs(d) <= 3.0 * e.se, f"{e.name}: error {d:+.3g}, se {e.se:.3g}"
    assert result.config.joints[0].compliance_deg_per_nm == pytest.approx(0.02, rel=0.1)
    assert result.config.fingers[0].pad.compliance_mm_per_n == pytest.approx(0.002, rel=0.1)
    # their standard errors written for the exploration's stated noise (tactile_jaw.envelope.joint_noise)
    se = {e.name: e.se for e in result.estimates}
    for f in result.config.fingers:
        for j in f.joints:
            assert j.compliance_sigma_deg_per_nm >= se[f"{f.name}.joint{j.id}.compliance_deg_per_nm"] > 0.0
        assert f.pad.compliance_sigma_mm_per_n >= se[f"{f.name}.pad.compliance_mm_per_n"] > 0.0


def test_a_rigid_jaws_readings_with_currents_calibrate_as_without():
    """No compliance in the truth: the compliance fit finds no c or k beyond 3 standard errors, and
    the rigid fit is kept, the same result as from the readings without their currents."""
    nominal, truth, readings = _yielding_p_readings(0.0, 0.0)
    result = cal.fit(nominal, DISK, readings)
    assert not any(e.kind.startswith("compliance") for e in result.estimates)
    assert result == cal.fit(nominal, DISK, [dataclasses.replace(r, current_ma=None) for r in readings])
