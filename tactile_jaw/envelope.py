"""What one touch's envelope says about the boundary it rolled on, from its own fit.

The pad lines ``n(ψ_i)·p = d_i`` of a rolling touch are the tangents of the touched
boundary; hand_driver.kinematics.touch_from_pad_lines fits the support values d(ψ) by a
polynomial. The same fit, about the centre of curvature, gives at the contact (the middle
reading) the radius of curvature ρ = −(d + d''), κ = 1/ρ and κ_s = dκ/ds = −ρ'/ρ³ (ρ' =
dρ/dψ), each with its deviation to first order in every joint angle of every reading
quantized to a tick (uniform: σ = tick/√12), and the χ² of the lines about the fitted
curve. :func:`fit_envelope` computes them; tactile_jaw.pipeline.feel uses ρ to tell a
corner (the contact fixed while the pad turns: ρ ≈ 0) and the χ² to tell a roll across a
corner or a closing segment (the lines are no smooth curve's tangents) from the curved
part, and hands the recognizer κ, κ_s with their covariance. docs/exploration.md.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from hand_driver import kinematics as kin
from hand_driver.units import RAD_PER_TICK

#: central-difference step (rad) of the joint-angle Jacobians
STEP_RAD = 1e-7
#: variance of one joint angle quantized to a tick (uniform)
QUANTIZATION_VAR = RAD_PER_TICK**2 / 12.0


@dataclass(frozen=True)
class EnvelopeFit:
    """The envelope fit's reading of the touched boundary at the contact."""

    kappa: float  # 1/mm
    kappa_s: float  # 1/mm²
    cov: np.ndarray  # 2×2 covariance of (κ, κ_s)
    rho: float  # radius of curvature (mm); ≈ 0 on a corner
    sigma_rho: float
    chi2: float  # of the pad lines about the fitted smooth support function, each by its deviation
    dof: int  # readings − fitted coefficients


def fit_envelope(finger, q) -> EnvelopeFit:
    """:class:`EnvelopeFit` of a touch of ``finger`` (hand_driver.config.FingerConfig)
    from its joint angles ``q`` (n, 2), n ≥ 3 readings with distinct ψ."""
    q = np.asarray(q, dtype=float)
    base, origin, chi2, dof = _fit(finger, q, None, with_chi2=True)
    jac = np.empty((3, q.size))
    for j in range(q.size):
        dq = np.zeros(q.size)
        dq[j] = STEP_RAD
        dq = dq.reshape(q.shape)
        jac[:, j] = (_fit(finger, q + dq, origin)[0] - _fit(finger, q - dq, origin)[0]) / (2.0 * STEP_RAD)
    cov = QUANTIZATION_VAR * jac @ jac.T
    kappa, kappa_s, rho = (float(v) for v in base)
    return EnvelopeFit(kappa, kappa_s, cov[:2, :2], rho, float(np.sqrt(cov[2, 2])), chi2, dof)


def _fit(finger, q, origin, with_chi2: bool = False):
    """([κ, κ_s, ρ] at the middle reading, centre of curvature, χ², dof) from the support
    values d(ψ) − n(ψ)·o fitted by a polynomial in ψ (degree kinematics.default_degree).
    About the centre of curvature ``o`` a circle's support values are constant, so the
    fit's truncation error is only that of the changing curvature; ``origin`` None: two
    passes, the first about the lines' mean foot."""
    line = kin.finger_pad_line(finger, q)
    psi = np.unwrap(np.asarray(line.psi, dtype=float))
    order = np.argsort(psi, kind="stable")
    psi, d, n = psi[order], np.asarray(line.d, dtype=float)[order], np.asarray(line.normal, dtype=float)[order]
    c0, scale = 0.5 * (psi[0] + psi[-1]), 0.5 * (psi[-1] - psi[0])
    x = (psi - c0) / scale
    m = psi.size // 2
    deg = kin.default_degree(psi.size)
    centre = np.mean(n * d[:, None], axis=0) if origin is None else origin
    for _ in range(2 if origin is None else 1):
        o = centre
        poly = np.polynomial.Polynomial.fit(x, d - n @ o, deg, domain=[-1, 1], window=[-1, 1])
        rho_t = poly(x[m]) + poly.deriv(2)(x[m]) / scale**2  # d + d'' = −ρ
        rho_1 = -(poly.deriv(1)(x[m]) + poly.deriv(3)(x[m]) / scale**2) / scale  # dρ/dψ
        nperp = np.array([-n[m, 1], n[m, 0]])
        contact = o + n[m] * poly(x[m]) + nperp * poly.deriv(1)(x[m]) / scale
        centre = contact - n[m] * rho_t  # inside the object, along n
    rho = -rho_t
    values = np.array([1.0 / rho, -rho_1 / rho**3, rho])
    if not with_chi2:
        return values, centre
    qs = np.asarray(q, dtype=float)[order]
    resid = d - n @ o - poly(x)
    chi2 = 0.0
    for i in range(psi.size):  # each line's deviation about the fixed fit, from its two joints
        grad = []
        for k in range(2):
            dq = np.zeros(2)
            dq[k] = STEP_RAD
            plus, minus = (kin.finger_pad_line(finger, qs[i] + sgn * dq) for sgn in (1.0, -1.0))
            y = [float(ln.d) - float(np.asarray(ln.normal) @ o)
                 - float(poly((np.remainder(float(ln.psi) - psi[i] + np.pi, 2 * np.pi) - np.pi + psi[i] - c0) / scale))
                 for ln in (plus, minus)]
            grad.append((y[0] - y[1]) / (2.0 * STEP_RAD))
        chi2 += float(resid[i] ** 2 / (QUANTIZATION_VAR * float(np.sum(np.square(grad)))))
    return values, centre, chi2, psi.size - deg - 1
