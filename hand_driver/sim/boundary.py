"""The scene object's boundary, exact, for the emulator's contact physics.

This is the one module of ``hand_driver`` that imports the recognizer, and only
``recognizer.curves`` (the exact canonical curves, docs/formats.md): the emulator must show
the very curves the recognizer answers with. Everything the physics needs of an object
goes through :class:`Boundary`:

- :meth:`Boundary.inside` — is a hand-frame point strictly inside the solid;
- :meth:`Boundary.crosses` — does the boundary cross a segment's interior transversally
  (a tangent touch, a flat face lying on the segment's line, a corner on it: no);
- :meth:`Boundary.points` — the boundary sampled in order within a disk (clearance bounds,
  nearest points for diagnostics);
- :attr:`Boundary.corners` — the corners of a finite object (hand frame).

An object is duck-typed (a ``recognizer.scene.SceneObject`` or anything with ``cls``,
``params``, ``pose``, ``side`` and optionally ``extent``/``closure``). An unbounded object
is the region on ``side`` of the whole curve (closed-form predicates). A finite object
(docs/formats.md, scene) is bounded by the curve over ``extent`` = [t0, t1] and the straight segments
P(t1) → closure corners → P(t0); a point is inside when a ray from it crosses that
boundary an odd number of times. Crossings are exact: the boundary meets a line n·p = d
where a closed-form equation in t holds (trigonometric for circle and ellipse, a quadratic
for line/parabola and for e^t on the hyperbola, a cubic for the cubical and semicubical
parabolas), restricted to the extent, and each straight segment in closed form.
"""

from __future__ import annotations

import math

import numpy as np

from recognizer.curves import CURVES

__all__ = ["Boundary"]

# Which side of the increasing-t traversal each class's "region" lies on (see _in_region).
_REGION_SIDE = {"line": "left", "circle": "left", "ellipse": "left", "parabola": "right",
                "hyperbola": "right", "cubical_parabola": "left", "semicubical_parabola": "right"}
#: the inside test's ray direction (rad, canonical frame): an irrational angle, so that a
#: ray through a corner or along a straight segment has probability zero
_RAY_ANGLE = 0.6180339887498949
#: a finite object's curve is sampled at most this far apart (mm) by :meth:`Boundary.points`
_SAMPLE_MM = 0.05


class Boundary:
    """One object's boundary in the hand frame (lengths mm)."""

    def __init__(self, obj):
        self.cls = obj.cls
        self.curve = CURVES[obj.cls](obj.params)
        self._p = {k: float(v) for k, v in self.curve.params.items()}
        pose = obj.pose
        self.pose = pose
        self._c, self._s = math.cos(pose.theta), math.sin(pose.theta)
        self._ox, self._oy = float(pose.x), float(pose.y)
        extent = getattr(obj, "extent", None)
        self.finite = extent is not None
        self._solid_is_region = obj.side == _REGION_SIDE[obj.cls]
        if self.finite:
            self.t0, self.t1 = (float(t) for t in extent)
            closure = getattr(obj, "closure", None) or ()
            path = [self._point(self.t1), *((float(x), float(y)) for x, y in closure), self._point(self.t0)]
            #: straight segments (ax, ay, bx, by) in the canonical frame, P(t1) → ... → P(t0)
            self._segments = [(*path[k], *path[k + 1]) for k in range(len(path) - 1)]
            self.corners = np.array([self._to_hand(*p) for p in path])
            pts = self.points((self._ox, self._oy), math.inf)
            centre = pts.mean(axis=0)
            #: a circle (hand frame) holding the whole finite boundary: outside it, outside the solid
            self._bound = (float(centre[0]), float(centre[1]), float(np.max(np.hypot(*(pts - centre).T))) + 1.0)
        else:
            self.t0, self.t1 = -math.inf, math.inf
            self._segments = []
            self.corners = np.zeros((0, 2))

    # ------------------------------------------------------------------ frames
    def _to_canon(self, x: float, y: float) -> tuple[float, float]:
        dx, dy = x - self._ox, y - self._oy
        return self._c * dx + self._s * dy, -self._s * dx + self._c * dy

    def _to_hand(self, u: float, v: float) -> tuple[float, float]:
        return self._c * u - self._s * v + self._ox, self._s * u + self._c * v + self._oy

    # ------------------------------------------------------------------ queries
    def inside(self, x: float, y: float) -> bool:
        """Is the hand-frame point strictly inside the solid?"""
        if self.finite:
            bx, by, br = self._bound
            if (x - bx) ** 2 + (y - by) ** 2 > br * br:
                return False
        u, v = self._to_canon(x, y)
        if not self.finite:
            region = self._in_region(u, v)
            return region if self._solid_is_region else not region
        dx, dy = math.cos(_RAY_ANGLE), math.sin(_RAY_ANGLE)
        nx, ny = -dy, dx
        d = nx * u + ny * v
        count = 0
        for t in self._line_hits(nx, ny, d):  # the curve over [t0, t1)
            if self.t0 <= t < self.t1:
                px, py = self._point(t)
                count += dx * (px - u) + dy * (py - v) > 0.0
        for ax, ay, bx, by in self._segments:  # each segment from its start, end excluded
            r = _segment_line_param(ax, ay, bx, by, nx, ny, d)
            if r is not None and 0.0 <= r < 1.0:
                count += dx * (ax + r * (bx - ax) - u) + dy * (ay + r * (by - ay) - v) > 0.0
        return count % 2 == 1

    def crosses(self, x0: float, y0: float, x1: float, y1: float) -> bool:
        """Does the boundary cross the open hand-frame segment (x0, y0)–(x1, y1)
        transversally, strictly inside its length? Tangent touches, a straight face on the
        segment's line and the corners themselves do not count."""
        length = math.hypot(x1 - x0, y1 - y0)
        tx, ty = (x1 - x0) / length, (y1 - y0) / length
        ntx, nty = self._c * tx + self._s * ty, -self._s * tx + self._c * ty  # canonical tangent
        nx, ny = -nty, ntx
        u0, v0 = self._to_canon(x0, y0)
        d = nx * u0 + ny * v0
        for t in self._line_hits(nx, ny, d):
            if self.t0 < t < self.t1:
                px, py = self._point(t)
                if 0.0 < ntx * (px - u0) + nty * (py - v0) < length:
                    return True
        for ax, ay, bx, by in self._segments:
            r = _segment_line_param(ax, ay, bx, by, nx, ny, d)
            if r is not None and 0.0 < r < 1.0:
                along = ntx * (ax + r * (bx - ax) - u0) + nty * (ay + r * (by - ay) - v0)
                if 0.0 < along < length:
                    return True
        return False

    def points(self, center: tuple[float, float], radius: float) -> np.ndarray:
        """Hand-frame points (N, 2) along the boundary, in order, within ``radius`` of
        ``center``: a closed curve at 4096 points, an unbounded one densely until out of
        reach, a finite object's curve at most ``_SAMPLE_MM`` apart and its straight
        segments at the same spacing."""
        if self.finite:
            x, y = self.curve.point(self._finite_t())
            canon = [np.stack([x, y], axis=-1)]
            step = max(float(np.max(np.hypot(*np.diff(canon[0], axis=0).T))), 1e-6) if len(x) > 1 else _SAMPLE_MM
            for ax, ay, bx, by in self._segments:
                n = max(2, math.ceil(math.hypot(bx - ax, by - ay) / step) + 1)
                r = np.linspace(0.0, 1.0, n)[1:]
                canon.append(np.stack([ax + r * (bx - ax), ay + r * (by - ay)], axis=-1))
            pts = np.concatenate(canon)
            hx, hy = self.pose.apply(pts[:, 0], pts[:, 1])
        else:
            hx, hy = self.pose.apply(*self.curve.point(self._open_t(center, radius)))
        pts = np.stack([hx, hy], axis=-1)
        keep = np.hypot(hx - center[0], hy - center[1]) <= radius
        return pts[keep]

    # ------------------------------------------------------------------ sampling
    def _finite_t(self) -> np.ndarray:
        t = np.linspace(self.t0, self.t1, 1025)
        arc = float(np.sum(np.hypot(*np.diff(np.array(self.curve.point(t)), axis=1))))
        return np.linspace(self.t0, self.t1, int(min(max(arc / _SAMPLE_MM, 1025), 40001)))

    def _open_t(self, center, radius) -> np.ndarray:
        if self.curve.t_period is not None:
            lo, hi = self.curve.t_period
            return np.linspace(lo, hi, 4096)
        span = 1.0
        for _ in range(60):  # grow until both ends are out of reach
            x, y = self.pose.apply(*self.curve.point(np.array([-span, span])))
            if np.all(np.hypot(x - center[0], y - center[1]) > radius):
                break
            span *= 1.5
        u = np.linspace(-1.0, 1.0, 8001)
        return span * np.sign(u) * np.abs(u) ** 2 if self.cls != "line" else span * u

    # ------------------------------------------------------------------ closed forms
    def _in_region(self, u: float, v: float) -> bool:
        """Is the canonical point strictly inside the class's region (docs/formats.md, canonical curves)?"""
        p, cls = self._p, self.cls
        if cls == "line":
            return v > 0
        if cls == "circle":
            return u * u + v * v < p["r"] ** 2
        if cls == "ellipse":
            return (u / p["a"]) ** 2 + (v / p["b"]) ** 2 < 1.0
        if cls == "parabola":
            return v * v < 4.0 * p["a"] * u
        if cls == "hyperbola":
            return u > 0 and (u / p["a"]) ** 2 - (v / p["b"]) ** 2 > 1.0
        if cls == "cubical_parabola":
            return v > p["a"] * u**3 + p["c"] * u
        return u > 0 and abs(v - p["b"] * u) < p["a"] * u**1.5  # semicubical, a > 0: between the branches

    def _point(self, t: float) -> tuple[float, float]:
        """Canonical point at t (docs/formats.md, canonical curves), scalar and fast."""
        p, cls = self._p, self.cls
        if cls == "line":
            return t, 0.0
        if cls == "circle":
            return p["r"] * math.cos(t), p["r"] * math.sin(t)
        if cls == "ellipse":
            return p["a"] * math.cos(t), p["b"] * math.sin(t)
        if cls == "parabola":
            return p["a"] * t * t, 2.0 * p["a"] * t
        if cls == "hyperbola":
            return p["a"] * math.cosh(t), p["b"] * math.sinh(t)
        if cls == "cubical_parabola":
            return t, p["a"] * t**3 + p["c"] * t
        return t * t, p["a"] * t**3 + p["b"] * t * t

    def _line_hits(self, nx: float, ny: float, d: float) -> list[float]:
        """Parameters t where the whole curve crosses the line n·p = d (canonical frame),
        transversal crossings only."""
        p, cls = self._p, self.cls
        if cls == "line":
            return [d / nx] if nx != 0.0 else []
        if cls in ("circle", "ellipse"):
            a, b = (p["r"], p["r"]) if cls == "circle" else (p["a"], p["b"])
            big = math.hypot(a * nx, b * ny)
            if big == 0.0 or abs(d) >= big:
                return []
            delta, w = math.atan2(b * ny, a * nx), math.acos(d / big)
            return [delta - w, delta + w]
        if cls == "parabola":
            return _real_roots([nx * p["a"], 2.0 * ny * p["a"], -d])
        if cls == "hyperbola":
            aa, bb = p["a"] * nx, p["b"] * ny
            return [math.log(w) for w in _real_roots([aa + bb, -2.0 * d, aa - bb]) if w > 0.0]
        if cls == "cubical_parabola":
            return _real_roots([ny * p["a"], 0.0, nx + ny * p["c"], -d])
        return _real_roots([ny * p["a"], nx + ny * p["b"], 0.0, -d])


def _segment_line_param(ax: float, ay: float, bx: float, by: float, nx: float, ny: float, d: float) -> float | None:
    """Where (fraction from a to b) the segment's line meets the line n·p = d; None when
    parallel."""
    da, db = nx * ax + ny * ay - d, nx * bx + ny * by - d
    if da == db:
        return None
    return da / (da - db)


def _real_roots(coeffs: list[float]) -> list[float]:
    """Real simple roots of a polynomial of degree ≤ 3 (highest power first); leading
    zeros dropped. Closed form (a cubic by Cardano or the trigonometric form, each root
    polished by Newton on the original coefficients); a cubic whose closed-form roots do
    not check out (ill-conditioned coefficients) goes to numpy's companion matrix."""
    c = list(coeffs)
    while c and abs(c[0]) < 1e-300:
        c.pop(0)
    if len(c) <= 1:
        return []
    if len(c) == 2:
        return [-c[1] / c[0]]
    if len(c) == 3:
        a, b, cc = c
        disc = b * b - 4 * a * cc
        if disc <= 0.0:
            return []
        r = math.sqrt(disc)
        q = -0.5 * (b + math.copysign(r, b))
        return [q / a, cc / q] if q != 0.0 else [0.0]
    roots = _cubic_roots(*c)
    if roots is not None:
        return roots
    roots = np.roots(c)
    real = roots[np.abs(roots.imag) <= 1e-12 * np.maximum(1.0, np.abs(roots.real))].real
    return [float(r) for r in real]


def _cubic_roots(a: float, b: float, c: float, d: float) -> list[float] | None:
    """Real roots of a t³ + b t² + c t + d (a ≠ 0), or None when they do not check out."""
    bb, cc, dd = b / a, c / a, d / a
    p = cc - bb * bb / 3.0  # the depressed cubic x³ + p x + q, t = x − bb/3
    q = 2.0 * bb**3 / 27.0 - bb * cc / 3.0 + dd
    disc = (0.5 * q) ** 2 + (p / 3.0) ** 3
    if disc > 0.0:  # one real root
        big = -math.copysign(abs(0.5 * q) + math.sqrt(disc), q)
        u = math.copysign(abs(big) ** (1.0 / 3.0), big)
        xs = [u - p / (3.0 * u)] if u != 0.0 else [0.0]
    elif p < 0.0:  # three real roots
        r = 2.0 * math.sqrt(-p / 3.0)
        arg = max(-1.0, min(1.0, 3.0 * q / (p * r)))
        ang = math.acos(arg) / 3.0
        xs = [r * math.cos(ang - 2.0 * math.pi * k / 3.0) for k in range(3)]
    else:  # a triple root: not a transversal crossing
        return []
    out = []
    for x in xs:
        t = x - bb / 3.0
        for _ in range(3):  # Newton on the original coefficients
            f = ((a * t + b) * t + c) * t + d
            df = (3.0 * a * t + 2.0 * b) * t + c
            if df == 0.0:
                break
            t -= f / df
        scale = abs(a * t**3) + abs(b * t * t) + abs(c * t) + abs(d)
        if not math.isfinite(t) or abs(((a * t + b) * t + c) * t + d) > 1e-9 * scale:
            return None
        out.append(t)
    return out
