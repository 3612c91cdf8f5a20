"""Exact canonical curves (docs/formats.md), vectorized, in closed form.

Every class gives the point, tangent angle φ, speed |dp/dt|, curvature κ = dφ/ds
(eq. 1, the curve traversed in increasing t) and its arc-length derivative κ_s
(eq. 2), all in closed form; arc length is closed form (elementary, or the incomplete
elliptic integral of the second kind for the ellipse) except for the hyperbola and the
cubical parabola, whose arc length is adaptive quadrature to ~1e-13 relative, and the
semicubical parabola near its a → 0 limit (fixed Gauss–Legendre, where the closed form cancels).

Formulas: parabola eqs. (3)-(4), ellipse eqs. (6)-(7), cubical parabola eqs. (12)-(13)
with the errata's fix (λ − c), docs/recognition.md; the others are derived the same way and checked against
sympy in tests/test_recognizer_curves.py.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar, Mapping

import numpy as np
from scipy import integrate, optimize, special

from tactile_common.errors import InputError, check_keys

__all__ = ["CURVES", "Curve", "Pose", "validate_params", "DEFAULT_SIDE", "travel_direction"]


def _arr(t):
    return np.asarray(t, dtype=float)


@dataclass(frozen=True)
class Pose:
    """Rigid motion canonical → hand frame: p_hand = R(theta) · p + (x, y)."""

    theta: float = 0.0
    x: float = 0.0
    y: float = 0.0

    def apply(self, px, py):
        c, s = np.cos(self.theta), np.sin(self.theta)
        px, py = _arr(px), _arr(py)
        return c * px - s * py + self.x, s * px + c * py + self.y

    def inverse(self, hx, hy):
        c, s = np.cos(self.theta), np.sin(self.theta)
        dx, dy = _arr(hx) - self.x, _arr(hy) - self.y
        return c * dx + s * dy, -s * dx + c * dy

    def to_json(self) -> dict:
        return {"theta": float(self.theta), "x": float(self.x), "y": float(self.y)}


class Curve:
    """One canonical curve; subclasses implement the closed forms."""

    name: ClassVar[str] = ""
    param_names: ClassVar[tuple[str, ...]] = ()
    #: the canonical κ sign when traversed in increasing t (0: changes sign or zero)
    kappa_sign: ClassVar[int] = 0
    #: (lo, hi) for periodic classes, None for an unbounded parameter
    t_period: ClassVar[tuple[float, float] | None] = None

    def __init__(self, params: Mapping[str, float] | None = None):
        params = dict(params or {})
        missing = [k for k in self.param_names if k not in params]
        if missing:
            raise InputError(f"{self.name}: missing parameter(s) {', '.join(missing)}")
        self.params = {k: float(params[k]) for k in self.param_names}
        for k, v in self.params.items():
            setattr(self, k, v)

    # -- closed forms, overridden -------------------------------------------------
    def point(self, t):  # pragma: no cover - abstract
        raise NotImplementedError

    def tangent_angle(self, t):  # pragma: no cover - abstract
        raise NotImplementedError

    def speed(self, t):  # pragma: no cover - abstract
        raise NotImplementedError

    def kappa(self, t):  # pragma: no cover - abstract
        raise NotImplementedError

    def kappa_s(self, t):  # pragma: no cover - abstract
        raise NotImplementedError

    def param_derivatives(self, t) -> tuple:
        """Per shape parameter (``param_names`` order): (∂x/∂p, ∂y/∂p, ∂φ/∂p) at t, t held
        (recognizer.refine's Jacobian columns of the shape parameters)."""
        raise NotImplementedError  # pragma: no cover - abstract

    def _arc(self, t):
        """An antiderivative S(t) of the speed (closed form), or None for quadrature."""
        return None

    # -- shared ----------------------------------------------------------------------
    def arc_length(self, t0, t1):
        """Signed arc length from t0 to t1 (vectorized)."""
        t0, t1 = np.broadcast_arrays(_arr(t0), _arr(t1))
        s0 = self._arc(t0)
        if s0 is not None:
            return self._arc(t1) - s0
        out = np.empty(t0.shape)
        for idx in np.ndindex(t0.shape):
            out[idx] = integrate.quad(lambda u: float(self.speed(u)), t0[idx], t1[idx],
                                      epsabs=0.0, epsrel=1e-13, limit=200)[0]
        return out

    def t_at_arc_length(self, t0, s):
        """The t reached after signed arc length s from t0 (vectorized)."""
        t0, s = np.broadcast_arrays(_arr(t0), _arr(s))
        out = np.empty(t0.shape)
        for idx in np.ndindex(t0.shape):
            a, target = float(t0[idx]), float(s[idx])
            if target == 0.0:
                out[idx] = a
                continue
            step = target / max(float(self.speed(a)), 1e-300)
            b = a + step
            f = lambda u: float(self.arc_length(a, u)) - target  # noqa: E731
            for _ in range(200):
                if np.sign(f(b)) == np.sign(target) or f(b) == 0.0:
                    break
                step *= 2.0
                b = a + step
            out[idx] = optimize.brentq(f, min(a, b), max(a, b), xtol=1e-15, rtol=1e-15, maxiter=200)
        return out

    def frame(self, t):
        """(x, y, φ, κ, κ_s) at t: what a touch at t measures in the canonical frame."""
        x, y = self.point(t)
        return x, y, self.tangent_angle(t), self.kappa(t), self.kappa_s(t)

    def point_tangent(self, t):
        """((x, y), φ) at t: ``point`` and ``tangent_angle`` (a class whose two share
        intermediates computes them once: the same values)."""
        return self.point(t), self.tangent_angle(t)

    def speed_kappa(self, t):
        """(speed, κ) at t: ``speed`` and ``kappa`` (shared intermediates computed once, as
        ``point_tangent``)."""
        return self.speed(t), self.kappa(t)

    def project(self, t, px, py, steps: int):
        """The parameters of the curve's points nearest the canonical-frame points (px, py),
        from the parameters t: ``steps`` Newton steps along the tangent, Δt = (p − c(t))·T/speed.
        A periodic curve moves at most 0.5 a step; where the speed is ≤ 1e-12 (a cusp) or a
        step is not finite, t stays; a step never leaves its branch (``keep_branch``)."""
        t = np.array(t, dtype=float)
        px, py = _arr(px), _arr(py)
        with np.errstate(all="ignore"):
            for _ in range(steps):
                cx, cy = self.point(t)
                ang = np.asarray(self.tangent_angle(t), float)
                sp = np.asarray(self.speed(t), float)
                step = ((px - cx) * np.cos(ang) + (py - cy) * np.sin(ang)) / np.where(sp > 1e-12, sp, np.inf)
                if self.t_period is not None:
                    step = np.clip(step, -0.5, 0.5)
                t_new = self.keep_branch(t, t + step)
                t = np.where(np.isfinite(t_new), t_new, t)
        return t

    def nearest(self, t_dense, px, py, steps: int) -> np.ndarray:
        """The parameters of the curve's points nearest the canonical-frame points (px, py):
        for each, the nearest of the points at the parameters ``t_dense`` (a dense grid over the
        stretch where to look), then ``steps`` Newton steps (:meth:`project`)."""
        t_dense = np.asarray(t_dense, dtype=float)
        px, py = _arr(px).reshape(-1), _arr(py).reshape(-1)
        cx, cy = self.point(t_dense)
        start = t_dense[np.argmin(np.hypot(cx[None, :] - px[:, None], cy[None, :] - py[:, None]), axis=1)]
        return self.project(start, px, py, steps)

    def keep_branch(self, t, t_new):
        """t_new where it lies on t's branch of the curve, else t (every class but the
        semicubical parabola has one branch)."""
        return t_new


class Line(Curve):
    name = "line"
    param_names = ()

    def point(self, t):
        t = _arr(t)
        return t.copy(), np.zeros_like(t)

    def tangent_angle(self, t):
        return np.zeros_like(_arr(t))

    def speed(self, t):
        return np.ones_like(_arr(t))

    def kappa(self, t):
        return np.zeros_like(_arr(t))

    def kappa_s(self, t):
        return np.zeros_like(_arr(t))

    def param_derivatives(self, t) -> tuple:
        return ()

    def _arc(self, t):
        return _arr(t).copy()


class Circle(Curve):
    name = "circle"
    param_names = ("r",)
    kappa_sign = 1
    t_period = (-np.pi, np.pi)

    def point(self, t):
        t = _arr(t)
        return self.r * np.cos(t), self.r * np.sin(t)

    def tangent_angle(self, t):
        return _arr(t) + np.pi / 2

    def speed(self, t):
        return np.full_like(_arr(t), self.r)

    def kappa(self, t):
        return np.full_like(_arr(t), np.reciprocal(np.float64(self.r)))  # r = 0 (a refinement's
        # log radius underflowed): ∞ for the caller's nonfinite guards, not ZeroDivisionError

    def kappa_s(self, t):
        return np.zeros_like(_arr(t))

    def param_derivatives(self, t) -> tuple:
        t = _arr(t)
        return ((np.cos(t), np.sin(t), np.zeros_like(t)),)

    def _arc(self, t):
        return self.r * _arr(t)


class Ellipse(Curve):
    """(a cos t, b sin t); κ eq. (6), κ_s eq. (7)."""

    name = "ellipse"
    param_names = ("a", "b")
    kappa_sign = 1
    t_period = (-np.pi, np.pi)

    def point(self, t):
        t = _arr(t)
        return self.a * np.cos(t), self.b * np.sin(t)

    def tangent_angle(self, t):
        t = _arr(t)
        return np.arctan2(self.b * np.cos(t), -self.a * np.sin(t))

    def _s2(self, t):
        t = _arr(t)
        return (self.a * np.sin(t)) ** 2 + (self.b * np.cos(t)) ** 2

    def speed(self, t):
        return np.hypot(self.a * np.sin(_arr(t)), self.b * np.cos(_arr(t)))

    def kappa(self, t):
        return self.a * self.b / self._s2(t) ** 1.5

    def point_tangent(self, t):
        t = _arr(t)
        c, s = np.cos(t), np.sin(t)
        return (self.a * c, self.b * s), np.arctan2(self.b * c, -self.a * s)

    def speed_kappa(self, t):
        t = _arr(t)
        u, v = self.a * np.sin(t), self.b * np.cos(t)
        return np.hypot(u, v), self.a * self.b / (u**2 + v**2) ** 1.5

    def kappa_s(self, t):
        t = _arr(t)
        a, b = self.a, self.b
        return -3 * a * b * (a - b) * (a + b) * np.sin(t) * np.cos(t) / self._s2(t) ** 3

    def param_derivatives(self, t) -> tuple:
        """φ = atan2(V, U), U = −a sin t, V = b cos t: dφ = (U dV − V dU)/(U² + V²)."""
        t = _arr(t)
        c, s = np.cos(t), np.sin(t)
        u, v = -self.a * s, self.b * c
        q = u * u + v * v
        zero = np.zeros_like(t)
        return ((c, zero, v * s / q), (zero, s, u * c / q))

    def _arc(self, t):
        a, b = max(self.a, self.b), min(self.a, self.b)
        t = _arr(t)
        if self.a >= self.b:
            return a * special.ellipeinc(t - np.pi / 2, 1.0 - (b / a) ** 2)
        return a * special.ellipeinc(t, 1.0 - (b / a) ** 2)


class Parabola(Curve):
    """(a t², 2 a t); κ eq. (3), κ_s eq. (4)."""

    name = "parabola"
    param_names = ("a",)
    kappa_sign = -1

    def point(self, t):
        t = _arr(t)
        return self.a * t * t, 2 * self.a * t

    def tangent_angle(self, t):
        return np.arctan2(1.0, _arr(t))

    def speed(self, t):
        return 2 * self.a * np.hypot(1.0, _arr(t))

    def kappa(self, t):
        return -1.0 / (2 * self.a * np.hypot(1.0, _arr(t)) ** 3)

    def speed_kappa(self, t):
        h = np.hypot(1.0, _arr(t))
        return 2 * self.a * h, -1.0 / (2 * self.a * h**3)

    def kappa_s(self, t):
        t = _arr(t)
        return 3 * t / (4 * self.a**2 * np.hypot(1.0, t) ** 6)

    def param_derivatives(self, t) -> tuple:
        t = _arr(t)
        return ((t * t, 2.0 * t, np.zeros_like(t)),)

    def _arc(self, t):
        t = _arr(t)
        return self.a * (t * np.hypot(1.0, t) + np.arcsinh(t))


class Hyperbola(Curve):
    """(a cosh t, b sinh t), branch x > 0: κ = −ab/S^{3/2}, κ_s = 3ab(a²+b²) sinh cosh/S³."""

    name = "hyperbola"
    param_names = ("a", "b")
    kappa_sign = -1

    def point(self, t):
        t = _arr(t)
        return self.a * np.cosh(t), self.b * np.sinh(t)

    def tangent_angle(self, t):
        t = _arr(t)
        return np.arctan2(self.b * np.cosh(t), self.a * np.sinh(t))

    def speed(self, t):
        t = _arr(t)
        return np.hypot(self.a * np.sinh(t), self.b * np.cosh(t))

    def kappa(self, t):
        return -self.a * self.b / self.speed(t) ** 3

    def point_tangent(self, t):
        t = _arr(t)
        ch, sh = np.cosh(t), np.sinh(t)
        return (self.a * ch, self.b * sh), np.arctan2(self.b * ch, self.a * sh)

    def speed_kappa(self, t):
        sp = self.speed(t)
        return sp, -self.a * self.b / sp**3

    def kappa_s(self, t):
        t = _arr(t)
        a, b = self.a, self.b
        return 3 * a * b * (a * a + b * b) * np.sinh(t) * np.cosh(t) / self.speed(t) ** 6

    def param_derivatives(self, t) -> tuple:
        """φ = atan2(V, U), U = a sinh t, V = b cosh t: dφ = (U dV − V dU)/(U² + V²)."""
        t = _arr(t)
        ch, sh = np.cosh(t), np.sinh(t)
        u, v = self.a * sh, self.b * ch
        q = u * u + v * v
        zero = np.zeros_like(t)
        return ((ch, zero, -v * sh / q), (zero, sh, u * ch / q))


class CubicalParabola(Curve):
    """(t, a t³ + c t), λ = 3at² + c; κ = 6at/(1+λ²)^{3/2}, κ_s eq. (13) (errata, docs/recognition.md)."""

    name = "cubical_parabola"
    param_names = ("a", "c")

    def _lam(self, t):
        t = _arr(t)
        return 3 * self.a * t * t + self.c

    def point(self, t):
        t = _arr(t)
        return t.copy(), self.a * t**3 + self.c * t

    def tangent_angle(self, t):
        return np.arctan(self._lam(t))

    def speed(self, t):
        return np.hypot(1.0, self._lam(t))

    def kappa(self, t):
        return 6 * self.a * _arr(t) / self.speed(t) ** 3

    def speed_kappa(self, t):
        sp = self.speed(t)
        return sp, 6 * self.a * _arr(t) / sp**3

    def kappa_s(self, t):
        t = _arr(t)
        lam = self._lam(t)
        q = 1.0 + lam * lam
        return (6 * self.a * q - 108 * self.a**2 * t * t * lam) / q**3

    def param_derivatives(self, t) -> tuple:
        """φ = arctan λ, λ = 3at² + c: dφ = dλ/(1 + λ²)."""
        t = _arr(t)
        q = 1.0 + self._lam(t) ** 2
        zero = np.zeros_like(t)
        return ((zero, t**3, 3.0 * t * t / q), (zero, t.copy(), 1.0 / q))


class SemicubicalParabola(Curve):
    """(t², a t³ + b t²), cusp at t = 0; with u = 3at + 2b:
    κ = 6a/(|t|(4+u²)^{3/2}), κ_s = −6a((4+u²) + 9aut)/(t³(4+u²)³)."""

    name = "semicubical_parabola"
    param_names = ("a", "b")
    kappa_sign = 1

    def _u(self, t):
        return 3 * self.a * _arr(t) + 2 * self.b

    def keep_branch(self, t, t_new):
        """Never across the cusp: the branches t < 0 and t > 0 are apart."""
        return np.where(np.sign(t_new) == np.sign(t), t_new, t)

    def point(self, t):
        t = _arr(t)
        return t * t, self.a * t**3 + self.b * t * t

    def tangent_angle(self, t):
        t = _arr(t)
        sg = np.where(t < 0, -1.0, 1.0)
        return np.arctan2(sg * self._u(t), sg * 2.0)

    def speed(self, t):
        t = _arr(t)
        return np.abs(t) * np.hypot(2.0, self._u(t))

    def kappa(self, t):
        t = _arr(t)
        with np.errstate(divide="ignore"):
            return 6 * self.a / (np.abs(t) * np.hypot(2.0, self._u(t)) ** 3)

    def speed_kappa(self, t):
        t = _arr(t)
        at, h = np.abs(t), np.hypot(2.0, self._u(t))
        with np.errstate(divide="ignore"):
            return at * h, 6 * self.a / (at * h**3)

    def kappa_s(self, t):
        t = _arr(t)
        u = self._u(t)
        q = 4.0 + u * u
        with np.errstate(divide="ignore", invalid="ignore"):
            return -6 * self.a * (q + 9 * self.a * u * t) / (t**3 * q**3)

    def param_derivatives(self, t) -> tuple:
        """φ = atan2(sg·u, sg·2), u = 3at + 2b: dφ = 2 du/(4 + u²) on either branch."""
        t = _arr(t)
        q = 4.0 + self._u(t) ** 2
        zero = np.zeros_like(t)
        return ((zero, t**3, 6.0 * t / q), (zero, t * t, 4.0 / q))

    def _arc(self, t):
        """S(t) = sign(t) ∫₀^|t| τ √(4 + u(τ)²) dτ: in closed form, antiderivative F(u)/(9a²)
        with u = 3aτ + 2b, where h = 3at is large against √(4 + u²) (else F(u) − F(2b) cancels:
        a = 1e-9 gave −96 for 4.88, a = 0 a division by zero); otherwise S = t² ∫₀¹ x √(4 +
        (2b + h x)²) dx by Gauss–Legendre, whose integrand's branch points x = (−2b ± 2i)/h lie
        more than ``_ARC_CLOSED`` / 2 from [0, 1] there (error far below 1e-16)."""
        shape, t = np.shape(t), _arr(t).reshape(-1)
        a, b = self.a, self.b
        u0, h = 2.0 * b, 3.0 * a * t
        closed = np.abs(h) * _ARC_CLOSED >= np.hypot(2.0, np.abs(u0) + np.abs(h))
        x, w = _GAUSS_01
        u = u0 + h[..., None] * x
        out = t * np.abs(t) * np.sum(w * x * np.hypot(2.0, u), axis=-1)
        if np.any(closed):
            def f(u):
                r = np.hypot(2.0, u)
                return r**3 / 3 - 2 * b * (u * r / 2 + 2 * np.arcsinh(u / 2))

            tc = t[closed]
            out[closed] = np.where(tc < 0, -1.0, 1.0) * (f(self._u(tc)) - f(u0)) / (9 * a * a)
        return out.reshape(shape)


#: the semicubical's arc length in closed form where |3at| · this ≥ √(4 + (|2b| + |3at|)²)
#: (the cancellation of its antiderivative then costs under 3 digits), else by quadrature
_ARC_CLOSED = 30.0
#: Gauss–Legendre nodes and weights on [0, 1] (16 points: exact for polynomials of degree 31)
_GAUSS_01 = tuple(0.5 * v for v in np.polynomial.legendre.leggauss(16))
_GAUSS_01 = (_GAUSS_01[0] + 0.5, _GAUSS_01[1])


def travel_direction(curve: Curve, pose: Pose, t, phi) -> int:
    """+1 when touches measuring tangent angles ``phi`` (hand frame) at the posed curve's
    parameters ``t`` run in increasing t, else −1 (the majority of cos(φ − tangent))."""
    with np.errstate(all="ignore"):
        ang = np.asarray(curve.tangent_angle(_arr(t)), float) + pose.theta
        return 1 if float(np.nansum(np.cos(_arr(phi) - ang))) >= 0 else -1


CURVES: dict[str, type[Curve]] = {
    c.name: c for c in (Line, Circle, Ellipse, Parabola, Hyperbola, CubicalParabola, SemicubicalParabola)
}

#: where the solid lies, relative to the canonical curve traversed in increasing t
DEFAULT_SIDE: dict[str, str] = {
    "line": "right",  # y < 0
    "circle": "left",  # interior
    "ellipse": "left",  # interior
    "parabola": "right",  # the side containing the focus
    "hyperbola": "right",  # the side containing the focus (x > a cosh-branch interior)
    "cubical_parabola": "right",  # below the graph y < a x³ + c x
    "semicubical_parabola": "right",  # inside the cusp: |y − b x| < a x^{3/2}
}


def validate_params(cls: str, params: Mapping[str, object], where: str = "params") -> dict[str, float]:
    """Check a class's parameters against the canonical forms (docs/formats.md); one-line InputError otherwise."""
    if cls not in CURVES:
        raise InputError(f"{where}: unknown class {cls!r}; allowed: {', '.join(CURVES)}")
    if not isinstance(params, Mapping):
        raise InputError(f"{where}: must be a mapping of {', '.join(CURVES[cls].param_names) or 'nothing'}")
    names = CURVES[cls].param_names
    check_keys(params, names, where, f"allowed for {cls}: {', '.join(names) or 'none'}")
    out: dict[str, float] = {}
    for k in names:
        if k not in params:
            raise InputError(f"{where}.{k}: missing for {cls}")
        v = params[k]
        if isinstance(v, bool) or not isinstance(v, (int, float)) or not np.isfinite(v):
            raise InputError(f"{where}.{k}: must be a finite number, got {v!r}")
        out[k] = float(v)
    positive = {"circle": ("r",), "ellipse": ("a", "b"), "parabola": ("a",), "hyperbola": ("a", "b"),
                "semicubical_parabola": ("a",)}.get(cls, ())
    for k in positive:
        if out[k] <= 0:
            raise InputError(f"{where}.{k}: must be > 0 for {cls}, got {out[k]}")
    if cls == "ellipse" and out["a"] < out["b"]:
        raise InputError(f"{where}: ellipse needs a >= b (got a={out['a']}, b={out['b']}); a = b is a circle")
    if cls == "cubical_parabola" and out["a"] == 0:
        raise InputError(f"{where}.a: must be nonzero for cubical_parabola")
    return out
