"""Nested starts: a richer class started from the fit of a class that is its limit.

A circle is an ellipse with a = b; a parabola is the limit of ellipses and hyperbolas
(a → ∞ with b²/a = 2A fixed: their vertex curvature a/b² stays the parabola's 1/(2A)) and
of both cubic families far from the inflection or the cusp (the hump of (t, a t³ + c t)
at t_h, c = −3a t_h², with 3 a t_h = 1/(4A) as t_h → ∞; a point of the semicubical
(t², a t³ + b t²) at t_0 with b = ∓(3/2) a |t_0|, where its slope is 0, with
(3/4) a / |t_0| = 1/(2A) as |t_0| → ∞). So the richer class fits any touches at least as
well as its limit; its own closed-form starts (recognizer.starts) sit in the ill-conditioned
far end of its family and can miss that (a cubical at χ² 18.5 where the parabola reached
4.5). :func:`nested_candidates` places the richer class at a member close to the limit's
fit — the touched stretch a small fraction (``NEAR_LIMIT``) of the distance to the
inflection, cusp or far vertex — so that refinement starts within a hair of the limit's χ²
and can only go down from there. docs/recognition.md#nested-starts.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from recognizer.class_limits import LIMIT_OF
from recognizer.curves import CURVES, Pose
from recognizer.result import Candidate

__all__ = ["NESTED_FROM", "NEAR_LIMIT", "nested_candidates"]

#: the richer classes started from each limit class's fit, in CURVES order (LIMIT_OF without
#: the line: every curved class contains it, and the jaw's lines are flat presses)
NESTED_FROM = {limit: tuple(cls for cls in CURVES if cls in richer)
               for limit, richer in LIMIT_OF.items() if limit != "line"}
#: the touched stretch (its largest distance from the limit's vertex across its axis) as
#: fractions of the distance from the vertex to where the richer member departs (its far
#: vertex, inflection or cusp), one start each: the start differs from the limit's curve by
#: about a third of the fraction times the stretch's sagitta (a circle's start is an ellipse
#: of a/b − 1 = the fraction). Measured on a parabola's touches (4 × 9 samples, σ 0.02 mm,
#: sagitta 6.3 mm, limit χ² 51.1): from 0.1 the cubical starts at χ² 8393 and refines to
#: 55.9; from 0.03 to 51.3, from 0.01 to 51.1 (the ellipse: 57.6, 50.8, 51.1): the farther
#: out, the worse the family's conditioning, the nearer, the farther LM has to go
NEAR_LIMIT = (0.03, 0.01)


def _place(limit: Candidate, cls: str, params: dict, rot: float, origin: tuple[float, float], t) -> Candidate:
    """A candidate of ``cls`` whose canonical frame is the limit's turned by ``rot`` with its
    origin at ``origin`` (limit's canonical frame), contact parameters ``t``."""
    x, y = (float(v) for v in limit.pose.apply(*origin))
    return replace(limit, cls=cls, params=params, pose=Pose(limit.pose.theta + rot, x, y), t=np.asarray(t, float),
                   uncertainty={}, reason=None)


def _from_parabola(limit: Candidate, cls: str, fraction: float) -> list[Candidate]:
    """Members of ``cls`` near the parabola ``limit`` (its frame: vertex at 0, the curve
    (A t², 2A t) opening toward +x)."""
    A = float(limit.params["a"])
    t = np.asarray(limit.t, float)
    y = 2.0 * A * t  # across the axis
    span = max(float(np.max(np.abs(y))), 2.0 * A)
    far = span / fraction  # where the richer member departs from the parabola
    if cls in ("ellipse", "hyperbola"):
        a = far * far / (2.0 * A)  # b = far, b²/a = 2A
        b = far
        if cls == "ellipse":  # vertex (−a, 0) of the ellipse centred at (a, 0)
            return [_place(limit, cls, {"a": a, "b": b}, 0.0, (a, 0.0), math.pi - np.arcsin(y / b))]
        return [_place(limit, cls, {"a": a, "b": b}, 0.0, (-a, 0.0), np.arcsinh(y / b))]
    out = []
    for sign in (1.0, -1.0):  # the richer member bends away on either side of the axis
        if cls == "cubical_parabola":
            th = sign * far  # hump at t_h, the parabola's axis along the cubical's +y
            a = 1.0 / (12.0 * A * th)
            c = -3.0 * a * th * th
            hump = (th, a * th**3 + c * th)
            # cubical frame = parabola frame turned by +90° about the hump: t = t_h − y
            cand = _place(limit, cls, {"a": a, "c": c}, -math.pi / 2, _back(hump, -math.pi / 2), th - y)
        else:
            x0 = far  # the point t_0 = sign·√x0 of the semicubical's branch on that side
            a = 2.0 * math.sqrt(x0) / (3.0 * A)
            b = -sign * 1.5 * a * math.sqrt(x0)
            t0 = sign * math.sqrt(x0)
            point = (x0, a * t0**3 + b * t0 * t0)
            rot = -sign * math.pi / 2  # branch t > 0 opens toward +y, t < 0 toward −y
            u = x0 - sign * y  # the semicubical's x at each contact
            cand = _place(limit, cls, {"a": a, "b": b}, rot, _back(point, rot), sign * np.sqrt(np.maximum(u, 0.0)))
        out.append(cand)
    return out


def _back(point: tuple[float, float], rot: float) -> tuple[float, float]:
    """Origin (limit's frame) of a frame turned by ``rot`` in which the limit's vertex is ``point``."""
    c, s = math.cos(rot), math.sin(rot)
    return -(c * point[0] - s * point[1]), -(s * point[0] + c * point[1])


def nested_candidates(limit: Candidate, cls: str, fractions: tuple[float, ...] = NEAR_LIMIT) -> list[Candidate]:
    """Unrefined starts of the richer class ``cls`` next to the limit class's fit ``limit``
    (``NESTED_FROM``), one per fraction (``NEAR_LIMIT``) and, for the cubic families, per
    side the member bends to (recognizer.refine then fits them)."""
    if cls not in NESTED_FROM.get(limit.cls, ()):
        return []
    return [c for fraction in fractions for c in _nested(limit, cls, fraction)]


def _nested(limit: Candidate, cls: str, fraction: float) -> list[Candidate]:
    if limit.cls == "circle":
        r = float(limit.params["r"])
        return [replace(limit, cls="ellipse", params={"a": r * (1.0 + fraction), "b": r},
                        t=np.asarray(limit.t, float), uncertainty={}, reason=None)]
    return _from_parabola(limit, cls, fraction)
