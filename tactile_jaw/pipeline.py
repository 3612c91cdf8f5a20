"""Servo ticks → pad lines → touches → recognition, each touch computed once.

:func:`feel` turns one rolling touch's in-contact readings into its pad lines, their
envelope (the contacts, hand_driver.kinematics.touch_from_pad_lines), where each contact
lies along the pad, and why the touch cannot be used (or None); the :class:`FeltTouch` is
kept and reused by the exploration's checks and object model, the recognizer's samples,
the log and the plot. :func:`make_recognizer` validates the scene and the stated noise
once and recognizes any list of felt touches; :func:`logged_touches` rebuilds a run log's
felt touches from its readings (replay, benchmarks).
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any, Callable, Sequence

import numpy as np

from hand_driver import kinematics as kin
from hand_driver.motion import EDGE_MARGIN_MM, FlatResult, Sample, TouchResult
from recognizer.classify import chi2_limit, recognize
from recognizer.result import Recognition, RecognizeOptions
from recognizer.scene import ALL_CLASSES, load_scene
from recognizer.touches import ContactTouch, Reach, Request, SamplesTouch, check_touch_count, parse_noise
from tactile_common.errors import InputError
from tactile_jaw.envelope import EnvelopeFit, fit_envelope
from tactile_jaw.flat import FLAT_NOISE, Face, feel_flat, recognized_touches
from tactile_jaw.settings import MIN_SAMPLES_PER_TOUCH, TOUCH_NOISE, ExploreSettings

#: a touch whose radius of curvature at the contact is below this (mm), or below
#: CORNER_SIGMAS of its deviation, rolled on a corner (the contact stayed put while the pad
#: turned), not on the curved part. A corner's measured radius scatters about 0 by σ_ρ
#: (1.3 mm over a 30° roll of 9 samples, ~4 mm over 18°): 2 σ misses 2.3 % of corners and
#: also refuses boundary bent tighter than ~2 σ_ρ, whose κ is too uncertain to use (2.5 σ
#: rejected the cubical example's hump, ρ 14.5 mm measured 8.25 ± 3.77 mm)
CORNER_RADIUS_MM = 1.0
CORNER_SIGMAS = 2.0
#: false-rejection rate of the test that a touch's pad lines are one smooth curve's tangents
SMOOTH_ALPHA = 1e-3
#: degree of d(ψ) whose envelope (constant radius of curvature over the roll) gives a
#: rolling touch's arc length when the default cubic's is not increasing
SMOOTH_DEGREE = 2
#: outcomes of a touch cut short whose samples so far may still be used
CUT_SHORT = ("unreachable", "no_contact", "blocked")


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

    @property
    def finger(self) -> str:
        return self.touch.finger

    def to_json(self) -> dict[str, Any]:
        """The samples touch (docs/formats.md) with ``finger`` and the envelope's ``curvature``
        (usable touches only): a request of these answers as the run did."""
        out = self.samples.to_json() if self.samples is not None else self.contacts.to_touch()
        out["finger"] = self.touch.finger
        return out

    def pad_segments(self) -> list[dict[str, Any]]:
        """The pad, as a segment, at every in-contact sample (for the plot)."""
        if self.lines is None:
            return []
        return [{"finger": self.touch.finger, "p0": tuple(p0), "p1": tuple(p1)}
                for p0, p1 in zip(self.lines.proximal, self.lines.distal)]


def feel(config, touch: TouchResult, samples: int, curve_checks: bool = True) -> FeltTouch:
    """The touch's pad lines (one forward-kinematics pass over its readings), their
    envelope (and, for rolling touches, its :class:`EnvelopeFit`), and why it cannot be used, or None: at least ``MIN_SAMPLES_PER_TOUCH``
    samples (all ``samples`` planned ones, or those taken before the roll ran out of reach
    or contact), arc length strictly increasing (the pad rolled on a boundary convex toward
    it, not on an edge or a corner; for rolling touches from the degree-``SMOOTH_DEGREE``
    fit when the cubic's is not) and every envelope contact on the pad,
    ``EDGE_MARGIN_MM`` from its ends (a pad end resting on the object is not a tangent
    contact); and, with ``curve_checks`` (rolling touches; not probes, whose short rolls
    cannot measure a radius of curvature), that it rolled on the curved part
    (:func:`off_curve_reason`). A flat press is felt by tactile_jaw.flat.feel_flat."""
    if isinstance(touch, FlatResult):
        lines, problem, contact, face = feel_flat(config, touch)
        return FeltTouch(touch, lines, None, None, problem, contact, face=face)
    finger = touch.finger
    lines = None
    if touch.samples:
        ticks = np.array([s.ticks for s in touch.samples], dtype=float)
        lines = kin.finger_pad_line_from_ticks(config, finger, ticks)

    def out(problem, contacts=None, pad_u=None, fit=None, off_curve=False):
        samples_touch = None
        if problem is None and fit is not None:
            samples_touch = SamplesTouch(contacts.phi, contacts.x, contacts.y, contacts.s,
                                         curvature=(fit.kappa, fit.kappa_s, fit.cov))
        return FeltTouch(touch, lines, contacts, pad_u, problem, samples_touch, fit, off_curve)

    cut_short = touch.outcome in CUT_SHORT
    if touch.outcome != "ok" and not cut_short:
        return out(touch.message or touch.outcome)
    if len(touch.samples) < max(3, min(samples, MIN_SAMPLES_PER_TOUCH)):  # an envelope needs 3 lines
        return out(touch.message if cut_short else f"{finger}: {len(touch.samples)} of {samples} samples")
    try:
        c = kin.touch_from_pad_lines(lines.psi, lines.d)
    except InputError as exc:
        return out(f"{finger}: {exc}")
    f = config.finger(finger)
    u = _pad_u(lines, c)
    fit = None
    if curve_checks:
        fit = fit_envelope(f, kin.ticks_to_angles(f.joints, ticks))
        off_curve = off_curve_reason(fit, c, float(np.ptp(c.psi)))
        if off_curve is not None:
            return out(f"{finger}: {off_curve}", c, u, fit, off_curve=True)
    if fit is not None and np.any(np.diff(c.s) <= 0.0):
        # the cubic's ρ(ψ) = −(d + d'') is linear in ψ and its slope is mostly noise over a
        # short roll (σ_ρ ≈ 4 mm over 18°): at the roll's ends it can dip below 0 on a
        # boundary of ρ ≈ 20 mm. The roll passed the corner test (ρ > 2 σ_ρ at the contact),
        # so its arc length comes from the smoother fit of constant ρ (degree 2)
        c = kin.touch_from_pad_lines(lines.psi, lines.d, degree=SMOOTH_DEGREE)
        u = _pad_u(lines, c)
    if np.any(np.diff(c.s) <= 0.0):
        return out(f"{finger}: arc length not increasing: the pad rolled on an edge or corner", c, u, fit)
    length = f.pad.length_mm
    if np.any(u < EDGE_MARGIN_MM) or np.any(u > length - EDGE_MARGIN_MM):
        return out(f"{finger}: contact {float(np.min(u)):.1f}..{float(np.max(u)):.1f} mm along the pad, "
                   f"not inside {EDGE_MARGIN_MM:g}..{length - EDGE_MARGIN_MM:g} mm (a pad end touched)", c, u, fit)
    return out(None, c, u, fit)


def _pad_u(lines: kin.PadLine, contacts: kin.TouchEnvelope) -> np.ndarray:
    """Each envelope contact's distance along its own reading's pad from the proximal end
    (PadLine.pad_coordinate), in the contacts' order (by ψ)."""
    taken = np.empty((contacts.order.size, 2))
    taken[contacts.order] = np.stack([contacts.x, contacts.y], axis=-1)
    return lines.pad_coordinate(taken)[contacts.order]


def off_curve_reason(fit: EnvelopeFit, contacts, turn_rad: float) -> str | None:
    """Why a touch fell off the object's curved part, or None: on a corner (the radius of
    curvature at the contact is below ``CORNER_RADIUS_MM`` or ``CORNER_SIGMAS`` of its
    deviation: the contact stayed put while the pad turned) or across a corner or closing
    segment (the pad lines are no smooth curve's tangents: their χ² about the envelope fit
    above its limit at ``SMOOTH_ALPHA``: a straight segment bridged between two corners
    makes d(ψ) kink)."""
    m = len(contacts.x) // 2
    if fit.rho < max(CORNER_RADIUS_MM, CORNER_SIGMAS * fit.sigma_rho):
        return (f"corner: the contact stayed near ({contacts.x[m]:.1f}, {contacts.y[m]:.1f}) mm while the pad "
                f"turned {np.degrees(turn_rad):.0f} deg (radius of curvature {fit.rho:.2f} ± {fit.sigma_rho:.2f} mm)")
    if fit.dof > 0 and fit.chi2 > chi2_limit(SMOOTH_ALPHA, fit.dof):
        return (f"off the curved part: the pad lines are no smooth curve's tangents (chi2 {fit.chi2:.3g} on "
                f"{fit.dof} dof): the roll crossed a corner or a straight closing segment")
    return None


def workspace_reach(config) -> Reach:
    """The jaw's workspace disk (config ``workspace``) as the recognizer's reach: where its
    ``next_touch`` may point."""
    (x, y), radius = config.workspace.center_mm, config.workspace.radius_mm
    return Reach(float(x), float(y), float(radius))


def make_recognizer(scene: dict[str, Any] | None, settings: ExploreSettings, noise: dict[str, float] | None = None,
                    reach: Reach | None = None) -> Callable[[Sequence[FeltTouch]], Recognition]:
    """Usable felt touches → Recognition, with the scene (a mapping, validated here once),
    ``noise`` (default ``TOUCH_NOISE``; flat touches alone state tactile_jaw.flat.FLAT_NOISE)
    and the settings' recognizer options. Each call extends one validated request with
    the touches' samples (already checked by :func:`feel`): nothing is parsed again per
    decision."""
    source = "exploration"
    loaded = load_scene(scene) if scene is not None else None
    classes = loaded.classes if loaded is not None else ALL_CLASSES
    rolling = dict(noise or TOUCH_NOISE)
    setups = {}
    for flat, raw in ((False, rolling), (True, FLAT_NOISE)):
        stated = parse_noise(dict(raw), f"{source}.noise")
        setups[flat] = (Request((), loaded, classes, stated, {}, source),
                        RecognizeOptions(noise=stated, reach=reach, **settings.recognize))

    def run(touches: Sequence[FeltTouch]) -> Recognition:
        check_touch_count(len(touches), classes, source)
        base, options = setups[all(isinstance(t.touch, FlatResult) for t in touches)]
        return recognize(replace(base, touches=tuple(t.samples for t in touches)), options)

    return run


def logged_touches(config, contents, settings: ExploreSettings) -> list[FeltTouch]:
    """The touches of a run log (hand_driver.log.read_log) the exploration recognized,
    rebuilt from its readings with the same checks it applied, in the same order: the
    usable ones, flat presses among them as tactile_jaw.flat.recognized_touches chooses."""
    slices = config.joint_slices()
    out = []
    for logged in contents.touches:
        samples = []
        for i, psi in zip(logged.readings, logged.psi):
            ticks = np.asarray(contents.readings[i]["ticks"], dtype=float)[slices[logged.finger]]
            line = kin.finger_pad_line_from_ticks(config, logged.finger, ticks)
            samples.append(Sample(reading=i, psi=psi, ticks=ticks, line=line, current_ma=None, robot_time=0.0))
        if logged.kind == "flat":
            touch = FlatResult(logged.finger, logged.touch, logged.psi_center or 0.0, samples,
                               outcome=logged.outcome or "interrupted", roles=list(logged.roles))
        else:
            touch = TouchResult(logged.finger, logged.touch, logged.psi_center or 0.0, samples,
                                outcome=logged.outcome or "interrupted")
        felt = feel(config, touch, settings.samples_per_touch)
        if felt.problem is None:
            out.append(felt)
    return recognized_touches(out)
