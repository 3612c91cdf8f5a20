"""What one touch's envelope says about the boundary it rolled on, and how well it says it.

The pad lines ``n(ψ_i)·p = d_i`` of a rolling touch are the tangents of the touched
boundary; hand_driver.kinematics.touch_from_pad_lines fits the support values d(ψ) by one
polynomial about the touch's centre of curvature and gives the contacts (the samples),
the radius of curvature ρ = −(d + d'') and dρ/dψ. :func:`fit_envelope` runs that one fit
on the touch's pad lines and adds what the recognizer and the checks need from it: at the
contact (the middle sample) κ = 1/ρ and κ_s = dκ/ds = −ρ'/ρ³; the deviation of κ, κ_s, ρ
and of every sample's position across and along its pad line, to first order in every
joint angle of every reading quantized to a tick (uniform: σ = tick/√12; the Jacobian by
central differences with the fit's origin held); and the χ² of the pad lines about the
fitted curve, each line by its own quantization deviation. tactile_jaw.pipeline.feel uses
ρ to tell a corner (the contact fixed while the pad turns: ρ ≈ 0), the χ² to tell a roll
across a corner or a closing segment (the lines are no smooth curve's tangents), and
hands the recognizer κ, κ_s with their covariance and the samples with the factor F of
their errors' covariance F·Fᵀ (x…, y…, φ… of all samples: they come from one fit, so their
errors are correlated, rank degree + 1 + n). docs/exploration.md#the-stated-noise.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from hand_driver import kinematics as kin
from hand_driver.units import rad_per_tick
from tactile_common.angles import wrap_angle

#: central-difference step (rad) of the joint-angle Jacobians
STEP_RAD = 1e-7


def quantization_var(finger) -> np.ndarray:
    """Variance (rad²) of each joint's angle quantized to a tick of its model (uniform)."""
    return rad_per_tick(kin.resolutions(finger.joints)) ** 2 / 12.0


@dataclass(frozen=True)
class EnvelopeFit:
    """One touch's envelope fit: its contacts and what it says at the contact, with deviations."""

    contacts: kin.TouchEnvelope
    kappa: float  # 1/mm
    kappa_s: float  # 1/mm²
    cov: np.ndarray  # 2×2 covariance of (κ, κ_s)
    rho: float  # radius of curvature (mm); ≈ 0 on a corner
    sigma_rho: float
    chi2: float  # of the pad lines about the fitted smooth support function, each by its deviation
    dof: int  # readings − fitted coefficients
    sigma_across: np.ndarray  # each sample's position across its pad line (mm), contacts' order
    sigma_along: np.ndarray  # and along it (mm): from the fit's slope d', U-shaped over the roll
    noise_factor: np.ndarray  # (3n, 2n) F: the samples' (x…, y…, φ…) errors = F · (joint errors / σ)


def fit_envelope(finger, q, lines: kin.PadLine, degree: int | None = None) -> EnvelopeFit:
    """:class:`EnvelopeFit` of a touch of ``finger`` (hand_driver.config.FingerConfig) from its
    joint angles ``q`` (n, 2) and their pad lines ``lines`` (n ≥ 3 readings with distinct ψ);
    ``degree`` of d(ψ) as kinematics.touch_from_pad_lines."""
    q = np.asarray(q, dtype=float)
    base = kin.touch_from_pad_lines(lines.psi, lines.d, degree=degree)
    n = q.shape[0]
    m = n // 2

    def outputs(qq):
        line = kin.finger_pad_line(finger, qq)
        c = kin.touch_from_pad_lines(line.psi, line.d, origin=base.origin, degree=base.degree)
        rho = c.rho[m]
        return np.concatenate(([1.0 / rho, -c.rho_psi[m] / rho**3, rho], c.x, c.y, c.psi))

    jac = np.empty((3 + 3 * n, q.size))
    for j in range(q.size):
        dq = np.zeros(q.size)
        dq[j] = STEP_RAD
        dq = dq.reshape(q.shape)
        jac[:, j] = (outputs(q + dq) - outputs(q - dq)) / (2.0 * STEP_RAD)
    normal = np.stack([np.cos(base.psi), np.sin(base.psi)], axis=-1)
    jx, jy = jac[3 : 3 + n], jac[3 + n : 3 + 2 * n]
    across = normal[:, :1] * jx + normal[:, 1:] * jy
    along = -normal[:, 1:] * jx + normal[:, :1] * jy
    qv = np.tile(quantization_var(finger), q.shape[0])  # per column of jac: reading-major, joint-minor
    cov = (jac[:3] * qv) @ jac[:3].T
    rho = float(base.rho[m])
    return EnvelopeFit(base, 1.0 / rho, float(-base.rho_psi[m] / rho**3), cov[:2, :2], rho,
                       float(np.sqrt(cov[2, 2])), _line_chi2(finger, q, base), n - base.degree - 1,
                       np.sqrt(np.sum(across**2 * qv, axis=1)),
                       np.sqrt(np.sum(along**2 * qv, axis=1)),
                       np.sqrt(qv) * jac[3:])


def _line_chi2(finger, q, base: kin.TouchEnvelope) -> float:
    """χ² of the pad lines about the fit: each line's residual d_i − d(ψ_i) by its own
    deviation, the fit held: ∂r_i/∂q = ∂d_i/∂q − d'(ψ_i)·∂ψ_i/∂q, d'(ψ_i) the contact's
    coordinate along the line (each line depends on its own reading's two joints)."""
    qs = q[base.order]
    grads = []
    for k in range(qs.shape[1]):
        dq = np.zeros(qs.shape)
        dq[:, k] = STEP_RAD
        plus, minus = kin.finger_pad_line(finger, qs + dq), kin.finger_pad_line(finger, qs - dq)
        dpsi = np.asarray(wrap_angle(plus.psi - minus.psi), dtype=float) / (2.0 * STEP_RAD)
        dd = (np.asarray(plus.d) - np.asarray(minus.d)) / (2.0 * STEP_RAD)
        slope = -np.sin(base.psi) * base.x + np.cos(base.psi) * base.y  # d'(ψ) = p·n⊥
        grads.append(dd - slope * dpsi)
    var = np.sum(quantization_var(finger)[:, None] * np.square(grads), axis=0)
    return float(np.sum(base.residual**2 / var))
