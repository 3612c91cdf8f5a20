"""Exploration: rolling touches with both fingers at once until the recognizer is sure.

Each round, every finger makes one rolling touch (hand_driver.motion.rolling_touch) in
the same bus cycles. Where to touch comes from a working model of the object, a circle
(centre c, radius R): the workspace disk's centre and half its radius before any
contact; then the least-squares circle through every contact found so far once their
tangents point at least 90° apart (before that, the points' mean distance from c).
A finger's candidate pad orientations ψ lie within ±75° of its pad's normal at zero
joint angles, 2.5° apart, such that for both ends of the roll inverse kinematics puts
the pad on the model's tangent line (and ``APPROACH_MARGIN_MM`` beyond it) with the
predicted contact ``PLAN_PAD_MARGIN`` of the pad's length away from either pad end. The
first touch of a finger takes the candidate nearest that normal and approaches from the
workspace edge; later ones take the candidate farthest (in ψ) from the finger's earlier
touches, so the touches see other parts (and curvatures) of the boundary, and approach
from ``APPROACH_MARGIN_MM`` outside the model's tangent. Between touches a pad retreats
to the workspace edge and turns along it.

After every round with at least ``settings.min_touches`` usable touches
(:func:`touch_problem`) the recognizer runs on all of them; exploration stops as soon as
it answers a class (its χ² tests found every touch consistent) or when the touch budget
is spent; then the recognizer answers on the usable touches if they suffice for any
class of the scene.
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
    roll_angles,
    rolling_touch,
    run_together,
)
from recognizer.errors import InputError

APPROACH_MARGIN_MM = 10.0
CANDIDATE_SPREAD_DEG = 75.0
CANDIDATE_STEP_DEG = 2.5
EDGE_TURN_STEP_DEG = 15.0
#: largest turn (rad) and shift (mm) per cycle of a transit outside the workspace disk
TRANSIT_STEPS = (math.radians(5.0), 3.0)
#: a used touch's contacts are at least this far (mm) from either end of the pad
PAD_EDGE_MARGIN_MM = 1.0
#: planning keeps the predicted contact this fraction of the pad's length from either end
PLAN_PAD_MARGIN = 0.2


#: the roll span (deg) below which κ_s drowns in encoder quantization on the default jaw:
#: exact ellipse touches through 4096-tick encoders are recognized with 30° and 9 samples,
#: not with 16° or 18° (README, section motion)
MIN_ROLL_SPAN_DEG = 30.0
#: the fewest samples per rolling touch that recognize on the default jaw (7 and 9 over
#: 30° do, 5 does not: README, section motion)
MIN_SAMPLES_PER_TOUCH = 7
#: per-sample noise the explorer states in its requests: envelope samples carry errors
#: that are smooth along a touch (one polynomial of the pad lines), which the estimator's
#: independent-noise model only covers with these deviations (README, section motion)
TOUCH_NOISE = {"phi": 0.005, "pos": 1.0}


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


def make_recognizer(scene: dict[str, Any] | None, settings: ExploreSettings) -> Callable[[list[dict]], Any]:
    """touches → Recognition, with the scene (a mapping), ``TOUCH_NOISE`` and the
    settings' recognizer options."""
    from recognizer.classify import recognize
    from recognizer.result import RecognizeOptions
    from recognizer.touches import parse_request

    def run(touches: list[dict]):
        request = parse_request({"scene": scene, "touches": touches, "noise": TOUCH_NOISE}, source="exploration")
        return recognize(request, RecognizeOptions(noise=request.noise, **settings.recognize))

    return run


@dataclass
class Exploration:
    """What an exploration did and found."""

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
    """The working circle model of the object (module docstring)."""

    def __init__(self, center, workspace_radius: float):
        self.center = np.asarray(center, dtype=float)
        self.radius = 0.5 * workspace_radius
        self.workspace_center = self.center.copy()
        self.workspace_radius = workspace_radius
        self.points = np.zeros((0, 2))
        self.normals = np.zeros(0)

    def add(self, x, y, phi) -> None:
        """Add a touch's contact points (and tangent angles); refit."""
        self.points = np.vstack([self.points, np.stack([x, y], axis=-1)])
        self.normals = np.concatenate([self.normals, np.asarray(phi, dtype=float)])
        p = self.points
        # a circle through the points only once they face directions at least 90° apart
        spread = np.max(np.abs(np.angle(np.exp(1j * (self.normals[:, None] - self.normals[None, :])))))
        if spread >= math.pi / 2:
            # algebraic circle fit: x² + y² = 2 a x + 2 b y + k, least squares
            a = np.column_stack([2 * p[:, 0], 2 * p[:, 1], np.ones(len(p))])
            sol, *_ = np.linalg.lstsq(a, np.sum(p * p, axis=1), rcond=None)
            center = sol[:2]
            radius = math.sqrt(max(sol[2] + float(center @ center), 0.0))
            inside = np.hypot(*(center - self.workspace_center)) <= self.workspace_radius
            if inside and 0.0 < radius <= self.workspace_radius:
                self.center, self.radius = center, radius
                return
        self.radius = float(np.mean(np.hypot(*(p - self.center).T)))

    def tangent(self, psi: float) -> tuple[float, np.ndarray]:
        """The model's tangent line for a pad with normal ψ: offset d and contact point."""
        n = np.array([math.cos(psi), math.sin(psi)])
        p = self.center - self.radius * n
        return float(n @ p), p

    def edge(self, psi: float) -> float:
        """Offset of the line with normal ψ tangent to the workspace disk (outside it)."""
        n = np.array([math.cos(psi), math.sin(psi)])
        return float(n @ self.workspace_center) - self.workspace_radius


def nominal_psi(finger) -> float:
    """The pad's outward normal angle at zero joint angles."""
    return finger.base.angle + finger.pad.side_sign * math.pi / 2


def feasible(finger, model: ObjectModel, psi: float, settings: ExploreSettings) -> bool:
    """Every roll orientation around ψ puts the pad on the model's tangent line, with the
    predicted contact on the pad, inside the joint limits, and also ``APPROACH_MARGIN_MM``
    beyond it; the edge line is reachable."""
    length = finger.pad.length_mm
    for a in roll_angles(psi, settings.roll_span_rad, settings.samples_per_touch)[[0, -1]]:
        d, p = model.tangent(float(a))
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
        return min(ok, key=lambda a: abs(a - nominal))
    gap = [min(abs(a - u) for u in used) for a in ok]
    if max(gap) < math.radians(CANDIDATE_STEP_DEG) - 1e-9:
        return None  # every feasible orientation was touched already
    return ok[int(np.argmax(gap))]


def transit(jaw: Jaw, finger: str, model: ObjectModel, psi_to: float):
    """Retreat to the workspace edge along the pad normal, then turn along the edge to ψ."""
    line = jaw.pad_line(jaw.last_state, finger)
    psi_from = float(line.psi)
    yield from move_line(jaw, finger, psi_from, min(float(line.d), model.edge(psi_from)), *TRANSIT_STEPS)
    delta = math.remainder(psi_to - psi_from, 2 * math.pi)
    steps = max(1, math.ceil(abs(math.degrees(delta)) / EDGE_TURN_STEP_DEG))
    for k in range(1, steps + 1):
        a = psi_from + delta * k / steps
        yield from move_line(jaw, finger, a, model.edge(a), *TRANSIT_STEPS)


def _touch_plan(jaw: Jaw, finger: str, model: ObjectModel, psi: float, first: bool,
                settings: ExploreSettings, touch_index: int, emit):
    """Transit, then one rolling touch around ψ; returns the TouchResult."""
    start = float(roll_angles(psi, settings.roll_span_rad, settings.samples_per_touch)[0])
    yield from transit(jaw, finger, model, start)
    edge = model.edge(start)
    if first:
        d_start, travel = edge, model.workspace_radius
    else:
        d_pred, _ = model.tangent(start)
        d_start = max(edge, d_pred - APPROACH_MARGIN_MM)
        travel = d_pred + APPROACH_MARGIN_MM - d_start
    return (yield from rolling_touch(jaw, finger, touch_index, psi, settings.roll_span_rad,
                                     settings.samples_per_touch, d_start, travel, on_event=emit))


def explore(jaw: Jaw, settings: ExploreSettings, recognize_touches: Callable[[list[dict]], Any],
            emit: Callable[[dict], None] | None = None,
            progress: Callable[[str], None] | None = None) -> Exploration:
    """Explore with both fingers (module docstring). ``recognize_touches`` maps a list of
    CONTRACTS §2 touches to a Recognition; ``emit`` receives log records; ``progress``
    one-line messages for people."""
    emit = emit or (lambda rec: None)
    say = progress or (lambda msg: None)
    cfg = jaw.config
    ws = cfg.workspace
    model = ObjectModel(ws.center_mm, ws.radius_mm)
    out = Exploration()
    used: dict[str, list[float]] = {f.name: [] for f in cfg.fingers}
    good: list[dict] = []
    t0 = jaw.robot_time()
    while len(out.touches) < settings.touches:
        plans = {}
        budget = settings.touches - len(out.touches)
        for f in cfg.fingers[:budget]:
            psi = choose_psi(f, model, settings, used[f.name])
            if psi is None:
                message = f"{f.name}: no untouched reachable pad orientation left"
                emit({"type": "event", "kind": "no_orientation", "message": message})
                say(message)
                continue
            used[f.name].append(psi)
            plans[f.name] = _touch_plan(jaw, f.name, model, psi, len(used[f.name]) == 1, settings,
                                        len(out.touches) + len(plans), emit)
        if not plans:
            break
        out.rounds += 1
        results = run_together(jaw, plans)
        for name in plans:
            touch = results[name]
            out.touches.append(touch)
            problem = touch_problem(cfg, touch, settings.samples_per_touch)
            if problem is None:
                samples = touch_to_samples(cfg, touch)
                good.append(samples)
                model.add(samples["x"], samples["y"], samples["phi"])
            else:
                if touch.outcome == "ok":
                    touch.outcome = "rejected"
                emit({"type": "event", "kind": "touch_rejected", "message": problem, "touch": touch.touch})
            say(f"touch {len(out.touches)}/{settings.touches}: {name} at psi {math.degrees(touch.psi_center):.1f} deg, "
                f"{len(touch.samples)} samples, {'used' if problem is None else 'not used: ' + problem}")
        if len(good) >= settings.min_touches:
            recognition = recognize_touches(good)
            out.recognition = recognition
            out.answers.append(recognition.cls)
            say(f"after {len(good)} touches: {recognition.cls}")
            if recognition.cls != "unclassified":
                break
    here = {f.name: float(jaw.pad_line(jaw.last_state, f.name).psi) for f in cfg.fingers}
    run_together(jaw, {name: transit(jaw, name, model, psi) for name, psi in here.items()})  # pads to the edge
    if out.recognition is None and good:
        try:  # the budget is spent with fewer usable touches than planned: answer if possible
            out.recognition = recognize_touches(good)
            out.answers.append(out.recognition.cls)
        except InputError as exc:
            emit({"type": "event", "kind": "too_few_touches", "message": str(exc)})
    out.request = {"touches": good}
    out.robot_time_s = jaw.robot_time() - t0
    return out
