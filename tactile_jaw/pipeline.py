"""Servo ticks → pad lines → touches → recognition, each touch computed once.

:func:`feel` turns one rolling touch's in-contact readings into its pad lines, their
envelope (the contacts, hand_driver.kinematics.touch_from_pad_lines), where each contact
lies along the pad, and why the touch cannot be used (or None); the :class:`FeltTouch` is
kept and reused by the exploration's checks and object model, the recognizer's samples,
the log and the plot. :func:`make_recognizer` validates the scene and the stated noise
once and recognizes any list of felt touches; :func:`logged_run` rebuilds a run log's
felt touches from its readings (replay, benchmarks).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields, replace
from typing import Any, Callable, Collection, Sequence

import numpy as np

from hand_driver import kinematics as kin
from hand_driver.flat_press import SEAT_TOL_MM, FlatResult
from hand_driver.motion import EDGE_MARGIN_MM, Sample, TouchResult
from recognizer.classify import chi2_limit, recognize
from recognizer.estimate import no_advance
from recognizer.profiles import PROFILES
from recognizer.result import Recognition, RecognizeOptions
from recognizer.scene import ALL_CLASSES, load_scene
from recognizer.touches import ContactTouch, NoiseModel, Reach, Request, SamplesTouch, check_touch_count, parse_noise
from tactile_common.errors import InputError
from tactile_jaw.curvature_pool import pooled
from tactile_jaw.envelope import MIN_DEGREE, EnvelopeFit, fit_envelope, joint_noise, point_miss_sigma
from tactile_jaw.flat import Face, bulged_presses, feel_flat, flat_noise, recognized_touches
from tactile_jaw.settings import MIN_SAMPLES_PER_TOUCH, ExploreSettings

#: a touch whose radius of curvature at the contact is below this (mm), or below
#: CORNER_SIGMAS of its deviation, rolled on a corner (the contact stayed put while the pad
#: turned), not on the curved part. A corner's measured radius scatters about 0 by σ_ρ
#: (1.3 mm over a 30° roll of 9 samples, ~4 mm over 18°): 2 σ misses 2.3 % of corners and
#: also refuses boundary bent tighter than ~2 σ_ρ, whose κ is too uncertain to use (2.5 σ
#: rejected the cubical example's hump, ρ 14.5 mm measured 8.25 ± 3.77 mm)
CORNER_RADIUS_MM = 1.0
CORNER_SIGMAS = 2.0
#: a stretch that no usable touch measured (:func:`moving_stretch`, :func:`on_pad_face`) shows
#: a curved part only when its radius of curvature is at least this many of its deviations:
#: beside a corner coarse encoders made pivots pass for 18.6 ± 4.2 mm (4.4 σ; a roll of the
#: block in tests/tools/test_demo_block_corner.py) and 11.6 ± 5.1 mm (the scan of X line 8 of
#: bench_explore --finite 20 --anywhere --seed 313 --classes line, its pad's end cut off); the
#: curves those rules exist for measured 15.7 ± 0.31 mm (50 σ) and 27–96 ± 0.3 mm
MOVED_SIGMAS = 10.0
#: a roll judged a corner whose radius could, within CORNER_SIGMAS σ_ρ, be one a wider roll
#: would not judge a corner (:func:`corner_in_doubt`) may be boundary bent tightly (an
#: X-series jaw's 18° roll on an ellipse's end, ρ = b²/a = 6.8 mm, measured 5.2 ± 4.1 mm; one
#: of b²/a = 5.4 mm measured 0.63 ± 3.78 mm): the same place rolled over this many times the
#: span measures ρ with σ_ρ about its square smaller (d'' of the envelope: 3.24 → 0.77 and
#: 3.37 → 0.80 mm on block corners of bench_explore --finite 10 --anywhere --seed 17), which
#: tells the two apart
WIDER_SPAN = 2.0
#: false-rejection rate of the test that a touch's pad lines are one smooth curve's tangents
SMOOTH_ALPHA = 1e-3
#: degree of d(ψ) whose envelope (constant radius of curvature over the roll) gives a
#: rolling touch's arc length when the default cubic's is not increasing
SMOOTH_DEGREE = 2
#: a rolling touch whose pad end points (the pad's proximal or distal end at each reading) lie
#: on one straight line within their noise (χ² at SMOOTH_ALPHA) is a pad end sliding along a
#: straight face, not a roll (:func:`slid_end`), when its pad lines' deviations are at
#: most this (mm): a roll bends the ends' paths too, but little — exact 18° rolls of the
#: P-series left pad on circles of radius 10–100 mm bent the straighter end's path by
#: 0.018–0.28 mm (≥ 60 of its deviations, 0.0002–0.0003 mm), the X-series pad's on a circle of
#: 20 mm by 0.04 mm, within its deviations (0.054 mm): with coarse encoders the test cannot
#: tell and is not made
SLIDE_MAX_SIGMA_MM = 0.002
#: outcomes of a touch cut short whose samples so far may still be used
CUT_SHORT = ("unreachable", "no_contact", "blocked")
#: a rolling touch's sample whose pad lay farther than this share of the roll's step from the
#: orientation it was commanded to is not one of the roll's samples (:func:`at_orientation`):
#: on the P-series jaw the measured pad normal is within 0.1° of the commanded one (the truth
#: jaw's backlash; 99.5 % within 0.001°) in all but 26 of 10,377 samples (seed 139's calibrated
#: runs, backlash and zero errors declared): in those a roll's first approach met the object
#: while the pad was still turning to its start (hand_driver.motion.rolling_touch: the move to
#: the start line) and stalled there, 4–43° off; 12.9° before the next sample, the envelope fit across that gap
#: misplaced the sample's contact and κ_s (random cubicals 115 of bench_explore --finite 20
#: --anywhere --seed 139 and 111 of seed 127: "no class fits", χ² 5.9e3 and 1.3e5, each
#: answered right without that one sample)
ORIENTATION_STEP_SHARE = 0.5
#: a usable touch's samples whose envelope contact lies within this distance (mm) of a corner
#: another touch pivoted about (:func:`clear_of_corners`) are not the curved part's: a pad
#: that rolls past the curve's end pivots about the end corner, and over a few samples
#: (2-4 deg) a pivot and an arc of radius 10-20 mm differ by ρδ²/2 ≈ 0.01-0.06 mm, below the
#: pad lines' deviation (about 0.05 mm), so neither the touch's χ² nor its radius tells them
#: apart; the envelope fit then places those samples 0.1-1.5 mm off the curve, past its end
#: (measured on the random cubical parabolas of bench_explore --finite 20 --seed 11: every
#: such sample within 1.5 mm of the corner another touch found)
CORNER_CLEARANCE_MM = 2.0
#: ... on a jaw whose pad lines deviate less, the arc within which they hide a pivot,
#: √(2σρ) (:func:`corner_clearance`), times this
CLEARANCE_SPREAD = 2.0
#: only a corner touch whose radius of curvature is below this many of its deviations, or
#: below ``CORNER_RADIUS_MM`` by this many, clears the samples around it
#: (:func:`clears_around`, :func:`clear_of_corners`): of the bench's touches rejected as
#: corners (ρ < 2 σ_ρ), 104 of 123 on true corners have ρ < σ_ρ but only 4 of 19 on a
#: cubical's hump of radius ≈ 10 mm (ρ 6.5 ± 3.6 mm: a point of the curve, whose clearance
#: would drop the good touches around it)
CLEARANCE_SIGMAS = 1.0
#: a corner a roll across a straight closing segment pivoted about (:func:`crossed_segment`)
#: counts when at least this many of its pad lines pass through it: two lines always meet
#: in a point, three meeting in one within their noise are a pivot
SEGMENT_CORNER_LINES = 3
#: the point a finger's pad lines of several touches pass through (:func:`shared_pivot`) is
#: refitted on the lines within their noise of it at most this many times (it settles in 2–3)
SHARED_PIVOT_ROUNDS = 8
#: a joint whose moment arm (kinematics.moment_arms) under a touch's press stays at least this
#: far (mm) from 0 one way has a known load: its gear rests on that side of its dead band.
#: Nearer its line of action the press's torque on it (arm × a few N, below 0.01 N·m) is of
#: the order of a gear's friction, and where the gear rests in its band is not known
LOAD_KNOWN_ARM_MM = 2.0


@dataclass(frozen=True)
class FeltTouch:
    """One touch's geometry, computed once by :func:`feel`."""

    touch: TouchResult
    lines: kin.PadLine | None  # the pad at every in-contact sample, in the order taken
    contacts: kin.TouchEnvelope | None  # their envelope, ordered by ψ (None when not computed)
    pad_u: np.ndarray | None  # each contact's distance along the pad from its proximal end (contacts' order)
    problem: str | None  # why the touch cannot be used, or None
    samples: SamplesTouch | ContactTouch | None  # the recognizer's touch when usable (a contact: flat press)
    fit: EnvelopeFit | None = None  # the envelope fit's curvature, radius and smoothness
    off_curve: bool = False  # it fell on a corner or across a closing segment (off_curve_reason)
    face: Face | None = None  # a flat press's face (tactile_jaw.flat)
    corner: tuple[float, float] | None = None  # the point it pivoted about, when it fell on a corner
    #: the end corners of the straight closing segment it rolled across (:func:`crossed_segment`)
    segment_corners: tuple[tuple[float, float], ...] = ()
    #: the corner a run of its lines turned about when it fell off the curved part (:func:`pivot_run`):
    #: the point (mm) and its covariance (mm²)
    pivot: tuple[np.ndarray, np.ndarray] | None = None
    #: an unusable roll's stretch on the curved part (:func:`curve_hint`): (x, y, φ) of its middle
    curve_at: tuple[float, float, float] | None = None
    #: and that stretch's end (ψ rad, x, y mm of its contact) on the side where the roll alone left the
    #: curved part, with that side: +1 its high ψ, −1 its low ψ (:func:`_felt_run`); None if both or neither
    curve_span: tuple[float, float, float, int] | None = None
    #: the pad end ("proximal", "distal") that slid along a straight face (:func:`slid_end`), when that rejected it
    slid: str | None = None

    @property
    def finger(self) -> str:
        return self.touch.finger

    def to_json(self) -> dict[str, Any]:
        """The samples touch (docs/formats.md) with ``finger`` and the envelope's ``curvature``
        (usable touches only): a request of these, pooled first (tactile_jaw.curvature_pool), answers
        as the run did."""
        out = self.samples.to_json() if self.samples is not None else self.contacts.to_touch()
        out["finger"] = self.touch.finger
        return out

    def pad_segments(self) -> list[dict[str, Any]]:
        """The pad, as a segment, at every in-contact sample (for the plot)."""
        if self.lines is None:
            return []
        return [{"finger": self.touch.finger, "p0": tuple(p0), "p1": tuple(p1)}
                for p0, p1 in zip(self.lines.proximal, self.lines.distal)]


def feel(config, touch: TouchResult, samples: int, curve_checks: bool = True, trim: bool = True) -> FeltTouch:
    """The touch's pad lines (one forward-kinematics pass over its readings), their
    envelope (and, for rolling touches, its :class:`EnvelopeFit`), and why it cannot be used, or None: at least ``MIN_SAMPLES_PER_TOUCH``
    samples (all ``samples`` planned ones, or those taken before the roll ran out of reach
    or contact), arc length strictly increasing (the pad rolled on a boundary convex toward
    it, not on an edge or a corner; for rolling touches from the degree-``SMOOTH_DEGREE``
    fit when the cubic's is not) and every envelope contact on the pad,
    ``EDGE_MARGIN_MM`` from its ends (a pad end resting on the object is not a tangent
    contact); and, with ``curve_checks`` (rolling touches; not probes, whose short rolls
    cannot measure a radius of curvature), that it rolled on the curved part
    (:func:`off_curve_reason`); a roll that ran off it at an end is used on its longest
    stretch that passes (``trim``, :func:`smooth_stretch`), else its shorter stretch on the
    curve is noted (``curve_at``, :func:`curve_hint`, :func:`moving_hint`, :func:`past_stretch`). The link angles
    are the encoders' less the backlash (:func:`touch_loads`) and, where the finger declares compliance, less
    each reading's deflection and its pad's give (:func:`touch_compliance`). A flat press is felt by
    tactile_jaw.flat.feel_flat."""
    if isinstance(touch, FlatResult):
        lines, problem, contact, face = feel_flat(config, touch)
        return FeltTouch(touch, lines, None, None, problem, contact, face=face)
    finger = touch.finger
    if curve_checks:
        touch = at_orientation(touch)
    lines = kin.PadLine.stack([s.line for s in touch.samples]) if touch.samples else None

    def out(problem, contacts=None, pad_u=None, fit=None, off_curve=False, corner=None, curve_at=None,
            curve_span=None, slid=None, segment_corners=(), pivot=None):
        samples_touch = None
        if problem is None and fit is not None:
            samples_touch = SamplesTouch(contacts.phi, contacts.x, contacts.y, contacts.s,
                                         curvature=(fit.kappa, fit.kappa_s, fit.cov), noise_factor=fit.noise_factor)
        return FeltTouch(touch, lines, contacts, pad_u, problem, samples_touch, fit, off_curve, corner=corner,
                         curve_at=curve_at, curve_span=curve_span, slid=slid, segment_corners=segment_corners,
                         pivot=pivot)

    cut_short = touch.outcome in CUT_SHORT
    if touch.outcome != "ok" and not cut_short:
        return out(touch.message or touch.outcome)
    if len(touch.samples) < max(3, min(samples, MIN_SAMPLES_PER_TOUCH)):  # an envelope needs 3 lines
        return out(touch.message if cut_short else f"{finger}: {len(touch.samples)} of {samples} samples")
    f = config.finger(finger)
    q = kin.ticks_to_angles(f.joints, np.array([s.ticks for s in touch.samples], dtype=float))
    fit = None
    try:
        loads = touch_loads(f, q, lines)
        if loads.reversed is not None:
            c = kin.touch_from_pad_lines(lines.psi, lines.d)
            return out(f"{finger}: the load on joint {f.joints[loads.reversed].id} reversed during the touch (its "
                       f"backlash would not stay one offset)", c, _pad_u(lines, c))
        if np.any(loads.offsets):
            q = q - loads.offsets
            lines = kin.finger_pad_line(f, q)
        bent = touch_compliance(f, touch.samples, q, lines)
        if bent is not None:
            q = q - bent.turns
            lines = kin.finger_pad_line(f, q)
        noise = joint_noise(f, loads.known, bent)
        if curve_checks:
            fit = fit_envelope(f, q, lines, noise=noise)
            c = fit.contacts
        else:
            c = kin.touch_from_pad_lines(lines.psi, lines.d)
    except InputError as exc:
        return out(f"{finger}: {exc}")
    u = _pad_u(lines, c)
    if curve_checks:
        segment = None if on_corner(fit) else crossed_segment(fit, c, lines)
        off_curve = off_curve_reason(fit, c, float(np.ptp(c.psi)), segment)
        if off_curve is not None:
            hint = span = None
            if trim and rough(fit) and off_curve == rough(fit):
                shorter = smooth_stretch(config, touch, samples)
                if shorter is not None:
                    return shorter
                hint, span = curve_hint(config, touch, samples)
            felt = out(f"{finger}: {off_curve}", c, u, fit, off_curve=True,
                       corner=pivot_point(lines) if on_corner(fit) else None, curve_at=hint, curve_span=span,
                       segment_corners=segment[2] if segment is not None else (),
                       pivot=pivot_run(lines, c, fit.line_sigma) if segment is None else None)
            if not (trim and rough(fit)):
                return felt
            if hint is None:
                felt = moving_hint(config, felt, samples)
            # no hint yet, or the middle of a run that lost both its ends: on past the stretch the contact moved on
            return past_stretch(config, felt, samples) if felt.curve_at is None or (hint is not None and span is None) \
                else felt
    if curve_checks:
        slid = slid_end(lines, fit)
        if slid is not None:
            end, chi2, dof = slid
            return out(f"{finger}: off the curved part: the pad's {end} end slid along a straight face (its points "
                       f"within their noise of one line, chi2 {chi2:.3g} on {dof} dof), a pad end, not the pad's face, "
                       f"touched", c, u, fit, off_curve=True, slid=end)
    if fit is not None and np.any(np.diff(c.s) <= 0.0):
        # the cubic's ρ(ψ) = −(d + d'') is linear in ψ and its slope is mostly noise over a
        # short roll (σ_ρ ≈ 4 mm over 18°): at the roll's ends it can dip below 0 on a
        # boundary of ρ ≈ 20 mm. The roll passed the corner test (ρ > 2 σ_ρ at the contact),
        # so its samples (and their deviations) come from the smoother fit of constant ρ
        # (degree 2); κ, κ_s stay the cubic's
        smooth = fit_envelope(f, q, lines, degree=SMOOTH_DEGREE, noise=noise)
        if rough(smooth) is not None:  # fine encoders: a constant ρ does not explain the lines
            felt = out(f"{finger}: arc length not increasing, and {rough(smooth)}", c, u, fit, off_curve=True)
            return moving_hint(config, felt, samples) if trim else felt
        fit = replace(fit, contacts=smooth.contacts, sigma_across=smooth.sigma_across,
                      sigma_along=smooth.sigma_along, noise_factor=smooth.noise_factor, next_terms=smooth.next_terms)
        c = fit.contacts
        u = _pad_u(lines, c)
    if no_advance(c.s) is not None:  # as the recognizer refuses them (a Δs of 2e-16 mm was not ≤ 0)
        return out(f"{finger}: arc length not increasing: the pad rolled on an edge or corner", c, u, fit)
    length = f.pad.length_mm
    if np.any(u < EDGE_MARGIN_MM) or np.any(u > length - EDGE_MARGIN_MM):
        return out(f"{finger}: contact {float(np.min(u)):.1f}..{float(np.max(u)):.1f} mm along the pad, "
                   f"not inside {EDGE_MARGIN_MM:g}..{length - EDGE_MARGIN_MM:g} mm (a pad end touched)", c, u, fit)
    return out(None, c, u, fit)


def at_orientation(touch: TouchResult) -> TouchResult:
    """``touch`` without the samples whose measured pad normal lies farther than
    ``ORIENTATION_STEP_SHARE`` of the roll's step (the commanded orientations' median spacing)
    from the orientation each was commanded to: the pad met the object before it turned
    there, so the sample's line is another roll's (the same object when every sample is kept)."""
    if len(touch.samples) < 2:
        return touch
    commanded = np.array([s.psi for s in touch.samples], float)
    step = float(np.median(np.abs(np.diff(commanded))))
    off = np.abs(np.remainder(np.array([s.psi_measured for s in touch.samples]) - commanded + math.pi,
                              2 * math.pi) - math.pi)
    keep = off <= ORIENTATION_STEP_SHARE * step
    if step <= 0.0 or np.all(keep):
        return touch
    return replace(touch, samples=[s for s, k in zip(touch.samples, keep) if k])


@dataclass(frozen=True)
class TouchLoads:
    """What backlash does to one touch's readings (:func:`touch_loads`)."""

    known: tuple[bool, ...]  # per joint: its load keeps one known direction over the touch
    offsets: np.ndarray  # (n, joints) rad to subtract from the joint angles: the backlash taken out
    reversed: int | None = None  # a joint with backlash whose load reversed during the touch


@dataclass(frozen=True)
class TouchCompliance:
    """What declared compliance does to one touch's readings (:func:`touch_compliance`)."""

    turns: np.ndarray  # (n, joints) rad to subtract from the joint angles: the links' deflection and the pad's give
    torques: np.ndarray  # (n, joints) N·m: each reading's joint torques, Kt·I
    force: np.ndarray  # (n,) N: each reading's contact force


def touch_loads(finger, q, lines: kin.PadLine) -> TouchLoads:
    """Each joint's load over a touch of ``finger`` (joint angles ``q`` (n, 2), pad lines
    ``lines``): the sign of kinematics.moment_arms of the pad's press (along its normal) at
    each reading's contact (the touch's envelope). A joint that declares backlash and whose
    moment arm stays at least ``LOAD_KNOWN_ARM_MM`` one way over the touch has a known load:
    its link angles are the encoder's less kinematics.load_offsets (0 under its working
    load); one whose arm keeps its sign but comes nearer its line of action is not known to
    rest on either side of its dead band (tactile_jaw.envelope.joint_noise states its half
    band); one whose arm changes sign reversed (its gear crossed the band within the touch:
    the touch is refused). A joint without declared backlash is known and never offset."""
    q = np.asarray(q, dtype=float)
    bands = np.array([j.backlash_deg > 0.0 for j in finger.joints])
    zero = np.zeros_like(q)
    if not np.any(bands):
        return TouchLoads(tuple(True for _ in finger.joints), zero)
    c = kin.touch_from_pad_lines(lines.psi, lines.d)
    points = np.empty((c.order.size, 2))
    points[c.order] = np.stack([c.x, c.y], axis=-1)  # each reading's contact, in the order taken
    arms = kin.moment_arms(finger, q, points)
    pos, neg = np.all(arms >= LOAD_KNOWN_ARM_MM, axis=0), np.all(arms <= -LOAD_KNOWN_ARM_MM, axis=0)
    turned = bands & np.any(arms > 0.0, axis=0) & np.any(arms < 0.0, axis=0)
    known = ~bands | pos | neg
    sign = np.where(pos, 1.0, np.where(neg, -1.0, 0.0))
    offsets = np.broadcast_to(np.where(bands, kin.load_offsets(finger, sign), 0.0), q.shape).copy()
    return TouchLoads(tuple(bool(k) for k in known), offsets,
                      int(np.flatnonzero(turned)[0]) if np.any(turned) else None)


def touch_compliance(finger, samples, q, lines: kin.PadLine) -> TouchCompliance | None:
    """What the finger's declared compliance did to a touch's readings (joint angles ``q`` (n, 2),
    backlash taken out, their pad lines ``lines``); None where the finger declares none. Each
    reading's joints carry τ = Kt·I from its own Present Currents (kinematics.joint_torques), the
    pad presses its contact (the touch's envelope) along its normal with the force F they balance
    (kinematics.pressed_force); its links stand c·τ behind the encoders and the pad's give k·F
    further in (kinematics.compliance_turns): the calibration's model (hand_driver.calibration_fit).
    InputError when a reading carries no joint currents: its deflection cannot be taken out."""
    if not kin.declares_compliance(finger):
        return None
    if any(s.joint_current_ma is None for s in samples):
        raise InputError("the jaw declares compliance but not every reading of the touch carries its joints' "
                         "currents: its deflection cannot be taken out")
    torques = kin.joint_torques(finger, np.array([s.joint_current_ma for s in samples], dtype=float))
    c = kin.touch_from_pad_lines(lines.psi, lines.d)
    points = np.empty((c.order.size, 2))
    points[c.order] = np.stack([c.x, c.y], axis=-1)  # each reading's contact, in the order taken
    force = kin.pressed_force(finger, q, points, torques)
    return TouchCompliance(kin.compliance_turns(finger, q, torques, force), torques, force)


def smooth_stretch(config, touch: TouchResult, samples: int) -> FeltTouch | None:
    """A rolling touch that failed the smoothness test, felt again on its longest run of
    consecutive samples (in ψ order) that passes every check once the fewest samples are
    dropped from its ends, and one more beside each cut (the roll left the curved part
    somewhere within that step: a first line past the end differs from the arc's
    continuation by ρδ²/2, a few µm, which a polynomial follows and then places that contact
    0.1–0.3 mm off along the pad); it must keep ``MIN_SAMPLES_PER_TOUCH``. None if no run
    does. With fine encoders a roll that ran onto the object's end corner shows it (at
    1,000,000 ticks per turn a pivot and an arc of radius 20 mm differ by 0.01 mm over 2°,
    50 times the lines' noise) and its curved part is kept."""
    order = np.argsort([s.psi for s in touch.samples], kind="stable")
    n = order.size
    for head, tail, _ in _passing_runs(config, touch, MIN_SAMPLES_PER_TOUCH, margin=1):
        lo, hi = head + (head > 0), n - tail - (tail > 0)
        again = feel(config, _subset(touch, order[lo:hi]), hi - lo, trim=False)
        return again if again.problem is None else None
    return None


#: the fewest readings whose envelope the smoothness test can still judge: the order rule's
#: lowest degree (``MIN_DEGREE``, its MIN_DEGREE + 1 coefficients) and one degree of freedom
#: left for the pad lines' χ² about it (tactile_jaw.envelope)
CURVE_HINT_SAMPLES = MIN_DEGREE + 2
#: the fewest consecutive three-line windows of a roll whose contact moved (:func:`moving_stretch`)
#: that no polygon shows, so that :func:`curved_part` counts as a curved part: a roll across a
#: block's face or a closing segment changes pivots between two lines, and only the two windows
#: holding both pivots move (ρ 150–894 ± 0.4 mm on the P-series jaw, runs of 2 in 16 of 115 line
#: logs); a third in a row needs a corner that holds at most two of the roll's lines,
#: one turning less than three roll steps (6.75° at 2.25°)
MOVED_RUN_WINDOWS = 3
#: the most runs :func:`_passing_runs` feels for one touch: every run of at least
#: ``CURVE_HINT_SAMPLES`` of the longest roll any profile plans (its (R − m)(R − m + 3)/2
#: runs dropping 1 … R − m samples, R its samples, m CURVE_HINT_SAMPLES: 65 for the accurate
#: profile's 15), so no roll's search is cut short; a flat press's scan (33 lines, ~430 runs,
#: each an envelope fit of its lines: 18 min of CPU on P line 4 of finite seed 199 of
#: session 19) is searched as far as a roll is, over its runs dropping the fewest lines
MAX_RUN_FITS = max((r - CURVE_HINT_SAMPLES) * (r - CURVE_HINT_SAMPLES + 3) // 2
                   for r in (p.samples_per_touch for p in PROFILES.values()))


def curve_hint(config, touch: TouchResult,
               samples: int) -> tuple[tuple[float, float, float] | None, tuple[float, float, float, int] | None]:
    """Where a roll that failed the smoothness test and could not be trimmed to a usable
    touch (:func:`smooth_stretch`) still rolled on the curved part, as the middle contact
    (x, y) mm and tangent φ (rad) of a roll of ``samples`` readings at the roll's step: its
    longest run of at least ``CURVE_HINT_SAMPLES`` consecutive samples (ψ order) that passes
    every check, when that run lies at one end of the roll the roll beside it away from the
    rest (:func:`_roll_beside`: centred on the run, a roll of the same span ran off again,
    calibrated P cubical 16 of bench_explore --finite 3 --anywhere --seed 13 --calibrate), else
    the run's middle; or None. A roll whose ρ grows many times
    within it (toward a cubical's inflection: 17 to 620 mm over 17° on the P-series jaw)
    and then pivots on the object's end corner keeps 6 smooth samples of 9, one too few for
    a touch (tools.bench_explore --finite 6 --anywhere --seed 17 --config
    config/jaw-p.yaml, cubical 30); the exploration aims its finger's next roll there
    (tactile_jaw.explore) instead of counting the roll as off the curved part. Returns (that
    hint, the stretch's ``FeltTouch.curve_span``), each None when no run passes."""
    found = _felt_run(config, touch)
    if found is None:
        return None, None
    head, tail, felt = found
    c = felt.contacts
    psi = np.sort([s.psi for s in touch.samples])
    step = float(np.median(np.diff(psi)))
    way = (1 if tail else 0) - (1 if head else 0)
    end = -1 if way > 0 else 0
    span = (float(c.psi[end]), float(c.x[end]), float(c.y[end]), way) if way else None
    if head and not tail:
        return _roll_beside(felt, np.arange(c.x.size), 0, 1.0, step * (samples - 1), samples), span
    if tail and not head:
        return _roll_beside(felt, np.arange(c.x.size), c.x.size - 1, -1.0, step * (samples - 1), samples), span
    m = c.x.size // 2
    return (float(c.x[m]), float(c.y[m]), float(c.psi[m]) - math.pi / 2), span


def moving_hint(config, felt: FeltTouch, samples: int) -> FeltTouch:
    """``felt``, a roll off the curved part with no run that passes every check
    (:func:`curve_hint` found none), with its ``curve_at`` where its stretch on which the
    contact still moved along a convex boundary (:func:`moving_stretch`) says the curve goes
    on: a roll of ``samples`` readings beside that stretch, away from the end of the roll
    that left it more (more samples outside the stretch's ψ range; :func:`_roll_beside`), or
    the stretch's middle when both ends left it alike. With fine encoders a curve whose ρ
    changes fast is no polynomial envelope within the lines' µm, so only this finds it: P
    hyperbola 92 of bench_explore --finite 20 --anywhere --seed 439 (the right pad's roll,
    5 of 9 lines on the branch, ρ 68 mm, then the end corner) rolled next about the other
    corner, retired, and was refused "closing segments, not a line" with no move (a pad
    already reached the curve). No ``curve_span``: the stretch leaves out the lines beside
    its ends, so its last contact is not where the curve ends."""
    stretch = moving_stretch(config, felt)
    if stretch is None:
        return felt
    c = stretch.contacts
    step = float(np.median(np.diff(np.sort([s.psi for s in felt.touch.samples]))))
    low, high = left_out(felt, stretch)
    if low == high:
        m = c.x.size // 2
        return replace(felt, curve_at=(float(c.x[m]), float(c.y[m]), float(c.psi[m]) - math.pi / 2))
    edge, sign = (0, 1.0) if low > high else (c.x.size - 1, -1.0)
    hint = _roll_beside(stretch, np.arange(c.x.size), edge, sign, step * (samples - 1), samples)
    return felt if hint is None else replace(felt, curve_at=hint)


def past_stretch(config, felt: FeltTouch, samples: int) -> FeltTouch:
    """``felt``, a roll off the curved part with no hint at one end of it (:func:`curve_hint`
    found no passing run, or one that lost samples at both ends; :func:`moving_hint` none),
    with its ``curve_at`` one roll on past its stretch on which the contact moved along a
    convex boundary (:func:`moving_stretch`, ``MOVED_RUN_WINDOWS`` windows: what
    :func:`curved_part` counts as a curved part), when that stretch leaves out more of the
    roll's lines at one end (:func:`left_out`: the roll ran onto a corner or closing segment
    there, as tactile_jaw.flat_phase.curve_stop reads it) than at the other: a roll of
    ``samples`` readings whose first reading lies one step past the stretch's other end
    (:func:`_roll_beside`), away from that corner; else ``felt`` unchanged. On a hyperbola's
    arm ρ shrinks several times toward the vertex within a roll, and with fine encoders no
    polynomial envelope follows such lines over a roll that also ran onto the end corner:
    P hyperbola 94 of bench_explore --finite 20 --anywhere --seed 571 (right roll at ψ
    73.5–91.5°: 3 lines through the end corner, 6 on the arm, ρ 124 → 23 mm) kept a run
    dropping 2 lines at each end and was rolled again at its middle, the same roll; calibrated
    P hyperbola 40 of seed 593 (5 lines on the corner, 4 on the arm: no passing run, a moving
    stretch of 4 windows, short of moving_hint's 5) had no hint and pressed flat instead; both were refused "no rolling touch on it was usable" with the
    arm past the stretch, ρ 30 → 10 mm, within the right pad's reach."""
    stretch = moving_stretch(config, felt, MOVED_RUN_WINDOWS)
    if stretch is None:
        return felt
    low, high = left_out(felt, stretch)
    if low == high:
        return felt
    c = stretch.contacts
    step = float(np.median(np.diff(np.sort([s.psi for s in felt.touch.samples]))))
    edge, sign = (c.x.size - 1, 1.0) if low > high else (0, -1.0)
    hint = _roll_beside(stretch, np.arange(c.x.size), edge, sign, step * (samples - 1), samples)
    return felt if hint is None else replace(felt, curve_at=hint)


def left_out(felt: FeltTouch, stretch: FeltTouch) -> tuple[int, int]:
    """How many of the roll ``felt``'s samples its ``stretch`` (felt from a subset of those
    samples: :func:`curved_part`, :func:`moving_stretch`) leaves out below and above its
    range of commanded ψ: the same readings compared, so no tolerance between commanded and
    measured ψ (µrad apart on the P-series jaw) decides a side. A flat press: (0, 0)."""
    if isinstance(felt.touch, FlatResult) or isinstance(stretch.touch, FlatResult):
        return 0, 0
    kept = [s.psi for s in stretch.touch.samples]
    whole = np.array([s.psi for s in felt.touch.samples], dtype=float)
    return int(np.sum(whole < min(kept))), int(np.sum(whole > max(kept)))


def _felt_run(config, touch: TouchResult) -> tuple[int, int, FeltTouch] | None:
    """(samples dropped at the start, at the end, the run felt) of the stretch of a roll that
    failed the smoothness test on which it still rolled on the curved part, or None: of the runs of at least ``CURVE_HINT_SAMPLES`` consecutive samples (ψ order)
    that pass every check with the fewest dropped (:func:`_passing_runs`), one at an end of
    the roll when such a run keeps that end and none keeps the other: the roll left the
    curved part at the other end alone, and the curve goes on past the kept end, where the
    next roll goes (:func:`curve_hint`) and a move points (tactile_jaw.flat_phase.curve_stop);
    else the first (the middle of the roll). P cubical 117 of bench_explore --finite 20
    --anywhere --seed 157: its right pad's 9-sample roll ran from ρ 25 mm onto the inflection
    and the end corner beside it; 5 samples passed dropping 2 at each end, or 3 and 1, or 4
    and 0, and the first, the roll's middle, was rolled again: the same roll, then a refusal
    naming no move."""
    runs, drop = [], None
    for head, tail, run in _passing_runs(config, touch, CURVE_HINT_SAMPLES):
        if drop is not None and head + tail > drop:
            break
        drop = head + tail
        runs.append((head, tail, run))
    if not runs:
        return None
    for end in (0, 1):  # a run keeps the low-ψ end (0: nothing dropped at the start) and none the other
        kept = [r for r in runs if r[end] == 0]
        if kept and not any(r[1 - end] == 0 for r in runs):
            return kept[0]
    return runs[0]


def _passing_runs(config, touch: TouchResult, least: int, margin: int = 0):
    """(samples dropped at the start, at the end, the run felt) of every run of consecutive
    samples (ψ order) that passes every check of :func:`feel` untrimmed, the fewest dropped
    first; each keeps at least ``least`` samples, also with ``margin`` more dropped beside
    each cut. At most ``MAX_RUN_FITS`` runs are felt: a roll's are all, a flat press's
    33-line scan's only those dropping the fewest lines (its runs are ~430 envelope fits)."""
    order = np.argsort([s.psi for s in touch.samples], kind="stable")
    n = order.size
    fits = 0
    for drop in range(1, n - least + 1):
        for head in range(drop + 1):
            tail = drop - head
            if n - tail - margin * (tail > 0) - (head + margin * (head > 0)) < least:
                continue
            if fits == MAX_RUN_FITS:
                return
            fits += 1
            felt = feel(config, _subset(touch, order[head : n - tail]), n - drop, trim=False)
            if felt.problem is None:
                yield head, tail, felt


def _subset(touch: TouchResult, taken) -> TouchResult:
    """The touch with only the samples ``taken`` (indices), in the order taken."""
    return replace(touch, samples=[touch.samples[i] for i in sorted(int(k) for k in taken)])


def _pad_u(lines: kin.PadLine, contacts: kin.TouchEnvelope) -> np.ndarray:
    """Each envelope contact's distance along its own reading's pad from the proximal end
    (PadLine.pad_coordinate), in the contacts' order (by ψ)."""
    taken = np.empty((contacts.order.size, 2))
    taken[contacts.order] = np.stack([contacts.x, contacts.y], axis=-1)
    return lines.pad_coordinate(taken)[contacts.order]


def on_corner(fit: EnvelopeFit) -> bool:
    """The touch rolled on a corner: its radius of curvature at the contact is below
    ``CORNER_RADIUS_MM`` or ``CORNER_SIGMAS`` of its deviation."""
    return bool(fit.rho < max(CORNER_RADIUS_MM, CORNER_SIGMAS * fit.sigma_rho))


def corner_in_doubt(fit: EnvelopeFit | None) -> bool:
    """A touch judged a corner (:func:`on_corner`) whose radius of curvature, within
    ``CORNER_SIGMAS`` of its deviation, reaches one that a roll ``WIDER_SPAN`` times wider at
    the same place (σ_ρ / WIDER_SPAN²) would not judge a corner: such a roll can tell a corner
    from tightly bent boundary. A corner is sure only when its radius stays a corner's at its
    deviation: with coarse encoders (σ_ρ of several mm over a short roll) a radius measured
    under ``CORNER_RADIUS_MM`` says nothing (an X-series ellipse's end of ρ 5.4 mm measured
    0.63 ± 3.78 mm)."""
    if fit is None or not on_corner(fit):
        return False
    wider = max(CORNER_RADIUS_MM, CORNER_SIGMAS * fit.sigma_rho / WIDER_SPAN ** 2)
    return bool(fit.rho + CORNER_SIGMAS * fit.sigma_rho >= wider)


def pivot_point(lines: kin.PadLine) -> tuple[float, float]:
    """The point the pad lines ``n(ψ_i)·p = d_i`` pass nearest (least squares): the corner
    a pad pivoted about."""
    p = kin.nearest_point(lines.normal, lines.d)
    return float(p[0]), float(p[1])


def clear_of_corners(config, usable: Sequence[FeltTouch], felt: Sequence[FeltTouch],
                     samples: int) -> tuple[list[FeltTouch], list[str]]:
    """The usable rolling touches without their samples that lie within their
    :func:`corner_clearance` of a corner another of the ``felt`` touches pivoted about
    (:attr:`FeltTouch.corner`, its radius of curvature below ``CLEARANCE_SIGMAS`` of its
    deviation) or past the end of the curved part where a roll of the same finger left it
    (:func:`curve_ends`) or whose pad lines pass through a corner the same finger's lines of
    its rolls and probes among ``felt`` pass through (:func:`on_shared_pivots`, beside a roll's
    own pivots, :func:`on_pivots`), and why each touch changed: a touch is felt again on its
    longest stretch of samples clear of the corners (:func:`feel`: it still needs
    ``MIN_SAMPLES_PER_TOUCH`` and passes every check again; samples beyond a corner's, whose
    contacts the envelope fit places past it, go too), else it is dropped. Other touches
    (and flat presses) are returned as they are."""
    corners = clearing_corners(felt)
    ends = curve_ends(felt)
    pivots = [t.pivot for t in felt if t.pivot is not None]
    pools: dict[str, Any] = {}  # each finger's pad lines of felt, gathered once (on_shared_pivots)
    kept, notes = [], []
    for t in usable:
        if t.contacts is None or t.fit is None:
            kept.append(t)
            continue
        c = t.contacts
        gaps = corner_gaps(c, corners) if corners.size else np.full((c.x.size, 1), np.inf)
        clearance = corner_clearance(t)
        near = gaps.min(axis=1) < clearance
        past = past_ends(c, ends.get(t.finger, []))
        shared, pivot = on_shared_pivots(config, t, felt, pools)
        on = on_pivots(t, pivots) | shared
        if not near.any() and not past.any() and not on.any():
            kept.append(t)
            continue
        run = longest_run(~(near | past | on))  # in ψ order: the roll's stretch between the corner's samples
        name = f"{t.finger}: touch {t.touch.touch}"
        if near.any():
            where = corners[np.argmin(gaps.min(axis=0))]
            why = (f"{int(near.sum())} of its {near.size} samples within {clearance:.2g} mm of the corner at "
                   f"({where[0]:.1f}, {where[1]:.1f}) mm another touch pivoted about")
        elif pivot is not None:
            why = f"{int(on.sum())} of its {on.size} samples with their pad line through the corner at {pivot.note()}"
        elif on.any():
            where = min((p for p, _ in pivots), key=lambda p: float(np.min(np.hypot(c.x - p[0], c.y - p[1]))))
            why = (f"{int(on.sum())} of its {on.size} samples with their pad line through the corner at "
                   f"({where[0]:.1f}, {where[1]:.1f}) mm another roll's lines turned about")
        else:
            why = (f"{int(past.sum())} of its {past.size} samples past the pad orientation where another roll of its "
                   f"finger left the curved part")
        if run.size:
            taken = sorted(int(c.order[j]) for j in run)
            again = feel(config, replace(t.touch, samples=[t.touch.samples[i] for i in taken]), samples)
            if again.problem is None:
                kept.append(again)
                left = near.size - int(np.sum(near | past | on)) - run.size
                notes.append(f"{name}: {why}: used without them" + (f" and the {left} beyond them" if left else ""))
                continue
            why += f"; without them: {again.problem.removeprefix(t.finger + ': ')}"
        notes.append(f"{name}: not used: {why}")
    return kept, notes


def curve_ends(felt: Sequence[FeltTouch]) -> dict[str, list[tuple[float, float, float, int]]]:
    """Per finger, where its rolls left the curved part at one end alone (``FeltTouch.curve_span``
    of a roll off the curve that still rolled on it): (ψ, x, y of the stretch's last contact on
    that end's side, +1 when the curve ends at higher ψ, −1 at lower). The pad normals at which a
    pad meets a finite object's curved part, convex toward it, are one interval of ψ whatever the
    roll: past its end the pad rests on the end corner (:func:`past_ends`). A usable roll's
    sample there lies on the corner, yet one line past the end is a tangent of the curve's
    continuation within ρδ²/2 (a µm), so the roll passes every check and the envelope places
    that contact 0.1–0.3 mm off along the pad (:func:`smooth_stretch`). P cubical 105 of bench_explore --finite 20
    --anywhere --seed 157 --config config/jaw-p.yaml: a usable roll's last sample lay 0.5° past
    the curve's end tangent (0.14 mm from the end corner; the other roll there, past it by 2.3°,
    was left out), its block of the refined fit's χ² was 23 on 15 rows, and no class fitted (p
    6.8e-4); without that sample: cubical, a +0.8 %, c +1.2 %."""
    ends: dict[str, list[tuple[float, float, float, int]]] = {}
    for t in felt:
        if t.curve_span is not None:
            ends.setdefault(t.finger, []).append(t.curve_span)
    return ends


def on_pivots(touch: FeltTouch, pivots: Sequence[tuple[np.ndarray, np.ndarray]]) -> np.ndarray:
    """Which samples of a usable ``touch`` (contacts' order) rest on one of the ``pivots``
    (:attr:`FeltTouch.pivot`: point, covariance): the contact within ``CORNER_CLEARANCE_MM`` of
    it and the sample's pad line through it within the limit at ``SMOOTH_ALPHA`` (1 dof) of
    the line's deviation and the point's along the line's normal. On a strictly convex
    stretch a tangent line meets the end corner only at it; a tangent one roll step (2.25°)
    before the end misses it by ρδ²/2, 15 µm at ρ 20 mm, 60 of a P-series line's deviations,
    while the 2 mm clearance of a corner roll would drop good samples beside a pivot that
    rough rolls found: P semicubicals 129 and 131 of finite seed 241 and 125 of seed 227 each
    lost a usable roll whose samples lay on the curve (≤ 0.4 µm off) 0.4–2 mm from the
    cusp-side corner, and were refused with 2 touches."""
    c = touch.contacts
    on = np.zeros(c.x.size, bool)
    if not pivots or touch.lines is None or touch.fit is None:
        return on
    normal, d = np.asarray(touch.lines.normal)[c.order], np.asarray(touch.lines.d)[c.order]
    sigma = np.asarray(touch.fit.line_sigma, dtype=float)
    for point, cov in pivots:
        miss = normal @ point - d
        limit = chi2_limit(SMOOTH_ALPHA, 1) * (sigma ** 2 + np.einsum("ij,jk,ik->i", normal, cov, normal))
        on |= (miss ** 2 <= limit) & (np.hypot(c.x - point[0], c.y - point[1]) < CORNER_CLEARANCE_MM)
    return on


@dataclass(frozen=True)
class SharedPivot:
    """A point a finger's pad lines of several touches pass through (:func:`shared_pivot`), with
    what tells it from a curve: the lines' χ² about the point and the χ² of the least-bent
    curve the usable roll admits, a circle of radius ``rho_low`` (eq. of a circle's tangent
    lines d = n·c − ρ)."""

    point: np.ndarray  # (2,) mm
    lines: int  # how many of the finger's lines are held to it (those within its arc of normals)
    touches: int  # how many of its touches those lines are of
    span_rad: float  # the spread of their pad normals
    chi2: float  # their χ² about the point (lines − 2 dof)
    rho_low: float  # mm: the least radius of curvature the roll admits, ρ − CORNER_SIGMAS σ_ρ
    chi2_rho: float  # their χ² about the best circle of that radius

    def note(self) -> str:
        return (f"({self.point[0]:.1f}, {self.point[1]:.1f}) mm that {self.lines} pad lines of {self.touches} of "
                f"its finger's touches pass through over {math.degrees(self.span_rad):.0f} deg (chi2 "
                f"{self.chi2:.3g} on {self.lines - 2} dof; a curve of radius >= {self.rho_low:.1f} mm: chi2 "
                f"{self.chi2_rho:.3g})")


def touch_pad_lines(finger, touch: TouchResult) -> tuple[kin.PadLine, np.ndarray] | None:
    """A rolling touch's or probe's pad lines (readings' order) with backlash and declared
    compliance taken out as :func:`feel` takes them out, and each line's joint σ's (n, joints,
    rad: its touch's quantization and offsets, tactile_jaw.envelope.joint_noise, independent
    here); None when it has fewer than 3 readings (the load's contacts are an envelope's) or
    its load reversed."""
    samples = touch.samples
    if len(samples) < 3:
        return None
    q = kin.ticks_to_angles(finger.joints, np.array([s.ticks for s in samples], dtype=float))
    try:
        loads = touch_loads(finger, q, kin.PadLine.stack([s.line for s in samples]))
        if loads.reversed is not None:
            return None
        q = q - loads.offsets
        bent = touch_compliance(finger, samples, q, kin.finger_pad_line(finger, q))
    except InputError:
        return None
    if bent is not None:
        q = q - bent.turns
    noise = joint_noise(finger, loads.known, bent)
    sigma = np.hypot(noise.quantization, np.asarray(noise.offset_rad, dtype=float))
    return kin.finger_pad_line(finger, q), np.broadcast_to(sigma, q.shape)


def finger_pad_lines(config, felt: Sequence[FeltTouch], finger: str
                     ) -> tuple[kin.PadLine, np.ndarray, np.ndarray] | None:
    """Every pad line finger ``finger`` felt on its rolls and probes of ``felt`` (flat presses
    aside), each touch's readings at their orientation (:func:`at_orientation`) as
    :func:`touch_pad_lines` gives them: (the lines, their joint σ's, each line's touch's index
    in ``felt``), None when there are none. The same lines whether a probe was felt as the run
    felt it or as replay does."""
    f = config.finger(finger)
    lines, sigmas, owner = [], [], []
    for k, t in enumerate(felt):
        if t.finger != finger or isinstance(t.touch, FlatResult):
            continue
        got = touch_pad_lines(f, at_orientation(t.touch))
        if got is not None:
            lines.append(got[0])
            sigmas.append(got[1])
            owner.append(np.full(got[1].shape[0], k))
    if not lines:
        return None
    joined = kin.PadLine(**{f.name: np.concatenate([np.asarray(getattr(ln, f.name)) for ln in lines])
                            for f in fields(kin.PadLine)})
    return joined, np.concatenate(sigmas), np.concatenate(owner)


def circle_chi2(normal: np.ndarray, d: np.ndarray, sigma: np.ndarray, rho: float) -> float:
    """The least χ² of pad lines ``normal``·p = ``d`` (deviations ``sigma``, mm) about the
    tangents of a circle of radius ``rho`` (d = n·c − ρ, its centre c fitted): ρ = 0 is a
    point the lines pass through."""
    w = 1.0 / sigma
    a, b = normal * w[:, None], (d + rho) * w
    centre = np.linalg.lstsq(a, b, rcond=None)[0]
    return float(np.sum((a @ centre - b) ** 2))


def shared_pivot(finger, pool: tuple[kin.PadLine, np.ndarray, np.ndarray], seed: np.ndarray, roll: FeltTouch
                 ) -> SharedPivot | None:
    """The point the finger's ``pool`` of lines (:func:`finger_pad_lines`) passes through near
    ``seed``, when it is a corner the usable ``roll`` rested on, else None. Its lines are those
    whose miss lies within the limit at ``SMOOTH_ALPHA`` (1 dof) of its deviation
    (tactile_jaw.envelope.point_miss_sigma), the point refitted on them until they stay the
    same (at least ``SEGMENT_CORNER_LINES``: two lines always meet). The normals of a convex
    boundary's point form one arc and its support function is single-valued, so every line of
    the finger whose normal lies between theirs is held to the point too (a selection by miss
    alone would make a curve's tangents near any of its points look like a pivot). It is a
    corner when those lines' normals spread wider than the roll's own, their χ² about the point
    lies within its limit at ``SMOOTH_ALPHA`` (lines − 2 dof), and a curve as little bent as the
    roll admits, a circle of radius
    ρ_low = ρ − ``CORNER_SIGMAS`` σ_ρ (the roll's envelope fit), explains them worse than the
    point by more than the limit at ``SMOOTH_ALPHA`` on 1 dof (the likelihood ratio of the two):
    a smooth boundary's tangent lines over a spread Δ miss any one point by about ρ(1 − cos Δ/2)
    (the X-series 13° roll cannot tell ρ 15 mm from a pivot; its lines and the same finger's
    probes over 48° tell it from ρ ≳ 1.5 mm)."""
    lines, joint_sigma, owner = pool
    normal, d = np.asarray(lines.normal, dtype=float), np.asarray(lines.d, dtype=float)
    limit1 = chi2_limit(SMOOTH_ALPHA, 1)
    point, taken = np.asarray(seed, dtype=float), None
    for _ in range(SHARED_PIVOT_ROUNDS):
        sigma = point_miss_sigma(finger, lines, point, joint_sigma)
        on = (normal @ point - d) ** 2 <= limit1 * sigma ** 2
        if on.sum() < SEGMENT_CORNER_LINES or (taken is not None and np.array_equal(on, taken)):
            break
        taken = on
        point = kin.nearest_point(normal[on] / sigma[on, None], d[on] / sigma[on])
    if taken is None or not np.array_equal(on, taken):
        return None
    rho_low = float(roll.fit.rho - CORNER_SIGMAS * roll.fit.sigma_rho)
    own = np.asarray(roll.lines.psi, dtype=float)
    psi = np.remainder(np.asarray(lines.psi, dtype=float) - own[0] + math.pi, 2 * math.pi) - math.pi  # about the roll
    own = np.remainder(own - own[0] + math.pi, 2 * math.pi) - math.pi
    # a boundary point's normals are one arc: every line of the finger within it is held to the point
    arc = (psi >= psi[on].min()) & (psi <= psi[on].max())
    k = int(arc.sum())
    if rho_low <= 0.0 or float(np.ptp(psi[arc])) <= float(np.ptp(own)):
        return None
    chi2 = circle_chi2(normal[arc], d[arc], sigma[arc], 0.0)
    chi2_rho = circle_chi2(normal[arc], d[arc], sigma[arc], rho_low)
    if chi2 > chi2_limit(SMOOTH_ALPHA, k - 2) or chi2_rho - chi2 <= limit1:
        return None
    return SharedPivot(point, k, int(np.unique(owner[arc]).size), float(np.ptp(psi[arc])), chi2, rho_low, chi2_rho)


def on_shared_pivot(finger, roll: FeltTouch, roll_lines: tuple[kin.PadLine, np.ndarray] | None,
                    point: np.ndarray) -> np.ndarray:
    """Which samples of the usable ``roll`` (contacts' order) have their pad line
    (``roll_lines``, :func:`touch_pad_lines` of the roll) through ``point`` within the limit at
    ``SMOOTH_ALPHA`` (1 dof) of the line's deviation there."""
    if roll_lines is None:
        return np.zeros(roll.contacts.x.size, bool)
    lines, joint_sigma = roll_lines
    sigma = point_miss_sigma(finger, lines, point, joint_sigma)
    on = (np.asarray(lines.normal) @ point - np.asarray(lines.d)) ** 2 <= chi2_limit(SMOOTH_ALPHA, 1) * sigma ** 2
    return on[roll.contacts.order]


def on_shared_pivots(config, roll: FeltTouch, felt: Sequence[FeltTouch],
                     pools: dict[str, Any] | None = None) -> tuple[np.ndarray, SharedPivot | None]:
    """Which samples of the usable ``roll`` (contacts' order) rest on a corner its finger's
    lines of every touch of ``felt`` pass through (:func:`shared_pivot`, sought from the point
    each of those touches' lines pass nearest), and the corner that holds most of them (None:
    none); ``pools``: each finger's lines of ``felt`` (:func:`finger_pad_lines`) as gathered so
    far for other rolls of the same ``felt``, filled here. Only a corner the roll's middle line passes through counts: the roll states its
    radius of curvature at its middle contact, and the radius may shrink toward its ends (a
    hyperbola's vertex, ρ = b²/a a few mm, whose tangents over 20° pass within an X-series line's
    noise of one point: 6 of X finite 617's rolls on a curve, each with 1–3 end samples through
    such a point 10–23 mm from any corner; the 11 whose middle passed through one lay 0.04–0.37
    mm from a true corner). A support line of a convex boundary through one of its points
    touches it there, so such a sample's contact is that corner, whatever the envelope fit
    placed: X cubical
    106 of bench_explore --finite 20 --anywhere --seed 617, moved as its first refusal advised:
    the left rolls at −121…−103° and −119…−101° (ρ 33.9 ± 4.8, 20.5 ± 4.7 mm) had 7 and 8 of
    9 lines through the block's closing corner within 0.004–0.12 mm, as had the finger's probes
    and rejected rolls there, −121° to −73° in all, and the answer was ellipse."""
    c = roll.contacts
    on = np.zeros(c.x.size, bool)
    if roll.lines is None or roll.fit is None or roll.fit.rho - CORNER_SIGMAS * roll.fit.sigma_rho <= 0.0:
        return on, None
    finger = config.finger(roll.finger)
    pools = {} if pools is None else pools
    if roll.finger not in pools:
        pools[roll.finger] = finger_pad_lines(config, felt, roll.finger)
    pool = pools[roll.finger]
    if pool is None:
        return on, None
    lines, _, owner = pool
    roll_lines = touch_pad_lines(finger, roll.touch)
    best, most = None, 0
    for k in np.unique(owner):
        mine = owner == k
        seed = kin.nearest_point(np.asarray(lines.normal)[mine], np.asarray(lines.d)[mine])
        pivot = shared_pivot(finger, pool, seed, roll)
        if pivot is None:
            continue
        these = on_shared_pivot(finger, roll, roll_lines, pivot.point)
        if not these[c.x.size // 2]:  # the roll states its radius at its middle contact, not at its ends
            continue
        on |= these
        if int(these.sum()) > most:
            best, most = pivot, int(these.sum())
    return on, best


def past_ends(c: kin.TouchEnvelope, ends: Sequence[tuple[float, float, float, int]]) -> np.ndarray:
    """Which contacts of ``c`` lie past one of a finger's ``ends`` (:func:`curve_ends`): their pad
    orientation beyond the end's and their contact within ``CORNER_CLEARANCE_MM`` of the end's
    (on the end corner, where the stretch left off; a roll can also lose an end to its pad's
    end, beyond which the curve goes on and its contacts move away)."""
    past = np.zeros(c.psi.shape, bool)
    for edge, x, y, way in ends:
        beyond = way * (np.remainder(c.psi - edge + math.pi, 2 * math.pi) - math.pi) > 0.0
        past |= beyond & (np.hypot(c.x - x, c.y - y) < CORNER_CLEARANCE_MM)
    return past


def corner_gaps(c: kin.TouchEnvelope, corners: np.ndarray) -> np.ndarray:
    """(samples, k) the distances (mm) of the contacts ``c`` from each of the ``corners`` (k, 2)."""
    return np.hypot(c.x[:, None] - corners[:, 0], c.y[:, None] - corners[:, 1])


def near_corners(c: kin.TouchEnvelope, corners: np.ndarray, clearance: float = CORNER_CLEARANCE_MM) -> np.ndarray:
    """(samples,) which of the contacts ``c`` lie within ``clearance`` (mm; a touch's
    :func:`corner_clearance`) of one of the ``corners`` (k, 2; none near when k = 0)."""
    if not len(corners):
        return np.zeros(c.x.size, bool)
    return corner_gaps(c, corners).min(axis=1) < clearance


def corner_clearance(touch: FeltTouch) -> float:
    """How near a corner (mm) a usable roll's samples may be pivots about it rather than the
    curve (ρ the roll's radius of curvature, Δψ its pad's turn between samples, σ its largest
    pad line deviation): over a turn δ a pivot and an arc differ by ρδ²/2, which the lines hide
    while δ < √(2σ/ρ), within the arc √(2σρ) of the corner, taken ``CLEARANCE_SPREAD`` times; and
    the envelope fit smooths the support function's kink at the corner over a sample, placing a
    pivoting sample's contact within about one step's arc ρΔψ of it. The larger, at most
    ``CORNER_CLEARANCE_MM``: X-series lines (σ ≈ 0.05 mm, ρ 10–20 mm) keep the 2 mm measured
    there; on P-series lines (σ ≈ 0.2 µm) it is one step's arc (0.4–0.8 mm on 2.25° steps),
    keeping the samples next to a part's end where its curvature, most telling, grows (a
    semicubical's tip toward its cusp)."""
    fit, c = touch.fit, touch.contacts
    if fit is None or c is None or c.psi.size < 2 or not np.size(fit.line_sigma):
        return CORNER_CLEARANCE_MM
    hidden = CLEARANCE_SPREAD * math.sqrt(2.0 * float(np.max(fit.line_sigma)) * abs(fit.rho))
    step = abs(fit.rho) * float(np.median(np.abs(np.diff(np.sort(c.psi)))))
    return min(CORNER_CLEARANCE_MM, max(hidden, step))


def clearing_corners(felt: Sequence[FeltTouch]) -> np.ndarray:
    """(k, 2) the corners the ``felt`` touches pivoted about whose radius of curvature is below
    ``CLEARANCE_SIGMAS`` of its deviation, but for a corner in doubt (:func:`corner_in_doubt`)
    whose radius a usable roll measured there more finely (:func:`measured_there`: the wider
    roll at that place), which is no corner; and the end corners of the closing segments
    rolls crossed (``FeltTouch.segment_corners``): the corners :func:`clear_of_corners`
    clears samples around."""
    return np.array([t.corner for t in felt if sure_corner(t, felt)]
                    + [p for t in felt for p in t.segment_corners], dtype=float).reshape(-1, 2)


def sure_corner(touch: FeltTouch, felt: Sequence[FeltTouch]) -> bool:
    """Whether ``touch`` pivoted about a corner :func:`clearing_corners` clears around: judged a
    corner, sure to be one (:func:`clears_around`), and not a corner in doubt that a usable roll of
    ``felt`` measured as tightly bent boundary there (:func:`measured_there`)."""
    return (touch.corner is not None and clears_around(touch.fit)
            and not (corner_in_doubt(touch.fit) and measured_there(touch, felt)))


def clears_around(fit: EnvelopeFit) -> bool:
    """Whether a roll judged a corner is sure to be one, so that the samples other rolls have
    around it are not the curved part's (:func:`clearing_corners`): its radius of curvature
    is below ``CLEARANCE_SIGMAS`` of its deviation (coarse encoders: no radius told from 0),
    or below ``CORNER_RADIUS_MM`` by that many deviations (fine encoders: a roll that began on
    the curve's end and pivoted about its end corner measures ρ 0.083 ± 0.017 mm on the
    P-series jaw, 5 deviations from 0 yet surely under :func:`on_corner`'s floor; the rolls that ran onto that
    corner kept a sample 0.2–0.6 mm off the curve and no class fitted: bench_explore --finite
    20 --anywhere --seed 107 --config config/jaw-p.yaml, cubical 116). A hump measured
    coarsely (ρ 6.5 ± 3.6 mm) passes neither."""
    if fit.rho < -(CORNER_RADIUS_MM + CORNER_SIGMAS * fit.sigma_rho):
        return False
    return bool(fit.rho < CLEARANCE_SIGMAS * fit.sigma_rho
                or fit.rho + CLEARANCE_SIGMAS * fit.sigma_rho < CORNER_RADIUS_MM)


def clear_side(touch: FeltTouch, corners: np.ndarray, span: float, samples: int) -> tuple[float, float, float] | None:
    """Where to roll again when a usable ``touch`` ran near a corner (``corners``,
    :func:`clearing_corners`) at one end of its roll and too few of its samples are clear of it
    (:func:`clear_of_corners` dropped it): the roll of ``span`` (rad) and ``samples`` readings
    whose nearest reading to the corner is the touch's clear sample next to the corner's
    (its longest run clear of the corner, which must reach the roll's other end), one
    reading's step farther, so that every contact lies on the curved part the touch felt clear
    of the corner and beyond it away from the corner (the support point of a boundary convex
    toward the pad moves one way along it as ψ turns). Returns (x, y, φ) of that roll's middle:
    its contact predicted by the circle the clear samples lie on (least squares, p = c + R n(ψ)),
    φ = ψ − π/2; None when the corner's samples are not at one end of the roll, or no clear
    sample is left. A 9-sample roll that ran 4 samples onto the object's end corner keeps 5,
    too few to use, and the planner's next roll for that finger went to the corner again (P
    cubical 107 of bench_explore --finite 20 --anywhere --seed 97 --config config/jaw-p.yaml:
    refused, "no rolling touch usable clear of the corners")."""
    c = touch.contacts
    if c is None or not corners.size:
        return None
    near = near_corners(c, corners, corner_clearance(touch))
    clear = longest_run(~near)  # the samples beyond the corner's, which the fit places past it, go too
    if not near.any() or clear.size < 3:
        return None
    if clear[0] > 0 and clear[-1] == near.size - 1:  # the corner at the low-ψ end: roll toward higher ψ
        edge, sign = clear[0], 1.0
    elif clear[0] == 0 and clear[-1] < near.size - 1:
        edge, sign = clear[-1], -1.0
    else:
        return None
    return _roll_beside(touch, clear, edge, sign, span, samples)


def on_osculating_circle(x_m: float, y_m: float, psi_m: float, rho: float, psi: float) -> np.ndarray:
    """The contact (x, y, mm) of a pad line of normal angle ``psi`` on the circle of radius
    ``rho`` through the contact (``x_m``, ``y_m``) whose pad normal is ``psi_m``: a stretch's
    osculating circle, p(ψ) = p_m − ρ (n(ψ) − n(ψ_m)) (a circle's pad lines d(ψ) = n(ψ)·centre − ρ
    touch it at centre − ρ n(ψ)): where a roll beside a stretch (:func:`_roll_beside`) or on
    along it (tactile_jaw.explore.felt_curve_roll) is aimed."""
    return np.array([x_m, y_m]) - rho * (kin.unit(psi) - kin.unit(psi_m))


def _roll_beside(touch: FeltTouch, good: np.ndarray, edge: int, sign: float, span: float,
                 samples: int) -> tuple[float, float, float] | None:
    """(x, y, φ) of the middle of a roll of ``span`` (rad) and ``samples`` readings whose
    reading nearest contact ``edge`` of ``touch`` (contacts' order) lies one reading's step
    beyond it toward ψ of ``sign``: its contact predicted from the middle one of the ``good``
    contacts (a roll's contacts are surest along the pad in its middle) along the circle of the
    touch's radius of curvature ρ, p(ψ) = p_m − ρ (n(ψ) − n(ψ_m)) (a circle's pad lines
    d(ψ) = n(ψ)·centre − ρ touch it at centre − ρ n(ψ)); φ = ψ − π/2; None if not finite."""
    c = touch.contacts
    step = span / max(samples - 1, 1)
    psi = float(c.psi[edge]) + sign * (0.5 * span + step)
    m = good[good.size // 2]
    rho = touch.fit.rho if touch.fit is not None and touch.fit.rho > 0.0 else 0.0
    point = on_osculating_circle(c.x[m], c.y[m], float(c.psi[m]), rho, psi)
    if not np.all(np.isfinite(point)):
        return None
    return float(point[0]), float(point[1]), psi - math.pi / 2


def measured_there(corner: FeltTouch, felt: Sequence[FeltTouch]) -> bool:
    """Did a usable rolling touch of ``felt`` measure the boundary's radius of curvature at
    the point the touch ``corner`` pivoted about, at least ``WIDER_SPAN`` times more finely
    (σ_ρ): its middle contact, where its κ and ρ are taken, within ``CORNER_CLEARANCE_MM`` of
    that point? It passed the corner test there (:func:`on_corner`), so the corner was tightly
    bent boundary measured coarsely: the wider roll at an X-series ellipse's end (ρ 5.4 mm,
    measured 0.63 ± 3.78 mm over 18°, then 8.99 ± 0.92 mm over 36°), whose samples that
    corner would otherwise trim. A real corner rolled wider pivots again (ρ ≈ 0); a roll of
    the same span that runs onto a real end corner measures no finer than the corner's
    own roll and does not count. The rule reads the touches alone, so replay applies it as
    the run did."""
    for t in felt:
        u = t.fit
        if (t.problem is not None or u is None or isinstance(t.touch, FlatResult)
                or not u.sigma_rho * WIDER_SPAN <= corner.fit.sigma_rho):
            continue
        m = len(t.contacts.x) // 2
        if math.hypot(t.contacts.x[m] - corner.corner[0], t.contacts.y[m] - corner.corner[1]) < CORNER_CLEARANCE_MM:
            return True
    return False


def longest_run(mask: np.ndarray) -> np.ndarray:
    """Indices of the longest stretch of consecutive True values of ``mask`` (the first of equals)."""
    best, start = np.zeros(0, dtype=int), None
    for i, v in enumerate(np.append(mask, False)):
        if v and start is None:
            start = i
        elif not v and start is not None:
            if i - start > best.size:
                best = np.arange(start, i)
            start = None
    return best


def off_curve_reason(fit: EnvelopeFit, contacts, turn_rad: float,
                     segment: tuple[float, int, tuple[tuple[float, float], ...]] | None = None) -> str | None:
    """Why a touch fell off the object's curved part, or None: on a corner (the radius of
    curvature at the contact is below ``CORNER_RADIUS_MM`` or ``CORNER_SIGMAS`` of its
    deviation: the contact stayed put while the pad turned), across a closing segment
    (``segment``, :func:`crossed_segment` of the touch: the order rule needed more than a
    cubic and the pad lines pass through two points, a segment's end corners, within their
    noise) or across a corner or closing segment (the pad lines are no smooth curve's
    tangents: their χ² about the envelope fit above its limit at ``SMOOTH_ALPHA``: a straight
    segment bridged between two corners makes d(ψ) kink)."""
    m = len(contacts.x) // 2
    if on_corner(fit):
        return (f"corner: the contact stayed near ({contacts.x[m]:.1f}, {contacts.y[m]:.1f}) mm while the pad "
                f"turned {np.degrees(turn_rad):.0f} deg (radius of curvature {fit.rho:.2f} ± {fit.sigma_rho:.2f} mm)")
    if segment is not None:
        chi2, split, _ = segment
        n = len(contacts.x)
        return (f"off the curved part: the pad lines pass through two points within their noise (chi2 {chi2:.3g} "
                f"on {n - 4} dof, {split} and {n - split} lines): the roll crossed a straight closing segment")
    return rough(fit)


def crossed_segment(fit: EnvelopeFit, contacts, lines: kin.PadLine | None
                    ) -> tuple[float, int, tuple[tuple[float, float], ...]] | None:
    """Whether a roll crossed a straight closing segment (the order rule needed more than a
    cubic and the pad ``lines`` pass through two points within their noise, better than the
    polynomial by Akaike's criterion: :func:`pivots_chi2`): its χ², the first run's length,
    and the segment's end corners the roll pivoted about, each through at least
    ``SEGMENT_CORNER_LINES`` lines (two lines always meet). Those are the object's corners: a
    roll of the other finger that ran onto one kept its sample there, a µm from the curve's
    continuation's tangent, and no class fitted (P semicubical 123 of bench_explore --finite 20
    --anywhere --seed 199 --config config/jaw-p.yaml: that touch's block of the χ² was 515 on
    6); :func:`clearing_corners` clears the samples around them. None when it did not."""
    n = len(contacts.x)
    if lines is None or contacts.degree <= MIN_DEGREE or n < 6:
        return None
    chi2, split, points = pivots_chi2(lines, contacts, fit.line_sigma)
    # two points (4 numbers and a split) against the polynomial (degree + 1): Akaike's criterion
    if not (chi2 <= chi2_limit(SMOOTH_ALPHA, n - 4) and chi2 + 2 * 5 < fit.chi2 + 2 * (contacts.degree + 1)):
        return None
    runs = (split, n - split)
    return chi2, split, tuple(p for p, k in zip(points, runs) if k >= SEGMENT_CORNER_LINES)


def pivot_run(lines: kin.PadLine, contacts, sigma: np.ndarray) -> tuple[np.ndarray, np.ndarray] | None:
    """The corner a run of a roll's pad lines turned about, or None: of the runs of at least
    ``SEGMENT_CORNER_LINES`` consecutive lines (ψ order), the longest (the first of equals)
    whose circle envelope d_i = n_i·c − ρ (least squares, each line by its deviation
    ``sigma``, mm, ψ order) fits them within its limit at ``SMOOTH_ALPHA`` and whose radius
    is a corner's at ``CORNER_SIGMAS`` of its deviation, |ρ| + CORNER_SIGMAS σ_ρ <
    ``CORNER_RADIUS_MM`` (fine encoders only: with coarse ones three lines of any tight curve
    meet within their noise); the point they pass nearest and its covariance (mm, mm²),
    which :func:`on_pivots` clears the lines through. A roll that ran off the curved
    part onto its end corner is rough, but its lines there all pass through that corner:
    calibrated P semicubical 69 of bench_explore --finite 10 --anywhere --seed 281 (run on
    def5a72), right roll 7 (2 lines on the curve, 7 through the end corner within 2 σ, ρ of
    the whole roll 10.5 mm) and left roll 6 (7 of 9, whole-roll ρ −51.7 mm: no corner by
    :func:`clears_around`); their other usable roll kept its last sample 0.7° past the
    curve's end tangent and 0.74 mm past the corner, the refined truth's χ² was 114 on 15
    and the answer the other branch's semicubical, a +89 %, b −452 %, σ 0.1 %. Every window
    is fitted, no early stop: rolls have at most 9 lines (28 windows); measured on the logs of
    session 22's held-out runs (P, X, calibrated P), 0–241 ms per exploration, median ≤ 1 ms,
    about 1 % of an exploration's CPU at worst (X rand18 of seed 269: 241 ms of 20 s)."""
    normal, d = np.asarray(lines.normal)[contacts.order], np.asarray(lines.d)[contacts.order]
    n = d.size
    for k in range(n, SEGMENT_CORNER_LINES - 1, -1):
        for start in range(n - k + 1):
            part = slice(start, start + k)
            w = 1.0 / np.asarray(sigma, dtype=float)[part]
            a = np.column_stack((normal[part], -np.ones(k))) * w[:, None]
            b = d[part] * w
            coef = np.linalg.lstsq(a, b, rcond=None)[0]
            chi2 = float(np.sum((a @ coef - b) ** 2))
            cov = np.linalg.pinv(a.T @ a)
            rho, sigma_rho = float(coef[2]), math.sqrt(max(float(cov[2, 2]), 0.0))
            if (k == 3 or chi2 <= chi2_limit(SMOOTH_ALPHA, k - 3)) and \
                    abs(rho) + CORNER_SIGMAS * sigma_rho < CORNER_RADIUS_MM:
                a = normal[part] * w[:, None]
                return kin.nearest_point(a, b), np.linalg.inv(a.T @ a)
    return None


def slid_end(lines: kin.PadLine, fit: EnvelopeFit) -> tuple[str, float, int] | None:
    """Whether a rolling touch is a pad end sliding along a straight face: the pad end
    ("proximal" or "distal") whose points over the readings lie on a straight line within the
    pad lines' deviations (χ² of their distances from the line fitted to them within its limit
    at ``SMOOTH_ALPHA``), with that χ² and its dof; None when neither does or the deviations
    exceed ``SLIDE_MAX_SIGMA_MM`` (coarse encoders cannot tell). The pad lines of such a slide
    have a smooth envelope a few mm inside the pad (random block 2 of ``bench_explore --finite
    10 --anywhere --classes line --config config/jaw-p.yaml --seed 11``: ρ 13.5 ± 0.014 and
    20.3 ± 0.014 mm, the proximal end on one line within 0.2 µm), which was taken for two
    touches of a curve: no class fit them, and no flat press followed."""
    return sliding_end(lines.at(np.asarray(fit.contacts.order)), fit.line_sigma)


def sliding_end(lines: kin.PadLine, sigma) -> tuple[str, float, int] | None:
    """:func:`slid_end` of pad ``lines`` (ψ order) of deviations ``sigma`` (mm, the same order)."""
    sigma = np.asarray(sigma, dtype=float)
    n = sigma.size
    if n < 4 or not np.all(np.isfinite(sigma)) or np.any(sigma <= 0.0) or np.max(sigma) > SLIDE_MAX_SIGMA_MM:
        return None
    for name in ("proximal", "distal"):
        chi2 = float(np.sum((kin.straight_line(np.asarray(getattr(lines, name), dtype=float)).v / sigma) ** 2))
        if chi2 <= chi2_limit(SMOOTH_ALPHA, n - 2):
            return name, chi2, n - 2
    return None


def rough(fit: EnvelopeFit) -> str | None:
    """Why a touch's pad lines are no smooth curve's tangents, or None: their χ² about the
    envelope fit above its limit at ``SMOOTH_ALPHA`` (a roll across a corner or a closing
    segment, or, with fine encoders, one that ran onto the end corner: :func:`smooth_stretch`)."""
    if fit.dof > 0 and fit.chi2 > chi2_limit(SMOOTH_ALPHA, fit.dof):
        return (f"off the curved part: the pad lines are no smooth curve's tangents (chi2 {fit.chi2:.3g} on "
                f"{fit.dof} dof): the roll crossed a corner or a straight closing segment")
    return None


def pivots_chi2(lines: kin.PadLine, contacts, sigma: np.ndarray
                ) -> tuple[float, int, tuple[tuple[float, float], ...]]:
    """How well two points explain a touch's pad lines (ψ order): the least χ², over the
    splits into a first run of ≥ 2 lines through one point and the rest through another (a
    pad rolled across a straight segment rests on one end corner, then on the other), of the
    lines' distances from their point, each by its deviation ``sigma`` (mm, ψ order); the
    first run's length; and the two points (the first run's first)."""
    normal, d = np.asarray(lines.normal)[contacts.order], np.asarray(lines.d)[contacts.order]
    best, split, points = math.inf, 0, ()
    for k in range(2, normal.shape[0] - 1):
        chi2, found = 0.0, []
        for part in (slice(0, k), slice(k, None)):
            point = kin.nearest_point(normal[part] / sigma[part, None], d[part] / sigma[part])
            chi2 += float(np.sum(((normal[part] @ point - d[part]) / sigma[part]) ** 2))
            found.append((float(point[0]), float(point[1])))
        if chi2 < best:
            best, split, points = chi2, k, tuple(found)
    return best, split, points


def workspace_reach(config) -> Reach:
    """The jaw's workspace disk (config ``workspace``) as the recognizer's reach: where its
    ``next_touch`` may point."""
    (x, y), radius = config.workspace.center_mm, config.workspace.radius_mm
    return Reach(float(x), float(y), float(radius))


def curved_part(config, felt: Sequence[FeltTouch], checked: Collection[int] = frozenset()) -> FeltTouch | None:
    """The first of the ``felt`` touches that rolled on a curved part of the boundary, or
    None: a flat press whose scan (the pad turning toward a seat, 20 lines over up to 60°)
    :func:`feel` accepts as a roll (its pad lines a smooth curve's tangents, its radius of
    curvature clear of a corner's, its contacts on the pad's face), or does once the lines
    past the pad's end are left out (:func:`on_pad_face`). Short rolling touches
    beside a corner are not counted: at 4,096 ticks a pivot passed for radius 18.6 ± 4.2 mm
    (tests/tools/test_demo_block_corner.py). A finite
    object of a curved class has straight segments only where it is closed, so once a curved
    part was felt the faces the pads pressed flat are closing segments, and one face's
    presses are no line (:func:`curve_refusal`; tactile_jaw.flat.recognized_touches). A
    block shows none: its corners are pivots (radius ≈ 0) and a pad end sliding on a face is
    no contact on the pad's face. A rolling touch that crossed a corner or closing segment
    (its lines no smooth curve's tangents) yet rolled on a curved part over a stretch of it
    (``curve_at``, :func:`curve_hint`) counts too, as that stretch (:func:`curved_stretch`):
    the corners it crossed are a finite curved object's, and its straight faces are closing
    segments (P cubical 116 of bench_explore --finite 20 --anywhere --seed 139: the left pad's
    two rolls kept 5 smooth samples of 9, ρ 43.9 ± 0.07 mm, beside the curve's end corner,
    and the right pad's presses on a closing segment were answered line); without such a
    stretch, one on which its contact moved along a convex boundary (:func:`moving_stretch`:
    a pivot keeps it fixed) over ``MOVED_RUN_WINDOWS`` windows of three lines or more, more than
    the two that straddle a pivot's change (P cubical 21 of bench_explore --finite 4 --anywhere
    --follow --seed 191: the left pad's roll pivoted on the curve's end corner, then its last
    lines moved along the curve, ρ 9–127 ± 0.4 mm over 3 windows, and the right pad's presses
    on a closing segment were answered line). Every roll is held to that test, whatever
    dropped it: one :func:`feel` found usable and :func:`clear_of_corners` dropped later (its
    samples near a corner another touch pivoted about, too few left), one whose contact reached
    a pad end. Its radius ≥ 2 σ_ρ alone is no curve beside a corner (a pivot passed for 18.6 ±
    4.2 mm at 4,096 ticks), but three windows each ≥ ``MOVED_SIGMAS`` σ_ρ are a contact moving
    along the boundary, which no pivot does (P cubical example scaled 1.5×, turned −75°, at
    (112, −8) mm: the left roll's contact moved 5 mm while the pad turned 13°, it was dropped
    for one sample within 2 mm of the corner, and the right pad's presses on the closing
    segment were answered line). So do one finger's
    presses whose seats stopped short of their supports by a bulge, twice on one face
    (tactile_jaw.flat.bulged_presses), as the last of them: P hyperbola 93 of --seed 191, the
    left pad's presses +0.26 mm on its curved part, its rolls on the corners, the right pad's
    presses on the closing segment answered line. ``checked``: the touches (their ``id``)
    found no curve before, not felt again (deterministic; a press's scan costs seconds of
    CPU), still counted among the bulged presses."""
    for t in felt:
        if id(t) in checked:
            continue
        if not isinstance(t.touch, FlatResult):
            stretch = curved_stretch(config, t) if t.curve_at is not None else None
            if stretch is None:  # whatever dropped it: its hint may be moving_hint's, or it was usable
                stretch = moving_stretch(config, t, MOVED_RUN_WINDOWS)
            if stretch is not None:
                return stretch
            continue
        scans = [s for s, role in zip(t.touch.samples, t.touch.roles) if role == "scan"]
        if len(scans) < MIN_SAMPLES_PER_TOUCH:
            continue
        roll = on_pad_face(config, feel(config, TouchResult(t.finger, t.touch.touch,
                                                            float(np.mean([s.psi for s in scans])), scans,
                                                            outcome="ok"), len(scans)))
        if roll is not None:
            return roll
    presses = bulged_presses(felt)
    return None if presses is None else presses[-1]


def curved_stretch(config, felt: FeltTouch) -> FeltTouch | None:
    """The stretch of a rolling touch ``felt`` that failed the smoothness test on which it
    rolled on a curved part, felt alone: its longest run of at least ``CURVE_HINT_SAMPLES``
    consecutive samples (ψ order) that passes every check of :func:`feel` (:func:`curve_hint`
    aims there), or None. A touch the exploration marked ``rejected`` is felt as taken
    (``ok``: only a touch taken whole is marked so)."""
    touch = replace(felt.touch, outcome="ok") if felt.touch.outcome == "rejected" else felt.touch
    found = _felt_run(config, touch)
    return None if found is None else found[2]


def moving_stretch(config, felt: FeltTouch, least: int = CURVE_HINT_SAMPLES) -> FeltTouch | None:
    """The stretch of a roll ``felt`` off the curved part on which its contact still moved
    along a convex boundary, felt alone (:func:`feel`, untrimmed: its envelope may still fail
    the smoothness test), or None: the longest run of at least ``least``
    (``CURVE_HINT_SAMPLES``; :func:`curved_part` counts ``MOVED_RUN_WINDOWS``, felt with the
    neighbours at its ends when shorter: every line of its windows) consecutive pad lines (ψ
    order), each with its two neighbours touching a circle —
    d_i = n_i·c − ρ solved exactly, σ_ρ from the lines' deviations — of radius clear of a
    corner's, ρ ≥ ``CORNER_RADIUS_MM`` and ≥ ``MOVED_SIGMAS`` σ_ρ, at a contact on the pad's
    face (``EDGE_MARGIN_MM`` from its ends), and whose pad ends slid along no straight line
    (:func:`sliding_end`); the neighbours at the run's ends are left out (a line through the
    end corner beside two on the curve passes too: 70 ± 0.4 mm on hyperbola 45 below, and
    the envelope fit with it placed a contact 2.3 mm past that corner); a touch the exploration marked ``rejected`` is felt as taken
    (:func:`curved_stretch`). A pivot keeps the contact fixed (ρ ≈ 0), a roll across a closing
    segment changes pivots between two lines (two windows straddle the change), a pad end
    sliding on a face is the pad end's path: a block shows no such run. With fine encoders
    a curve whose ρ changes fast is no polynomial envelope within the lines' µm
    (:func:`_felt_run` finds no passing run): calibrated P hyperbola 45 of bench_explore
    --finite 10 --anywhere --calibrate --seed 433, whose left roll kept 8 lines on the branch
    (ρ of its lines' triples 27–96 ± 0.3 mm) before its end corner; with coarse ones σ_ρ of three lines
    is tens of mm and no run qualifies."""
    lines, fit = felt.lines, felt.fit
    if lines is None or fit is None or felt.slid is not None:
        return None
    order = np.asarray(fit.contacts.order)
    normal, d = np.asarray(lines.normal, dtype=float)[order], np.asarray(lines.d, dtype=float)[order]
    sigma = np.asarray(fit.line_sigma, dtype=float)
    moved = np.zeros(d.size, dtype=bool)  # a window's middle line: the contact there moved
    length = config.finger(felt.finger).pad.length_mm
    for k in range(1, d.size - 1):
        part = slice(k - 1, k + 2)
        a = np.column_stack((normal[part], -np.ones(3))) / sigma[part, None]
        if abs(np.linalg.det(a)) < 1e-12:
            continue
        c = np.linalg.solve(a, d[part] / sigma[part])
        sigma_rho = math.sqrt(max(float(np.linalg.inv(a.T @ a)[2, 2]), 0.0))
        u = float(lines.at(order[k]).pad_coordinate(c[:2] - c[2] * normal[k]))
        moved[k] = (c[2] >= max(CORNER_RADIUS_MM, MOVED_SIGMAS * sigma_rho)
                    and EDGE_MARGIN_MM <= u <= length - EDGE_MARGIN_MM)
    run = longest_run(moved)
    if run.size < least:
        return None
    if run.size < CURVE_HINT_SAMPLES:  # too few lines for the smoothness test: every line of its windows
        run = np.arange(run[0] - 1, run[-1] + 2)
    taken = order[run]
    if sliding_end(lines.at(taken), sigma[run]) is not None:
        return None
    touch = replace(felt.touch, outcome="ok") if felt.touch.outcome == "rejected" else felt.touch
    stretch = feel(config, _subset(touch, taken), taken.size, trim=False)
    return stretch if stretch.fit is not None else None


def on_pad_face(config, felt: FeltTouch) -> FeltTouch | None:
    """A flat press's scan (``felt``, felt as a roll) that rolled on a curved part: as felt
    when usable, else felt again without the samples at either end of its ψ range whose
    contact lies off the pad's face (``EDGE_MARGIN_MM`` from its ends) and one beside each cut
    (the contact ran off the pad within that step; past it the pad end rests on the object),
    as often as that leaves fewer, when it is then usable and its radius of curvature at least
    ``MOVED_SIGMAS`` of its deviation; else None. A pad turning toward a
    seat on a curved part rolls on it until the contact reaches the pad's end: mixed jaw
    (XM430 base, PH42 distal) hyperbola 18 of bench_explore --finite 4 --anywhere --seed
    191, the left press's scan rolled 50° on the branch (ρ 15.7 ± 0.3 mm, 18 of 24 lines)
    before its proximal end met it, and the right pad's presses on the closing segment were
    answered line."""
    length = config.finger(felt.finger).pad.length_mm
    while felt.problem is not None and felt.pad_u is not None and felt.contacts is not None:
        on = (felt.pad_u >= EDGE_MARGIN_MM) & (felt.pad_u <= length - EDGE_MARGIN_MM)
        if np.all(on) or not np.any(on):
            return None
        first, last = int(np.argmax(on)), on.size - int(np.argmax(on[::-1]))
        keep = np.asarray(felt.contacts.order)[first + (first > 0) : last - (last < on.size)]
        if keep.size < MIN_SAMPLES_PER_TOUCH or keep.size == on.size:
            return None
        felt = feel(config, _subset(felt.touch, keep), keep.size, trim=False)
    return felt if felt.problem is None and felt.fit.rho >= MOVED_SIGMAS * felt.fit.sigma_rho else None


def curve_refusal(curve: FeltTouch) -> Recognition:
    """The refusal of a line from flat presses after ``curve`` (:func:`curved_part`) rolled on
    a curved part, or pressed one (a press whose seat bulged): the faces pressed are closing
    segments."""
    if isinstance(curve.touch, FlatResult):
        x, y = curve.face.middle
        felt = (f"pressed a curved part of the boundary: its seats stopped {curve.face.bulge:+.2f} mm short of the line "
                f"through their supports near ({x:.1f}, {y:.1f}) mm, twice (at most {SEAT_TOL_MM:g})")
    else:
        c, m = curve.contacts, len(curve.contacts.x) // 2
        felt = (f"rolled on a curved part of the boundary (radius of curvature {curve.fit.rho:.1f} ± "
                f"{curve.fit.sigma_rho:.2g} mm near ({c.x[m]:.1f}, {c.y[m]:.1f}) mm)")
    return Recognition("unclassified", reason=(
        f"{curve.finger}: touch {curve.touch.touch} {felt} but no rolling touch on it was usable clear of the "
        f"corners: the straight faces the pads pressed are the object's closing segments, not a line"))


def stated_noise(touches: Sequence[FeltTouch]) -> NoiseModel:
    """The per-sample noise the jaw states for these usable touches, from what they show
    themselves (docs/exploration.md#the-stated-noise): σ_φ of the pad angle (two joints, each
    quantized to a tick), and the RMS over every sample of its position's deviation across
    and along its pad line, propagated from the ticks through its touch's envelope fit
    (tactile_jaw.envelope); flat presses alone (tactile_jaw.flat) state ``flat_noise`` of their faces."""
    if _flat_only(touches):
        return parse_noise(flat_noise([t.face for t in touches]), "flat touches' noise")
    rolling = [t for t in touches if t.fit is not None]
    across = np.concatenate([t.fit.sigma_across for t in rolling])
    along = np.concatenate([t.fit.sigma_along for t in rolling])
    # σ_φ of each sample from its joints' ticks (the φ rows of the fit's noise factor)
    phi = np.concatenate([np.sum(t.fit.noise_factor[2 * len(t.fit.sigma_across):] ** 2, axis=1) for t in rolling])
    return NoiseModel(phi=float(np.sqrt(np.mean(phi))), pos=float(np.sqrt(np.mean(across**2))),
                      pos_along=float(np.sqrt(np.mean(along**2))))


def _flat_only(touches: Sequence[FeltTouch]) -> bool:
    return bool(touches) and all(isinstance(t.touch, FlatResult) for t in touches)


def make_recognizer(scene: dict[str, Any] | None, settings: ExploreSettings, noise: dict[str, float] | None = None,
                    reach: Reach | None = None) -> Callable[..., Recognition]:
    """Usable felt touches → Recognition, with the scene (a mapping, validated here once),
    the stated noise (``noise``, a fixed noise mapping for rolling touches such as an old
    log's; default: each call's :func:`stated_noise` of its touches) and the settings'
    recognizer options. Each call extends one validated request with the touches' samples
    (already checked by :func:`feel`): nothing is parsed again per decision. A call's
    ``reach`` replaces ``reach`` for that call (where its ``next_touch`` may point); its
    ``classes`` (a subset of the scene's) fits only those (tactile_jaw.separation).
    ``run.pooled(touches)``: the touches as a call pools them (tactile_jaw.curvature_pool),
    the last set pooled kept, so that a caller that also writes them (``tactile replay
    --touches``) and the calls on the same touches pool them once."""
    source = "exploration"
    loaded = load_scene(scene) if scene is not None else None
    fixed = parse_noise(dict(noise), f"{source}.noise") if noise is not None else None
    base = Request((), loaded, loaded.classes if loaded is not None else ALL_CLASSES, fixed, {}, source)
    options = RecognizeOptions(noise=fixed, reach=reach, **settings.recognize)
    last: list = [(), []]  # the touches last pooled (the same objects, in order) and their pooled copies

    def pool(touches: Sequence[FeltTouch]) -> list[FeltTouch]:
        if len(touches) != len(last[0]) or any(a is not b for a, b in zip(touches, last[0])):
            last[:] = [tuple(touches), pooled(touches)]
        return list(last[1])

    def run(touches: Sequence[FeltTouch], reach: Reach | None = None,
            classes: Sequence[str] | None = None) -> Recognition:
        request = base if classes is None else replace(base, classes=tuple(c for c in base.classes if c in classes))
        check_touch_count(len(touches), request.classes, source)
        stated = stated_noise(touches) if fixed is None or _flat_only(touches) else fixed
        return recognize(replace(request, touches=tuple(t.samples for t in pool(touches)), noise=stated),
                         replace(options, noise=stated, reach=options.reach if reach is None else reach))

    run.pooled = pool  # type: ignore[attr-defined]
    return run


@dataclass(frozen=True)
class LoggedRun:
    """A run log's touches as the exploration felt them (:func:`logged_run`)."""

    usable: list[FeltTouch]  # the usable touches, in the run's order
    curve: FeltTouch | None  # the first that rolled on a curved part (:func:`curved_part`)
    touches: list[FeltTouch]  # those the exploration recognized


def logged_run(config, contents, settings: ExploreSettings) -> LoggedRun:
    """The touches of a run log (hand_driver.log.read_log) rebuilt from its readings with the
    same checks the exploration applied, in the same order: the usable ones clear of the
    corners (:func:`clear_of_corners`), flat presses among them as
    tactile_jaw.flat.recognized_touches chooses (a face felt fewer than ``min_touches`` times
    is no line)."""
    usable, felt = logged_felt(config, contents, settings)
    curve = curved_part(config, felt)
    clear = clear_of_corners(config, usable, felt, settings.samples_per_touch)[0]
    return LoggedRun(usable, curve, recognized_touches(clear, settings.min_touches, curved=curve is not None))


def logged_touches(config, contents, settings: ExploreSettings) -> list[FeltTouch]:
    """The touches of a run log the exploration recognized (:func:`logged_run`'s)."""
    return logged_run(config, contents, settings).touches


def too_few_clear(usable: Sequence[FeltTouch], used: int, exc: Exception) -> Recognition:
    """The refusal when the touches clear of the corners (``usable``, of ``used`` usable
    ones) are too few to recognize (``exc``: the recognizer's count error)."""
    return Recognition("unclassified", reason=f"only {len(usable)} of the {used} usable touches are clear of the "
                                              f"corners other touches pivoted about: {exc}")


def logged_samples(config, finger: str, ticks, psi, readings=None, currents=None) -> list[Sample]:
    """A touch's samples rebuilt from its logged joint ticks (one row per reading) and
    commanded pad orientations ``psi``: pad lines by the config's kinematics, in one pass;
    ``readings`` their indices in the log (default 0, 1, …); ``currents`` each reading's joint
    currents (mA, None where not logged)."""
    ticks = np.asarray(ticks, dtype=float)
    lines = kin.finger_pad_line_from_ticks(config, finger, ticks)
    readings = range(len(ticks)) if readings is None else readings
    currents = [None] * len(ticks) if currents is None else currents
    return [Sample(reading=i, psi=float(p), ticks=ticks[k], line=lines.at(k), current_ma=None, robot_time=0.0,
                   joint_current_ma=currents[k])
            for k, (i, p) in enumerate(zip(readings, psi))]


def _logged_currents(reading: dict, joints: slice) -> tuple[float, ...] | None:
    """A logged reading's joint currents (mA) of one finger's ``joints``; None unless every one was read."""
    logged = reading.get("current_ma")
    if logged is None or any(c is None for c in logged[joints]):
        return None
    return tuple(float(c) for c in logged[joints])


def logged_felt(config, contents, settings: ExploreSettings) -> tuple[list[FeltTouch], list[FeltTouch]]:
    """A run log's touches rebuilt from its readings, each felt with the checks the
    exploration applied: (the usable ones, every one), in the log's order."""
    slices = config.joint_slices()
    out, felt_all = [], []
    for logged in contents.touches:
        samples = []
        if logged.readings:
            ticks = [np.asarray(contents.readings[i]["ticks"], dtype=float)[slices[logged.finger]]
                     for i in logged.readings]
            samples = logged_samples(config, logged.finger, ticks, logged.psi, logged.readings,
                                     [_logged_currents(contents.readings[i], slices[logged.finger])
                                      for i in logged.readings])
        if logged.kind == "flat":
            touch = FlatResult(logged.finger, logged.touch, logged.psi_center or 0.0, samples,
                               outcome=logged.outcome or "interrupted", roles=list(logged.roles))
        else:
            touch = TouchResult(logged.finger, logged.touch, logged.psi_center or 0.0, samples,
                                outcome=logged.outcome or "interrupted")
        felt = feel(config, touch, settings.samples_per_touch)
        felt_all.append(felt)
        if felt.problem is None:
            out.append(felt)
    return out, felt_all
