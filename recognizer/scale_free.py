"""The recognizer's numerics in scale-free units: lengths in units of the touches' spread.

Every fit, floor and step of the recognizer is tuned on touches that span ~1–100 mm; at
1e-4 mm or 1e5 mm its constants in mm (a forward-difference step, a σ floor, a default
position noise) meant something else, and the stated σ's covered the truth less well at
the extremes (tools.bench_sigma, samples, seed 1: 92.7–94.7 % within 1.96 σ at 1e-4 and
1e5 mm against 98.3 % at every decade between). So ``recognize`` works on the request with
positions measured from O, the middle of the touches' positions, and every length divided
by U, the power of two nearest the touches' spread (a division by a power of two is exact
in floating point), and maps the answer back: κ·U, κ_s·U², positions (less O), arc lengths
and the position noise / U; the shape parameters by their dimensions (``PARAM_POWER``), a
cubical's t by U, a semicubical's by √U. Both matter: a conic through contacts 1e6 units
from the origin (touches of 1e-4 mm, 150 mm away) is ill-conditioned, as is a σ floor in
mm. A line's offset is measured from the hand's origin: recognizer.classify states its σ
there (the angle's σ times the distance along the line from O's foot added with the
correlation of the fit's angle and offset at O) before the answer comes back here.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from recognizer.contacts import Contacts
from recognizer.curves import CURVES, Pose
from recognizer.noise import NoiseModel
from recognizer.touches import ContactTouch, MissedPlace, Request, SamplesTouch

__all__ = ["Unit", "PARAM_POWER", "UNIT_RANGE_MM"]

#: the unit stays within these (mm): touches 1e-300 mm apart (a hostile request) would put
#: 1/U² beyond the floating-point range; 1e-9 … 1e9 holds every spread limits.py lets through
#: with room (positions within 1 km, recognized at 1e-4 mm and below)
UNIT_RANGE_MM = (1e-9, 1e9)

#: each shape parameter's power of length: p in mm^k scales as U^k
PARAM_POWER = {("circle", "r"): 1, ("ellipse", "a"): 1, ("ellipse", "b"): 1, ("parabola", "a"): 1,
               ("hyperbola", "a"): 1, ("hyperbola", "b"): 1, ("cubical_parabola", "a"): -2,
               ("cubical_parabola", "c"): 0, ("semicubical_parabola", "a"): -0.5, ("semicubical_parabola", "b"): 0}
#: each class's contact parameter t's power of length (the others' t are angles)
T_POWER = {"line": 1.0, "cubical_parabola": 1.0, "semicubical_parabola": 0.5}


def _spread(touches) -> float:
    """Largest extent of every position of the touches (hypot of the x and y ranges), or
    the radius of curvature of the sharpest contact where they all coincide, else 1."""
    xs = np.concatenate([np.atleast_1d(np.asarray(t.x, float)) for t in touches])
    ys = np.concatenate([np.atleast_1d(np.asarray(t.y, float)) for t in touches])
    span = math.hypot(float(np.ptp(xs)), float(np.ptp(ys)))
    if span > 0 and math.isfinite(span):
        return span
    k = max((abs(float(t.kappa)) for t in touches if isinstance(t, ContactTouch)), default=0.0)
    return 1.0 / k if k > 0 else 1.0


class _ReachInUnits:
    """A reach in mm asked about places in units of U."""

    def __init__(self, reach, unit: "Unit"):
        self.reach, self.unit = reach, unit

    def contains(self, px, py, phi=None):
        u = self.unit
        return self.reach.contains(np.asarray(px, float) * u.u + u.ox, np.asarray(py, float) * u.u + u.oy, phi)


@dataclass(frozen=True)
class Unit:
    """Lengths in the recognizer's numerics: (position − (ox, oy)) / u mm, u a power of two."""

    u: float
    ox: float = 0.0
    oy: float = 0.0

    @classmethod
    def of(cls, request: Request) -> "Unit":
        if not request.touches:
            return cls(1.0)
        lo, hi = UNIT_RANGE_MM
        xs = np.concatenate([np.atleast_1d(np.asarray(t.x, float)) for t in request.touches])
        ys = np.concatenate([np.atleast_1d(np.asarray(t.y, float)) for t in request.touches])
        return cls(2.0 ** round(math.log2(min(max(_spread(request.touches), lo), hi))), 0.5 * float(xs.min() + xs.max()),
                   0.5 * float(ys.min() + ys.max()))

    @property
    def identity(self) -> bool:
        return self.u == 1.0 and self.ox == 0.0 and self.oy == 0.0

    # -- into units of U ---------------------------------------------------------------
    def noise(self, nm: NoiseModel | None) -> NoiseModel | None:
        if nm is None or self.u == 1.0:
            return nm
        return NoiseModel(nm.phi, nm.pos / self.u, None if nm.pos_along is None else nm.pos_along / self.u)

    def _reach(self, r):
        """A reach (anything with ``contains(x, y, phi)``: a disk, a jaw's pads) asked in units of U."""
        return None if r is None else _ReachInUnits(r, self)

    def _missed(self, places) -> tuple[MissedPlace, ...]:
        """Places where touches were lost (``options.missed``), in units of U (phi unchanged)."""
        return tuple(MissedPlace((p.x - self.ox) / self.u, (p.y - self.oy) / self.u, p.phi) for p in places)

    def _cov(self, cov) -> np.ndarray:
        d = np.array([self.u, self.u * self.u])
        return np.asarray(cov, float) * np.outer(d, d)

    def _touch(self, t):
        u = self.u
        if isinstance(t, ContactTouch):
            return ContactTouch((t.x - self.ox) / u, (t.y - self.oy) / u, t.phi, t.kappa * u, t.kappa_s * u * u, self._cov(t.cov))
        curvature = None if t.curvature is None else (
            t.curvature[0] * u, t.curvature[1] * u * u, self._cov(t.curvature[2]))
        factor = None
        if t.noise_factor is not None:
            n = len(t.phi)
            factor = np.asarray(t.noise_factor, float).copy()
            factor[: 2 * n] /= u
        return SamplesTouch(t.phi, (t.x - self.ox) / u, (t.y - self.oy) / u, None if t.s is None else t.s / u, curvature, factor)

    def request(self, request: Request) -> Request:
        if self.identity:
            return request
        opts = dict(request.options)
        if opts.get("reach") is not None:
            opts["reach"] = self._reach(opts["reach"])
        if opts.get("missed"):
            opts["missed"] = self._missed(opts["missed"])
        return replace(request, touches=tuple(self._touch(t) for t in request.touches),
                       noise=self.noise(request.noise), options=opts)

    def options(self, options):
        if self.identity:
            return options
        return replace(options, noise=self.noise(options.noise), reach=self._reach(options.reach),
                       missed=self._missed(options.missed))

    # -- back to mm ------------------------------------------------------------------------
    def contacts(self, d: Contacts) -> Contacts:
        """The touches' local geometry in mm (the invariants a person reads)."""
        if self.identity:
            return d
        u = self.u
        cov = np.asarray(d.cov, float) * np.outer([1 / u, 1 / u**2], [1 / u, 1 / u**2])
        return Contacts(d.x * u + self.ox, d.y * u + self.oy, d.phi, d.kappa / u, d.kappa_s / u**2, cov, d.sig_pos * u, d.sig_phi,
                        d.reach * u)

    def param(self, cls: str, name: str) -> float:
        """The factor from a shape parameter in units of U to mm (u to its power in mm)."""
        return self.u ** PARAM_POWER[(cls, name)]

    def answer(self, rec):
        """The recognition in mm (its invariants are computed in mm by the caller)."""
        if self.identity:
            return rec
        u, cls = self.u, rec.cls
        out = {}
        if cls != "unclassified":
            params = {k: v * self.param(cls, k) for k, v in rec.params.items()}
            th, x, y = rec.pose.theta, rec.pose.x * u + self.ox, rec.pose.y * u + self.oy
            tf = u ** T_POWER.get(cls, 0.0)
            ts = [c["t"] * tf for c in rec.contacts]
            unc = {}
            for k, v in rec.uncertainty.items():
                f = 1.0 if k == "pose_theta" else u if k.startswith("pose_") else self.param(cls, k)
                unc[k] = None if v is None else v * f
            if cls == "line":  # the foot of the perpendicular from the hand's origin (localize)
                ux, uy = math.cos(th), math.sin(th)
                along = x * ux + y * uy
                x, y, ts = x - along * ux, y - along * uy, [t + along for t in ts]
            contacts = [{"t": t, "x": c["x"] * u + self.ox, "y": c["y"] * u + self.oy} for t, c in zip(ts, rec.contacts)]
            interval = {k: None if v is None else [e * self.param(cls, k) for e in v] for k, v in rec.interval.items()}
            out.update(params=params, pose=Pose(th, x, y), contacts=contacts, uncertainty=unc, interval=interval)
            if rec.cov_pose is not None:  # (shape parameters, θ, x, y)
                f = np.array([self.param(cls, k) for k in CURVES[cls].param_names] + [1.0, u, u])
                out["cov_pose"] = rec.cov_pose * np.outer(f, f)
        if rec.next_touch is not None:
            out["next_touch"] = {**rec.next_touch, "x": rec.next_touch["x"] * u + self.ox,
                                 "y": rec.next_touch["y"] * u + self.oy}
        return replace(rec, **out)
