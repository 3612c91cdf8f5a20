"""A general least-squares ellipse fit of points, the reference ``tactile bench`` compares
the refined recognizer against: scikit-image's EllipseModel when installed (the ``bench``
extra), else the Halír–Flusser direct fit implemented here."""

from __future__ import annotations

import numpy as np

def fit_ellipse_halir_flusser(x: np.ndarray, y: np.ndarray) -> tuple[float, float] | None:
    """Semi-axes (a ≥ b) of the Halír–Flusser (1998) direct least-squares ellipse fit
    (Fitzgibbon's constraint 4AC − B² = 1, numerically stable split), or None."""
    mx, my, sc = x.mean(), y.mean(), max(float(np.ptp(x)), float(np.ptp(y)), 1e-12)
    u, v = (x - mx) / sc, (y - my) / sc
    d1 = np.stack([u * u, u * v, v * v], axis=1)
    d2 = np.stack([u, v, np.ones_like(u)], axis=1)
    s1, s2, s3 = d1.T @ d1, d1.T @ d2, d2.T @ d2
    try:
        t = -np.linalg.solve(s3, s2.T)
    except np.linalg.LinAlgError:
        return None
    m = s1 + s2 @ t
    m = np.array([m[2] / 2, -m[1], m[0] / 2])
    w, vecs = np.linalg.eig(m)
    vecs = np.real(vecs)
    cond = 4 * vecs[0] * vecs[2] - vecs[1] ** 2
    ok = np.flatnonzero(cond > 0)
    if ok.size == 0:
        return None
    a1 = vecs[:, ok[0]]
    coef = np.concatenate([a1, t @ a1])
    return _conic_axes(coef, sc)


def _conic_axes(coef: np.ndarray, scale: float) -> tuple[float, float] | None:
    """Semi-axes of the ellipse A u² + B uv + C v² + D u + E v + F = 0 (scaled by ``scale``)."""
    a, b, c, d, e, f = coef
    mat = np.array([[a, b / 2], [b / 2, c]])
    try:
        center = np.linalg.solve(2 * mat, -np.array([d, e]))
    except np.linalg.LinAlgError:
        return None
    f0 = f + 0.5 * (d * center[0] + e * center[1])
    ev = np.linalg.eigvalsh(mat)
    if np.any(ev * -f0 <= 0):
        return None
    axes = np.sqrt(-f0 / ev) * scale
    return float(max(axes)), float(min(axes))


def fit_ellipse_reference(x: np.ndarray, y: np.ndarray) -> tuple[tuple[float, float] | None, str]:
    """A general least-squares ellipse fit of points: scikit-image's EllipseModel when
    importable, else Halír–Flusser. Returns (semi-axes or None, which)."""
    try:
        from skimage.measure import EllipseModel
    except ImportError:
        return fit_ellipse_halir_flusser(x, y), "Halír–Flusser direct least squares (tools/ellipse_reference.py)"
    import skimage

    name = f"scikit-image {skimage.__version__} EllipseModel"
    pts = np.stack([x, y], axis=1)
    if hasattr(EllipseModel, "from_estimate"):
        model = EllipseModel.from_estimate(pts)
        if not model:
            return None, name
        axes = tuple(float(v) for v in model.axis_lengths)
    else:  # scikit-image < 0.26
        model = EllipseModel()
        if not model.estimate(pts):
            return None, name
        axes = tuple(float(v) for v in model.params[2:4])
    if not all(np.isfinite(axes)):
        return None, name
    return (max(axes), min(axes)), name
