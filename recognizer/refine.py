"""Least-squares refinement over every sample of every touch, for one class at a time.

After the invariants give a class, its parameters, pose and a contact parameter t per
touch (paper Sects. 2–4), this fits the class's exact curve to all measurements at once:

unknowns   canonical parameters (positive ones as logarithms, so a > 0 holds), pose
           (θ, x, y) and one curve parameter t per sample;
residuals  per sample: (x − X(t))/σ_pos, (y − Y(t))/σ_pos and the wrapped tangent-angle
           difference (φ − Φ(t) − π·[touches run in decreasing t])/σ_φ; per contact-touch
           additionally (κ − κ(t))/σ_κ and (κ_s − κ_s(t))/σ_κs from its covariance.

Solved by MINPACK's Levenberg–Marquardt (``least_squares`` below, through
``scipy.optimize.leastsq``) with an analytic Jacobian: for t and the pose
(dX/dt = speed·(cos Φ, sin Φ), dΦ/dt = κ·speed) and for the ≤ 2 shape parameters
(``Curve.param_derivatives``; forward differences only where contact touches add κ, κ_s
rows). Gauge freedoms are removed: a circle's θ is held (its t's absorb a rotation); a
line's pose moves only across the line.

Weights: the request's (or options') NoiseModel; a zero σ is floored (``SIGMA_FLOOR_*``).
A samples touch with a ``noise_factor`` F (its samples' errors have covariance F·Fᵀ,
correlated: the jaw's samples come from one fit) is weighed by the pseudo-inverse of F
instead (generalized least squares: rank(F) whitened residuals for the touch's 3n raw
ones), after a first solve weighted per sample as a robust start.
Without a noise model σ_φ and σ_pos are estimated from the residuals (two rounds) and
the log-likelihood is the profile one, −2 ln L = Σ_groups n_g ln(RSS_g / n_g).

Each refined candidate carries ``chi2``, ``dof`` (observations − unknowns), ``n_obs``,
``loglik``, ``bic`` = −2 ln L + k·ln n (k every unknown: shape parameters, pose, t's;
recognizer.classify adds a likelihood-ratio test between nested classes),
``p_value`` (χ² upper tail), ``consistent`` (p ≥ alpha), ``uncertainty`` (standard
deviations of parameters and pose from (JᵀJ)⁻¹) and ``cov`` (the parameter covariance).
Canonical conventions hold on output (ellipse a ≥ b: axes swapped with θ += π/2).

Length (~500 lines, above the ~400 of the guide): one job, the fit over every sample; the
problem (packing with gauges, residuals, Jacobian, across/along weighting), the σ's
estimated from residuals and the candidate's statistics all read the same packing of
unknowns, and splitting them would spread that packing over modules.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import Any, Sequence

import numpy as np
from scipy import optimize, sparse, special

from recognizer.curves import CURVES, Pose, travel_direction
from recognizer.localize import SINGULAR, scaled_covariance
from recognizer.result import Candidate, shape_pose_vector
from tactile_common.angles import wrap_angle

SIGMA_FLOOR_PHI = 1e-9
"""rad: σ_φ used when the noise model says 0 (exact data)."""
SIGMA_FLOOR_POS = 1e-9
"""mm: σ_pos used when the noise model says 0."""
MAX_NFEV = 40
MAX_NFEV_EXACT, TOL_EXACT, EXACT_GO_ON, EXACT_DONE = 400, 1e-15, 1e4, 1e-10
"""exact data (every stated deviation zero: the σ floors) are fitted on to rounding when,
after MAX_NFEV evaluations, χ² per residual is below EXACT_GO_ON (a right class on the
way; a wrong one is ~1e6 and more): a short stretch of boundary or touches far out on an
arm (ill-conditioned fits) get there only after hundreds of steps. EXACT_DONE: χ² per
residual at rounding (a right class ends at 1e-13–1e-15). (The fit went on only above 1,
then above 1e-6: a semicubical on a nearly straight stretch stopped at χ² 1.4e-5 over 81
residuals with its a 1e-4 off; at 3.6, 9e-5 off.)"""
VALLEY_NFEV, VALLEY_STEPS, VALLEY_BELOW = 40, 30, 1.0
"""``_valley_search``: evaluations of each point's fit of the other unknowns, and points; it
runs when exact data's fit stops (at ``MAX_NFEV_EXACT``, or making no progress) with χ² per
residual between EXACT_DONE and VALLEY_BELOW (within the floors' noise: a right class on its
valley, 2 % off at 0.004–0.05; the semicubical's wrong branches stall at 25–60 and more)."""
FD_STEP = 1.5e-8
"""relative forward-difference step for the shape parameters' Jacobian columns (√ε) where
contact touches add κ, κ_s rows (samples alone: closed form, ``_Problem._shape_columns``)."""
TOL = 1e-10
"""least_squares' xtol, ftol, gtol: a relative χ² change of 1e-10 is far below any decision
(1e-12 ran most wrong-class fits to the evaluation cap for nothing)."""
RESIDUAL_CAP = 1e30
"""whitened residuals are capped at this (σ's) and Jacobian entries at JACOBIAN_CAP, so that
χ² = Σr², JᵀJ and Jᵀr cannot overflow (a wild start of a cubic class); exact data
(σ = 1e-9) puts a fair start at 1e8–1e12 σ, far below the cap."""
JACOBIAN_CAP = 1e120
SPARSE_UNKNOWNS = 200
"""above this many unknowns (shape, pose and every sample's t) refinement solves on the sparse
Jacobian and states the covariance by blocks (``least_squares``, ``_unknowns_cov``): a
20-touch × 15-sample request has 305. At and below it, the dense solve and pseudo-inverse
(bench_wide's and the standard bench's requests, 12 touches × 15 samples)."""
FACTOR_RCOND = 1e-6
"""a noise factor's singular values below this fraction of its largest are its null space (the
jaw's has its rank's smallest at ~2e-4; its null ones were ~1e-11 by central differences,
rounding since tactile_jaw.envelope states it in closed form)."""


def _across_along(x, y, c, s, ratio):
    """Position residuals (x, y)/σ_pos → (across the measured tangent)/σ_pos and (along
    it)/σ_along, ``c``, ``s`` the measured tangent's cosine and sine, ``ratio`` σ_pos/σ_along:
    the one per-sample weighting of positions (refinement weighs each sample across and
    along its tangent separately)."""
    return c * y - s * x, (c * x + s * y) * ratio


_POSITIVE = {"circle": ("r",), "ellipse": ("a", "b"), "parabola": ("a",), "hyperbola": ("a", "b"),
             "semicubical_parabola": ("a",)}


@dataclass
class RefinedCandidate(Candidate):
    """A Candidate after refinement: ``cov`` the covariance of the shape parameters (in
    ``param_names`` order), ``t_samples`` the fitted t of every sample per touch,
    ``sigma`` the σ_φ and σ_pos used, ``nfev`` the function evaluations, ``cov_pose`` the
    covariance of (shape parameters, θ, x, y) together (what recognizer.next_touch
    propagates to predicted touches)."""

    cov: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))
    cov_pose: np.ndarray | None = None
    t_samples: list = field(default_factory=list)
    sigma: dict = field(default_factory=dict)
    nfev: int = 0
    #: (problem, unknowns, their covariance, canonical permutation): what
    #: recognizer.intervals needs to profile the fit
    fit: tuple | None = field(default=None, repr=False, compare=False)


@dataclass
class _Data:
    """All measurements of a request, flattened (samples first, then contact touches)."""

    x: np.ndarray
    y: np.ndarray
    phi: np.ndarray
    touch_of: np.ndarray          # touch index of each sample row
    mid: list[int]                # row of each touch's contact sample
    contact_rows: list[int]       # rows that are contact-touches (κ, κ_s residuals)
    kappa: np.ndarray             # per contact row
    kappa_s: np.ndarray
    sig_kappa: np.ndarray
    sig_kappa_s: np.ndarray
    s_rel: np.ndarray             # arc length of each row from its touch's contact (0 for contacts)
    factors: list = field(default_factory=list)  # per samples-touch: (its rows, noise factor or None)


def _arrays(touch: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray | None]:
    g = (lambda k: getattr(touch, k, None)) if not isinstance(touch, dict) else touch.get
    s = g("s")
    return (np.unwrap(np.asarray(g("phi"), float)), np.asarray(g("x"), float), np.asarray(g("y"), float),
            None if s is None else np.asarray(s, float))


def _collect(touches: Sequence[Any]) -> _Data:
    xs, ys, ps, tof, mid, srel = [], [], [], [], [], []
    crows, ck, cks, sk, sks = [], [], [], [], []
    factors = []
    row = 0
    for i, tch in enumerate(touches):
        if hasattr(tch, "kappa"):  # a contact-touch
            xs.append([float(tch.x)])
            ys.append([float(tch.y)])
            ps.append([float(tch.phi)])
            tof.append([i])
            srel.append([0.0])
            mid.append(row)
            crows.append(row)
            ck.append(float(tch.kappa))
            cks.append(float(tch.kappa_s))
            cov = np.asarray(getattr(tch, "cov", np.zeros((2, 2))), float)
            sk.append(math.sqrt(max(cov[0, 0], 0.0)))
            sks.append(math.sqrt(max(cov[1, 1], 0.0)))
            row += 1
            continue
        phi, x, y, s = _arrays(tch)
        n = phi.size
        if s is None:
            s = np.concatenate(([0.0], np.cumsum(np.hypot(np.diff(x), np.diff(y)))))
        xs.append(x)
        ys.append(y)
        ps.append(phi)
        tof.append(np.full(n, i))
        srel.append(s - s[n // 2])
        mid.append(row + n // 2)
        factors.append((np.arange(row, row + n), getattr(tch, "noise_factor", None)))
        row += n
    return _Data(np.concatenate(xs), np.concatenate(ys), np.concatenate(ps), np.concatenate(tof).astype(int),
                 mid, crows, np.array(ck), np.array(cks), np.array(sk), np.array(sks), np.concatenate(srel),
                 factors)


class _Problem:
    """Packs unknowns, evaluates residuals and the Jacobian for one class."""

    def __init__(self, cls: str, data: _Data, pose: Pose, direction: int, sig_phi: float, sig_pos: float,
                 sig_along: float | None = None, factors: bool = False):
        self.cls = cls
        self.names = CURVES[cls].param_names
        self.pos_names = _POSITIVE.get(cls, ())
        self.data = data
        self.direction = direction
        self.sig_phi = sig_phi
        self.sig_pos = sig_pos
        # anisotropic positions: rows (x, y) become (across, along) the measured tangent
        self.aniso = sig_along is not None and sig_along != sig_pos
        if self.aniso:
            self._cos, self._sin = np.cos(data.phi), np.sin(data.phi)
            self._ratio = sig_pos / sig_along
        self.theta0 = pose.theta
        self.anchor = np.array([pose.x, pose.y])
        self.n_rows = data.x.size
        k = len(self.names)
        self.k = k
        # pose unknowns: circle (x, y); line (θ, d across the line); others (θ, x, y)
        self.n_pose = {"circle": 2, "line": 2}.get(cls, 3)
        self.n_glob = k + self.n_pose
        self.n_raw = 3 * self.n_rows + 2 * len(data.contact_rows)
        self.whiten = self._whitening(sig_phi, sig_pos, sig_along) if factors else None
        if self.whiten is not None:  # sample rows are whitened per touch from raw (mm, rad) residuals
            self.sig_phi = self.sig_pos = 1.0
            self.aniso = False
        self.n_res = self.n_raw if self.whiten is None else (
            sum(idx.size if w is None else w.shape[0] for idx, w in self.whiten) + 2 * len(data.contact_rows))
        self._memo: tuple[bytes, tuple] | None = None
        self._res_memo: tuple[bytes, np.ndarray] | None = None
        self._jac_memo: tuple[bytes, np.ndarray] | None = None
        self._t_flat: tuple | None = None
        self._const: np.ndarray | None = None

    def _whitening(self, sig_phi: float, sig_pos: float, sig_along: float | None) -> list:
        """Per samples-touch (raw rows of x, y, φ; W): W·r is that touch's residuals whitened,
        W the pseudo-inverse of its noise factor F (sample errors' covariance F·Fᵀ, rows x…,
        y…, φ…); W None for a touch without F: the noise model's per-sample weights
        (:func:`_across_along`, the σ's kept in ``_sample_sigmas``)."""
        n = self.n_rows
        self._sample_sigmas = (sig_phi, sig_pos, sig_pos / (sig_pos if sig_along is None else sig_along))
        out = []
        for rows, factor in self.data.factors:
            idx = np.concatenate([rows, n + rows, 2 * n + rows])
            w = None
            if factor is not None:
                f = np.asarray(factor, float)
                scale = np.sqrt(np.sum(f * f, axis=1))  # each row's own deviation
                scale = np.where(scale > 0.0, scale, 1.0)
                u, sv, _ = np.linalg.svd(f / scale[:, None], full_matrices=False)
                keep = sv > FACTOR_RCOND * sv[0]
                w = (u[:, keep] / sv[keep]).T / scale
            out.append((idx, w))
        return out

    def t_blocks(self) -> list[np.ndarray]:
        """The samples' t unknowns (numbered from 0) that share residual rows: each touch
        whitened by a noise factor (its samples' errors correlated); every other t enters
        only its own sample's rows."""
        if self.whiten is None:
            return []
        return [rows for rows, factor in self.data.factors if factor is not None]

    def _whitened(self, a: np.ndarray) -> np.ndarray:
        """Raw residuals (or Jacobian rows) → whitened: each touch's W·rows, contact rows kept."""
        if self.whiten is None:
            return a
        sig_phi, sig_pos, ratio = self._sample_sigmas
        parts = []
        for idx, w in self.whiten:
            if w is not None:
                parts.append(w @ a[idx])
                continue
            k = idx.size // 3
            c, s = self._tangent(idx[:k], a.ndim)
            parts += [*_across_along(a[idx[:k]] / sig_pos, a[idx[k : 2 * k]] / sig_pos, c, s, ratio),
                      a[idx[2 * k :]] / sig_phi]
        return np.concatenate(parts + [a[3 * self.n_rows :]])

    def _tangent(self, rows: np.ndarray, ndim: int) -> tuple[np.ndarray, np.ndarray]:
        """Cosine and sine of the measured tangent at ``rows``, shaped for residuals
        (``ndim`` 1) or Jacobian rows (2)."""
        c, s = np.cos(self.data.phi[rows]), np.sin(self.data.phi[rows])
        return (c, s) if ndim == 1 else (c[:, None], s[:, None])

    def _model_at(self, z: np.ndarray, key: bytes):
        """``unpack`` and ``_model`` at z (``key``: its bytes), memoized for the last z
        (least_squares asks for the Jacobian at the point whose residuals it just evaluated)."""
        if self._memo is None or self._memo[0] != key:
            params, pose, t = self.unpack(z.copy())
            self._memo = (key, (params, pose, t, *self._model(params, pose, t)))
        return self._memo[1]

    # -- packing ------------------------------------------------------------------------
    def pack(self, params: dict, pose: Pose, t: np.ndarray) -> np.ndarray:
        q = [math.log(params[n]) if n in self.pos_names else params[n] for n in self.names]
        if self.cls == "circle":
            g = [pose.x, pose.y]
        elif self.cls == "line":
            g = [pose.theta, 0.0]
        else:
            g = [pose.theta, pose.x, pose.y]
        return np.concatenate((q, g, t))

    def unpack(self, z: np.ndarray) -> tuple[dict, Pose, np.ndarray]:
        k = self.k
        g = z[: self.n_glob].tolist()  # Python floats: the same values as float(z[i]), read once
        params = {n: (math.exp(min(g[i], 700.0)) if n in self.pos_names else g[i])
                  for i, n in enumerate(self.names)}
        if self.cls == "circle":
            pose = Pose(self.theta0, g[k], g[k + 1])
        elif self.cls == "line":
            th, d = g[k], g[k + 1]
            pose = Pose(th, self.anchor[0] - d * math.sin(th), self.anchor[1] + d * math.cos(th))
        else:
            pose = Pose(g[k], g[k + 1], g[k + 2])
        return params, pose, z[self.n_glob :]

    # -- model -----------------------------------------------------------------------------
    def _model(self, params: dict, pose: Pose, t: np.ndarray):
        """The curve and its hand-frame x, y, φ (κ, κ_s at contact rows) at the unknowns
        (errstate: the caller's: ``residuals``, ``jacobian`` or ``least_squares``'s around a solve)."""
        curve = CURVES[self.cls](params)
        (px, py), tangent = curve.point_tangent(t)
        hx, hy = pose.apply(px, py)
        phi = np.asarray(tangent, float) + pose.theta + (np.pi if self.direction < 0 else 0.0)
        extra = None
        if self.data.contact_rows:
            tc = t[self.data.contact_rows]
            sign = 1.0 if self.direction > 0 else -1.0
            extra = (sign * np.asarray(curve.kappa(tc), float), np.asarray(curve.kappa_s(tc), float))
        return curve, np.asarray(hx, float), np.asarray(hy, float), phi, extra

    def residuals(self, z: np.ndarray) -> np.ndarray:
        """The whitened residuals at z (``_residuals`` under ``np.errstate(all="ignore")``)."""
        with np.errstate(all="ignore"):
            return self._residuals(z)

    def _residuals(self, z: np.ndarray) -> np.ndarray:
        """The whitened residuals at z under the caller's errstate (``least_squares`` enters one
        for its whole solve, not one per evaluation), memoized for the last z (leastsq
        evaluates its start twice, once to check shapes): a fresh array each call."""
        key = z.tobytes()
        if self._res_memo is not None and self._res_memo[0] == key:
            return self._res_memo[1].copy()
        d = self.data
        _, _, _, _, hx, hy, phi, extra = self._model_at(z, key)
        parts = [(d.x - hx) / self.sig_pos, (d.y - hy) / self.sig_pos, wrap_angle(d.phi - phi) / self.sig_phi]
        if extra is not None:
            parts += [(d.kappa - extra[0]) / d.sig_kappa, (d.kappa_s - extra[1]) / d.sig_kappa_s]
        r = self._whitened(np.concatenate(parts))
        if self.aniso:
            self._across_along(r)
        if not _within(r, RESIDUAL_CAP):
            bad = ~np.isfinite(r)  # (in place on the fresh array: as np.where(finite, clip, 1e8))
            r.clip(-RESIDUAL_CAP, RESIDUAL_CAP, out=r)
            if bad.any():
                r[bad] = 1e8
        self._res_memo = (key, r.copy())
        return r

    def _across_along(self, a: np.ndarray) -> None:
        """In place: position rows (x, y)/σ_pos of residuals or Jacobian → (across the
        measured tangent)/σ_pos and (along it)/σ_along (:func:`_across_along`)."""
        n = self.n_rows
        c, s = (self._cos, self._sin) if a.ndim == 1 else (self._cos[:, None], self._sin[:, None])
        a[:n], a[n : 2 * n] = _across_along(a[:n].copy(), a[n : 2 * n].copy(), c, s, self._ratio)

    def jacobian(self, z: np.ndarray) -> np.ndarray:
        """The Jacobian at z (``_jacobian_at`` under ``np.errstate(all="ignore")``)."""
        with np.errstate(all="ignore"):
            return self._jacobian_at(z)

    def _jacobian_at(self, z: np.ndarray) -> np.ndarray:
        """The Jacobian at z under the caller's errstate (as ``_residuals``), memoized for the
        last z (MINPACK asks for it at the start that ``least_squares`` checked, and
        refine_one at the solution): a fresh array each call."""
        key = z.tobytes()
        if self._jac_memo is not None and self._jac_memo[0] == key:
            return self._jac_memo[1].copy()
        jac = self._jacobian(z, key)
        self._jac_memo = (key, jac.copy())
        return jac

    def _jacobian(self, z: np.ndarray, key: bytes) -> np.ndarray:
        _, pose, t, curve, hx, hy, phi, _ = self._model_at(z, key)
        n = self.n_rows
        nc = len(self.data.contact_rows)
        rows = 3 * n + 2 * nc
        jac = self._constant_jacobian(rows, z.size)  # raw rows (whitened at the end)
        speed, kap = (np.asarray(v, float) for v in curve.speed_kappa(t))
        ang = phi - (np.pi if self.direction < 0 else 0.0)
        flat = jac.reshape(-1)  # each sample's t column: one entry in each of its x, y, φ rows
        fx, fy, fphi = self._t_entries(z.size)
        neg = -speed
        np.divide(neg * np.cos(ang), self.sig_pos, out=flat[fx])
        np.divide(neg * np.sin(ang), self.sig_pos, out=flat[fy])
        np.divide(-kap * speed, self.sig_phi, out=flat[fphi])
        k = self.k
        # pose columns (their constant entries: ``_constant_jacobian``)
        if self.cls == "line":
            th = pose.theta
            # (x, y) = anchor + d·(−sin θ, cos θ): ∂/∂θ includes the anchor's rotation term
            dpx = -(hy - pose.y) - z[k + 1] * math.cos(th)
            dpy = hx - pose.x - z[k + 1] * math.sin(th)
            jac[:n, k] = -dpx / self.sig_pos
            jac[n : 2 * n, k] = -dpy / self.sig_pos
            jac[:n, k + 1] = math.sin(th) / self.sig_pos
            jac[n : 2 * n, k + 1] = -math.cos(th) / self.sig_pos
        elif self.cls != "circle":
            np.divide(hy - pose.y, self.sig_pos, out=jac[:n, k])  # −(−(hy − y))/σ: the sign of −dx_th/σ
            np.divide(-(hx - pose.x), self.sig_pos, out=jac[n : 2 * n, k])
        if nc:
            # shape parameters: forward differences from the memoized model (step √ε·max(|z|, 1))
            # (the κ, κ_s rows of contact touches); contact rows' t: central differences
            base = self._raw_from(hx, hy, phi, self._memo[1][7])
            for i in range(k):
                h = FD_STEP * max(abs(z[i]), 1.0)
                zp = z.copy()
                zp[i] += h
                h = zp[i] - z[i]
                jac[:, i] = (self._raw(zp) - base) / h
        else:
            self._shape_columns(jac, z, curve, pose, t)
        if nc:
            for j, r in enumerate(self.data.contact_rows):
                c = self.n_glob + r
                h = 1e-7 * max(abs(z[c]), 1.0)
                zp, zm = z.copy(), z.copy()
                zp[c] += h
                zm[c] -= h
                jac[3 * n :, c] = ((self._raw(zp) - self._raw(zm)) / (2 * h))[3 * n :]
        if self.whiten is None and not self.aniso and _within(jac, JACOBIAN_CAP):
            return jac  # every entry finite and inside the cap: the steps below change nothing
        bad = ~np.isfinite(jac)
        if bad.any():
            jac[bad] = 0.0
        jac = self._whitened(jac)
        if self.aniso:
            self._across_along(jac)
        return jac.clip(-JACOBIAN_CAP, JACOBIAN_CAP, out=jac)

    def _constant_jacobian(self, rows: int, m: int) -> np.ndarray:
        """A fresh raw Jacobian of ``rows`` × ``m`` holding the entries that do not depend on
        the unknowns (the pose's translation columns and θ's φ rows, −1/σ; zeros elsewhere),
        copied from one made once per problem."""
        if self._const is None or self._const.shape != (rows, m):
            n, k = self.n_rows, self.k
            jac = np.zeros((rows, m))
            if self.cls == "circle":
                jac[:n, k] = -1.0 / self.sig_pos
                jac[n : 2 * n, k + 1] = -1.0 / self.sig_pos
            elif self.cls == "line":
                jac[2 * n : 3 * n, k] = -1.0 / self.sig_phi
            else:
                jac[2 * n : 3 * n, k] = -1.0 / self.sig_phi
                jac[:n, k + 1] = -1.0 / self.sig_pos
                jac[n : 2 * n, k + 2] = -1.0 / self.sig_pos
            self._const = jac
        return self._const.copy()

    def _shape_columns(self, jac: np.ndarray, z: np.ndarray, curve, pose: Pose, t: np.ndarray) -> None:
        """The shape parameters' raw columns in closed form (``Curve.param_derivatives``,
        turned into the hand frame; a log parameter's column times the parameter): the forward
        differences they replace cost two model evaluations per Jacobian, half of the
        refinement's time in its Jacobian. A log parameter at the ``unpack`` clamp (z ≥ 700)
        moves nothing: its column is zero, as a difference there was."""
        n = self.n_rows
        c, s = math.cos(pose.theta), math.sin(pose.theta)
        for i, (dx, dy, dphi) in enumerate(curve.param_derivatives(t)):  # (errstate: the caller's)
            name = self.names[i]
            if name in self.pos_names:
                if not z[i] < 700.0:
                    continue
                scale = curve.params[name]
            else:
                scale = 1.0
            f = -scale / self.sig_pos
            np.multiply(c * dx - s * dy, f, out=jac[:n, i])
            np.multiply(s * dx + c * dy, f, out=jac[n : 2 * n, i])
            np.multiply(dphi, -scale / self.sig_phi, out=jac[2 * n : 3 * n, i])

    def _t_entries(self, m: int) -> tuple[slice, slice, slice]:
        """Flat positions, in the raw Jacobian of ``m`` columns, of each sample's t entry in its
        x, y and φ rows: sample i's t is column n_glob + i of rows i, n + i and 2n + i, so each
        set lies on a diagonal, a strided slice of the flat array (computed once per problem)."""
        if self._t_flat is None or self._t_flat[0] != m:
            n, step = self.n_rows, m + 1
            first = [r * m + self.n_glob for r in (0, n, 2 * n)]
            self._t_flat = (m, tuple(slice(f, f + (n - 1) * step + 1, step) for f in first))
        return self._t_flat[1]

    def _raw(self, z: np.ndarray) -> np.ndarray:
        """Residuals without the angle wrap's discontinuity (for differences)."""
        params, pose, t = self.unpack(z)
        _, hx, hy, phi, extra = self._model(params, pose, t)
        return self._raw_from(hx, hy, phi, extra)

    def _raw_from(self, hx: np.ndarray, hy: np.ndarray, phi: np.ndarray, extra) -> np.ndarray:
        d = self.data
        n = self.n_rows
        r = np.empty(self.n_raw)
        np.subtract(d.x, hx, out=r[:n])
        np.subtract(d.y, hy, out=r[n : 2 * n])
        r[: 2 * n] *= 1.0 / self.sig_pos
        np.subtract(d.phi, phi, out=r[2 * n : 3 * n])
        r[2 * n : 3 * n] *= 1.0 / self.sig_phi
        if extra is not None:
            r[3 * n :] = np.concatenate(((d.kappa - extra[0]) / d.sig_kappa, (d.kappa_s - extra[1]) / d.sig_kappa_s))
        bad = ~np.isfinite(r)
        if bad.any():
            r[bad] = 0.0
        return r


def _within(a: np.ndarray, cap: float) -> bool:
    """Every entry of ``a`` finite and of magnitude below ``cap`` (so capping and the
    non-finite replacement would leave it as it is), decided by one sum of squares: NaN or
    ±inf makes it so, and below (cap/10)² no entry reaches the cap; a larger sum
    (or an overflow: under the caller's errstate) answers False and the caller checks
    entry by entry."""
    v = a.reshape(-1)
    return bool(v @ v < (0.1 * cap) ** 2)


def _initial_t(cls: str, params: dict, pose: Pose, t_contacts: np.ndarray, data: _Data, direction: int) -> np.ndarray:
    """Every sample's t: its contact's t moved by its arc length (on the contact's branch of
    a semicubical's cusp, else the contact's t), then projected onto the curve
    (``Curve.project``, 8 steps)."""
    curve = CURVES[cls](params)
    tc = np.asarray(t_contacts, float)[data.touch_of]
    with np.errstate(all="ignore"):
        sp = np.asarray(curve.speed(tc), float)
        t = tc + direction * data.s_rel / np.where(sp > 1e-12, sp, np.inf)
    t = curve.keep_branch(tc, np.where(np.isfinite(t), t, tc))
    return _in_order(curve.project(t, *pose.inverse(data.x, data.y), steps=8), data, direction)


def _in_order(t: np.ndarray, data: _Data, direction: int) -> np.ndarray:
    """Each touch's sample t's kept in the order of their arc lengths from its contact:
    going out from the contact, a sample's t may not fall back past its neighbour's.
    Projected one by one, the samples next to a semicubical's cusp can cross (tools.bench_wide
    seed 9, semicubical trial 31, a touch at the cusp's clearance: t 0.44, 0.27, 0.72, …
    from a fair fit), and the solve does not uncross them (χ² 29397; the truth's 86)."""
    t = t.copy()
    u = direction * data.s_rel  # t grows with u along the curve
    for k, row in enumerate(data.mid):
        rows = np.flatnonzero(data.touch_of == k)
        rows = rows[np.argsort(u[rows])]  # along the curve
        out, back = rows[u[rows] > 0], rows[u[rows] < 0][::-1]  # each going out from the contact
        t[out] = np.maximum.accumulate(np.concatenate(([t[row]], t[out])))[1:]
        t[back] = np.minimum.accumulate(np.concatenate(([t[row]], t[back])))[1:]
    return t


def _valley_search(problem: _Problem, z: np.ndarray) -> tuple[np.ndarray, int]:
    """Exact data whose fit still crawls at ``MAX_NFEV_EXACT``: the minimum along its valley,
    as a 1-D search (Brent) over the shape unknown the valley moves most (the weakest
    direction of the column-scaled Jacobian), every other unknown fitted at each point
    (``VALLEY_NFEV`` evaluations from the best point yet, moved along the linearized
    valley). A semicubical touched on a nearly straight stretch (|b| ≳ 20·|a·t|, its tangent
    turning by 0.3–3 mrad) fits its exact samples within 1e-10 of a unit for a and b 2 %
    off along a bending valley (the Jacobian's smallest scaled singular value ~1e-8 of its
    largest) that Levenberg–Marquardt follows a few 1e-4 per hundred steps; at each fixed b
    the rest is well conditioned (1e-6) and converges in ~15 evaluations, and the profile
    χ² is a parabola in b, so the search ends in ~10 points. Returns (z, evaluations)."""
    k = problem.k
    jac = problem.jacobian(z)
    norms = np.linalg.norm(jac, axis=0)
    norms = np.where((norms > 0) & np.isfinite(norms), norms, 1.0)
    try:
        _, sv, vt = np.linalg.svd(jac / norms, full_matrices=False)
    except np.linalg.LinAlgError:
        return z, 0
    i = int(np.argmax(np.abs(vt[-1, :k])))
    cov = _pinv_cov(jac)
    if not (cov[i, i] > 0 and np.isfinite(cov[i, i])):
        return z, 0
    lin = np.nan_to_num(cov[:, i] / cov[i, i], nan=0.0, posinf=0.0, neginf=0.0)
    free = np.ones(z.size, bool)
    free[i] = False
    best = {"chi2": float(problem.residuals(z) @ problem.residuals(z)), "z": z.copy()}
    used = [0]

    def profile(v: float) -> float:
        start = best["z"] + lin * (v - best["z"][i])
        start[i] = v
        zf, res = fit_held(problem, start, free, VALLEY_NFEV, TOL_EXACT)
        used[0] += int(res.nfev)
        chi2 = 2.0 * float(res.cost)
        if chi2 < best["chi2"]:
            best.update(chi2=chi2, z=zf.copy())
        return chi2

    h = math.sqrt(cov[i, i] * max(best["chi2"], 1e-30))
    with np.errstate(all="ignore"):
        try:
            optimize.minimize_scalar(profile, bracket=(z[i], z[i] + h), method="brent",
                                     options={"xtol": 1e-12, "maxiter": VALLEY_STEPS})
        except (ValueError, RuntimeError, FloatingPointError):
            pass
    return best["z"], used[0]


def _sigmas(noise: Any) -> tuple[float | None, float | None]:
    if noise is None:
        return None, None
    return (max(float(getattr(noise, "phi", 0.0) or 0.0), SIGMA_FLOOR_PHI),
            max(float(getattr(noise, "pos", 0.0) or 0.0), SIGMA_FLOOR_POS))


def _canonical(cls: str, params: dict, pose: Pose, t: np.ndarray) -> tuple[dict, Pose, np.ndarray, list[int]]:
    """Canonical conventions: ellipse a ≥ b. Returns the permutation of parameters."""
    if cls == "ellipse" and params["b"] > params["a"]:
        params = {"a": params["b"], "b": params["a"]}
        pose = Pose(float(wrap_angle(np.array(pose.theta + np.pi / 2))), pose.x, pose.y)
        return params, pose, t - np.pi / 2, [1, 0]
    if cls in ("circle", "ellipse"):
        pose = Pose(float(wrap_angle(np.array(pose.theta))), pose.x, pose.y)
    return params, pose, t, list(range(len(params)))


def _residual_sigmas(problem: _Problem, z: np.ndarray, scale: float) -> tuple[float, float]:
    """σ_pos and σ_φ from the residuals at z, each group's sum of squares divided by its
    residual degrees of freedom n_g − Σ_g hᵢ (hᵢ the leverages, diagonal of J(JᵀJ)⁺Jᵀ):
    every sample's own t absorbs part of its noise, so RSS/n would underestimate σ
    (σ_φ by 2–10× on short touches, the Neyman–Scott bias)."""
    r = problem.residuals(z)
    n = problem.n_rows
    u, sv, _ = np.linalg.svd(problem.jacobian(z), full_matrices=False)
    h = (u[:, sv > 1e-10 * sv[0]] ** 2).sum(axis=1) if sv.size and sv[0] > 0 else np.zeros(r.size)
    dof_pos = max(2 * n - float(h[: 2 * n].sum()), 1.0)
    dof_phi = max(n - float(h[2 * n : 3 * n].sum()), 1.0)
    rp = r[: 2 * n] * problem.sig_pos
    rf = r[2 * n : 3 * n] * problem.sig_phi
    return (max(math.sqrt(float(rp @ rp) / dof_pos), SIGMA_FLOOR_POS * scale),
            max(math.sqrt(float(rf @ rf) / dof_phi), SIGMA_FLOOR_PHI))


def _shape_pose_cov(problem: _Problem, cls: str, z: np.ndarray, cov_z: np.ndarray) -> np.ndarray:
    """Covariance of the canonical (shape parameters, θ, x, y) from the unknowns' covariance:
    T·C·Tᵀ with T the forward-difference Jacobian of that vector in the shape and pose
    unknowns (log parameters, the circle's and line's gauges, the ellipse's axis swap)."""
    ng = problem.n_glob

    def vec(zz: np.ndarray) -> np.ndarray:
        params, pose, t = problem.unpack(zz)
        params, pose, _, _ = _canonical(cls, params, pose, t)
        return shape_pose_vector(cls, params, pose)

    v0 = vec(z)
    T = np.zeros((v0.size, ng))
    for i in range(ng):
        h = 1e-7 * max(abs(z[i]), 1.0)
        zp = z.copy()
        zp[i] += h
        d = vec(zp) - v0
        d[-3] = wrap_angle(d[-3])
        T[:, i] = d / h
    c = cov_z[:ng, :ng]
    lost = ~np.isfinite(np.diag(c))  # undetermined unknowns: so is every output they move
    with np.errstate(over="ignore", invalid="ignore"):
        out = T @ np.where(np.isfinite(c), c, 0.0) @ T.T
    return _lost(out, (T[:, lost] != 0).any(axis=1)) if lost.any() else out


@dataclass
class _Solved:
    """What the refinement reads of a solve: the solution, ½χ², the residuals there, the
    function evaluations."""

    x: np.ndarray
    cost: float
    fun: np.ndarray
    nfev: int


def fit_held(problem, z: np.ndarray, free: np.ndarray, max_nfev: int, tol: float) -> tuple[np.ndarray, "_Solved"]:
    """``problem``'s unknowns ``free`` refitted from ``z``, the others held at their values in
    ``z`` (a point of a profile): (every unknown at the fit, the solve)."""
    zf = z.copy()

    def fun(v):
        zf[free] = v
        return problem.residuals(zf)

    def jac(v):
        zf[free] = v
        return problem.jacobian(zf)[:, free]

    res = least_squares(fun, jac, z[free], problem.n_res, max_nfev, tol)
    zf[free] = res.x
    return zf, res


def least_squares(fun, jac, z0: np.ndarray, n_res: int, max_nfev: int, tol: float):
    """The refinement's solve: MINPACK's Levenberg–Marquardt (lmder, Jacobian-scaled) on the
    dense Jacobian, through ``scipy.optimize.leastsq`` — the same routine and arguments as
    ``scipy.optimize.least_squares(method="lm", x_scale="jac")``, so the same iterates, without
    that wrapper's per-evaluation bookkeeping and its two extra Jacobians (at the start and the
    solution); trust-region reflective where unknowns outnumber residuals; above
    ``SPARSE_UNKNOWNS`` unknowns the trust-region reflective method on the Jacobian as a
    sparse matrix with LSMR steps (each sample's t enters 3 of the residuals: O(m·n) per
    step where the dense factorization takes O(m·n²)). Below that the block structure is
    no lever: at a 3-touch request's 81 × 32, MINPACK's dense QR and step take ~110 µs an
    iteration (~11 % of a recognition), and a Schur-complement step over the t's in NumPy
    cost as much and ended its 40 evaluations at a higher χ² (docs/benchmarks.md, session 24).
    The whole solve runs under ``np.errstate(all="ignore")``, ``fun`` and ``jac`` included
    (``_Problem._residuals`` and ``_jacobian_at``: one context a solve, not two an iteration)."""
    with np.errstate(all="ignore"):
        return _solve(fun, jac, z0, n_res, max_nfev, tol)


def _solve(fun, jac, z0: np.ndarray, n_res: int, max_nfev: int, tol: float):
    """``least_squares`` under the caller's errstate."""
    kw = dict(x_scale="jac", max_nfev=max_nfev, xtol=tol, ftol=tol, gtol=tol)
    if z0.size > SPARSE_UNKNOWNS:
        return optimize.least_squares(fun, z0, jac=lambda z: sparse.csr_matrix(jac(z)), method="trf",
                                      tr_solver="lsmr", **kw)
    if n_res < z0.size:
        return optimize.least_squares(fun, z0, jac=jac, method="trf", **kw)
    # full_output for nfev and fvec; leastsq also forms its covariance (unused: ``_pinv_cov``),
    # which overflows on a badly scaled fit (under ``least_squares``'s errstate: no RuntimeWarning
    # on the user's stderr)
    padded_fun, padded_jac = _pad_last_column(fun, jac)
    x, _, info, _, _ = optimize.leastsq(padded_fun, np.append(z0, 0.0), Dfun=padded_jac, full_output=True,
                                        ftol=tol, xtol=tol, gtol=tol, maxfev=max_nfev, factor=100.0, diag=None)
    f = info["fvec"][:-1]
    return _Solved(x[:-1], 0.5 * float(np.dot(f, f)), f, int(info["nfev"]))


#: the padding unknown's Jacobian entry (``_pad_last_column``): below any column norm a
#: whitened Jacobian has, so column pivoting leaves it last
PAD_COLUMN = 1e-300


def _pad_last_column(fun, jac):
    """``fun`` and ``jac`` with one more unknown and one more residual, always 0, whose
    Jacobian column is ``PAD_COLUMN`` in the new row alone. SciPy's C MINPACK (1.15 to at
    least 1.17.1) recomputes a column's norm in ``qrfac`` over one row too many: for the
    last column it reads one double past the end of the Jacobian's memory, so the same
    problem gave different iterates run to run (docs/estimation.md "Repeatable
    refinements"). With the padding column last, that read stays inside the array and
    reads the padding's 0; the padding is orthogonal to every other column and its
    residual is 0, so its step is 0 and the other unknowns' iterates are those of the
    unpadded problem without the stray read."""
    def padded_fun(z: np.ndarray) -> np.ndarray:
        r = fun(z[:-1])
        out = np.empty(r.size + 1)
        out[:-1] = r
        out[-1] = 0.0
        return out

    def padded_jac(z: np.ndarray) -> np.ndarray:
        j = jac(z[:-1])
        out = np.zeros((j.shape[0] + 1, j.shape[1] + 1))
        out[:-1, :-1] = j
        out[-1, -1] = PAD_COLUMN
        return out

    return padded_fun, padded_jac


def _pinv_cov(jac: np.ndarray) -> np.ndarray:
    """(JᵀJ)⁻¹ of every unknown by the contact stage's rule (``localize.scaled_covariance``):
    J's columns scaled to unit norm, no singular value dropped; a direction the data do not
    determine (a scaled singular value below ``SINGULAR`` of the largest, or a zero column)
    gives every unknown it moves infinite variance, never zero (the pseudo-inverse dropped
    singular values below 1e-10 and gave such a direction none)."""
    with np.errstate(over="ignore", invalid="ignore"):
        return scaled_covariance(jac)


def _lost(cov: np.ndarray, lost: np.ndarray) -> np.ndarray:
    """``cov`` with the unknowns ``lost`` (moved by an undetermined direction) undetermined:
    their variances ∞, their covariances NaN (``localize.scaled_covariance``'s marking)."""
    cov[lost, :] = np.nan
    cov[:, lost] = np.nan
    cov[lost, lost] = np.inf
    return cov


def _unknowns_cov(problem: _Problem, jac: np.ndarray) -> np.ndarray:
    """(JᵀJ)⁻¹ of every unknown, by blocks: J's columns scaled to unit norm, the globals g
    (shape, pose) and the samples' t. Each t enters only its own sample's residuals (its
    touch's, when the touch is whitened by a noise factor), so D = J_tᵀJ_t is block
    diagonal and the Schur complement S = A − B·D⁻¹·Bᵀ (A = J_gᵀJ_g, B = J_gᵀJ_t) gives
    C_gg = S⁻¹, C_gt = −S⁻¹·B·D⁻¹, C_tt = D⁻¹ + D⁻¹·Bᵀ·S⁻¹·B·D⁻¹: O(m·n) operations (and the
    n × n result) where the SVD of the whole m × n Jacobian takes O(m·n²) (a 20-touch ×
    15-sample request: 300 t's). S⁻¹ comes from the SVD of the globals' columns projected
    off the t's, (I − J_t·D⁻¹·J_tᵀ)·J_g (no cancellation). The rule of ``_pinv_cov``: no
    singular value dropped; a direction below ``SINGULAR`` (of S, of a block of D, a zero
    t column) makes every unknown it moves undetermined (``_lost``), never zero."""
    with np.errstate(over="ignore"):  # a column beyond 1e154 (a diverged wrong class): left unscaled
        norms = np.linalg.norm(jac, axis=0)
    norms = np.where((norms > 0) & np.isfinite(norms), norms, 1.0)
    jn = jac / norms
    ng, nt = problem.n_glob, jac.shape[1] - problem.n_glob
    jg, jt = jn[:, :ng], jn[:, ng:]
    d_inv = np.zeros((nt, nt))
    lost_t = np.zeros(nt, bool)
    single = np.ones(nt, bool)
    for block in problem.t_blocks():
        single[block] = False
        w, v = np.linalg.eigh(jt[:, block].T @ jt[:, block])
        zero = ~(w > SINGULAR**2 * max(w[-1], 0.0)) if w.size and w[-1] > 0 else np.ones(w.size, bool)
        d_inv[np.ix_(block, block)] = (v[:, ~zero] / w[~zero]) @ v[:, ~zero].T
        lost_t[block] = (np.abs(v[:, zero]) > 1e-8).any(axis=1)
    j = np.flatnonzero(single)
    dd = np.einsum("ij,ij->j", jt[:, j], jt[:, j])
    gone = ~(dd > SINGULAR**2)  # unit-scaled columns: a t that no residual sees
    d_inv[j, j] = np.where(gone, 0.0, 1.0 / np.where(gone, 1.0, dd))
    lost_t[j[gone]] = True
    b = jg.T @ jt
    e = b @ d_inv
    # S = J_gᵀ(I − P_t)J_g from the projected columns themselves (no cancellation in A − B·D⁺·Bᵀ)
    _, sv, vt = np.linalg.svd(jg - jt @ e.T, full_matrices=False)
    if sv.size < ng:  # fewer residuals than globals: the missing directions are undetermined
        sv = np.concatenate((sv, np.zeros(ng - sv.size)))
        vt = np.vstack((vt, np.linalg.svd(np.eye(ng) - vt.T @ vt)[2][: ng - vt.shape[0]]))
    zero = ~(sv > SINGULAR * sv[0]) if sv.size and sv[0] > 0 else np.ones(sv.size, bool)
    s_inv = (vt[~zero].T / sv[~zero] ** 2) @ vt[~zero]
    se = s_inv @ e
    cov = np.block([[s_inv, -se], [-se.T, d_inv + e.T @ se]])
    # an undetermined global direction v moves the t's by −eᵀv along with it
    null_g = vt[zero]
    lost = np.concatenate(((np.abs(null_g) > 1e-8).any(axis=0), lost_t | (np.abs(null_g @ e) > 1e-8).any(axis=0)))
    with np.errstate(over="ignore", invalid="ignore"):
        return _lost(cov, lost) / np.outer(norms, norms)


def refine_one(candidate: Candidate, touches: Sequence[Any], noise: Any = None, alpha: float = 1e-3,
               data: _Data | None = None) -> RefinedCandidate:
    """Refine one candidate over every sample of ``touches`` (see module docstring);
    ``data``: the touches already flattened (``_collect``; refine_candidates does it once)."""
    cls = candidate.cls
    data = _collect(touches) if data is None else data
    params = {k: float(v) for k, v in candidate.params.items()}
    for name in _POSITIVE.get(cls, ()):
        params[name] = max(params.get(name, 1.0), 1e-9)
    t_contacts = np.asarray(candidate.t, float)
    direction = travel_direction(CURVES[cls](params), candidate.pose, t_contacts, data.phi[data.mid])
    t0 = _initial_t(cls, params, candidate.pose, t_contacts, data, direction)
    sig_phi, sig_pos = _sigmas(noise)
    known = sig_phi is not None
    exact = known and not (getattr(noise, "phi", 0.0) or getattr(noise, "pos", 0.0) or getattr(noise, "pos_along", 0.0))
    pos_along = getattr(noise, "pos_along", None) if known else None
    sig_along = None if pos_along is None else max(float(pos_along), SIGMA_FLOOR_POS)
    scale = max(float(np.ptp(data.x)), float(np.ptp(data.y)), 1.0)
    if not known:
        sig_phi, sig_pos = 1e-3, 1e-3 * scale
    for c in range(data.sig_kappa.size):  # contact touches: exact data gets a floor
        data.sig_kappa[c] = max(data.sig_kappa[c], 1e-9 * (abs(data.kappa[c]) + 1e-6))
        data.sig_kappa_s[c] = max(data.sig_kappa_s[c], 1e-9 * (abs(data.kappa_s[c]) + 1e-9))
    z = None
    nfev = 0
    res = None
    problem = None
    for _round in range(1 if known else 3):
        problem = _Problem(cls, data, candidate.pose, direction, sig_phi, sig_pos, sig_along)
        z0 = problem.pack(params, candidate.pose, t0) if z is None else z
        res = least_squares(problem._residuals, problem._jacobian_at, z0, problem.n_res, MAX_NFEV, TOL)
        nfev += int(res.nfev)
        z = res.x
        if known and any(f is not None for _, f in data.factors):
            # touches that state their samples' error covariance: from the per-sample weighted
            # optimum (a robust start), the fit in their own metric
            problem = _Problem(cls, data, candidate.pose, direction, sig_phi, sig_pos, sig_along, factors=True)
            res = least_squares(problem._residuals, problem._jacobian_at, z, problem.n_res, MAX_NFEV, TOL)
            nfev += int(res.nfev)
            z = res.x
        if exact and 2.0 * res.cost < EXACT_GO_ON * res.fun.size:  # a right class, not yet there
            res = least_squares(problem._residuals, problem._jacobian_at, z, problem.n_res, MAX_NFEV_EXACT, TOL_EXACT)
            nfev += int(res.nfev)
            z = res.x
            if problem.k and EXACT_DONE * res.fun.size < 2.0 * res.cost < VALLEY_BELOW * res.fun.size:
                # stopped short of rounding within the floors' noise: along its valley
                z, used = _valley_search(problem, z)
                nfev += used
        if not known:
            sig_pos, sig_phi = _residual_sigmas(problem, z, scale)
    assert problem is not None and res is not None and z is not None
    params_f, pose_f, t_f = problem.unpack(z)
    r = problem.residuals(z)
    n_obs = r.size
    n_unknown = z.size
    dof = max(n_obs - n_unknown, 0)
    chi2 = float(r @ r)
    if known:
        loglik = -0.5 * chi2
    else:
        n = problem.n_rows
        rp = r[: 2 * n] * problem.sig_pos
        rf = r[2 * n : 3 * n] * problem.sig_phi
        loglik = -0.5 * (2 * n * math.log(max(float(rp @ rp) / (2 * n), (SIGMA_FLOOR_POS * scale) ** 2))
                         + n * math.log(max(float(rf @ rf) / n, SIGMA_FLOOR_PHI**2)))
    bic = -2.0 * loglik + n_unknown * math.log(max(n_obs, 2))
    p_value = float(special.chdtrc(dof, chi2)) if dof > 0 else 1.0  # the χ² upper tail (stats.chi2.sf's own, 50× cheaper)
    # covariance of the unknowns, then the shape parameters and pose in their own units
    jac = problem.jacobian(z)
    cov_z = _unknowns_cov(problem, jac) if z.size > SPARSE_UNKNOWNS else _pinv_cov(jac)
    k = problem.k
    dq = np.array([params_f[nm] if nm in problem.pos_names else 1.0 for nm in problem.names])
    with np.errstate(over="ignore", invalid="ignore"):  # a degenerate fit's covariance may overflow;
        cov_p = cov_z[:k, :k] * np.outer(dq, dq)  # non-finite values reach JSON as null
    params_c, pose_c, t_c, perm = _canonical(cls, params_f, pose_f, t_f)
    cov_p = cov_p[np.ix_(perm, perm)]
    names_c = CURVES[cls].param_names
    unc = {nm: float(math.sqrt(max(cov_p[i, i], 0.0))) for i, nm in enumerate(names_c)}
    pose_unc = np.sqrt(np.clip(np.diag(cov_z)[k : k + problem.n_pose], 0.0, None))
    pose_keys = {"circle": ("x", "y"), "line": ("theta", "offset")}.get(cls, ("theta", "x", "y"))
    unc.update({f"pose_{key}": float(v) for key, v in zip(pose_keys, pose_unc)})
    t_touch = t_c[data.mid]
    t_samples = [t_c[data.touch_of == i] for i in range(len(data.mid))]
    finite = all(np.isfinite(v) for v in params_c.values()) and np.all(np.isfinite(t_c)) and \
        np.isfinite(chi2) and all(np.isfinite([pose_c.theta, pose_c.x, pose_c.y]))
    base = replace(candidate) if not isinstance(candidate, RefinedCandidate) else candidate
    fields = {f: getattr(base, f) for f in Candidate.__dataclass_fields__}
    if not finite:
        fields.update(chi2=math.inf, loglik=-math.inf, bic=math.inf, p_value=0.0, consistent=False,
                      reason=f"{cls}: refinement diverged")
        return RefinedCandidate(**fields, cov=np.zeros((k, k)), sigma={"phi": sig_phi, "pos": sig_pos}, nfev=nfev)
    fields.update(params=params_c, pose=pose_c, t=t_touch, chi2=chi2, dof=dof, n_obs=n_obs, loglik=loglik,
                  bic=bic, p_value=p_value, consistent=bool(p_value >= alpha), uncertainty=unc)
    if fields["consistent"] is False:
        fields["reason"] = (f"{cls}: refined fit χ² = {chi2:.3g} on {dof} degrees of freedom "
                            f"(p = {p_value:.2g} < α = {alpha:g})")
    elif fields["consistent"]:
        fields["reason"] = None
    cov_pose = _shape_pose_cov(problem, cls, z, cov_z)
    return RefinedCandidate(**fields, cov=cov_p, cov_pose=cov_pose, t_samples=t_samples, fit=(problem, z, cov_z, perm),
                            sigma={"phi": float(sig_phi), "pos": float(sig_pos)}, nfev=nfev)


def refine_candidates(candidates: Sequence[Candidate], request: Any, options: Any) -> list[RefinedCandidate]:
    """Refine every candidate on the request's touches; the noise model is the options'
    (else the request's, else estimated from the residuals); alpha from the options."""
    noise = getattr(options, "noise", None) or getattr(request, "noise", None)
    alpha = float(getattr(options, "alpha", 1e-3) or 1e-3)
    touches = request.touches
    try:  # flattened once for every candidate (refine_one's κ floors on it are idempotent)
        data = _collect(touches) if candidates else None
    except (ValueError, np.linalg.LinAlgError, FloatingPointError):
        data = None  # each refine_one below collects again and says why it failed
    out = []
    for cand in candidates:
        try:
            out.append(refine_one(cand, touches, noise, alpha, data))
        except (ValueError, np.linalg.LinAlgError, FloatingPointError) as exc:
            fields = {f: getattr(cand, f) for f in Candidate.__dataclass_fields__}
            fields.update(chi2=math.inf, loglik=-math.inf, bic=math.inf, p_value=0.0, consistent=False,
                          reason=f"{cand.cls}: refinement failed ({exc})")
            out.append(RefinedCandidate(**fields))
    return out
