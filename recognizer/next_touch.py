"""Where one more touch tells the most (the answer's ``next_touch``, docs/formats.md).

The candidates are the classes fitted to the touches, each with its parameters, pose and
their joint covariance C (recognizer.refine; the stated σ's of an unrefined fit), weighted
w ∝ exp(−BIC/2). Places on the leading candidate's curve (the answer, else the class of
least χ² against its limit) are scored. A touch there is a roll: with its n samples it
measures the boundary's offset across the tangent and its tangent angle, noise
diag(σ_pos², σ_φ²)/n, and the curvature and its arc-length derivative (κ, κ_s) with the
covariance C_roll the request's own rolls state (``roll_cov``); R is the 4×4 block
diagonal of the two. Every candidate predicts that measurement: its curve's closest point
to the place, the offset along the leader's normal, the tangent angle there (mod π), κ
signed along the leader's tangent and κ_s (a reversed traversal flips κ's sign and keeps
κ_s's), with the predictive covariance P = G·C·Gᵀ (G by forward differences of the
prediction in the shape parameters and the pose). Everything is whitened by R first
(W·R·Wᵀ = I), so that a millimetre offset and a κ_s in 1/mm² are compared in σ's.

Expected information gain (nats) of a place:
- classes: for each other candidate c, χ²_c = Δᵀ(R + P_ℓ + P_c)⁻¹Δ + 8·D_cov is the expected
  separation of the two predictions (Δ = c's − the leader's; D_cov the Bhattacharyya
  distance's covariance term, ``_separation``); the pair's class entropy (w_ℓ + w_c)·H(w_ℓ/(w_ℓ + w_c))
  is resolved in proportion 1 − exp(−χ²_c/8) (the Bhattacharyya bound on the error of
  telling two Gaussians apart). P_ℓ and P_c there are conditioned on the touches (``_told``:
  C' = (C⁻¹ + G_Tᵀ R⁻¹ G_T)⁻¹, G_T the measurement at every touch): a touch adds only what the
  touches have not measured, and a candidate's spread at a touched place is at most that
  touch's noise, however large its linearized C. Both ways round, the smaller counting: c true, the pad
  touches c's closest point q to the place, and the leader explains that touch by its own
  closest point to q (measured across c's tangent at q), not by the place (each touch gets
  its own point on every curve: a place on a semicubical leader's other branch, beyond its
  cusp, whose rival contact the leader meets on its touched branch, tells nothing);
- parameters: w_ℓ · ½ ln det(I + R⁻¹P_ℓ), the entropy the leader's parameters and pose
  lose (the determinant lemma for the linearized update C' = C − C Gᵀ(GCGᵀ + R)⁻¹GC).

The roll's κ and κ_s are what tell classes apart where their positions agree within the
parameters' uncertainty: a semicubical parabola's branch far from its cusp and a parabola
through the same touches bend differently along a roll (bench_wide: modelled as one point,
the suggested touches left the far branch 76.9 % right).

A pad reaches a place only from the free side: a touch is sent as the place and its
tangent, and the pad comes in along its normal from away from the solid (the side the
touches curve toward: ``Contacts.dominant_kappa``). A pad, ``PAD_ROLLS`` rolls either side
of its middle and starting the touches' extent out, lands on a candidate's curve where
tools.pad_approach says it does (``_landed``: the point farthest out under the pad is met by
its face, with room for the roll, clear of a cusp; a pad meeting it with its end seats up to
``SEAT_RAD``). Places are kept where it lands on the leader's curve. A touch lost tells
nothing whichever candidate is true, so the class gain is weighted by the chance the pad
lands and seats: Σ w_c·p_c over the leader and the rivals (normalized), p_c = 0 where the
pad does not land on c's curve there, or, on a semicubical rival, where the place lies toward
its cusp from its touches (``_toward_cusp``: far out on a branch the cusp's place is barely
measured), or, where its fit puts its cusp beyond the other end of the touches from the one
where the leader's |κ| grows (``_cusp_elsewhere``), at the places beyond that end and within a
pad's half length less a roll's reach of the touch there (``_cusp_side``: the class's cusp lies
that way whatever that fit says, as little as a roll's reach beyond that touch; on an ellipse
leader, the half of the untouched arc next to that end), else the chance that c's tangent, in
c's own direction of travel, lies within the pad's tolerance of the pad's orientation
(``_seats``: c's predicted tilt and its σ_φ; a tilt δφ puts the contact δφ/|κ| along the pad,
which must leave room for the roll, and a pad turns ``SEAT_RAD`` to seat). The leader's
parameter gain counts with the leader's own p.
Where some helpful place lands for every candidate at least ``LAND_WEIGHT_MIN`` likely, only
such places are chosen, a semicubical leader's other branch, which no rival has, excepted;
where none does, still none on ``_cusp_side`` while such a semicubical rival is a candidate.
A line leader's rivals are all curved, one alternative "curved, not line" of weight their
sum W: its entropy with the leader is resolved in proportion to Σ w_c·p_c·(1 − exp(−χ²_c/8))/W,
and the places kept are where the pad lands for at least ``CURVED_LAND_MIN`` of W (rival by
rival, a far hyperbola arm answered line was tested only where the ellipse rival bends);
the pad's landing on them is checked first at the ``LAND_FIRST`` places of largest possible
class gain, then, while none of those checked beats the others' bound, at as many again of
the others (the same choice).
Each candidate's pad comes in from that candidate's own free side where its curve turns one
way over its touches (``_solid_left``).
Before (session 17), a rival counted only in its own pair and only where the pad landed on
its curve at its mean: places where the rivals' tangents were tilted from the leader's, or
unknown (a circle leader's far side, 9e3 rad for the ellipse rival), were suggested and the
touch lost (bench_wide seeds 179 and 5, ellipse short stretches), and far out on a
semicubical's branch, answered parabola, suggested touches were lost beside its true cusp
(seed 179).

A place a touch was sent to and lost (``options.missed``: its point and pad orientation, as
a suggestion gives them) says the pad met nothing it could roll on there, whatever the
candidates say. A pad sent along the same normal near the same place meets the same thing, so
no place is suggested where its pad would come in on that stretch again
(``_on_missed_stretch``): its middle less than a pad length (2 ``PAD_ROLLS`` rolls) from the
lost pad's along its tangent (the pads overlap, and where along itself the lost pad met what
stopped it is not known), and its orientation within the pad's tilt tolerance of the lost
pad's (``_tilt_tolerance``, the one ``_seats`` uses: the larger of ``SEAT_RAD``, the turn a
pad makes to seat, and, on the leader's curve of curvature κ there, (``PAD_ROLLS`` − ½)·roll·|κ|,
the tilt that moves the contact a roll's room along the pad), so that both come in along one
normal.
The miss is not weighed as evidence against the candidates a pad would have landed on there:
the landing is modelled on each candidate's mean curve (only its tangent's tilt has a
probability, ``_seats``), so the leader's own suggested place has a landing probability near
1 and one miss would rule the leader out, though its position and curvature σ's alone can
make a pad miss.

A touch whose contact the recognizer would count at one place with an earlier touch
(``Contacts.at_touched_place``: ``Contacts.places``' χ² with that touch's deviations) adds no
place and only re-draws that touch's noise: such places are suggested only where no other
place helps.

Greedy, one touch at a time (adaptive-submodular selection, so greedy is near-optimal):
while some place resolves at least ``CLASS_GAIN_MIN`` nats of class entropy, the place of
largest class gain, else of largest gain. A touch is ``roll`` long: no place within
roll/2 of the leader's cusp (a pad cannot roll through it), and a semicubical rival's
prediction counts nothing where its closest point lies that near its cusp. A place helps
when its class gain is at least ``CLASS_GAIN_MIN`` nats or it shrinks the leader's largest relative parameter σ by at least
``SHRINK_MIN`` while that σ is above ``REL_SIGMA_ENOUGH``; ``None`` when no place helps.
Places: the leader's curve over its touched span widened by the span on each side (a closed
curve all round; a semicubical parabola's also mirrored onto its other branch, the same t's
of the other sign: the one stretch no other class has), no farther than the touches'
extent from the nearest touch on a line, ``PLACE_EXTENTS`` extents on another open curve (a
parabola's, hyperbola's or cubical's places also one to ``PLACE_EXTENTS`` spans out,
``_far_span``, where a pad lands within ``_pad_span``'s two), inside
``options.reach`` when given (any object with ``contains(x, y, phi)``, phi the place's
tangent in the touches' direction of travel: a hand-frame disk, recognizer.touches.Reach,
or a robot's own reach, which depends on the orientation its pad must take there).
A place beyond one extent, where the leader's curve is extrapolated, is suggested only
while some rival at least ``LAND_WEIGHT_MIN`` likely is told from the leader by no place
within one extent where the pad lands on it (expected χ² below ``FAR_SEPARATION``: a
semicubical far out on a branch against a parabola, bench_wide seed 349 trial 11), only to
tell classes apart (class gain at least ``CLASS_GAIN_MIN``) and only where the pad lands
whichever likely class is true: never for the leader's parameters alone (bench_wide seed 5
cubical trial 0, no rival: at two extents the pad landed 100 mm, 0.08 L, from where the
leader's extrapolation put the place) nor for a rival a nearer place tells apart (seed 179
parabola trial 6: the place across the vertex decides).
"""

from __future__ import annotations

import math
import threading
from typing import Sequence

import numpy as np
from scipy import special

from recognizer.contacts import Contacts
from recognizer.curves import CURVES, Pose, travel_direction
from recognizer.result import Candidate
from recognizer.scale_free import PARAM_POWER
from recognizer.touches import MissedPlace, NoiseModel, Reach
from tactile_common.angles import wrap_angle

__all__ = ["next_touch", "roll_cov", "CLASS_GAIN_MIN", "SHRINK_MIN", "REL_SIGMA_ENOUGH"]

CLASS_GAIN_MIN = 0.01
"""nats of class entropy a touch must be expected to resolve to count as telling classes apart."""
SHRINK_MIN = 1.1
"""factor by which the largest relative parameter σ must be expected to shrink."""
REL_SIGMA_ENOUGH = 1e-3
"""a largest relative parameter σ below this needs no further touch."""
UNDETERMINED = 1e3
"""an undetermined parameter's σ, in units of its own size (``_natural``)."""
N_PLACES = 160
N_DENSE = 400
MIN_WEIGHT = 1e-3
PAD_ROLLS = 1.0
"""a pad's half length in rolls: a pad twice as long as the request's touches roll."""
SEAT_RAD = 0.05
"""how far a pad that meets the boundary with its end turns to seat on it (rad; tools.pad_approach)."""
FLAT_TOL = 1e-9
"""points within this fraction of the pad's half length of the farthest out meet its face together."""
LAND_WEIGHT_MIN = 0.01
"""a candidate at least this likely must be landed on too, where some helpful place is."""
CURVED_LAND_MIN = 0.5
"""the fraction of a line leader's curved rivals' weight a pad must land for (``LAND_WEIGHT_MIN``'s rule for a line)."""
LAND_FIRST = 16
"""a line leader's places whose landing is checked first, those of largest possible class gain
(then batches as large as all checked so far)."""
SEPARATION_MIN = 0.1
"""an expected χ² separation below this (1.2 % of a pair's entropy) is not checked the other way round."""
PLACE_EXTENTS = 3.0
"""how far places are proposed, in touched spans beyond the touches and in extents from the
nearest touch (an open curve; beyond one extent, to tell classes apart only): far out on a
semicubical's branch it and a parabola differ most there, and toward the cusp no pad has
room to roll (docs/benchmarks.md, sessions 28 and 29)."""
FAR_SEPARATION = 1.0
"""the expected χ² separation (one measurement's noise) a rival must lack at every place within
one extent where the pad lands on it before places beyond tell it from the leader."""


def _wrap_half(a):
    """Angle difference of two undirected lines, in [−π/2, π/2)."""
    return np.remainder(np.asarray(a, float) + np.pi / 2, np.pi) - np.pi / 2


def _posed(cls: str, vec: np.ndarray):
    names = CURVES[cls].param_names
    k = len(names)
    return CURVES[cls]({n: float(v) for n, v in zip(names, vec[:k])}), Pose(*(float(v) for v in vec[k:k + 3]))


def _natural(c: Candidate, scale: float) -> np.ndarray:
    """Each of (shape, θ, x, y)'s own size: a shape parameter's magnitude, at least the
    touches' spread to its power of length (``PARAM_POWER``: a parameter at 0, a → 0 of a
    hyperbola, still has a size); a radian for θ; the spread for x and y."""
    names = CURVES[c.cls].param_names
    vals = [abs(float(c.params[n])) for n in names]
    return np.array([max(v, scale ** PARAM_POWER[(c.cls, n)]) for n, v in zip(names, vals)] + [1.0, scale, scale])


def _cov(c: Candidate, scale: float) -> np.ndarray:
    """Joint covariance of (shape, θ, x, y): refine's, else the stated σ's (diagonal). A
    direction the touches do not determine (an infinite or undefined variance: the stated
    σ is null) is as uncertain as can be: σ = ``UNDETERMINED`` times its own size
    (``_natural``), uncorrelated; never 0, which would make a place that determines it
    look useless."""
    cov = getattr(c, "cov_pose", None)
    names = CURVES[c.cls].param_names
    if cov is None or cov.shape != (len(names) + 3,) * 2:
        sig = [_sigma(c.uncertainty.get(n, 0.0)) for n in names] + \
              [_sigma(c.uncertainty.get(f"pose_{k}", 0.0)) for k in ("theta", "x", "y")]
        cov = np.diag(np.square(sig))
    cov = np.array(cov, float)
    lost = ~np.isfinite(np.diag(cov)) | ~np.all(np.isfinite(cov), axis=1)
    if lost.any():
        cov[lost, :] = cov[:, lost] = 0.0
        cov[lost, lost] = np.square(UNDETERMINED * _natural(c, scale)[lost])
    return np.where(np.isfinite(cov), cov, 0.0)


def _sigma(v) -> float:
    """A stated σ: None (JSON's null for an undetermined one) is infinite; absent is 0
    (the class has no such σ, a circle's θ)."""
    return math.inf if v is None else float(v)


def _t_span(c: Candidate, widen: float = 1.0, n: int = N_PLACES) -> np.ndarray:
    curve = CURVES[c.cls]
    t = np.asarray(c.t, float)
    if curve.t_period is not None:
        return np.linspace(-np.pi, np.pi, n, endpoint=False)
    lo, hi = float(t.min()), float(t.max())
    w = max(hi - lo, 1e-9)
    return np.linspace(lo - widen * w, hi + widen * w, n)


def _far_span(c: Candidate, n: int = N_PLACES // 4) -> np.ndarray:
    """t's of an open curve one to ``PLACE_EXTENTS`` touched spans beyond its touches, n each
    side: none on a closed curve (``_t_span`` is all round), a line (whose places stay within
    one extent: its rivals are one alternative, the landing checks run in batches) or a
    semicubical parabola, whose other branch, which no rival has, tells it apart (bench_wide
    seed 149 semicubical 1)."""
    if CURVES[c.cls].t_period is not None or c.cls in ("line", "semicubical_parabola"):
        return np.zeros(0)
    t = np.asarray(c.t, float)
    lo, hi = float(t.min()), float(t.max())
    w = max(hi - lo, 1e-9)
    step = np.linspace(w, PLACE_EXTENTS * w, n + 1)[1:]
    return np.concatenate((lo - step, hi + step))


def _pad_span(c: Candidate, n: int = N_DENSE) -> np.ndarray:
    """Dense t's of a candidate's curve where a pad might meet it: twice the touched span
    each side (a semicubical parabola's both branches through the cusp, as densely on the
    touched stretch and its mirror as elsewhere: touches far out on a branch span a small
    part of their t's; a closed curve all round)."""
    t = _t_span(c, 2.0, n)
    if CURVES[c.cls].t_period is None and c.cls == "semicubical_parabola":
        far = float(np.max(np.abs(t)))
        return np.unique(np.concatenate((np.linspace(-far, far, n), t, -t)))
    return t


class _WorkArrays(threading.local):
    """Each thread's (places × dense points) work arrays, by name, kept between calls: at 160 ×
    400 a fresh one is 0.5 MB that glibc maps anew and the kernel pages in (~125 page faults,
    ~1 ms here), several times a call; kept, they are paged in once a process. What they hold
    never leaves the function that filled it (``_closest``, ``_landed``, ``_met_by_face``)."""

    def __init__(self) -> None:
        self.arrays: dict[str, np.ndarray] = {}


_WORK = _WorkArrays()


def _work(name: str, rows: int, cols: int) -> np.ndarray:
    """The thread's work array ``name`` as ``rows`` × ``cols`` (contents undefined), grown when too small."""
    buf = _WORK.arrays.get(name)
    if buf is None or buf.size < rows * cols:
        buf = _WORK.arrays[name] = np.empty(rows * cols)
    return buf[: rows * cols].reshape(rows, cols)


def _rows(a: np.ndarray, rows: np.ndarray, name: str) -> np.ndarray:
    """``a[rows]`` (rows of a 2-D array) in the work array ``name``."""
    return np.take(a, rows, axis=0, out=_work(name, rows.size, a.shape[1]))


def _squares_added(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """a² + b² in ``a`` (``b`` overwritten): ``a ** 2 + b ** 2`` bit for bit, in the arrays given."""
    np.square(a, out=a)
    a += np.square(b, out=b)
    return a


def _closest(curve, pose: Pose, t_dense: np.ndarray, dense: tuple, px: np.ndarray, py: np.ndarray) -> np.ndarray:
    """t of the curve's point closest to each hand-frame (px, py): the nearest dense
    sample (``dense``: the hand-frame points at ``t_dense``), then three Newton steps
    (``Curve.project``)."""
    cx, cy = dense
    d2 = _squares_added(np.subtract(px[:, None], cx[None, :], out=_work("a", px.size, cx.size)),
                        np.subtract(py[:, None], cy[None, :], out=_work("b", py.size, cy.size)))
    t = t_dense[np.argmin(d2, axis=1)]
    return curve.project(t, *pose.inverse(px, py), steps=3)


def _measure(curve, pose: Pose, t: np.ndarray, px, py, nx, ny, lead_phi) -> np.ndarray:
    """(offset along the leader's normal, tangent angle − leader's mod π, κ signed along the
    leader's tangent, κ_s; the leader's own: 0, 0, its κ, κ_s) of the posed curve at its points t near the places (px, py)."""
    qx, qy = pose.apply(*curve.point(t))
    ang = np.asarray(curve.tangent_angle(t), float) + pose.theta
    along = np.where(np.cos(ang - lead_phi) >= 0.0, 1.0, -1.0)
    return np.stack([(qx - px) * nx + (qy - py) * ny, _wrap_half(ang - lead_phi),
                     along * np.asarray(curve.kappa(t), float), np.asarray(curve.kappa_s(t), float)], axis=-1)


def _landed(curve, pose: Pose, t_dense: np.ndarray, px, py, phi, left: bool, half_pad: float, reach: float,
            standoff: float) -> np.ndarray:
    """Whether a pad sent to each place (px, py) with orientation ``phi`` (the direction of
    travel), coming in along its normal from the free side (the solid on the ``left`` of
    travel or not) from ``standoff`` out, lands on this posed curve (tools.pad_approach's
    rule on the dense points ``t_dense``): the point farthest out among those under the pad
    (|lateral| ≤ ``half_pad``) is met by the pad's face (its neighbours are under the pad
    too: not a concave stretch bridged, not another branch met by the pad's end), leaves
    ``reach`` of the pad either side for the roll, and is not within ``reach`` of a
    semicubical parabola's cusp. A pad whose end meets the curve seats, turning up to
    ``SEAT_RAD`` to the tangent of the curve's point nearest the place, and lands if it
    lands so."""
    cx, cy = pose.apply(*curve.point(t_dense))
    dx = np.subtract(cx[None, :], px[:, None], out=_work("a", px.size, cx.size))
    dy = np.subtract(cy[None, :], py[:, None], out=_work("b", py.size, cy.size))
    out = _met_by_face(curve, t_dense, dx, dy, phi, left, half_pad, reach, standoff)
    lost = np.flatnonzero(~out)
    if lost.size:
        near = t_dense[np.argmin(_squares_added(_rows(dx, lost, "v"), _rows(dy, lost, "w")), axis=1)]
        seated = phi[lost] + _wrap_half(np.asarray(curve.tangent_angle(near), float) + pose.theta - phi[lost])
        turn = np.abs(seated - phi[lost]) <= SEAT_RAD
        k = lost[turn]
        out[k] = _met_by_face(curve, t_dense, _rows(dx, k, "c"), _rows(dy, k, "d"), seated[turn], left, half_pad, reach,
                              standoff)
    return out


def _met_by_face(curve, t_dense, dx, dy, phi, left, half_pad, reach, standoff) -> np.ndarray:
    """``_landed`` without seating: (dx, dy), the dense points less each place. Only the
    points under the pad (|lateral| ≤ half_pad) are asked further, each with the same
    arithmetic (a place's pad covers a fraction of the dense span)."""
    ux, uy = np.cos(phi)[:, None], np.sin(phi)[:, None]
    sgn = -1.0 if left else 1.0
    out_x, out_y = -sgn * uy, sgn * ux  # h = (dx, dy)·(out_x, out_y): how far out

    def seen_at(r, col):
        """Whether the dense point col lies under place r's pad, not beyond ``standoff`` out."""
        h = dx[r, col] * out_x[r, 0] + dy[r, col] * out_y[r, 0]
        return (np.abs(v[r, col]) <= half_pad) & (h <= standoff) & np.isfinite(h)

    v = np.multiply(dx, ux, out=_work("v", *dx.shape))
    v += np.multiply(dy, uy, out=_work("w", *dx.shape))  # dx·ux + dy·uy
    r, col = np.nonzero(np.abs(v, out=_work("w", *dx.shape)) <= half_pad)
    h = dx[r, col] * out_x[r, 0] + dy[r, col] * out_y[r, 0]
    seen = (h <= standoff) & np.isfinite(h)
    r, col, h = r[seen], col[seen], h[seen]
    # the face meets every point as far out as the farthest at once (a straight stretch: all of
    # them, their h equal but for rounding); the contact is the one nearest the pad's middle,
    # not whichever rounding puts out farthest (a line leader kept 60 of 160 places, as rounding fell)
    far = np.full(phi.size, -np.inf)
    np.maximum.at(far, r, h)
    top = h >= far[r] - FLAT_TOL * half_pad
    r, col = r[top], col[top]
    first = np.lexsort((col, np.abs(v[r, col]), r))  # by place, then |lateral|, then column (np.argmin's)
    first = first[np.diff(r[first], prepend=-1) != 0]
    j = np.zeros(phi.size, int)
    j[r[first]] = col[first]
    met = np.zeros(phi.size, bool)
    met[r] = True
    rows = np.arange(j.size)
    n = t_dense.size
    closed = curve.t_period is not None
    lo, hi = (j - 1) % n, (j + 1) % n
    ok = met & seen_at(rows, j) & seen_at(rows, lo) & seen_at(rows, hi) & (np.abs(v[rows, j]) + reach <= half_pad)
    if not closed:  # the dense span's ends: what lies beyond is not known
        ok &= (j > 0) & (j < n - 1)
    if curve.name == "semicubical_parabola":
        tj = t_dense[j]
        ok &= (np.sign(t_dense[lo]) == np.sign(t_dense[hi])) & \
            (np.abs(curve.arc_length(np.zeros_like(tj), tj)) >= reach)
    return ok


def _touchable(curve, t: np.ndarray, roll: float) -> np.ndarray:
    """Whether a touch of arc length ``roll`` centred at each t stays on one smooth piece of
    the curve (a pad cannot roll through a semicubical parabola's cusp)."""
    if curve.name != "semicubical_parabola" or roll <= 0:
        return np.ones(np.shape(t), bool)
    return np.abs(curve.arc_length(np.zeros_like(t), t)) >= 0.5 * roll


def _solid_left(c: Candidate, d: Contacts, turn: float) -> bool:
    """Whether the solid lies on the left of the touches' direction of travel, c true: on
    the side c's curve turns to over its touches where it turns one way there (a convex
    piece), else the side the touches turn to (``turn``, ``Contacts.dominant_kappa``).
    Far out on a hyperbola arm the touches barely turn and their side can come out wrong
    (bench_wide seed 271 hyperbola 11: ``turn`` +0.16 against a truth turning right): a
    pad then came in from the hyperbola rival's solid side everywhere and never landed
    on it."""
    k = np.asarray(c.curve().kappa(np.asarray(c.t, float)), float) * \
        travel_direction(c.curve(), c.pose, c.t, d.phi)
    if k.size and np.all(k > 0):
        return True
    if k.size and np.all(k < 0):
        return False
    return turn > 0


def _toward_cusp(c: Candidate, t: np.ndarray) -> np.ndarray:
    """Whether each of a semicubical parabola's points t lies toward its cusp from its
    touches, all on one branch: between them and the cusp, or past it on the other branch.
    Far out on a branch the cusp's place is barely measured (bench_wide --set wide seed 179,
    semicubical trials 3, 9, 11: suggestions 0.01–0.03 L from the true cusp, 0.13–0.27 L
    beyond the last touch, were lost), so a pad sent there may meet the cusp or the other
    branch whatever the fit says."""
    touched = np.asarray(c.t, float)
    side = np.sign(touched)
    if c.cls != "semicubical_parabola" or not touched.size or np.any(side != side[0]):
        return np.zeros(np.shape(t), bool)
    return (np.sign(t) != side[0]) | (np.abs(t) < np.min(np.abs(touched)))


def _growth(leader: Candidate) -> tuple[int, np.ndarray, float | None, float, float, float]:
    """(+1 / −1 / 0: the leader's |κ| grows monotonically over its touches toward their end of
    larger / smaller u, or peaks between them (a vertex touched) or is constant; each touch's u;
    the curve's period or None; the t of u = 0; the touched u's least and greatest). u is t on
    an open curve, on a closed one (an ellipse) the way along the curve from the start of the
    touched arc, the curve less its largest gap between touches. 0 for a line or a
    semicubical parabola."""
    touched = np.asarray(leader.t, float)
    curve = leader.curve()
    if leader.cls in ("line", "semicubical_parabola") or touched.size < 2:
        return 0, touched, None, 0.0, 0.0, 0.0
    period = None if curve.t_period is None else float(curve.t_period[1] - curve.t_period[0])
    if period is None:
        start = 0.0
        u = touched
    else:
        s = np.sort(np.mod(touched, period))
        gaps = np.diff(np.append(s, s[0] + period))
        start = float(s[(int(np.argmax(gaps)) + 1) % s.size])
        u = np.mod(touched - start, period)
    lo, hi = float(u.min()), float(u.max())
    k = np.abs(np.asarray(curve.kappa(start + np.linspace(lo, hi, 33)), float))
    if not np.all(np.isfinite(k)) or k[0] == k[-1] or not np.all(np.diff(k) >= 0 if k[-1] > k[0] else np.diff(k) <= 0):
        return 0, u, period, start, lo, hi
    return (1 if k[-1] > k[0] else -1), u, period, start, lo, hi


def _cusp_side(leader: Candidate, t: np.ndarray, near: float = 0.0) -> np.ndarray:
    """Whether each of a curved leader's places t lies beyond its touches on the end where its
    |κ| grows (monotonically over the touches, ``_growth``): there a semicubical parabola
    through the same touches has its cusp (its |κ| falls monotonically away from the cusp, so
    the cusp lies where the touches' curvature grows), wherever its own fit put it, and a pad
    sent there may meet that cusp, or its other branch beside it, and be lost when the
    semicubical is true (bench_wide --set wide seed 443, semicubical trials 5 and 13, answered
    parabola: the rival's fit had its cusp beyond the other end of the touches, and the place
    lay 0.05–0.11 extents from the true cusp; across the parabola's vertex, 0.2 L from it, the
    pad still met the cusp). On a closed leader (an ellipse; a circle's |κ| grows nowhere) the
    cusp's side is the half of the untouched arc next to the growing end (seed 467 trials 1
    and 2, one branch far and both branches, answered ellipse: its sharp end, where |κ| grows,
    was suggested 0.01–0.03 extents from the true cusp and the touch was lost). Also the places
    within ``near`` of the touch at the growing end: the cusp lies beyond that touch by as
    little as its roll's reach, and a pad's end meets it from a place up to the pad's half
    length less that reach inside (the same trials, the touch at that end suggested again:
    the pad's end met the true cusp 40 mm beyond it, the pad 86 mm long)."""
    t = np.asarray(t, float)
    grow, _, period, start, lo, hi = _growth(leader)
    if grow == 0:
        return np.zeros(t.shape, bool)
    if period is None:
        side = t > hi if grow > 0 else t < lo
    else:
        u = np.mod(t - start, period)
        half = hi + 0.5 * (period - (hi - lo))  # the untouched arc's middle
        side = ((u > hi) & (u <= half)) if grow > 0 else u > half
    if near > 0:
        curve = leader.curve()
        end = start + (hi if grow > 0 else lo)
        ex, ey = leader.pose.apply(*curve.point(np.array([end])))
        qx, qy = leader.pose.apply(*curve.point(t))
        side |= np.hypot(qx - ex[0], qy - ey[0]) < near
    return side


def _cusp_elsewhere(c: Candidate, leader: Candidate) -> bool:
    """Whether a semicubical rival's fit, all on one branch, puts its cusp beyond the other end
    of the touches from the leader's cusp side (``_cusp_side``): its |t| is larger at the touch
    farthest toward where the leader's |κ| grows than at the touch farthest the other way."""
    grow, u, _, _, _, _ = _growth(leader)
    ct = np.asarray(c.t, float)
    if grow == 0 or c.cls != "semicubical_parabola" or ct.size != u.size or np.any(np.sign(ct) != np.sign(ct[0])):
        return False
    at_growth, other = (np.argmax(u), np.argmin(u)) if grow > 0 else (np.argmin(u), np.argmax(u))
    return bool(abs(ct[at_growth]) > abs(ct[other]))


class _Predictor:
    """What a candidate's predictions (``_prediction``) share, made once per ``next_touch``
    call (the leader is predicted at the places and again at every rival's contacts): its
    unknowns (shape, θ, x, y), their covariance (``_cov``), its posed curve, its dense points
    ``t_dense`` in the hand frame (``_closest``) and, for each unknown of nonzero variance,
    the finite-difference step h (a millionth of the unknown's own size, ``_natural``, not
    of its σ: an undetermined one's is 1e3 sizes) and the curve posed with it moved by h."""

    def __init__(self, c: Candidate, t_dense: np.ndarray, scale: float):
        self.vec, self.C = c.vector(), _cov(c, scale)
        size = _natural(c, scale)
        self.curve, self.pose = _posed(c.cls, self.vec)
        self.t_dense = t_dense
        self.dense = self.pose.apply(*self.curve.point(t_dense))
        self.steps = []
        for i in range(self.vec.size):
            if self.C[i, i] <= 0:
                continue
            h = 1e-6 * max(abs(self.vec[i]), min(size[i], 1e-3 * math.sqrt(self.C[i, i])), 1e-12)
            vp = self.vec.copy()
            vp[i] += h
            self.steps.append((i, h, *_posed(c.cls, vp)))


def _prediction(pr: _Predictor, px, py, nx, ny, lead_phi, W: np.ndarray, roll: float = 0.0):
    """(whitened mean (m, 4), whitened covariance (m, 4, 4), whitened G, touchable (m,)) of
    a candidate's measurement at every place (W whitens R; ``pr``: the candidate's
    ``_Predictor``): where its closest point is too near its cusp for a touch, its
    prediction tells nothing (not touchable); G by forward differences."""
    curve, pose = pr.curve, pr.pose
    t = _closest(curve, pose, pr.t_dense, pr.dense, px, py)
    mean = _measure(curve, pose, t, px, py, nx, ny, lead_phi)
    G = np.zeros(mean.shape + (pr.vec.size,))
    for i, h, cp, pp in pr.steps:
        tp = cp.project(t, *pp.inverse(px, py), steps=1)
        G[..., i] = (_measure(cp, pp, tp, px, py, nx, ny, lead_phi) - mean) / h
    mean, G = mean @ W.T, np.einsum("ab,mbi->mai", W, G)
    G = np.where(np.isfinite(G), G, 0.0)
    return mean, _spread(G, pr.C), G, _touchable(curve, t, roll), (curve, pose, t)


def _told(pr: _Predictor, d: Contacts, W: np.ndarray) -> np.ndarray:
    """The candidate's covariance of (shape, θ, x, y) conditioned on what its touches measured:
    C' = (C⁻¹ + G_Tᵀ G_T)⁻¹, G_T the whitened measurement (offset, tangent angle, κ, κ_s;
    ``_measure``) at every touch's contact along its tangent, each touch measured as well as
    a new roll (R = I whitened). A posterior cannot be less sure of a measured quantity than
    its measurement: the predictive spread at a touched place is at most that touch's noise.
    The linearized C of a rival at its limit of the leader is not (bench_wide --set wide seed
    619 parabola trial 12: the hyperbola and cubical rivals' G·C·Gᵀ ≈ 1e16 at the first touch's
    place, whose second touch "told parabola from hyperbola, expected χ² 130" by that spread
    alone, re-drew the first touch's noise and turned the answer semicubical). Where C holds
    the touches already (a well-posed fit) the spread they measured at most halves. Computed
    as S·V·diag(1/(1 + σ²))·Vᵀ·S with S = C^½ and G_T·S = U·diag(σ)·Vᵀ (no C⁻¹: an undetermined
    direction's variance is ~1e16 times another's)."""
    nx, ny = -np.sin(d.phi), np.cos(d.phi)
    G = _prediction(pr, d.x, d.y, nx, ny, d.phi, W)[2].reshape(4 * d.n, -1)
    vals, vecs = np.linalg.eigh(0.5 * (pr.C + pr.C.T))
    root = (vecs * np.sqrt(np.clip(vals, 0.0, None))) @ vecs.T
    sv, v_t = np.linalg.svd(G @ root, full_matrices=True)[1:]
    keep = np.ones(v_t.shape[0])
    keep[:sv.size] = 1.0 / (1.0 + sv * sv)
    B = root @ v_t.T
    return (B * keep) @ B.T


def _spread(G: np.ndarray, C: np.ndarray) -> np.ndarray:
    """The whitened predictive covariances G·C·Gᵀ (m, 4, 4) of whitened G (m, 4, k)."""
    return np.einsum("mai,ij,mbj->mab", G, C, G)


def _separation(delta: np.ndarray, P_a: np.ndarray, P_b: np.ndarray) -> np.ndarray:
    """Expected χ² separation of two candidates' whitened predictions N(a, I + P_a) and
    N(b, I + P_b) at each place (delta = b − a): Δᵀ(I + P_a + P_b)⁻¹Δ plus 8 × the
    Bhattacharyya distance's covariance term ½ ln det Σ − ¼ ln det(I + P_a) − ¼ ln det(I + P_b),
    Σ = I + (P_a + P_b)/2. Where one candidate predicts a measurement tightly and the other
    only loosely (a far hyperbola arm's rival of a line leader, whose vertex is barely
    placed: bench_wide seed 229 hyperbola 3, mean term ≤ 0.33 at every place, no
    suggestion), a touch there tells them apart even with equal means; a term that is not
    finite counts nothing."""
    eye = np.eye(delta.shape[-1])[None]
    mean_term = np.einsum("ma,mab,mb->m", delta, _inv(eye + P_a + P_b), delta)
    cov_term = 0.5 * np.linalg.slogdet(eye + 0.5 * (P_a + P_b))[1] - 0.25 * np.linalg.slogdet(eye + P_a)[1] \
        - 0.25 * np.linalg.slogdet(eye + P_b)[1]
    return mean_term + 8.0 * np.where(np.isfinite(cov_term), np.maximum(cov_term, 0.0), 0.0)


def _seats(tilt: np.ndarray, mean: np.ndarray, P: np.ndarray, W: np.ndarray, roll: float) -> np.ndarray:
    """Probability that a pad sent with a place's tangent (the leader's, in the direction of
    travel) meets a candidate's curve with its face, the candidate true: the curve's tangent
    there in its own direction of travel is tilted from the pad's by δφ ~ N(``tilt``, σ_φ²)
    (σ_φ the predicted tangent angle's σ, from the whitened prediction ``mean``, ``P``; W
    whitens R). A pad tilted by δφ meets a curve of curvature κ where the tangent has turned
    by δφ, δφ/|κ| along the pad, which leaves room for the roll while that is at most
    (``PAD_ROLLS`` − ½)·roll, and a pad that meets it with its end turns ``SEAT_RAD`` to
    seat; a tilt beyond π/2 comes in from the solid's side. So P(|δφ| ≤ tol): where the
    candidate's tangent differs from the leader's, or is unknown (a stretch extrapolated far
    from the touches), the touch is likely lost if that candidate is true."""
    kappa = np.abs(np.linalg.solve(W[2:, 2:], mean[:, 2:].T)[0])
    tol = _tilt_tolerance(kappa, roll)
    s_phi = np.sqrt(np.clip(P[:, 1, 1], 0.0, None)) / W[1, 1]
    s_phi = np.maximum(s_phi, 1e-12 * tol)  # an exact prediction: the tilt is the mean's
    p = special.ndtr((tol - tilt) / s_phi) - special.ndtr((-tol - tilt) / s_phi)
    return np.where(np.isfinite(p), p, 0.0)


def _tilt(c: Candidate, d: Contacts, posed, travel: np.ndarray) -> np.ndarray:
    """The angle from a pad's orientation ``travel`` to candidate c's tangent, in c's own
    direction of travel (the touches' on c), at c's points ``posed`` (``_prediction``): near
    π where c's curve runs the other way (the pad comes in from c's solid side)."""
    curve, pose, t = posed
    way = np.pi if travel_direction(c.curve(), c.pose, c.t, d.phi) < 0 else 0.0
    return wrap_angle(np.asarray(curve.tangent_angle(t), float) + pose.theta + way - travel)


def _contact(posed, lead_phi):
    """(x, y, tangent angle within π/2 of ``lead_phi``) of a candidate's points t: where a
    pad aimed at the places would touch that candidate's curve."""
    curve, pose, t = posed
    qx, qy = pose.apply(*curve.point(t))
    ang = np.asarray(curve.tangent_angle(t), float) + pose.theta
    return np.asarray(qx, float), np.asarray(qy, float), lead_phi + _wrap_half(ang - lead_phi)


def _line_rivals_landed(curved: list, idx: np.ndarray, pair: np.ndarray, w_rivals: float, lands) -> tuple[np.ndarray, np.ndarray]:
    """A line leader's class gain and whether a pad lands for at least ``CURVED_LAND_MIN`` of
    its curved rivals' weight ``w_rivals``, at the places ``idx`` (elsewhere 0 and False):
    ``pair`` · Σ w_c·p_c·seats_c·resolved_c / ``w_rivals``, p_c the rival clear of its cusp there and
    ``lands(c, idx)``; ``curved``: (c, w_c, clear, seats, resolved) over every place."""
    size = curved[0][2].size
    on, told = np.zeros(size), np.zeros(size)
    for c, wc, clear, seats, resolved in curved:
        on_c = np.zeros(size, bool)
        k = idx[clear[idx]]  # a place's landing is its own: asked only where c is clear of its cusp
        if k.size:
            on_c[k] = lands(c, k)
        on += wc * on_c
        told += wc * on_c * seats * resolved
    return pair * told / w_rivals, on >= CURVED_LAND_MIN * w_rivals


def _beats_the_rest(ig_class: np.ndarray, on_all: np.ndarray, bound: np.ndarray, rest: np.ndarray) -> bool:
    """Whether the first place of largest class gain among those that help and land
    (``ig_class`` ≥ CLASS_GAIN_MIN, ``on_all``) would stay the choice whatever the places
    ``rest`` (sorted by decreasing ``bound``, their largest possible gain, then by index)
    gave: its gain beats their bounds, or equals them and comes first."""
    ok = on_all & (ig_class >= CLASS_GAIN_MIN)
    if not ok.any():
        return False
    best = float(np.max(ig_class[ok]))
    first = int(np.flatnonzero(ok & (ig_class == best))[0])
    top = float(bound[rest[0]])
    return best > top or (best == top and bool(np.all(rest[bound[rest] >= best] > first)))


def _inv(S: np.ndarray) -> np.ndarray:
    """Inverses of whitened predictive covariances (m, 4, 4) = I + PSD (pseudo-inverses:
    a direction the prediction's uncertainty swamps, P ~ 1e30 from an ill-determined rival,
    tells nothing); 0 (no information) where one is not finite."""
    good = np.all(np.isfinite(S), axis=(1, 2))
    out = np.zeros_like(S)
    if good.any():
        out[good] = np.linalg.pinv(S[good], hermitian=True)
    return out


def roll_cov(d: Contacts) -> np.ndarray:
    """The (κ, κ_s) covariance of one more roll like the request's: the stated covariance,
    with the floors of ``Contacts.whitener``, of the touch of median κ variance (the same
    estimator over the same length of roll and noise states about the same covariance
    anywhere; the median keeps one touch's large truncation term out)."""
    W = d.whitener()
    covs = [np.linalg.inv(w.T @ w) for w in W]
    return covs[int(np.argsort([c[0, 0] for c in covs])[(len(covs) - 1) // 2])]


def _whitener(noise: NoiseModel, samples: int, c_roll: np.ndarray) -> np.ndarray:
    """W with W·R·Wᵀ = I for R = diag(σ_pos²/n, σ_φ²/n) ⊕ C_roll."""
    n = max(samples, 1)
    W = np.zeros((4, 4))
    W[0, 0] = math.sqrt(n) / max(noise.pos, 1e-12)
    W[1, 1] = math.sqrt(n) / max(noise.phi, 1e-12)
    W[2:, 2:] = np.linalg.inv(np.linalg.cholesky(c_roll))
    return W


def _entropy2(p):
    p = np.clip(p, 1e-300, 1.0)
    q = np.clip(1.0 - p, 1e-300, 1.0)
    return -(p * np.log(p) + q * np.log(q))


def next_touch(cands: Sequence[Candidate], leader: Candidate, d: Contacts, noise: NoiseModel,
               samples: int, reach: Reach | None = None, roll: float = 0.0,
               missed: Sequence[MissedPlace] = ()) -> dict | None:
    """The suggested next touch (module docstring) or None when no touch helps; ``missed``:
    places where touches sent were lost (``_on_missed_stretch``)."""
    with np.errstate(all="ignore"):
        return _next_touch(cands, leader, d, noise, samples, reach, roll, missed)


def _on_missed_stretch(px, py, travel, kappa, missed: Sequence[MissedPlace], roll: float) -> np.ndarray:
    """Whether a pad sent to each place (px, py) with orientation ``travel`` (the direction of
    travel), on a curve of curvature ``kappa`` there, comes in on the stretch a pad sent to one
    of the ``missed`` places met, and was lost there: its middle less than a pad length
    (2 ``PAD_ROLLS`` rolls) from that pad's along its tangent (the two pads overlap, and the
    lost one may have met what stopped it anywhere along itself) and its orientation within
    the pad's tilt tolerance of that pad's (``_tilt_tolerance``: tilted less, a pad's face
    meets the same stretch with room for its roll, so the two come in along one normal).
    Across the tangent nothing counts: a pad sweeps its whole normal strip on its way in."""
    px, py, travel = np.asarray(px, float), np.asarray(py, float), np.asarray(travel, float)
    tol = _tilt_tolerance(np.abs(np.asarray(kappa, float)), roll)
    same = np.zeros(px.shape, bool)
    for m in missed:
        along = (px - m.x) * math.cos(m.phi) + (py - m.y) * math.sin(m.phi)
        same |= (np.abs(wrap_angle(travel - m.phi)) <= tol) & (np.abs(along) < 2.0 * PAD_ROLLS * roll)
    return same


def _tilt_tolerance(kappa: np.ndarray, roll: float) -> np.ndarray:
    """How far a pad may be tilted from a boundary's tangent and still meet it with its face
    with room for the roll, on a curve of curvature |κ| ``kappa``: a tilt δφ puts the contact
    δφ/|κ| along the pad, at most (``PAD_ROLLS`` − ½)·roll, and a pad that meets it with its
    end turns ``SEAT_RAD`` to seat; a tilt beyond π/2 comes in from the solid's side."""
    return np.clip(kappa * roll * (PAD_ROLLS - 0.5), SEAT_RAD, np.pi / 2)


def _next_touch(cands, leader, d, noise, samples, reach, roll, missed):
    bic = np.array([c.bic for c in cands], float)
    ok = np.isfinite(bic)
    if not ok.any():
        return None
    w = np.where(ok, np.exp(-0.5 * (bic - bic[ok].min())), 0.0)
    w /= w.sum()
    lead_i = next(i for i, c in enumerate(cands) if c is leader)
    others = [(c, w[i]) for i, c in enumerate(cands) if i != lead_i and w[i] > MIN_WEIGHT]
    w_lead = max(float(w[lead_i]), MIN_WEIGHT)
    turn = d.dominant_kappa()
    padded = roll > 0 and turn != 0  # a pad's approach modelled: the solid's side is known
    pads = {}  # id(candidate): its curve, dense t's and pad's side for ``lands``

    def lands(c: Candidate, px, py, travel) -> np.ndarray:
        """Whether a pad sent to each place lands there on c's curve (``_landed``). A
        semicubical rival whose other branch would have kept the pads off all its own
        touches (a cusp placed beside touches far out on a branch) says nothing about that
        branch: its touched one only."""
        if not padded:
            return np.ones(px.size, bool)
        if id(c) not in pads:  # what does not change from place to place, once per candidate
            curve, t_pad = c.curve(), _pad_span(c)
            args = (_solid_left(c, d, turn), PAD_ROLLS * roll, 0.5 * roll, d.scale)
            if c is not leader and c.cls == "semicubical_parabola" and \
                    not _landed(curve, c.pose, t_pad, d.x, d.y, d.phi, *args).any():
                side = np.sign(np.median(c.t))
                t_pad = t_pad[np.sign(t_pad) == side] if side else t_pad
            pads[id(c)] = curve, t_pad, args
        curve, t_pad, args = pads[id(c)]
        return _landed(curve, c.pose, t_pad, px, py, travel, *args)

    # places on the leader's curve (a semicubical's other branch too, as far from the cusp)
    curve = leader.curve()
    t = np.concatenate((_t_span(leader), _far_span(leader)))
    if curve.name == "semicubical_parabola":
        t = np.concatenate((t, -t))
    px, py = leader.pose.apply(*curve.point(t))
    phi = np.asarray(curve.tangent_angle(t), float) + leader.pose.theta
    keep = np.isfinite(px) & np.isfinite(py) & np.isfinite(phi)
    far = np.zeros(px.size, bool)  # beyond one extent of the touches: for telling classes apart only
    if curve.t_period is None:
        near = np.min(np.hypot(px[:, None] - d.x[None, :], py[:, None] - d.y[None, :]), axis=1)
        far = near > d.scale
        keep &= near <= (d.scale if curve.name == "line" else PLACE_EXTENTS * d.scale)
    flip = np.pi if travel_direction(curve, leader.pose, leader.t, d.phi) < 0 else 0.0  # to the direction of travel
    if reach is not None:  # the place's tangent in the touches' direction of travel: a robot's reach may depend on it
        keep &= reach.contains(px, py, phi + flip)
    keep &= _touchable(curve, t, roll)
    keep &= ~_on_missed_stretch(px, py, phi + flip, curve.kappa(t), missed, roll)
    if keep.any() and curve.name != "line":  # where a pad sent there lands on the leader's curve (a line: anywhere)
        keep[keep] = lands(leader, px[keep], py[keep], phi[keep] + flip)
    if not keep.any():
        return None
    px, py, phi, far = px[keep], py[keep], phi[keep], far[keep]
    cusp_side = _cusp_side(leader, t[keep], (PAD_ROLLS - 0.5) * roll)
    misplaced = False  # a semicubical rival whose fit puts its cusp beyond the touches' other end
    nx, ny = -np.sin(phi), np.cos(phi)
    W = _whitener(noise, samples, roll_cov(d))
    scale = d.scale
    lead_pred = _Predictor(leader, np.concatenate((_t_span(leader, 1.0, N_DENSE), _far_span(leader, N_DENSE // 2))),
                           scale)
    mean_lead, P_lead, G_lead, _, _ = _prediction(lead_pred, px, py, nx, ny, phi, W)
    told_lead = _told(lead_pred, d, W)  # what a touch adds beside the touches, for telling classes apart
    S_lead = _spread(G_lead, told_lead)
    own = np.all(np.isfinite(mean_lead), axis=1)  # the leader's κ, κ_s defined there
    # parameters: entropy lost, and the shrink of the largest relative σ (whitened: R = I)
    eye = np.eye(4)[None]
    P_lead = np.where(np.isfinite(P_lead), P_lead, 0.0)
    ig_param = 0.5 * np.linalg.slogdet(eye + P_lead)[1]
    seat_lead = _seats(np.zeros(px.size), mean_lead, P_lead, W, roll) if padded else np.ones(px.size)
    C = lead_pred.C
    k = len(CURVES[leader.cls].param_names)
    shrink = np.ones(px.size)
    rel_now = 0.0
    if k:
        vals = np.abs(leader.vector()[:k])
        rel = np.sqrt(np.clip(np.diag(C)[:k], 0, None)) / np.where(vals > 0, vals, 1.0)
        i_max = int(np.argmax(rel))
        rel_now = float(rel[i_max])
        CG = np.einsum("ij,maj->mia", C, G_lead)  # C·Gᵀ per place
        K = np.einsum("mia,mab->mib", CG, _inv(P_lead + eye))
        var_after = C[i_max, i_max] - np.einsum("mb,mb->m", K[:, i_max, :], CG[:, i_max, :])
        shrink = math.sqrt(max(C[i_max, i_max], 0.0)) / np.sqrt(np.clip(var_after, 1e-300, None))
    # classes
    ig_class = np.zeros(px.size)
    on_all = np.ones(px.size, bool)  # the pad lands whichever likely class is true
    best_sep = {}
    landed = w_lead * seat_lead
    line_lead = leader.cls == "line"
    untold = False  # some likely rival no place within one extent tells from the leader
    curved = []  # a line leader's rivals: (c, weight, clear of a cusp, seats, resolved), landing checked below
    for c, wc in others:
        pred_c = _Predictor(c, _t_span(c, 2.0, N_DENSE), scale)
        mean_c, P_c, G_c, ok_c, posed_c = _prediction(pred_c, px, py, nx, ny, phi, W, roll)
        told_c = _told(pred_c, d, W)
        S_c = _spread(G_c, told_c)
        chi2 = _separation(mean_c - mean_lead, S_lead, S_c)
        # c true: the pad touches c's curve at c's point nearest the place; the leader
        # explains that touch by its own nearest point, not by the place
        # (only where the first way separates them at all: the smaller counts)
        sep = np.flatnonzero(~(chi2 <= SEPARATION_MIN))
        if sep.size:
            qx, qy, qphi = _contact((posed_c[0], posed_c[1], posed_c[2][sep]), phi[sep])
            mean_b, _, G_b, _, _ = _prediction(lead_pred, qx, qy, -np.sin(qphi), np.cos(qphi), qphi, W)
            delta = mean_b - np.concatenate((np.zeros_like(mean_c[sep, :2]), mean_c[sep, 2:]), axis=1)
            chi2_b = _separation(delta, _spread(G_b, told_lead), S_c[sep])
            chi2[sep] = np.minimum(chi2[sep], np.where(np.isfinite(chi2_b), chi2_b, np.inf))
        chi2 = np.where(ok_c & own, np.where(np.isfinite(chi2), chi2, 1e6), 0.0)
        # c true: the pad lands on c's curve, never toward a semicubical rival's cusp from its
        # touches, and seats there, or the touch is lost
        on_c = ~_toward_cusp(c, posed_c[2])
        if _cusp_elsewhere(c, leader):
            on_c &= ~cusp_side  # its fit puts its cusp elsewhere: nor where the touches' curvature grows
            misplaced = True
        seats = _seats(_tilt(c, d, posed_c, phi + flip), mean_c, P_c, W, roll) if padded else 1.0
        resolved = 1.0 - np.exp(-chi2 / 8.0)
        if line_lead:
            curved.append((c, wc, on_c, seats, resolved))
        else:
            if padded:  # a place's landing is its own: asked only where c's pad may land
                k_c = np.flatnonzero(on_c)
                on_c[k_c] = lands(c, px[k_c], py[k_c], phi[k_c] + flip)
            if wc >= LAND_WEIGHT_MIN:
                on_all &= on_c
            landed += wc * on_c * seats
            near_c = ~far & on_c
            if wc >= LAND_WEIGHT_MIN and not (near_c.any() and float(np.max(chi2[near_c])) >= FAR_SEPARATION):
                untold = True  # no place within one extent tells this likely rival from the leader
            ig_class += (w_lead + wc) * _entropy2(w_lead / (w_lead + wc)) * resolved
        best_sep[c.cls] = chi2
    w_rivals = sum(wc for _, wc in others)
    if line_lead and w_rivals > 0:
        # every rival of a line is curved: one alternative, "curved, not line", of weight
        # their sum, resolved in proportion to the weight a pad lands for and tells from the
        # line there; the pad must land for at least half of it. Rival by rival, a far
        # hyperbola arm answered line was tested where the ellipse rival bends (outward),
        # never where the hyperbola rival does (toward its vertex, vetoed by the semicubical
        # rival's cusp beside the touches; bench_wide seed 271 hyperbola 7)
        # The landing checks (half of the time: bench_wide seed 293 line answers 84 / 128 ms)
        # run first at the LAND_FIRST places of largest ``bound`` (the class gain were the pad
        # to land for every rival), then at as many again of the next, for as long as no place
        # landed for beats every unchecked one's bound (those reaching CLASS_GAIN_MIN): the same choice
        pair = (w_lead + w_rivals) * _entropy2(w_lead / (w_lead + w_rivals)) * seat_lead
        bound = pair * sum(wc * on_c * seats * resolved for _, wc, on_c, seats, resolved in curved) / w_rivals
        order = np.argsort(-bound, kind="stable")
        order = order[bound[order] >= CLASS_GAIN_MIN]

        def lands_at(c: Candidate, k: np.ndarray):
            return lands(c, px[k], py[k], phi[k] + flip) if padded else True

        done = LAND_FIRST
        ig_class, on_all = _line_rivals_landed(curved, order[:done], pair, w_rivals, lands_at)
        while order.size > done and not _beats_the_rest(ig_class, on_all, bound, order[done:]):
            # as many again of the rest: each place's gain and landing are its own (0 and False elsewhere)
            ig_more, on_more = _line_rivals_landed(curved, order[done:2 * done], pair, w_rivals, lands_at)
            ig_class, on_all = ig_class + ig_more, on_all | on_more
            done *= 2
    else:  # a lost touch tells nothing, whichever candidate is true: every pair's resolution
        # counts in proportion to the chance the pad lands and seats
        ig_class *= landed / (w_lead + w_rivals)
    gain = ig_class + w_lead * seat_lead * np.where(np.isfinite(ig_param), ig_param, 0.0)
    helps = (ig_class >= CLASS_GAIN_MIN) | ((shrink >= SHRINK_MIN) & (rel_now >= REL_SIGMA_ENOUGH))
    # beyond one extent, where the leader's extrapolation drifts: only a place that tells
    # likely classes apart and where the pad lands whichever likely class is true
    helps &= ~far | ((ig_class >= CLASS_GAIN_MIN) & on_all & untold)
    if not helps.any():
        return None
    # a lost touch tells nothing: where it lands for every likely class, but on a semicubical
    # leader's other branch, which no rival has
    if curve.name == "semicubical_parabola":
        on_all |= np.sign(t[keep]) != np.sign(np.median(leader.t))
    if (helps & on_all).any():
        helps &= on_all
    elif misplaced and (helps & ~cusp_side).any():  # no place lands for all (a degenerate
        helps &= ~cusp_side  # semicubical rival lands nowhere): still never on the cusp's side
    # a touch at a touched place adds no place and re-draws that touch's noise: elsewhere, where some place helps
    fresh = helps & ~d.at_touched_place(px, py, phi)
    if fresh.any():
        helps = fresh
    # while the class is in doubt, the place that tells the classes apart best; else the
    # place of largest gain (parameters)
    score = ig_class if float(np.max(ig_class)) >= CLASS_GAIN_MIN else gain
    j = int(np.argmax(np.where(helps, score, -np.inf)))
    why = _why(leader, best_sep, j, ig_class[j], shrink[j], rel_now)
    return {"x": float(px[j]), "y": float(py[j]), "phi": float(wrap_angle(phi[j] + flip)),
            "gain": float(gain[j]), "why": why}


def _why(leader: Candidate, sep: dict, j: int, ig_class: float, shrink: float, rel_now: float) -> str:
    parts = []
    if ig_class >= CLASS_GAIN_MIN and sep:
        cls, chi2 = max(((c, float(v[j])) for c, v in sep.items()), key=lambda kv: kv[1])
        parts.append(f"tells {leader.cls} from {cls} (expected chi2 separation {chi2:.3g})")
    if rel_now >= REL_SIGMA_ENOUGH and shrink >= SHRINK_MIN:
        parts.append(f"shrinks the largest relative parameter uncertainty ({100 * rel_now:.2g} %) "
                     f"by {shrink:.2g}x")
    return "a touch here " + " and ".join(parts) if parts else "the most informative place left"
