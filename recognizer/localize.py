"""Parameters, contact parameters t (quadrant and branch resolved) and pose, per class.

For one class and the touches' local geometry (x, y, φ, κ, κ_s with covariances):

1. Direction. The canonical curves have a fixed κ sign when traversed in increasing t
   (ellipse, circle, semicubical +; parabola, hyperbola −). Touches going the other way
   see φ + π and −κ (κ_s unchanged); they are flipped to the canonical direction. A
   reversed cubical parabola is the same curve turned by π, a reversed line the line
   turned by π: no flip for those.
2. Closed-form start from the invariants (paper §§2–4, ERRATA): ellipse/hyperbola a, b
   from I_c1, I_c2 of the best-conditioned pair; parabola a from I_p, t = κ_s/(3κ²);
   ellipse t from sin²t = ((ab/κ)^{2/3} − b²)/(a² − b²) with the quadrant from
   sign(sin t cos t) = −sign(κ_s) and the half-turn from the tangent; hyperbola
   sinh²t = ((ab/|κ|)^{2/3} − b²)/(a² + b²), sign t = sign κ_s; cubical and semicubical
   parabolas: canonical tangent angle ψ from ``invariants.slope_angles`` (both roots, and
   for the semicubical both half-turns, i.e. both branches t ≷ 0, are tried), then
   a, c (or a, b) from I_cp1/I_cp2 (I_scp1/I_scp2), t = κ(1+λ²)^{3/2}/(6a)
   (resp. 2(λ − b)/(3a)). Pose: θ = circular mean of φ_i − φ(t_i), (x, y) = mean of
   p_i − R(θ)·p(t_i).
3. Levenberg–Marquardt on the exact contact equations of every touch: position, tangent
   angle, κ(t_i) and κ_s(t_i) against the measurements, whitened by their standard
   deviations (analytic derivatives in t and pose; forward differences in the shape
   parameters). Positive parameters are fitted in log form.
4. Canonical answer: ellipse a ≥ b (else swap, θ += π/2, t −= π/2) and θ in (−π/2, π/2]
   (the ellipse's half-turn symmetry, t += π); circle θ = 0; line (x, y) the foot of the
   perpendicular from the hand origin; every other class θ in (−π, π]; periodic t in
   (−π, π].
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from recognizer import invariants as inv
from recognizer.curves import CURVES, Pose

__all__ = ["Contacts", "Fit", "fit_class", "EPS_FLOOR", "N_SHAPE"]

#: relative floor of every measurement's standard deviation (exact data, zero covariance)
EPS_FLOOR = 1e-7
_LOG = {"line": (), "circle": (True,), "ellipse": (True, True), "parabola": (True,), "hyperbola": (True, True),
        "cubical_parabola": (False, False), "semicubical_parabola": (True, False)}
#: shape parameters + pose degrees of freedom not lost to a symmetry (BIC counts these)
N_SHAPE = {"line": 0 + 2, "circle": 1 + 2, "ellipse": 2 + 3, "parabola": 1 + 3, "hyperbola": 2 + 3,
           "cubical_parabola": 2 + 3, "semicubical_parabola": 2 + 3}


def _wrap(a):
    return np.remainder(np.asarray(a, float) + np.pi, 2 * np.pi) - np.pi


def _circmean(a):
    a = np.asarray(a, float)
    return float(np.arctan2(np.sin(a).sum(), np.cos(a).sum()))


@dataclass
class Contacts:
    """The local geometry of every touch, with standard deviations (floors applied)."""

    x: np.ndarray
    y: np.ndarray
    phi: np.ndarray
    kappa: np.ndarray
    kappa_s: np.ndarray
    cov: np.ndarray  # (n, 2, 2) covariance of (κ, κ_s)
    sig_pos: np.ndarray
    sig_phi: np.ndarray

    @property
    def n(self) -> int:
        return len(self.x)

    def __post_init__(self):
        self._scale = None
        self._white = None

    @property
    def scale(self) -> float:
        """L: the touches' extent (largest distance between two contacts), mm."""
        if self._scale is None:
            self._scale = self._extent()
        return self._scale

    def _extent(self) -> float:
        d = np.hypot(self.x[:, None] - self.x[None, :], self.y[:, None] - self.y[None, :])
        span = float(d.max())
        if span > 0:
            return span
        k = float(np.max(np.abs(self.kappa)))
        return 1.0 / k if k > 0 else 1.0

    def whitener(self) -> np.ndarray:
        """(n, 2, 2) W with W·(δκ, δκ_s) standardized; floors EPS_FLOOR·(|κ| + 1/L) and
        EPS_FLOOR·(|κ_s| + κ² + |κ|/L + 1/L²) added to the variances (κ² is κ_s's natural
        scale: at a sharp vertex κ_s swings by ~κ² over a roundoff-sized step)."""
        if self._white is None:
            self._white = self._whitener()
        return self._white

    def _whitener(self) -> np.ndarray:
        L = self.scale
        fk = EPS_FLOOR * (np.abs(self.kappa) + 1.0 / L)
        fks = EPS_FLOOR * (np.abs(self.kappa_s) + self.kappa**2 + np.abs(self.kappa) / L + 1.0 / L**2)
        c = self.cov.copy()
        c[:, 0, 0] += fk**2
        c[:, 1, 1] += fks**2
        return np.linalg.inv(np.linalg.cholesky(c))

    def flipped(self) -> "Contacts":
        """The same touches seen in the other direction (φ + π, −κ); the whitener of
        (κ, κ_s) changes only by the sign of its κ column."""
        f = Contacts(self.x, self.y, self.phi + np.pi, -self.kappa, self.kappa_s, self.cov,
                     self.sig_pos, self.sig_phi)
        f._scale = self.scale
        if not np.any(self.cov[:, 0, 1]):
            f._white = self.whitener()
        return f


@dataclass
class Fit:
    cls: str
    params: dict
    pose: Pose
    t: np.ndarray
    chi2: float
    n_obs: int
    n_free: int
    residuals: np.ndarray  # whitened, (n, 5): x, y, φ, κ, κ_s
    sigma: dict
    init_params: dict


class _Model:
    def __init__(self, cls: str, data: Contacts):
        self.cls, self.d = cls, data
        self.curve_cls = CURVES[cls]
        self.names = self.curve_cls.param_names
        self.log = _LOG[cls]
        self.np = len(self.names)
        self.W = data.whitener()
        L = data.scale
        self.sp = np.maximum(data.sig_pos, EPS_FLOOR * L)
        self.sf = np.maximum(data.sig_phi, EPS_FLOOR)
        self.tscale = {"line": L, "cubical_parabola": L, "semicubical_parabola": math.sqrt(L)}.get(cls, 1.0)

    def params_of(self, z) -> dict:
        p = z[: self.np]
        return {k: (math.exp(v) if lg else float(v)) for k, v, lg in zip(self.names, p, self.log)}

    def pack(self, params: dict, theta, X, Y, t) -> np.ndarray:
        p = [math.log(params[k]) if lg else params[k] for k, lg in zip(self.names, self.log)]
        return np.concatenate([p, [theta, X, Y], np.asarray(t, float)])

    def eval(self, z):
        """Whitened residuals (n, 5) and the pieces the Jacobian needs."""
        c = self.curve_cls(self.params_of(z))
        th, X, Y = z[self.np: self.np + 3]
        t = z[self.np + 3:]
        px, py = c.point(t)
        phc, kc, ksc, sp = c.tangent_angle(t), c.kappa(t), c.kappa_s(t), c.speed(t)
        ct, st = math.cos(th), math.sin(th)
        hx, hy = ct * px - st * py + X, st * px + ct * py + Y
        d = self.d
        r = np.empty((len(t), 5))
        r[:, 0] = (hx - d.x) / self.sp
        r[:, 1] = (hy - d.y) / self.sp
        r[:, 2] = _wrap(phc + th - d.phi) / self.sf
        e0, e1 = kc - d.kappa, ksc - d.kappa_s
        W = self.W
        r[:, 3] = W[:, 0, 0] * e0 + W[:, 0, 1] * e1
        r[:, 4] = W[:, 1, 0] * e0 + W[:, 1, 1] * e1
        return r, (c, t, px, py, phc, kc, ksc, sp, ct, st)

    def jac(self, z, r, parts):
        c, t, px, py, phc, kc, ksc, sp, ct, st = parts
        n = len(t)
        m = self.np + 3 + n
        J = np.zeros((n, 5, m))
        # shape parameters: forward differences
        for j in range(self.np):
            if self.log[j]:
                h = 1e-7
            elif self.cls == "cubical_parabola" and j == 0:  # a, 1/mm², never 0
                h = 1e-7 * abs(z[j])
            else:  # dimensionless slopes c, b
                h = 1e-7 * max(abs(z[j]), 1.0)
            zz = z.copy()
            zz[j] += h
            J[:, :, j] = (self.eval(zz)[0] - r) / h
        o = self.np
        # pose
        J[:, 0, o] = (-st * px - ct * py) / self.sp
        J[:, 1, o] = (ct * px - st * py) / self.sp
        J[:, 2, o] = 1.0 / self.sf
        J[:, 0, o + 1] = 1.0 / self.sp
        J[:, 1, o + 2] = 1.0 / self.sp
        # contact parameters: dp/dt = speed·(cos φ, sin φ), dφ/dt = κ·speed, dκ/dt = κ_s·speed
        ang = phc + z[o]
        idx = np.arange(n)
        col = o + 3 + idx
        J[idx, 0, col] = sp * np.cos(ang) / self.sp
        J[idx, 1, col] = sp * np.sin(ang) / self.sp
        J[idx, 2, col] = kc * sp / self.sf
        h = 1e-6 * np.maximum(np.abs(t), self.tscale)
        kss = (c.kappa_s(t + h) - c.kappa_s(t - h)) / (2 * h)
        e0, e1, W = ksc * sp, kss, self.W
        J[idx, 3, col] = W[:, 0, 0] * e0 + W[:, 0, 1] * e1
        J[idx, 4, col] = W[:, 1, 0] * e0 + W[:, 1, 1] * e1
        return J.reshape(n * 5, m)

    def solve(self, z0, max_iter=40, give_up=math.inf):
        """Levenberg–Marquardt from z0; stops early once the cost is negligible (exact data)
        or when after 4 iterations it is still above ``give_up`` (hopeless class)."""
        z = np.asarray(z0, float).copy()
        r, parts = self.eval(z)
        if not np.all(np.isfinite(r)):
            return z, math.inf, None
        cost = float(np.sum(r * r))
        mu = 1e-6
        J = None
        for it in range(max_iter):
            if cost < 1e-12 or (it >= 4 and cost > give_up):
                break
            J = self.jac(z, r, parts)
            if not np.all(np.isfinite(J)):
                break
            cn = np.linalg.norm(J, axis=0)
            cn[cn == 0] = 1.0
            Js = J / cn
            improved = False
            for _ in range(8):
                A = np.vstack([Js, math.sqrt(mu) * np.eye(Js.shape[1])])
                b = np.concatenate([-r.ravel(), np.zeros(Js.shape[1])])
                step = np.linalg.lstsq(A, b, rcond=None)[0] / cn
                zn = z + step
                rn, pn = self.eval(zn)
                cn_cost = float(np.sum(rn * rn)) if np.all(np.isfinite(rn)) else math.inf
                if cn_cost < cost:
                    improved = True
                    small = cost - cn_cost <= 1e-14 * cost + 1e-24
                    z, r, parts, cost = zn, rn, pn, cn_cost
                    mu = max(mu / 10, 1e-12)
                    break
                mu *= 10
            if not improved or small:
                break
        J = self.jac(z, r, parts)
        return z, cost, J


# -- closed-form starts -------------------------------------------------------------------

def _pose_from(curve, t, d: Contacts):
    px, py = curve.point(t)
    th = _circmean(d.phi - curve.tangent_angle(t))
    ct, st = math.cos(th), math.sin(th)
    return th, float(np.mean(d.x - (ct * px - st * py))), float(np.mean(d.y - (st * px + ct * py)))


def _best_pair(d: Contacts):
    n = d.n
    best, bi, bj = -1.0, 0, 1
    for i in range(n):
        for j in range(i + 1, n):
            q = float(inv.pair_condition(d.kappa[i], d.kappa[j]))
            if q > best:
                best, bi, bj = q, i, j
    return bi, bj


def _starts(cls: str, d: Contacts):
    """Closed-form (params, t) starting points for a class (data in canonical direction)."""
    k, ks = d.kappa, d.kappa_s
    if cls == "line":
        th = _circmean(d.phi)
        return [({}, (d.x - d.x.mean()) * math.cos(th) + (d.y - d.y.mean()) * math.sin(th))]
    if cls == "circle":
        mk = float(np.mean(k))
        if not mk > 0:
            return []
        r = 1.0 / mk
        cx = np.mean(d.x - r * np.sin(d.phi))
        cy = np.mean(d.y + r * np.cos(d.phi))
        return [({"r": r}, np.arctan2(d.y - cy, d.x - cx))]
    if cls == "parabola":
        a = float(np.median(1.0 / (2.0 * inv.I_p(k, ks) ** 1.5)))
        return [({"a": a}, ks / (3.0 * k * k))] if a > 0 and np.isfinite(a) else []
    if cls in ("ellipse", "hyperbola"):
        i, j = _best_pair(d)
        c1 = float(inv.I_c1(k[i], ks[i], k[j], ks[j]))
        c2 = float(inv.I_c2(k[i], ks[i], k[j], ks[j]))
        if not (np.isfinite(c1) and np.isfinite(c2)):
            return []
        if cls == "ellipse":
            if c1 <= 0:
                return []
            P = c1**-1.5  # ab
            S = c2 * P ** (4.0 / 3.0)  # a² + b²
            disc = max(S * S - 4 * P * P, 0.0)
            a2 = (S + math.sqrt(disc)) / 2
            a = math.sqrt(a2)
            b = P / a
            if a <= b * (1 + 1e-9):
                b = a / (1 + 1e-6)
            w = (a * b / np.abs(k)) ** (2.0 / 3.0)
            s2 = np.clip((w - b * b) / ((a - b) * (a + b)), 0.0, 1.0)
            t0 = np.arctan2(np.sqrt(s2), np.sqrt(1.0 - s2)) * np.where(ks > 0, -1.0, 1.0)
            cur = CURVES["ellipse"]({"a": a, "b": b})
            th = float(d.phi[0] - cur.tangent_angle(t0[0]))
            flip = np.abs(_wrap(cur.tangent_angle(t0) + th - d.phi)) > np.pi / 2
            return [({"a": a, "b": b}, t0 + np.pi * flip)]
        if c1 >= 0:
            return []
        P = (-c1) ** -1.5
        D = c2 * P ** (4.0 / 3.0)  # a² − b²
        a2 = (D + math.hypot(D, 2 * P)) / 2
        a = math.sqrt(a2)
        b = P / a
        w = (a * b / np.abs(k)) ** (2.0 / 3.0)
        sh = np.sqrt(np.clip((w - b * b) / (a * a + b * b), 0.0, None))
        return [({"a": a, "b": b}, np.arcsinh(sh) * np.sign(ks))]
    # cubic classes: canonical tangent angle from the slope equation of the best-turning pair
    kk = inv.K_CUBICAL if cls == "cubical_parabola" else inv.K_SEMICUBICAL
    n = d.n
    i, j = max(((i, j) for i in range(n) for j in range(i + 1, n)),
               key=lambda p: abs(math.sin(d.phi[p[1]] - d.phi[p[0]])))
    roots, _ = inv.slope_angles(k[i], ks[i], k[j], ks[j], float(d.phi[j] - d.phi[i]), kk)
    out = []
    for psi in roots:
        for half in ((0.0,) if cls == "cubical_parabola" else (0.0, np.pi)):
            th = float(d.phi[i] - psi - half)
            psis = _wrap(d.phi - th)
            lam = np.tan(psis)
            if cls == "cubical_parabola":
                a = float(np.median(inv.I_cp1(lam, k, ks)))
                c = float(np.median(inv.I_cp2(lam, k, ks)))
                if not (np.isfinite(a) and np.isfinite(c)) or a == 0:
                    continue
                out.append(({"a": a, "c": c}, k * (1 + lam * lam) ** 1.5 / (6 * a)))
            else:
                a = float(np.median(inv.I_scp1(lam, k, ks)))
                b = float(np.median(inv.I_scp2(lam, k, ks)))
                if not (np.isfinite(a) and np.isfinite(b)) or a <= 0:
                    continue
                t = 2 * (lam - b) / (3 * a)
                out.append(({"a": a, "b": b}, t))
    return out


def _canonical(cls: str, params: dict, th: float, X: float, Y: float, t: np.ndarray):
    t = np.asarray(t, float).copy()
    if cls == "ellipse" and params["b"] > params["a"]:
        params = {"a": params["b"], "b": params["a"]}
        th += np.pi / 2
        t -= np.pi / 2
    if cls == "ellipse":
        w = float(_wrap(th))
        if w > np.pi / 2 or w <= -np.pi / 2:
            w = float(_wrap(w - np.pi))
            t += np.pi
        th = w
    elif cls == "circle":
        t += th
        th = 0.0
    elif cls == "line":
        ux, uy = math.cos(th), math.sin(th)
        tau = X * ux + Y * uy
        X, Y = X - tau * ux, Y - tau * uy
        t += tau
    if CURVES[cls].t_period is not None:
        t = _wrap(t)
    return params, float(_wrap(th)), X, Y, t


#: a start whose position-and-angle χ² per observation exceeds this (~1e5 σ) is not refined
HOPELESS_PER_OBS = 1e10


def fit_class(cls: str, data: Contacts, max_starts: int = 2, give_up: float = math.inf) -> Fit | None:
    """Fit one class to every touch: closed-form start, then Levenberg–Marquardt.

    Returns None when the class has no closed-form start or its best start is hopeless
    (position-and-angle χ² > HOPELESS_PER_OBS per observation); ``give_up`` stops the iterations of a class
    whose χ² stays above it."""
    sign = CURVES[cls].kappa_sign
    d = data
    if sign != 0:
        dom = float(data.kappa[np.argmax(np.abs(data.kappa))])
        if dom != 0 and math.copysign(1.0, dom) != sign:
            d = data.flipped()
    model = _Model(cls, d)
    starts = []
    with np.errstate(all="ignore"):
        for params, t in _starts(cls, d):
            if not np.all(np.isfinite(t)):
                continue
            cur = CURVES[cls](params)
            th, X, Y = _pose_from(cur, t, d)
            z = model.pack(params, th, X, Y, t)
            r, _ = model.eval(z)
            cost = float(np.sum(r[:, :3] ** 2))  # position and angle: well-conditioned at any aspect
            if np.isfinite(cost):
                starts.append((cost, z, params))
        if not starts:
            return None
        starts.sort(key=lambda s: s[0])
        if starts[0][0] > HOPELESS_PER_OBS * 3 * d.n:
            return None
        best = None
        for cost0, z0, p0 in starts[:max_starts]:
            z, cost, J = model.solve(z0, give_up=give_up)
            if best is None or cost < best[1]:
                best = (z, cost, J, p0)
            if cost < give_up * 1e-3:
                break
    z, cost, J, p0 = best
    if not np.isfinite(cost):
        return None
    r, _ = model.eval(z)
    params = model.params_of(z)
    th, X, Y = (float(v) for v in z[model.np: model.np + 3])
    t = z[model.np + 3:]
    sigma = {}
    if J is not None and np.all(np.isfinite(J)):
        cov = np.linalg.pinv(J.T @ J)
        for idx, (name, lg) in enumerate(zip(model.names, model.log)):
            s = math.sqrt(max(cov[idx, idx], 0.0))
            sigma[name] = s * params[name] if lg else s
    params, th, X, Y, t = _canonical(cls, params, th, X, Y, t)
    return Fit(cls, params, Pose(th, X, Y), t, cost, 5 * d.n, N_SHAPE[cls] + d.n, r, sigma, p0)
