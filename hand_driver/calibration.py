"""Calibration: fit the jaw's kinematic parameters from touches on a known object.

Unknowns (per finger): the ``zero_tick`` of both joints, the ``link_mm`` of both links
and the pad's ``offset_mm``; nuisance: the reference object's pose. Readings are joint
ticks at contact, of two kinds:

- ``face``: the pad lies tangent to the reference (a disk: the pad line is at distance r
  from the centre, ``n(ψ)·C − d − r = 0``; a flat block: the pad lies on the face, both
  pad ends on the face line ``m·p = h``);
- ``corner``: the pad's distal corner (fingertip end of the pad surface) touches the
  reference (disk: ``|corner − C| − r = 0``; block: ``m·corner − h = 0``).

Why both kinds (identifiability): a face contact depends on the distal link only through
its direction (the pad is parallel to it), so ``link_mm`` of the distal joint is
invisible to face touches; corner touches see it. The pad offset and the proximal link
are separated by face touches at many pad orientations; the zero ticks of a finger are
separated from the object's unknown position only because both fingers touch the same
object (a single finger turning about its own base together with the object is a
symmetry). The touch plan (:func:`plan_touches`) therefore uses, for each finger, face
touches spread over its reachable orientations on both inverse-kinematics branches and
corner touches spread around the reachable arc. The fit (scipy.optimize.least_squares)
reports residuals before (nominal config, only the object's pose fitted) and after,
standard errors from the Jacobian (σ² (JᵀJ)⁻¹ with σ² from the residuals, floored at the
quantization variance), and refuses (:class:`CalibrationRefused`) when the Jacobian is
rank deficient or a parameter's standard error exceeds its tolerance.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import least_squares

from hand_driver import kinematics as kin
from hand_driver.config import JawConfig
from tactile_common.errors import InputError

#: a reading whose residual exceeds this many quantization σ is not the modelled contact
OUTLIER_Z = 4.0
#: screening passes (reclassify pad-end contacts, drop unexplained readings, refit)
SCREEN_PASSES = 4
#: default standard-error tolerances: half the recovery targets (1 tick, 0.1 mm)
TOLERANCES = {"zero_tick": 0.5, "link_mm": 0.05, "offset_mm": 0.05}
#: what each parameter kind needs, for refusals
_NEEDS = {
    "zero_tick": "face touches of this finger at widely spread pad orientations, with the other finger "
                 "touching the same object",
    "link_mm": "corner touches (distal link) or face touches at widely spread orientations (proximal link)",
    "offset_mm": "face touches at widely spread pad orientations",
}


class CalibrationRefused(InputError):
    """The touches do not determine every parameter to its tolerance."""


@dataclass(frozen=True)
class Reading:
    """One contact: finger name, kind ('face', 'corner' or 'heel'), that finger's two
    encoder ticks, and which placement of the reference it touched (0, 1, ...)."""

    finger: str
    kind: str
    ticks: tuple[float, float]
    placement: int = 0


@dataclass(frozen=True)
class Estimate:
    name: str  # e.g. "left.joint1.zero_tick", "left.pad.offset_mm"
    kind: str  # zero_tick | link_mm | offset_mm
    before: float
    after: float
    se: float
    tolerance: float


@dataclass(frozen=True)
class CalibrationResult:
    config: JawConfig
    estimates: tuple[Estimate, ...]
    reference_poses: tuple[dict, ...]
    rms_before_mm: float
    rms_after_mm: float
    max_after_mm: float
    n_readings: int  # readings used by the fit
    n_reclassified: int = 0  # face readings found to be pad-end contacts (Model.screen)
    n_dropped: int = 0  # readings the contact model cannot explain, left out

    def to_json(self) -> dict:
        return {
            "readings": self.n_readings,
            "reclassified": self.n_reclassified,
            "dropped": self.n_dropped,
            "rms_before_mm": self.rms_before_mm,
            "rms_after_mm": self.rms_after_mm,
            "max_residual_after_mm": self.max_after_mm,
            "reference_poses": list(self.reference_poses),
            "parameters": [{"name": e.name, "before": e.before, "after": e.after, "se": e.se,
                            "tolerance": e.tolerance} for e in self.estimates],
        }


# ----------------------------------------------------------------------------- model

_KINDS = ("zero_tick", "zero_tick", "link_mm", "link_mm", "offset_mm")


def _param_names(cfg: JawConfig) -> list[tuple[str, str]]:
    out = []
    for f in cfg.fingers:
        out += [(f"{f.name}.joint{j.id}.zero_tick", "zero_tick") for j in f.joints]
        out += [(f"{f.name}.joint{j.id}.link_mm", "link_mm") for j in f.joints]
        out.append((f"{f.name}.pad.offset_mm", "offset_mm"))
    return out


def _pack(cfg: JawConfig) -> np.ndarray:
    v = []
    for f in cfg.fingers:
        v += [j.zero_tick for j in f.joints] + [j.link_mm for j in f.joints] + [f.pad.offset_mm]
    return np.array(v, dtype=float)


def apply_params(cfg: JawConfig, v) -> JawConfig:
    """A copy of ``cfg`` with the calibrated parameters ``v`` (the fit's order)."""
    fingers, k = [], 0
    for f in cfg.fingers:
        z, links, off = v[k:k + 2], v[k + 2:k + 4], v[k + 4]
        k += 5
        joints = tuple(dataclasses.replace(j, zero_tick=float(z[i]), link_mm=float(links[i]))
                       for i, j in enumerate(f.joints))
        fingers.append(dataclasses.replace(f, joints=joints, pad=dataclasses.replace(f.pad, offset_mm=float(off))))
    return dataclasses.replace(cfg, fingers=tuple(fingers))


class _Model:
    """Residuals (mm) of every reading for kinematic parameters v and object pose w."""

    def __init__(self, cfg: JawConfig, reference, readings: list[Reading]):
        self.cfg = cfg
        self.cls = reference.cls
        if self.cls == "circle":
            self.r = float(reference.params["r"])
        elif self.cls != "line":
            raise InputError(f"reference object class {self.cls!r} not supported; use a circle (disk) or a "
                             f"line (flat block face)")
        names = [f.name for f in cfg.fingers]
        self.placements = sorted({r.placement for r in readings})
        if self.placements != list(range(len(self.placements))):
            raise InputError(f"placements must be numbered 0, 1, ...; got {self.placements}")
        self.groups = []
        self.members = []  # per group, the indices of its readings in ``readings``
        for pl in self.placements:
            for fi, f in enumerate(cfg.fingers):
                for kind in ("face", "corner", "heel"):
                    sel = [i for i, r in enumerate(readings)
                           if r.finger == f.name and r.kind == kind and r.placement == pl]
                    if sel:
                        self.groups.append((pl, fi, kind, np.array([readings[i].ticks for i in sel], dtype=float)))
                        self.members.append(sel)
        unknown = {r.finger for r in readings} - set(names)
        if unknown:
            raise InputError(f"readings name unknown finger(s) {sorted(unknown)}; fingers are {names}")
        bad = {r.kind for r in readings} - {"face", "corner", "heel"}
        if bad:
            raise InputError(f"reading kinds must be 'face', 'corner' or 'heel', got {sorted(bad)}")

    def lines(self, v, fi: int, ticks) -> kin.PadLine:
        f = self.cfg.fingers[fi]
        k = 5 * fi
        zero, links, off = v[k:k + 2], v[k + 2:k + 4], v[k + 4]
        sign = np.array([j.direction for j in f.joints], dtype=float)
        q = sign * (ticks - zero) * kin.RAD_PER_TICK
        return kin.chain_pad_line((f.base.x, f.base.y, f.base.angle), q, links, off, f.pad.length_mm,
                                  f.pad.side_sign)

    def residuals(self, v, w) -> np.ndarray:
        """Residuals (mm); ``w`` holds two pose numbers per placement (disk: centre x, y;
        block: face normal angle, offset)."""
        out = []
        for pl, fi, kind, ticks in self.groups:
            line = self.lines(v, fi, ticks)
            a, b = w[2 * pl], w[2 * pl + 1]
            if self.cls == "circle":
                c = np.array([a, b])
                if kind == "face":
                    out.append(line.normal @ c - line.d - self.r)
                else:
                    end = line.distal if kind == "corner" else line.proximal
                    out.append(np.hypot(*(end - c).T) - self.r)
            else:
                m = np.array([math.cos(a), math.sin(a)])
                if kind == "face":
                    out += [line.proximal @ m - b, line.distal @ m - b]
                else:
                    out.append((line.distal if kind == "corner" else line.proximal) @ m - b)
        return np.concatenate(out)

    def pose_start(self, v) -> np.ndarray:
        """Each placement's pose from its face readings by linear least squares."""
        w = []
        for pl in self.placements:
            faces = [(fi, t) for p, fi, kind, t in self.groups if kind == "face" and p == pl]
            if not faces:
                raise CalibrationRefused(f"placement {pl}: no face touches, so the reference cannot be located")
            lines = [self.lines(v, fi, t) for fi, t in faces]
            if self.cls == "circle":  # n·C = d + r
                a = np.concatenate([ln.normal for ln in lines])
                b = np.concatenate([ln.d + self.r for ln in lines])
                w += list(np.linalg.lstsq(a, b, rcond=None)[0])
            else:
                psi = np.concatenate([ln.psi for ln in lines])
                ang = math.atan2(np.mean(np.sin(psi + np.pi)), np.mean(np.cos(psi + np.pi)))
                m = np.array([math.cos(ang), math.sin(ang)])
                w += [ang, float(np.mean(np.concatenate([ln.distal @ m for ln in lines])))]
        return np.array(w)

    def screen(self, v, w, z, readings: list[Reading]) -> tuple[list[Reading], int, int]:
        """Readings the contact model explains at (v, w): a disk face touch whose tangent
        point lies off the pad was a pad-end contact and becomes 'heel'/'corner'; if none
        does, the readings with a normalized residual |z| above OUTLIER_Z (quantization
        alone gives ≤ √6 ≈ 2.45) and above half the largest |z| are dropped (the worst
        first: one bad reading pulls the fit and so the others' residuals). Returns
        (readings, reclassified, dropped)."""
        kinds = [r.kind for r in readings]
        keep = [True] * len(readings)
        row = 0
        reclassified = 0
        limit = max(OUTLIER_Z, 0.5 * float(np.max(np.abs(z))))
        worst = []
        for (pl, fi, kind, ticks), members in zip(self.groups, self.members):
            per = 2 if (self.cls == "line" and kind == "face") else 1
            zg = np.abs(np.asarray(z[row:row + per * len(members)])).reshape(len(members), per).max(axis=1)
            row += per * len(members)
            if self.cls == "circle" and kind == "face":
                line = self.lines(v, fi, ticks)
                c = np.array([w[2 * pl], w[2 * pl + 1]])
                u = line.pad_coordinate(c - self.r * line.normal)
                length = self.cfg.fingers[fi].pad.length_mm
                for i, uu in zip(members, np.atleast_1d(u)):
                    if not 0.0 <= uu <= length:
                        kinds[i] = "heel" if uu < 0.0 else "corner"
                        reclassified += 1
            worst += [i for i, zz in zip(members, zg) if zz > limit]
        if not reclassified:
            for i in worst:
                keep[i] = False
        out = [dataclasses.replace(r, kind=k) for r, k, ok in zip(readings, kinds, keep) if ok]
        return out, reclassified, keep.count(False)

    def reading_sigmas(self, v, w) -> np.ndarray:
        """Per-residual standard deviation (mm) that encoder quantization alone produces:
        ±½ tick uniform per joint, σ² = Σ_joints (∂residual/∂tick)² / 12."""
        h = 1e-3
        sens = []
        for group in self.groups:
            var = 0.0
            for k in range(2):
                dt = np.zeros_like(group[3])
                dt[:, k] = h
                plus = self._group_residual(v, w, group, group[3] + dt)
                minus = self._group_residual(v, w, group, group[3] - dt)
                var = var + ((plus - minus) / (2 * h)) ** 2
            sens.append(var)
        return np.sqrt(np.concatenate(sens) / 12.0)

    def _group_residual(self, v, w, group, ticks):
        saved = self.groups
        self.groups = [group[:3] + (ticks,)]
        try:
            return self.residuals(v, w)
        finally:
            self.groups = saved


def fit(cfg: JawConfig, reference, readings: list[Reading], tolerances: dict | None = None) -> CalibrationResult:
    """Least-squares calibration (module docstring); :class:`CalibrationRefused` when a
    parameter is not determined to its tolerance."""
    tol = dict(TOLERANCES, **(tolerances or {}))
    v0 = _pack(cfg)
    names = _param_names(cfg)
    nv = v0.size
    used, n_reclassified, n_dropped = list(readings), 0, 0
    for attempt in range(SCREEN_PASSES + 1):
        model = _Model(cfg, reference, used)
        n_pose = 2 * len(model.placements)
        n_res = sum(len(t) * (2 if (model.cls == "line" and kind == "face") else 1)
                    for _, _, kind, t in model.groups)
        if n_res <= nv + n_pose:
            raise CalibrationRefused(f"{n_res} residuals for {nv + n_pose} unknowns: more touches are needed "
                                     f"(face and corner touches of both fingers on every placement)")
        # before: nominal parameters, only the pose fitted
        w0 = model.pose_start(v0)
        before = least_squares(lambda w: model.residuals(v0, w), w0, method="lm")
        x0 = np.concatenate([v0, before.x])
        # weighted by each reading's quantization σ (at the nominal geometry), so that
        # readings with long lever arms (coarse) count less than fine ones
        sig = np.maximum(model.reading_sigmas(v0, before.x), 1e-4)
        res = least_squares(lambda x: model.residuals(x[:nv], x[nv:]) / sig, x0, method="lm", x_scale="jac",
                            xtol=1e-12, ftol=1e-12, gtol=1e-12, max_nfev=2000)
        sv = np.linalg.svd(res.jac, compute_uv=False)
        col = np.linalg.norm(res.jac, axis=0)
        unseen = np.any(col <= 1e-6 * np.max(col))  # a parameter the readings do not see
        if attempt == SCREEN_PASSES or unseen or sv[-1] <= 1e-9 * sv[0]:  # rank deficient: refused below
            break
        screened, moved, dropped = model.screen(res.x[:nv], res.x[nv:], res.fun, used)
        if not moved and not dropped:
            break
        used, n_reclassified, n_dropped = screened, n_reclassified + moved, n_dropped + dropped
    r = res.fun * sig  # mm
    m, p = r.size, x0.size
    jac = res.jac
    u, s, vt = np.linalg.svd(jac, full_matrices=False)
    col = np.linalg.norm(jac, axis=0)
    if np.any(col == 0.0) or s[-1] <= 1e-9 * s[0]:
        weak = int(np.argmax(np.abs(vt[-1])))
        what = names[weak][0] if weak < nv else "the reference pose"
        kind = names[weak][1] if weak < nv else "zero_tick"
        raise CalibrationRefused(f"the touches cannot determine {what} (rank-deficient Jacobian); "
                                 f"it needs {_NEEDS[kind]}")
    # variance factor: χ²/dof of the weighted fit, never below the quantization model's 1
    sigma2 = max(float(res.fun @ res.fun) / (m - p), 1.0)
    cov = sigma2 * (vt.T / s**2) @ vt
    se = np.sqrt(np.diag(cov))
    estimates = tuple(Estimate(name, kind, float(v0[i]), float(res.x[i]), float(se[i]), tol[kind])
                      for i, (name, kind) in enumerate(names))
    worst = [e for e in estimates if e.se > e.tolerance]
    if worst:
        e = max(worst, key=lambda e: e.se / e.tolerance)
        raise CalibrationRefused(f"the touches determine {e.name} only to ±{e.se:.3g} (tolerance {e.tolerance:g}); "
                                 f"it needs {_NEEDS[e.kind]}")
    w = res.x[nv:]
    poses = tuple({"x": float(w[2 * i]), "y": float(w[2 * i + 1])} if model.cls == "circle"
                  else {"normal_angle": float(w[2 * i]), "offset_mm": float(w[2 * i + 1])}
                  for i in model.placements)
    return CalibrationResult(config=apply_params(cfg, res.x[:nv]), estimates=estimates, reference_poses=poses,
                             rms_before_mm=float(np.sqrt(np.mean(before.fun**2))),
                             rms_after_mm=float(np.sqrt(np.mean(r**2))), max_after_mm=float(np.max(np.abs(r))),
                             n_readings=len(used), n_reclassified=n_reclassified, n_dropped=n_dropped)


# ----------------------------------------------------------------------------- plan

#: a corner touch needs the pad to leave the object at least this steeply (rad)
CORNER_TILT_RAD = math.radians(20.0)


@dataclass(frozen=True)
class PlannedTouch:
    """Where to touch: ``face`` at pad normal angle ``psi``, or ``corner`` at ``point``
    approached along ``-direction`` (the reference's outward normal there); ``q`` is the
    nominal contact configuration (rad), which fixes the inverse-kinematics branch."""

    finger: str
    kind: str
    psi: float
    point: tuple[float, float]
    direction: tuple[float, float]
    q: tuple[float, float]


def plan_touches(cfg: JawConfig, reference, center, faces: int = 14, corners: int = 8,
                 margin_rad: float = math.radians(3.0), clearance_mm: float = 2.0,
                 gap: float = 3.0, accept=None) -> list[PlannedTouch]:
    """The calibration touch plan on a disk of the reference's radius centred at ``center``
    (the expected position). Per finger and inverse-kinematics branch: ``faces`` pad
    orientations evenly over the reachable range (contact ≥ 3 mm inside the pad), and
    ``corners`` contacts of each pad end ('corner': the fingertip end, 'heel': the
    proximal end) evenly over the reachable arc, with the pad leaving the disk by ≥ 20°.
    Only configurations whose links clear the disk by ``clearance_mm`` are used (the
    links are not modelled by the emulator, but they are real), only contacts whose
    approach pose ``gap`` mm outside the disk is inside the joint limits too, and, with
    ``accept(finger, q_approach) -> bool``, only approach poses it accepts (a clear path)."""
    if reference.cls != "circle":
        raise InputError("the calibration touch plan needs a disk reference (class circle)")
    r = float(reference.params["r"])
    c = np.asarray(center, dtype=float)
    plan: list[PlannedTouch] = []
    grid = np.linspace(-np.pi, np.pi, 181)[:-1]  # 2° steps
    for f in cfg.fingers:
        def clear(q) -> bool:
            line = kin.finger_pad_line(f, q)
            base = np.array([f.base.x, f.base.y])
            tip = line.joint2 + f.joints[1].link_mm * line.tangent
            return (_segment_distance(c, base, line.joint2) >= r + clearance_mm
                    and _segment_distance(c, line.joint2, tip) >= r + clearance_mm)

        face_ok = []
        for psi in grid:
            n = np.array([math.cos(psi), math.sin(psi)])
            pt = c - r * n
            pre = [q for q in kin.ik_line_solutions(f, psi, float(n @ c) - r - gap)
                   if kin.within_limits(f.joints, q, margin_rad)]
            for q in kin.ik_line_solutions(f, psi, float(n @ c) - r):
                u = float(kin.finger_pad_line(f, q).pad_coordinate(pt))
                if kin.within_limits(f.joints, q, margin_rad) and 3.0 <= u <= f.pad.length_mm - 3.0 and clear(q):
                    near = [p for p in pre if np.sum(kin._wrap(p - q) ** 2) < 0.25]
                    if near:
                        face_ok.append((psi, q, pt, near[0]))
        plan += _spread(f.name, "face", face_ok, faces, lambda it: (it[0], (-math.cos(it[0]), -math.sin(it[0]))),
                        None if accept is None else lambda it, name=f.name: accept(name, it[3]))
        for kind, end, sign in (("corner", "distal", -1.0), ("heel", "proximal", 1.0)):
            ok = []
            for beta in grid:
                m = np.array([math.cos(beta), math.sin(beta)])
                pt = c + r * m
                pre = kin.ik_corner(f, c + (r + gap) * m, margin_rad, end=end)
                for q in kin.ik_corner(f, pt, margin_rad, end=end):
                    line = kin.finger_pad_line(f, q)
                    if float(sign * line.tangent @ m) >= math.sin(CORNER_TILT_RAD) and clear(q):
                        near = [p for p in pre if np.sum(kin._wrap(p - q) ** 2) < 0.25]
                        if near:
                            ok.append((beta, q, pt, near[0]))
            plan += _spread(f.name, kind, ok, corners, lambda it: (float("nan"), (math.cos(it[0]), math.sin(it[0]))),
                            None if accept is None else lambda it, name=f.name: accept(name, it[3]))
    return plan


def _segment_distance(p, a, b) -> float:
    ab = b - a
    t = float(np.clip((p - a) @ ab / max(float(ab @ ab), 1e-300), 0.0, 1.0))
    return float(np.hypot(*(p - a - t * ab)))


def _spread(finger: str, kind: str, items: list, count: int, meta, accept=None) -> list[PlannedTouch]:
    """``count`` items evenly over the sorted angle range, per IK branch (sign of q2); with
    ``accept(item) -> bool`` each pick moves to the nearest accepted item not yet taken."""
    out = []
    for branch in (1.0, -1.0):
        sel = sorted((it for it in items if math.copysign(1.0, it[1][1]) == branch), key=lambda it: it[0])
        if len(sel) < 2:
            continue
        taken: set[int] = set()
        for i in np.unique(np.round(np.linspace(0, len(sel) - 1, count)).astype(int)):
            order = sorted(range(len(sel)), key=lambda k: abs(k - i))[:max(3, len(sel) // count)]
            pick = next((k for k in order if k not in taken and (accept is None or accept(sel[k]))), None)
            if pick is None:
                continue
            taken.add(pick)
            q, pt = sel[pick][1], sel[pick][2]
            psi, direction = meta(sel[pick])
            out.append(PlannedTouch(finger, kind, float(psi), (float(pt[0]), float(pt[1])), direction,
                                    (float(q[0]), float(q[1]))))
    return out


def synthesize(truth: JawConfig, reference, nominal_plan: list[PlannedTouch], quantize: bool = True,
               placement: int = 0) -> list[Reading]:
    """Readings a jaw with geometry ``truth`` would produce for a plan (tests and
    benchmarks): the exact truth contact configuration on the same IK branch (face touches
    whose tangent point falls off the truth pad are left out: a pad end would touch), as ticks
    of the truth zero ticks, rounded to whole ticks as the encoders do (unless quantize=False)."""
    out = []
    r = float(reference.params["r"])
    c = np.array([reference.pose.x, reference.pose.y])
    for t in nominal_plan:
        f = truth.finger(t.finger)
        if t.kind == "face":
            n = np.array([math.cos(t.psi), math.sin(t.psi)])
            sols = kin.ik_line_solutions(f, t.psi, float(n @ c) - r)
        else:
            pt = c + r * np.asarray(t.direction)
            sols = kin.ik_corner(f, pt, margin_rad=-math.pi, end="distal" if t.kind == "corner" else "proximal")
        if not sols:
            continue
        q = min(sols, key=lambda s: float(np.sum(kin._wrap(s - np.asarray(t.q)) ** 2)))
        if t.kind == "face":  # the tangent point off the truth pad: a pad end would touch instead
            line = kin.finger_pad_line(f, q)
            if not 0.0 <= float(line.pad_coordinate(c - r * line.normal)) <= f.pad.length_mm:
                continue
        ticks = kin.angles_to_ticks(f.joints, q)
        if quantize:
            ticks = np.rint(ticks)
        out.append(Reading(t.finger, t.kind, (float(ticks[0]), float(ticks[1])), placement))
    return out


# ----------------------------------------------------------------------------- touching

#: pre-contact gap (mm) from which every calibration touch approaches, and its travel
APPROACH_GAP_MM = 5.0
APPROACH_TRAVEL_MM = 12.0
#: locating touches start this far (mm) outside the expected disk: the placement may be
#: off by up to this much
LOCATE_GAP_MM = 6.0
#: transit keeps the pads this far (mm) from the located disk (less than APPROACH_GAP_MM)
TRANSIT_CLEARANCE_MM = 4.0
#: suggested placements of the reference disk (hand frame, mm). A base joint's zero tick
#: is fixed only through the disk centre's distance from each base (trilateration by the
#: two fingers), and that distance trades against the proximal ``link_mm``, which face
#: touches separate only through the spread of cos(q2) over the touches. Disks straight
#: ahead give each finger a narrow q2 range (base zero ticks to ~0.6 tick standard error
#: with (60,0), (85,±10)); a disk off to each side makes the finger on that side fold, and
#: (60,0), (85,0), (70,±30) give ~0.25 tick with the same number of touches (Fisher
#: information of the default plan, confirmed on the emulated bus).
DEFAULT_PLACEMENTS = ((60.0, 0.0), (85.0, 0.0), (65.0, 30.0), (65.0, -30.0))


def home_pose(finger) -> np.ndarray:
    """A finger's parking pose: opened outward, clear of the workspace."""
    out = np.array([math.radians(40.0), math.radians(30.0)]) * finger.pad.side_sign * -1.0
    lo = np.array([j.min_rad for j in finger.joints])
    hi = np.array([j.max_rad for j in finger.joints])
    return np.clip(out, lo, hi)


def park(jaw) -> None:
    """Move both fingers to their parking poses (:func:`home_pose`) together."""
    from hand_driver.motion import move_to, run_together

    run_together(jaw, {f.name: move_to(jaw, f.name, home_pose(f)) for f in jaw.config.fingers})


def _corner_approach(jaw, finger: str, center, r: float, direction, end: str, q_branch, gap0: float,
                     travel: float):
    """Guarded approach of a pad end toward the disk centre along −direction, from
    ``gap0`` mm outside the disk (nominal geometry); returns the contact ticks or None."""
    from hand_driver.motion import LIMIT_MARGIN_RAD

    m = jaw.config.motion
    step = m.approach_step_mm
    f = jaw.config.finger(finger)
    mvec, c = np.asarray(direction, dtype=float), np.asarray(center, dtype=float)

    def solve(gap, q_ref):
        sols = kin.ik_corner(f, c + (r + gap) * mvec, LIMIT_MARGIN_RAD, end=end)
        if not sols:
            raise kin.Unreachable(f"finger {finger}: pad {end} end cannot reach the reference")
        return min(sols, key=lambda q: float(np.sum(kin._wrap(q - q_ref) ** 2)))

    t0 = jaw.robot_time()
    gap_goal = gap0
    state, _ = yield solve(gap_goal, q_branch)
    history: list[float] = []
    while True:
        line = jaw.pad_line(state, finger)
        point = line.distal if end == "distal" else line.proximal
        gap = float(mvec @ (point - c)) - r
        history.append(gap)
        current = jaw.finger_current(state, finger)
        felt = current is not None and current >= m.contact_current_ma
        stalled = len(history) >= 3 and gap - gap_goal >= 1.5 * step and history[-3] - history[-1] < 0.2 * step
        if felt or stalled:
            return jaw.finger_ticks(state, finger)
        elapsed = jaw.robot_time() - t0
        if gap0 - gap_goal >= travel or elapsed > m.max_touch_s:
            return None
        gap_goal = max(gap0 - m.approach_speed_mm_s * elapsed, gap - 2.0 * step, gap0 - travel)
        state, _ = yield solve(gap_goal, jaw.finger_q(state, finger))


def _pre_pose(cfg: JawConfig, t: PlannedTouch, center, r: float, gap: float):
    """Nominal joint angles ``gap`` mm before the planned contact, on its branch."""
    f = cfg.finger(t.finger)
    c = np.asarray(center, dtype=float)
    if t.kind == "face":
        n = np.array([math.cos(t.psi), math.sin(t.psi)])
        sols = kin.ik_line_solutions(f, t.psi, float(n @ c) - r - gap)
    else:
        pt = c + (r + gap) * np.asarray(t.direction)
        sols = kin.ik_corner(f, pt, end="distal" if t.kind == "corner" else "proximal")
    sols = [q for q in sols if kin.within_limits(f.joints, q)]
    if not sols:
        return None
    return min(sols, key=lambda q: float(np.sum(kin._wrap(q - np.asarray(t.q)) ** 2)))


def _route(guard, finger: str, here, target, home) -> list | None:
    """Joint-space waypoints from ``here`` to ``target`` whose straight segments keep the
    pad clear of the expected disk: direct, or via the parking pose and/or the corners of
    the joint-space box (one joint moved first); None if none is clear."""
    candidates = [[], [home]]
    for a in (here, home):
        candidates += [[np.array([a[0], target[1]])], [np.array([target[0], a[1]])]]
    candidates += [[home, np.array([home[0], target[1]])], [home, np.array([target[0], home[1]])]]
    checked: dict[bytes, bool] = {}  # candidates share segments: test each once

    def clear(a, b) -> bool:
        key = np.concatenate([np.asarray(a, dtype=float), np.asarray(b, dtype=float)]).tobytes()
        if key not in checked:
            checked[key] = guard(finger, a, b)
        return checked[key]

    for via in candidates:
        points = [here] + via + [target]
        if all(clear(a, b) for a, b in zip(points[:-1], points[1:])):
            return via + [target]
    return None


def _finger_touches(jaw, finger: str, plan: list[PlannedTouch], center, r: float, placement: int,
                    guard, out: list[Reading], skipped: list[str], gap: float = APPROACH_GAP_MM,
                    travel: float = APPROACH_TRAVEL_MM):
    """One finger's motion through its planned touches (a generator for run_together).
    The waypoints since the finger last left its parking pose are kept (``trail``): when
    no clear route leads from where it is to the next touch, it retraces them (segments
    already found clear) to park and plans from there; it also retraces them at the end."""
    from hand_driver.motion import guarded_approach, move_to

    cfg = jaw.config
    f = cfg.finger(finger)
    home = home_pose(f)
    here = jaw.finger_q(jaw.last_state, finger)
    trail = [here]

    def retrace():
        for q in trail[-2::-1]:
            yield from move_to(jaw, finger, q)
        return [trail[0]]

    for t in plan:
        pre = _pre_pose(cfg, t, center, r, gap)
        if pre is None:
            skipped.append(f"{finger} {t.kind}: unreachable")
            continue
        route = _route(guard, finger, here, pre, home)
        if route is None and len(trail) > 1:
            trail = yield from retrace()
            here = trail[0]
            route = _route(guard, finger, here, pre, home)
        if route is None:
            skipped.append(f"{finger} {t.kind}: no clear path")
            continue
        reached = True
        for q in route:
            reached = (yield from move_to(jaw, finger, q)) and reached
        here = route[-1]
        homed = [i for i, q in enumerate(route) if q is home]
        trail = [home] + route[homed[-1] + 1:] if homed else trail + route
        if not reached:  # blocked on the way (the object is not where expected): park, skip
            skipped.append(f"{finger} {t.kind}: blocked on the way")
            yield from move_to(jaw, finger, home)
            here = home
            trail = [home]
            continue
        if t.kind == "face":
            n = np.array([math.cos(t.psi), math.sin(t.psi)])
            d_pre = float(n @ np.asarray(center)) - r - gap
            try:
                result = yield from guarded_approach(jaw, finger, t.psi, d_pre, travel)
                ticks = None if result.contact is None else result.contact.ticks
            except kin.Unreachable:
                ticks = None
        else:
            try:
                ticks = yield from _corner_approach(jaw, finger, center, r, t.direction,
                                                    "distal" if t.kind == "corner" else "proximal", pre, gap, travel)
            except kin.Unreachable:
                ticks = None
        if ticks is None:
            skipped.append(f"{finger} {t.kind}: no contact")
        else:
            out.append(Reading(finger, t.kind, (float(ticks[0]), float(ticks[1])), placement))
        yield from move_to(jaw, finger, pre)
    if len(trail) > 1 and not guard(finger, here, home):
        trail = yield from retrace()
        here = trail[0]
    for q in _route(guard, finger, here, home, home) or []:  # direct, or round the disk
        yield from move_to(jaw, finger, q)


def touch_reference(jaw, reference, guess, placement: int = 0, faces: int = 10, corners: int = 6,
                    locate: int = 2) -> tuple[list[Reading], np.ndarray, list[str]]:
    """Touch one placement of a disk reference with both fingers: ``locate`` face touches
    per finger (a finger that cannot reach enough face orientations leaves its share to the
    other) from LOCATE_GAP_MM outside the expected disk at ``guess`` find it (nominal
    geometry, least squares), then the full plan (:func:`plan_touches`) runs with both
    fingers at once. Returns the readings (locating touches included), the located
    centre and what was skipped."""
    from hand_driver.motion import run_together

    cfg = jaw.config
    r = float(reference.params["r"])
    readings: list[Reading] = []
    skipped: list[str] = []

    def make_guard(center, extra):
        """guard(finger, q_from, q_to): does the straight joint-space move keep the pad
        ``extra`` mm clear of the expected disk (sampled every 0.01 rad)?"""
        c = np.asarray(center, dtype=float)

        def guard(finger, q_from, q_to) -> bool:
            q_from, q_to = np.asarray(q_from, dtype=float), np.asarray(q_to, dtype=float)
            n = max(2, math.ceil(float(np.max(np.abs(q_to - q_from))) / 0.01) + 1)
            qs = q_from + np.linspace(0.0, 1.0, n)[:, None] * (q_to - q_from)
            line = kin.finger_pad_line(cfg.finger(finger), qs)
            ab = line.distal - line.proximal
            u = np.clip(np.sum((c - line.proximal) * ab, axis=1) / np.sum(ab * ab, axis=1), 0.0, 1.0)
            dist = np.hypot(*(line.proximal + u[:, None] * ab - c).T)
            return bool(np.all(dist >= r + extra))
        return guard

    # 0. park both fingers (opening them moves the pads away from the workspace)
    park(jaw)
    # 1. locate: the pads start LOCATE_GAP_MM outside the expected disk
    loc_gap, loc_travel = LOCATE_GAP_MM, 2.0 * LOCATE_GAP_MM
    guard = make_guard(guess, loc_gap - 0.5)
    homes = {f.name: home_pose(f) for f in cfg.fingers}

    def reachable(g):
        return lambda name, q: _route(g, name, homes[name], q, homes[name]) is not None

    loc_plan = plan_touches(cfg, reference, guess, faces=15, corners=0, gap=loc_gap, accept=reachable(guard))
    options = {f.name: sorted((t for t in loc_plan if t.finger == f.name and t.kind == "face"), key=lambda t: t.psi)
               for f in cfg.fingers}
    # `locate` per finger; what a finger cannot reach (a disk off to its side) the other takes
    counts = {name: min(len(mine), locate) for name, mine in options.items()}
    for name, mine in options.items():
        spare = locate * len(options) - sum(counts.values())
        counts[name] += min(spare, len(mine) - counts[name])
    by_finger = {}
    for name, mine in options.items():  # the middles of equal parts of the reachable orientations
        n = counts[name]
        by_finger[name] = [mine[min(len(mine) - 1, round((k + 0.5) * len(mine) / n - 0.5))] for k in range(n)]
    run_together(jaw, {name: _finger_touches(jaw, name, items, guess, r, placement, guard, readings, skipped,
                                             gap=loc_gap, travel=loc_travel) for name, items in by_finger.items()})
    faces_found = [rd for rd in readings if rd.kind == "face"]
    if len(faces_found) < 3:
        raise CalibrationRefused(f"placement {placement}: found the reference with only {len(faces_found)} "
                                 f"touches ({'; '.join(sorted(set(skipped))) or 'none skipped'}); place the disk "
                                 f"of radius {r:g} mm near ({guess[0]:g}, {guess[1]:g})")
    model = _Model(cfg, reference, [dataclasses.replace(rd, placement=0) for rd in faces_found])
    center = model.pose_start(_pack(cfg))[:2]
    # 2. the full plan around the located disk
    guard = make_guard(center, TRANSIT_CLEARANCE_MM)
    plan = plan_touches(cfg, reference, center, faces=faces, corners=corners, gap=APPROACH_GAP_MM,
                        accept=reachable(guard))
    run_together(jaw, {f.name: _finger_touches(jaw, f.name, [t for t in plan if t.finger == f.name], center, r,
                                               placement, guard, readings, skipped) for f in cfg.fingers})
    return readings, center, skipped
