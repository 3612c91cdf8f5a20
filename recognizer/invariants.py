"""The paper's invariants in numerically stable forms (eqs. 5, 9, 10, 14, 15, 18, 19).

κ^{2/3} is |κ|^{2/3} (errata, docs/recognition.md). Stable rewrites:

- I_p = |κ|^{2/3} + κ_s² / (9 |κ|^{10/3})                                  (eq. 5)
- with d = |κ₁|^{2/3} − |κ₂|^{2/3} = (|κ₁| − |κ₂|)(x + y)/(x² + xy + y²), x, y = |κ|^{1/3}
  (no cancellation between the two powers) and q = κ_s²/(9|κ|^{10/3}),
  r = κ_s²/(9|κ|^{8/3}):
  I_c1 = |κ₁κ₂|^{2/3} (1 + (q₁ − q₂)/d)                                    (eq. 9)
  I_c2 = |κ₁|^{2/3} + |κ₂|^{2/3} + (r₁ − r₂)/d                              (eq. 10)
  Both are 0/0 when |κ₁| = |κ₂| (a circle, or symmetric points of an ellipse): such a
  pair carries no information and ``pair_condition`` says how close to that it is.
- Cubical parabola, λ = tan ψ, ψ the tangent angle in the canonical frame:
  I_cp1 = (κ_s + 3λκ²)(1+λ²)²/6 = a, I_cp2 = λ − κ²(1+λ²)/(2(κ_s + 3λκ²)) = c.
- Semicubical parabola: I_scp1 = √|−8κ³(1+λ²)^{5/2} / (9(κ_s + 3λκ²))| = a (errata, docs/recognition.md:
  the radicand is −a² on the branch t < 0), I_scp2 = λ + κ²(1+λ²)/(κ_s + 3λκ²) = b.
- The unknown canonical rotation: ``slope_angles`` solves I_cp2 (or I_scp2) equal at two
  touches whose tangent turns by Δ. The paper's quartic in λ₁ is (1+λ₁²) × a quadratic
  (errata, docs/recognition.md); we solve that quadratic as a quadratic form in (sin ψ₁, cos ψ₁), so a
  vertical canonical tangent (λ → ∞) is no special case. Coefficients from a sympy
  derivation (checked in tests/test_recognizer_invariants.py).
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["pow23", "diff23", "I_p", "I_c1", "I_c2", "pair_condition", "I_cp1", "I_cp2", "I_scp1",
           "I_scp2", "slope_angles", "propagate", "I_p_s", "I_c12_s", "pair_condition_s"]

K_CUBICAL = -0.5  # I_cp2 = λ + k κ²(1+λ²)/(κ_s + 3λκ²) with k = −1/2
K_SEMICUBICAL = 1.0  # I_scp2: k = +1


def pow23(k):
    """|κ|^{2/3}."""
    return np.cbrt(np.abs(np.asarray(k, dtype=float))) ** 2


def diff23(k1, k2):
    """|κ₁|^{2/3} − |κ₂|^{2/3} without cancellation between the powers."""
    a1, a2 = np.abs(np.asarray(k1, float)), np.abs(np.asarray(k2, float))
    x, y = np.cbrt(a1), np.cbrt(a2)
    return (a1 - a2) * (x + y) / (x * x + x * y + y * y)


def I_p(k, ks):
    """Eq. (5): 1/(2a)^{2/3} on a parabola."""
    k, ks = np.asarray(k, float), np.asarray(ks, float)
    return pow23(k) + ks * ks / (9.0 * pow23(k) ** 5)


def pair_condition(k1, k2):
    """|d| / (|κ₁|^{2/3} + |κ₂|^{2/3}) in [0, 1]: 0 means the pair cannot give I_c1, I_c2."""
    return np.abs(diff23(k1, k2)) / (pow23(k1) + pow23(k2))


def I_c1(k1, ks1, k2, ks2):
    """Eq. (9): 1/(ab)^{2/3} (ellipse), −1/(ab)^{2/3} (hyperbola), 0 (parabola)."""
    q1 = np.asarray(ks1, float) ** 2 / (9.0 * pow23(k1) ** 5)
    q2 = np.asarray(ks2, float) ** 2 / (9.0 * pow23(k2) ** 5)
    return np.cbrt(np.abs(np.asarray(k1, float) * k2)) ** 2 * (1.0 + (q1 - q2) / diff23(k1, k2))


def I_c2(k1, ks1, k2, ks2):
    """Eq. (10): (a²+b²)/(ab)^{4/3} (ellipse), (a²−b²)/(ab)^{4/3} (hyperbola), 1/(2a)^{2/3}."""
    r1 = np.asarray(ks1, float) ** 2 / (9.0 * pow23(k1) ** 4)
    r2 = np.asarray(ks2, float) ** 2 / (9.0 * pow23(k2) ** 4)
    return pow23(k1) + pow23(k2) + (r1 - r2) / diff23(k1, k2)


# -- the same for one touch (pair) of Python floats: math instead of NumPy calls -------

def _diff23_s(k1: float, k2: float) -> float:
    a1, a2 = abs(k1), abs(k2)
    x, y = math.cbrt(a1), math.cbrt(a2)
    return (a1 - a2) * (x + y) / (x * x + x * y + y * y)


def I_p_s(k: float, ks: float) -> float:
    """Eq. (5) for one touch (κ ≠ 0)."""
    p = math.cbrt(abs(k)) ** 2
    return p + ks * ks / (9.0 * p**5)


def pair_condition_s(k1: float, k2: float) -> float:
    """``pair_condition`` of one pair; nan for κ₁ = κ₂ = 0."""
    x, y = math.cbrt(abs(k1)), math.cbrt(abs(k2))
    den = x * x + y * y
    return abs(_diff23_s(k1, k2)) / den if den > 0 else math.nan


def I_c12_s(k1: float, ks1: float, k2: float, ks2: float) -> tuple[float, float]:
    """(I_c1, I_c2) of one pair, eqs. (9)-(10); nan where the pair gives none."""
    p1, p2 = math.cbrt(abs(k1)) ** 2, math.cbrt(abs(k2)) ** 2
    try:
        d = _diff23_s(k1, k2)
        c1 = math.cbrt(abs(k1 * k2)) ** 2 * (1.0 + (ks1 * ks1 / (9.0 * p1**5) - ks2 * ks2 / (9.0 * p2**5)) / d)
        c2 = p1 + p2 + (ks1 * ks1 / (9.0 * p1**4) - ks2 * ks2 / (9.0 * p2**4)) / d
    except (ArithmeticError, ValueError):
        return math.nan, math.nan
    return c1, c2


def _den(lam, k, ks):
    return ks + 3.0 * lam * k * k


def I_cp1(lam, k, ks):
    """Eq. (14): a of the cubical parabola."""
    lam = np.asarray(lam, float)
    return _den(lam, k, ks) * (1.0 + lam * lam) ** 2 / 6.0


def I_cp2(lam, k, ks):
    """Eq. (15): c of the cubical parabola."""
    lam = np.asarray(lam, float)
    return lam - np.asarray(k, float) ** 2 * (1.0 + lam * lam) / (2.0 * _den(lam, k, ks))


def I_scp1(lam, k, ks):
    """Eq. (18) with the errata's fix (docs/recognition.md): a = √|radicand| (> 0)."""
    lam = np.asarray(lam, float)
    k = np.asarray(k, float)
    return np.sqrt(np.abs(-8.0 * k**3 * (1.0 + lam * lam) ** 2.5 / (9.0 * _den(lam, k, ks))))


def I_scp2(lam, k, ks):
    """Eq. (19): b of the semicubical parabola."""
    lam = np.asarray(lam, float)
    return lam + np.asarray(k, float) ** 2 * (1.0 + lam * lam) / _den(lam, k, ks)


def slope_angles(k1, ks1, k2, ks2, delta, kk):
    """Canonical tangent angles ψ₁ (mod π) at which λ + kk·κ²(1+λ²)/(κ_s+3λκ²) takes the
    same value at touch 1 (λ₁ = tan ψ₁) and touch 2 (λ₂ = tan(ψ₁ + Δ)), Δ = φ₂ − φ₁.

    Returns (ψ list, residual): 0, 1 or 2 angles; a negative discriminant is clipped to
    its nearest (double) root and the clipped amount returned as residual."""
    cd, sd = math.cos(delta), math.sin(delta)
    a1, a2 = k1 * k1, k2 * k2
    A = -a1 * (kk + 3) * (cd * cd * ks2 + 3 * cd * a2 * sd - ks2)
    B = (6 * cd * cd * kk * a1 * a2 + 9 * cd * cd * a1 * a2 - cd * cd * ks1 * ks2 - 2 * cd * kk * a1 * ks2 * sd
         - 3 * cd * a1 * ks2 * sd - 3 * cd * a2 * ks1 * sd - 6 * kk * a1 * a2 - 9 * a1 * a2 + ks1 * ks2)
    C = (cd * cd * kk * a1 * ks2 + 3 * cd * cd * a2 * ks1 + 3 * cd * kk * a1 * a2 * sd - cd * ks1 * ks2 * sd
         - kk * a2 * ks1 - 3 * a2 * ks1)
    # A s² + B s c + C c² = (A+C)/2 + R cos(2ψ − β)
    R = math.hypot((C - A) / 2, B / 2)
    if R == 0:
        return [], float("inf")
    beta = math.atan2(B / 2, (C - A) / 2)
    ratio = -(A + C) / (2 * R)
    resid = max(0.0, abs(ratio) - 1.0)
    g = math.acos(min(max(ratio, -1.0), 1.0))
    roots = [0.5 * (beta + g), 0.5 * (beta - g)]
    if g == 0.0:
        roots = roots[:1]
    return [math.atan(math.tan(r)) for r in roots], resid


def propagate(fn, values, cov_blocks, eps=1e-7):
    """First-order variance of fn(*values) given 2×2 covariances of (κ, κ_s) pairs.

    ``values`` is (κ₁, κ_s1, κ₂, κ_s2, ...) and ``cov_blocks`` one 2×2 matrix per pair;
    the derivative is a central difference with a relative step."""
    values = np.asarray(values, float)
    var = 0.0
    for i, cov in enumerate(cov_blocks):
        if not np.any(cov):
            continue
        g = np.zeros(2)
        for j in range(2):
            idx = 2 * i + j
            h = eps * max(abs(values[idx]), 1e-300)
            up, dn = values.copy(), values.copy()
            up[idx] += h
            dn[idx] -= h
            g[j] = (fn(*up) - fn(*dn)) / (2 * h)
        var += float(g @ cov @ g)
    return var
