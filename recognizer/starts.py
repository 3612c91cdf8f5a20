"""Closed-form starting points of the contact fit, per class (paper §§2–4, errata in docs/recognition.md).

For one class and the touches' local geometry (data in the class's canonical direction,
recognizer.localize flips them first), each start is (params, t per touch):

- line: the mean tangent direction; circle: r = 1/mean κ and the centre;
- ellipse, hyperbola: a, b from I_c1, I_c2 (eqs. 9, 10) of the best-conditioned pair, with
  sin²t = ((ab/κ)^{2/3} − b²)/(a² − b²) (quadrant from sign(sin t cos t) = −sign κ_s and
  the half-turn from the tangent), sinh²t = ((ab/|κ|)^{2/3} − b²)/(a² + b²),
  sign t = sign κ_s; and the conic through the touches' positions and tangents
  (``conic_start``), which does not lean on κ_s; the hyperbola also from a scan of its
  branch's shape and location (``hyperbola_scan``), far out on an arm where κ, κ_s are
  barely measured, and the ellipse, with every start, from one of its shape and location
  (``ellipse_scan``), along the valley of ellipses a short stretch fits;
- parabola: a from I_p, t = κ_s/(3κ²);
- cubical and semicubical parabolas: the canonical tangent angle ψ from
  ``invariants.slope_angles`` (both roots; for the semicubical both branches t ≷ 0), then
  a, c (a, b) from I_cp1/I_cp2 (I_scp1/I_scp2), t = ±√((λ − c)/(3a)) with the sign of
  κ/a (resp. 2(λ − b)/(3a)); for the semicubical also a scan of its shape and location
  that leans on positions and tangents first (``semicubical_scan``).

``pose_from`` places a start: θ the circular mean of φ_i − φ(t_i), (x, y) the mean of
p_i − R(θ)·p(t_i), and scores it by the position-and-angle χ².
"""

from __future__ import annotations

import itertools
import math

import numpy as np

from recognizer import invariants as inv
from recognizer.contacts import Contacts
from recognizer.curves import CURVES
from recognizer.solver import KERNELS
from tactile_common.angles import wrap_angle

__all__ = ["starts", "pose_from", "conic_start", "inflection_start", "cubical_scan", "semicubical_scan", "hyperbola_scan", "hyperbola_asymptote", "ellipse_scan", "clear_of_cusp",
           "cusp_clearance"]

_PI = math.pi


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


def pose_from(cls: str, params: dict, t, d: Contacts) -> tuple[float, float, float, float]:
    """Pose putting the curve points at t onto the touches (θ the circular mean of the angle
    differences, (x, y) the mean offset) and its position-and-angle χ² (inf when not finite)."""
    kern = KERNELS[cls]
    p = tuple(params[k] for k in CURVES[cls].param_names)
    fr = [kern(p, ti) for ti in t]
    rows = d.rows()
    dph = [row[2] - f[2] for row, f in zip(rows, fr)]
    th = _circmean_s(dph)
    ct, st = math.cos(th), math.sin(th)
    ex = [row[0] - (ct * f[0] - st * f[1]) for row, f in zip(rows, fr)]
    ey = [row[1] - (st * f[0] + ct * f[1]) for row, f in zip(rows, fr)]
    X, Y = _mean(ex), _mean(ey)
    cost = sum(((X - a) ** 2 + (Y - b) ** 2) / row[5] ** 2 + (wrap_angle(th - c) / row[6]) ** 2
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


def conic_start(cls: str, d: Contacts) -> list[tuple[dict, list]]:
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


#: a sum over an axis shorter than this NumPy adds left to right, from +0.0 (longer ones
#: pairwise, eight partial sums at a time)
SEQUENTIAL_SUM = 8


def sum_last(a: np.ndarray, keepdims: bool = False) -> np.ndarray:
    """``a.sum(-1)`` over the touches' (last) axis of a scan's grid, the same bits: NumPy adds
    an axis of fewer than ``SEQUENTIAL_SUM`` entries left to right from +0.0 in one inner
    loop per output element, ~15× the time of the same adds made elementwise over the grid
    (75 × 81 outputs of 3 touches: 97 against 7 µs); so here 0.0 + a₀ + a₁ + …, in that
    order (tests/recognizer/test_scan_sums.py checks the bits against NumPy's); a longer
    axis by NumPy itself."""
    n = a.shape[-1]
    if not 0 < n < SEQUENTIAL_SUM:
        return a.sum(-1, keepdims=keepdims)
    s = a[..., 0] + 0.0
    for i in range(1, n):
        s = s + a[..., i]
    return s[..., None] if keepdims else s


def all_last(a: np.ndarray) -> np.ndarray:
    """``np.all(a, axis=-1)`` of a boolean grid as a₀ & a₁ & … (the same values; NumPy's
    reduction over a short last axis is as slow as its sum, ``sum_last``)."""
    s = a[..., 0].copy()
    for i in range(1, a.shape[-1]):
        s &= a[..., i]
    return s


def _scan_data(d: Contacts):
    """What both scans score against: positions, φ, κ, κ_s, the positions' weights
    1/σ_pos² and the (κ, κ_s) whitener."""
    x, y, phi, k, ks = (np.asarray(c, float) for c in d.cols())
    w_pos = np.array([1.0 / r[5] ** 2 for r in d.rows()])
    return x, y, phi, k, ks, w_pos, d.whitener()


def _similarity_fit(x, y, w_pos, th, px, py):
    """Weighted least squares of the touches' positions by scale · R(θ)·(px, py) +
    translation over broadcast scan points (θ broadcastable against px): (scale, χ² of
    the positions)."""
    c, s_ = np.cos(th), np.sin(th)
    qx, qy = c * px - s_ * py, s_ * px + c * py
    wsum = w_pos.sum()
    dx, dy = x - (w_pos * x).sum() / wsum, y - (w_pos * y).sum() / wsum
    dqx = qx - sum_last(w_pos * qx, keepdims=True) / wsum
    dqy = qy - sum_last(w_pos * qy, keepdims=True) / wsum
    scale = sum_last(w_pos * (dx * dqx + dy * dqy)) / sum_last(w_pos * (dqx**2 + dqy**2))
    sc = scale[..., None]
    return scale, sum_last(w_pos * ((dx - sc * dqx) ** 2 + (dy - sc * dqy) ** 2))


def _similarity_pose(x, y, w_pos, th, scale, px, py):
    """The translation of ``_similarity_fit``'s solution: weighted mean position minus
    scale · R(θ)·(weighted mean of (px, py))."""
    c, s_ = np.cos(th), np.sin(th)
    wsum = w_pos.sum()
    mx = sum_last(w_pos * (c * px - s_ * py)) / wsum
    my = sum_last(w_pos * (s_ * px + c * py)) / wsum
    return (w_pos * x).sum() / wsum - scale * mx, (w_pos * y).sum() / wsum - scale * my


#: a semicubical scan point is admissible when every touch's contact lies at least this
#: fraction of its reach (``Contacts.reach``) from the cusp along the curve (the scan's
#: scale and placement are approximate: the truth lies at ≥ 1 reach)
CUSP_CLEAR = 1.0
#: rounds of placing the touches by their positions in a scan (``_placed``), Newton steps each
PLACE_ROUNDS, PLACE_STEPS = 1, 3


def _placed(x, y, w_pos, th, t, point, deriv, keep):
    """A scan point's touches after 1..n placed by their positions (touch 0 stays: it and
    its tangent fix the frame): each moved to the scale-free curve's point nearest its
    position mapped into the curve's frame (``PLACE_STEPS`` Gauss–Newton steps of the
    distance, ``keep(t_old, t_new)`` keeping a step on its piece of the curve), then the
    scale and translation fitted again; ``PLACE_ROUNDS`` rounds. Far out on a branch or an
    arm the tangent barely turns, so a touch placed by its tangent angle alone is placed by
    the angle's noise (the semicubical's v moves 0.4 per 1.5 mrad where its slope is 20):
    positions place it along the curve to within their own deviation. Returns (t, scale,
    position χ²)."""
    c, s_ = np.cos(th)[..., None], np.sin(th)[..., None]
    px, py = point(t)
    scale, _ = _similarity_fit(x, y, w_pos, th[..., None], px, py)
    for _ in range(PLACE_ROUNDS):
        # a negative scale: the touches' order along the curve is wrong (placed by tangents
        # that barely turn); the positions place them again at the scale's size
        scale = np.abs(scale)
        tx, ty = _similarity_pose(x, y, w_pos, th[..., None], scale, px, py)
        sc = np.where(scale > 0, scale, np.nan)[..., None]
        dx, dy = x - tx[..., None], y - ty[..., None]
        qx, qy = (c * dx + s_ * dy) / sc, (c * dy - s_ * dx) / sc
        for _ in range(PLACE_STEPS):
            px, py = point(t)
            dpx, dpy = deriv(t)
            step = ((qx - px) * dpx + (qy - py) * dpy) / (dpx * dpx + dpy * dpy)
            moved = keep(t, t + step)
            moved[..., 0] = t[..., 0]
            t = np.where(np.isfinite(moved), moved, t)
        px, py = point(t)
        scale, cost = _similarity_fit(x, y, w_pos, th[..., None], px, py)
    return t, scale, cost


def _curvature_chi2(W, rk, rks):
    """χ² of the κ, κ_s residuals under the whitener ``W`` (one 2×2 per touch)."""
    r0 = W[:, 0, 0] * rk + W[:, 0, 1] * rks
    r1 = W[:, 1, 0] * rk + W[:, 1, 1] * rks
    return sum_last(r0 * r0 + r1 * r1)


def _separated_best(cost: np.ndarray, n_best: int) -> list[tuple[int, int]]:
    """Grid indices (i, j) of a scan's lowest finite costs, best first, each more than 4
    steps of i or 6 of j from every one kept before it, at most ``n_best``."""
    kept: list[tuple[int, int]] = []
    for flat in np.argsort(cost, axis=None)[: 50 * n_best]:
        i, j = (int(q) for q in np.unravel_index(flat, cost.shape))
        if not np.isfinite(cost[i, j]) or len(kept) == n_best:
            break
        if not any(abs(i - ii) <= 4 and abs(j - jj) <= 6 for ii, jj in kept):
            kept.append((i, j))
    return kept


def _arc_sf(u, b):
    """Antiderivative of the scale-free semicubical's (v², v³ + b v²) speed in u = 3v + 2b
    (recognizer.curves.SemicubicalParabola._arc with a = 1): its arc length from the cusp
    to v is |_arc_sf(3v + 2b) − _arc_sf(2b)|."""
    r = np.hypot(2.0, u)
    return (r**3 / 3 - 2 * b * (u * r / 2 + 2 * np.arcsinh(u / 2))) / 9


def _scan_cost(d: Contacts, b: np.ndarray, v0: np.ndarray, sg: float):
    """The semicubical scan's score at shapes b and first-touch coordinates v0 on branch
    sg (broadcast arrays): χ² of positions, κ and κ_s with φ fitted exactly; returns
    (cost, v per touch, scale 1/a²), cost inf where a touch's v is not on the branch its
    tangent angle points to (the other touches may lie on either branch), and v and scale
    NaN there: each point's score is its own, so such points are scored no further."""
    x, y, phi, k, ks, w_pos, W = _scan_data(d)
    sig_phi = np.array([r[6] for r in d.rows()])
    th = phi[0] - np.arctan2(sg * (3 * v0 + 2 * b), 2 * sg)
    psi = wrap_angle(phi - th[..., None])
    b = np.broadcast_to(b, th.shape)[..., None]
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        v = (2 * np.tan(psi) - 2 * b) / 3
        # each touch on the branch its tangent points to: ψ within ±π/2 on v > 0, beyond on v < 0
        branch = all_last((np.abs(psi) < _PI / 2) == (v > 0))
        cost_all, v_all, scale_all = np.full(th.shape, np.inf), np.full(v.shape, np.nan), np.full(th.shape, np.nan)
        if not branch.any():
            return cost_all, v_all, scale_all
        th, v, b = th[branch], v[branch], b[branch]  # the admissible points alone, in a row
        v, scale, cost = _placed(x, y, w_pos, th, v, lambda u: (u * u, u * u * (u + b)),
                                 lambda u: (2 * u, u * (3 * u + 2 * b)),
                                 lambda u, un: np.where(un * u > 0, un, 0.5 * u))
        ok = scale > 0
        sc = scale[..., None]
        sg = np.where(v > 0, 1.0, -1.0)
        u = 3 * v + 2 * b
        if d.reach > 0:  # a pad cannot roll through the cusp: every touch reaches clear of it
            ok &= all_last(sc * np.abs(_arc_sf(u, b) - _arc_sf(2 * b, b)) >= CUSP_CLEAR * d.reach)
        q = 4.0 + u * u
        rphi = wrap_angle(phi - th[..., None] - np.arctan2(sg * u, 2 * sg)) / sig_phi
        rk = k - 6.0 / (np.abs(v) * q**1.5) / sc
        rks = ks + 6.0 * (q + 9 * u * v) / (v**3 * q**3) / (sc * sc)
        cost = cost + sum_last(rphi * rphi) + _curvature_chi2(W, rk, rks)
    cost_all[branch] = np.where(ok & np.isfinite(cost), cost, np.inf)
    v_all[branch], scale_all[branch] = v, scale
    return cost_all, v_all, scale_all


def _scan_start(b: float, scale: float, v) -> tuple[dict, list]:
    """The semicubical start of a scan point: a = 1/√scale, t = v/a."""
    root = math.sqrt(float(scale))
    return {"a": 1.0 / root, "b": float(b)}, [float(vi) * root for vi in v]


def semicubical_scan(d: Contacts, n_best: int = 4) -> list[tuple[dict, list]]:
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

    The best ``n_best`` separated scan points are returned (``_separated_best`` on each
    branch, then the best of both), and on each branch the best
    point without a turning point (b·v ≥ 0) when none of those is one. A branch with a
    turning point (b·v < 0: its slope (3v + 2b)/2 passes through 0 at v = −2b/3,
    parabola-like around it) and one without can fit a stretch touched on one branch far
    from the cusp equally well, and the score, which fits φ exactly, falls slowly along
    that valley towards the parabola limit |b| → ∞: the best points by score all have a
    turning point, and the contact fit and the refinement started there stop at their
    iteration budgets (40) long before the valley's other end (tools.bench_wide seed 5,
    semicubical trial 13 after two suggested touches: the 4 best points refined to
    χ² 116–168, the best one without a turning point to the truth's 102.9)."""
    bs = np.sinh(np.linspace(-math.asinh(SCAN_B), math.asinh(SCAN_B), SCAN_NB))
    g = np.geomspace(*SCAN_V, SCAN_NV)
    found, extra = [], []
    for sg in (1.0, -1.0):
        v0 = sg * g[None, :] * np.maximum(1.0, np.abs(bs))[:, None]
        cost, v, scale = _scan_cost(d, bs[:, None], v0, sg)
        found += [(float(cost[i, j]), sg, i, j, _scan_start(bs[i], scale[i, j], v[i, j]))
                  for i, j in _separated_best(cost, n_best)]
        without = np.where((bs * sg >= 0)[:, None], cost, np.inf)
        i, j = np.unravel_index(int(np.argmin(without)), cost.shape)
        if np.isfinite(without[i, j]):
            extra.append((float(without[i, j]), sg, int(i), int(j), _scan_start(bs[i], scale[i, j], v[i, j])))
    found.sort(key=lambda f: f[:4])
    found = found[:n_best]
    found += [e for e in extra if not any(f[1] == e[1] and bs[f[2]] * f[1] >= 0 for f in found)]
    return [start for *_, start in found]


#: the ellipse scan: shape e = b/a on a log grid over SCAN_EE, the first touch's t over
#: [−π/2, π/2) (the half-turn symmetry gives the rest)
SCAN_EE, SCAN_NEE, SCAN_NTE = (1e-2, 1.0), 41, 72


def ellipse_scan(d: Contacts, n_best: int = 3) -> list[tuple[dict, list]]:
    """Starts for the ellipse from the tangent angles and positions first.

    On a short stretch κ_s is barely measured and the invariants' start (eqs. 9, 10) and
    the conic through the touches can sit far along the valley of ellipses that fit it
    (tools.bench_wide seeds 9 and 11, short stretches answered semicubical: the ellipse
    refined to χ² 53–66 near the parabola limit, the truth's valley 38–62). The
    scale-free ellipse (cos t, e sin t) (e = b/a ≤ 1) is scanned over e and the first
    touch's t: its tangent angle ψ(t) = atan2(e cos t, −sin t) turns once around, so φ₀
    fixes the frame θ = φ₀ − ψ(t₀) and every other touch's t = atan2(−cos ψᵢ, sin ψᵢ/e);
    the scale a and the translation follow from the positions by linear least squares,
    and the point is scored by the χ² of the positions and of κ = e/(a h³),
    κ_s = −3e(1 − e²) sin t cos t/(a² h⁶) (h = hypot(sin t, e cos t)) under their stated
    deviations. A short stretch fits a whole valley of ellipses, from round ones to the
    parabola limit e → 0, nearly equally well (the score of a stretch of 0.4 rad falls
    towards e → 0 while the refined fit over every sample prefers the truth's e 0.68:
    seed 11 trial 26), so the grid of e is cut into ``n_best`` bands and the best point
    of each is returned."""
    x, y, phi, k, ks, w_pos, W = _scan_data(d)
    e = np.geomspace(*SCAN_EE, SCAN_NEE)[:, None, None]
    t0 = np.linspace(-_PI / 2, _PI / 2, SCAN_NTE, endpoint=False)[None, :, None]
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        th = phi[0] - np.arctan2(e * np.cos(t0), -np.sin(t0))
        psi = phi - th
        tt = np.arctan2(-np.cos(psi), np.sin(psi) / e)
        tt = tt + np.round((t0 - tt[..., :1]) / (2 * _PI)) * 2 * _PI  # the first touch's t exactly t0
        sn, cs = np.sin(tt), np.cos(tt)
        scale, cost = _similarity_fit(x, y, w_pos, th, cs, e * sn)
        sc = scale[..., None]
        h = np.hypot(sn, e * cs)
        rk = k - e / (sc * h**3)
        rks = ks + 3 * e * (1 - e * e) * sn * cs / (sc * sc * h**6)
        cost = np.where((scale > 0) & np.isfinite(cost), cost + _curvature_chi2(W, rk, rks), np.inf)
    best = []
    for rows in np.array_split(np.arange(SCAN_NEE), n_best):  # the valley runs along e: one start per band
        i, j = np.unravel_index(int(np.argmin(cost[rows])), (rows.size, cost.shape[1]))
        if np.isfinite(cost[rows[i], j]):
            best.append((int(rows[i]), int(j)))
    return [({"a": float(scale[i, j]), "b": float(e[i, 0, 0] * scale[i, j])}, tt[i, j].tolist()) for i, j in best]


#: the hyperbola scan: shape e = b/a on a log grid over SCAN_E, the first touch's t over ±SCAN_T
SCAN_E, SCAN_NE = (1e-2, 1e2), 49
SCAN_T, SCAN_NT = 7.0, 71


def hyperbola_scan(d: Contacts, n_best: int = 3) -> list[tuple[dict, list]]:
    """Starts for the hyperbola from the tangent angles and positions first.

    Far out on an arm κ and κ_s are small and poorly measured: the invariants and the
    conic through the touches can miss the right basin altogether. The scale-free branch
    (cosh t, e sinh t) (e = b/a) is scanned over e and the first touch's t: its tangent
    angle ψ(t) = atan2(e cosh t, sinh t) is monotonic, so φ₀ fixes the frame
    θ = φ₀ − ψ(t₀) and every other touch's t from tanh tᵢ = e·cot ψᵢ (a touch whose
    ψᵢ lies outside the branch's range makes the point inadmissible); the scale a and the
    translation follow from the positions by linear least squares, and the point is scored
    by the χ² of the positions and of κ = −e/(a h³), κ_s = 3e(1 + e²) sinh t cosh t/(a² h⁶)
    (h = hypot(sinh t, e cosh t), eqs. 6–7's quantities) under their stated deviations.
    The best ``n_best`` points separated on the grid (``_separated_best``) are returned."""
    x, y, phi, k, ks, w_pos, W = _scan_data(d)
    e = np.geomspace(*SCAN_E, SCAN_NE)[:, None, None]
    t0 = np.linspace(-SCAN_T, SCAN_T, SCAN_NT)[None, :, None]
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        th = phi[0] - np.arctan2(e * np.cosh(t0), np.sinh(t0))
        psi = wrap_angle(phi - th)
        ok = all_last((psi > 0) & (psi < _PI))
        tt = np.arctanh(e * np.cos(psi) / np.sin(psi))
        ok &= all_last(np.isfinite(tt))
        ch, sh = np.cosh(tt), np.sinh(tt)
        scale, cost = _similarity_fit(x, y, w_pos, th, ch, e * sh)
        ok &= scale > 0
        sc = scale[..., None]
        h = np.hypot(sh, e * ch)
        rk = k + e / (sc * h**3)
        rks = ks - 3 * e * (1 + e * e) * sh * ch / (sc * sc * h**6)
        cost = np.where(ok & np.isfinite(cost), cost + _curvature_chi2(W, rk, rks), np.inf)
    return [({"a": float(scale[i, j]), "b": float(e[i, 0, 0]) * float(scale[i, j])}, tt[i, j].tolist())
            for i, j in _separated_best(cost, n_best)]


#: the asymptote start: the touched stretch at t FAR_T[0] … FAR_T[1] of a rectangular hyperbola
FAR_T = (3.0, 4.5)


def hyperbola_asymptote(d: Contacts) -> list[tuple[dict, list]]:
    """Hyperbola starts far out on an arm, from the touches' positions along their tangent.

    Far out on an arm (t ≳ 3) the tangent is within its noise of the asymptote's, so a
    touch placed by its tangent angle (``hyperbola_scan``) is placed by noise, or nowhere
    (e·cot ψ beyond 1), and the touches' κ, κ_s and the bends of their positions and
    tangents are noise: they tell neither the centre's distance along the asymptote nor
    which way the arm bends (tools.bench_wide --set wide seed 1, hyperbola trial 7: a
    curve d = K/s across the asymptote fitted to them bends the wrong way at every
    distance). The samples tell: the refinement over every sample reaches the truth's
    basin from a band of starts two decades wide in a (seed 1, trial 3: a 0.002–0.2 for a
    truth of 0.007, the touches at t 3.2–5.4). So the start puts the touched stretch at
    t ``FAR_T`` of the rectangular hyperbola (a = b; along its asymptote
    s = a e^{|t|}/√2 from the centre) whose asymptote runs along the touches' mean
    tangent: its a from the stretch's length along it, each touch's t from its position
    along it, on either side: moving away from the centre (t > 0, the centre behind the
    touches) or toward it (t < 0, ahead)."""
    if d.n < 2:
        return []
    x, y, phi = (np.asarray(c, float) for c in d.cols()[:3])
    al = _circmean_s(phi.tolist())
    sa = (x - x.mean()) * math.cos(al) + (y - y.mean()) * math.sin(al)
    span = float(sa.max() - sa.min())
    if not (span > 0 and np.all(np.isfinite(sa))):
        return []
    lo, hi = math.exp(FAR_T[0]), math.exp(FAR_T[1])
    a = math.sqrt(2.0) * span / (hi - lo)
    out = []
    for sign, s in ((1.0, sa - sa.min()), (-1.0, sa.max() - sa)):  # |s| − a·e^{t_lo}/√2 from the near end
        t = sign * np.log(math.sqrt(2.0) * s / a + lo)
        out.append(({"a": a, "b": a}, t.tolist()))
    return out


def starts(cls: str, d: Contacts, every_pair: bool = False) -> list[tuple[dict, list]]:
    """Closed-form (params, t) starting points for a class (data in canonical direction):
    ellipse and hyperbola from the invariants and from the conic through the touches
    (``conic_start``), the hyperbola also from ``hyperbola_scan``, the ellipse with ``every_pair``
    from ``ellipse_scan``; the cubic classes by ``_cubic_starts``."""
    x, y, phi, k, ks = d.cols()
    if cls == "line":
        th = _circmean_s(phi)
        c, s = math.cos(th), math.sin(th)
        mx, my = _mean(x), _mean(y)
        return [({}, [(xi - mx) * c + (yi - my) * s for xi, yi in zip(x, y)])]
    if cls == "circle":
        # the constant κ's maximum-likelihood value: each κ weighed by its inverse variance
        # (plain mean with zero covariance): the plain mean let one badly measured κ decide
        # (a jaw touch rolled across a pad's end, κ −31 ± 159 beside three of 2.3–2.7 ± 0.3–0.4
        # /unit: mean negative, no circle start, no circle fit, and an ellipse b/a 0.997 was
        # the answer: tools.bench_explore --finite 10 --anywhere --seed 61, X-series circle 18)
        var = d.cov[:, 0, 0]
        mk = float(np.sum(d.kappa / var) / np.sum(1.0 / var)) if np.all(var > 0) and np.all(np.isfinite(var)) \
            else _mean(k)
        if not mk > 0:
            return []
        r = 1.0 / mk
        cx = _mean([xi - r * math.sin(f) for xi, f in zip(x, phi)])
        cy = _mean([yi + r * math.cos(f) for yi, f in zip(y, phi)])
        return [({"r": r}, [math.atan2(yi - cy, xi - cx) for xi, yi in zip(x, y)])]
    if cls in ("ellipse", "hyperbola"):  # the invariants divide by κ; the conic through the touches does not
        out = (_conic_invariant_starts(cls, d) if 0.0 not in k else []) + conic_start(cls, d)
        if cls == "hyperbola" and d.n >= 2:
            out += hyperbola_scan(d)
        elif every_pair and d.n >= 2:
            out += ellipse_scan(d)
        return out
    if cls == "parabola":
        if 0.0 in k:  # I_p divides by κ: no start
            return []
        each = [1.0 / (2.0 * inv.I_p_s(ki, ksi) ** 1.5) for ki, ksi in zip(k, ks)]
        a = _median(each)
        out = [({"a": a}, [ksi / (3.0 * ki * ki) for ki, ksi in zip(k, ks)])] if a > 0 and math.isfinite(a) else []
        # κ is measured far better than κ_s: for every touch's a (and the median), |t| from
        # |κ| = 1/(2a(1 + t²)^{3/2}) (eq. 3), each touch's side of the vertex the one whose
        # tangent angles and positions fit best (κ_s's sign, eq. 4, is noise far out)
        for ai in sorted({v for v in each + [a] if v > 0 and math.isfinite(v)}):
            mag = [math.sqrt(max((2.0 * ai * abs(ki)) ** (-2.0 / 3.0) - 1.0, 0.0)) for ki in k]
            best = min((pose_from("parabola", {"a": ai}, [m * sg for m, sg in zip(mag, signs)], d)[3], signs)
                       for signs in _vertex_sides(phi))
            out.append(({"a": ai}, [m * sg for m, sg in zip(mag, best[1])]))
        return out
    return _cubic_starts(cls, d, every_pair)


#: up to this many touches every assignment of touches to the vertex's sides is tried (2^n)
EXHAUSTIVE_SIDES = 8


def _vertex_sides(phi):
    """Candidate sides (±1 per touch) of a parabola's vertex: every assignment for up to
    ``EXHAUSTIVE_SIDES`` touches; beyond, only those consistent with the tangent angle's
    monotony along the curve (the touches in order of φ, unwrapped after the largest gap
    since a parabola's tangents span less than π, split once, in either direction): 2(n + 1)
    assignments instead of 2^n (20 touches took minutes)."""
    n = len(phi)
    if n <= EXHAUSTIVE_SIDES:
        return list(itertools.product((1.0, -1.0), repeat=n))
    order = sorted(range(n), key=lambda i: phi[i] % (2 * _PI))
    ang = [phi[i] % (2 * _PI) for i in order]
    gaps = [(ang[(r + 1) % n] - ang[r]) % (2 * _PI) for r in range(n)]
    start = (max(range(n), key=gaps.__getitem__) + 1) % n
    order = order[start:] + order[:start]
    out = []
    for k in range(n + 1):
        signs = [0.0] * n
        for rank, i in enumerate(order):
            signs[i] = -1.0 if rank < k else 1.0
        out += [tuple(signs), tuple(-v for v in signs)]
    return out


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
        psi = [KERNELS["ellipse"]((a, b), t)[2] for t in t0]
        th = phi[0] - psi[0]
        return [({"a": a, "b": b}, [t + _PI if abs(wrap_angle(p + th - f)) > _PI / 2 else t
                                    for t, p, f in zip(t0, psi, phi)])]
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
    of its shape and location (``semicubical_scan``)."""
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
        lam = [math.tan(wrap_angle(f - th)) for f in phi]
        dens = [ksi + 3.0 * li * ki * ki for li, ki, ksi in zip(lam, k, ks)]
        if cls == "cubical_parabola":
            a = _median([de * (1.0 + li * li) ** 2 / 6.0 for li, de in zip(lam, dens)])
            c = _median([li - _div(ki * ki * (1.0 + li * li), 2.0 * de) for li, ki, de in zip(lam, k, dens)])
            if not (math.isfinite(a) and math.isfinite(c)) or a == 0:
                continue
            # |t| from the tangent (λ = 3at² + c), its sign from κ = 6at/(1 + λ²)^{3/2}: on a steep
            # stretch κ is small and noisy, and t = κ(1 + λ²)^{3/2}/(6a) multiplies its error
            out.append(({"a": a, "c": c}, [math.copysign(math.sqrt(max((li - c) / (3 * a), 0.0)), ki / a)
                                           for li, ki in zip(lam, k)]))
        else:
            a = _median([math.sqrt(abs(_div(-8.0 * ki**3 * (1.0 + li * li) ** 2.5, 9.0 * de)))
                         for li, ki, de in zip(lam, k, dens)])
            b = _median([li + _div(ki * ki * (1.0 + li * li), de) for li, ki, de in zip(lam, k, dens)])
            if not (math.isfinite(a) and math.isfinite(b)) or a <= 0:
                continue
            out.append(({"a": a, "b": b}, [2 * (li - b) / (3 * a) for li in lam]))
    if cls == "cubical_parabola" and d.n >= 2:
        out += inflection_start(d)
    if cls == "cubical_parabola" and every_pair and d.n >= 3:
        out += cubical_scan(d)
    if cls == "semicubical_parabola" and every_pair and d.n >= 2:
        out += semicubical_scan(d)
    if cls == "semicubical_parabola" and d.reach > 0:
        out = [st for st in out if clear_of_cusp(st, d.reach)]
    return out


#: rounds of the inflection start's linear solves (each at the arc lengths of the last)
INFLECTION_ROUNDS = 3


def inflection_start(d: Contacts) -> list[tuple[dict, list]]:
    """A cubical start from the touches in their own frame, not leaning on the slope
    equation: near its inflection a cubical of slope c runs along its tangent line with,
    s the arc length from the inflection and A = a/(1 + c²)², κ = 6A·s and κ_s = 6A −
    180·A²·c·s² (to the first order in c·A·s²). The touches' κ = p·(sᵢ − s₀) and
    κ_s = p − r·(sᵢ − s₀)² (sᵢ along their mean tangent), whitened, fitted by least squares
    (linear in p, q = −p·s₀, then r at that s₀) give A = p/6, the inflection s₀ and
    c = r/(5p²); then a = A(1 + c²)² and tᵢ = (sᵢ − s₀)/√(1 + c²). On a steep stretch
    (c ≥ 3e4) the slope equation's λ = tan ψ carries λ − c = 3at² below its rounding and its
    starts land 1e14 and more away (a steep cubical got no fit: answered line naming no
    cubical)."""
    x, y, phi, k, ks = d.cols()
    rows = d.rows()
    ang = _circmean_s(phi)
    ca, sa = math.cos(ang), math.sin(ang)
    xm, ym = _mean(x), _mean(y)
    u = np.array([(xi - xm) * ca + (yi - ym) * sa for xi, yi in zip(x, y)])
    w = np.array([r[7:11] for r in rows])  # (W₀₀, W₀₁, W₁₀, W₁₁): inverse Cholesky factor of each (κ, κ_s) covariance
    k, ks = np.array(k), np.array(ks)
    # κ = p·u + q, κ_s = p − r·s² with s = u + q/p: linear in (p, q, r) at s fixed, s from the last solve
    s, r = u, 0.0
    with np.errstate(all="ignore"):
        for _ in range(INFLECTION_ROUNDS):
            m = np.concatenate((np.column_stack((w[:, 0] * u, w[:, 0], 0.0 * u)),
                                np.column_stack((w[:, 2] * u + w[:, 3], w[:, 2], -w[:, 3] * s * s))))
            rhs = np.concatenate((w[:, 0] * k, w[:, 2] * k + w[:, 3] * ks))
            (p, q, r), *_ = np.linalg.lstsq(m, rhs, rcond=None)
            if not (p != 0 and math.isfinite(p) and math.isfinite(q) and math.isfinite(r)):
                return []
            s = u + q / p
        p = float(p)
        if not 5.0 * p * p > 0:  # underflow
            return []
        c = float(r) / (5.0 * p * p)
        g = 1.0 + c * c
        a = p / 6.0 * g * g
        if not (math.isfinite(a) and a != 0):
            return []
        return [({"a": a, "c": c}, [float(v) for v in s / math.sqrt(g)])]


#: the cubical scan: the frame angle θ on a grid of this many points over the full turn, each
#: local minimum then narrowed ``SCAN_ZOOMS`` times by a grid of ``SCAN_NZOOM`` points over the
#: last grid's two neighbouring steps (far on one side λ is steep, and 0.5° of θ moves it by
#: (1 + λ²)·0.0087: at λ 6.5, by 0.37)
SCAN_NTH, SCAN_ZOOMS, SCAN_NZOOM = 720, 4, 21


def _cubical_scan_data(d: Contacts) -> tuple:
    """What ``_cubical_scan_cost`` scores against, computed once per scan (its ~15 calls, the
    zooms, share it): ``_scan_data``, the φ deviations, the positions' weight sum and the
    positions from their weighted mean."""
    x, y, phi, k, ks, w_pos, W = _scan_data(d)
    sig_phi = np.array([r[6] for r in d.rows()])
    wsum = w_pos.sum()
    return phi, k, ks, w_pos, W, sig_phi, wsum, x - (w_pos * x).sum() / wsum, y - (w_pos * y).sum() / wsum


def _cubical_scan_cost(data: tuple, th: np.ndarray):
    """``cubical_scan``'s score at frame angles ``th`` (1-D) on ``_cubical_scan_data``:
    (cost, a, c, t per touch), cost inf where a touch's tangent lies beyond ±π/2 of θ or
    the slopes give no a."""
    phi, k, ks, w_pos, W, sig_phi, wsum, dx, dy = data
    th = th[:, None]
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        psi = wrap_angle(phi - th)
        ok = all_last(np.abs(psi) < _PI / 2)
        lam = np.where(ok[:, None], np.tan(psi), 0.0)
        u = np.cos(th) * dx + np.sin(th) * dy
        v = np.cos(th) * dy - np.sin(th) * dx
        q = 1.0 + lam * lam
        one, zero = np.ones_like(u), np.zeros_like(u)
        # linear in (A₂, A₁, A₀, B₀), each row whitened: λ = A₂u² + A₁u + A₀ (λ's deviation
        # from φ's), κ(1 + λ²)^{3/2} = 2A₂u + A₁ (= 6at), v = A₂u³/3 + A₁u²/2 + A₀u + B₀
        # (a position's error along u moves v by λ times it)
        m = np.concatenate((np.stack((u * u, u, one, zero), -1) / (q * sig_phi)[..., None],
                            np.stack((2.0 * u, one, zero, zero), -1) * (W[:, 0, 0] / q**1.5)[..., None],
                            np.stack((u**3 / 3.0, 0.5 * u * u, u, one), -1) * np.sqrt(w_pos / q)[..., None]), axis=1)
        b = np.concatenate((lam / (q * sig_phi), one * (k * W[:, 0, 0]), v * np.sqrt(w_pos / q)), axis=1)
        lhs = np.einsum("nki,nkj->nij", m, m)
        rhs = np.einsum("nki,nk->ni", m, b)
        good = ok & np.all(np.isfinite(lhs), axis=(1, 2)) & np.all(np.isfinite(rhs), axis=1)
        good[good] &= np.abs(np.linalg.det(lhs[good])) > 0
        coef = np.full(rhs.shape, np.nan)
        if np.any(good):
            coef[good] = np.linalg.solve(lhs[good], rhs[good][..., None])[..., 0]
        a2, a1, a0 = coef[:, 0], coef[:, 1], coef[:, 2]
        u0 = -a1 / (2.0 * a2)
        a, c = a2 / 3.0, a0 - a2 * u0 * u0
        t = u - u0[:, None]
        curve_v = a[:, None] * t**3 + c[:, None] * t
        v0 = sum_last(w_pos * (v - curve_v)) / wsum
        rv = v - v0[:, None] - curve_v
        lam_t = 3.0 * a[:, None] * t * t + c[:, None]
        q = 1.0 + lam_t * lam_t
        rphi = (np.arctan(lam_t) - psi) / sig_phi
        rk = k - 6.0 * a[:, None] * t / q**1.5
        rks = ks - (6.0 * a[:, None] * q - 108.0 * a[:, None] ** 2 * t * t * lam_t) / q**3
        cost = sum_last(w_pos * rv * rv / q) + sum_last(rphi * rphi) + _curvature_chi2(W, rk, rks)
        cost = np.where(good & (a != 0) & np.isfinite(cost), cost, np.inf)
    return cost, a, c, t


def cubical_scan(d: Contacts, n_best: int = 3) -> list[tuple[dict, list]]:
    """Starts for the cubical parabola from the tangent angles and positions first.

    Far on one side of the inflection the touches' tangents turn little, κ_s is barely
    measured, and the slope equation's frames can all miss the truth's valley
    (tools.bench_sigma seed 103, a cubical far on one side: every start ended at a of the
    other sign, 108 stated σ from the truth, whose valley lay Δχ² 2.2 above it). Here the
    frame angle θ is scanned over the full turn: in the frame the curve is
    (u₀ + t, v₀ + a t³ + c t), its slope λ = 3a(u − u₀)² + c a quadratic in the touches'
    coordinates uᵢ along the frame's axis, so the touches' λᵢ = tan(φᵢ − θ) (each within
    ±π/2 of θ: a cubical's tangent never turns past the vertical, and a half-turned frame
    is the curve traversed the other way), with their κᵢ(1 + λᵢ²)^{3/2} = 6a(uᵢ − u₀) and
    their positions across the axis (a cubic in uᵢ of the same coefficients), give a, c
    and u₀ by weighted linear least squares, v₀ the positions' weighted mean offset (from
    the slopes alone, exact for three touches, the noise of three steep slopes went into
    a, c, u₀ whole: far on one side the scan missed the lowest valley, tools.bench_sigma
    seed 113 trial 15, z −5.4 in a valley Δχ² 0.7 above it); each point
    is scored by the χ² of the tangent angles, the positions (an offset across the frame's
    axis is √(1 + λ²) times the offset across the curve, so its square is divided by 1 + λ²,
    as the linear rows weigh it: unweighted, steep touches scored up to 360× their χ² and
    the truth's frame was passed over, tools.bench_sigma seed 181 trial 26, z 55) and
    κ = 6at/(1 + λ²)^{3/2}, κ_s (eq. 13) under their stated deviations. The ``n_best``
    lowest local minima over θ, each narrowed (``SCAN_ZOOMS``), are returned, t = uᵢ − u₀.
    Needs three places: through two, every frame fits."""
    if len(d.places()) < 3:
        return []
    th = np.linspace(-_PI, _PI, SCAN_NTH, endpoint=False)
    data = _cubical_scan_data(d)
    cost = _cubical_scan_cost(data, th)[0]
    n = cost.size
    minima = sorted((i for i in range(n) if np.isfinite(cost[i]) and cost[i] <= cost[i - 1]
                     and cost[i] <= cost[(i + 1) % n]), key=lambda i: cost[i])
    out = []
    for i in minima[:n_best]:
        best, step = float(th[i]), 2.0 * _PI / SCAN_NTH
        for _ in range(SCAN_ZOOMS):
            grid = best + np.linspace(-step, step, SCAN_NZOOM)
            cz = _cubical_scan_cost(data, grid)[0]
            best, step = float(grid[int(np.argmin(cz))]), 2.0 * step / (SCAN_NZOOM - 1)
        cost1, a, c, t = _cubical_scan_cost(data, np.array([best]))
        if np.isfinite(cost1[0]):
            out.append(({"a": float(a[0]), "c": float(c[0])}, t[0].tolist()))
    return out


def clear_of_cusp(start: tuple[dict, list], reach: float) -> bool:
    """Whether every touch of a semicubical start lies at least ``CUSP_CLEAR`` of its reach
    from the cusp along the curve: a touch rolls ``reach`` either side of its contact and
    no pad rolls through a cusp, so a start that puts a touch nearer is not the object
    (tools.bench_wide seed 5, semicubical trial 3 after two suggested touches: the slope
    equation's and the scan's best starts placed a touch 15 mm of arc from the cusp where
    its samples span ±31 mm; their contact fits were consistent, their refinements
    stalled at χ² 4.7e4 with the samples piled at the cusp)."""
    return cusp_clearance(start) >= CUSP_CLEAR * reach


def cusp_clearance(start: tuple[dict, list]) -> float:
    """The shortest arc length (mm) from a semicubical start's cusp to one of its touches."""
    params, t = start
    arc = CURVES["semicubical_parabola"](params).arc_length(np.zeros(len(t)), np.asarray(t, float))
    arc = np.abs(np.asarray(arc, float))
    return float(np.min(arc)) if arc.size and np.all(np.isfinite(arc)) else 0.0
