"""Where a hand touches: the recognizer on a widened distribution, per class and per region,
with an oracle for every wrong answer, suggested against random extra touches, and the
honesty of the stated σ's (not a test).

    python -m tools.bench_wide [--set wide|hand] [--aim approach|nearest] [--trials 40] [--seed 1] [--jobs 2] [--out FILE.md] [--records FILE.json]
    python -m tools.bench_wide --coverage-only [--first 40] [--trials 80]   (σ coverage alone)
    tactile bench --wide-trials N        (writes OUT/bench_wide.md beside the other results)

``--set wide`` (the default; issue 21's distributions, ``WIDE_REGIONS``): every region of
the earlier set and far stretches (a semicubical's branch far out, a hyperbola's arm far
out), a long thin ellipse's sharp end (a touch's tangent turns through about a radian),
small shapes of fixed size (a circle of r = 3.3 mm, a cubical region of 4 mm); region
sizes L log-uniform over 1–1,500 mm; a quarter of each region's trials touch one of their
three places twice (fresh noise); and every trial's touches once more noise-free (noise
model zero): ``noise-free exact`` is the class right with relative error ≤ 1e-6.
``--set hand`` is the earlier distribution (L 30–120 mm), kept to reproduce its figures.

Each trial draws a shape of one class and a region of it (``REGIONS``: one branch of a
semicubical near or far from its cusp or both branches, a hyperbola near its vertex or out
on an arm, a cubical parabola on one side of its inflection or across it, a short or long
stretch of an ellipse or circle, a parabola on one side or across its vertex, a line), three
contacts spread over the region, 3 touches × 9 samples 2 % of the region's extent L apart
(a semicubical touch never reaches across the cusp), standard noise (φ 1.5 mrad,
positions 0.1 % of L), the balanced profile, every class allowed. Rows:

- ``3 touches``: right class, median relative error; compute time per recognition.
- oracle, for every wrong answer: the true class refined from the truth and the answered
  class from the answer; *data-limited* when the answer fits at least as well after the
  penalty for parameters (BIC, or the likelihood-ratio test of a nested answer), else a
  *search miss*; an ``unclassified`` answer is a search miss when the truth, refined from
  itself, passes its consistency test.
- ``3 + 2 random``: two more touches at random places of the region.
- ``3 + ≤2 suggested``: up to two more touches where ``next_touch`` says, stopping when it
  says null. The object is the whole curve around the region (both sides of the vertex,
  cusp or inflection, a semicubical's other branch). ``--aim approach`` (the default): every
  extra touch is sent as a place and a pad orientation (a random one: the region's random
  point as the 3-touch answer places it, with its tangent) and lands where a pad coming in
  along its normal first meets the object (tools.pad_approach), or is lost. Each suggested
  touch sent is one of the two attempts, landed or lost, as each random one is; a lost one
  is sent back as missed (``options.missed``: next_touch keeps off the stretch its pad met)
  and the next suggestion asked for with the same touches and the missed places, as a hand
  whose touch met nothing asks again. ``--aim nearest``: a suggestion is touched at the
  true curve's point closest to it (a semicubical's clear of the cusp), a random touch where
  drawn. ``aim miss`` is how far the landing lies from the place sent to; ``suggested used``
  the suggested touches that landed; ``touches lost`` of those sent; ``next_touch ms`` over
  every next_touch of the 3-touch recognition and of the recognitions after each suggested
  attempt (a re-ask after a lost one included).
- coverage: on right answers of ``3 touches``, the fraction of shape parameters within
  1.96 stated σ and the RMS of (p̂ − p)/σ. ``--coverage-only`` runs the 3-touch
  recognitions alone (trials ``--first`` … ``--first + --trials − 1``) and gives each
  class's coverage with its 95 % binomial (Wilson) interval: with 40 trials a class has
  40–80 values, and a calibrated σ shows 100 % about one time in eight.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
from collections import defaultdict
from dataclasses import dataclass

import numpy as np

from recognizer import synth
from recognizer.class_limits import LIMIT_OF
from recognizer.classify import MODEL_ALPHA, RIVAL_BIC, chi2_limit, recognize
from recognizer.curves import CURVES, Pose, travel_direction
from recognizer.localize import N_SHAPE
from recognizer.profiles import PROFILES
from recognizer.refine import refine_one
from recognizer.result import Candidate, RecognizeOptions
from recognizer.touches import MissedPlace, NoiseModel, Request, SamplesTouch
from tools.bench import _pool, rel_error
from tools.bench_sigma import interval_z
from tools.pad_approach import Landing, land, solid_left

CLASSES = tuple(CURVES)
SPEC_PHI, SPEC_POS_FRAC, SPACING, SAMPLES = 1.5e-3, 1e-3, 0.02, 9
EXACT_REL = 1e-6  # noise-free samples: the answer's largest acceptable relative error
#: per class: region name → (canonical shape at unit scale, contact range of t, branch sign)
REGIONS = {
    "line": {"segment": ({}, (-0.5, 0.5))},
    "circle": {"short arc": ({"r": 0.5}, "short"), "all round": ({"r": 0.5}, (-np.pi, np.pi))},
    "ellipse": {"short stretch": ({"a": 0.5, "b": None}, "short"), "long stretch": ({"a": 0.5, "b": None}, (-np.pi, np.pi))},
    "parabola": {"one side": ({"a": 1.0}, (0.3, 2.5)), "across vertex": ({"a": 1.0}, (-1.5, 1.5)),
                 "far out": ({"a": 1.0}, (2.0, 5.0))},
    "hyperbola": {"near vertex": ({"a": 1.0, "b": None}, (-1.0, 1.0)), "out on an arm": ({"a": 1.0, "b": None}, (1.2, 3.0)),
                  "both arms far": ({"a": 1.0, "b": None}, (-2.8, 2.8))},
    "cubical_parabola": {"one side of inflection": ({"a": None, "c": None}, (0.15, 1.2)),
                         "across inflection": ({"a": None, "c": None}, (-1.0, 1.0))},
    "semicubical_parabola": {"one branch near cusp": ({"a": 1.0, "b": None}, (0.0, 0.6)),
                             "one branch far": ({"a": 1.0, "b": None}, (0.8, 2.5)),
                             "both branches": ({"a": 1.0, "b": None}, "both")},
}


#: the widened distributions of issue 21 (``--set wide``, the default): regions spanning
#: 1–1,500 mm (L log-uniform), far stretches (a semicubical's branch at t 3–15 of its unit
#: shape, a hyperbola's arm at t 3–6), a long thin ellipse's sharp end (b/a 0.10–0.15: a
#: touch's tangent turns through about a radian), small shapes of fixed size (a circle of
#: r = 3.3 mm, a cubical region of 4 mm); a quarter of each region's trials touch one of the
#: three places twice (a repeated touch, fresh noise). Per region: (unit shape, contact
#: range of t, options): ``r_mm`` a circle's fixed radius, ``L_mm`` a fixed region size.
WIDE_REGIONS = {
    "line": {"segment": ({}, (-0.5, 0.5), {})},
    "circle": {"short arc": ({"r": 0.5}, "short", {}), "all round": ({"r": 0.5}, (-np.pi, np.pi), {}),
               "small (r 3.3 mm)": ({"r": 0.5}, "short", {"r_mm": 3.3})},
    "ellipse": {"short stretch": ({"a": 0.5, "b": None}, "short", {}),
                "long stretch": ({"a": 0.5, "b": None}, (-np.pi, np.pi), {}),
                "thin, sharp end": ({"a": 0.5, "b": "thin"}, "sharp end", {})},
    "parabola": {"one side": ({"a": 1.0}, (0.3, 2.5), {}), "across vertex": ({"a": 1.0}, (-1.5, 1.5), {}),
                 "far out": ({"a": 1.0}, (2.0, 5.0), {})},
    "hyperbola": {"near vertex": ({"a": 1.0, "b": None}, (-1.0, 1.0), {}),
                  "out on an arm": ({"a": 1.0, "b": None}, (1.2, 3.0), {}),
                  "both arms far": ({"a": 1.0, "b": None}, (-2.8, 2.8), {}),
                  "far on an arm": ({"a": 1.0, "b": None}, (3.0, 6.0), {})},
    "cubical_parabola": {"one side of inflection": ({"a": None, "c": None}, (0.15, 1.2), {}),
                         "across inflection": ({"a": None, "c": None}, (-1.0, 1.0), {}),
                         "small (4 mm)": ({"a": None, "c": None}, (-1.0, 1.0), {"L_mm": 4.0})},
    "semicubical_parabola": {"one branch near cusp": ({"a": 1.0, "b": None}, (0.0, 0.6), {}),
                             "one branch far": ({"a": 1.0, "b": None}, (0.8, 2.5), {}),
                             "both branches": ({"a": 1.0, "b": None}, "both", {}),
                             "far out on a branch": ({"a": 1.0, "b": None}, (3.0, 15.0), {})},
}
WIDE_L_MM = (1.0, 1500.0)
SETS = ("wide", "hand")
AIMS = ("approach", "nearest")
PAD_ROLLS = 1.0
"""``--aim approach``: half the pad's length in rolls (a pad twice as long as a roll: a contact
up to half a roll from the pad's middle leaves room for the roll on the pad)."""


def _rng(seed: int, *keys: int) -> np.random.Generator:
    return np.random.default_rng([seed, *keys])


def _draw_params(cls: str, params: dict, rs) -> dict:
    params = dict(params)
    for k, v in params.items():
        if v == "thin":
            params[k] = 0.5 * rs.uniform(0.10, 0.15)
        elif v is None:
            params[k] = {"b": {"ellipse": 0.5 * rs.uniform(0.35, 0.9), "hyperbola": rs.uniform(0.4, 2.0),
                               "semicubical_parabola": float(rs.choice([-1, 1]) * rs.uniform(0.1, 1.5))}.get(cls),
                         "a": float(rs.choice([-1, 1]) * rs.uniform(0.25, 0.75)),
                         "c": float(rs.choice([-1, 1]) * rs.uniform(0.3, 1.0))}[k]
    return params


def draw_case(cls: str, i: int, seed: int, dist: str = "hand"):
    """(region name, shape, contact ts (3, or 4 with a repeated touch), (lo, hi, branch sign,
    both branches, cusp clearance), rng for noise) of trial i of a class; ``dist``: "hand"
    (``REGIONS``, L 30–120 mm) or "wide" (``WIDE_REGIONS``, L 1–1,500 mm)."""
    rs = _rng(seed, CLASSES.index(cls), i, 77 if dist == "hand" else 21)
    table = REGIONS if dist == "hand" else WIDE_REGIONS
    names = list(table[cls])
    region = names[i % len(names)]
    params, span, *opt = table[cls][region]
    opt = opt[0] if opt else {}
    params = _draw_params(cls, params, rs)
    if span == "short":
        t0 = rs.uniform(-np.pi, np.pi)
        span = (t0, t0 + rs.uniform(0.5, 1.2))
    elif span == "sharp end":  # around the end of the major axis, where κ = a/b²
        t0 = rs.uniform(-0.15, 0.15) + (np.pi if rs.uniform() < 0.5 else 0.0)
        span = (t0 - 0.45, t0 + 0.45)
    both = span == "both"
    if both:
        span = (0.3, 2.0)
    if dist == "hand":
        L = rs.uniform(30.0, 120.0)
    else:
        L = opt.get("L_mm") or float(np.exp(rs.uniform(*np.log(WIDE_L_MM))))
    curve = CURVES[cls](params)
    region_t = np.linspace(*span, 400)
    if both:
        region_t = np.concatenate((-region_t[::-1], region_t))
    k = L / synth.extent(curve, region_t)
    if "r_mm" in opt:
        k = opt["r_mm"] / params["r"]
    params, span = synth._scaled(cls, params, span, k)
    curve = CURVES[cls](params)
    L = synth.extent(curve, synth.region(cls, span) if both else np.linspace(*span, 400)) if "r_mm" in opt else L
    pose = Pose(rs.uniform(-np.pi, np.pi), 150.0 + rs.uniform(-30, 30), rs.uniform(-30, 30))
    shape = synth.Shape(cls, params, pose, L, span, curve)
    reach = synth.touch_reach(SAMPLES, SPACING * L)
    lo, hi = span
    if cls == "semicubical_parabola":  # no touch reaches across the cusp
        clear = synth._clear_of_cusp(curve, 1.02 * reach, max(abs(hi), 1e-9))
        lo, hi = max(lo, clear), max(hi, max(lo, clear) + 0.3 * (hi - lo))
    edges = np.linspace(lo, hi, 4)
    ts = np.array([rs.uniform(a + 0.05 * (b - a), b - 0.05 * (b - a)) for a, b in zip(edges[:-1], edges[1:])])
    sign = 1.0
    if cls == "semicubical_parabola":
        sign = float(rs.choice([-1, 1]))
        ts = np.sort(ts * (rs.choice([-1.0, 1.0], 3) if both else sign))
    clear = 0.0
    if cls == "semicubical_parabola":
        clear = synth._clear_of_cusp(curve, 1.02 * reach, max(abs(hi), 1e-9))
    if dist == "wide" and (i // len(names)) % 4 == 3:  # one place touched twice
        ts = np.sort(np.append(ts, ts[int(rs.integers(3))]))
    return region, shape, ts, (lo, hi, sign, both, clear), rs


def _touches(shape, ts, rs, direction):
    noise = synth.SynthNoise(SPEC_PHI, SPEC_POS_FRAC * shape.size)
    touches, _ = synth.sample_shape(shape, ts, SAMPLES, SPACING * shape.size, direction, noise, rs, with_s=False)
    return touches, noise


@dataclass(frozen=True)
class Trial:
    """Trial i of a class as every run of it draws it: ``draw_case``'s region, shape, contact
    ts and region bounds, the traversal direction, and the 3 (or 4) noisy touches with their
    noise model; ``rs`` has made those draws, so the random touches' draws come next."""

    region: str
    shape: synth.Shape
    ts: np.ndarray
    lo: float
    hi: float
    sign: float
    both: bool
    clear: float
    direction: int
    touches: list
    noise: NoiseModel
    rs: np.random.Generator

    def random_t(self) -> float:
        """A random touch's place in the region (a semicubical's clear of its cusp, on the
        touched branch or, with ``both``, either): the bench's next draw from ``rs``."""
        t = self.rs.uniform(self.lo, self.hi)
        if self.shape.cls == "semicubical_parabola":
            t = max(abs(t), self.clear) * (self.rs.choice([-1.0, 1.0]) if self.both else self.sign)
        return t


def drawn_trial(cls: str, i: int, seed: int, dist: str = "hand") -> Trial:
    """Trial i of ``cls`` drawn in the bench's order: ``draw_case``, the direction, the touches."""
    region, shape, ts, (lo, hi, sign, both, clear), rs = draw_case(cls, i, seed, dist)
    direction = int(rs.choice([-1, 1]))
    touches, noise = _touches(shape, ts, rs, direction)
    return Trial(region, shape, ts, lo, hi, sign, both, clear, direction, touches, NoiseModel(noise.phi, noise.pos), rs)


def _recognize(touches, nm, reach=None, missed=()):
    """(recognition, CPU s, request) of ``touches``; ``missed``: the places where sent touches
    were lost (``options.missed``: next_touch keeps off them)."""
    opt = {k: v for k, v in (("reach", reach), ("missed", tuple(missed))) if v}
    req = Request(tuple(SamplesTouch(t.phi, t.x, t.y, t.s) for t in touches), None, CLASSES, nm, opt)
    opts = RecognizeOptions(noise=nm, reach=reach, missed=tuple(missed), **PROFILES["balanced"].options())
    t0 = time.process_time()
    out = recognize(req, opts)
    return out, time.process_time() - t0, req


def _oracle(shape, ts, direction, rec, req, nm, extra_ts=()) -> str:
    """'data-limited' or 'search miss' for a wrong answer (module docstring); ``extra_ts``:
    the true t's of touches appended after the first ones (the suggested ones)."""
    t_true = np.concatenate((np.asarray(ts if direction > 0 else ts[::-1], float), np.asarray(extra_ts, float)))
    truth = refine_one(Candidate(shape.cls, dict(shape.params), shape.pose, t_true, 0.0, 0, 0), req.touches, nm)
    if rec.cls == "unclassified":
        return "search miss" if truth.consistent else "data-limited"
    t_ans = np.array([c["t"] for c in rec.contacts], float)
    ans = refine_one(Candidate(rec.cls, dict(rec.params), rec.pose, t_ans, 0.0, 0, 0), req.touches, nm)
    if ans.bic <= truth.bic * (1 + 1e-9) + 1e-9:
        return "data-limited"
    if shape.cls in LIMIT_OF.get(rec.cls, ()) and \
            2.0 * (truth.loglik - ans.loglik) <= chi2_limit(MODEL_ALPHA, N_SHAPE[shape.cls] - N_SHAPE[rec.cls]):
        return "data-limited"
    return "search miss"


def _ranking(rec) -> list:
    """(class, consistent, χ², dof, BIC) of every candidate: enough to replay the model choice."""
    return [[r.cls, bool(r.consistent), float(r.chi2), int(r.dof), float(r.bic)] for r in rec.ranking]


def _rival(rec) -> bool:
    """Whether a class answer said it could not tell (a close rival named:
    recognizer.classify.close_rivals)."""
    return rec.cls != "unclassified" and any("rival_bic" in a for a in rec.also_fits)


def _named(rec) -> list[str]:
    """The classes a class answer names as also fitting (``also_fits``: close rivals and the
    richer classes it is a limit of)."""
    return [a["class"] for a in rec.also_fits] if rec.cls != "unclassified" else []


def _extra_touch(shape, t, rs, direction):
    touches, _ = _touches(shape, [t], rs, direction)
    return touches[0]


def _object_range(shape, lo, hi):
    """The object's extent in t: the whole curve around the region, both sides of the
    vertex, cusp or inflection (|t| up to twice the region's farthest plus its span; a
    closed curve all round: None)."""
    if shape.curve.t_period is not None:
        return None
    far = 2.0 * max(abs(lo), abs(hi)) + (hi - lo)
    return (-far, far)


def _closest_t(shape, x, y, lo, hi, clear):
    """The true curve's parameter closest to a suggested point (``--aim nearest``): the
    object is the whole curve around the region (``_object_range``; a semicubical touch
    kept clear of the cusp: a pad cannot roll through it)."""
    rng = _object_range(shape, lo, hi)
    if rng is None:
        t = np.linspace(-np.pi, np.pi, 4000)
    else:
        t = np.linspace(0.0, rng[1], 8000)
        if shape.cls == "semicubical_parabola":
            t = np.maximum(t, clear)
        t = np.concatenate((-t[::-1], t))
    px, py = shape.pose.apply(*shape.curve.point(t))
    return float(t[int(np.argmin(np.hypot(px - x, py - y)))])


def _send(shape, x, y, phi, lo, hi, clear, aim, left, direction) -> Landing:
    """Where a touch sent to (x, y) with pad orientation ``phi`` lands: ``approach``, a pad
    coming in along its normal (tools.pad_approach: lost where it meets no smooth stretch
    with room for its roll); ``nearest``, the true curve's point nearest the place."""
    if aim == "nearest":
        t = _closest_t(shape, x, y, lo, hi, clear)
        qx, qy = shape.pose.apply(*shape.curve.point(t))
        return Landing(t, "", float(math.hypot(float(qx) - x, float(qy) - y)))
    ds = SPACING * shape.size
    return land(shape.curve, shape.pose, _object_range(shape, lo, hi), x, y, phi, left, direction,
                PAD_ROLLS * (SAMPLES - 1) * ds, synth.touch_reach(SAMPLES, ds), shape.size)


def _aim_at(shape, t, direction):
    """(x, y, pad orientation) of the true curve's point t."""
    x, y = shape.pose.apply(*shape.curve.point(np.array([t])))
    phi = float(np.asarray(shape.curve.tangent_angle(np.array([t])), float)[0]) + shape.pose.theta
    return float(x[0]), float(y[0]), phi + (math.pi if direction < 0 else 0.0)


def _random_aim(shape, t, direction, rec, touches):
    """Where a hand sends a random touch at the region's point t (``--aim approach``): the
    place as the hand knows it, the 3-touch answer's curve at its point nearest the true
    one, with that curve's tangent in the direction of travel (the true point and tangent
    when the answer is ``unclassified``: the hand has no curve)."""
    x, y, phi = _aim_at(shape, t, direction)
    if rec.cls == "unclassified" or rec.pose is None:
        return x, y, phi
    curve = CURVES[rec.cls](rec.params)
    tc = np.array([c["t"] for c in rec.contacts], float)
    if curve.t_period is not None:
        dense = np.linspace(-np.pi, np.pi, 4000, endpoint=False)
    else:
        w = max(float(np.ptp(tc)), 1e-9)
        dense = np.linspace(tc.min() - 2.0 * w, tc.max() + 2.0 * w, 4000)
    cx, cy = rec.pose.apply(*curve.point(dense))
    k = int(np.nanargmin(np.hypot(cx - x, cy - y)))
    ang = float(np.asarray(curve.tangent_angle(dense[k:k + 1]), float)[0]) + rec.pose.theta
    way = travel_direction(curve, rec.pose, tc, [tt.phi[len(tt.phi) // 2] for tt in touches])
    return float(cx[k]), float(cy[k]), ang + (math.pi if way < 0 else 0.0)


SUGGESTED_ATTEMPTS = 2
"""suggested touches sent per trial, landed or lost (as many as the random ones)."""


@dataclass
class Suggested:
    """The ``3 + ≤2 suggested`` stage of a trial: the last recognition and its request (None
    when none followed an attempt), how many suggested touches landed, each one sent (its
    landing, why it was lost, the suggestion's reason, leader and next_touch ms), and the
    next_touch ms of every recognition after an attempt (a re-ask after a lost one included)."""

    rec: object
    request: Request | None
    used: int
    sent: list
    nt_ms: list


def suggested_touches(rec, touches, nm, send, touch_at) -> Suggested:
    """Up to ``SUGGESTED_ATTEMPTS`` touches where ``next_touch`` says, from the 3-touch
    recognition ``rec`` of ``touches``: each sent (``send(next_touch)`` → Landing) is one
    attempt, landed or lost; a landed one is touched (``touch_at(t)`` → the touch) and the
    touches recognized again, a lost one sent back as missed (``options.missed``) and, while an
    attempt is left, the next suggestion asked for with the same touches, as a hand whose touch
    met nothing asks again."""
    cur, tl, missed, out = rec, list(touches), [], Suggested(rec, None, 0, [], [])
    for attempt in range(SUGGESTED_ATTEMPTS):
        nt = cur.next_touch
        if nt is None:
            break
        landing = send(nt)
        out.sent.append({"t": landing.t, "why": nt["why"], "leader": cur.cls, "lost": landing.why,
                         "ms": cur.timing.get("next_touch_cpu_ms"), "miss_mm": landing.miss_mm})
        if landing.t is not None:
            tl.append(touch_at(landing.t))
            out.used += 1
        elif attempt + 1 < SUGGESTED_ATTEMPTS:
            missed.append(MissedPlace(nt["x"], nt["y"], nt["phi"]))
        else:
            break  # lost, and no attempt left to ask again for
        cur, _, req = _recognize(tl, nm, missed=missed)
        out.rec, out.request = cur, req
        out.nt_ms.append(cur.timing.get("next_touch_cpu_ms", math.nan))
    return out


def _exact(shape, ts, direction) -> dict:
    """The same touches noise-free (noise model zero): class and relative error."""
    touches, _ = synth.sample_shape(shape, ts, SAMPLES, SPACING * shape.size, direction, None, None, with_s=False)
    rec, dt, _ = _recognize(touches, NoiseModel(0.0, 0.0))
    err = rel_error(shape.params, rec.params) if rec.cls == shape.cls else math.nan
    return {"got0": rec.cls, "err0": err, "exact": bool(rec.cls == shape.cls and err <= EXACT_REL),
            "why0": rec.reason if rec.cls != shape.cls else "", "ms0": 1e3 * dt}


def run_trial(task) -> dict:
    cls, i, seed, *rest = task
    coverage_only = bool(rest and rest[0])
    dist = rest[1] if len(rest) > 1 else "hand"
    aim = rest[2] if len(rest) > 2 else "approach"
    tr = drawn_trial(cls, i, seed, dist)
    shape, ts, direction, touches, nm, rs = tr.shape, tr.ts, tr.direction, tr.touches, tr.noise, tr.rs
    lo, hi, clear = tr.lo, tr.hi, tr.clear
    out = {"cls": cls, "region": tr.region, "i": i, "L": float(shape.size), "repeated": bool(len(ts) > 3)}
    if dist == "wide" and not coverage_only:
        out.update(_exact(shape, ts, direction))
    rec, dt, req = _recognize(touches, nm)
    out.update(rival3=_rival(rec), named3=_named(rec), rank3=_ranking(rec), got3=rec.cls, err3=rel_error(shape.params, rec.params) if rec.cls == cls else math.nan, ms=1e3 * dt,
               nt_ms=rec.timing.get("next_touch_cpu_ms", math.nan))
    if rec.cls == cls:
        out["z"], out["zi"] = _z(shape, rec)
    if coverage_only:
        return out
    if rec.cls != cls:
        out["oracle"] = _oracle(shape, ts, direction, rec, req, nm)
    # two random extra touches in the region, sent as a hand sends any touch (``aim``:
    # ``approach``, to the region's point as the 3-touch answer places it, with its tangent)
    left = solid_left(shape.curve, ts, direction)
    extra = []
    for _ in range(2):
        t = tr.random_t()
        if aim == "nearest":  # touched where drawn
            landing = Landing(t, "", 0.0)
        else:
            landing = _send(shape, *_random_aim(shape, t, direction, rec, touches), lo, hi, clear, aim, left, direction)
        out.setdefault("random", []).append({"t": landing.t, "lost": landing.why})
        if landing.t is not None:
            extra.append(_extra_touch(shape, landing.t, rs, direction))
    rec5, _, _ = _recognize(list(touches) + extra, nm)
    out.update(rank5=_ranking(rec5), got5=rec5.cls, err5=rel_error(shape.params, rec5.params) if rec5.cls == cls else math.nan)
    def send(nt) -> Landing:
        return _send(shape, nt["x"], nt["y"], nt["phi"], lo, hi, clear, aim, left, direction)

    sug = suggested_touches(rec, touches, nm, send, lambda t: _extra_touch(shape, t, rs, direction))
    cur, used, reqS = sug.rec, sug.used, sug.request
    out.update(suggested=sug.sent, nt_ms_all=[out["nt_ms"]] + sug.nt_ms)
    if cur.cls != cls and used:
        out["oracleS"] = _oracle(shape, ts, direction, cur, reqS, nm, [s["t"] for s in sug.sent if s["t"] is not None])
    out.update(rivalS=_rival(cur), namedS=_named(cur), rankS=_ranking(cur), t3=[float(v) for v in ts], span=[float(lo), float(hi)],
               params=dict(shape.params), gotS=cur.cls, errS=rel_error(shape.params, cur.params) if cur.cls == cls else math.nan, used=used)
    if cur.cls == cls:
        out["zS"], out["ziS"] = _z(shape, cur)
    return out


def _z(shape, rec) -> tuple[list, list]:
    """The right answer's z = (stated − true) / stated σ of each shape parameter it states a σ
    for, and the same against its 95 % interval (tools.bench_sigma.interval_z)."""
    stated = [(k, v) for k, v in shape.params.items() if rec.uncertainty.get(k) and rec.uncertainty[k] > 0]
    return ([(rec.params[k] - v) / rec.uncertainty[k] for k, v in stated],
            [interval_z(rec, k, v) for k, v in stated])


def _pct(v) -> str:
    return f"{100 * float(np.mean(v)):.1f}" if len(v) else "–"


def _med(v) -> str:
    v = [x for x in v if np.isfinite(x)]
    return f"{100 * float(np.median(v)):.3g}" if v else "–"


def report(recs: list[dict]) -> str:
    lines = []
    groups = [("all", recs)] + [(c, [r for r in recs if r["cls"] == c]) for c in CLASSES]
    lines += ["| class | trials | 3 touches: right % | median err % | search misses % | data-limited % | "
              "3+2 random: right % | median err % | 3+≤2 suggested: right % | median err % | suggested used | "
              "suggested aim miss mm (median / max) | touches lost (random / suggested) | σ coverage (1.96σ) % | RMS z | compute ms | "
              "next_touch ms (mean / max) | noise-free exact % |",
              "|---|" + "---|" * 17]
    for name, rs in groups:
        if not rs:
            continue
        z = np.array([v for r in rs for v in r.get("z", [])], float)
        cov = _pct(np.abs(z) <= 1.96) if z.size else "–"
        rms = f"{math.sqrt(float(np.mean(z ** 2))):.2f}" if z.size else "–"
        nt = np.array([v for r in rs for v in r.get("nt_ms_all", [r["nt_ms"]])], float)
        nt = nt[np.isfinite(nt)]
        miss = [s["miss_mm"] for r in rs for s in r.get("suggested", ()) if s.get("t") is not None]
        lost = (f"{sum(bool(x.get('lost')) for r in rs for x in r.get('random', ()))} of {sum(len(r.get('random', ())) for r in rs)} / "
                f"{sum(bool(x.get('lost')) for r in rs for x in r.get('suggested', ()))} of {sum(len(r.get('suggested', ())) for r in rs)}")
        lines.append(
            f"| {name} | {len(rs)} | {_pct([r['got3'] == r['cls'] for r in rs])} | {_med([r['err3'] for r in rs])} | "
            f"{_pct([r.get('oracle') == 'search miss' for r in rs])} | {_pct([r.get('oracle') == 'data-limited' for r in rs])} | "
            f"{_pct([r['got5'] == r['cls'] for r in rs])} | {_med([r['err5'] for r in rs])} | "
            f"{_pct([r['gotS'] == r['cls'] for r in rs])} | {_med([r['errS'] for r in rs])} | "
            f"{np.mean([r['used'] for r in rs]):.2f} | "
            f"{(f'{np.median(miss):.2g} / {np.max(miss):.2g}') if miss else '–'} | {lost} | {cov} | {rms} | {np.mean([r['ms'] for r in rs]):.0f} | "
            f"{(f'{nt.mean():.0f} / {nt.max():.0f}') if nt.size else '–'} | {_exact_pct(rs)} |")
    lines += ["", "Per region (3 touches / 3 + 2 random / 3 + ≤2 suggested, right class %):", "",
              "| class | region | trials | 3 | 3+2 random | 3+≤2 suggested | search misses (3 / suggested) | wrong answers (3) | noise-free exact % |",
              "|---|---|---|---|---|---|---|---|---|"]
    by = defaultdict(list)
    for r in recs:
        by[(r["cls"], r["region"])].append(r)
    for (c, reg), rs in sorted(by.items(), key=lambda kv: (CLASSES.index(kv[0][0]), kv[0][1])):
        wrong = sorted({r["got3"] for r in rs if r["got3"] != c})
        lines.append(f"| {c} | {reg} | {len(rs)} | {_pct([r['got3'] == c for r in rs])} | "
                     f"{_pct([r['got5'] == c for r in rs])} | {_pct([r['gotS'] == c for r in rs])} | "
                     f"{sum(r.get('oracle') == 'search miss' for r in rs)} / {sum(r.get('oracleS') == 'search miss' for r in rs)} | "
                     f"{', '.join(wrong) or '–'} | {_exact_pct(rs)} |")
    for k, what in (("3", "3 touches"), ("S", "3 + ≤2 suggested")):
        said = [r for r in recs if r.get("rival" + k)]
        lines += ["", f"Answers that said they could not tell a close rival (ΔBIC < {RIVAL_BIC:g}), {what}: "
                  f"{len(said)} of {len(recs)}, {sum(r['got' + k] == r['cls'] for r in said)} of them right; "
                  f"wrong answers that did not say so: "
                  f"{sum(r['got' + k] not in (r['cls'], 'unclassified') for r in recs if not r.get('rival' + k))}."]
        wrong = [r for r in recs if r["got" + k] not in (r["cls"], "unclassified")]
        right = [r for r in recs if r["got" + k] == r["cls"]]
        lines += [f"Wrong answers ({what}) naming the true class among those that also fit (a close rival, or a "
                  f"richer class the answer is a limit of): {sum(r['cls'] in r.get('named' + k, ()) for r in wrong)} "
                  f"of {len(wrong)}; right answers naming a close rival: {sum(bool(r.get('rival' + k)) for r in right)} "
                  f"of {len(right)}."]
    rep = [r for r in recs if r.get("repeated")]
    if rep:
        lines += ["", f"Trials with one place touched twice: {len(rep)}; right class 3 / 3+2 random / 3+≤2 suggested: "
                  f"{_pct([r['got3'] == r['cls'] for r in rep])} / {_pct([r['got5'] == r['cls'] for r in rep])} / "
                  f"{_pct([r['gotS'] == r['cls'] for r in rep])} %; noise-free exact {_exact_pct(rep)} %."]
    lines += ["", "σ coverage of the right 3-touch answers, per class and per decade of the region size L:", "",
              coverage_report(recs)]
    lines += ["", "σ coverage of the right 3 + ≤ 2 suggested answers, per class and per decade of the region size L:",
              "", coverage_report(recs, "S")]
    inexact = [r for r in recs if "exact" in r and not r["exact"]]
    if inexact:
        lines += ["", "Noise-free answers not exact (class right and relative error ≤ 1e-6):", ""]
        lines += [f"- {r['cls']} trial {r['i']} ({r['region']}, L {r['L']:.3g} mm): {r['got0']}"
                  + (f", error {r['err0']:.2g}" if r["got0"] == r["cls"] else f" ({r['why0']})") for r in inexact]
    return "\n".join(lines)


def _exact_pct(rs) -> str:
    return _pct([r["exact"] for r in rs if "exact" in r])


def _wilson(k: int, n: int, z: float = 1.96) -> tuple[float, float]:
    """95 % Wilson score interval of a binomial proportion k/n."""
    p = k / n
    mid = (p + z * z / (2 * n)) / (1 + z * z / n)
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / (1 + z * z / n)
    return mid - half, mid + half


def _decade(r: dict) -> int:
    """The scale decade k of a trial's region size L (10^k ≤ L < 10^(k+1) mm)."""
    return int(math.floor(math.log10(r["L"])))


def coverage_report(recs: list[dict], stage: str = "") -> str:
    """Per class and per scale decade of L: σ coverage of the right 3-touch answers (``stage``
    "S": of the right answers after ≤ 2 suggested touches) with its 95 % (Wilson) interval,
    within 3 σ, RMS z, the same with the answer's 95 % interval (``Recognition.interval``;
    tools.bench_sigma.interval_z) and the largest |z|."""
    lines = ["| class / decade of L | trials | right % | values | σ coverage (1.96σ) % | 95 % interval | ≤ 3σ % | RMS z | "
             "interval: ≤ 1.96 / ≤ 3 % | largest |z| |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    groups = [(name, [r for r in recs if name in ("all", r["cls"])]) for name in ("all",) + CLASSES]
    sized = [r for r in recs if "L" in r]  # (records of an earlier bench_wide carry no L)
    groups += [(f"L 1e{k} mm", [r for r in sized if _decade(r) == k]) for k in sorted({_decade(r) for r in sized})]
    for name, rs in groups:
        z = np.abs(np.array([v for r in rs for v in r.get("z" + stage, [])], float))
        zi = np.abs(np.array([v for r in rs for v in r.get("zi" + stage, r.get("z" + stage, []))], float))
        if not z.size:
            continue
        k = int(np.sum(z <= 1.96))
        lo, hi = _wilson(k, z.size)
        got = "gotS" if stage else "got3"
        lines.append(f"| {name} | {len(rs)} | {_pct([r.get(got) == r['cls'] for r in rs])} | {z.size} | "
                     f"{100 * k / z.size:.1f} | {100 * lo:.1f}–{100 * hi:.1f} | {_pct(z <= 3.0)} | "
                     f"{math.sqrt(float(np.mean(z ** 2))):.2f} | {_pct(zi <= 1.96)} / {_pct(zi <= 3.0)} | {z.max():.3g} |")
    return "\n".join(lines)


def run_wide(classes, trials: int, seed: int, jobs: int, progress, first: int = 0,
             coverage_only: bool = False, dist: str = "wide", aim: str = "approach") -> list[dict]:
    """Every trial's record (``trials`` per class from trial ``first``), in ``jobs``
    processes; ``coverage_only``: the 3-touch recognition alone; ``dist``: the trials'
    distribution (``SETS``); ``aim``: where a sent touch lands (``AIMS``)."""

    tasks = [(c, i, seed, coverage_only, dist, aim) for c in classes for i in range(first, first + trials)]
    recs = []
    t0 = time.perf_counter()
    pool = _pool(jobs) if jobs > 1 else None
    it = pool.imap_unordered(run_trial, tasks) if pool else map(run_trial, tasks)
    try:
        for k, r in enumerate(it, 1):
            recs.append(r)
            progress(f"wide: {k}/{len(tasks)} ({time.perf_counter() - t0:.0f} s)", k == len(tasks))
    finally:
        if pool:
            pool.terminate()
    return recs


def markdown(recs: list[dict], command: str, wall_s: float, jobs: int) -> str:
    return (f"Generated by `{command}` ({len(recs)} trials, {wall_s:.0f} s wall, {jobs} processes; "
            "compute and next_touch times are CPU time per recognition).\n\n" + report(recs))


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--trials", type=int, default=40, help="trials per class (regions in turn)")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--classes", nargs="+", default=list(CLASSES))
    ap.add_argument("--out", default=None, help="also write the tables to this markdown file")
    ap.add_argument("--records", default=None, help="also write every trial's record to this JSON file")
    ap.add_argument("--coverage-only", action="store_true",
                    help="only the 3-touch recognitions: sigma coverage per class with its 95 %% interval")
    ap.add_argument("--first", type=int, default=0, help="index of the first trial of each class")
    ap.add_argument("--set", choices=SETS, default="wide",
                    help="wide: the widened distributions (L 1-1500 mm, far stretches, thin ellipses' sharp ends, "
                         "small shapes, repeated touches; noise-free exactness); hand: the earlier regions, L 30-120 mm")
    ap.add_argument("--aim", choices=AIMS, default="approach",
                    help="approach: a sent touch lands where a pad with its orientation, coming in along its normal, "
                         "first meets the object, or is lost (a lost suggested touch counts as one of the two "
                         "suggested attempts and is sent back as options.missed for the next suggestion); nearest: "
                         "at the true curve's point nearest the place (the rule before session 17, an upper bound)")
    args = ap.parse_args(argv)
    if args.trials < 1 or args.first < 0:
        raise SystemExit("bench_wide: --trials must be >= 1 and --first >= 0")
    t0 = time.perf_counter()

    def progress(msg: str, final: bool) -> None:
        sys.stderr.write(f"\r[bench_wide] {msg}   " + ("\n" if final else ""))
        sys.stderr.flush()

    recs = run_wide(args.classes, args.trials, args.seed, args.jobs, progress, args.first, args.coverage_only, args.set, args.aim)
    if args.coverage_only:
        text = (f"Generated by `python -m tools.bench_wide --coverage-only --first {args.first} --trials {args.trials} "
                f"--seed {args.seed} --set {args.set}` ({len(recs)} trials, {time.perf_counter() - t0:.0f} s wall).\n\n"
                + coverage_report(recs))
    else:
        text = markdown(recs, f"python -m tools.bench_wide --set {args.set} --trials {args.trials} --seed {args.seed}"
                              + (f" --first {args.first}" if args.first else "") + f" --aim {args.aim}",
                        time.perf_counter() - t0, args.jobs)
    print(text)
    if args.out:
        with open(args.out, "w", encoding="utf-8") as f:
            f.write(text + "\n")
    if args.records:
        with open(args.records, "w", encoding="utf-8") as f:
            json.dump(sorted(recs, key=lambda r: (CLASSES.index(r["cls"]), r["i"])), f, default=float)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
