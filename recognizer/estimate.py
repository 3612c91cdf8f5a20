"""Local geometry (κ, κ_s) at the contact of a samples-touch, with its covariance.

A samples-touch (CONTRACTS §2) is one local rolling move: tangent angles φ_i and contact
points (x_i, y_i), optionally arc lengths s_i. Its contact is the middle sample
m = n // 2. κ = dφ/ds and κ_s = d²φ/ds² there (paper eqs. 1–2).

Methods
- ``"central"``: the paper's finite differences (Sect. 1.2) on samples m−1, m, m+1,
  written for unequal spacing (the derivatives of the quadratic through the three
  points; for equal spacing exactly the paper's quotients). Error O(Δs²) for κ and
  O(Δs) for κ_s on unequal spacing, O(Δs²) on equal spacing.
- ``"poly"``: local polynomial least squares of φ(s) − φ(s_m) in the Taylor basis
  u^k/k! (u = s − s_m) over all the touch's samples; the degree (2 … min(6, N−3)) is
  chosen from the data by the corrected Akaike criterion (AICc) — with a known φ noise
  χ² + 2k + 2k(k+1)/(N−k−1), without it N·ln(RSS/N) + the same penalty.
  Error O(Δs^{d}) for κ and O(Δs^{d−1}) for κ_s at degree d on exact data.
- ``"auto"``: ``"central"`` for 3 or 4 samples, ``"poly"`` otherwise.

Arc length: ``s`` when the touch has it; otherwise the cumulative chord between
consecutive points corrected to the circular arc through them with the measured turn
Δφ: Δs = chord · (Δφ/2) / sin(Δφ/2) (exact on circles, error O(Δs³·κ_s) otherwise).

Covariance of (κ, κ_s)
- ``noise`` given (attributes ``phi``: std of φ in rad, ``pos``: std of x and y in mm,
  optional ``s``: std of each given s in mm): first-order propagation
  J · diag(σ²) · Jᵀ, J the derivative of the estimate with respect to every φ_i, x_i,
  y_i (when s comes from the positions) and s_i, by central differences with the
  model choice held fixed.
- ``noise`` None: φ noise estimated from the fit residuals, σ̂² = RSS/(N − k), floored
  at ``SIGMA_PHI_FLOOR`` (1e-10 rad) so exact data gives a tiny but positive covariance;
  ``"poly"`` adds the squared change of the estimate from degree d−1 to d as a
  truncation term. ``"central"`` on exactly 3 samples has no spare sample: its
  covariance is the floor's propagation only.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from recognizer.errors import InputError

SIGMA_PHI_FLOOR = 1e-10
"""rad: the smallest φ noise assumed when it is estimated from residuals."""

MAX_DEGREE = 6
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


@dataclass(frozen=True)
class _Fit:
    """One polynomial fit: chosen indices and degree; results."""

    lo: int
    hi: int
    degree: int
    phi0: float
    kappa: float
    kappa_s: float
    rss: float


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


def _check_spacing(s: np.ndarray, where: str) -> None:
    ds = np.diff(s)
    scale = max(float(np.max(np.abs(s))), 1.0)
    bad = np.flatnonzero(ds <= 1e-12 * scale)
    if bad.size:
        i = int(bad[0])
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


def _poly_fit(phi: np.ndarray, s: np.ndarray, m: int, lo: int, hi: int, degree: int) -> _Fit:
    u = s[lo : hi + 1] - s[m]
    scale = max(float(np.max(np.abs(u))), 1e-300)
    a = _design(u, degree, scale)
    rhs = phi[lo : hi + 1] - phi[m]
    coef, *_ = np.linalg.lstsq(a, rhs, rcond=None)
    resid = rhs - a @ coef
    return _Fit(lo, hi, degree, float(phi[m] + coef[0]), float(coef[1] / scale),
                float(coef[2] / scale**2), float(resid @ resid))


def _central(phi: np.ndarray, s: np.ndarray, m: int) -> _Fit:
    """Derivatives at s_m of the quadratic through samples m−1, m, m+1."""
    h1 = s[m] - s[m - 1]
    h2 = s[m + 1] - s[m]
    d1 = (phi[m] - phi[m - 1]) / h1
    d2 = (phi[m + 1] - phi[m]) / h2
    kappa = (h2 * d1 + h1 * d2) / (h1 + h2)
    kappa_s = 2.0 * (d2 - d1) / (h1 + h2)
    return _Fit(m - 1, m + 1, 2, float(phi[m]), float(kappa), float(kappa_s), 0.0)


def _aicc(rss: float, n: int, k: int, sigma: float | None) -> float:
    penalty = 2 * k + 2 * k * (k + 1) / max(n - k - 1, 1e-9)
    if sigma is not None and sigma > 0:
        return rss / sigma**2 + penalty
    return n * np.log(max(rss / n, 1e-300)) + penalty


def _choose(phi: np.ndarray, s: np.ndarray, m: int, method: str, sigma_phi: float | None) -> tuple[_Fit, _Fit | None]:
    """The fit of the chosen method and model, and the next-lower-degree fit (if any)."""
    n = phi.size
    if method == "central":
        return _central(phi, s, m), None
    max_deg = min(MAX_DEGREE, n - 3) if n >= 5 else 2
    best: tuple[float, _Fit] | None = None
    fits: dict[int, _Fit] = {}
    for degree in range(2, max(max_deg, 2) + 1):
        fit = _poly_fit(phi, s, m, 0, n - 1, degree)
        fits[degree] = fit
        score = _aicc(fit.rss, n, degree + 1, sigma_phi)
        if best is None or score < best[0] - 1e-12:
            best = (score, fit)
    assert best is not None
    chosen = best[1]
    return chosen, fits.get(chosen.degree - 1)


def _estimate_frozen(phi: np.ndarray, x: np.ndarray, y: np.ndarray, s: np.ndarray | None,
                     m: int, method: str, degree: int) -> np.ndarray:
    """(κ, κ_s) for fixed model choice; used for derivatives of the estimate."""
    ss = _arc_length(phi, x, y) if s is None else s
    if method == "central":
        fit = _central(phi, ss, m)
    else:
        fit = _poly_fit(phi, ss, m, 0, phi.size - 1, degree)
    return np.array([fit.kappa, fit.kappa_s])


def _jacobian_cov(phi: np.ndarray, x: np.ndarray, y: np.ndarray, s: np.ndarray | None, m: int,
                  method: str, degree: int, sig_phi: float, sig_pos: float, sig_s: float) -> np.ndarray:
    """J diag(σ²) Jᵀ by central differences over every input the estimate depends on."""
    cov = np.zeros((2, 2))
    scale = max(float(np.ptp(x)), float(np.ptp(y)), float(np.ptp(s)) if s is not None else 0.0, 1e-3)
    groups: list[tuple[int, float, float]] = [(0, sig_phi, 1e-6)]
    if s is None:
        groups += [(1, sig_pos, 1e-6 * scale), (2, sig_pos, 1e-6 * scale)]
    else:
        groups += [(3, sig_s, 1e-6 * scale)]
    for which, sigma, step in groups:
        if sigma <= 0:
            continue
        for i in range(phi.size):
            arrays = [phi, x, y, s]
            plus = [a.copy() if a is not None else None for a in arrays]
            minus = [a.copy() if a is not None else None for a in arrays]
            plus[which][i] += step
            minus[which][i] -= step
            d = (_estimate_frozen(plus[0], plus[1], plus[2], plus[3], m, method, degree)
                 - _estimate_frozen(minus[0], minus[1], minus[2], minus[3], m, method, degree)) / (2 * step)
            cov += sigma**2 * np.outer(d, d)
    return cov


def _residual_cov(phi: np.ndarray, s: np.ndarray, m: int, fit: _Fit, method: str) -> np.ndarray:
    """Covariance from the φ residual variance (noise unknown)."""
    n_used = fit.hi - fit.lo + 1
    k = fit.degree + 1
    sigma2 = fit.rss / (n_used - k) if n_used > k else 0.0
    sigma2 = max(sigma2, SIGMA_PHI_FLOOR**2)
    if method == "central":
        grad = np.zeros((2, phi.size))
        for i in (m - 1, m, m + 1):
            e = np.zeros(phi.size)
            e[i] = 1.0
            c = _central(e, s, m)
            grad[:, i] = (c.kappa, c.kappa_s)
        return sigma2 * grad @ grad.T
    u = s[fit.lo : fit.hi + 1] - s[m]
    scale = max(float(np.max(np.abs(u))), 1e-300)
    a = _design(u, fit.degree, scale)
    inv = np.linalg.pinv(a.T @ a)
    sel = np.array([[0, 1 / scale] + [0] * (fit.degree - 1), [0, 0, 1 / scale**2] + [0] * (fit.degree - 2)])
    return sigma2 * sel @ inv @ sel.T


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
        method = "central" if n < 5 else "poly"
    sig_phi = float(getattr(noise, "phi", 0.0) or 0.0) if noise is not None else None
    fit, lower = _choose(phi, ss, m, method, sig_phi)
    if noise is not None:
        sig_pos = float(getattr(noise, "pos", 0.0) or 0.0)
        sig_s = float(getattr(noise, "s", 0.0) or 0.0)
        cov = _jacobian_cov(phi, x, y, None if s is None else ss, m, method, fit.degree,
                            max(sig_phi or 0.0, SIGMA_PHI_FLOOR), sig_pos, sig_s)
    else:
        cov = _residual_cov(phi, ss, m, fit, method)
        if lower is not None:
            d = np.array([fit.kappa - lower.kappa, fit.kappa_s - lower.kappa_s])
            cov = cov + np.diag(d**2)
    cov = 0.5 * (cov + cov.T)
    if not np.all(np.isfinite(cov)) or not np.isfinite(fit.kappa) or not np.isfinite(fit.kappa_s):
        raise InputError(f"{where}: samples too close together to estimate curvature")
    return LocalGeometry(float(x[m]), float(y[m]), phi_raw_m + float(fit.phi0 - phi[m]), fit.kappa, fit.kappa_s, cov, method, fit.degree)
