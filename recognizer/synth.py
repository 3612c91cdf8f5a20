"""Synthetic touches from exact curves, with noise: the shared generator of the benchmark
and the tests.

A touch is ``n`` samples at equal arc-length spacing ``ds`` around a contact parameter
``t_c`` (the middle sample n // 2 sits exactly at t_c), traversed in increasing t
(``direction=+1``) or decreasing t (``-1``: tangent angles turn by π and κ changes
sign), mapped to the hand frame by a pose. Noise (all Gaussian, independent):
``phi`` rad on every tangent angle, ``pos`` mm on every x and y, ``s`` mm on every given
arc length (the first stays 0).

Random shapes (:func:`random_shape`) have a size L (mm, the extent of the part of the
boundary that is touched: its largest chord) drawn from ``size_range``; each class's
shape is drawn at unit size and scaled so that the touched region spans exactly L, with
random aspect (ellipse b/a in [0.35, 0.9], hyperbola b/a in [0.4, 2.0], cubic
coefficients of either sign, the cubics' second coefficient (c, b) of magnitude in
[0.3, 1]). The semicubical parabola is touched on both branches around its cusp
(:func:`region`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Sequence

import numpy as np
from scipy import optimize

from recognizer.curves import CURVES, Curve, Pose
from recognizer.touches import SamplesTouch


@dataclass(frozen=True)
class SynthNoise:
    """Standard deviations: ``phi`` rad, ``pos`` mm (x and y), ``s`` mm (given arc length)."""

    phi: float = 0.0
    pos: float = 0.0
    s: float = 0.0


@dataclass(frozen=True)
class Shape:
    """A random shape: class, parameters, pose, size L (mm) and the contact range of t."""

    cls: str
    params: dict[str, float]
    pose: Pose
    size: float
    t_range: tuple[float, float]
    curve: Curve = field(repr=False, compare=False, default=None)  # type: ignore[assignment]


def t_at_arc(curve: Curve, t0: float, s: np.ndarray) -> np.ndarray:
    """Parameters reached after signed arc lengths ``s`` from ``t0`` (Newton on the
    speed, bracketed by brentq when Newton stalls); ~1e-13 relative."""
    out = np.empty(len(s))
    for i, target in enumerate(np.asarray(s, dtype=float)):
        if target == 0.0:
            out[i] = t0
            continue
        t = t0 + target / max(float(curve.speed(t0)), 1e-300)
        ok = False
        for _ in range(50):
            f = float(curve.arc_length(t0, t)) - target
            sp = max(float(curve.speed(t)), 1e-300)
            step = f / sp
            t -= step
            if abs(step) <= 1e-14 * max(abs(t), 1.0):
                ok = True
                break
        if not ok:
            b = t0 + 2 * target / max(float(curve.speed(t0)), 1e-300)
            g = lambda u: float(curve.arc_length(t0, u)) - target  # noqa: E731
            while np.sign(g(b)) != np.sign(target):
                b = t0 + 2 * (b - t0)
            t = optimize.brentq(g, min(t0, b), max(t0, b), xtol=1e-14)
        out[i] = t
    return out


def touch_reach(n: int, ds: float) -> float:
    """Arc length (mm) a touch of ``n`` samples ``ds`` apart reaches from its contact, on
    its longer side (:func:`sample_touch`'s layout: the contact is sample n // 2)."""
    return max(n // 2, n - 1 - n // 2) * ds


def sample_touch(curve: Curve, pose: Pose, t_c: float, n: int, ds: float, direction: int = 1,
                 noise: SynthNoise | None = None, rng: np.random.Generator | None = None,
                 with_s: bool = True) -> tuple[SamplesTouch, np.ndarray]:
    """A touch of ``n`` samples spaced ``ds`` (mm of arc) around t_c; returns the touch and
    the exact parameters t of its samples."""
    m = n // 2
    offsets = (np.arange(n) - m) * ds * direction
    ts = t_at_arc(curve, t_c, offsets)
    px, py = curve.point(ts)
    hx, hy = pose.apply(px, py)
    phi = np.asarray(curve.tangent_angle(ts), dtype=float) + pose.theta + (np.pi if direction < 0 else 0.0)
    phi = np.unwrap(phi)
    s = np.arange(n) * ds
    hx, hy = np.asarray(hx, dtype=float), np.asarray(hy, dtype=float)
    if noise is not None and rng is not None:
        phi = phi + rng.normal(0.0, noise.phi, n) if noise.phi > 0 else phi
        if noise.pos > 0:
            hx = hx + rng.normal(0.0, noise.pos, n)
            hy = hy + rng.normal(0.0, noise.pos, n)
        if noise.s > 0:
            s = s + np.concatenate(([0.0], rng.normal(0.0, noise.s, n - 1)))
    return SamplesTouch(phi, hx, hy, s if with_s else None), ts


def _uniform(rng: np.random.Generator, lo: float, hi: float) -> float:
    return float(rng.uniform(lo, hi))


def _signed(rng: np.random.Generator, lo: float, hi: float) -> float:
    """A value of random sign with magnitude uniform in [lo, hi] (relative errors of a
    parameter near 0 would measure nothing but its closeness to 0)."""
    return float(rng.choice([-1.0, 1.0]) * rng.uniform(lo, hi))


def region(cls: str, t_range: tuple[float, float], n: int = 400) -> np.ndarray:
    """Parameters t of a class's touched region: ``n`` over ``t_range``, and for the
    semicubical parabola as many over its mirror −t_range too (its other branch: an
    object's boundary runs along both branches into the cusp's tip, and touches fall on
    either side of it, as they fall on both sides of a parabola's vertex)."""
    t = np.linspace(*t_range, n)
    return np.concatenate((-t[::-1], t)) if cls == "semicubical_parabola" else t


def extent(curve: Curve, t: np.ndarray) -> float:
    """Largest distance between two points of the curve at parameters ``t`` (mm)."""
    x, y = curve.point(np.asarray(t, dtype=float))
    return float(np.sqrt(np.max((x[:, None] - x[None, :]) ** 2 + (y[:, None] - y[None, :]) ** 2)))


def _scaled(cls: str, params: dict[str, float], t_range: tuple[float, float], k: float):
    """The same shape enlarged k times: parameters and contact range of t."""
    lo, hi = t_range
    if cls in ("circle", "ellipse", "parabola", "hyperbola"):
        return {n: v * k for n, v in params.items()}, t_range
    if cls == "cubical_parabola":  # (t, a t³ + c t) → (kt, k a t³ + k c t): t' = kt, a' = a/k²
        return {"a": params["a"] / k**2, "c": params["c"]}, (lo * k, hi * k)
    if cls == "semicubical_parabola":  # (t², a t³ + b t²) × k: t' = √k t, a' = a/√k
        return {"a": params["a"] / math.sqrt(k), "b": params["b"]}, (lo * math.sqrt(k), hi * math.sqrt(k))
    return params, (lo * k, hi * k)  # line


def random_shape(cls: str, rng: np.random.Generator, size_range: tuple[float, float] = (30.0, 120.0),
                 pose_range: float = 150.0) -> Shape:
    """A random shape of class ``cls`` in a random pose whose touched region (``t_range``)
    has extent (largest chord) L ∈ size_range mm: the class's shape parameters are drawn
    at unit size, then the curve is scaled so that its touched region spans exactly L."""
    L = _uniform(rng, *size_range)
    if cls == "line":
        params, t_range = {}, (-0.5, 0.5)
    elif cls == "circle":
        params, t_range = {"r": 0.5}, (-np.pi, np.pi)
    elif cls == "ellipse":
        params, t_range = {"a": 0.5, "b": 0.5 * _uniform(rng, 0.35, 0.9)}, (-np.pi, np.pi)
    elif cls == "parabola":
        params, t_range = {"a": 1.0}, (-1.5, 1.5)
    elif cls == "hyperbola":
        params, t_range = {"a": 1.0, "b": _uniform(rng, 0.4, 2.0)}, (-1.2, 1.2)
    elif cls == "cubical_parabola":
        # the slope runs from c at the inflection to 3a + c at the ends t = ±1, |a| in [0.25, 0.75]
        params, t_range = {"a": float(rng.choice([-1.0, 1.0]) * _uniform(rng, 0.25, 0.75)),
                           "c": _signed(rng, 0.3, 1.0)}, (-1.0, 1.0)
    elif cls == "semicubical_parabola":
        # (t², t³ + b t²) with contacts at |t| ∈ [0.8, 1.6] on either branch: from 8–16 % of
        # the touched extent away from the cusp (no touch of 9 samples 2 % of L apart reaches
        # across it; longer touches: contact_ts(reach=...)) to the far ends
        params, t_range = {"a": 1.0, "b": _signed(rng, 0.3, 1.0)}, (0.8, 1.6)
    else:
        raise ValueError(f"unknown class {cls!r}")
    params, t_range = _scaled(cls, params, t_range, L / extent(CURVES[cls](params), region(cls, t_range)))
    pose = Pose(_uniform(rng, -np.pi, np.pi), _uniform(rng, -pose_range, pose_range) * 0.2 + pose_range,
                _uniform(rng, -pose_range, pose_range) * 0.2)
    return Shape(cls, params, pose, L, t_range, CURVES[cls](params))


def _clear_of_cusp(curve: Curve, reach: float, t_hi: float) -> float:
    """Smallest |t| of the semicubical parabola beyond which both branches are at least
    ``reach`` (mm) of arc from the cusp (with b ≠ 0 they differ): a touch reaching
    ``reach`` either side of its contact stays on its branch (a pad cannot roll through
    a cusp)."""
    def f(u: float) -> float:
        return min(float(curve.arc_length(0.0, u)), float(curve.arc_length(-u, 0.0))) - reach

    while f(t_hi) < 0:
        t_hi *= 2.0
    return float(optimize.brentq(f, 0.0, t_hi, xtol=1e-12))


def contact_ts(shape: Shape, k: int, rng: np.random.Generator, margin: float = 0.0,
               reach: float = 0.0) -> np.ndarray:
    """``k`` contact parameters spread over the shape's t-range: one uniformly drawn in
    each of k equal slices (inner ``margin`` fraction of every slice excluded), so the
    touches see different parts of the boundary. The semicubical parabola's touches each
    fall on a branch (t > 0 or t < 0) drawn at random (``region``), and where a touch
    reaching ``reach`` mm of arc either side of its contact (:func:`touch_reach`) could
    cross the cusp, the range is moved out (same width) until none can; increasing t."""
    lo, hi = shape.t_range
    if shape.cls == "semicubical_parabola" and reach > 0:
        shift = _clear_of_cusp(shape.curve, 1.02 * reach, hi) - (lo + margin * (hi - lo) / k)
        if shift > 0:
            lo, hi = lo + shift, hi + shift
    edges = np.linspace(lo, hi, k + 1)
    w = edges[1] - edges[0]
    ts = np.array([_uniform(rng, e + margin * w, e + (1 - margin) * w) for e in edges[:-1]])
    if shape.cls == "semicubical_parabola":
        ts = np.sort(ts * rng.choice([-1.0, 1.0], size=k))
    return ts


def sample_shape(shape: Shape, ts: Sequence[float], n: int, ds: float, direction: int = 1,
                 noise: SynthNoise | None = None, rng: np.random.Generator | None = None,
                 with_s: bool = True) -> tuple[list[SamplesTouch], list[np.ndarray]]:
    """One touch per contact parameter (in the order of traversal for ``direction``)."""
    order = list(ts) if direction > 0 else list(ts)[::-1]
    touches, sample_ts = [], []
    for t_c in order:
        touch, tt = sample_touch(shape.curve, shape.pose, float(t_c), n, ds, direction, noise, rng, with_s)
        touches.append(touch)
        sample_ts.append(tt)
    return touches, sample_ts
