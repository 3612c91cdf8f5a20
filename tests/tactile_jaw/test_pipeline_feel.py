"""tactile_jaw.pipeline: a touch felt once (pad lines, envelope, checks) and the envelope's
own curvature with its quantization covariance, against exact tangent lines of a circle
and an ellipse (closed forms)."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from hand_driver import kinematics as kin
from hand_driver.config import load_config
from hand_driver.motion import Sample, TouchResult
from hand_driver.units import rad_per_tick
from recognizer.curves import CURVES, Pose
from recognizer.touches import parse_request
from tactile_common.errors import InputError
from tactile_jaw.envelope import fit_envelope
from tactile_jaw.pipeline import FeltTouch, clear_of_corners, feel, make_recognizer, stated_noise
from tactile_jaw.settings import ExploreSettings, phi_sigma

CONFIG = load_config("config/jaw.yaml")
LEFT = CONFIG.finger("left")
CENTRE = np.array([110.0, 0.0])


def ellipse_tangent_angles(a: float, b: float, psis) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Joint angles putting the left pad on the exact tangent of an axis-aligned ellipse
    (semi-axes a, b, centre CENTRE) for pad normals ψ, the contact points, and the
    ellipse parameter t of each contact."""
    qs, points, ts = [], [], []
    for psi in psis:
        theta = psi + math.pi  # the object's outward normal at the contact
        t = math.atan2(b * math.sin(theta), a * math.cos(theta))
        p = CENTRE + np.array([a * math.cos(t), b * math.sin(t)])
        qs.append(kin.ik_tangent(LEFT, p, psi))
        points.append(p)
        ts.append(t)
    return np.array(qs), np.array(points), np.array(ts)


def test_circle_curvature_is_exact():
    psis = math.radians(-80.0) + np.linspace(-0.15, 0.15, 9)
    q, _, _ = ellipse_tangent_angles(20.0, 20.0, psis)
    fit = fit_envelope(LEFT, q, kin.finger_pad_line(LEFT, q))
    kappa, kappa_s, cov = fit.kappa, fit.kappa_s, fit.cov
    assert kappa == pytest.approx(1.0 / 20.0, rel=1e-5)  # the second pass's centre is 1e-4 mm off
    assert abs(kappa_s) < 1e-9
    assert cov.shape == (2, 2) and np.all(np.linalg.eigvalsh(cov) > 0)


@pytest.mark.parametrize("centre_deg", [-100.0, -85.0, -70.0])
def test_ellipse_curvature_against_closed_form(centre_deg):
    """An 18° roll of 9 exact tangents: the cubic d(ψ) truncates the ellipse's support
    function (its radius of curvature changes by ~25 % over the roll here), so κ is within
    1.5 % and κ_s within 3 % of κ² of the closed forms (eqs. 6, 7; measured: 1.0 %, 2 %)."""
    a, b = 28.0, 17.0
    psis = math.radians(centre_deg) + np.linspace(-1, 1, 9) * math.radians(9.0)
    q, _, ts = ellipse_tangent_angles(a, b, psis)
    fit = fit_envelope(LEFT, q, kin.finger_pad_line(LEFT, q))
    kappa, kappa_s = fit.kappa, fit.kappa_s
    curve = CURVES["ellipse"]({"a": a, "b": b})
    t = ts[len(ts) // 2]
    assert kappa == pytest.approx(float(curve.kappa(t)), rel=1.5e-2)
    assert kappa_s == pytest.approx(float(curve.kappa_s(t)), abs=0.03 * float(curve.kappa(t)) ** 2)


@pytest.mark.parametrize("path", ["config/jaw.yaml", "config/jaw-p.yaml"])
def test_covariance_matches_quantization_scatter(path):
    """The stated covariance is the scatter of κ, κ_s when every joint angle is off by a
    uniform error of up to half a tick of its model (Monte Carlo, 400 draws; X-series, and
    the P-series jaw whose two joints differ in resolution), at the cubic (the order rule
    gives these rolls a cubic but for about 1 draw in 400)."""
    a, b = 28.0, 17.0
    psis = math.radians(-75.0) + np.linspace(-1, 1, 9) * math.radians(9.0)
    q, _, _ = ellipse_tangent_angles(a, b, psis)
    left = load_config(path).finger("left")
    cov = fit_envelope(left, q, kin.finger_pad_line(left, q), degree=3).cov
    rng = np.random.default_rng(3)
    tick = rad_per_tick(kin.resolutions(left.joints))
    draws_q = [q + rng.uniform(-0.5, 0.5, q.shape) * tick for _ in range(400)]
    fits = [fit_envelope(left, qq, kin.finger_pad_line(left, qq), degree=3) for qq in draws_q]
    draws = np.array([(f.kappa, f.kappa_s) for f in fits])
    ratio = draws.std(axis=0) / np.sqrt(np.diag(cov))
    assert np.all((ratio > 0.85) & (ratio < 1.15)), ratio


def touch_from_angles(q, finger: str = "left", outcome: str = "ok") -> TouchResult:
    f = CONFIG.finger(finger)
    samples = []
    for i, qi in enumerate(q):
        ticks = kin.angles_to_ticks(f.joints, qi)
        samples.append(Sample(reading=i, psi=float(kin.finger_pad_line(f, qi).psi), ticks=ticks,
                              line=kin.finger_pad_line_from_ticks(CONFIG, finger, ticks), current_ma=None,
                              robot_time=0.0))
    return TouchResult(finger, 0, float(np.mean([s.psi for s in samples])), samples, outcome=outcome)


def test_feel_a_good_touch_once():
    psis = math.radians(-80.0) + np.linspace(-1, 1, 9) * math.radians(9.0)
    q, points, _ = ellipse_tangent_angles(28.0, 17.0, psis)
    felt = feel(CONFIG, touch_from_angles(q), 9)
    assert felt.problem is None
    np.testing.assert_allclose(np.stack([felt.contacts.x, felt.contacts.y], axis=-1), points, atol=0.1)
    assert felt.samples.curvature is not None and len(felt.pad_segments()) == 9
    assert felt.to_json()["finger"] == "left" and len(felt.to_json()["phi"]) == 9


def test_feel_refuses_too_few_samples():
    psis = math.radians(-80.0) + np.linspace(-1, 1, 2) * math.radians(9.0)
    q, _, _ = ellipse_tangent_angles(28.0, 17.0, psis)
    felt = feel(CONFIG, touch_from_angles(q, outcome="no_contact"), 9)
    assert felt.problem is not None and felt.samples is None and felt.contacts is None


def quantized_touch(contact, psis) -> TouchResult:
    """The left pad on the object's tangent lines of normals ψ through ``contact(ψ)`` (the
    point where the pad meets the object), each reading's joint angles rounded to whole
    ticks as the encoders do."""
    q = np.array([kin.ik_tangent(LEFT, contact(psi), float(psi)) for psi in psis])
    ticks = np.rint(kin.angles_to_ticks(LEFT.joints, q))
    return touch_from_angles(kin.ticks_to_angles(LEFT.joints, ticks))


@pytest.mark.parametrize("span_deg, samples", [(18.0, 9), (30.0, 9), (24.0, 15)])
def test_a_corner_touch_is_rejected(span_deg, samples):
    """The pad rolling on a corner of the object: every pad line passes through the corner."""
    corner = np.array([112.0, 14.0])
    psis = math.radians(-80.0) + np.linspace(-0.5, 0.5, samples) * math.radians(span_deg)
    felt = feel(CONFIG, quantized_touch(lambda psi: corner, psis), samples)
    assert felt.problem is not None and "corner" in felt.problem, felt.problem
    assert felt.samples is None


def test_a_touch_across_a_closing_segment_is_rejected():
    """The pad rolling across a straight closing segment 16 mm long: below the segment's
    normal it rests on one end corner, above it on the other, so the pad lines kink."""
    psi_s = math.radians(-80.0)
    along = np.array([-math.sin(psi_s), math.cos(psi_s)])
    mid = np.array([112.0, 14.0])
    ends = (mid - 8.0 * along, mid + 8.0 * along)
    psis = psi_s + np.linspace(-0.5, 0.5, 9) * math.radians(18.0)
    felt = feel(CONFIG, quantized_touch(
        lambda psi: min(ends, key=lambda e: float(np.array([math.cos(psi), math.sin(psi)]) @ e)), psis), 9)
    assert felt.problem is not None and ("off the curved part" in felt.problem or "corner" in felt.problem), \
        felt.problem


def test_the_curved_part_is_kept():
    """The same rolls on an ellipse's curved part (radius of curvature 10–50 mm) pass."""
    for centre_deg in (-95.0, -85.0, -75.0):
        psis = math.radians(centre_deg) + np.linspace(-0.5, 0.5, 9) * math.radians(18.0)
        _, points, _ = ellipse_tangent_angles(28.0, 17.0, psis)
        felt = feel(CONFIG, quantized_touch(lambda psi: points[int(np.argmin(np.abs(psis - psi)))], psis), 9)
        assert felt.problem is None, felt.problem


def test_good_circle_touches_are_kept_whatever_the_quantization():
    """18° rolls of 9 readings on a circle of radius 20 mm, quantized to ticks: the cubic
    fit's arc length dips at a roll's end on about a third of them (its ρ(ψ) slope is
    noise); each is kept, its arc length increasing and its mean step r·Δψ (0.785 mm)
    within 3 σ_ρ (σ_ρ ≈ 4 mm)."""
    r = 20.0
    for cx in (108.0, 110.0, 112.0):
        centre = np.array([cx, 0.0])
        for centre_deg in np.arange(-115.0, -64.0, 5.0):
            psis = math.radians(centre_deg) + np.linspace(-0.5, 0.5, 9) * math.radians(18.0)
            felt = feel(CONFIG, quantized_touch(
                lambda psi: centre - r * np.array([math.cos(psi), math.sin(psi)]), psis), 9)
            assert felt.problem is None, (cx, centre_deg, felt.problem)
            steps = np.diff(felt.contacts.s)
            assert np.all(steps > 0.0)
            assert abs(np.mean(steps) / (r * math.radians(18.0) / 8) - 1.0) < 0.6, (cx, centre_deg, steps)


def test_stated_noise_is_the_scatter_of_quantized_rolls():
    """Per-sample deviations stated from each touch's own fit (tactile_jaw.pipeline.
    stated_noise) against the real errors of 40 exact 18° rolls of 9 readings on circles
    r 15–35 mm at random places, every joint angle rounded to a tick (as the encoders do): the
    errors across and along the pad (truth: the circle's point of normal ψ) have mean z² ≈ 1
    (expected 1; the old fixed 0.06 / 0.6 mm gave 0.25 across), the along-pad errors are
    U-shaped over the roll (ends ≥ 2.5× the middle) and the RMS is what the request states."""
    rng = np.random.default_rng(7)
    felt, errors = [], []
    while len(felt) < 40:
        r = rng.uniform(15.0, 35.0)
        centre = np.array([110.0 + rng.uniform(-5, 5), rng.uniform(-5, 5)])
        psis = math.radians(rng.uniform(-100.0, -70.0)) + np.linspace(-0.5, 0.5, 9) * math.radians(18.0)
        try:
            q = np.array([kin.ik_tangent(LEFT, centre - r * np.array([math.cos(p), math.sin(p)]), float(p))
                          for p in psis])
        except kin.Unreachable:
            continue
        ticks = np.rint(kin.angles_to_ticks(LEFT.joints, q))
        f = feel(CONFIG, touch_from_angles(kin.ticks_to_angles(LEFT.joints, ticks)), 9)
        if f.problem is not None and "along the pad" in f.problem:
            continue  # this place put a pad end on the circle
        assert f.problem is None, f.problem
        c = f.contacts
        n = np.stack([np.cos(c.psi), np.sin(c.psi)], axis=-1)
        e = np.stack([c.x, c.y], axis=-1) - (centre - r * n)
        errors.append((np.sum(e * n, axis=1), n[:, 0] * e[:, 1] - n[:, 1] * e[:, 0]))
        felt.append(f)
    across, along = (np.concatenate([e[k] for e in errors]) for k in (0, 1))
    s_across = np.concatenate([f.fit.sigma_across for f in felt])
    s_along = np.concatenate([f.fit.sigma_along for f in felt])
    assert 0.7 < np.mean((across / s_across) ** 2) < 1.4
    assert 0.7 < np.mean((along / s_along) ** 2) < 1.4
    ends, middle = s_along.reshape(40, 9)[:, [0, 8]], s_along.reshape(40, 9)[:, 4]
    assert np.all(ends.min(axis=1) > 2.5 * middle)
    # the touches whose noise is the quantization alone (on 2 of the 40 the order rule also
    # states a truncation, envelope._with_truncation: their along-pad deviations are wider)
    plain = [k for k, f in enumerate(felt) if f.fit.noise_factor.shape[1] == 18]
    assert len(plain) >= 36
    stated = stated_noise([felt[k] for k in plain])
    assert stated.phi == pytest.approx(phi_sigma(LEFT.joints))
    assert 0.8 < stated.pos / np.sqrt(np.mean(np.concatenate([errors[k][0] for k in plain]) ** 2)) < 1.25
    assert 0.8 < stated.pos_along / np.sqrt(np.mean(np.concatenate([errors[k][1] for k in plain]) ** 2)) < 1.25


def _ellipse_touch(finger: str, a: float, b: float, pose, psi_c: float) -> FeltTouch:
    """An exact 18° roll of 9 readings of ``finger`` on the posed ellipse, quantized to ticks."""
    f = CONFIG.finger(finger)
    psis = psi_c + np.linspace(-0.5, 0.5, 9) * math.radians(18.0)
    q = []
    for psi in psis:
        th = psi + math.pi - pose.theta  # the object's outward normal, in its own frame
        t = math.atan2(b * math.sin(th), a * math.cos(th))
        q.append(kin.ik_tangent(f, np.array(pose.apply(a * math.cos(t), b * math.sin(t)), dtype=float), float(psi)))
    ticks = np.rint(kin.angles_to_ticks(f.joints, np.array(q)))
    return feel(CONFIG, touch_from_angles(kin.ticks_to_angles(f.joints, ticks), finger), 9)


def _rank(factor) -> int:
    return int(np.linalg.matrix_rank(factor, tol=1e-6 * np.linalg.norm(factor, 2)))


def test_true_class_chi2_is_calibrated():
    """12 random ellipses, 4 exact quantized touches each, recognized as ellipses with the
    stated noise: each touch's samples carry their error covariance (noise_factor, rank
    degree + 1 + n), so the χ² counts what the touches measure (dof = Σ(degree + 1) − 5,
    not 2 per sample) and the true class's χ²/dof averages ~0.8 (measured 0.76 on 16,
    0.80 on 40; no p below 1e-3). Without the factors the same requests, weighted per sample
    with the same marginal deviations, give χ²/dof ≈ 0.6 on 140 dof whose tail spreads
    (p < 1e-3 on 1 of 60, p > 0.9 on 49 of 60): the samples' errors are correlated."""
    rng = np.random.default_rng(11)
    recognize_ellipse = make_recognizer({"classes": ["ellipse"]}, ExploreSettings.from_profile("balanced"))
    ratios = []
    while len(ratios) < 12:
        a = rng.uniform(15.0, 32.0)
        b = a * rng.uniform(0.45, 0.95)
        pose = Pose(float(rng.uniform(-math.pi, math.pi)), 110.0 + rng.uniform(-5, 5), rng.uniform(-4, 4))
        try:
            felt = [_ellipse_touch(fname, a, b, pose, math.radians(c + rng.uniform(-4, 4)))
                    for fname, c in (("left", -95), ("left", -72), ("right", 75), ("right", 98))]
        except kin.Unreachable:
            continue
        felt = [f for f in felt if f.problem is None]
        if len(felt) < 3:
            continue
        top = recognize_ellipse(felt).ranking[0]
        # the recognizer pools the touches (tactile_jaw.curvature_pool: the next degrees' terms, one
        # noise-factor column each): the ranks it counts are the pooled touches'
        assert top.dof == sum(_rank(p.samples.noise_factor) - f.contacts.x.size
                              for f, p in zip(felt, recognize_ellipse.pooled(felt))) - 5
        assert top.p_value > 1e-3, (a, b, top.chi2, top.dof)
        ratios.append(top.chi2 / top.dof)
    assert 0.45 < np.mean(ratios) < 1.3, ratios


def test_a_touch_with_its_noise_factor_goes_through_json():
    """A felt touch's request form carries its samples' noise factor (3n × 2n, rank
    degree + 1 + n) and parses back to the same; a factor of the wrong shape or all zeros
    is refused with one line."""
    psis = math.radians(-80.0) + np.linspace(-1, 1, 9) * math.radians(9.0)
    q, _, _ = ellipse_tangent_angles(28.0, 17.0, psis)
    felt = feel(CONFIG, quantized_touch(lambda psi: ellipse_tangent_angles(28.0, 17.0, [psi])[1][0], psis), 9)
    factor = felt.samples.noise_factor
    assert factor.shape == (27, 18) and np.linalg.matrix_rank(factor, tol=1e-6 * np.linalg.norm(factor, 2)) == 4 + 9
    request = {"touches": [felt.to_json()] * 3}
    parsed = parse_request(json.loads(json.dumps(request)))
    np.testing.assert_allclose(parsed.touches[0].noise_factor, factor)
    for bad in (factor[:-1].tolist(), np.zeros_like(factor).tolist(), [[1.0]] * 26 + [[1.0, 2.0]]):
        with pytest.raises(InputError, match="noise_factor"):
            parse_request({"touches": [{**felt.to_json(), "noise_factor": bad}] * 3})


def _arc_then_corner(theta_end: float, r: float = 20.0):
    """Contact of the left pad of normal ψ on a circle of radius r about CENTRE whose curved
    part ends at the outward normal angle ``theta_end``: past it the pad pivots about the
    end corner E (returned too)."""
    end = CENTRE + r * np.array([math.cos(theta_end), math.sin(theta_end)])

    def contact(psi):
        theta = psi + math.pi  # the object's outward normal at the contact
        return CENTRE + r * np.array([math.cos(theta), math.sin(theta)]) if theta <= theta_end else end

    return contact, end


def test_a_corner_touch_states_the_corner():
    """A roll on a corner gives the point every pad line passes through: the corner, to the
    lines' quantization (0.05 mm across the pad; along it, over an 18° roll, measured 0.18 mm)."""
    corner = np.array([112.0, 14.0])
    psis = math.radians(-80.0) + np.linspace(-0.5, 0.5, 9) * math.radians(18.0)
    felt = feel(CONFIG, quantized_touch(lambda psi: corner, psis), 9)
    assert felt.off_curve and felt.corner is not None
    assert math.hypot(felt.corner[0] - corner[0], felt.corner[1] - corner[1]) < 0.3


@pytest.mark.parametrize("samples, span_deg, kept", [(9, 18.0, False), (15, 24.0, True)])
def test_a_roll_past_the_curves_end_loses_its_samples_at_the_corner(samples, span_deg, kept):
    """A roll whose last three pad lines pivot about the curve's end corner passes every
    check of its own (over 2° a pivot and the arc differ by ~0.01 mm); once another touch
    has pivoted about that corner, the samples within CORNER_CLEARANCE_MM of it go: a
    15-sample roll is used without them (its 9 contacts then on the circle), a 9-sample one
    keeps too few and is dropped, each with the reason; a touch away from the corner is
    returned as it is."""
    step = math.radians(span_deg) / (samples - 1)
    centre_psi = math.radians(-80.0)
    theta_end = centre_psi + math.pi + step * (samples // 2 - 3 + 0.5)  # the last 3 readings past the end
    contact, end = _arc_then_corner(theta_end)
    psis = centre_psi + np.linspace(-0.5, 0.5, samples) * math.radians(span_deg)
    past = feel(CONFIG, quantized_touch(contact, psis), samples)
    assert past.problem is None, past.problem  # the bug: nothing in the touch itself tells
    on_corner = feel(CONFIG, quantized_touch(lambda psi: end, psis + math.radians(22.0)), samples)
    assert on_corner.corner is not None
    away = feel(CONFIG, quantized_touch(contact, psis - math.radians(20.0)), samples)
    assert away.problem is None
    usable, notes = clear_of_corners(CONFIG, [past, away], [past, on_corner, away], samples)
    assert usable[-1] is away and len(notes) == 1 and "within 2 mm of the corner" in notes[0], notes
    if kept:
        assert len(usable) == 2 and "used without them" in notes[0], notes
        c = usable[0].contacts
        assert c.x.size == 9  # 5 within 2 mm of the corner, and the one the fit placed beyond them
        assert np.max(np.abs(np.hypot(c.x - CENTRE[0], c.y - CENTRE[1]) - 20.0)) < 0.05
    else:
        assert len(usable) == 1 and "not used" in notes[0]


def test_no_corner_changes_nothing():
    psis = math.radians(-80.0) + np.linspace(-0.5, 0.5, 9) * math.radians(18.0)
    contact, _ = _arc_then_corner(math.radians(200.0))
    felt = feel(CONFIG, quantized_touch(contact, psis), 9)
    assert clear_of_corners(CONFIG, [felt], [felt], 9) == ([felt], [])


P_CONFIG = load_config("config/jaw-p.yaml")


def _p_touch(q) -> TouchResult:
    """The left pad of the P-series jaw at joint angles ``q`` (n, 2), rounded to whole ticks."""
    f = P_CONFIG.finger("left")
    samples = []
    for i, qi in enumerate(q):
        ticks = np.rint(kin.angles_to_ticks(f.joints, qi))
        line = kin.finger_pad_line_from_ticks(P_CONFIG, "left", ticks)
        samples.append(Sample(reading=i, psi=float(line.psi), ticks=ticks, line=line, current_ma=None, robot_time=0.0))
    return TouchResult("left", 0, float(np.mean([s.psi for s in samples])), samples, outcome="ok")


@pytest.mark.parametrize("turn_deg", [-3.0, 0.0, 3.0])
def test_a_pad_end_sliding_along_a_face_is_no_roll(turn_deg):
    """The left pad of the P-series jaw turned over 18° (ψ −91.5…−73.5°) with its proximal
    end resting on a block's side face, outward normal at 41.6° (random block 2 of
    ``bench_explore --finite 10 --anywhere --classes line --config config/jaw-p.yaml --seed
    11``, whose two such rolls were used as a curve's touches: no class fit, refused), here
    turned by ``turn_deg``, each pad line's d solved so that the end lies on the face: the
    pad lines have a smooth envelope inside the pad, but the end's points lie on one line
    within the ticks' rounding, where a roll would have bent its path by ~0.1 mm. Rolls on
    circles of radius 20 mm, the same ticks, are kept."""
    f = P_CONFIG.finger("left")
    m = kin.unit(math.radians(41.64 + turn_deg))  # the face's outward normal
    point = np.array([92.26, 40.82])
    qs = []
    for psi in math.radians(-82.5) + np.linspace(-0.5, 0.5, 9) * math.radians(18.0):
        lo, hi = -80.0, 0.0  # the proximal end outside the face (m·x > m·point), then inside

        def off(d):
            return float(m @ (kin.finger_pad_line(f, kin.ik_line(f, psi, d)).proximal - point))

        assert off(lo) > 0.0 > off(hi)
        for _ in range(60):
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if off(mid) > 0.0 else (lo, mid)
        q = kin.ik_line(f, psi, lo)
        assert float(m @ (kin.finger_pad_line(f, q).distal - point)) > 5.0  # the rest of the pad off the face
        qs.append(q)
    felt = feel(P_CONFIG, _p_touch(np.array(qs)), 9)
    assert felt.problem is not None and "proximal end slid along a straight face" in felt.problem, felt.problem
    assert felt.off_curve
    for cx in (108.0, 112.0):
        for centre_deg in (-110.0, -90.0, -70.0):
            psis = math.radians(centre_deg) + np.linspace(-0.5, 0.5, 9) * math.radians(18.0)
            q = [kin.ik_tangent(f, np.array([cx, 0.0]) - 20.0 * np.array([math.cos(p), math.sin(p)]), float(p))
                 for p in psis]
            circle = feel(P_CONFIG, _p_touch(np.array(q)), 9)
            assert circle.problem is None or "slid" not in circle.problem, circle.problem


def test_samples_without_arc_length_between_them_are_refused_by_feel_as_by_the_recognizer():
    """tactile_jaw.pipeline.feel rejects a touch by the recognizer's own rule
    (recognizer.estimate.no_advance), not by Δs ≤ 0: a touch whose envelope put two contacts
    2e-16 mm apart was used and then made the exploration exit 2 (`samples 5 and 6 have no
    arc length between them`, random X ellipse 5 of bench_explore --finite 2 --anywhere --seed 13)."""
    from recognizer.estimate import _check_spacing, no_advance
    from tactile_common.errors import InputError

    s = np.array([3.0, 4.0, 5.0, 5.0 + 2.08e-16, 6.0])
    assert no_advance(s) == 2
    with pytest.raises(InputError, match="samples 2 and 3 have no arc length"):
        _check_spacing(s - s[0], "t")
    assert no_advance(np.array([3.0, 4.0, 5.0, 5.001, 6.0])) is None
    assert no_advance(np.array([1e6, 1e6 + 1e-7, 1e6 + 1.0])) is None  # relative to the stretch, not to s
