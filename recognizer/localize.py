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
from scipy.linalg.lapack import dgesdd

from recognizer import invariants as inv
from recognizer.curves import CURVES, Pose

__all__ = ["Contacts", "Fit", "fit_class", "fit_class_every_start", "EPS_FLOOR", "N_SHAPE"]

#: relative floor of every measurement's standard deviation (exact data, zero covariance)
EPS_FLOOR = 1e-7
_LOG = {"line": (), "circle": (True,), "ellipse": (True, True), "parabola": (True,), "hyperbola": (True, True),
        "cubical_parabola": (False, False), "semicubical_parabola": (True, False)}
#: shape parameters + pose degrees of freedom not lost to a symmetry (BIC counts these)
N_SHAPE = {"line": 0 + 2, "circle": 1 + 2, "ellipse": 2 + 3, "parabola": 1 + 3, "hyperbola": 2 + 3,
           "cubical_parabola": 2 + 3, "semicubical_parabola": 2 + 3}


_PI, _TAU = math.pi, 2.0 * math.pi
_NUMERIC_ERRORS = (ArithmeticError, ValueError)  # math raises where NumPy gives inf/nan


def _svd(a: np.ndarray):
    """Thin SVD (u, s, vᵀ) by LAPACK gesdd, as np.linalg.svd computes it, without that
    wrapper's per-call cost (a third of the time on a 25×10 Jacobian)."""
    u, s, vt, info = dgesdd(a, compute_uv=1, full_matrices=0)
    if info != 0:  # not converged: NumPy's own path raises LinAlgError
        return np.linalg.svd(a, full_matrices=False)
    return u, s, vt


def _wrap(a):
    return np.remainder(np.asarray(a, float) + np.pi, 2 * np.pi) - np.pi


def _wrap_s(a: float) -> float:
    return (a + _PI) % _TAU - _PI


def _circmean_s(a) -> float:
    return math.atan2(math.fsum(map(math.sin, a)), math.fsum(map(math.cos, a)))


def _mean(a) -> float:
    return math.fsum(a) / len(a)


def _median(a) -> float:
    """np.median of a short list: nan when any value is nan."""
    if any(v != v for v in a):
        return math.nan
    s = sorted(a)
    h = len(s) // 2
    return s[h] if len(s) % 2 else (s[h - 1] + s[h]) / 2


def _div(a: float, b: float) -> float:
    """a / b with IEEE results (±inf, nan) where Python raises."""
    try:
        return a / b
    except ZeroDivisionError:
        return math.nan if a == 0 or a != a else math.copysign(math.inf, a) * math.copysign(1.0, b)


# -- scalar closed forms of recognizer.curves (same formulas), for 3-5 touches ------------
# kernel(p, t) -> (x, y, φ, κ, κ_s, speed) at one t; p the shape parameters in param_names
# order. Python floats: a NumPy call costs more than these few operations.

def _k_line(p, t):
    return t, 0.0, 0.0, 0.0, 0.0, 1.0


def _k_circle(p, t):
    r = p[0]
    return r * math.cos(t), r * math.sin(t), t + _PI / 2, 1.0 / r, 0.0, r


def _k_ellipse(p, t):
    a, b = p
    s, c = math.sin(t), math.cos(t)
    s2 = (a * s) ** 2 + (b * c) ** 2
    return (a * c, b * s, math.atan2(b * c, -a * s), a * b / s2**1.5,
            -3 * a * b * (a - b) * (a + b) * s * c / s2**3, math.hypot(a * s, b * c))


def _k_parabola(p, t):
    a = p[0]
    h = math.hypot(1.0, t)
    return a * t * t, 2 * a * t, math.atan2(1.0, t), -1.0 / (2 * a * h**3), 3 * t / (4 * a * a * h**6), 2 * a * h


def _k_hyperbola(p, t):
    a, b = p
    ch, sh = math.cosh(t), math.sinh(t)
    sp = math.hypot(a * sh, b * ch)
    return (a * ch, b * sh, math.atan2(b * ch, a * sh), -a * b / sp**3,
            3 * a * b * (a * a + b * b) * sh * ch / sp**6, sp)


def _k_cubical(p, t):
    a, c = p
    lam = 3 * a * t * t + c
    q = 1.0 + lam * lam
    sp = math.hypot(1.0, lam)
    return t, a * t**3 + c * t, math.atan(lam), 6 * a * t / sp**3, (6 * a * q - 108 * a * a * t * t * lam) / q**3, sp


def _k_semicubical(p, t):
    a, b = p
    u = 3 * a * t + 2 * b
    sg = -1.0 if t < 0 else 1.0
    hu = math.hypot(2.0, u)
    q = 4.0 + u * u
    return (t * t, a * t**3 + b * t * t, math.atan2(sg * u, sg * 2.0), 6 * a / (abs(t) * hu**3),
            -6 * a * (q + 9 * a * u * t) / (t**3 * q**3), abs(t) * hu)


_KERNELS = {"line": _k_line, "circle": _k_circle, "ellipse": _k_ellipse, "parabola": _k_parabola,
            "hyperbola": _k_hyperbola, "cubical_parabola": _k_cubical, "semicubical_parabola": _k_semicubical}


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
        self._wl = None
        self._rows = None
        self._cols = None
        self._flip = None

    @property
    def scale(self) -> float:
        """L: the touches' extent (largest distance between two contacts), mm."""
        if self._scale is None:
            self._scale = self._extent()
        return self._scale

    def _extent(self) -> float:
        x, y = self.x.tolist(), self.y.tolist()
        span = max((math.hypot(x[i] - x[j], y[i] - y[j]) for i in range(len(x)) for j in range(i + 1, len(x))),
                   default=0.0)
        if span > 0:
            return span
        k = float(np.max(np.abs(self.kappa)))
        return 1.0 / k if k > 0 else 1.0

    def whitener(self) -> np.ndarray:
        """(n, 2, 2) W with W·(δκ, δκ_s) standardized; floors EPS_FLOOR·(|κ| + 1/L) and
        EPS_FLOOR·(|κ_s| + κ² + |κ|/L + 1/L²) added to the variances (κ² is κ_s's natural
        scale: at a sharp vertex κ_s swings by ~κ² over a roundoff-sized step)."""
        if self._white is None:
            self._white = np.array(self._whitener_rows(), dtype=float).reshape(-1, 2, 2)
        return self._white

    def _whitener_rows(self) -> list[tuple]:
        """(W₀₀, W₀₁, W₁₀, W₁₁) per touch: inv(cholesky(C)) of each 2×2 C in closed form,
        C = L·Lᵀ, L = [[l₀₀, 0], [l₁₀, l₁₁]]."""
        if self._wl is not None:
            return self._wl
        L = self.scale
        out = []
        for k, ks, ((c00, c01), (c10, c11)) in zip(self.kappa.tolist(), self.kappa_s.tolist(), self.cov.tolist()):
            fk = EPS_FLOOR * (abs(k) + 1.0 / L)
            fks = EPS_FLOOR * (abs(ks) + k * k + abs(k) / L + 1.0 / L**2)
            c00, c11 = c00 + fk * fk, c11 + fks * fks
            if not c00 > 0:
                raise np.linalg.LinAlgError("Matrix is not positive definite")
            l00 = math.sqrt(c00)
            l10 = c10 / l00
            d = c11 - l10 * l10
            if not d > 0:
                raise np.linalg.LinAlgError("Matrix is not positive definite")
            l11 = math.sqrt(d)
            out.append((1.0 / l00, 0.0, -l10 / (l00 * l11), 1.0 / l11))
        self._wl = out
        return out

    def rows(self) -> list[tuple]:
        """Per touch, as Python floats: (x, y, φ, κ, κ_s, σ_pos, σ_φ, W₀₀, W₀₁, W₁₀, W₁₁),
        the deviations with their floors EPS_FLOOR·L and EPS_FLOOR."""
        if self._rows is None:
            lo = EPS_FLOOR * self.scale
            self._rows = [(x, y, f, k, ks, max(sp, lo), max(sf, EPS_FLOOR), *w) for x, y, f, k, ks, sp, sf, w in zip(
                self.x.tolist(), self.y.tolist(), self.phi.tolist(), self.kappa.tolist(), self.kappa_s.tolist(),
                self.sig_pos.tolist(), self.sig_phi.tolist(), self._whitener_rows())]
        return self._rows

    @property
    def exact(self) -> bool:
        """No stated noise: zero κ/κ_s covariance and zero position and angle deviations."""
        return not (np.any(self.cov) or np.any(self.sig_pos) or np.any(self.sig_phi))

    @property
    def eased(self) -> bool:
        """Exact positions and angles (zero stated deviations) with uncertain κ, κ_s: the
        case of noise-free samples, whose fits start from a widened problem."""
        return bool(np.any(self.cov)) and not (np.any(self.sig_pos) or np.any(self.sig_phi))

    def cols(self) -> tuple[list, list, list, list, list]:
        """(x, y, φ, κ, κ_s) as lists of Python floats."""
        if self._cols is None:
            self._cols = tuple(list(c) for c in zip(*(r[:5] for r in self.rows())))
        return self._cols

    def dominant_kappa(self) -> float:
        """The κ of largest magnitude (the first of equals): its sign is the direction."""
        k = self.cols()[3]
        return max(k, key=abs)

    def flipped(self) -> "Contacts":
        """The same touches seen in the other direction (φ + π, −κ). With D = diag(−1, 1)
        the covariance of (−κ, κ_s) is D·C·D (the κ/κ_s cross term changes sign) and
        W·D whitens it: the κ column of W changes sign (the floors see |κ| and κ² only).
        Made once."""
        if self._flip is None:
            cov = self.cov.copy()
            cov[:, 0, 1] *= -1.0
            cov[:, 1, 0] *= -1.0
            f = Contacts(self.x, self.y, self.phi + np.pi, -self.kappa, self.kappa_s, cov,
                         self.sig_pos, self.sig_phi)
            f._scale = self.scale
            f._wl = [(-w00, w01, -w10, w11) for w00, w01, w10, w11 in self._whitener_rows()]
            f._rows = [(x, y, p + np.pi, -k, ks, sp, sf, -w00, w01, -w10, w11)
                       for x, y, p, k, ks, sp, sf, w00, w01, w10, w11 in self.rows()]
            self._flip = f
        return self._flip


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
        self.names = CURVES[cls].param_names
        self.log = _LOG[cls]
        self.np = len(self.names)
        self.kern = _KERNELS[cls]
        self.rows = data.rows()
        L = data.scale
        self.tscale = L if cls in ("line", "cubical_parabola") else math.sqrt(L) if cls == "semicubical_parabola" else 1.0

    def floor(self) -> float:
        """A lower bound of the cost over every parameter value: the line's κ, κ_s are 0
        and the circle's κ_s 0 and κ one value 1/r (the best common κ, by weighted least
        squares); 0 for other classes."""
        if self.cls == "line":
            return sum((w00 * k + w01 * ks) ** 2 + (w10 * k + w11 * ks) ** 2
                       for _, _, _, k, ks, _, _, w00, w01, w10, w11 in self.rows)
        if self.cls != "circle":
            return 0.0
        # rows κ̂·W[:, 0] − W·(κ, κ_s) are linear in the common κ̂
        ab = [(w0, -w0 * k - w1 * ks) for _, _, _, k, ks, _, _, w00, w01, w10, w11 in self.rows
              for w0, w1 in ((w00, w01), (w10, w11))]
        saa = sum(a * a for a, _ in ab)
        c = -sum(a * b for a, b in ab) / saa if saa > 0 else 0.0
        return sum((a * c + b) ** 2 for a, b in ab)

    def params_of(self, z) -> dict:
        p = z[: self.np]
        return {k: (math.exp(v) if lg else float(v)) for k, v, lg in zip(self.names, p, self.log)}

    def pack(self, params: dict, theta, X, Y, t) -> np.ndarray:
        p = [math.log(params[k]) if lg else params[k] for k, lg in zip(self.names, self.log)]
        return np.array(p + [theta, X, Y] + list(t), dtype=float)

    def eval(self, z):
        """Whitened residuals of every touch (a flat list x, y, φ, κ, κ_s, ...), their sum
        of squares (inf when not finite) and the pieces the Jacobian needs; (None, inf,
        None) where the curve is not defined."""
        zl = z.tolist() if isinstance(z, np.ndarray) else z
        o = self.np
        th, X, Y = zl[o: o + 3]
        kern = self.kern
        r = []
        fr = []
        try:
            p = tuple(math.exp(v) if lg else v for v, lg in zip(zl[:o], self.log))
            ct, st = math.cos(th), math.sin(th)
            for t, (x, y, phi, k, ks, sp, sf, w00, w01, w10, w11) in zip(zl[o + 3:], self.rows):
                f = kern(p, t)
                px, py = f[0], f[1]
                e0, e1 = f[3] - k, f[4] - ks
                r += ((ct * px - st * py + X - x) / sp, (st * px + ct * py + Y - y) / sp,
                      ((f[2] + th - phi + _PI) % _TAU - _PI) / sf, w00 * e0 + w01 * e1, w10 * e0 + w11 * e1)
                fr.append(f)
        except _NUMERIC_ERRORS:
            return None, math.inf, None
        cost = sum(v * v for v in r)
        return r, (cost if math.isfinite(cost) else math.inf), (p, ct, st, fr)

    def jac(self, z, r, parts):
        """Jacobian (5n, m) of the residuals: forward differences in the shape parameters,
        analytic in pose and t (dp/dt = speed·(cos φ, sin φ), dφ/dt = κ·speed,
        dκ/dt = κ_s·speed, dκ_s/dt a central difference). Built in Python floats, one
        NumPy conversion at the end (an element-wise NumPy fill costs more than the math)."""
        p, ct, st, fr = parts
        n = len(fr)
        o = self.np
        m = o + 3 + n
        zl = z.tolist()
        th, X, Y = zl[o: o + 3]
        ts = zl[o + 3:]
        rl = r.tolist() if isinstance(r, np.ndarray) else r
        kern, tscale, rows = self.kern, self.tscale, self.rows
        # shape columns: the residuals at a forward step of one shape parameter (as eval)
        shape = []
        for j in range(o):
            if self.log[j]:
                h = 1e-7
            elif self.cls == "cubical_parabola" and j == 0:  # a, 1/mm², never 0
                h = 1e-7 * abs(zl[j])
            else:  # dimensionless slopes c, b
                h = 1e-7 * max(abs(zl[j]), 1.0)
            zj = zl[j] + h
            pj = p[:j] + (math.exp(zj) if self.log[j] else zj,) + p[j + 1:]
            col = []
            try:
                for t, (x, y, phi, k, ks, sp, sf, w00, w01, w10, w11) in zip(ts, rows):
                    f = kern(pj, t)
                    px, py = f[0], f[1]
                    e0, e1 = f[3] - k, f[4] - ks
                    col += ((ct * px - st * py + X - x) / sp, (st * px + ct * py + Y - y) / sp,
                            ((f[2] + th - phi + _PI) % _TAU - _PI) / sf, w00 * e0 + w01 * e1, w10 * e0 + w11 * e1)
                col = [(a - b) / h for a, b in zip(col, rl)]
            except _NUMERIC_ERRORS:
                col = [math.nan] * (5 * n)
            shape.append(col)
        out = []
        for i, (t, f, row) in enumerate(zip(ts, fr, rows)):
            px, py, ph, kc, ksc, spd = f
            sp, sf, w00, w01, w10, w11 = row[5:]
            h = 1e-6 * max(abs(t), tscale)
            try:
                kss = (kern(p, t + h)[4] - kern(p, t - h)[4]) / (2 * h)
            except _NUMERIC_ERRORS:
                kss = math.nan
            ang = ph + th
            e0 = ksc * spd
            before, after = [0.0] * i, [0.0] * (n - 1 - i)
            b = 5 * i
            out += [c[b] for c in shape]
            out += ((-st * px - ct * py) / sp, 1.0 / sp, 0.0)
            out += before
            out.append(spd * math.cos(ang) / sp)
            out += after
            out += [c[b + 1] for c in shape]
            out += ((ct * px - st * py) / sp, 0.0, 1.0 / sp)
            out += before
            out.append(spd * math.sin(ang) / sp)
            out += after
            out += [c[b + 2] for c in shape]
            out += (1.0 / sf, 0.0, 0.0)
            out += before
            out.append(kc * spd / sf)
            out += after
            out += [c[b + 3] for c in shape]
            out += (0.0, 0.0, 0.0)
            out += before
            out.append(w00 * e0 + w01 * kss)
            out += after
            out += [c[b + 4] for c in shape]
            out += (0.0, 0.0, 0.0)
            out += before
            out.append(w10 * e0 + w11 * kss)
            out += after
        return np.fromiter(out, float, 5 * n * m).reshape(5 * n, m)

    def solve(self, z0, max_iter=40, give_up=math.inf):
        """Levenberg–Marquardt from z0; stops early once the cost is negligible (exact data)
        or when after 4 iterations it is still above ``give_up`` (hopeless class); not at all
        when even the class's ``floor`` is above it (same verdict) or, on exact data, when
        the start is HOPELESS_START times above it (a wrong class: the right class's
        closed-form start is within 1e-4 of ``give_up`` on exact data; with noise a start
        that far off can still end consistent, so there the rule is off).
        Each iteration takes one SVD of the column-scaled Jacobian; every damping tried is
        then a product with it (the least-squares step of [J; √μ·I] x = [−r; 0]).
        Returns (z, cost, residuals, parts) (what ``jac`` needs at z)."""
        z = np.asarray(z0, float).copy()
        r, cost, parts = self.eval(z)
        if r is None or not cost < math.inf:
            return z, math.inf, None, None
        r = np.array(r)
        mu = 1e-6
        if cost > give_up and ((self.d.exact and cost > HOPELESS_START * give_up) or self.floor() > give_up):
            max_iter = 0
        for it in range(max_iter):
            if cost < 1e-12 or (it >= 4 and cost > give_up):
                break
            J = self.jac(z, r, parts)
            if not np.all(np.isfinite(J)):
                break
            cn = np.sqrt(np.einsum("ij,ij->j", J, J))
            cn[cn == 0] = 1.0
            U, s, Vt = _svd(J / cn)
            g = s * (U.T @ -r)
            s2 = s * s
            improved = False
            for _ in range(8):
                zn = z + (Vt.T @ (g / (s2 + mu))) / cn
                rn, cn_cost, pn = self.eval(zn)
                if cn_cost < cost:
                    improved = True
                    small = cost - cn_cost <= 1e-14 * cost + 1e-24
                    z, r, parts, cost = zn, np.array(rn), pn, cn_cost
                    mu = max(mu / 10, 1e-12)
                    break
                mu *= 10
            if not improved or small:
                break
        return z, cost, r, parts


# -- closed-form starts -------------------------------------------------------------------

def _pose_from(kern, p, t, d: Contacts):
    """Pose putting the curve points at t onto the touches (θ the circular mean of the angle
    differences, (x, y) the mean offset) and its position-and-angle cost."""
    fr = [kern(p, ti) for ti in t]
    rows = d.rows()
    dph = [row[2] - f[2] for row, f in zip(rows, fr)]
    th = _circmean_s(dph)
    ct, st = math.cos(th), math.sin(th)
    ex = [row[0] - (ct * f[0] - st * f[1]) for row, f in zip(rows, fr)]
    ey = [row[1] - (st * f[0] + ct * f[1]) for row, f in zip(rows, fr)]
    X, Y = _mean(ex), _mean(ey)
    cost = sum(((X - a) ** 2 + (Y - b) ** 2) / row[5] ** 2 + (_wrap_s(th - c) / row[6]) ** 2
               for a, b, c, row in zip(ex, ey, dph, rows))
    return th, X, Y, (cost if math.isfinite(cost) else math.inf)


def _best_pair(k):
    n = len(k)
    best, bi, bj = -1.0, 0, 1
    for i in range(n):
        for j in range(i + 1, n):
            q = inv.pair_condition_s(k[i], k[j])
            if q > best:
                best, bi, bj = q, i, j
    return bi, bj


def _conic_start(cls: str, d: Contacts) -> list[tuple[dict, list]]:
    """An ellipse or hyperbola start from the touches' positions and tangents alone.

    The invariants I_c1, I_c2 (eqs. 9, 10) lean on κ_s, the worst-measured quantity: under
    noise they can give no start or one in the wrong basin. A conic Q = Ax² + Bxy + Cy² +
    Dx + Ey + F through every contact point (Q(p) = 0) and tangent to its pad there
    (∇Q(p)·(cos φ, sin φ) = 0) is linear in (A…F): with three touches, six equations for
    five ratios, solved by the SVD in coordinates centred and scaled by L. Its centre,
    axes and discriminant give a, b, the frame and t per touch (none when the conic is of
    the other type)."""
    x, y, phi = (np.asarray(c, float) for c in d.cols()[:3])
    if d.n < 3:
        return []
    L = d.scale
    mx, my = x.mean(), y.mean()
    u, w = (x - mx) / L, (y - my) / L
    c, s = np.cos(phi), np.sin(phi)
    rows = np.vstack([np.stack([u * u, u * w, w * w, u, w, np.ones_like(u)], axis=1),
                      np.stack([2 * u * c, w * c + u * s, 2 * w * s, c, s, np.zeros_like(u)], axis=1)])
    if not np.all(np.isfinite(rows)):
        return []
    A, B, C, D, E, F = np.linalg.svd(rows)[2][-1]
    M = np.array([[A, B / 2], [B / 2, C]])
    det = A * C - B * B / 4
    if abs(det) < 1e-12 * (A * A + B * B + C * C):
        return []
    centre = -np.linalg.solve(M, [D / 2, E / 2])
    Fc = F + 0.5 * (D * centre[0] + E * centre[1])
    lam, vec = np.linalg.eigh(M)
    if cls == "ellipse":
        if det <= 0 or not np.all(-Fc / lam > 0):
            return []
        i = int(np.argmin(np.abs(lam)))  # the major axis: the eigenvalue of smaller magnitude
        a, b = math.sqrt(-Fc / lam[i]) * L, math.sqrt(-Fc / lam[1 - i]) * L
    else:
        if det >= 0:
            return []
        transverse = np.flatnonzero(-Fc * lam > 0)  # x'²/a² − y'²/b² = 1; none: a pair of lines
        if transverse.size != 1:
            return []
        i = int(transverse[0])
        a, b = math.sqrt(-Fc / lam[i]) * L, math.sqrt(Fc / lam[1 - i]) * L
    ex = vec[:, i]
    th = math.atan2(ex[1], ex[0])
    cx, cy = mx + centre[0] * L, my + centre[1] * L
    ct, st = math.cos(th), math.sin(th)
    xp = (x - cx) * ct + (y - cy) * st
    yp = -(x - cx) * st + (y - cy) * ct
    if cls == "ellipse":
        t = np.arctan2(yp / b, xp / a)
    else:
        if np.mean(xp) < 0:  # contacts on the other branch: turn the frame by π
            xp, yp = -xp, -yp
        t = np.arcsinh(yp / b)
    if not (math.isfinite(a) and math.isfinite(b) and np.all(np.isfinite(t))):
        return []
    return [({"a": a, "b": b}, t.tolist())]


#: the semicubical scan: shape b on an asinh grid over ±SCAN_B, the first touch's
#: scale-free coordinate |v| = |a·t| on a log grid over SCAN_V (times max(1, |b|))
SCAN_B, SCAN_NB = 20.0, 75
SCAN_V, SCAN_NV = (1e-2, 1e2), 81


def _scan_cost(d: Contacts, b: np.ndarray, v0: np.ndarray, sg: float):
    """The semicubical scan's score at shapes b and first-touch coordinates v0 on branch
    sg (broadcast arrays): χ² of positions, κ and κ_s with φ fitted exactly; returns
    (cost, v per touch, scale 1/a²), cost inf where a touch's v is not on the branch its
    tangent angle points to (the other touches may lie on either branch)."""
    x, y, phi, k, ks = (np.asarray(c, float) for c in d.cols())
    rows = d.rows()
    w_pos = np.array([1.0 / r[5] ** 2 for r in rows])
    W = d.whitener()
    b = b[..., None]
    th = phi[0] - np.arctan2(sg * (3 * v0 + 2 * b[..., 0]), 2 * sg)
    psi = _wrap(phi - th[..., None])
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        v = (2 * np.tan(psi) - 2 * b) / 3
        # each touch on the branch its tangent points to: ψ within ±π/2 on v > 0, beyond on v < 0
        ok = np.all((np.abs(psi) < _PI / 2) == (v > 0), axis=-1)
        px, py = v * v, v**3 + b * v * v
        c, s_ = np.cos(th)[..., None], np.sin(th)[..., None]
        qx, qy = c * px - s_ * py, s_ * px + c * py
        wsum = w_pos.sum()
        dx, dy = x - (w_pos * x).sum() / wsum, y - (w_pos * y).sum() / wsum
        dqx = qx - (w_pos * qx).sum(-1, keepdims=True) / wsum
        dqy = qy - (w_pos * qy).sum(-1, keepdims=True) / wsum
        scale = (w_pos * (dx * dqx + dy * dqy)).sum(-1) / (w_pos * (dqx**2 + dqy**2)).sum(-1)
        ok &= scale > 0
        sc = scale[..., None]
        cost = (w_pos * ((dx - sc * dqx) ** 2 + (dy - sc * dqy) ** 2)).sum(-1)
        u = 3 * v + 2 * b
        q = 4.0 + u * u
        rk = k - 6.0 / (np.abs(v) * q**1.5) / sc
        rks = ks + 6.0 * (q + 9 * u * v) / (v**3 * q**3) / (sc * sc)
        r0 = W[:, 0, 0] * rk + W[:, 0, 1] * rks
        r1 = W[:, 1, 0] * rk + W[:, 1, 1] * rks
        cost = cost + (r0 * r0 + r1 * r1).sum(-1)
    return np.where(ok & np.isfinite(cost), cost, np.inf), v, scale


def _semicubical_scan(d: Contacts, n_best: int = 4) -> list[tuple[dict, list]]:
    """Starts for the semicubical parabola from the tangent angles and positions first.

    Under noise κ_s is the worst-measured quantity, and the slope equation built on it can
    miss the right frame entirely. Here the scale-free curve (v², v³ + b v²) (v = a t, the
    curve shrunk by a²) is scanned over its shape b and the first touch's v on both
    branches: the tangent angle ψ(v) = atan2(σ(3v + 2b), 2σ) (σ = sign v) is monotonic on
    a branch, so φ₀ fixes the frame θ = φ₀ − ψ(v₀) and every other touch's v from
    tan ψᵢ = (3vᵢ + 2b)/2, on the branch (either: touches around the cusp's tip) that ψᵢ
    points to; the scale 1/a² and the translation follow from the positions by
    linear least squares, and the point is scored by the χ² of the positions and of
    κ = a²κ̃(v), κ_s = a⁴κ̃_s(v) (eq. 18–19's quantities) under their stated deviations.
    The best ``n_best`` separated scan points are returned (a start needs only to lie in
    the right basin: the contact fit that follows polishes it)."""
    bs = np.sinh(np.linspace(-math.asinh(SCAN_B), math.asinh(SCAN_B), SCAN_NB))
    g = np.geomspace(*SCAN_V, SCAN_NV)
    found = []
    for sg in (1.0, -1.0):
        v0 = sg * g[None, :] * np.maximum(1.0, np.abs(bs))[:, None]
        cost, v, scale = _scan_cost(d, bs[:, None], v0, sg)
        for flat in np.argsort(cost, axis=None)[: 50 * n_best]:
            i, j = np.unravel_index(flat, cost.shape)
            if not np.isfinite(cost[i, j]):
                break
            if not any(s == sg and abs(i - ii) <= 4 and abs(j - jj) <= 6 for _, s, ii, jj, _ in found):
                root = math.sqrt(float(scale[i, j]))
                found.append((float(cost[i, j]), sg, int(i), int(j),
                              ({"a": 1.0 / root, "b": float(bs[i])}, [float(vi) * root for vi in v[i, j]])))
    found.sort(key=lambda f: f[:4])
    return [start for *_, start in found[:n_best]]


def _starts(cls: str, d: Contacts, every_pair: bool = False):
    """Closed-form (params, t) starting points for a class (data in canonical direction):
    ellipse and hyperbola from the invariants and from the conic through the touches
    (``_conic_start``); the cubic classes by ``_cubic_starts``."""
    x, y, phi, k, ks = d.cols()
    if cls == "line":
        th = _circmean_s(phi)
        c, s = math.cos(th), math.sin(th)
        mx, my = _mean(x), _mean(y)
        return [({}, [(xi - mx) * c + (yi - my) * s for xi, yi in zip(x, y)])]
    if cls == "circle":
        mk = _mean(k)
        if not mk > 0:
            return []
        r = 1.0 / mk
        cx = _mean([xi - r * math.sin(f) for xi, f in zip(x, phi)])
        cy = _mean([yi + r * math.cos(f) for yi, f in zip(y, phi)])
        return [({"r": r}, [math.atan2(yi - cy, xi - cx) for xi, yi in zip(x, y)])]
    if cls in ("ellipse", "hyperbola"):  # the invariants divide by κ; the conic through the touches does not
        return (_conic_invariant_starts(cls, d) if 0.0 not in k else []) + _conic_start(cls, d)
    if cls == "parabola":
        if 0.0 in k:  # I_p divides by κ: no start
            return []
        a = _median([1.0 / (2.0 * inv.I_p_s(ki, ksi) ** 1.5) for ki, ksi in zip(k, ks)])
        return [({"a": a}, [ksi / (3.0 * ki * ki) for ki, ksi in zip(k, ks)])] if a > 0 and math.isfinite(a) else []
    return _cubic_starts(cls, d, every_pair)


def _conic_invariant_starts(cls: str, d: Contacts) -> list[tuple[dict, list]]:
    """Ellipse or hyperbola a, b from I_c1, I_c2 (eqs. 9, 10) of the best-conditioned pair, t per touch."""
    _, _, phi, k, ks = d.cols()
    i, j = _best_pair(k)
    c1, c2 = inv.I_c12_s(k[i], ks[i], k[j], ks[j])
    if not (math.isfinite(c1) and math.isfinite(c2)):
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
        t0 = []
        for ki, ksi in zip(k, ks):
            w = (a * b / abs(ki)) ** (2.0 / 3.0)
            s2 = min(max((w - b * b) / ((a - b) * (a + b)), 0.0), 1.0)
            t0.append(math.atan2(math.sqrt(s2), math.sqrt(1.0 - s2)) * (-1.0 if ksi > 0 else 1.0))
        th = phi[0] - _k_ellipse((a, b), t0[0])[2]
        return [({"a": a, "b": b}, [t + _PI if abs(_wrap_s(_k_ellipse((a, b), t)[2] + th - f)) > _PI / 2 else t
                                    for t, f in zip(t0, phi)])]
    if c1 >= 0:
        return []
    P = (-c1) ** -1.5
    D = c2 * P ** (4.0 / 3.0)  # a² − b²
    a2 = (D + math.hypot(D, 2 * P)) / 2
    a = math.sqrt(a2)
    b = P / a
    t = []
    for ki, ksi in zip(k, ks):
        w = (a * b / abs(ki)) ** (2.0 / 3.0)
        sh = math.sqrt(max((w - b * b) / (a * a + b * b), 0.0))
        t.append(math.asinh(sh) * (0.0 if ksi == 0 else math.copysign(1.0, ksi)))
    return [({"a": a, "b": b}, t)]


def _cubic_starts(cls: str, d: Contacts, every_pair: bool) -> list[tuple[dict, list]]:
    """Cubical / semicubical parabola starts: the canonical tangent angle from the slope
    equation of the best-turning pair (every pair with ``every_pair``), then a, c (a, b)
    from I_cp1/I_cp2 (I_scp1/I_scp2); for the semicubical with ``every_pair`` also the scan
    of its shape and location (``_semicubical_scan``)."""
    _, _, phi, k, ks = d.cols()
    # cubic classes: canonical tangent angle from the slope equation of the best-turning pair
    kk = inv.K_CUBICAL if cls == "cubical_parabola" else inv.K_SEMICUBICAL
    n = d.n
    pairs = sorted(((i, j) for i in range(n) for j in range(i + 1, n)),
                   key=lambda q: -abs(math.sin(phi[q[1]] - phi[q[0]])))
    frames = []
    for i, j in (pairs if every_pair else pairs[:1]):
        roots, _ = inv.slope_angles(k[i], ks[i], k[j], ks[j], phi[j] - phi[i], kk)
        frames += [phi[i] - psi for psi in roots]
    out = []
    for th in frames:
        # λ = tan ψ is blind to a half turn of the frame: the branch (sign of t) of the
        # semicubical parabola follows from t = 2(λ − b)/(3a), so one turn per root
        lam = [math.tan(_wrap_s(f - th)) for f in phi]
        dens = [ksi + 3.0 * li * ki * ki for li, ki, ksi in zip(lam, k, ks)]
        if cls == "cubical_parabola":
            a = _median([de * (1.0 + li * li) ** 2 / 6.0 for li, de in zip(lam, dens)])
            c = _median([li - _div(ki * ki * (1.0 + li * li), 2.0 * de) for li, ki, de in zip(lam, k, dens)])
            if not (math.isfinite(a) and math.isfinite(c)) or a == 0:
                continue
            out.append(({"a": a, "c": c}, [ki * (1 + li * li) ** 1.5 / (6 * a) for li, ki in zip(lam, k)]))
        else:
            a = _median([math.sqrt(abs(_div(-8.0 * ki**3 * (1.0 + li * li) ** 2.5, 9.0 * de)))
                         for li, ki, de in zip(lam, k, dens)])
            b = _median([li + _div(ki * ki * (1.0 + li * li), de) for li, ki, de in zip(lam, k, dens)])
            if not (math.isfinite(a) and math.isfinite(b)) or a <= 0:
                continue
            out.append(({"a": a, "b": b}, [2 * (li - b) / (3 * a) for li in lam]))
    if cls == "semicubical_parabola" and every_pair and d.n >= 2:
        out += _semicubical_scan(d)
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
#: on exact data, a start whose χ² exceeds this many times the give-up level is not iterated
HOPELESS_START = 1e6


def fit_class(cls: str, data: Contacts, max_starts: int = 2, give_up: float = math.inf,
              sigma_below: float = math.inf) -> Fit | None:
    """Fit one class to every touch: closed-form start, then Levenberg–Marquardt.

    Returns None when the class has no closed-form start or, on exact data, its best start
    is hopeless (position-and-angle χ² > HOPELESS_PER_OBS per observation; with exact
    positions and angles but uncertain κ, κ_s such a start is first eased,
    ``_eased_start``); ``give_up`` stops the iterations of a class
    whose χ² stays above it. The parameters' standard deviations (``Fit.sigma``) are
    computed only for a χ² ≤ ``sigma_below`` (a class that fails its test reports none)."""
    fits = _fit_starts(cls, data, max_starts, give_up, sigma_below, every=False)
    return fits[0] if fits else None


def fit_class_every_start(cls: str, data: Contacts, give_up: float = math.inf,
                          sigma_below: float = math.inf) -> list[Fit]:
    """One fit per closed-form start (every slope root and branch of the cubic classes),
    best first: the invariants' noisy start can sit on the wrong branch, and a later
    refinement over every sample cannot jump branches, so each is offered to it."""
    return _fit_starts(cls, data, 8, give_up, sigma_below, every=True)


def _fit_starts(cls: str, data: Contacts, max_starts: int, give_up: float, sigma_below: float,
                every: bool) -> list[Fit]:
    sign = CURVES[cls].kappa_sign
    d = data
    if sign != 0:
        dom = data.dominant_kappa()
        if dom != 0 and math.copysign(1.0, dom) != sign:
            d = data.flipped()
    model = _Model(cls, d)
    kern = model.kern
    starts = []
    try:
        closed_form = _starts(cls, d, every_pair=every)
    except _NUMERIC_ERRORS:  # an overflow NumPy would have turned into a non-finite start
        closed_form = []
    for params, t in closed_form:
        if not all(map(math.isfinite, t)):
            continue
        try:  # cost of position and angle: well-conditioned at any aspect
            th, X, Y, cost = _pose_from(kern, tuple(params[k] for k in model.names), t, d)
        except _NUMERIC_ERRORS:
            continue
        if cost < math.inf:
            starts.append((cost, (params, th, X, Y, t), params))
    if not starts:
        return []
    starts.sort(key=lambda s: s[0])
    if starts[0][0] > HOPELESS_PER_OBS * 3 * d.n and not d.eased:
        return []
    solved = []
    for cost0, z0, p0 in starts[:max_starts]:
        if every and cost0 > HOPELESS_PER_OBS * 3 * d.n and not d.eased:
            continue
        z = model.pack(*z0)
        if cost0 > give_up and d.eased:
            z = _eased_start(cls, d, z, cost0)
        z, cost, r, parts = model.solve(z, give_up=give_up)
        if np.isfinite(cost):
            solved.append((cost, z, r, parts, p0))
        if not every and cost < give_up * 1e-3:
            break
    solved.sort(key=lambda s: s[0])
    if every:  # starts that converged to the same fit (several pairs give one frame) once
        kept = []
        for sol in solved:
            if not any(np.allclose(sol[1], k[1], rtol=1e-6, atol=1e-9) for k in kept):
                kept.append(sol)
        solved = kept
    return [_finish(model, cls, d, z, cost, r, parts, p0, sigma_below)
            for cost, z, r, parts, p0 in (solved if every else solved[:1])]


def _eased_start(cls: str, d: Contacts, z0: np.ndarray, cost0: float) -> np.ndarray:
    """A start for touches whose positions and angles are far more certain than their κ, κ_s
    (noise-free samples: exact positions, estimated curvatures). A closed-form start made
    from poorly conditioned κ, κ_s can miss the positions by 1e5 of their σ, where the fit
    gives up although the class is right. So first fit with the position and angle
    deviations widened until the start is within about one of them and return that fit's
    solution (the caller iterates from it with the stated deviations)."""
    f = math.sqrt(cost0 / (3 * d.n))
    rows = d.rows()
    wide = Contacts(d.x, d.y, d.phi, d.kappa, d.kappa_s, d.cov,
                    np.array([r[5] * f for r in rows]), np.array([r[6] * f for r in rows]))
    z, cost, _, _ = _Model(cls, wide).solve(z0)
    return z if math.isfinite(cost) else z0


def _finish(model: _Model, cls: str, d: Contacts, z, cost, r, parts, p0, sigma_below: float) -> Fit:
    """The Fit at the solution z: parameters, σ's (χ² ≤ ``sigma_below``), canonical form."""
    params = model.params_of(z)
    th, X, Y = (float(v) for v in z[model.np: model.np + 3])
    t = z[model.np + 3:]
    sigma = {}
    J = model.jac(z, r, parts) if model.np and cost <= sigma_below else None
    if J is not None and np.all(np.isfinite(J)):
        # diagonal of pinv(JᵀJ) from the SVD of J (singular values of JᵀJ below 1e-15 of the largest dropped)
        _, s, Vt = _svd(J)
        keep = s * s > 1e-15 * s[0] ** 2
        var = (Vt[keep, : model.np] ** 2 / (s[keep] ** 2)[:, None]).sum(axis=0)
        for idx, (name, lg) in enumerate(zip(model.names, model.log)):
            sd = math.sqrt(max(float(var[idx]), 0.0))
            sigma[name] = sd * params[name] if lg else sd
    params, th, X, Y, t = _canonical(cls, params, th, X, Y, t)
    return Fit(cls, params, Pose(th, X, Y), t, cost, 5 * d.n, N_SHAPE[cls] + d.n, r.reshape(-1, 5), sigma, p0)
