"""Kinematics of the jaw: ticks → joint angles → pad lines → contacts → touches.

Pure, vectorized functions (numpy broadcasting over leading axes of readings).

Frames and conventions (docs/ARCHITECTURE.md): hand frame x forward, y left, angles CCW;
``q = direction · (tick − zero_tick) · 2π/ticks_per_rev`` (each joint's model's resolution). Finger with base ``(bx, by, β)``, joint
angles ``q1, q2`` and links ``L1, L2``: ``α1 = β + q1``, ``α2 = α1 + q2``, distal joint
``J2 = B + L1·e(α1)``, fingertip ``J2 + L2·e(α2)``. The pad is the segment
``J2 + u·e(α2) + offset·n`` for ``u ∈ [L2 − length, L2]``, with outward normal
``n = e(α2 + side·π/2)`` (side = +1 'left', −1 'right'), pointing from the finger into
the world. A pad line is ``{p : n(ψ)·p = d}`` with ψ the angle of n.

The envelope (:class:`TouchEnvelope`). A pad rolled on a boundary that is convex toward it gives lines
``n(ψ)·p = d(ψ)``; the boundary point touched at ψ is their envelope
``p = d·n + d'·n⊥`` with ``n⊥ = dn/dψ``, the boundary's tangent angle is
``φ = ψ − π/2`` (the solid on the left of the traversal: increasing ψ is
counter-clockwise around the object), and since the radius of curvature is
``ρ = −(d + d'')``, arc length is ``s(ψ) = −∫(d + d'') dψ`` (exact identity). d' and d''
come from one least-squares polynomial of d(ψ) over the touch, about the touch's centre of
curvature so the polynomial only has to follow the change of the boundary's curvature; the
same fit gives ρ and dρ/dψ at every sample (tactile_jaw.envelope reads κ, κ_s from them).

Accuracy: the only data error is encoder quantization, ±½ tick = ±π/ticks_per_rev rad per
joint. :func:`quantization_bound` propagates it to first order (worst case over all joints,
Σ_j |∂output/∂q_j|·π/ticks_per_rev_j) for every output of :func:`touch_from_pad_lines`; the
tests check the errors on exact curves against it (docs/kinematics.md). A jaw that declares
compliance (hand_driver.config) reads each link c·τ behind its encoder and its pad's face k·F in:
:func:`compliance_turns` takes both out of a reading, τ = Kt·I from its own Present Currents
(:func:`joint_torques`) and F the force they balance (:func:`pressed_force`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from hand_driver.config import FingerConfig, JawConfig, JointConfig
from hand_driver.units import half_tick_rad, rad_to_ticks_exact, ticks_to_rad
from tactile_common.angles import wrap_angle
from tactile_common.errors import InputError


class Unreachable(InputError):
    """No joint angles within the limits put the pad where asked."""


def unit(angle: float) -> np.ndarray:
    """The unit vector at ``angle`` (rad) from +x: a pad line's normal n(ψ), a direction."""
    return np.array([math.cos(angle), math.sin(angle)])


def _e(a):
    """:func:`unit` over an array of angles (the last axis holds x, y)."""
    a = np.asarray(a, dtype=float)
    return np.stack([np.cos(a), np.sin(a)], axis=-1)


# ----------------------------------------------------------------------------- ticks


def ticks_to_angles(joints: tuple[JointConfig, ...], ticks) -> np.ndarray:
    """Encoder ticks (..., n_joints) → joint angles q (rad), same shape: the link angles of
    joints under their working load (:func:`working_loads`; :func:`load_offsets` for others)."""
    zero = np.array([j.zero_tick for j in joints])
    sign = np.array([j.direction for j in joints], dtype=float)
    return ticks_to_rad(ticks, zero, sign, resolutions(joints))


#: a pad cannot be moved along its normal at a fixed angle when the base link is within this of
#: parallel to it (n·e1⊥ below it): :func:`give_turns` then gives no turn
GIVE_SINGULAR_COS = 0.05


def give_turns(base_angle: float, q, l1: float, side_sign: float, depth_mm) -> np.ndarray:
    """Joint turns (rad, (..., 2)) that move a pad line ``depth_mm`` along its normal at the same
    angle ψ: the base joint by Δ = δ / (L1 · n·e1⊥), the distal by −Δ (the pad translates along
    e1⊥, its normal component δ): how a pad's face giving δ under its contact force places the links
    (the emulator's declared pad compliance, hand_driver.sim.errors, and the calibration's model of
    it). No turn where ``depth_mm`` ≤ 0 or the base link is within ``GIVE_SINGULAR_COS`` of
    parallel to the pad. Vectorized over ``q`` (..., 2) and ``depth_mm`` (...)."""
    q = np.asarray(q, dtype=float)
    depth = np.asarray(depth_mm, dtype=float)
    a1 = base_angle + q[..., 0]
    a2 = a1 + q[..., 1]
    reach = l1 * side_sign * (np.sin(a2) * np.sin(a1) + np.cos(a2) * np.cos(a1))  # L1 · n·e1⊥
    ok = (depth > 0.0) & (np.abs(reach) >= GIVE_SINGULAR_COS * l1)
    turn = np.where(ok, depth / np.where(ok, reach, 1.0), 0.0)
    return np.stack([turn, -turn], axis=-1)


def joint_torques(finger: FingerConfig, current_ma) -> np.ndarray:
    """Each joint's torque (N·m along its angle) from its Present Current (mA as read, (..., 2)):
    Kt·I, each model's torque constant (hand_driver.control_table), signed by the joint's direction:
    a blocked servo's current balances its contact's torque (hand_driver.sim.errors)."""
    kt = np.array([j.spec.torque_nm_per_a for j in finger.joints])
    sign = np.array([j.direction for j in finger.joints], dtype=float)
    return kt * sign * np.asarray(current_ma, dtype=float) / 1000.0


def pressed_force(finger: FingerConfig, q, point, torques, direction=None) -> np.ndarray:
    """The contact force F ≥ 0 (N, (...)) that the joints' torques ``torques`` (N·m, (..., 2))
    balance best, τ_j = a_j·F, a_j the :func:`moment_arms` (m) of the press at ``point`` along
    ``direction`` (default the pad's normal): :func:`balanced_force`."""
    return balanced_force(moment_arms(finger, q, point, direction) / 1000.0, torques)


def balanced_force(arms_m, torques) -> np.ndarray:
    """The force F ≥ 0 (N, (...)) that joint torques ``torques`` (N·m, (..., 2)) balance best
    against moment arms ``arms_m`` (m, (..., 2)), τ_j = a_j·F: the least squares
    Σ a_j τ_j / Σ a_j² (0 where every arm is 0): :func:`pressed_force`, and the emulator's
    force of a pad from its servos' currents or drive (hand_driver.sim.errors)."""
    arms = np.asarray(arms_m, dtype=float)
    norm = np.maximum(np.sum(arms**2, axis=-1), 1e-12)
    return np.maximum(0.0, np.sum(arms * np.asarray(torques, dtype=float), axis=-1) / norm)


def declares_compliance(finger: FingerConfig) -> bool:
    """Whether any of the finger's joints declares a compliance or its pad a give."""
    return any(j.compliance_deg_per_nm > 0.0 for j in finger.joints) or finger.pad.compliance_mm_per_n > 0.0


def compliance_turns(finger: FingerConfig, q, torques, force) -> np.ndarray:
    """What to subtract from the encoders' joint angles ``q`` (rad, (..., 2)) for the link angles
    of readings whose joints carry ``torques`` (N·m) and whose pad presses with ``force`` (N):
    each link c·τ behind its encoder (c ``compliance_deg_per_nm``), then the turns that put the
    pad's line k·F further in along its normal (k ``compliance_mm_per_n``, :func:`give_turns`):
    the emulator's declared compliance (hand_driver.sim.errors) and the calibration's model of it
    (:func:`yield_turns` with the finger's own link, c and k)."""
    return yield_turns(finger.base.angle, finger.joints[0].link_mm, finger.pad.side_sign,
                       np.radians([j.compliance_deg_per_nm for j in finger.joints]),
                       finger.pad.compliance_mm_per_n, q, torques, force)


def yield_turns(base_angle: float, l1: float, side_sign: float, c_rad_per_nm, k_mm_per_n: float, q, torques,
                force) -> np.ndarray:
    """:func:`compliance_turns` of a finger with base angle ``base_angle``, base link ``l1`` (mm),
    pad side ``side_sign``, joint compliances ``c_rad_per_nm`` (rad per N·m, (2,)) and pad give
    ``k_mm_per_n``: c·τ, plus the :func:`give_turns` of k·F from the encoders' angles less c·τ.
    The calibration (hand_driver.calibration_fit) calls it with the parameters it fits."""
    q = np.asarray(q, dtype=float)
    bent = np.asarray(c_rad_per_nm, dtype=float) * np.asarray(torques, dtype=float)
    give = k_mm_per_n * np.asarray(force, dtype=float)
    return bent + give_turns(base_angle, q - bent, l1, side_sign, give)


def working_loads(finger: FingerConfig) -> np.ndarray:
    """Each joint's working load direction (±1, counter-clockwise +): the way a press of the
    pad's face turns it, toward the pad's side. A joint's torque is arm·F with arm from
    :func:`moment_arms`; for a face contact u mm along the distal link from its joint the
    distal arm is side·u and the proximal one side·(L1·cos q2 + u), so both joints bear
    toward the pad's side unless the finger is folded beyond |q2| ≈ 100°. With declared backlash, ``zero_tick`` is the encoder reading at
    the link's zero under this load (hand_driver.sim.errors, hand_driver.calibration_fit)."""
    return np.full(len(finger.joints), float(finger.pad.side_sign))


def load_offsets(finger: FingerConfig, load) -> np.ndarray:
    """What to subtract from :func:`ticks_to_angles` (rad, broadcast like ``load``) for the link
    angles of a reading whose joints bear the load signs ``load`` (0: unloaded, taken as the
    working load): (load − working)·backlash/2 per joint; zero under the working load."""
    load = np.asarray(load, dtype=float)
    w = working_loads(finger)
    half = np.radians([j.backlash_deg for j in finger.joints]) / 2.0
    return np.where(load == 0.0, 0.0, load - w) * half


def angles_to_ticks(joints: tuple[JointConfig, ...], q) -> np.ndarray:
    """Joint angles (..., n_joints) → encoder ticks (float; round to command a servo)."""
    zero = np.array([j.zero_tick for j in joints])
    sign = np.array([j.direction for j in joints], dtype=float)
    return rad_to_ticks_exact(q, zero, sign, resolutions(joints))


def resolutions(joints: tuple[JointConfig, ...]) -> np.ndarray:
    """Encoder ticks per turn of each joint (its model's resolution)."""
    return np.array([j.ticks_per_rev for j in joints], dtype=float)


def within_limits(joints: tuple[JointConfig, ...], q, margin_rad: float = 0.0) -> np.ndarray:
    """True where every joint angle is inside [min_deg, max_deg] (shrunk by margin)."""
    q = np.asarray(q, dtype=float)
    lo = np.array([j.min_rad for j in joints]) + margin_rad
    hi = np.array([j.max_rad for j in joints]) - margin_rad
    return np.all((q >= lo) & (q <= hi), axis=-1)


# ----------------------------------------------------------------------------- forward


@dataclass(frozen=True)
class PadLine:
    """Pad pose(s); arrays with leading reading axes. ``normal`` points into the world."""

    psi: np.ndarray  # angle of the outward normal
    d: np.ndarray  # n·p for every p on the pad line
    normal: np.ndarray  # (..., 2)
    tangent: np.ndarray  # (..., 2): the distal link direction e(α2)
    proximal: np.ndarray  # (..., 2) pad end nearer the distal joint
    distal: np.ndarray  # (..., 2) pad end at the fingertip
    joint2: np.ndarray  # (..., 2) the distal joint J2

    def pad_coordinate(self, p) -> np.ndarray:
        """Position of point(s) p along the pad, measured from the proximal end (mm)."""
        return np.sum((np.asarray(p, dtype=float) - self.proximal) * self.tangent, axis=-1)

    def at(self, i) -> "PadLine":
        """The pad line(s) of reading(s) ``i`` (an index or index array of the leading axis)."""
        return PadLine(*(np.asarray(getattr(self, f))[i] for f in _PAD_FIELDS))

    @staticmethod
    def stack(lines) -> "PadLine":
        """One PadLine of a sequence of single readings' pad lines (a touch's samples)."""
        return PadLine(*(np.stack([np.asarray(getattr(ln, f)) for ln in lines]) for f in _PAD_FIELDS))


_PAD_FIELDS = ("psi", "d", "normal", "tangent", "proximal", "distal", "joint2")


def crossing(a: PadLine, b: PadLine) -> np.ndarray | None:
    """The point two single pad lines ``n·p = d`` cross at (their envelope point, or what the
    pad turned about between them), or None if they are parallel."""
    m = np.array([a.normal, b.normal], dtype=float)
    if abs(np.linalg.det(m)) < 1e-9:
        return None
    return np.linalg.solve(m, np.array([float(a.d), float(b.d)]))


def nearest_point(normals, d) -> np.ndarray:
    """The point nearest the lines ``normals[i]·p = d[i]`` (least squares; ≥ 2 lines of
    distinct angle): the corner a pad pivoted about."""
    return np.linalg.lstsq(np.asarray(normals, dtype=float), np.asarray(d, dtype=float), rcond=None)[0]


@dataclass(frozen=True)
class StraightLine:
    """The straight line nearest points (total least squares: the first right singular vector
    of the points about ``centre`` is its direction), as ``centre`` on it, the unit vectors
    ``along`` and ``across`` it, and each point's coordinates ``u`` along and ``v`` across it
    from ``centre``: a pad end sliding along a face, the ends resting on one."""

    centre: np.ndarray
    along: np.ndarray
    across: np.ndarray
    u: np.ndarray
    v: np.ndarray

    @property
    def worst(self) -> float:
        """The largest distance of a point from the line (mm)."""
        return float(np.max(np.abs(self.v)))

    @property
    def ends(self) -> tuple[np.ndarray, np.ndarray]:
        """The feet of the points farthest apart along the line."""
        return self.centre + float(np.min(self.u)) * self.along, self.centre + float(np.max(self.u)) * self.along


def straight_line(points, through=None) -> StraightLine:
    """:class:`StraightLine` nearest ``points`` (n, 2), n ≥ 2: through their centroid, or
    through the point ``through`` (a corner, a support the line must pass)."""
    pts = np.asarray(points, dtype=float).reshape(-1, 2)
    centre = pts.mean(axis=0) if through is None else np.asarray(through, dtype=float)
    rel = pts - centre
    along, across = np.linalg.svd(rel)[2]
    return StraightLine(centre, along, across, rel @ along, rel @ across)


def chain_pad_line(base, q, links, pad_offset, pad_length, side_sign) -> PadLine:
    """Forward kinematics with explicit geometry (used by the fit): ``base`` (x, y, angle),
    ``q`` (..., 2), ``links`` (L1, L2)."""
    q = np.asarray(q, dtype=float)
    bx, by, ba = base
    a1 = ba + q[..., 0]
    a2 = a1 + q[..., 1]
    e1, e2 = _e(a1), _e(a2)
    j2 = np.array([bx, by]) + links[0] * e1
    psi = a2 + side_sign * (np.pi / 2)
    n = _e(psi)
    distal = j2 + links[1] * e2 + pad_offset * n
    proximal = distal - pad_length * e2
    return PadLine(psi=wrap_angle(psi), d=np.sum(n * distal, axis=-1), normal=n, tangent=e2,
                   proximal=proximal, distal=distal, joint2=j2)


def finger_pad_line(finger: FingerConfig, q) -> PadLine:
    """Pad line(s) of one finger for its joint angles q (..., 2) in rad."""
    j1, j2 = finger.joints
    return chain_pad_line((finger.base.x, finger.base.y, finger.base.angle), q,
                          (j1.link_mm, j2.link_mm), finger.pad.offset_mm, finger.pad.length_mm,
                          finger.pad.side_sign)


def finger_pad_line_from_ticks(cfg: JawConfig, finger: str, ticks) -> PadLine:
    """Pad line(s) of ``finger`` from that finger's encoder ticks (..., 2)."""
    f = cfg.finger(finger)
    return finger_pad_line(f, ticks_to_angles(f.joints, ticks))


# ----------------------------------------------------------------------------- inverse


def moment_arms(finger: FingerConfig, q, point, direction=None) -> np.ndarray:
    """Moment arm (mm) about each joint of a unit force the finger applies at ``point`` along
    the unit vector ``direction``: ((p − J_j) × direction)_z, counter-clockwise positive, so
    joint j carries the torque arm_j·F (N·mm) and its gear's teeth bear on the side
    sign(arm_j): **the one load direction** of the emulator's backlash (hand_driver.sim.errors),
    the calibration's readings and the exploration's touches (tactile_jaw.pipeline). For a pad
    pressing an object ``direction`` is the pad's outward normal (the default, None); a pad
    end pressing it pushes along the object's normal. Vectorized: ``q`` (..., 2), ``point``
    and ``direction`` (..., 2) → (..., 2). Along the pad's normal at u mm along the distal
    link from its joint the distal arm is side·u and the proximal one side·(L1·cos q2 + u):
    :func:`working_loads`."""
    q = np.asarray(q, dtype=float)
    p = np.asarray(point, dtype=float)
    if direction is None:
        direction = finger_pad_line(finger, q).normal
    u = np.asarray(direction, dtype=float)
    a1 = finger.base.angle + q[..., 0]
    j1 = np.array([finger.base.x, finger.base.y])
    j2 = j1 + finger.joints[0].link_mm * np.stack([np.cos(a1), np.sin(a1)], axis=-1)
    return np.stack([(p[..., 0] - j[..., 0]) * u[..., 1] - (p[..., 1] - j[..., 1]) * u[..., 0] for j in (j1, j2)],
                    axis=-1)


def ik_line_angles(finger: FingerConfig, psi, d) -> tuple[np.ndarray, np.ndarray]:
    """Both joint-angle solutions (rad, limits not checked) putting the pad on each line
    ``n(ψ)·p = d`` with its outward normal at angle ψ, every line at once (``psi``, ``d``
    broadcast to one shape S): q (2, *S, 2), the solution with α1 = ψ + arccos c first, and
    whether each line is within reach, |c| ≤ 1 (S). The one inverse kinematics of a pad line
    (:func:`ik_line_solutions` is its one-line case): the same arithmetic for one line as for many."""
    psi, d = np.broadcast_arrays(np.asarray(psi, dtype=float), np.asarray(d, dtype=float))
    j1 = finger.joints[0]
    c = (d - finger.pad.offset_mm - (np.cos(psi) * finger.base.x + np.sin(psi) * finger.base.y)) / j1.link_mm
    acos = np.arccos(np.clip(c, -1.0, 1.0))
    a1 = psi + _BOTH.reshape((2,) + (1,) * psi.ndim) * acos  # ψ + arccos c, ψ − arccos c
    a2 = psi - finger.pad.side_sign * (math.pi / 2)
    return wrap_angle(np.stack([a1 - finger.base.angle, a2 - a1], axis=-1)), np.abs(c) <= 1.0


#: the two solutions' signs of arccos c (:func:`ik_line_angles`)
_BOTH = np.array([1.0, -1.0])


def ik_line_solutions(finger: FingerConfig, psi: float, d: float) -> list[np.ndarray]:
    """Both joint-angle solutions (rad, limits not checked) putting the pad on the line
    ``n(ψ)·p = d`` with its outward normal at angle ψ; empty if out of reach
    (:func:`ik_line_angles` of one line)."""
    q, real = ik_line_angles(finger, float(psi), float(d))
    return [q[0], q[1]] if bool(real) else []


def ik_line(finger: FingerConfig, psi: float, d: float, contact=None, pad_u: float | None = None,
            margin_rad: float = 0.0) -> np.ndarray:
    """Joint angles (rad) putting the pad on line ``n(ψ)·p = d`` inside the joint limits.

    With ``contact`` (a point on that line) the solution must have the contact on the pad;
    among valid solutions the one whose contact is nearest ``pad_u`` (mm from the pad's
    proximal end; default the pad's middle) wins. Raises :class:`Unreachable`."""
    sols = [q for q in ik_line_solutions(finger, psi, d) if within_limits(finger.joints, q, margin_rad)]
    if contact is not None:
        target = 0.5 * finger.pad.length_mm if pad_u is None else pad_u
        scored = []
        for q in sols:
            u = float(finger_pad_line(finger, q).pad_coordinate(contact))
            if 0.0 <= u <= finger.pad.length_mm:
                scored.append((abs(u - target), q))
        sols = [q for _, q in sorted(scored, key=lambda t: t[0])]
    if not sols:
        where = "" if contact is None else f" with the contact ({contact[0]:.1f}, {contact[1]:.1f}) on the pad"
        raise Unreachable(f"finger {finger.name}: no joint angles within limits put the pad on the line "
                          f"psi={math.degrees(psi):.1f} deg, d={d:.1f} mm{where}")
    return sols[0]


def ik_tangent(finger: FingerConfig, point, psi: float, pad_u: float | None = None,
               margin_rad: float = 0.0) -> np.ndarray:
    """Joint angles putting the pad through ``point`` with outward normal angle ψ and the
    point on the pad (nearest ``pad_u``)."""
    n = unit(psi)
    return ik_line(finger, psi, float(n @ np.asarray(point, dtype=float)), contact=point, pad_u=pad_u,
                   margin_rad=margin_rad)


def ik_corner(finger: FingerConfig, point, margin_rad: float = 0.0, end: str = "distal") -> list[np.ndarray]:
    """Joint-angle solutions (within limits) putting one end of the pad surface on
    ``point``: ``end`` 'distal' (the fingertip corner) or 'proximal'. Two-link IK."""
    j1, j2 = finger.joints
    off, side = finger.pad.offset_mm, finger.pad.side_sign
    along = j2.link_mm - (finger.pad.length_mm if end == "proximal" else 0.0)
    r2 = math.hypot(along, off)
    gamma = math.atan2(side * off, along)  # corner direction relative to e(α2)
    v = np.asarray(point, dtype=float) - np.array([finger.base.x, finger.base.y])
    dist = float(np.hypot(*v))
    c = (dist**2 - j1.link_mm**2 - r2**2) / (2 * j1.link_mm * r2)
    if abs(c) > 1.0:
        return []
    out = []
    for sgn in (1.0, -1.0):
        k = sgn * math.acos(c)  # angle of the corner vector relative to link 1
        a1 = math.atan2(v[1], v[0]) - math.atan2(r2 * math.sin(k), j1.link_mm + r2 * math.cos(k))
        q = np.array([float(wrap_angle(a1 - finger.base.angle)), float(wrap_angle(k - gamma))])
        if within_limits(finger.joints, q, margin_rad):
            out.append(q)
    return out


# ----------------------------------------------------------------------------- contacts


@dataclass(frozen=True)
class TouchEnvelope:
    """Envelope of a rolled pad: samples ordered by increasing ψ (CCW around the solid),
    with the fit's radius of curvature and its residuals."""

    psi: np.ndarray
    phi: np.ndarray
    x: np.ndarray
    y: np.ndarray
    s: np.ndarray
    order: np.ndarray  # indices of the input readings in output order
    rho: np.ndarray  # radius of curvature −(d + d'') of the fit at each sample (mm; ≈ 0 on a corner)
    rho_psi: np.ndarray  # its derivative dρ/dψ at each sample (mm/rad)
    residual: np.ndarray  # each pad line's d minus the fitted d(ψ) (mm)
    origin: np.ndarray  # the fit's local origin: the centre of curvature at the middle sample
    degree: int  # of the polynomial d(ψ)

    def to_touch(self) -> dict:
        """The samples touch of the input format (docs/formats.md)."""
        return {"phi": [float(v) for v in self.phi], "x": [float(v) for v in self.x],
                "y": [float(v) for v in self.y], "s": [float(v) for v in self.s]}


def default_degree(n: int) -> int:
    """Polynomial degree of d(ψ) for n readings when nothing chooses it: 3 from 6 readings
    on, else n − 2 ≥ 1 (tactile_jaw.envelope chooses it from the data and the noise)."""
    return 3 if n >= 6 else max(1, n - 2)


def determined_degree(psi) -> int:
    """The highest degree of d(ψ) whose least-squares fit the pad angles ``psi`` (≥ 1, any
    order) determine: its design matrix in :func:`touch_from_pad_lines`'s abscissae, columns
    scaled to unit norm as numpy's fit scales them, has full rank at the tolerance numpy's
    fit uses (len · ε of the largest singular value). A higher degree is fitted rank-deficient
    (numpy's RankWarning): its coefficients are not the readings' but the solver's choice
    (a flat press's scan of 30 lines over 58°, P-series line 16 of bench_explore --finite 20
    --anywhere --seed 173: degrees 25 and 26)."""
    psi = np.sort(np.unwrap(np.asarray(psi, dtype=float)))
    x, _ = _abscissae(psi)
    vander = np.polynomial.polynomial.polyvander(x, psi.size - 1)
    tol = psi.size * np.finfo(float).eps
    for deg in range(1, psi.size):
        cols = vander[:, : deg + 1]
        sv = np.linalg.svd(cols / np.linalg.norm(cols, axis=0), compute_uv=False)
        if sv[-1] <= tol * sv[0]:
            return deg - 1
    return psi.size - 1


def _abscissae(psi: np.ndarray) -> tuple[np.ndarray, float]:
    """The fit's abscissae x ∈ [−1, 1] of ascending pad angles ``psi``, and the half range (rad)
    they are scaled by."""
    scale = max(0.5 * (psi[-1] - psi[0]), 1e-12)
    return (psi - 0.5 * (psi[0] + psi[-1])) / scale, scale


#: a pass whose radius of curvature at the middle sample is beyond this (mm) or not finite
#: keeps its own origin: a boundary this flat has its centre of curvature too far out to fit about
FLAT_RHO_MM = 1e4


def touch_from_pad_lines(psi, d, origin=None, degree: int | None = None) -> TouchEnvelope:
    """The envelope of one rolling touch from its pad lines ``n(ψ_i)·p = d_i`` (≥ 3 readings,
    distinct ψ): one least-squares polynomial of the support values d(ψ) − n(ψ)·o, about a
    local origin o. ``origin`` None: two passes, the first about the lines' mean foot, the
    second about the first pass's centre of curvature at the middle sample (about it a
    circle's support values are constant, so the polynomial only follows the change of
    curvature; tactile_jaw.envelope differentiates the fit with ``origin`` fixed)."""
    psi = np.unwrap(np.asarray(psi, dtype=float))
    d = np.asarray(d, dtype=float)
    if psi.shape != d.shape or psi.ndim != 1 or psi.size < 3:
        raise InputError(f"a rolling touch needs ≥ 3 pad lines with matching psi and d; got {psi.shape}, {d.shape}")
    if not (np.all(np.isfinite(psi)) and np.all(np.isfinite(d))):
        raise InputError("pad lines must be finite numbers")
    order = np.argsort(psi, kind="stable")
    psi, d = psi[order], d[order]
    if np.any(np.diff(psi) <= 0):
        raise InputError("a rolling touch needs distinct pad angles psi; the pad did not roll")
    deg = default_degree(psi.size) if degree is None else degree
    if not 1 <= deg <= psi.size - 1:
        raise InputError(f"polynomial degree {deg} out of range [1, {psi.size - 1}] for {psi.size} readings")
    x, scale = _abscissae(psi)
    n = _e(psi)
    nperp = np.stack([-n[:, 1], n[:, 0]], axis=-1)
    m = psi.size // 2
    if origin is None:
        first = _envelope(x, scale, d, n, nperp, np.mean(n * d[:, None], axis=0), deg)
        rho_m = first[3][m]
        origin = (np.array([first[0][m], first[1][m]]) + n[m] * rho_m  # into the object
                  if np.isfinite(rho_m) and abs(rho_m) < FLAT_RHO_MM else first[6])
    px, py, s, rho, rho_psi, residual, o = _envelope(x, scale, d, n, nperp, np.asarray(origin, dtype=float), deg)
    return TouchEnvelope(psi=psi, phi=wrap_angle(psi - np.pi / 2), x=px, y=py, s=s, order=order, rho=rho,
                         rho_psi=rho_psi, residual=residual, origin=o, degree=deg)


def _envelope(x, scale, d, n, nperp, o, deg):
    """(x, y, arc length, ρ, dρ/dψ, residual, origin) of the samples from a degree-``deg``
    fit of the support values d(ψ) − n·o about origin o: the envelope point
    ``o + f n + f' n⊥``, ρ = −(f + f''), s = ∫ρ dψ."""
    dl = d - n @ o  # support values about the local origin
    poly = np.polynomial.Polynomial.fit(x, dl, deg, domain=[-1, 1], window=[-1, 1])
    f0 = poly(x)
    f1 = poly.deriv(1)(x) / scale
    radius = poly + poly.deriv(2) / scale**2  # d + d'' = −ρ, in x
    integral = radius.integ()
    s = -(integral(x) - integral(x[0])) * scale
    p = o + n * f0[:, None] + nperp * f1[:, None]
    return p[:, 0], p[:, 1], s, -radius(x), -radius.deriv(1)(x) / scale, dl - f0, o


def touch_from_ticks(cfg: JawConfig, finger: str, ticks, degree: int | None = None) -> TouchEnvelope:
    """The envelope of one rolling touch of ``finger`` from its encoder ticks (n, 2)."""
    line = finger_pad_line_from_ticks(cfg, finger, ticks)
    return touch_from_pad_lines(line.psi, line.d, degree=degree)


def quantization_bound(finger: FingerConfig, q, degree: int | None = None,
                       half_step=None) -> dict[str, np.ndarray]:
    """First-order worst-case error of every output of a touch when each joint angle of
    each reading may be off by up to ``half_step`` (rad, scalar or one per joint; default
    ½ tick of each joint's model): for each output
    Σ over readings and joints of |∂output/∂q|·half_step (central differences).

    Returns arrays (in output order) for keys 'phi', 'x', 'y', 's' and 'point'
    (hypot of the x and y bounds: a bound on the contact point's distance error)."""
    q = np.asarray(q, dtype=float)

    def outputs(qq):
        line = finger_pad_line(finger, qq)
        c = touch_from_pad_lines(line.psi, line.d, degree=degree)
        return c, np.concatenate([c.phi, c.x, c.y, c.s])

    half = np.broadcast_to(half_tick_rad(resolutions(finger.joints)) if half_step is None
                           else np.asarray(half_step, dtype=float), (q.shape[1],))
    base, _ = outputs(q)
    m = q.shape[0]
    h = 1e-6
    bound = np.zeros(4 * m)
    for i in range(m):
        for k in range(q.shape[1]):
            dq = np.zeros_like(q)
            dq[i, k] = h
            c_plus, v_plus = outputs(q + dq)
            c_minus, v_minus = outputs(q - dq)
            if not (np.array_equal(c_plus.order, base.order) and np.array_equal(c_minus.order, base.order)):
                raise InputError("readings too close in psi for a first-order bound")
            bound += np.abs((v_plus - v_minus) / (2 * h)) * half[k]
    phi_b, x_b, y_b, s_b = np.split(bound, 4)
    return {"phi": phi_b, "x": x_b, "y": y_b, "s": s_b, "point": np.hypot(x_b, y_b)}
