"""Local geometry (κ, κ_s) at the contact of a samples-touch, with its covariance.

A samples-touch (docs/formats.md, touches) is one local rolling move: tangent angles φ_i and contact
points (x_i, y_i), optionally arc lengths s_i. Its contact is the middle sample
m = n // 2. κ = dφ/ds and κ_s = d²φ/ds² there (paper eqs. 1–2).

Methods
- ``"central"``: the paper's finite differences (Sect. 1.2) on samples m−1, m, m+1,
  written for unequal spacing (the derivatives of the quadratic through the three
  points; for equal spacing exactly the paper's quotients). Error O(Δs²) for κ and for
  κ_s on equal spacing (O(Δs) for κ_s on unequal spacing).
- ``"poly"``: polynomial least squares of φ(s) − φ(s_m) in the Taylor basis u^k/k!
  (u = s − s_m) over all the touch's samples, degree 2 … min(7, n − 2). With a noise
  model the degree d for κ_s is the lowest whose φ residuals pass a χ² goodness-of-fit
  test at ``GOF_LEVEL`` (d + 2 when the touch turns by more than ``TURN_LIMIT``), κ takes
  the next odd degree (on a symmetric window an even-degree fit leaves an O(Δs²) bias in
  κ that φ's residuals cannot show under noise). Without one (degree ≤ n − 3) each output
  takes the degree of least estimated mean squared error (variance + squared bias against
  the highest degree). Error O(Δs^(d−1)) or better on exact data.
- ``"auto"``: ``"central"`` for 3 samples, ``"poly"`` otherwise.

Arc length: ``s`` when the touch has it; otherwise the cumulative chord between
consecutive points corrected to the circular arc through them with the measured turn
Δφ: Δs = chord · (Δφ/2) / sin(Δφ/2) (exact on circles).

Covariance of (κ, κ_s)
- ``noise`` given (attributes ``phi``: std of φ in rad, ``pos``: std of x and y in mm,
  optional ``s``: std of each given s in mm; zeros mean exact data): first-order
  propagation J · diag(σ²) · Jᵀ with the model choice held fixed — exact for φ (the
  estimate is linear in φ), analytic derivatives of the fit with respect to the arc
  lengths, chained to the positions through the chords — plus the squared truncation
  bias: the change to a fit two degrees higher less ``BIAS_NOISE_FACTOR`` times that
  change's noise variance (clipped at 0); at the highest degree the last change.
- ``noise`` None: φ noise estimated from the residuals of the highest-degree fit,
  floored at ``SIGMA_PHI_FLOOR`` (1e-10 rad), propagated, plus the same bias terms.
- ``"central"`` adds its difference to the quartic through the 5 middle samples as
  truncation term; on 3 or 4 samples it has no spare sample and its covariance is the
  noise's (or the floor's) propagation only — document your noise model for them.

Length (~410 lines): one job, κ and κ_s with their covariance; the methods share the
arc-length, Taylor-basis and propagation helpers below.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from typing import Any

import numpy as np

from scipy import stats

from tactile_common.errors import InputError

SIGMA_PHI_FLOOR = 1e-10
"""rad: the smallest φ noise assumed when it is estimated from residuals."""

MAX_DEGREE = 7
GOF_LEVEL = 0.01
TURN_LIMIT = 0.5
"""rad: above this tangent turn over a touch κ_s takes two more polynomial degrees."""
BIAS_NOISE_FACTOR = 2.0
"""the squared change to the fit two degrees higher, less this many times its own noise
variance, is added to the covariance as squared truncation bias (known noise)."""
"""level of the χ² goodness-of-fit test that picks the degree when the noise is known."""
METHODS = ("auto", "central", "poly")


@dataclass(frozen=True)
class LocalGeometry:
    """Local geometry at a touch's contact (middle sample): position (mm), tangent angle
    φ (rad), curvature κ (1/mm), its arc-length derivative κ_s (1/mm²) and the 2×2
    covariance of (κ, κ_s). ``method`` and ``degree`` say how it was estimated."""

    x: float
    y: float
    phi: float
    kappa: float
    kappa_s: float
    cov: np.ndarray
    method: str = "given"
    degree: int = 0


def _as_array(touch: Any, key: str, where: str) -> np.ndarray | None:
    value = getattr(touch, key, None)
    if value is None and isinstance(touch, dict):
        value = touch.get(key)
    if value is None:
        return None
    try:
        arr = np.asarray(value, dtype=float).reshape(-1)
    except (TypeError, ValueError) as exc:
        raise InputError(f"{where}: key '{key}' must be a list of numbers") from exc
    if not np.all(np.isfinite(arr)):
        raise InputError(f"{where}: key '{key}' holds NaN or infinite numbers")
    return arr


def _arc_length(phi: np.ndarray, x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Cumulative arc length from positions, chords corrected to circular arcs."""
    chord = np.hypot(np.diff(x), np.diff(y))
    half = 0.5 * np.diff(phi)
    ds = chord / np.sinc(half / np.pi)  # np.sinc(z) = sin(πz)/(πz)
    return np.concatenate(([0.0], np.cumsum(ds)))


def no_advance(s) -> int | None:
    """The first i whose samples i and i + 1 have no arc length between them (Δs at most
    1e-12 of the largest |s − s₀|, or of 1 mm), or None: such samples are refused."""
    s = np.asarray(s, dtype=float) - float(s[0])
    ds = np.diff(s)
    bad = np.flatnonzero(ds <= 1e-12 * max(float(np.max(np.abs(s))), 1.0))
    return int(bad[0]) if bad.size else None


def _check_spacing(s: np.ndarray, where: str) -> None:
    i = no_advance(s)
    if i is not None:
        ds = np.diff(s)
        raise InputError(
            f"{where}: samples {i} and {i + 1} have no arc length between them "
            f"(Δs = {ds[i]:.3g} mm); samples must advance along the boundary"
        )


def _design(u: np.ndarray, degree: int, scale: float) -> np.ndarray:
    """Columns (u/L)^k / k!, k = 0..degree."""
    v = u / scale
    cols = [np.ones_like(v)]
    fact = 1.0
    for k in range(1, degree + 1):
        fact *= k
        cols.append(v**k / fact)
    return np.stack(cols, axis=1)


def _poly_maps(s: np.ndarray, m: int, degree: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Linear maps of a degree-``degree`` fit over all samples: rows giving (κ, κ_s)
    from φ, the hat matrix's residual projector, and φ(s_m) − φ_m's row."""
    u = s - s[m]
    scale = max(float(np.max(np.abs(u))), 1e-300)
    a = _design(u, degree, scale)
    pinv = np.linalg.pinv(a)
    g = np.stack([pinv[1] / scale, pinv[2] / scale**2])
    resid = np.eye(s.size) - a @ pinv
    return g, resid, pinv[0]


def _central_map(s: np.ndarray, m: int) -> np.ndarray:
    """Rows giving (κ, κ_s) at s_m from the quadratic through samples m−1, m, m+1
    (the paper's quotients for equal spacing)."""
    h1 = s[m] - s[m - 1]
    h2 = s[m + 1] - s[m]
    g = np.zeros((2, s.size))
    g[0, m - 1 : m + 2] = (-h2 / (h1 * (h1 + h2)), (h2 - h1) / (h1 * h2), h1 / (h2 * (h1 + h2)))
    g[1, m - 1 : m + 2] = (2 / (h1 * (h1 + h2)), -2 / (h1 * h2), 2 / (h2 * (h1 + h2)))
    return g


@dataclass(frozen=True)
class _Choice:
    """The model behind an estimate: method and the degrees used for κ and for κ_s."""

    method: str
    deg_k: int
    deg_ks: int


def _maps(s: np.ndarray, m: int, choice: _Choice) -> tuple[np.ndarray, np.ndarray]:
    """(2×n map to (κ, κ_s), row of the φ offset at s_m) for a fixed choice."""
    if choice.method == "central":
        return _central_map(s, m), np.zeros(s.size)
    gk, _, p0 = _poly_maps(s, m, choice.deg_k)
    gks, _, _ = _poly_maps(s, m, choice.deg_ks)
    return np.stack([gk[0], gks[1]]), p0


def _truncation(values: list[float]) -> float:
    """Truncation error of the last estimate of a sequence by increasing degree: its last
    change (conservative: the error of the previous degree)."""
    ref = values[-1]
    tiny = 1e-9 * max(abs(v) for v in values)
    errs = [abs(v - ref) for v in values[:-1]]
    distinct: list[float] = []
    for e in reversed(errs):
        if e > tiny and (not distinct or abs(e - distinct[-1]) > 1e-6 * e):
            distinct.append(e)
        if len(distinct) == 2:
            break
    if not distinct:
        return 0.0
    return distinct[0]


def _select(phi: np.ndarray, s: np.ndarray, m: int, sigma_fit: float | None, max_deg: int) -> tuple[_Choice, np.ndarray, float]:
    """Degrees for κ and κ_s minimising the estimated mean squared error (variance +
    squared bias, the bias measured against the highest degree and corrected for the
    noise of that difference); returns the choice, the squared-bias terms and σ̂ of φ."""
    degrees = list(range(2, max_deg + 1))
    maps = {d: _poly_maps(s, m, d) for d in degrees}
    top = maps[degrees[-1]]
    rphi = phi - phi[m]
    if sigma_fit is None:
        dof = s.size - (degrees[-1] + 1)
        rss = float(np.sum((top[1] @ rphi) ** 2))
        sigma = max(np.sqrt(rss / dof) if dof > 0 else 0.0, SIGMA_PHI_FLOOR)
    else:
        sigma = max(sigma_fit, SIGMA_PHI_FLOOR)
    est = {d: maps[d][0] @ rphi for d in degrees}
    chosen = []
    bias2 = np.zeros(2)
    for j in range(2):
        ref_g = top[0][j]
        best = None
        for d in degrees:
            g = maps[d][0][j]
            var = sigma**2 * float(g @ g)
            if d == degrees[-1]:
                b2 = _truncation([est[k][j] for k in degrees]) ** 2
            else:
                diff = g - ref_g
                b2 = max(0.0, (est[d][j] - est[degrees[-1]][j]) ** 2 - sigma**2 * float(diff @ diff))
            if best is None or var + b2 < best[0]:
                best = (var + b2, d, b2)
        assert best is not None
        chosen.append(best[1])
        bias2[j] = best[2]
    return _Choice("poly", chosen[0], chosen[1]), bias2, sigma


@lru_cache(maxsize=64)
def _gof_limit(dof: int) -> float:
    """The goodness-of-fit test's χ² threshold at ``GOF_LEVEL`` (stats.chi2.ppf costs ~0.2 ms
    a call; a recognition asks it a few times per touch, for a handful of dof)."""
    return float(stats.chi2.ppf(1.0 - GOF_LEVEL, dof))


def _select_gof(phi: np.ndarray, s: np.ndarray, m: int, sigma: float, max_deg: int) -> _Choice:
    """Known noise: the lowest degree d whose φ residuals pass the χ² goodness-of-fit test
    at level ``GOF_LEVEL`` (the highest degree if none does) gives κ_s; κ comes from the
    next odd degree (on a symmetric window an even-degree fit leaves κ's O(Δs²) bias,
    which φ's residuals cannot reveal under noise); κ_s from d + 2 when the touch turns
    by more than ``TURN_LIMIT`` (its window is then not local enough for degree d)."""
    rphi = phi - phi[m]
    sigma = max(sigma, SIGMA_PHI_FLOOR)
    for d in range(2, max_deg + 1):
        _, resid, _ = _poly_maps(s, m, d)
        dof = s.size - d - 1
        if dof <= 0:
            break
        chi2 = float(np.sum((resid @ rphi) ** 2)) / sigma**2
        if chi2 <= _gof_limit(dof):
            turn = abs(float(phi[-1] - phi[0]))
            d_ks = min(d + 2, max_deg) if turn > TURN_LIMIT else d
            return _Choice("poly", min(d + 1 - d % 2, max_deg), d_ks)
    return _Choice("poly", max_deg, max_deg)


def _bias2_known(phi: np.ndarray, s: np.ndarray, m: int, sigma: float, choice: _Choice,
                 max_deg: int) -> np.ndarray:
    """Squared truncation bias of each output under known noise: the change to the fit
    two degrees higher (at most the interpolating degree) when it is significant (beyond the 1 % χ²₁
    quantile of its own noise), else 0; at the highest degree the extrapolated last
    change."""
    rphi = phi - phi[m]
    top = max(max_deg, min(MAX_DEGREE + 1, s.size - 1))
    degrees = list(range(2, top + 1))
    maps = {d: _poly_maps(s, m, d)[0] for d in degrees}
    out = np.zeros(2)
    for j, d in enumerate((choice.deg_k, choice.deg_ks)):
        values = {k: float(maps[k][j] @ rphi) for k in degrees}
        tiny = 1e-9 * max(abs(v) for v in values.values())
        higher = [k for k in (d + 2, d + 1) if k <= top and abs(values[k] - values[d]) > tiny]
        if higher:
            g = maps[d][j] - maps[higher[0]][j]
            diff = values[d] - values[higher[0]]
            var_diff = max(sigma, SIGMA_PHI_FLOOR) ** 2 * float(g @ g)
            out[j] = max(diff**2 - BIAS_NOISE_FACTOR * var_diff, 0.0)
        else:
            out[j] = _truncation([values[k] for k in degrees if k <= d]) ** 2
    return out


def _central_bias2(phi: np.ndarray, s: np.ndarray, m: int, sigma: float) -> np.ndarray:
    """Squared truncation bias of the central differences: their difference to the
    quartic through the 5 middle samples, less that difference's noise variance (0 when
    the touch has fewer than 5 samples)."""
    if m < 2 or m + 2 >= s.size:
        return np.zeros(2)
    sub = slice(m - 2, m + 3)
    g5 = np.zeros((2, s.size))
    g5[:, sub] = _poly_maps(s[sub], 2, 4)[0]
    g = _central_map(s, m) - g5
    diff = g @ (phi - phi[m])
    return np.maximum(diff**2 - BIAS_NOISE_FACTOR * sigma**2 * np.sum(g * g, axis=1), 0.0)


def _d_ds(phi: np.ndarray, s: np.ndarray, m: int, choice: _Choice) -> np.ndarray:
    """∂(κ, κ_s)/∂s_i (2×n), the model choice held fixed: for a polynomial fit
    c = (AᵀA)⁻¹Aᵀr, ∂c/∂u_i = (AᵀA)⁻¹(a_i'ᵀ e_i − a_iᵀ a_i'·c) with e the residuals and
    a_i' the derivative of row i; u = s − s_m. Central differences for "central"."""
    rphi = phi - phi[m]
    n = s.size
    if choice.method == "central":
        out = np.zeros((2, n))
        step = 1e-6 * max(float(np.ptp(s)), 1e-3)
        for i in range(n):
            sp, sm = s.copy(), s.copy()
            sp[i] += step
            sm[i] -= step
            out[:, i] = (_central_map(sp, m) @ rphi - _central_map(sm, m) @ rphi) / (2 * step)
        return out
    u = s - s[m]
    scale = max(float(np.max(np.abs(u))), 1e-300)
    out = np.zeros((2, n))
    for row, degree in ((0, choice.deg_k), (1, choice.deg_ks)):
        a = _design(u, degree, scale)
        da = np.zeros_like(a)
        da[:, 1:] = a[:, :-1] / scale  # d/du of (u/L)^k/k! is (u/L)^(k-1)/(k-1)!/L
        mat = np.linalg.pinv(a.T @ a)
        c = mat @ (a.T @ rphi)
        e = rphi - a @ c
        dc = mat @ (da.T * e - a.T * (da @ c))  # column i: ∂c/∂u_i
        du = dc[row + 1] / scale ** (row + 1)
        out[row] = du
        out[row, m] -= du.sum()
    return out


def _jacobian_cov(phi: np.ndarray, x: np.ndarray, y: np.ndarray, s: np.ndarray | None, m: int,
                  choice: _Choice, sig_phi: float, sig_pos: float, sig_s: float) -> np.ndarray:
    """J diag(σ²) Jᵀ over every input the estimate depends on, the model choice held
    fixed: φ exactly (the estimate is linear in φ), arc lengths by central differences,
    positions through the chord lengths that make the arc lengths (chain rule)."""
    ss = _arc_length(phi, x, y) if s is None else s
    g, _ = _maps(ss, m, choice)
    jac_phi = g.copy()
    jac_phi[:, m] -= g.sum(axis=1)
    cov = sig_phi**2 * jac_phi @ jac_phi.T
    sig_arc = sig_pos if s is None else sig_s
    if sig_arc <= 0:
        return cov
    jac_s = _d_ds(phi, ss, m, choice)
    if s is not None:
        return cov + sig_s**2 * jac_s @ jac_s.T
    dx, dy = np.diff(x), np.diff(y)
    chord = np.hypot(dx, dy)
    corr = 1.0 / np.sinc(0.5 * np.diff(phi) / np.pi)
    # s_i = Σ_{j<i} chord_j · corr_j: ∂θ/∂chord_j = corr_j Σ_{i>j} ∂θ/∂s_i
    d_chord = corr * np.cumsum(jac_s[:, ::-1], axis=1)[:, ::-1][:, 1:]
    ux, uy = dx / chord, dy / chord
    jac_x = np.zeros((2, phi.size))
    jac_y = np.zeros((2, phi.size))
    jac_x[:, 1:] += d_chord * ux
    jac_x[:, :-1] -= d_chord * ux
    jac_y[:, 1:] += d_chord * uy
    jac_y[:, :-1] -= d_chord * uy
    return cov + sig_pos**2 * (jac_x @ jac_x.T + jac_y @ jac_y.T)


def estimate_local(touch: Any, method: str = "auto", noise: Any = None, where: str = "touch") -> LocalGeometry:
    """κ, κ_s and their covariance at the contact (sample n // 2) of a samples-touch.

    ``touch`` has arrays ``phi``, ``x``, ``y`` and optional ``s`` (attributes or keys);
    ``noise`` has ``phi`` (rad) and ``pos`` (mm) standard deviations (optional ``s``),
    or is None. ``where`` names the touch in error messages. Raises InputError on
    unequal lengths, fewer than 3 samples, non-finite numbers or samples that do not
    advance (zero arc length between neighbours)."""
    if method not in METHODS:
        raise InputError(f"estimator: method {method!r} is not one of {', '.join(METHODS)}")
    phi = _as_array(touch, "phi", where)
    x = _as_array(touch, "x", where)
    y = _as_array(touch, "y", where)
    s = _as_array(touch, "s", where)
    if phi is None or x is None or y is None:
        raise InputError(f"{where}: a samples-touch needs keys 'phi', 'x' and 'y'")
    n = phi.size
    if x.size != n or y.size != n or (s is not None and s.size != n):
        raise InputError(f"{where}: 'phi', 'x', 'y' (and 's') must have equal lengths")
    if n < 3:
        raise InputError(f"{where}: a samples-touch needs at least 3 samples, got {n}")
    phi_raw_m = float(phi[n // 2])
    phi = np.unwrap(phi)
    ss = _arc_length(phi, x, y) if s is None else s - s[0]
    _check_spacing(ss, where)
    m = n // 2
    if method == "auto":
        method = "central" if n < 4 else "poly"
    sig_phi = float(getattr(noise, "phi", 0.0) or 0.0) if noise is not None else None
    # arc lengths come from the positions' along-track components: their deviation counts
    sig_pos = float(getattr(noise, "along", getattr(noise, "pos", 0.0)) or 0.0) if noise is not None else 0.0
    sig_s = float(getattr(noise, "s", 0.0) or 0.0) if noise is not None else 0.0
    rphi = phi - phi[m]
    if method == "central":
        choice = _Choice("central", 2, 2)
        sigma = max(sig_phi or 0.0, SIGMA_PHI_FLOOR)
        bias2 = _central_bias2(phi, ss, m, sigma)
    else:
        if noise is None:
            max_deg = max(2, min(MAX_DEGREE, n - 3))
            sig_fit = None
        else:
            max_deg = max(2, min(MAX_DEGREE, n - 2))
            # position (or arc-length) noise moves samples along the curve: φ error κ·δs
            kappa0 = float((_poly_maps(ss, m, 2)[0] @ rphi)[0])
            extra = 2 * sig_pos**2 if s is None else sig_s**2
            sig_fit = float(np.sqrt(sig_phi**2 + kappa0**2 * extra))
        if sig_fit is None:
            choice, bias2, sigma = _select(phi, ss, m, None, max_deg)
        else:
            choice, sigma = _select_gof(phi, ss, m, sig_fit, max_deg), sig_fit
            bias2 = _bias2_known(phi, ss, m, sig_fit, choice, max_deg)
    g, p0 = _maps(ss, m, choice)
    kappa, kappa_s = (float(v) for v in g @ rphi)
    phi0 = phi_raw_m + float(p0 @ rphi)
    if noise is not None:
        cov = _jacobian_cov(phi, x, y, None if s is None else ss, m, choice,
                            max(sig_phi or 0.0, SIGMA_PHI_FLOOR), sig_pos, sig_s)
    else:
        jac = g.copy()
        jac[:, m] -= g.sum(axis=1)
        cov = sigma**2 * jac @ jac.T
    cov = cov + np.diag(bias2)
    cov = 0.5 * (cov + cov.T)
    if not (np.all(np.isfinite(cov)) and np.isfinite(kappa) and np.isfinite(kappa_s) and np.isfinite(phi0)):
        raise InputError(f"{where}: samples too close together to estimate curvature")
    return LocalGeometry(float(x[m]), float(y[m]), phi0, kappa, kappa_s, cov, method,
                         max(choice.deg_k, choice.deg_ks))
