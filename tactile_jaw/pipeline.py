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
from hand_driver.motion import EDGE_MARGIN_MM, Sample, TouchResult
from hand_driver.units import RAD_PER_TICK
from recognizer.classify import recognize
from recognizer.result import Recognition, RecognizeOptions
from recognizer.scene import ALL_CLASSES, load_scene
from recognizer.touches import Request, SamplesTouch, check_touch_count, parse_noise
from tactile_common.errors import InputError
from tactile_jaw.settings import MIN_SAMPLES_PER_TOUCH, TOUCH_NOISE, ExploreSettings

#: central-difference step (rad) of the curvature's joint-angle Jacobian
CURVATURE_STEP_RAD = 1e-7
#: outcomes of a touch cut short whose samples so far may still be used
CUT_SHORT = ("unreachable", "no_contact", "blocked")


@dataclass(frozen=True)
class FeltTouch:
    """One touch's geometry, computed once by :func:`feel`."""

    touch: TouchResult
    lines: kin.PadLine | None  # the pad at every in-contact sample, in the order taken
    contacts: kin.Contacts | None  # their envelope, ordered by ψ (None when not computed)
    pad_u: np.ndarray | None  # each contact's distance along the pad from its proximal end (contacts' order)
    problem: str | None  # why the touch cannot be used, or None
    samples: SamplesTouch | None  # the recognizer's samples touch when usable

    @property
    def finger(self) -> str:
        return self.touch.finger

    def to_json(self) -> dict[str, Any]:
        """The samples touch (docs/formats.md) with ``finger`` (usable touches only)."""
        out = self.contacts.to_touch()
        out["finger"] = self.touch.finger
        return out

    def pad_segments(self) -> list[dict[str, Any]]:
        """The pad, as a segment, at every in-contact sample (for the plot)."""
        if self.lines is None:
            return []
        return [{"finger": self.touch.finger, "p0": tuple(p0), "p1": tuple(p1)}
                for p0, p1 in zip(self.lines.proximal, self.lines.distal)]


def envelope_curvature(finger, q) -> tuple[float, float, np.ndarray]:
    """κ, κ_s at the contact (reading n // 2 in ψ order) from the touch's own envelope fit:
    the polynomial d(ψ) of hand_driver.kinematics.touch_from_pad_lines, about the centre of
    curvature (:func:`_curvature_at`), with their 2×2 covariance to first order in every
    joint angle ``q`` (n, 2) of every reading, each quantized to a tick (uniform:
    σ = tick/√12). Emulated touches: as accurate as the recognizer's estimate from the
    smoothed samples, whose stated σ is ~20× too small (docs/exploration.md)."""
    q = np.asarray(q, dtype=float)
    base, origin = _curvature_at(finger, q, None)
    jac = np.empty((2, q.size))
    for j in range(q.size):
        dq = np.zeros(q.size)
        dq[j] = CURVATURE_STEP_RAD
        dq = dq.reshape(q.shape)
        jac[:, j] = (_curvature_at(finger, q + dq, origin)[0] - _curvature_at(finger, q - dq, origin)[0]) \
            / (2.0 * CURVATURE_STEP_RAD)
    return float(base[0]), float(base[1]), (RAD_PER_TICK**2 / 12.0) * jac @ jac.T


def _curvature_at(finger, q, origin) -> tuple[np.ndarray, np.ndarray]:
    """([κ, κ_s], centre of curvature) at the middle reading from the support values
    d(ψ) − n(ψ)·o fitted by a polynomial in ψ (degree kinematics.default_degree): with
    ρ̃ = d + d'' (minus the radius of curvature) κ = −1/ρ̃ and κ_s = −ρ̃'/ρ̃³. About the
    centre of curvature ``o`` the support values of a circle are constant, so the fit's
    truncation error is only that of the changing curvature; ``origin`` None: two passes,
    the first about the lines' mean foot."""
    line = kin.finger_pad_line(finger, q)
    psi = np.unwrap(np.asarray(line.psi, dtype=float))
    order = np.argsort(psi, kind="stable")
    psi, d, n = psi[order], np.asarray(line.d, dtype=float)[order], np.asarray(line.normal, dtype=float)[order]
    c0, scale = 0.5 * (psi[0] + psi[-1]), 0.5 * (psi[-1] - psi[0])
    x = (psi - c0) / scale
    m = psi.size // 2
    passes = [np.mean(n * d[:, None], axis=0), None] if origin is None else [origin]
    for o in passes:
        if o is None:
            o = centre
        poly = np.polynomial.Polynomial.fit(x, d - n @ o, kin.default_degree(psi.size), domain=[-1, 1],
                                            window=[-1, 1])
        rho = poly(x[m]) + poly.deriv(2)(x[m]) / scale**2
        rho_1 = (poly.deriv(1)(x[m]) + poly.deriv(3)(x[m]) / scale**2) / scale
        nperp = np.array([-n[m, 1], n[m, 0]])
        contact = o + n[m] * poly(x[m]) + nperp * poly.deriv(1)(x[m]) / scale
        centre = contact - n[m] * rho  # ρ̃ < 0: the centre lies inside the object, along n
    return np.array([-1.0 / rho, -rho_1 / rho**3]), centre


def feel(config, touch: TouchResult, samples: int) -> FeltTouch:
    """The touch's pad lines (one forward-kinematics pass over its readings), their
    envelope, and why it cannot be used, or None: at least ``MIN_SAMPLES_PER_TOUCH``
    samples (all ``samples`` planned ones, or those taken before the roll ran out of reach
    or contact), arc length strictly increasing (the pad rolled on a boundary convex toward
    it, not on an edge or a corner) and every envelope contact on the pad,
    ``EDGE_MARGIN_MM`` from its ends (a pad end resting on the object is not a tangent
    contact)."""
    finger = touch.finger
    lines = None
    if touch.samples:
        ticks = np.array([s.ticks for s in touch.samples], dtype=float)
        lines = kin.finger_pad_line_from_ticks(config, finger, ticks)

    def out(problem, contacts=None, pad_u=None):
        samples_touch = None
        if problem is None:
            f = config.finger(finger)
            q = kin.ticks_to_angles(f.joints, ticks)
            samples_touch = SamplesTouch(contacts.phi, contacts.x, contacts.y, contacts.s,
                                         curvature=envelope_curvature(f, q))
        return FeltTouch(touch, lines, contacts, pad_u, problem, samples_touch)

    cut_short = touch.outcome in CUT_SHORT
    if touch.outcome != "ok" and not cut_short:
        return out(touch.message or touch.outcome)
    if len(touch.samples) < max(3, min(samples, MIN_SAMPLES_PER_TOUCH)):  # an envelope needs 3 lines
        return out(touch.message if cut_short else f"{finger}: {len(touch.samples)} of {samples} samples")
    try:
        c = kin.touch_from_pad_lines(lines.psi, lines.d)
    except InputError as exc:
        return out(f"{finger}: {exc}")
    if np.any(np.diff(c.s) <= 0.0):
        return out(f"{finger}: arc length not increasing: the pad rolled on an edge or corner", c)
    u = np.sum((np.stack([c.x, c.y], axis=-1) - lines.proximal[c.order]) * lines.tangent[c.order], axis=-1)
    length = config.finger(finger).pad.length_mm
    if np.any(u < EDGE_MARGIN_MM) or np.any(u > length - EDGE_MARGIN_MM):
        return out(f"{finger}: contact {float(np.min(u)):.1f}..{float(np.max(u)):.1f} mm along the pad, "
                   f"not inside {EDGE_MARGIN_MM:g}..{length - EDGE_MARGIN_MM:g} mm (a pad end touched)", c, u)
    return out(None, c, u)


def make_recognizer(scene: dict[str, Any] | None, settings: ExploreSettings,
                    noise: dict[str, float] | None = None) -> Callable[[Sequence[FeltTouch]], Recognition]:
    """Usable felt touches → Recognition, with the scene (a mapping, validated here once),
    ``noise`` (default ``TOUCH_NOISE``) and the settings' recognizer options. Each call
    extends one validated request with the touches' samples (already checked by
    :func:`feel`): nothing is parsed again per decision."""
    source = "exploration"
    loaded = load_scene(scene) if scene is not None else None
    stated = parse_noise(dict(noise or TOUCH_NOISE), f"{source}.noise")
    base = Request((), loaded, loaded.classes if loaded is not None else ALL_CLASSES, stated, {}, source)
    options = RecognizeOptions(noise=stated, **settings.recognize)

    def run(touches: Sequence[FeltTouch]) -> Recognition:
        check_touch_count(len(touches), base.classes, source)
        return recognize(replace(base, touches=tuple(t.samples for t in touches)), options)

    return run


def logged_touches(config, contents, settings: ExploreSettings) -> list[FeltTouch]:
    """The usable touches of a run log (hand_driver.log.read_log), rebuilt from its
    readings with the same checks the exploration applied, in the same order."""
    slices = config.joint_slices()
    out = []
    for logged in contents.touches:
        samples = []
        for i, psi in zip(logged.readings, logged.psi):
            ticks = np.asarray(contents.readings[i]["ticks"], dtype=float)[slices[logged.finger]]
            line = kin.finger_pad_line_from_ticks(config, logged.finger, ticks)
            samples.append(Sample(reading=i, psi=psi, ticks=ticks, line=line, current_ma=None, robot_time=0.0))
        touch = TouchResult(logged.finger, logged.touch, logged.psi_center or 0.0, samples,
                            outcome=logged.outcome or "interrupted")
        felt = feel(config, touch, settings.samples_per_touch)
        if felt.problem is None:
            out.append(felt)
    return out
