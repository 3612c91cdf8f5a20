"""The contact fit of one class: the exact contact equations of every touch, solved by
Levenberg–Marquardt.

Unknowns z: the shape parameters (positive ones as logarithms), the pose (θ, x, y) and
one contact parameter t per touch. Residuals, per touch: position (x, y)/σ_pos, wrapped
tangent angle φ/σ_φ, and (κ, κ_s) whitened by the touch's covariance
(recognizer.contacts). Jacobian: closed form in every unknown (``DERIVATIVES``: the
kernels differentiated in their shape parameters and κ_s in t); until session 22 the
shape columns were forward differences and dκ_s/dt a central one, ~2× the Jacobian's
cost (each difference a further kernel evaluation per touch).

Why a solver of its own and scalar closed forms beside recognizer.curves (measured on
56 balanced requests, 8 per class, seed 1, CPU time per recognition, same machine and
load): this module as it is, 93 ms; the same Levenberg–Marquardt evaluating
recognizer.curves' vectorized forms, 150 ms; scipy.optimize.least_squares (refine's
engine) on those forms, 167 ms, MINPACK through scipy.optimize.leastsq 135 ms with one
semicubical answer in a worse minimum (1.1 % → 85 % error). A fit sees 3–5 touches and
is evaluated ~10⁴ times per recognition: NumPy's per-call cost on 3-element arrays
(~1 µs a call, ~50 µs per evaluation) outweighs the arithmetic, and least_squares adds
its own wrapper per call. So the kernels below restate the closed forms of
recognizer.curves on Python floats (checked against them to 1e-13 in
tests/recognizer/test_recognizer_fast.py); refinement over every sample (dozens of rows)
keeps MINPACK (recognizer.refine.least_squares).
"""

from __future__ import annotations

import math

import numpy as np
from scipy.linalg.lapack import dgesdd

from recognizer.contacts import Contacts
from recognizer.curves import CURVES

__all__ = ["ContactModel", "KERNELS", "DERIVATIVES", "HOPELESS_START", "svd"]

_LOG = {"line": (), "circle": (True,), "ellipse": (True, True), "parabola": (True,), "hyperbola": (True, True),
        "cubical_parabola": (False, False), "semicubical_parabola": (True, False)}
_PI, _TAU = math.pi, 2.0 * math.pi
_NUMERIC_ERRORS = (ArithmeticError, ValueError)  # math raises where NumPy gives inf/nan
#: on exact data, a start whose χ² exceeds this many times the give-up level is not iterated
HOPELESS_START = 1e6
#: iterations after which a fit still above the give-up level is dropped (a hopeless class):
#: a far start of the right class can need 8 (tools.bench_wide seed 9, cubical trial 17 after
#: touches far out on the steep part, one with κ of the wrong sign: its start began 1e5
#: above the give-up level and stalled there for a few iterations; dropped after 4, the
#: answer was unclassified; after 8 it goes on to χ² 16.3)
GIVE_UP_AFTER = 8


def svd(a: np.ndarray):
    """Thin SVD (u, s, vᵀ) by LAPACK gesdd, as np.linalg.svd computes it, without that
    wrapper's per-call cost (a third of the time on a 25×10 Jacobian)."""
    u, s, vt, info = dgesdd(a, compute_uv=1, full_matrices=0)
    if info != 0:  # not converged: NumPy's own path raises LinAlgError
        return np.linalg.svd(a, full_matrices=False)
    return u, s, vt


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


KERNELS = {"line": _k_line, "circle": _k_circle, "ellipse": _k_ellipse, "parabola": _k_parabola,
            "hyperbola": _k_hyperbola, "cubical_parabola": _k_cubical, "semicubical_parabola": _k_semicubical}


# derivative(p, t) -> ∂(x, y, φ, κ, κ_s)/∂p_j for each shape parameter in turn (raw, not
# logarithmic), then dκ_s/dt: a flat tuple of 5·len(p) + 1 floats, the closed forms of the
# kernels above differentiated (checked against central differences of the kernels in
# tests/recognizer/test_solver_jacobian.py).

def _d_line(p, t):
    return (0.0,)


def _d_circle(p, t):
    r = p[0]
    return math.cos(t), math.sin(t), 0.0, -1.0 / (r * r), 0.0, 0.0


def _d_ellipse(p, t):
    a, b = p
    s, c = math.sin(t), math.cos(t)
    s2 = (a * s) ** 2 + (b * c) ** 2
    k = a * b / s2**1.5
    g = s * c / s2**3
    ks = -3 * a * b * (a - b) * (a + b) * g
    return (c, 0.0, b * s * c / s2, k * (1 / a - 3 * a * s * s / s2), -3 * b * (3 * a * a - b * b) * g - 6 * a * s * s * ks / s2,
            0.0, s, -a * s * c / s2, k * (1 / b - 3 * b * c * c / s2), -3 * a * (a * a - 3 * b * b) * g - 6 * b * c * c * ks / s2,
            -3 * a * b * (a - b) * (a + b) * ((c - s) * (c + s) / s2**3 - 6 * (a - b) * (a + b) * (s * c) ** 2 / s2**4))


def _d_parabola(p, t):
    a = p[0]
    h2 = 1.0 + t * t
    k = -1.0 / (2 * a * h2**1.5)
    ks = 3 * t / (4 * a * a * h2**3)
    return t * t, 2 * t, 0.0, -k / a, -2 * ks / a, 3 * (1 - 5 * t * t) / (4 * a * a * h2**4)


def _d_hyperbola(p, t):
    a, b = p
    ch, sh = math.cosh(t), math.sinh(t)
    q = (a * sh) ** 2 + (b * ch) ** 2
    k = -a * b / q**1.5
    g = sh * ch / q**3
    ks = 3 * a * b * (a * a + b * b) * g
    return (ch, 0.0, -b * sh * ch / q, k * (1 / a - 3 * a * sh * sh / q), 3 * b * (3 * a * a + b * b) * g - 6 * a * sh * sh * ks / q,
            0.0, sh, a * sh * ch / q, k * (1 / b - 3 * b * ch * ch / q), 3 * a * (a * a + 3 * b * b) * g - 6 * b * ch * ch * ks / q,
            3 * a * b * (a * a + b * b) * ((ch * ch + sh * sh) / q**3 - 6 * (a * a + b * b) * (sh * ch) ** 2 / q**4))


def _d_cubical(p, t):
    a, c = p
    t2 = t * t
    lam = 3 * a * t2 + c
    q = 1.0 + lam * lam
    n = 6 * a * q - 108 * a * a * t2 * lam
    q3 = q**3
    dk_dlam = -18 * a * t * lam / q**2.5
    dn_a = 6 * q - 180 * a * t2 * lam - 324 * a * a * t2 * t2
    dn_c = 12 * a * lam - 108 * a * a * t2
    dq_dt = 12 * a * t * lam
    dn_dt = -144 * a * a * t * lam - 648 * a**3 * t2 * t
    return (0.0, t2 * t, 3 * t2 / q, 6 * t / q**1.5 + 3 * t2 * dk_dlam, (dn_a - 6 * n * lam * 3 * t2 / q) / q3,
            0.0, t, 1.0 / q, dk_dlam, (dn_c - 6 * n * lam / q) / q3,
            (dn_dt - 3 * n * dq_dt / q) / q3)


def _d_semicubical(p, t):
    a, b = p
    u = 3 * a * t + 2 * b
    q = 4.0 + u * u
    k = 6 * a / (abs(t) * q**1.5)
    m = q + 9 * a * u * t
    f = -6 / (t**3 * q**3)
    return (0.0, t**3, 6 * t / q, 6 / (abs(t) * q**1.5) - 9 * k * u * t / q, f * (m + a * (15 * u * t + 27 * a * t * t) - 18 * a * m * u * t / q),
            0.0, t * t, 4 / q, -6 * k * u / q, f * a * (4 * u + 18 * a * t - 12 * m * u / q),
            f * a * (15 * a * u + 27 * a * a * t - 3 * m / t - 18 * a * m * u / q))


DERIVATIVES = {"line": _d_line, "circle": _d_circle, "ellipse": _d_ellipse, "parabola": _d_parabola,
               "hyperbola": _d_hyperbola, "cubical_parabola": _d_cubical, "semicubical_parabola": _d_semicubical}



class ContactModel:
    def __init__(self, cls: str, data: Contacts):
        self.cls, self.d = cls, data
        self.names = CURVES[cls].param_names
        self.log = _LOG[cls]
        self.np = len(self.names)
        self.kern = KERNELS[cls]
        self.deriv = DERIVATIVES[cls]
        self.rows = data.rows()
        self._lay = None  # (touches, constant flat Jacobian, positions of jac's entries)

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
        cost = sum([v * v for v in r])  # (a list: the same sum, in the same order, without a generator)
        return r, (cost if math.isfinite(cost) else math.inf), (p, ct, st, fr)

    def jac(self, z, parts):
        """Jacobian (5n, m) of the residuals in closed form: shape columns from
        ``DERIVATIVES`` (∂/∂log p = p·∂/∂p for the positive parameters), pose columns, and
        one t column per touch (dp/dt = speed·(cos φ, sin φ), dφ/dt = κ·speed,
        dκ/dt = κ_s·speed, dκ_s/dt from ``DERIVATIVES``). Built in Python floats: at 3–5
        touches the same closed forms as NumPy arrays over every touch cost twice as much
        (NumPy's per-call cost outweighs the arithmetic). Only the entries that depend on z
        are computed, in the order of ``_layout``'s flat positions, and put into a copy of
        its constant Jacobian in one NumPy call."""
        p, ct, st, fr = parts
        n, o = len(fr), self.np
        flat, pos = self._layout(n)
        zl = z.tolist()
        th = zl[o]
        deriv = self.deriv
        scale = [v if lg else 1.0 for v, lg in zip(p, self.log)]
        out = []
        try:
            for t, (px, py, ph, kc, ksc, spd), row in zip(zl[o + 3:], fr, self.rows):
                sp, sf, w00, w01, w10, w11 = row[5:]
                d = deriv(p, t)
                for j, g in enumerate(scale):
                    dx, dy, df, dk, dks = d[5 * j: 5 * j + 5]
                    if g != 1.0:
                        dx, dy, df, dk, dks = g * dx, g * dy, g * df, g * dk, g * dks
                    out += ((ct * dx - st * dy) / sp, (st * dx + ct * dy) / sp, df / sf,
                            w00 * dk + w01 * dks, w10 * dk + w11 * dks)
                ang = ph + th
                e0, e1 = ksc * spd, d[-1]
                out += ((-st * px - ct * py) / sp, (ct * px - st * py) / sp, spd * math.cos(ang) / sp,
                        spd * math.sin(ang) / sp, kc * spd / sf, w00 * e0 + w01 * e1, w10 * e0 + w11 * e1)
        except _NUMERIC_ERRORS:
            return np.full((5 * n, o + 3 + n), math.nan)
        jac = flat.copy()
        jac[pos] = out
        return jac.reshape(5 * n, o + 3 + n)

    def _layout(self, n: int) -> tuple[np.ndarray, np.ndarray]:
        """The Jacobian of ``n`` touches (5n × m, m = shape + 3 + n) as a flat array holding
        its constant entries (1/σ_pos in the translation columns, 1/σ_φ in θ's φ row, zeros)
        and the flat positions of the entries ``jac`` computes, in its order: per touch,
        each shape column's x, y, φ, κ, κ_s rows, then θ's x and y rows and the touch's t
        column's x, y, φ, κ, κ_s rows (made once per model)."""
        if self._lay is None or self._lay[0] != n:
            o = self.np
            m = o + 3 + n
            flat = np.zeros(5 * n * m)
            pos = []
            for i, row in enumerate(self.rows[:n]):
                sp, sf = row[5], row[6]
                base = [5 * i * m + q * m for q in range(5)]  # the touch's x, y, φ, κ, κ_s rows
                flat[base[0] + o + 1] = 1.0 / sp
                flat[base[1] + o + 2] = 1.0 / sp
                flat[base[2] + o] = 1.0 / sf
                for j in range(o):
                    pos += [b + j for b in base]
                pos += [base[0] + o, base[1] + o] + [b + o + 3 + i for b in base]
            self._lay = (n, flat, np.array(pos, dtype=np.intp))
        return self._lay[1], self._lay[2]

    def solve(self, z0, max_iter=40, give_up=math.inf):
        """Levenberg–Marquardt from z0; stops early once the cost is negligible (exact data)
        or when after ``GIVE_UP_AFTER`` iterations it is still above ``give_up`` (hopeless class); not at all
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
            if cost < 1e-12 or (it >= GIVE_UP_AFTER and cost > give_up):
                break
            J = self.jac(z, parts)
            if not np.isfinite(J).all():
                break
            cn = np.sqrt(np.einsum("ij,ij->j", J, J))
            cn[cn == 0] = 1.0
            U, s, Vt = svd(J / cn)
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
