"""What one touch's envelope says about the boundary it rolled on, and how well it says it.

The pad lines ``n(ψ_i)·p = d_i`` of a rolling touch are the tangents of the touched
boundary; hand_driver.kinematics.touch_from_pad_lines fits the support values d(ψ) by one
polynomial about the touch's centre of curvature and gives the contacts (the samples),
the radius of curvature ρ = −(d + d'') and dρ/dψ. :func:`fit_envelope` runs that one fit
on the touch's pad lines and adds what the recognizer and the checks need from it: at the
contact (the middle sample) κ = 1/ρ and κ_s = dκ/ds = −ρ'/ρ³; the deviation of κ, κ_s, ρ
and of every sample's position across and along its pad line, to first order in every
joint angle of every reading quantized to a tick (uniform: σ = tick/√12; the Jacobian in
closed form with the fit's origin held, :func:`_propagate`); and the χ² of the pad lines about the
fitted curve, each line by its own quantization deviation. tactile_jaw.pipeline.feel uses
ρ to tell a corner (the contact fixed while the pad turns: ρ ≈ 0), the χ² to tell a roll
across a corner or a closing segment (the lines are no smooth curve's tangents), and
hands the recognizer κ, κ_s with their covariance and the samples with the factor F of
their errors' covariance F·Fᵀ (x…, y…, φ… of all samples: they come from one fit, so their
errors are correlated, rank degree + 1 + n). docs/exploration.md#the-stated-noise.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np
from scipy import linalg, stats

from hand_driver import kinematics as kin
from hand_driver.units import rad_per_tick
from tactile_common.blas import one_blas_thread
from tactile_common.errors import InputError

@dataclass(frozen=True)
class JointNoise:
    """What a finger's two joints put into its readings during one touch: each reading
    quantized to the joint's encoder tick (uniform, independent per reading: σ = tick/√12),
    and an error that stays the same over the touch (σ per joint, rad: where a gear with
    backlash rests in its dead band; the rolls keep each joint's load in one direction, so
    backlash is such an offset: docs/exploration.md#the-stated-noise)."""

    tick_rad: tuple[float, float]
    offset_rad: tuple[float, float] = (0.0, 0.0)
    #: σ (mm) of the finger's link lengths and its pad's offset over the touch (what a
    #: calibration leaves uncertain: ``link_sigma_mm``, ``pad.offset_sigma_mm``)
    link_mm: tuple[float, float] = (0.0, 0.0)
    pad_mm: float = 0.0
    #: what a declared compliance's correction leaves (tactile_jaw.pipeline.touch_compliance): σ per
    #: joint (rad) of each reading's c·τ from its current quantized to one unit (independent per reading) ...
    current_rad: tuple[float, float] = (0.0, 0.0)
    #: ... each reading's c·τ off by the standard error of c (rad, (n, joints) in the order taken,
    #: one error per joint over the touch) ...
    bent_rad: np.ndarray | None = field(default=None, compare=False)
    #: ... and its pad's give k·F off by the standard error of k (mm along the normal, (n,))
    give_mm: np.ndarray | None = field(default=None, compare=False)

    @property
    def quantization(self) -> np.ndarray:
        """σ of each joint's independent error per reading (rad): its quantization, and its
        compliance correction's current quantized (``current_rad``)."""
        return np.hypot(np.asarray(self.tick_rad, dtype=float) / math.sqrt(12.0), self.current_rad)

    def order_test(self) -> JointNoise:
        """The noise the order rule's truncation test (:func:`truncation`) weighs the fits'
        difference by: every joint quantized at least as coarsely as the finger's coarsest joint.
        That test is first order, and ψ, the sum of the finger's joint angles, carries the coarsest
        joint's error into every reading: the fits' response to ψ is not linear (their design
        moves with ψ, their residuals are about |base − centre of curvature| × that error), and
        at 4,096 ticks per turn its second-order part (~13 % of the first on a 20 mm circle) lies
        also in the one direction of the difference that only a fine joint's first-order noise
        reaches; a fine joint (a PH42's 607,500 ticks) states that noise ~150 times smaller than
        that part, and the test called its χ² ~10⁴ on exact circle rolls (every one took degree
        4–5 where a jaw of two coarse or two fine joints takes 3). Only where that second-order part
        (``SECOND_ORDER_PER_RAD`` × tick²) exceeds the finest joint's tick; else the noise itself.
        docs/exploration.md#the-stated-noise."""
        floor = max(self.tick_rad)
        if min(self.tick_rad) >= SECOND_ORDER_PER_RAD * floor**2:
            return self  # the finest joint's tick exceeds the coarsest one's second-order part
        return replace(self, tick_rad=(floor,) * len(self.tick_rad))


#: the coarsest joint's second-order effect through ψ relative to its first-order one, per rad
#: of its tick (:meth:`JointNoise.order_test`): 13 % at 4,096 ticks per turn (1.53 mrad) on the
#: circle example's 20 mm rolls (session 28). Floored only where that part, this × tick², exceeds
#: the finest joint's tick: an XM430 base (0.2 mrad) beside a PH42 (0.010 mrad), not the
#: P-series jaw's PH54 and PH42 (9e-9 rad beside 0.006 mrad), whose order rule is unchanged
SECOND_ORDER_PER_RAD = 85.0


def joint_noise(finger, load_known=None, bent=None) -> JointNoise:
    """The noise a finger's joints declare (hand_driver.config) over one touch: each joint's
    tick (its model's resolution) and its offset over the touch. ``zero_tick`` is the
    encoder's reading at the link's zero under the joint's working load (the calibration
    measures it so), and a touch whose load on a joint is known and keeps one direction
    reads that joint's link angle with its backlash taken out (tactile_jaw.pipeline.feel:
    kinematics.load_offsets of the sign of kinematics.moment_arms), so its offset is only
    the zero's standard error z (``zero_sigma_deg``, written by ``tactile calibrate``). A
    joint whose load over the touch is not known to stay one way (``load_known`` False for
    it; None: known on every joint) may rest anywhere in its dead band: σ = √(z² + (b/2)²),
    b its declared ``backlash_deg``. The calibrated link lengths and pad offset are off by
    their ``link_sigma_mm`` and ``pad.offset_sigma_mm`` the same way over a touch. A touch whose
    declared compliance was taken out (``bent``, tactile_jaw.pipeline.TouchCompliance: each
    reading's torques τ and force F) keeps what that leaves: each reading's c·τ off by c times its
    current quantized to one unit (Kt·unit/√12 per joint, independent), and by the standard error
    of c (``compliance_sigma_deg_per_nm``) times τ and of k (``compliance_sigma_mm_per_n``) times F,
    one error over the touch. docs/exploration.md#the-stated-noise."""
    ticks = rad_per_tick(kin.resolutions(finger.joints))
    known = [True] * len(finger.joints) if load_known is None else [bool(k) for k in load_known]
    noise = JointNoise(tuple(float(t) for t in ticks),
                       tuple(math.radians(j.zero_sigma_deg if k else math.hypot(j.zero_sigma_deg, j.backlash_deg / 2.0))
                             for j, k in zip(finger.joints, known)),
                       tuple(float(j.link_sigma_mm) for j in finger.joints), float(finger.pad.offset_sigma_mm))
    if bent is None:
        return noise
    step = [math.radians(j.compliance_deg_per_nm) * j.spec.torque_nm_per_a * (j.spec.current_unit_ma or 0.0) / 1000.0
            for j in finger.joints]
    se = np.radians([j.compliance_sigma_deg_per_nm for j in finger.joints])
    return replace(noise, current_rad=tuple(float(s) / math.sqrt(12.0) for s in step),
                   bent_rad=se * np.asarray(bent.torques, dtype=float),
                   give_mm=finger.pad.compliance_sigma_mm_per_n * np.asarray(bent.force, dtype=float))


@dataclass(frozen=True)
class EnvelopeFit:
    """One touch's envelope fit: its contacts and what it says at the contact, with deviations."""

    contacts: kin.TouchEnvelope
    kappa: float  # 1/mm
    kappa_s: float  # 1/mm²
    cov: np.ndarray  # 2×2 covariance of (κ, κ_s)
    rho: float  # radius of curvature (mm) at the contact, of the lowest degree weighed; ≈ 0 on a corner
    sigma_rho: float  # its deviation
    chi2: float  # of the pad lines about the fitted smooth support function, each by its deviation
    dof: int  # readings − fitted coefficients
    sigma_across: np.ndarray  # each sample's position across its pad line (mm), contacts' order
    sigma_along: np.ndarray  # and along it (mm): from the fit's slope d', U-shaped over the roll
    noise_factor: np.ndarray  # (3n, 2n [+ 2]) F: the samples' (x…, y…, φ…) errors = F · (unit normal draws)
    line_sigma: np.ndarray  # each pad line's deviation about the fit (mm), contacts' order
    sigma_phi: np.ndarray  # each sample's tangent angle deviation (rad), contacts' order
    kappa_degree: int  # the degree of d(ψ) κ, κ_s come from (:func:`curvature_degree`)
    #: κ, κ_s at every degree the order rule fitted (tactile_jaw.curvature_pool)
    ladder: CurvatureLadder | None = None
    #: the next degrees' terms the contacts' degree leaves out (tactile_jaw.curvature_pool states them)
    next_terms: tuple[NextTerm, ...] = ()
    #: the terms above ``kappa_degree`` its κ, κ_s leave out where :func:`curvature_degree` stated
    #: none (tactile_jaw.curvature_pool states them in their covariance)
    kappa_terms: tuple[NextTerm, ...] = ()


@dataclass(frozen=True)
class NextTerm:
    """A term of d(ψ) above the contacts' degree k (degree j = k + 1 or k + 2): its size c = d^(j)
    (mm/rad^j, the richer fit's, constant over the roll) with its noise variance, and what a unit
    of it does to the samples the degree-k fit states (``pattern``: rows as
    ``EnvelopeFit.noise_factor``'s, x…, y…, φ…). The fit of degree k cannot follow it (its least
    squares leave a degree-j term's part orthogonal to degree k in the samples: the truncation),
    and on one roll c is mostly noise; a finger's rolls near one place share it
    (tactile_jaw.curvature_pool pools it). Both k + 1 and k + 2: where a roll is symmetric about
    a vertex of the boundary d(ψ) is even there and its odd term vanishes (an ellipse's flat side:
    the quartic kept, its quintic term ~0, its sextic term 0.2–0.3 µm across, 1–2 σ)."""

    degree: int  # j: k + 1 or k + 2
    value: float  # c (mm/rad^j)
    variance: float  # of c, from the readings' noise (the two fits see the same readings)
    pattern: np.ndarray  # (3n,) the degree-k samples' error per unit c
    #: j = k + 1 only: the size (in units of c) of the roll's own truncation against j where its own
    #: test found one (:func:`_with_truncation`: the noise factor's last column, |c|·√(1 − rank/χ²)·e
    #: in x, y), else 0; tactile_jaw.curvature_pool states the term once, in its place
    own: float = 0.0
    #: (2,) the degree-k fit's κ, κ_s error at the contact per unit c (as ``pattern``, of the
    #: κ, κ_s rows): tactile_jaw.curvature_pool states it for the terms above κ's own degree
    curvature: np.ndarray = field(default_factory=lambda: np.zeros(2))


@dataclass(frozen=True)
class CurvatureLadder:
    """What each degree of d(ψ) the order rule fitted says at a touch's contact: the
    comparison of one degree with a richer one that tactile_jaw.curvature_pool pools across a
    finger's rolls (the truncation of a degree against the next is systematic where a finger
    rolls again near the same place; one roll's own comparison is mostly noise)."""

    values: dict[int, np.ndarray]  # degree → (2,) κ, κ_s
    rows: dict[int, np.ndarray]  # degree → (2, w) their rows of the noise factor (the same w draws for every degree)
    own: np.ndarray  # (2, W ≥ w) the stated κ, κ_s's rows (kappa_degree's, with any truncation column)

    def difference(self, k: int) -> tuple[np.ndarray, np.ndarray, int] | None:
        """κ, κ_s of degree k less those of degree k + 2 (or k + 1 where k + 2 was not fitted), that
        difference's variance (both fits see the same readings: the difference of their noise
        factors), and the richer degree; None if neither was fitted. Two degrees up: about the
        roll's middle κ comes from d(ψ)'s even coefficients and κ_s from its odd ones, so on a
        roll symmetric in ψ one degree up changes only one of them (the cubic's κ is the
        quadratic's); k + 2 changes both."""
        richer = k + 2 if k + 2 in self.values else k + 1
        if k not in self.values or richer not in self.values:
            return None
        return (self.values[k] - self.values[richer], np.sum((self.rows[k] - self.rows[richer]) ** 2, axis=1),
                richer)


#: the lowest degree of d(ψ) the order rule gives a roll: κ_s = −ρ'/ρ³ at the contact
#: needs ρ(ψ) = −(d + d'') to vary, and degree 2 holds it constant
MIN_DEGREE = 3
#: degrees of freedom the order rule leaves the pad lines' χ² about the fit (the smoothness
#: test, tactile_jaw.pipeline.off_curve_reason): a polynomial with fewer left follows a kink
DEGREE_DOF = 3


def degrees(n: int) -> range:
    """The degrees of d(ψ) the order rule weighs for n readings: ``MIN_DEGREE`` to
    n − 1 − ``DEGREE_DOF`` (just kinematics.default_degree when fewer readings leave no choice)."""
    lo = min(MIN_DEGREE, kin.default_degree(n))
    return range(lo, max(lo, n - 1 - DEGREE_DOF) + 1)


def fit_envelope(finger, q, lines: kin.PadLine, degree: int | None = None,
                 noise: JointNoise | None = None) -> EnvelopeFit:
    """:class:`EnvelopeFit` of a touch of ``finger`` (hand_driver.config.FingerConfig) from its
    joint angles ``q`` (n, 2) and their pad lines ``lines`` (n ≥ 3 readings with distinct ψ);
    deviations from ``noise`` (default: what the finger's joints declare, :func:`joint_noise`).
    The ``degree`` of d(ψ): given, else the order rule (:func:`choose_degree`). On one BLAS
    thread (tactile_common.blas): its matrices are small (the truncation's SVD of a 30-line
    flat-press scan is 60 × 60), where OpenBLAS's threads only contend: on 2 loaded cores
    tactile_jaw.pipeline.curved_part of random block 4's two presses (bench_explore --finite 20
    --anywhere --seed 107, P-series) took 6.5 s of CPU and 21 s of wall time, 2.8 s and 8 s on
    one thread."""
    with one_blas_thread():
        return _fit_envelope(finger, q, lines, degree, noise)


def _fit_envelope(finger, q, lines: kin.PadLine, degree: int | None, noise: JointNoise | None) -> EnvelopeFit:
    """:func:`fit_envelope`'s body."""
    q = np.asarray(q, dtype=float)
    noise = joint_noise(finger) if noise is None else noise
    first = kin.touch_from_pad_lines(lines.psi, lines.d, degree=degree)
    weighed = degrees(q.shape[0]) if degree is None else range(first.degree, first.degree + 1)
    fits, tests = {}, {}
    tested = noise.order_test()

    def fit_of(k):
        if k not in fits:
            contacts, factor = fits[k] = _propagate(finger, q, first.origin, k, noise)
            if not (np.all(np.isfinite(factor)) and np.all(np.isfinite(contacts.x)) and np.all(np.isfinite(contacts.y))):
                raise InputError(f"these {q.shape[0]} readings determine no envelope of degree {k} "
                                 f"(their pad lines are degenerate)")
        return fits[k]

    def test_of(k):
        """The fit of degree k with the noise its order test weighs (:meth:`JointNoise.order_test`)."""
        if tested == noise:
            return fit_of(k)
        if k not in tests:
            tests[k] = (fit_of(k)[0], _propagate(finger, q, first.origin, k, tested)[1])
        return tests[k]

    capped = degree is None  # the order rule's cap: the next degree's truncation is stated
    top = kin.determined_degree(lines.psi)  # no degree the readings do not determine
    base, factor = choose_degree(fit_of, test_of, weighed, capped, top)
    # choose_degree's truncation column, if it stated one
    own = factor[3:, -1] if factor.shape[1] > fit_of(base.degree)[1].shape[1] else None
    curved, curved_factor = curvature_degree(fit_of, test_of, weighed, base.degree, capped, top)
    lowest = fit_of(weighed.start)[1]  # the corner test's ρ: the most precise one
    n = q.shape[0]
    m = n // 2
    normal = np.stack([np.cos(base.psi), np.sin(base.psi)], axis=-1)
    fx, fy, fpsi = factor[3 : 3 + n], factor[3 + n : 3 + 2 * n], factor[3 + 2 * n :]
    across = normal[:, :1] * fx + normal[:, 1:] * fy
    along = -normal[:, 1:] * fx + normal[:, :1] * fy
    cov = curved_factor[:2] @ curved_factor[:2].T
    rho = float(fits[weighed.start][0].rho[m])
    sigma = _line_sigma(finger, q, base, noise.quantization)
    kappa, kappa_s = _at_contact(curved)
    rule = {k: fit for k, fit in fits.items() if k in weighed}  # not a degree past the cap: its bias is stated there
    width = min(f.shape[1] for _, f in rule.values())
    ladder = CurvatureLadder({k: _at_contact(c) for k, (c, _) in rule.items()},
                             {k: f[:2, :width].copy() for k, (_, f) in rule.items()}, curved_factor[:2].copy())
    return EnvelopeFit(base, float(kappa), float(kappa_s), cov, rho,
                       float(np.sqrt(np.sum(lowest[2] ** 2))), float(np.sum((base.residual / sigma) ** 2)),
                       n - base.degree - 1, np.sqrt(np.sum(across**2, axis=1)), np.sqrt(np.sum(along**2, axis=1)),
                       factor[3:], sigma, np.sqrt(np.sum(fpsi**2, axis=1)), curved.degree, ladder,
                       next_terms(fit_of, base.degree, top, own), _kappa_terms(fit_of, curved, curved_factor, top))


def _kappa_terms(fit_of, curved: kin.TouchEnvelope, factor: np.ndarray, top: int) -> tuple[NextTerm, ...]:
    """The terms one and two degrees above κ's degree (:func:`next_terms`) whose truncation of κ, κ_s
    is not yet stated: the k + 1 term not where :func:`curvature_degree` stated a truncation column
    of its own (its factor wider than the plain fit's)."""
    terms = next_terms(fit_of, curved.degree, top)
    if factor.shape[1] > fit_of(curved.degree)[1].shape[1]:
        terms = tuple(t for t in terms if t.degree > curved.degree + 1)
    return terms


def next_terms(fit_of, k: int, top: int, own: np.ndarray | None = None) -> tuple[NextTerm, ...]:
    """:class:`NextTerm` of degrees j = k + 1 and k + 2 of the degree-k fit (``fit_of`` as in
    :func:`choose_degree`), each from its comparison with the fit of degree j; none where the
    readings do not determine j (above ``top``) or are fewer than j + 1. ``own``: the degree-k
    fit's own truncation column against k + 1 (:func:`_with_truncation`), if it states one.
    With ψ and the origin held both fits are linear in the support values d_i, and both reproduce
    a polynomial of degree ≤ k and leave the degree-j fit's residuals alone, so the samples'
    difference is Δ = Σ_i c_i e_i exactly over the terms i = k + 1 … j, e_i the pattern of
    u_i = (ψ − ψ_m)^i / i! ((∂/∂d of degree k − of degree j)·u_i): c by least squares on the
    e_i (x, y rows), its noise from the difference of the two noise factors; the term j is c_j."""
    c, f = fit_of(k)
    n = c.x.size
    richer = range(k + 1, min(k + 2, top, n - 1) + 1)
    if not richer:
        return ()
    jac_k = _envelope_jacobian(c)[1]  # the degree-k fit's, the same against every j
    shifted = c.psi - c.psi[n // 2]
    out = []
    for j in richer:
        c_hi, f_hi = fit_of(j)
        jac = jac_k - _envelope_jacobian(c_hi)[1]
        responses = np.stack([jac @ (shifted**i / math.factorial(i)) for i in range(k + 1, j + 1)], axis=1)
        patterns = responses[3:]
        diff, dfac = _difference((c, f), (c_hi, f_hi))
        e = patterns[: 2 * n]
        if not (np.all(np.isfinite(e)) and np.linalg.matrix_rank(e) == e.shape[1]):
            break
        solve = np.linalg.pinv(e)[-1]  # the term j's row of the least squares
        stated = 0.0 if own is None or j > k + 1 else float(np.linalg.norm(own[: 2 * n]) / np.linalg.norm(e[:, 0]))
        out.append(NextTerm(j, float(solve @ diff), float(np.sum((solve @ dfac) ** 2)), patterns[:, -1], stated,
                            responses[:2, -1].copy()))
    return tuple(out)


#: a richer degree of d(ψ) is taken when its contacts differ from the present degree's by
#: more than that difference's own noise allows at this level (χ² of the difference). Small:
#: a degree taken on noise alone costs much (over an 18° roll of 9 readings at 4,096 ticks
#: per turn a quartic's radius of curvature is uncertain by ±12 mm where the cubic's is by
#: ±4: the corner test then refuses good rolls); what the test leaves undetected is stated
#: as noise (:func:`_with_truncation`)
ORDER_ALPHA = 1e-2


#: the truncation a richer degree shows at this level, not at ``ORDER_ALPHA``, is stated as
#: noise (:func:`_with_truncation`): too small to pay for a degree, too likely to leave out
TRUNCATION_ALPHA = 0.05


def choose_degree(fit_of, test_of, weighed: range, capped: bool = False, top: int | None = None):
    """The order rule: from the lowest degree ``weighed``, step up to a richer one (one or two
    degrees up: d(ψ)'s truncation may be even or odd) while it changes the contacts
    significantly (:func:`truncation`: the χ² of the difference above its limit at
    ``ORDER_ALPHA``); the chosen degree's noise factor also holds the truncation estimated
    against the next degree, also at the top of ``weighed`` when ``capped`` (the rule chose:
    the readings still fit one degree more, and a far arm's truncation at the cap made "no
    class fits" on the P-series hyperbola example). No degree above ``top`` is fitted: the
    readings do not determine it (kinematics.determined_degree). ``fit_of(k)`` is
    :func:`_propagate` at degree k, ``test_of(k)`` the same with the noise the test weighs
    (:meth:`JointNoise.order_test`: ``fit_of`` itself where no joint is floored); returns the chosen
    (contacts, factor)."""
    k = weighed.start
    top = fit_of(k)[0].x.size - 1 if top is None else top
    while True:
        richer = range(k + 1, min(k + 2, weighed.stop - 1, top) + 1)
        steps = [j for j in richer if _significant(*truncation(test_of(k), test_of(j)))]
        if not steps:
            beyond = capped and k + 2 < fit_of(k)[0].x.size and k + 1 <= top  # at the cap, the next degree still fits
            return _with_truncation(fit_of(k), fit_of(k + 1), test_of) if richer or beyond else fit_of(k)
        k = steps[0]


def curvature_degree(fit_of, test_of, weighed: range, k: int, capped: bool = False, top: int | None = None):
    """The degree κ and κ_s at the contact come from: from the contacts' degree ``k`` (:func:`choose_degree`)
    step up while the next degree states them with less expected squared error
    (:func:`_less_error`). Fine encoders make a low degree's κ precise but biased while its
    contacts pass the position test (the P-series cubical example's cubic: κ 1 % off, σ 0.1 %;
    the quartic's −0.1 %, σ 0.5 %); the contacts keep their own degree, whose arc length a
    noisier one could fold. Returns (contacts, factor) of that degree, its truncation against
    the next one stated as in :func:`choose_degree`; none above ``top`` (as there; ``test_of`` too)."""
    top = fit_of(k)[0].x.size - 1 if top is None else top
    while k + 1 < min(weighed.stop, top + 1) and _less_error(fit_of(k), fit_of(k + 1)):
        k += 1
    if k + 1 > top:
        return fit_of(k)
    if k + 1 < weighed.stop:
        return _with_truncation(fit_of(k), fit_of(k + 1), test_of)
    if capped and len(weighed) == 1 and k + 1 < fit_of(k)[0].x.size:
        # the readings leave the order rule one degree: the next one, through them, states κ,
        # κ_s when it shows a bias worth its noise (:func:`_less_error`: dev seed 13 cubical 11,
        # fast, a cubic 3.0 % low where the quartic is 0.3 %, σ 0.9 %); else what they cannot
        # tell from it is stated as noise
        if _less_error(fit_of(k), fit_of(k + 1)):
            return fit_of(k + 1)
        return _with_untestable_truncation(fit_of(k), fit_of(k + 1))
    if capped and k + 2 < fit_of(k)[0].x.size:  # at the order rule's cap: the next degree still fits, and
        # the bias it shows in κ, κ_s is stated (the far arm of the P-series hyperbola example:
        # κ at degree 5 of 9 readings 1.8 % off with σ 0.19 %, z 9.7)
        return _with_curvature_bias(fit_of(k), fit_of(k + 1))
    return fit_of(k)


def _curvature_difference(fit, richer) -> tuple[np.ndarray, np.ndarray]:
    """κ and κ_s at the contact of ``fit`` less ``richer``'s, and that difference's variance
    (from the difference of their noise factors: both fits see the same readings)."""
    (c, f), (c_hi, f_hi) = fit, richer
    width = min(f.shape[1], f_hi.shape[1])
    return _at_contact(c) - _at_contact(c_hi), np.sum((f[:2, :width] - f_hi[:2, :width]) ** 2, axis=1)


def _at_contact(c: kin.TouchEnvelope) -> np.ndarray:
    """κ = 1/ρ and κ_s = −ρ'/ρ³ of an envelope at its contact (the middle sample)."""
    m = c.x.size // 2
    return np.array([1.0 / c.rho[m], -c.rho_psi[m] / c.rho[m] ** 3])


def _with_curvature_bias(fit, richer):
    """``fit`` with the bias of its κ, κ_s that the ``richer`` degree shows, max(0, Δ² − var Δ),
    as one more column of its noise factor (κ, κ_s rows only)."""
    d, var_d = _curvature_difference(fit, richer)
    bias = np.sign(d) * np.sqrt(np.maximum(0.0, d**2 - var_d))
    if not (np.all(np.isfinite(bias)) and np.any(bias != 0.0)):
        return fit
    return _with_curvature_column(fit, bias)


def _with_untestable_truncation(fit, richer):
    """``fit`` with a truncation of its κ, κ_s as large as the deviation of their difference to
    the ``richer`` degree, as one more column of its noise factor (κ, κ_s rows only): a roll of
    too few readings for the order rule to weigh two degrees (the ``fast`` profile's 5) cannot
    detect a bias below that, and on fine encoders it exceeds the fit's own σ (P-series cubical,
    dev seed 13 object 10: κ of the cubic 0.2–1.2 % low on all 7 rolls with σ 0.17 %, z to −7;
    the deviation of the difference to the quartic 0.9–1.1 %)."""
    _, var_d = _curvature_difference(fit, richer)
    if not np.all(np.isfinite(var_d)):
        return fit
    return _with_curvature_column(fit, np.sqrt(var_d))


def _with_curvature_column(fit, column):
    """``fit`` (contacts, noise factor) with one more noise-factor column holding ``column``
    (κ, κ_s) in its κ, κ_s rows and zero elsewhere: a truncation stated as noise."""
    c, f = fit
    col = np.zeros((f.shape[0], 1))
    col[:2, 0] = column
    return c, np.hstack([f, col])


def _less_error(fit, richer) -> bool:
    """Whether the ``richer`` degree states κ and κ_s at the contact with less expected squared
    error than ``fit``: each one's variance plus, for ``fit``, its truncation's squared bias
    estimated without its noise, max(0, Δ² − var Δ) (Δ the two degrees' difference, var Δ
    from the difference of their noise factors), summed over κ and κ_s each in units of
    ``fit``'s variance."""
    (_, f), (_, f_hi) = fit, richer
    d, var_d = _curvature_difference(fit, richer)
    var = np.sum(f[:2] ** 2, axis=1)
    var_hi = np.sum(f_hi[:2] ** 2, axis=1)
    if not (np.all(np.isfinite(d)) and np.all(var > 0.0)):
        return False
    bias2 = np.maximum(0.0, d**2 - var_d)
    return float(np.sum(var_hi / var)) < float(np.sum((var + bias2) / var))


def _significant(chi2: float, rank: int) -> bool:
    return rank > 0 and chi2 > stats.chi2.isf(ORDER_ALPHA, rank)


def truncation(fit, richer) -> tuple[float, int]:
    """How significantly a ``richer`` degree's contacts differ from ``fit``'s: the χ² of the
    difference of the samples' x, y by its own covariance (the difference of the two noise
    factors: both fits see the same readings), and its rank. Each fit is (contacts,
    factor) of :func:`_propagate`."""
    diff, dfac = _difference(fit, richer)
    try:
        u, sv, vt = np.linalg.svd(dfac, full_matrices=False)
    except np.linalg.LinAlgError:  # LAPACK's divide and conquer (gesdd) can fail to converge on
        # a finite, nearly rank-deficient difference (a flat press's scan, P-series seed-61 block 3);
        # the QR iteration (gesvd) is slower and does not
        u, sv, vt = linalg.svd(dfac, full_matrices=False, lapack_driver="gesvd")
    keep = sv > 1e-9 * max(float(sv[0]), 1e-300)
    z = (u[:, keep].T @ diff) / sv[keep]
    return float(z @ z), int(np.count_nonzero(keep))


def _difference(fit, richer) -> tuple[np.ndarray, np.ndarray]:
    """The samples' x…, y… of ``fit`` less ``richer``'s, and the factor of that difference's noise."""
    (c, f), (c_hi, f_hi) = fit, richer
    n = c.x.size
    width = min(f.shape[1], f_hi.shape[1])
    rows = slice(3, 3 + 2 * n)
    return np.concatenate([c.x - c_hi.x, c.y - c_hi.y]), f[rows, :width] - f_hi[rows, :width]


def _with_truncation(fit, richer, test_of):
    """``fit`` with its truncation as one more column of its noise factor: every output's
    difference to the ``richer`` degree's, scaled by the share of the difference's χ² above
    its expectation under noise alone (none when it is within: :func:`truncation`, weighed as
    ``test_of`` of the two degrees states, :func:`choose_degree`)."""
    (c, f), (c_hi, _) = fit, richer
    chi2, rank = truncation(test_of(c.degree), test_of(c_hi.degree))
    if rank == 0 or chi2 <= stats.chi2.isf(TRUNCATION_ALPHA, rank):
        return fit
    n, m = c.x.size, c.x.size // 2
    diff = np.concatenate([_at_contact(c) - _at_contact(c_hi), [c.rho[m] - c_hi.rho[m]],
                           c.x - c_hi.x, c.y - c_hi.y, np.zeros(n)])
    return c, np.hstack([f, diff[:, None] * math.sqrt(1.0 - rank / chi2)])


def _propagate(finger, q, origin, degree: int, noise: JointNoise) -> tuple[kin.TouchEnvelope, np.ndarray]:
    """The envelope of degree ``degree`` about ``origin`` and its noise factor F: rows κ, κ_s,
    ρ at the middle sample, then x…, y…, ψ… of the samples (contacts' order); columns unit
    draws: each reading's joints quantized (σ tick/√12, independent), then each joint's
    offset over the touch (``noise.offset_rad``, where declared), then each link length's and
    the pad offset's error (where declared). The Jacobian is analytic, the origin held: the
    fit's in its pad lines (:func:`_envelope_jacobian`) times the lines' in the joint angles
    and the geometry (:func:`_line_jacobian`)."""
    lines = kin.finger_pad_line(finger, q)
    base = kin.touch_from_pad_lines(lines.psi, lines.d, origin=origin, degree=degree)
    n = q.shape[0]
    by_psi, by_d = _envelope_jacobian(base)
    dd = _line_jacobian(finger, q, lines)
    # the contacts' i-th line is reading order[i]'s: it moves with that reading's two joints
    # (∂ψ/∂q_k = 1, :func:`_line_jacobian`)
    jac = np.empty((3 + 3 * n, n, 2))
    jac[:, base.order, :] = by_psi[:, :, None] + by_d[:, :, None] * dd["q"][base.order][None]
    jac = jac.reshape(3 + 3 * n, 2 * n)
    factor = jac * np.tile(noise.quantization, n)
    offsets = np.asarray(noise.offset_rad, dtype=float)
    if np.any(offsets > 0.0):
        shared = jac.reshape(jac.shape[0], n, 2).sum(axis=1) * offsets
        factor = np.hstack([factor, shared[:, offsets > 0.0]])
    geometry = [(sigma, dd["link"][:, k]) for k, sigma in enumerate(noise.link_mm)] + [(noise.pad_mm, dd["pad"])]
    for sigma, moves in geometry:
        if sigma > 0.0:  # the same error over every reading: one column (ψ does not move with it)
            factor = np.hstack([factor, sigma * (by_d @ moves[base.order])[:, None]])
    if noise.bent_rad is not None:  # one error of each joint's c over the touch, times each reading's τ
        bent = np.einsum("rij,ij->rj", jac.reshape(jac.shape[0], n, 2), noise.bent_rad)
        factor = np.hstack([factor, bent[:, np.any(noise.bent_rad != 0.0, axis=0)]])
    if noise.give_mm is not None and np.any(noise.give_mm > 0.0):  # one error of k, times each reading's F
        factor = np.hstack([factor, (by_d @ noise.give_mm[base.order])[:, None]])
    return base, factor


def _line_jacobian(finger, q, lines: kin.PadLine) -> dict[str, np.ndarray]:
    """How each reading's pad line n(ψ)·p = d (``lines``, kinematics.finger_pad_line of ``q``)
    moves, readings' order: under ``"q"`` ∂d/∂q (n, 2), ``"link"`` ∂d/∂L (n, 2) of the link
    lengths, ``"pad"`` ∂d/∂(pad offset) (n,). ψ is the distal link's angle plus a constant, so
    ∂ψ/∂q_k = 1 (the callers' unit term); a line turned about a point P keeps its distance to
    P, so ∂d = n⊥·P per radian about P (the base for q1, the distal joint J2 for q2); a longer
    proximal link moves the line along its direction e1 (∂d = n·e1); the distal link runs along
    the pad (n·e2 = 0); the pad offset moves it along n."""
    nperp = np.stack([-lines.normal[..., 1], lines.normal[..., 0]], axis=-1)
    a1 = finger.base.angle + q[:, 0]
    e1 = np.stack([np.cos(a1), np.sin(a1)], axis=-1)
    base = np.array([finger.base.x, finger.base.y])
    dd_q = np.stack([nperp @ base, np.sum(nperp * lines.joint2, axis=-1)], axis=-1)
    dd_link = np.stack([np.sum(lines.normal * e1, axis=-1), np.zeros(q.shape[0])], axis=-1)
    return {"q": dd_q, "link": dd_link, "pad": np.ones(q.shape[0])}


def _envelope_jacobian(c: kin.TouchEnvelope) -> tuple[np.ndarray, np.ndarray]:
    """∂/∂ψ_i and ∂/∂d_i (each (3 + 3n, n), contacts' order) of :func:`_propagate`'s outputs
    (κ, κ_s, ρ at the middle sample, then x…, y…, ψ…) of the envelope ``c``, its origin o
    held. The fit is the least-squares polynomial g(ψ) of the support values d_i − n(ψ_i)·o
    (kinematics.touch_from_pad_lines; the same polynomial in any basis of its degree): A its
    design, a_i its rows, b'_i their ψ derivatives, r_i the residuals, ∂coef/∂d_i =
    (AᵀA)⁻¹a_i and ∂coef/∂ψ_i = (AᵀA)⁻¹(b'_i r_i − a_i n⊥_i·p_i) (g'_i + n⊥_i·o = n⊥_i·p_i).
    Each output also moves with its own ψ: the contact p = o + g n + g' n⊥ by −ρ n⊥,
    ρ = −(g + g'') by dρ/dψ, dρ/dψ = −(g' + g''') by −(g'' + g⁗)."""
    n, k = c.x.size, c.degree
    m = n // 2
    scale = max(0.5 * (c.psi[-1] - c.psi[0]), 1e-12)
    x = (c.psi - 0.5 * (c.psi[0] + c.psi[-1])) / scale

    def basis(order: int, rows=slice(None)) -> np.ndarray:
        """The Legendre basis' order-th ψ derivative at x[rows] (well conditioned at any degree)."""
        if order > k:
            return np.zeros((x[rows].size, k + 1))
        coef = np.polynomial.legendre.legder(np.eye(k + 1), order, axis=0)
        return np.polynomial.legendre.legvander(x[rows], k - order) @ coef / scale**order

    design, d1 = basis(0), basis(1)
    q_a, r_a = np.linalg.qr(design)
    pinv = linalg.solve_triangular(r_a, q_a.T)  # (AᵀA)⁻¹Aᵀ
    gram_d1 = linalg.solve_triangular(r_a, linalg.solve_triangular(r_a, d1.T, trans="T"))  # (AᵀA)⁻¹b'_i
    normal = np.stack([np.cos(c.psi), np.sin(c.psi)], axis=-1)
    nperp = np.stack([-normal[:, 1], normal[:, 0]], axis=-1)
    points = np.stack([c.x, c.y], axis=-1)
    coefficients = pinv @ (np.sum(normal * (points - c.origin), axis=-1) + c.residual)
    mid = slice(m, m + 1)
    rho_row = -(basis(0, mid) + basis(2, mid))[0]
    slope_row = -(basis(1, mid) + basis(3, mid))[0]
    rho, slope = c.rho[m], c.rho_psi[m]
    rows_x = normal[:, :1] * design + nperp[:, :1] * d1
    rows_y = normal[:, 1:] * design + nperp[:, 1:] * d1
    out = []
    for coef, own in ((gram_d1 * c.residual - pinv * np.sum(nperp * points, axis=-1), True), (pinv, False)):
        j_rho, j_slope, j_x, j_y = rho_row @ coef, slope_row @ coef, rows_x @ coef, rows_y @ coef
        if own:
            j_rho[m] += slope
            j_slope[m] -= float((basis(2, mid) + basis(4, mid))[0] @ coefficients)
            j_x[np.arange(n), np.arange(n)] -= c.rho * nperp[:, 0]
            j_y[np.arange(n), np.arange(n)] -= c.rho * nperp[:, 1]
        out.append(np.vstack([-j_rho / rho**2, -j_slope / rho**3 + 3.0 * slope * j_rho / rho**4, j_rho, j_x, j_y,
                              np.eye(n) if own else np.zeros((n, n))]))
    return out[0], out[1]


def _line_sigma(finger, q, base: kin.TouchEnvelope, sq: np.ndarray) -> np.ndarray:
    """Each pad line's deviation about the fit (mm, contacts' order): its residual
    d_i − d(ψ_i) with the fit held moves as ∂r_i/∂q = ∂d_i/∂q − d'(ψ_i)·∂ψ_i/∂q, d'(ψ_i)
    the contact's coordinate along the line (each line depends on its own reading's two
    joints, each quantized with σ ``sq``)."""
    qs = q[base.order]
    dd = _line_jacobian(finger, qs, kin.finger_pad_line(finger, qs))
    slope = -np.sin(base.psi) * base.x + np.cos(base.psi) * base.y  # d'(ψ) = p·n⊥
    return np.sqrt(np.sum(((dd["q"] - slope[:, None]) * sq) ** 2, axis=1))  # ∂ψ/∂q = 1


def point_miss_sigma(finger, lines: kin.PadLine, point, joint_sigma: np.ndarray) -> np.ndarray:
    """Each pad line's deviation (mm) of its miss n(ψ_i)·p − d_i of the point ``point``, its
    joints off by independent errors of σ ``joint_sigma`` (n, joints; rad): a joint turned by δ
    turns the line about the joint's centre J, which moves it at p by n⊥·(J − p)·δ
    (:func:`_line_jacobian`'s ∂d/∂q with ∂ψ/∂q = 1)."""
    nperp = np.stack([-lines.normal[..., 1], lines.normal[..., 0]], axis=-1)
    arms = np.stack([nperp @ np.array([finger.base.x, finger.base.y]), np.sum(nperp * lines.joint2, axis=-1)],
                    axis=-1) - (nperp @ np.asarray(point, dtype=float))[:, None]
    return np.sqrt(np.sum((arms * joint_sigma) ** 2, axis=1))
