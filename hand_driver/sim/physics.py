"""Contact physics of the emulated jaw: flat pads meeting the scene's object.

Only the pads are modelled (zero-thickness segments from hand_driver.kinematics), not the
links, and only the scene's one object, seen through :class:`hand_driver.sim.boundary.Boundary`
(an unbounded curve with the solid on its ``side``, or a finite object: the curve over its
extent, the straight closing segments and their corners). A pad penetrates the solid when
one of its end points is inside the solid or when the boundary crosses the segment
transversally (exact crossings, closed form). A pad tangent to the curve, lying flat on a
closing segment or resting on a corner touches without penetrating, so a pad rolled on a
corner pivots about it.

:meth:`ContactWorld.constrain` moves along a straight joint-space step and stops at the
last configuration without penetration (bisection to ``tol_rad``: ``TOL_TICKS`` of the truth
jaw's finest encoder tick); far from the object a
clearance bound (bounding circles of the boundary within reach, and the largest distance
any pad point can travel in the step) accepts the whole step without any root finding.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from hand_driver.config import JawConfig
from hand_driver.sim.boundary import Boundary
from hand_driver.units import rad_per_tick

#: the bisection's tolerance in the finest encoder tick of the truth jaw. The last configuration
#: without penetration leaves the pad short of the boundary by up to tol_rad × its arm, on one
#: side only: a bias, not noise. At the former 1e-6 rad (0.16 of a PH54-100's 6.3e-6 rad tick)
#: that gap, ~5e-5 mm on average, was the P-series jaw's circles' r bias (seed 283: mean z +1.0
#: of 20; circle 22 r +2.1e-4 mm, z 3.96 → 2.15 at 1e-9 rad, the same at 1e-11)
TOL_TICKS = 1e-4


@dataclass(frozen=True)
class PadContact:
    """Diagnostics of one pad: the nearest boundary point and the gap to it."""

    finger: str
    gap_mm: float  # distance from the pad segment to the boundary (0 when touching)
    point: tuple[float, float]  # nearest boundary point, hand frame
    pad_u_mm: float  # where along the pad (from its proximal end) the nearest point projects
    penetrating: bool


class ContactWorld:
    """The truth jaw and the scene object; joint vectors are rad, in config joint order."""

    def __init__(self, truth_config: JawConfig, scene_object, max_sweep_mm: float = 2.0):
        self.cfg = truth_config
        self.obj = scene_object
        self.tol_rad = TOL_TICKS * float(np.min(rad_per_tick([j.ticks_per_rev for j in truth_config.joints])))
        self.max_sweep_mm = max_sweep_mm
        self.boundary = Boundary(scene_object)
        self._fingers = []
        for f in truth_config.fingers:
            j1, j2 = f.joints
            self._fingers.append((f.name, f.base.x, f.base.y, f.base.angle, j1.link_mm, j2.link_mm,
                                  f.pad.offset_mm, f.pad.length_mm, f.pad.side_sign))
        self._reach = max(math.hypot(bx, by) + l1 + math.hypot(l2, off) + 1.0
                          for _, bx, by, _, l1, l2, off, _, _ in self._fingers)
        self._build_chunks()

    # ------------------------------------------------------------------ geometry helpers
    def _pads(self, q) -> list[tuple[float, float, float, float]]:
        """Pad segments (x0, y0, x1, y1) per finger, proximal → distal."""
        out, k = [], 0
        for _, bx, by, ba, l1, l2, off, plen, side in self._fingers:
            a1 = ba + q[k]
            a2 = a1 + q[k + 1]
            k += 2
            c2, s2 = math.cos(a2), math.sin(a2)
            nx, ny = -side * s2, side * c2
            x1 = bx + l1 * math.cos(a1) + l2 * c2 + off * nx
            y1 = by + l1 * math.sin(a1) + l2 * s2 + off * ny
            out.append((x1 - plen * c2, y1 - plen * s2, x1, y1))
        return out

    def _lever_arms(self) -> np.ndarray:
        """Largest distance from each joint to any point of its finger's pad."""
        arms = []
        for _, _, _, _, l1, l2, off, _, _ in self._fingers:
            r2 = math.hypot(l2, off)
            arms += [l1 + r2, r2]
        return np.array(arms)

    def _build_chunks(self) -> None:
        """Bounding circles of the boundary within reach of the pads."""
        pts = self.boundary.points((0.0, 0.0), self._reach + 20.0)
        self._pts = pts
        centers, radii = [], []
        spacing = float(np.max(np.hypot(*np.diff(pts, axis=0).T))) if len(pts) > 1 else 0.0
        for chunk in np.array_split(pts, max(1, len(pts) // 64)) if len(pts) else []:
            c = chunk.mean(axis=0)
            centers.append(c)
            radii.append(float(np.max(np.hypot(*(chunk - c).T))) + spacing)
        self._centers = np.array(centers).reshape(-1, 2)
        self._radii = np.array(radii)
        self._arms = self._lever_arms()
        # one circle around every chunk: the first, pure-Python clearance test
        if len(pts):
            c = pts.mean(axis=0)
            self._outer = (float(c[0]), float(c[1]), float(np.max(np.hypot(*(pts - c).T))) + spacing)
        else:
            self._outer = (0.0, 0.0, -math.inf)

    def _pad_clearances(self, pads) -> list[float]:
        """Per pad, a lower bound (mm) on its distance to the boundary."""
        if not len(self._radii):
            return [math.inf] * len(pads)
        seg = np.array(pads)
        mid = 0.5 * (seg[:, :2] + seg[:, 2:])
        half = 0.5 * np.hypot(seg[:, 2] - seg[:, 0], seg[:, 3] - seg[:, 1])
        dist = np.hypot(mid[:, None, 0] - self._centers[None, :, 0], mid[:, None, 1] - self._centers[None, :, 1])
        return list((dist - self._radii[None, :]).min(axis=1) - half)

    def clearance(self, q) -> float:
        """A lower bound (mm) on the distance from every pad to the boundary."""
        return min(self._pad_clearances(self._pads(q)))

    # ------------------------------------------------------------------ exact predicate
    def _pad_penetrates(self, seg: tuple[float, float, float, float]) -> bool:
        x0, y0, x1, y1 = seg
        b = self.boundary
        return b.inside(x0, y0) or b.inside(x1, y1) or b.crosses(x0, y0, x1, y1)

    def penetrates(self, q, pads: list[int] | None = None) -> bool:
        """Does any pad (or any of the listed pads) penetrate the solid at joint angles q
        (rad, config order)?"""
        segs = self._pads(q)
        return any(self._pad_penetrates(segs[i]) for i in (range(len(segs)) if pads is None else pads))

    # ------------------------------------------------------------------ public
    def constrain(self, q_from, q_to) -> np.ndarray:
        """The farthest configuration on the straight joint-space step q_from → q_to at
        which no pad penetrates the object (q_from is assumed free), finger by finger: a
        pad depends only on its own finger's joints, so a blocked finger does not stop the
        other. Only pads that can reach the object during the step (travel ≥ clearance)
        are tested."""
        q_from = np.asarray(q_from, dtype=float)
        q_to = np.asarray(q_to, dtype=float)
        out = q_to.copy()
        dq = q_to - q_from
        arms = self._arms
        sweeps = [abs(float(dq[2 * i])) * arms[2 * i] + abs(float(dq[2 * i + 1])) * arms[2 * i + 1]
                  for i in range(len(self._fingers))]
        if not any(sw > 0.0 for sw in sweeps):
            return out
        pads = self._pads(q_from)
        ox, oy, orad = self._outer
        near = False
        for (x0, y0, x1, y1), sweep in zip(pads, sweeps):
            gap = math.hypot(0.5 * (x0 + x1) - ox, 0.5 * (y0 + y1) - oy) - orad - 0.5 * math.hypot(x1 - x0, y1 - y0)
            near = near or (sweep > 0.0 and sweep >= gap)
        if not near:  # every pad stays outside the circle around the whole boundary
            return out
        clear = self._pad_clearances(pads)
        for i, sweep in enumerate(sweeps):
            if sweep > 0.0 and sweep >= clear[i]:
                sl = slice(2 * i, 2 * i + 2)
                out[sl] = q_from[sl] + self._blocked_fraction(q_from, dq, i, float(sweep)) * dq[sl]
        return out

    def _blocked_fraction(self, q_from: np.ndarray, dq: np.ndarray, pad: int, sweep: float) -> float:
        """Largest fraction of finger ``pad``'s step without penetration (bisection)."""
        step = np.zeros_like(dq)
        step[2 * pad:2 * pad + 2] = dq[2 * pad:2 * pad + 2]
        tol = self.tol_rad / max(float(np.max(np.abs(step))), 1e-300)
        n = max(1, math.ceil(sweep / self.max_sweep_mm))
        lo = 0.0
        for k in range(1, n + 1):
            hi = k / n
            if self.penetrates(q_from + hi * step, [pad]):
                break
            lo = hi
        else:
            return 1.0
        if lo == 0.0 and self.penetrates(q_from + tol * step, [pad]):
            return 0.0  # pressing into a contact: no bisection needed
        while hi - lo > tol:
            mid = 0.5 * (lo + hi)
            if self.penetrates(q_from + mid * step, [pad]):
                hi = mid
            else:
                lo = mid
        return lo

    def contact_info(self, q) -> list[PadContact]:
        """Per finger: nearest boundary point to its pad, the gap, penetration flag (for
        diagnostics: the gap is measured to the boundary sampled densely within reach,
        4096 points around a closed curve)."""
        out = []
        for (name, *_), seg in zip(self._fingers, self._pads(np.asarray(q, dtype=float))):
            x0, y0, x1, y1 = seg
            a = np.array([x0, y0])
            t = np.array([x1 - x0, y1 - y0])
            length = float(np.hypot(*t))
            t /= length
            if not len(self._pts):
                out.append(PadContact(name, math.inf, (math.nan, math.nan), math.nan, False))
                continue
            rel = self._pts - a
            u = np.clip(rel @ t, 0.0, length)
            dist = np.hypot(*(rel - u[:, None] * t).T)
            i = int(np.argmin(dist))
            gap = float(dist[i])
            pen = self._pad_penetrates(seg)
            out.append(PadContact(name, 0.0 if pen else gap, (float(self._pts[i, 0]), float(self._pts[i, 1])),
                                  float(u[i]), pen))
        return out

    def surface_direction(self, point) -> np.ndarray | None:
        """The unit normal of the boundary at ``point`` (from its dense samples, either way
        round; None without samples): the direction of a frictionless contact force there."""
        if len(self._pts) < 3:
            return None
        i = int(np.argmin(np.hypot(*(self._pts - np.asarray(point, dtype=float)).T)))
        a, b = self._pts[max(i - 1, 0)], self._pts[min(i + 1, len(self._pts) - 1)]
        t = b - a
        norm = float(np.hypot(*t))
        return None if norm == 0.0 else np.array([-t[1], t[0]]) / norm

    def touching(self, q, touch_mm: float = 0.05) -> dict[str, bool]:
        """Finger name → is its pad within ``touch_mm`` of the boundary (or in it)?"""
        return {c.finger: c.penetrating or c.gap_mm <= touch_mm for c in self.contact_info(q)}

