"""The touches' local geometry as the contact fit sees it: position, tangent angle, κ, κ_s
of every touch with their standard deviations, floors for exact data, the whitener of
each touch's (κ, κ_s) covariance and the same touches seen in the other direction."""

from __future__ import annotations

import math
from dataclasses import InitVar, dataclass

import numpy as np

__all__ = ["Contacts", "EPS_FLOOR", "SAME_PLACE_CHI2"]

#: relative floor of every measurement's standard deviation (exact data, zero covariance)
EPS_FLOOR = 1e-7
#: the touches' κ's, summed in their deviations, decide the direction of travel from this
#: many deviations on (``Contacts.dominant_kappa``)
TURN_Z = 3.0
#: two touches are at one place when their positions and tangent angles differ by less than
#: their noise explains: Δx, Δy, Δφ whitened by the sum of both touches' variances have a
#: squared norm below the χ² quantile of 3 degrees of freedom at 0.999 (16.27), so a touch
#: repeated with the stated noise is one place 999 times in 1000
SAME_PLACE_CHI2 = 16.266236196238129


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
    #: arc length (mm) a touch reaches either side of its contact (half the median roll of
    #: the request's samples-touches; 0 for contacts): no touch rolls through a cusp
    reach: float = 0.0
    #: L (``scale``) when the caller states it: another view of the same touches keeps their
    #: L (the flipped view; the samples of recognizer.classify._samples_conic, whose floors
    #: stay the contacts'); None: computed from the positions when first asked
    extent: InitVar[float | None] = None

    @property
    def n(self) -> int:
        return len(self.x)

    def __post_init__(self, extent: float | None):
        self._scale = extent
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
        if span > 1e-150:  # the floors divide by L²: touches a denormal apart are at one point
            return span
        k = float(np.max(np.abs(self.kappa)))
        return 1.0 / k if k > 1e-150 else 1.0

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
        """A turning whose sign is the direction: the κ's summed in their deviations
        (Σ κᵢ/σ_κᵢ, ``rows``' whitener); where that is below ``TURN_Z`` (κ barely measured,
        far out on an arm) the side of each touch's tangent line on which the others lie,
        in their deviations (a convex piece lies on the side it turns to; pairs whose
        tangents differ by π/2 or more, across a cusp, are left out); 0 when neither says.
        The κ of largest magnitude, which this was, is the worst measured where all are
        small (tools.bench_wide --set wide seed 1, hyperbola trial 3 far on an arm,
        noise-free: κ 1.9e-4 ± 1.6e-4 against −7.5e-5 ± 3e-8 and −1.1e-5 ± 3e-8, flipped
        the wrong way, unclassified)."""
        rows = self.rows()
        z = sum(r[3] * r[7] for r in rows)
        if abs(z) >= TURN_Z:
            return z
        side = 0.0
        for i, ri in enumerate(rows):
            ci, si = math.cos(ri[2]), math.sin(ri[2])
            for j, rj in enumerate(rows):
                dx, dy = rj[0] - ri[0], rj[1] - ri[1]
                if i == j or abs((rj[2] - ri[2] + math.pi) % (2 * math.pi) - math.pi) >= math.pi / 2:
                    continue
                sd = math.sqrt(ri[5] ** 2 + rj[5] ** 2 + (ri[6] * math.hypot(dx, dy)) ** 2)
                side += (ci * dy - si * dx) / sd
        return side if side != 0.0 else z

    def places(self) -> list[list[int]]:
        """The touches grouped by place (docs/recognition.md, touches at one place): i and j
        are at one place when (Δx² + Δy²)/(σ_pos,i² + σ_pos,j²) + Δφ²/(σ_φ,i² + σ_φ,j²) ≤
        ``SAME_PLACE_CHI2`` (the deviations with their floors, Δφ the angle between the tangent lines, either direction), and places
        chain (a touch at one place with either of two is at one place with both). A
        touch repeated at one place tells that place more precisely, never a second
        one: the classes are tested on the number of places, not of touches."""
        rows = self.rows()
        n = len(rows)
        root = list(range(n))

        def find(i: int) -> int:
            while root[i] != i:
                root[i] = root[root[i]]
                i = root[i]
            return i

        for i in range(n):
            xi, yi, fi, _, _, pi, si = rows[i][:7]
            for j in range(i + 1, n):
                xj, yj, fj, _, _, pj, sj = rows[j][:7]
                if _place_chi2(xi - xj, yi - yj, fi - fj, pi * pi + pj * pj, si * si + sj * sj) <= SAME_PLACE_CHI2:
                    root[find(i)] = find(j)
        groups: dict[int, list[int]] = {}
        for i in range(n):
            groups.setdefault(find(i), []).append(i)
        return sorted(groups.values())

    def at_touched_place(self, x, y, phi) -> np.ndarray:
        """Whether a new touch whose contact lies at each (x, y) with tangent φ would be at
        one place with some touch (``places``' rule), its deviations that touch's own (a
        roll like it measures the place as well): the recognizer would count it no new
        place, and its measurement only re-draws that touch's noise."""
        x, y, phi = (np.asarray(v, float) for v in (x, y, phi))
        same = np.zeros(np.broadcast(x, y, phi).shape, bool)
        for xi, yi, fi, _, _, pi, si in (r[:7] for r in self.rows()):
            same |= _place_chi2(x - xi, y - yi, phi - fi, 2.0 * pi * pi, 2.0 * si * si) <= SAME_PLACE_CHI2
        return same

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
                         self.sig_pos, self.sig_phi, self.reach, extent=self.scale)
            f._wl = [(-w00, w01, -w10, w11) for w00, w01, w10, w11 in self._whitener_rows()]
            f._rows = [(x, y, p + np.pi, -k, ks, sp, sf, -w00, w01, -w10, w11)
                       for x, y, p, k, ks, sp, sf, w00, w01, w10, w11 in self.rows()]
            self._flip = f
        return self._flip


def _place_chi2(dx, dy, dphi, var_pos, var_phi):
    """The squared whitened distance of two contacts (``Contacts.places``): (Δx² + Δy²)/var_pos
    + Δφ²/var_phi, Δφ the angle between their tangent lines (either direction), var_pos and
    var_phi the sums of both contacts' variances."""
    dline = np.remainder(np.asarray(dphi, float) + math.pi / 2, math.pi) - math.pi / 2
    return (dx * dx + dy * dy) / var_pos + dline * dline / var_phi

