"""Where a flat pad sent to a place lands on an object (tools.bench_wide's hand; not a test).

A touch is sent as a place (x, y) and a pad orientation φ (the boundary's tangent angle
there in the touches' direction of travel: ``next_touch``'s output). The pad, a straight
segment of ``2 · half_pad`` centred on the place along φ, comes in along its normal from the
free side, away from the solid, from ``standoff`` out; it lands where it first meets the object: the point of the
boundary, among those facing the pad (lateral offset within the pad), farthest out along
the pad's outward normal. It is a touch (the pad then rolls there, the same roll as every
other touch) only when that point is a smooth point of the boundary met by the pad's face
(a local maximum of the height, so the boundary's tangent there is φ), leaving room on the
pad for the roll (|lateral offset| + the roll's reach ≤ half_pad), with the roll clear of a
cusp and of the object's ends (corners). A pad that meets the boundary with its end (a small
tilt on a flat stretch), or too far from its middle for the roll, turns to seat on it, up to
``SEAT_RAD``: to the tangent of the boundary point under its middle, and lands there if its
face then meets the boundary there. Otherwise the touch is lost, and says why: the pad
meets nothing, its end meets the boundary, it meets a corner, an end or a cusp, the roll runs
off the pad, across the cusp or past a corner, or it meets the boundary from the solid's side.
A stretch where the solid is concave toward the pad is only bridged: the pad meets what
lies beyond it, or rests on its end.

The object is the canonical curve over ``t_range`` (a closed curve all round), with the
solid on the side given by ``solid_left`` (relative to the direction of travel): a flat pad
touches a boundary with its face only where the solid is convex toward it (docs/formats.md).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy import optimize

from recognizer.curves import DEFAULT_SIDE, Curve, Pose
from recognizer.next_touch import SEAT_RAD

__all__ = ["Landing", "land", "solid_left"]

N_DENSE = 20001
PAD_END = "the pad's end meets the boundary, not its face"
OFF_PAD = "the roll runs off the pad"


@dataclass(frozen=True)
class Landing:
    """Where a sent touch landed: the true curve's parameter ``t`` of its contact (None when
    the touch is lost), why it was lost (``""`` when not), and how far the contact lies from
    the place it was sent to (mm; nan when lost)."""

    t: float | None
    why: str = ""
    miss_mm: float = math.nan


def solid_left(curve: Curve, ts, direction: int) -> bool:
    """Whether the solid lies on the left of the direction of travel: the side the touched
    contacts ``ts`` curve toward (a flat pad touches only where the solid is convex toward
    it; across a cubical's inflection, the side most of them curve toward); a line's is the
    class's default side (docs/formats.md)."""
    k = np.sign(np.asarray(curve.kappa(np.asarray(ts, float)), float)) * direction
    total = float(np.sum(k))
    if total != 0.0:
        return total > 0.0
    return (DEFAULT_SIDE[curve.name] == "left") == (direction > 0)


def land(curve: Curve, pose: Pose, t_range: tuple[float, float] | None, x: float, y: float, phi: float,
         left: bool, direction: int, half_pad: float, reach: float, standoff: float,
         seat: float = SEAT_RAD) -> Landing:
    """Where a pad sent to (x, y) with orientation ``phi`` lands (module docstring).
    ``t_range``: the object's extent in t (None: a closed curve, all round); ``left``: the
    solid on the left of the direction of travel (``direction``: +1 increasing t);
    ``reach``: how far the roll reaches from its contact on either side (mm of arc);
    ``standoff``: how far out along its normal the pad starts (what lies farther out is
    behind it). Among boundary points of equal height (a flat stretch) the pad's contact is
    the one nearest its middle. A pad that meets the boundary with its end, or whose contact
    leaves no room for the roll, seats: it turns (at most ``seat`` rad) to the tangent of the
    boundary point it first meets under its middle, and lands there if its face meets the
    boundary there."""
    first = _first_met(curve, pose, t_range, x, y, phi, left, direction, half_pad, reach, standoff)
    if first.why not in (PAD_END, OFF_PAD) or seat <= 0:
        return first
    under = _under_middle(curve, pose, t_range, x, y, phi, left, direction, standoff)
    if under is None or abs(_wrap(under - phi)) > seat:
        return first
    seated = _first_met(curve, pose, t_range, x, y, under, left, direction, half_pad, reach, standoff)
    return seated if seated.t is not None else first


def _wrap(a: float) -> float:
    return (a + math.pi) % (2.0 * math.pi) - math.pi


def _dense(curve: Curve, t_range):
    """The object's t's, ``N_DENSE`` of them (a closed curve's once round)."""
    if curve.t_period is not None:
        return np.linspace(*curve.t_period, N_DENSE, endpoint=False)
    return np.linspace(*t_range, N_DENSE)


def _under_middle(curve: Curve, pose: Pose, t_range, x, y, phi, left, direction, standoff) -> float | None:
    """The tangent (direction of travel) of the boundary point a pad at (x, y) with
    orientation ``phi`` meets first under its middle (where the boundary crosses its normal
    line), or None when nothing is there."""
    ux, uy = math.cos(phi), math.sin(phi)
    sgn = -1.0 if left else 1.0
    nx, ny = -sgn * uy, sgn * ux
    t = _dense(curve, t_range)
    with np.errstate(all="ignore"):
        px, py = pose.apply(*curve.point(t))
    dx, dy = np.asarray(px, float) - x, np.asarray(py, float) - y
    height, lateral = dx * nx + dy * ny, dx * ux + dy * uy
    cross = np.flatnonzero((np.sign(lateral[:-1]) != np.sign(lateral[1:])) & np.isfinite(height[:-1]))
    cross = cross[height[cross] <= standoff]
    if not cross.size:
        return None
    k = int(cross[np.argmax(height[cross])])
    f = lateral[k] / (lateral[k] - lateral[k + 1])
    tk = t[k] + f * (t[k + 1] - t[k])
    return float(np.asarray(curve.tangent_angle(np.array([tk])), float)[0]) + pose.theta + \
        (math.pi if direction < 0 else 0.0)


def _first_met(curve: Curve, pose: Pose, t_range, x, y, phi, left, direction, half_pad, reach, standoff) -> Landing:
    """Where the pad's face first meets the boundary without turning (``land``)."""
    ux, uy = math.cos(phi), math.sin(phi)
    sgn = -1.0 if left else 1.0  # the pad's outward normal: away from the solid
    nx, ny = -sgn * uy, sgn * ux
    periodic = curve.t_period is not None
    lo, hi = curve.t_period if periodic else t_range
    t = _dense(curve, t_range)
    with np.errstate(all="ignore"):
        px, py = pose.apply(*curve.point(t))
    dx, dy = np.asarray(px, float) - x, np.asarray(py, float) - y
    height, lateral = dx * nx + dy * ny, dx * ux + dy * uy
    seen = (np.abs(lateral) <= half_pad) & (height <= standoff)
    seen &= np.isfinite(height)
    if not seen.any():
        return Landing(None, "the pad meets nothing")
    h = np.where(seen, height, -np.inf)
    top = h >= np.max(h) - 1e-12 * (standoff + abs(x) + abs(y))
    j = int(np.argmin(np.where(top, np.abs(lateral), np.inf)))
    n = t.size
    if periodic:
        nb = ((j - 1) % n, (j + 1) % n)
    else:
        if j in (0, n - 1):
            return Landing(None, "the pad meets the object's end (a corner)")
        nb = (j - 1, j + 1)
    if not (seen[nb[0]] and seen[nb[1]]):
        return Landing(None, PAD_END)
    if curve.name == "semicubical_parabola" and (t[nb[0]] <= 0.0 <= t[nb[1]]):
        return Landing(None, "the pad meets the cusp")

    def minus_height(u: float) -> float:
        qx, qy = pose.apply(*curve.point(np.array([u])))
        return -float((qx[0] - x) * nx + (qy[0] - y) * ny)

    a, b = t[nb[0]], t[nb[1]]
    if periodic and b < a:
        b += hi - lo
    res = optimize.minimize_scalar(minus_height, bounds=(a, b), method="bounded",
                                   options={"xatol": 1e-13 * max(1.0, abs(a), abs(b))})
    tc = float(res.x)
    if periodic:
        tc = float(np.remainder(tc - lo, hi - lo) + lo)
    qx, qy = pose.apply(*curve.point(np.array([tc])))
    qx, qy = float(qx[0]), float(qy[0])
    ang = float(np.asarray(curve.tangent_angle(np.array([tc])), float)[0]) + pose.theta + (math.pi if direction < 0 else 0.0)
    miss = math.hypot(qx - x, qy - y)
    if math.cos(ang - phi) <= 0.0:
        return Landing(None, "the pad meets the boundary from the solid's side", miss)
    if abs((qx - x) * ux + (qy - y) * uy) + reach > half_pad:
        return Landing(None, OFF_PAD, miss)
    if curve.name == "semicubical_parabola" and abs(float(curve.arc_length(0.0, tc))) < reach:
        return Landing(None, "the roll crosses the cusp", miss)
    if not periodic and min(abs(float(curve.arc_length(lo, tc))), abs(float(curve.arc_length(tc, hi)))) < reach:
        return Landing(None, "the roll runs past the object's end (a corner)", miss)
    return Landing(tc, "", miss)
