"""Exploration: rolling touches with both fingers at once until the recognizer is sure.

Probes (guarded approaches with a short roll from several pad orientations) first locate
the boundary; the pad lines of face contacts sample the object's support function, which
:class:`ObjectModel` fits locally to predict tangents. Each round, every finger makes one
rolling touch (hand_driver.motion.rolling_touch) in the same bus cycles, at a feasible
orientation (:func:`feasible`) farthest from its earlier touches (:func:`choose_psi`),
starting ``APPROACH_MARGIN_MM`` outside the predicted tangent. Between touches a pad
retreats to the workspace edge and turns along it. README, section motion.

After every round with at least ``settings.min_touches`` usable touches
(:func:`touch_problem`) the recognizer runs on all of them; exploration stops as soon as
its answer is decisive (:func:`indecision`: no class with more freedom fits significantly
better, every other consistent class is ``DECISIVE_CHI2`` worse in χ², except the
ellipse for a circle answer that stays the same without the last touch, and every shape
parameter is known to ``DECISIVE_REL_SIGMA``) or when the touch budget is spent; then the answer on the
usable touches is the class if decisive, else ``unclassified`` with the reason
(:func:`final_answer`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Callable

import numpy as np

from hand_driver import kinematics as kin
from hand_driver.motion import (
    LIMIT_MARGIN_RAD,
    Jaw,
    Sample,
    TouchResult,
    move_line,
    move_to,
    roll_angles,
    rolling_touch,
    run_together,
)
from tactile_common.errors import InputError

APPROACH_MARGIN_MM = 10.0
CANDIDATE_SPREAD_DEG = 75.0
CANDIDATE_STEP_DEG = 2.5
EDGE_TURN_STEP_DEG = 15.0
#: largest turn (rad) and shift (mm) per cycle of a transit outside the workspace disk
TRANSIT_STEPS = (math.radians(5.0), 3.0)
#: a used touch's contacts are at least this far (mm) from either end of the pad
PAD_EDGE_MARGIN_MM = 1.0
#: planning keeps the predicted contact this fraction of the pad's length from either end
PLAN_PAD_MARGIN = 0.1
#: probes: pad normals (deg) relative to the pad's normal at zero joint angles, samples
#: and span (deg) of each probe's short roll, and the fraction of the pad's length from
#: either end where its contact must lie to count as a face contact
PROBE_OFFSETS_DEG = (-60.0, -40.0, -20.0, 0.0, 20.0, 40.0, 60.0)
PROBE_SAMPLES = 4
PROBE_SPAN_DEG = 6.0
PROBE_PAD_MARGIN = 0.1
#: a finger stops probing once its face contacts span this many degrees of pad normal
PROBE_ENOUGH_DEG = 40.0
#: a finger with a single face contact after the grid probes again this far (deg) either side
PROBE_REFINE_DEG = 10.0
#: the object model predicts a tangent for ψ from felt lines within MODEL_REACH_DEG that
#: span at least MODEL_MIN_SPAN_DEG, the nearest at most MODEL_EXTRAPOLATE_DEG away
MODEL_REACH_DEG = 45.0
MODEL_MIN_SPAN_DEG = 3.0
MODEL_EXTRAPOLATE_DEG = 30.0
#: ... weighting each line by 1 / (1 + (Δψ / MODEL_WEIGHT_DEG)²), Δψ its distance from ψ
MODEL_WEIGHT_DEG = 10.0


#: the roll span (deg) below which κ_s drowns in encoder quantization on the default jaw:
#: exact ellipse touches through 4096-tick encoders are recognized with 30° and 9 samples,
#: not with 16° or 18° (README, section motion)
MIN_ROLL_SPAN_DEG = 30.0
#: the fewest samples per rolling touch that recognize on the default jaw (7 and 9 over
#: 30° do, 5 does not: README, section motion)
MIN_SAMPLES_PER_TOUCH = 7
#: per-sample noise the explorer states in its requests (README, section motion): φ is the
#: pad's angle q1 + q2, each joint quantized to a tick (uniform, σ = tick/√12), so
#: σ_φ = √2 · (2π/4096)/√12 = 6.3e-4 rad. Positions: a contact point lies on its pad line,
#: which the encoders fix to ~0.03 mm, but where along the line comes from the envelope of
#: neighbouring lines (a difference of quantized readings): at the true shape, emulated
#: touches of the default ellipse miss it by 0.029–0.031 mm RMS across the tangent and
#: 0.32–0.53 mm along it (perfect and calibrated configs). Stated: 0.06 mm across
#: (``pos``) and 0.6 mm along (``pos_along``); one isotropic 0.3 mm made calibrated
#: configs fail the χ² test (168 on 103 dof at the true shape) and weighted the along-track
#: errors like the shape information across the tangent
TOUCH_NOISE = {"phi": math.sqrt(2.0) * (2.0 * math.pi / 4096.0) / math.sqrt(12.0), "pos": 0.06, "pos_along": 0.6}
#: a consistent rival class whose χ² exceeds the answer's by this much (likelihood ratio
#: e^-5, "very strong" evidence on Kass & Raftery's scale) no longer keeps exploration going
DECISIVE_CHI2 = 10.0
#: (answer, rival): the answer is an exact special case of the rival
SUBMODELS = frozenset({("circle", "ellipse")})
#: an answer is decisive only once every shape parameter's standard deviation is at most
#: this fraction of its magnitude (of max(|p|, 1) for the dimensionless ``DIMENSIONLESS``)
DECISIVE_REL_SIGMA = 0.02
DIMENSIONLESS = frozenset({("cubical_parabola", "c"), ("semicubical_parabola", "b")})


@dataclass(frozen=True)
class ExploreSettings:
    """How much to touch: a budget of touches (both fingers together, rejected ones
    included), samples per rolling touch, the roll's total span, the fewest usable
    touches before recognizing, and the recognizer options."""

    touches: int
    samples_per_touch: int
    roll_span_rad: float
    min_touches: int = 3
    profile: str | None = None
    recognize: dict[str, Any] = field(default_factory=dict)  # RecognizeOptions keywords

    @classmethod
    def from_profile(cls, name: str) -> "ExploreSettings":
        """Settings of a recognizer.profiles profile: its samples per touch raised to
        ``MIN_SAMPLES_PER_TOUCH``, its roll span raised to ``MIN_ROLL_SPAN_DEG``, a budget
        of twice its touches plus two, its recognizer options."""
        from recognizer.profiles import get_profile

        p = get_profile(name, "--profile")
        return cls(touches=2 * p.touches + 2, samples_per_touch=max(p.samples_per_touch, MIN_SAMPLES_PER_TOUCH),
                   roll_span_rad=math.radians(max(p.roll_span_deg, MIN_ROLL_SPAN_DEG)),
                   min_touches=p.touches, profile=p.name, recognize=p.options())

    def to_json(self) -> dict[str, Any]:
        return {"touches": self.touches, "samples_per_touch": self.samples_per_touch,
                "roll_span_deg": math.degrees(self.roll_span_rad), "min_touches": self.min_touches,
                "profile": self.profile, "recognize": self.recognize}

    @classmethod
    def from_json(cls, obj: dict[str, Any]) -> "ExploreSettings":
        return cls(touches=int(obj["touches"]), samples_per_touch=int(obj["samples_per_touch"]),
                   roll_span_rad=math.radians(float(obj["roll_span_deg"])), min_touches=int(obj["min_touches"]),
                   profile=obj.get("profile"), recognize=dict(obj.get("recognize") or {}))


def make_recognizer(scene: dict[str, Any] | None, settings: ExploreSettings,
                    noise: dict[str, float] | None = None) -> Callable[[list[dict]], Any]:
    """touches → Recognition, with the scene (a mapping), ``noise`` (default
    ``TOUCH_NOISE``) and the settings' recognizer options."""
    from recognizer.classify import recognize
    from recognizer.result import RecognizeOptions
    from recognizer.touches import parse_request

    stated = dict(noise or TOUCH_NOISE)

    def run(touches: list[dict]):
        request = parse_request({"scene": scene, "touches": touches, "noise": stated}, source="exploration")
        return recognize(request, RecognizeOptions(noise=request.noise, **settings.recognize))

    return run


def indecision(recognition, shorter, settings: ExploreSettings) -> str | None:
    """Why a class answer is not yet decisive (the stopping rule, README section motion),
    or None when it is. ``recognition`` is on every usable touch, ``shorter`` on all but the
    last (None if too few). Decisive: (a) no consistent class with more free parameters
    fits significantly better (likelihood ratio: Δχ² below the χ²_Δk limit at the
    recognizer's alpha); (b) every other consistent class is ruled out by the data, its χ²
    ``DECISIVE_CHI2`` above the answer's, except a class the answer is an exact special
    case of (``SUBMODELS``: a circle is an ellipse with a = b), for which (a) decides once
    the answer is stable, the same class without the last touch; (c) its shape parameters
    are determined (:func:`imprecision`). A class the answer is only a limit of (a
    parabola of long ellipses and hyperbolas) or that fits as well is no evidence either
    way: BIC's parameter penalty alone would always pick the limit."""
    from recognizer.classify import chi2_limit

    ranked = [r for r in recognition.ranking if r.get("consistent")]
    best = next(r for r in ranked if r["class"] == recognition.cls)
    alpha = float(settings.recognize.get("alpha", 1e-3))
    for r in ranked:
        dk = best["dof"] - r["dof"]  # same observations: Δdof = Δ free parameters
        if dk > 0 and best["chi2"] - r["chi2"] > chi2_limit(alpha, dk):
            return f"{r['class']} fits significantly better than {best['class']} (chi2 {r['chi2']:.3g} vs {best['chi2']:.3g})"
    rivals = [r for r in ranked if r["class"] != recognition.cls and r["chi2"] - best["chi2"] < DECISIVE_CHI2]
    others = [r for r in rivals if (recognition.cls, r["class"]) not in SUBMODELS]
    if others:
        runner = min(others, key=lambda r: r["chi2"])
        return (f"{best['class']} (chi2 {best['chi2']:.1f}) and {runner['class']} (chi2 {runner['chi2']:.1f}) both "
                f"fit, less than {DECISIVE_CHI2:g} apart: the touches cannot tell them apart")
    if rivals and (shorter is None or shorter.cls != recognition.cls):
        return (f"{best['class']} and {rivals[0]['class']} both fit and the answer "
                + ("changed with the last touch" if shorter is not None else "was not yet checked with one touch fewer"))
    return imprecision(recognition)


def imprecision(recognition) -> str | None:
    """Why the answer's shape parameters are not yet determined (a standard deviation above
    ``DECISIVE_REL_SIGMA`` of the parameter's magnitude), or None. Touches that all see one
    short arc fit one class decisively yet leave its parameters loose (an ellipse from 30°
    of its boundary: a ±4 %, b ±9 %), and their errors along the pad are correlated, so such
    an answer can be off by far more than its stated deviation: explore on instead."""
    loose = []
    for name, value in recognition.params.items():
        sd = recognition.uncertainty.get(name)
        if sd is None:
            continue
        ref = max(abs(value), 1.0) if (recognition.cls, name) in DIMENSIONLESS else abs(value)
        if not (math.isfinite(sd) and sd <= DECISIVE_REL_SIGMA * ref):
            loose.append(f"{name} ±{100.0 * sd / ref:.2g} %" if ref > 0 and math.isfinite(sd) else f"{name} undetermined")
    if loose:
        return f"{recognition.cls} parameters not yet within {100 * DECISIVE_REL_SIGMA:g} %: {', '.join(loose)}"
    return None


def decide(recognize_touches: Callable[[list[dict]], Any], touches: list[dict], settings: ExploreSettings):
    """(Recognition, why it is not decisive or None): :func:`indecision` on the recognizer's
    answer on ``touches`` (and on all but the last, when it needs that)."""
    recognition = recognize_touches(touches)
    if recognition.cls == "unclassified":
        return recognition, recognition.reason
    shorter = None
    if len(touches) > settings.min_touches:
        try:
            shorter = recognize_touches(touches[:-1])
        except InputError:
            shorter = None
    return recognition, indecision(recognition, shorter, settings)


def final_answer(recognize_touches: Callable[[list[dict]], Any], touches: list[dict], settings: ExploreSettings):
    """The answer on the usable touches once exploration ends: the recognizer's class when
    it is decisive (:func:`decide`), else ``unclassified`` with the reason; a wrong class
    said confidently is worse than a refusal. Replay uses this on the logged touches."""
    from recognizer.result import Recognition

    recognition, why = decide(recognize_touches, touches, settings)
    if recognition.cls == "unclassified" or why is None:
        return recognition
    return Recognition("unclassified", reason=f"not decisive after {len(touches)} usable touches: {why}",
                       ranking=recognition.ranking, timing=recognition.timing)


@dataclass
class Exploration:
    """What an exploration did and found."""

    probes: list[TouchResult] = field(default_factory=list)  # every probe, in order
    touches: list[TouchResult] = field(default_factory=list)  # every touch attempted, in order
    request: dict[str, Any] = field(default_factory=dict)  # CONTRACTS §2, good touches only
    recognition: Any = None  # recognizer.result.Recognition
    rounds: int = 0
    robot_time_s: float = 0.0
    answers: list[str] = field(default_factory=list)  # class after each recognition


def touch_to_samples(config, touch: TouchResult) -> dict[str, Any]:
    """CONTRACTS §2 samples touch (with ``finger``) from a touch's in-contact readings."""
    ticks = np.array([s.ticks for s in touch.samples], dtype=float)
    out = kin.touch_from_ticks(config, touch.finger, ticks).to_touch()
    out["finger"] = touch.finger
    return out


def touch_problem(config, touch: TouchResult, samples: int) -> str | None:
    """Why a touch cannot be used, or None: at least ``MIN_SAMPLES_PER_TOUCH`` samples
    (all planned ones, or those taken before the roll ran out of reach or contact), arc
    length strictly increasing (the pad rolled on a boundary convex toward it, not on an
    edge or a corner) and every envelope contact on the pad, ``PAD_EDGE_MARGIN_MM`` from
    its ends (a pad end resting on the object is not a tangent contact)."""
    cut_short = touch.outcome in ("unreachable", "no_contact", "blocked")
    if touch.outcome != "ok" and not cut_short:
        return touch.message or touch.outcome
    if len(touch.samples) < min(samples, MIN_SAMPLES_PER_TOUCH):
        return touch.message if cut_short else f"{touch.finger}: {len(touch.samples)} of {samples} samples"
    ticks = np.array([s.ticks for s in touch.samples], dtype=float)
    try:
        c = kin.touch_from_ticks(config, touch.finger, ticks)
    except InputError as exc:
        return f"{touch.finger}: {exc}"
    if np.any(np.diff(c.s) <= 0.0):
        return f"{touch.finger}: arc length not increasing: the pad rolled on an edge or corner"
    lines = kin.finger_pad_line_from_ticks(config, touch.finger, ticks[c.order])
    u = lines.pad_coordinate(np.stack([c.x, c.y], axis=-1))
    length = config.finger(touch.finger).pad.length_mm
    if np.any(u < PAD_EDGE_MARGIN_MM) or np.any(u > length - PAD_EDGE_MARGIN_MM):
        return (f"{touch.finger}: contact {float(np.min(u)):.1f}..{float(np.max(u)):.1f} mm along the pad, "
                f"not inside {PAD_EDGE_MARGIN_MM:g}..{length - PAD_EDGE_MARGIN_MM:g} mm (a pad end touched)")
    return None


def logged_touches(config, contents, settings: ExploreSettings) -> list[dict[str, Any]]:
    """The usable touches of a run log (hand_driver.log.read_log), rebuilt from its
    readings with the same checks the exploration applied, in the same order."""
    slices = config.joint_slices()
    out = []
    for logged in contents.touches:
        samples = []
        for i, psi in zip(logged.readings, logged.psi):
            ticks = np.asarray(contents.readings[i]["ticks"], dtype=float)[slices[logged.finger]]
            line = kin.finger_pad_line_from_ticks(config, logged.finger, ticks)
            samples.append(Sample(reading=i, psi=psi, ticks=ticks, psi_measured=float(line.psi), d=float(line.d),
                                  current_ma=None, robot_time=0.0))
        touch = TouchResult(logged.finger, logged.touch, logged.psi_center or 0.0, samples,
                            outcome=logged.outcome or "interrupted")
        if touch_problem(config, touch, settings.samples_per_touch) is None:
            out.append(touch_to_samples(config, touch))
    return out


class ObjectModel:
    """What the pads felt (module docstring): the in-contact pad lines ψ, d of face
    contacts. The object's support function d(ψ) (the first line of normal ψ that meets
    it) is fitted near ψ by a quadratic; its tangent point is d·n(ψ) + d'(ψ)·n'(ψ)."""

    def __init__(self, center, workspace_radius: float):
        self.workspace_center = np.asarray(center, dtype=float)
        self.workspace_radius = workspace_radius
        self.psi = np.zeros(0)
        self.d = np.zeros(0)

    def add(self, psi, d) -> None:
        """Add felt pad lines (face contacts only)."""
        self.psi = np.concatenate([self.psi, np.atleast_1d(np.asarray(psi, dtype=float))])
        self.d = np.concatenate([self.d, np.atleast_1d(np.asarray(d, dtype=float))])

    def tangent(self, psi: float) -> tuple[float, np.ndarray] | None:
        """The predicted pad line offset d and contact point for a pad with normal ψ, or
        None where nothing was felt within ``MODEL_REACH_DEG`` or the lines there span
        less than ``MODEL_MIN_SPAN_DEG``."""
        delta = np.remainder(self.psi - psi + math.pi, 2 * math.pi) - math.pi
        near = np.abs(delta) <= math.radians(MODEL_REACH_DEG)
        if np.count_nonzero(near) < 2 or np.ptp(delta[near]) < math.radians(MODEL_MIN_SPAN_DEG):
            return None
        if np.min(np.abs(delta[near])) > math.radians(MODEL_EXTRAPOLATE_DEG):
            return None
        deg = 2 if np.ptp(delta[near]) >= math.radians(2 * MODEL_MIN_SPAN_DEG) and np.count_nonzero(near) >= 3 else 1
        weight = 1.0 / (1.0 + (delta[near] / math.radians(MODEL_WEIGHT_DEG)) ** 2)
        coef = np.polynomial.polynomial.polyfit(delta[near], self.d[near], deg, w=weight)
        n = np.array([math.cos(psi), math.sin(psi)])
        dn = np.array([-math.sin(psi), math.cos(psi)])
        return float(coef[0]), coef[0] * n + coef[1] * dn

    def edge(self, psi: float) -> float:
        """Offset of the line with normal ψ tangent to the workspace disk (outside it)."""
        n = np.array([math.cos(psi), math.sin(psi)])
        return float(n @ self.workspace_center) - self.workspace_radius


def nominal_psi(finger) -> float:
    """The pad's outward normal angle at zero joint angles."""
    return finger.base.angle + finger.pad.side_sign * math.pi / 2


def feasible(finger, model: ObjectModel, psi: float, settings: ExploreSettings) -> bool:
    """Every roll orientation around ψ has a predicted tangent (:meth:`ObjectModel.tangent`)
    that puts the pad on it, with the predicted contact on the pad, inside the joint
    limits, and also ``APPROACH_MARGIN_MM`` beyond it; the edge line is reachable."""
    length = finger.pad.length_mm
    for a in roll_angles(psi, settings.roll_span_rad, settings.samples_per_touch)[[0, -1]]:
        predicted = model.tangent(float(a))
        if predicted is None:
            return False
        d, p = predicted
        try:
            kin.ik_line(finger, float(a), d, contact=p, margin_rad=LIMIT_MARGIN_RAD)
            kin.ik_line(finger, float(a), d + APPROACH_MARGIN_MM, margin_rad=LIMIT_MARGIN_RAD)
            kin.ik_line(finger, float(a), model.edge(float(a)), margin_rad=LIMIT_MARGIN_RAD)
        except kin.Unreachable:
            return False
        u = [float(kin.finger_pad_line(finger, q).pad_coordinate(p))
             for q in kin.ik_line_solutions(finger, float(a), d)
             if kin.within_limits(finger.joints, q, LIMIT_MARGIN_RAD)]
        if not any(PLAN_PAD_MARGIN * length <= v <= (1 - PLAN_PAD_MARGIN) * length for v in u):
            return False
    return True


def choose_psi(finger, model: ObjectModel, settings: ExploreSettings, used: list[float]) -> float | None:
    """Next pad orientation for ``finger`` (module docstring), None if none is feasible."""
    nominal = nominal_psi(finger)
    offsets = np.arange(-CANDIDATE_SPREAD_DEG, CANDIDATE_SPREAD_DEG + 1e-9, CANDIDATE_STEP_DEG)
    cands = [nominal + math.radians(o) for o in offsets]
    ok = [a for a in cands if feasible(finger, model, a, settings)]
    if not ok:
        return None
    if not used:
        return ok[len(ok) // 2]
    gap = [min(abs(a - u) for u in used) for a in ok]
    if max(gap) < math.radians(CANDIDATE_STEP_DEG) - 1e-9:
        return None  # every feasible orientation was touched already
    return ok[int(np.argmax(gap))]


def transit(jaw: Jaw, finger: str, model: ObjectModel, psi_to: float):
    """Retreat to the workspace edge along the pad normal, then turn along the edge to ψ.
    Where the edge is out of the joints' reach along this normal (a pad turned far past its
    nominal direction), the pad retreats as far as it can and the finger swings open in
    joint space to its edge pose at the nominal ψ, and turns from there: without this, one
    such pose made every later transit of the finger fail and spent the touch budget."""
    line = jaw.pad_line(jaw.last_state, finger)
    psi_from = float(line.psi)
    try:
        yield from move_line(jaw, finger, psi_from, min(float(line.d), model.edge(psi_from)), *TRANSIT_STEPS)
    except kin.Unreachable:
        f = jaw.config.finger(finger)
        psi_from = nominal_psi(f)
        q_open = kin.ik_line(f, psi_from, model.edge(psi_from), margin_rad=LIMIT_MARGIN_RAD)
        yield from move_to(jaw, finger, q_open)
    delta = math.remainder(psi_to - psi_from, 2 * math.pi)
    steps = max(1, math.ceil(abs(math.degrees(delta)) / EDGE_TURN_STEP_DEG))
    for k in range(1, steps + 1):
        a = psi_from + delta * k / steps
        yield from move_line(jaw, finger, a, model.edge(a), *TRANSIT_STEPS)


def _transit_or_problem(jaw: Jaw, finger: str, model: ObjectModel, psi_to: float):
    """:func:`transit`; why it could not go on (the path left the joint limits), or None."""
    try:
        yield from transit(jaw, finger, model, psi_to)
    except kin.Unreachable as exc:
        return f"{finger}: transit to psi={math.degrees(psi_to):.1f} deg: {exc}"
    return None


def _touch_plan(jaw: Jaw, finger: str, model: ObjectModel, psi: float, settings: ExploreSettings,
                touch_index: int, emit):
    """Transit, then one rolling touch around ψ from ``APPROACH_MARGIN_MM`` outside the
    predicted tangent line; returns the TouchResult."""
    start = float(roll_angles(psi, settings.roll_span_rad, settings.samples_per_touch)[0])
    problem = yield from _transit_or_problem(jaw, finger, model, start)
    if problem is not None:
        return TouchResult(finger, touch_index, psi, outcome="unreachable", message=problem)
    d_pred, _ = model.tangent(start)
    d_start = max(model.edge(start), d_pred - APPROACH_MARGIN_MM)
    travel = d_pred + APPROACH_MARGIN_MM - d_start
    return (yield from rolling_touch(jaw, finger, touch_index, psi, settings.roll_span_rad,
                                     settings.samples_per_touch, d_start, travel, on_event=emit))


def open_pose(config) -> np.ndarray:
    """Joint angles (rad, config order) of the opened jaw: every pad at its normal at zero
    joint angles, on the line tangent to the workspace disk (config ``workspace``) from
    outside; where an exploration starts its probes."""
    ws = config.workspace
    model = ObjectModel(ws.center_mm, ws.radius_mm)
    out = []
    for f in config.fingers:
        psi = nominal_psi(f)
        out.append(kin.ik_line(f, psi, model.edge(psi), margin_rad=LIMIT_MARGIN_RAD))
    return np.concatenate(out)


def probe_psis(finger, model: ObjectModel) -> list[float]:
    """The probe orientations of a finger: its pad's normal at zero joint angles ±
    ``PROBE_OFFSETS_DEG`` whose workspace-edge line is reachable, nearest that normal first."""
    nominal = nominal_psi(finger)
    out = []
    for o in sorted(PROBE_OFFSETS_DEG, key=abs):
        a = nominal + math.radians(o)
        try:
            kin.ik_line(finger, a, model.edge(a), margin_rad=LIMIT_MARGIN_RAD)
        except kin.Unreachable:
            continue
        out.append(a)
    return out


def _probe_plan(jaw: Jaw, finger: str, model: ObjectModel, psi: float, touch_index: int, emit):
    """Transit, then a short rolling touch (``PROBE_SAMPLES`` over ``PROBE_SPAN_DEG``) from
    the workspace edge across the whole workspace disk; returns the TouchResult."""
    span = math.radians(PROBE_SPAN_DEG)
    start = float(roll_angles(psi, span, PROBE_SAMPLES)[0])
    problem = yield from _transit_or_problem(jaw, finger, model, start)
    if problem is not None:
        return TouchResult(finger, touch_index, psi, outcome="unreachable", message=problem)
    return (yield from rolling_touch(jaw, finger, touch_index, psi, span, PROBE_SAMPLES, model.edge(start),
                                     2.0 * model.workspace_radius, on_event=emit))


def probe_face_contact(config, touch: TouchResult) -> float | None:
    """Where a probe touched along the pad (mm from its proximal end, the middle sample's
    envelope contact) if the probe passes :func:`touch_problem` (all samples, arc length
    increasing: a pad end sliding on the boundary moves the envelope backwards) and every
    contact is ``PROBE_PAD_MARGIN`` of the pad's length from either end; else None."""
    if len(touch.samples) < PROBE_SAMPLES or touch_problem(config, touch, PROBE_SAMPLES) is not None:
        return None
    ticks = np.array([s.ticks for s in touch.samples], dtype=float)
    c = kin.touch_from_ticks(config, touch.finger, ticks)
    lines = kin.finger_pad_line_from_ticks(config, touch.finger, ticks[c.order])
    u = lines.pad_coordinate(np.stack([c.x, c.y], axis=-1))
    length = config.finger(touch.finger).pad.length_mm
    if np.any(u < PROBE_PAD_MARGIN * length) or np.any(u > (1 - PROBE_PAD_MARGIN) * length):
        return None
    return float(u[len(u) // 2])


def _memo(recognize_touches: Callable[[list[dict]], Any]) -> Callable[[list[dict]], Any]:
    """``recognize_touches`` remembering its answers by the touches' identities."""
    seen: dict[tuple[int, ...], Any] = {}

    def run(touches: list[dict]):
        key = tuple(id(t) for t in touches)
        if key not in seen:
            seen[key] = recognize_touches(touches)
        return seen[key]

    return run


def explore(jaw: Jaw, settings: ExploreSettings, recognize_touches: Callable[[list[dict]], Any],
            emit: Callable[[dict], None] | None = None,
            progress: Callable[[str], None] | None = None) -> Exploration:
    """Explore with both fingers (module docstring). ``recognize_touches`` maps a list of
    CONTRACTS §2 touches to a Recognition; ``emit`` receives log records; ``progress``
    one-line messages for people."""
    emit = emit or (lambda rec: None)
    say = progress or (lambda msg: None)
    recognize_touches = _memo(recognize_touches)
    cfg = jaw.config
    ws = cfg.workspace
    model = ObjectModel(ws.center_mm, ws.radius_mm)
    out = Exploration()
    t0 = jaw.robot_time()
    index = 0
    queues = {f.name: probe_psis(f, model) for f in cfg.fingers}
    faces: dict[str, list[float]] = {f.name: [] for f in cfg.fingers}
    refined = False
    while True:
        if not any(queues.values()):
            if refined:
                break
            refined = True  # one more pass: around a finger's only face contact, PROBE_REFINE_DEG either side
            queues = {f.name: [faces[f.name][0] + math.radians(sign * PROBE_REFINE_DEG) for sign in (-1, 1)]
                      if len(faces[f.name]) == 1 else [] for f in cfg.fingers}
            if not any(queues.values()):
                break
        plans = {}
        for name, queue in queues.items():
            if queue:
                plans[name] = _probe_plan(jaw, name, model, queue.pop(0), index + len(plans), emit)
        results = run_together(jaw, plans)
        for name in plans:
            probe = results[name]
            out.probes.append(probe)
            index += 1
            u = probe_face_contact(cfg, probe)
            if u is not None:
                model.add([s.psi_measured for s in probe.samples], [s.d for s in probe.samples])
                faces[name].append(probe.psi_center)
                if np.ptp(faces[name]) >= math.radians(PROBE_ENOUGH_DEG) - 1e-9:
                    queues[name] = []  # enough felt to plan this finger's touches
            say(f"probe {len(out.probes)}: {name} at psi {math.degrees(probe.psi_center):.1f} deg: "
                + (f"pad face {u:.1f} mm from its proximal end" if u is not None else
                   probe.message or f"{len(probe.samples)} samples, not on the pad's face"))
    used: dict[str, list[float]] = {f.name: [] for f in cfg.fingers}
    good: list[dict] = []
    while len(out.touches) < settings.touches:
        plans = {}
        budget = settings.touches - len(out.touches)
        for f in cfg.fingers[:budget]:
            psi = choose_psi(f, model, settings, used[f.name])
            if psi is None:
                message = (f"{f.name}: no untouched pad orientation left for which the felt lines predict a "
                           f"{math.degrees(settings.roll_span_rad):g} deg roll on the pad's face")
                emit({"type": "event", "kind": "no_orientation", "message": message})
                say(message)
                continue
            used[f.name].append(psi)
            plans[f.name] = _touch_plan(jaw, f.name, model, psi, settings, index + len(plans), emit)
        if not plans:
            break
        index += len(plans)
        out.rounds += 1
        results = run_together(jaw, plans)
        for name in plans:
            touch = results[name]
            out.touches.append(touch)
            problem = touch_problem(cfg, touch, settings.samples_per_touch)
            if problem is None:
                samples = touch_to_samples(cfg, touch)
                good.append(samples)
                model.add([s.psi_measured for s in touch.samples], [s.d for s in touch.samples])
            else:
                if touch.outcome == "ok":
                    touch.outcome = "rejected"
                emit({"type": "event", "kind": "touch_rejected", "message": problem, "touch": touch.touch})
            say(f"touch {len(out.touches)}/{settings.touches}: {name} at psi {math.degrees(touch.psi_center):.1f} deg, "
                f"{len(touch.samples)} samples, {'used' if problem is None else 'not used: ' + problem}")
        if len(good) >= settings.min_touches:
            recognition, why = decide(recognize_touches, good, settings)
            out.recognition = recognition
            out.answers.append(recognition.cls)
            say(f"after {len(good)} touches: {recognition.cls}" + ("" if why is None else f", not decisive: {why}"))
            if why is None:
                break
    here = {f.name: float(jaw.pad_line(jaw.last_state, f.name).psi) for f in cfg.fingers}
    run_together(jaw, {name: _transit_or_problem(jaw, name, model, psi) for name, psi in here.items()})  # to the edge
    if not model.psi.size:
        message = (f"no probe of {len(out.probes)} found a contact on a pad's face: within reach of the pads the "
                   f"object offers no boundary they can roll on (flat, concave, or felt only by a pad end)")
        emit({"type": "event", "kind": "no_face_contact", "message": message})
        say(message)
    if good:
        try:  # the answer on every usable touch, a refusal unless decisive
            out.recognition = final_answer(recognize_touches, good, settings)
            out.answers.append(out.recognition.cls)
        except InputError as exc:
            emit({"type": "event", "kind": "too_few_touches", "message": str(exc)})
    out.request = {"touches": good}
    out.robot_time_s = jaw.robot_time() - t0
    return out
