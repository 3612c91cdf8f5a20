"""Calibration fit: the jaw's kinematic parameters from contact readings on a known object.

Pure (no bus): :func:`fit` takes readings (encoder ticks at contact) and returns the
calibrated config with standard errors, or refuses. The touch plan is in
hand_driver.calibration_plan, the jaw procedure that collects readings in
hand_driver.calibration.

Unknowns (per finger): the ``zero_tick`` of both joints, the ``link_mm`` of both links
and the pad's ``offset_mm``; nuisance: the reference object's pose. Readings are joint
ticks at contact, of two kinds:

- ``face``: the pad lies tangent to the reference (a disk: the pad line is at distance r
  from the centre, ``n(ψ)·C − d − r = 0``; a flat block: the pad lies on the face, both
  pad ends on the face line ``m·p = h``);
- ``corner``: the pad's distal corner (fingertip end of the pad surface) touches the
  reference (disk: ``|corner − C| − r = 0``; block: ``m·corner − h = 0``); ``heel``: the
  proximal end does.

Why both kinds (identifiability): a face contact depends on the distal link only through
its direction (the pad is parallel to it), so ``link_mm`` of the distal joint is
invisible to face touches; corner touches see it. The pad offset and the proximal link
are separated by face touches at many pad orientations; the zero ticks of a finger are
separated from the object's unknown position only because both fingers touch the same
object (a single finger turning about its own base together with the object is a
symmetry). The fit (scipy.optimize.least_squares) reports residuals before (nominal
config, only the object's pose fitted) and after, standard errors from the Jacobian
(σ² (JᵀJ)⁻¹ with σ² from the residuals, floored at the quantization variance), and
refuses (:class:`CalibrationRefused`) when the Jacobian is rank deficient or a parameter's
standard error exceeds its tolerance.

Backlash (``backlash=True``; docs/kinematics.md, calibration): a joint's encoder leads its link
by ±h, on the side its load pushes (hand_driver.sim.errors). Each reading's load on each joint
is the sign s of the moment arm of the force the finger applies at the contact
(kinematics.moment_arms: along the pad's normal for a face touch, toward the disk's centre
for a pad end), judged at the nominal geometry; ``zero_tick`` is the link's zero under the
joint's working load w (kinematics.working_loads: a press of the pad's face), so the link
angle is the encoder's less (s − w)·h (kinematics.load_offsets). A joint the readings load
both ways (the plan's two inverse-kinematics branches and its corner touches do) gets its
band 2h as an unknown, ``backlash_deg``; a joint loaded one way only keeps ``backlash_deg``
as configured and its ``zero_tick`` is the offset under that load. Zero ticks are in each joint's model's
ticks; their tolerance is the larger of ``zero_tick`` (0.5 tick) and ``ZERO_FLOOR_DEG``.

Compliance (docs/kinematics.md, declared compliance): a blocked servo's current balances the
contact's torque, Kt_j·I_j = τ_j = a_j·F (hand_driver.sim.errors), so each reading's own currents
(``Reading.current_ma``) give its joints' torques (kinematics.joint_torques) and, by least squares
against the moment arms at its contact, its force F (:meth:`ContactModel.set_forces`). A joint of
compliance c reads its link c·τ behind the encoder, and a pad of give k stands k·F behind the line
its links give. Where every reading carries its currents the fit with every c and k as unknowns
(``compliance_deg_per_nm``, ``compliance_mm_per_n``) is made, and kept when some c or k is above
``COMPLIANCE_Z`` standard errors; a jaw that does not measurably yield keeps the rigid fit, so its
calibration is the same as without currents. Each reading keeps its quantization σ: what the load
model leaves, the current's resolution (one unit, ±½ uniform) times c (and k/|a|), is 0.02–0.07 µm
at the pad on the P-series jaw at 0.02°/N·m and 0.002 mm/N, against the quantization's 0.1–0.3 µm,
and is not yet added (nor a real jaw's gear friction f, f·c per joint: the e-Manual states none).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import least_squares

from hand_driver import kinematics as kin
from hand_driver.config import JawConfig
from hand_driver.units import ticks_to_rad
from tactile_common.errors import InputError

#: a reading whose residual exceeds this many quantization σ is not the modelled contact
OUTLIER_Z = 4.0
#: screening passes (reclassify pad-end contacts, drop unexplained readings, refit): seed 563's
#: emulated readings need 5
SCREEN_PASSES = 8
#: the screening fits' Cauchy loss scale, in quantization σ: a reading the contact model does not
#: explain (a load sign judged wrong, a pad end labelled face: 5–80 µm, 50–600 σ off) weighs
#: about (this / z)² of a good one, so it hardly pulls the fit that judges the others
ROBUST_Z = 3.0
#: its reweighting passes at most, and the change of every weight below which they have settled
ROBUST_PASSES = 20
ROBUST_SETTLED = 1e-3
#: default standard-error tolerances: half the recovery targets (1 tick, 0.1 mm, 0.02° of band)
TOLERANCES = {"zero_tick": 0.5, "link_mm": 0.05, "offset_mm": 0.05, "backlash_deg": 0.01,
              "compliance_deg_per_nm": 0.05, "compliance_mm_per_n": 0.005}
#: a zero tick's tolerance is never below this angle (deg): 14 ticks of a PH54, whose encoder
#: is finer than the contact physics of a calibration touch
ZERO_FLOOR_DEG = 0.005
#: a joint's band is fitted when at least this many readings load it each way
BAND_MIN_EACH_WAY = 3
#: a joint whose model states a band (the e-Manual's backlash b) has it fitted from any readings
#: that load it both ways, with b as a prior of deviation ``BAND_PRIOR_FRACTION``·b: the band a
#: few readings against the working load cannot fix is then b ± b/2, and what that leaves is in
#: every parameter's standard error (docs/kinematics.md, backlash on the X-series jaw)
BAND_PRIOR_FRACTION = 0.5
#: with declared compliance measured (module docstring): the compliant fit is kept when some joint's c
#: or pad's k comes out above this many standard errors, else the rigid one (a jaw whose links and
#: pads do not yield is calibrated exactly as before)
COMPLIANCE_Z = 3.0
#: a reading's leverage in the standard errors is taken as at most this (one that alone fixes a
#: parameter has leverage 1 and a zero residual: its leave-one-out residual r/(1 − h) is finite)
LEVERAGE_MAX = 1.0 - 1e-9
#: what each parameter kind needs, for refusals
_NEEDS = {
    "zero_tick": "face touches of this finger at widely spread pad orientations, with the other finger "
                 "touching the same object",
    "link_mm": "corner touches (distal link) or face touches at widely spread orientations (proximal link)",
    "offset_mm": "face touches at widely spread pad orientations",
    "backlash_deg": "touches that load the joint both ways (both inverse-kinematics branches, corner touches)",
    "compliance_deg_per_nm": "touches that load the joint with widely different torques",
    "compliance_mm_per_n": "face touches pressed with widely different forces",
}


class CalibrationRefused(InputError):
    """The touches do not determine every parameter to its tolerance."""


@dataclass(frozen=True)
class Reading:
    """One contact: finger name, kind ('face', 'corner' or 'heel'), that finger's two
    encoder ticks, which placement of the reference it touched (0, 1, ...), and its two joints'
    Present Current at that reading (mA as the bus reads them; None: not read)."""

    finger: str
    kind: str
    ticks: tuple[float, float]
    placement: int = 0
    current_ma: tuple[float, float] | None = None


@dataclass(frozen=True)
class Estimate:
    name: str  # e.g. "left.joint1.zero_tick", "left.pad.offset_mm", "left.joint1.backlash_deg"
    kind: str  # zero_tick | link_mm | offset_mm | backlash_deg
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
    n_reclassified: int = 0  # face readings found to be pad-end contacts (ContactModel.screen)
    n_dropped: int = 0  # readings the contact model cannot explain, left out
    #: with backlash: per joint (name, readings loading it negatively, positively, band fitted)
    loads: tuple[tuple[str, int, int, bool], ...] = ()

    def to_json(self) -> dict:
        return {
            "loads": [{"joint": n, "negative": a, "positive": b, "band_fitted": f} for n, a, b, f in self.loads],
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

def _param_names(cfg: JawConfig, bands: tuple[int, ...] = (), compliance: bool = False) -> list[tuple[str, str]]:
    out = []
    for f in cfg.fingers:
        out += [(f"{f.name}.joint{j.id}.zero_tick", "zero_tick") for j in f.joints]
        out += [(f"{f.name}.joint{j.id}.link_mm", "link_mm") for j in f.joints]
        out.append((f"{f.name}.pad.offset_mm", "offset_mm"))
    names = {k: f"{f.name}.joint{j.id}" for k, (f, j) in enumerate((f, j) for f in cfg.fingers for j in f.joints)}
    out += [(f"{names[k]}.backlash_deg", "backlash_deg") for k in bands]
    if compliance:
        out += [(f"{names[k]}.compliance_deg_per_nm", "compliance_deg_per_nm") for k in range(len(names))]
        out += [(f"{f.name}.pad.compliance_mm_per_n", "compliance_mm_per_n") for f in cfg.fingers]
    return out


def pack_params(cfg: JawConfig, bands: tuple[int, ...] = (), compliance: bool = False) -> np.ndarray:
    """The fit's unknowns of ``cfg``: per finger both zero ticks, both links and the pad
    offset, then the band (backlash_deg) of each joint of ``bands`` (indices in cfg.joints), then
    with ``compliance`` every joint's compliance_deg_per_nm and every pad's compliance_mm_per_n."""
    v = []
    for f in cfg.fingers:
        v += [j.zero_tick for j in f.joints] + [j.link_mm for j in f.joints] + [f.pad.offset_mm]
    joints = cfg.joints
    v += [joints[k].backlash_deg for k in bands]
    if compliance:
        v += [j.compliance_deg_per_nm for j in joints] + [f.pad.compliance_mm_per_n for f in cfg.fingers]
    return np.array(v, dtype=float)


def apply_params(cfg: JawConfig, v, bands: tuple[int, ...] = (), compliance: bool = False) -> JawConfig:
    """A copy of ``cfg`` with the calibrated parameters ``v`` (the fit's order)."""
    fingers, k = [], 0
    nf, nj = len(cfg.fingers), len(cfg.joints)
    band_of = dict(zip(bands, v[5 * nf:5 * nf + len(bands)]))
    first = 5 * nf + len(bands)
    g = 0
    for fi, f in enumerate(cfg.fingers):
        z, links, off = v[k:k + 2], v[k + 2:k + 4], v[k + 4]
        k += 5
        joints = []
        for i, j in enumerate(f.joints):
            j = dataclasses.replace(j, zero_tick=float(z[i]), link_mm=float(links[i]))
            if g in band_of:
                j = dataclasses.replace(j, backlash_deg=max(0.0, float(band_of[g])))
            if compliance:
                j = dataclasses.replace(j, compliance_deg_per_nm=max(0.0, float(v[first + g])))
            joints.append(j)
            g += 1
        pad = dataclasses.replace(f.pad, offset_mm=float(off))
        if compliance:
            pad = dataclasses.replace(pad, compliance_mm_per_n=max(0.0, float(v[first + nj + fi])))
        fingers.append(dataclasses.replace(f, joints=tuple(joints), pad=pad))
    return dataclasses.replace(cfg, fingers=tuple(fingers))


class ContactModel:
    """Residuals (mm) of every reading for kinematic parameters v and object pose w."""

    def __init__(self, cfg: JawConfig, reference, readings: list[Reading], bands: tuple[int, ...] = (),
                 compliance: bool = False):
        self.cfg = cfg
        self.bands = tuple(bands)  # joints (indices in cfg.joints) whose band is an unknown
        #: every joint's compliance and every pad's give are unknowns, each reading's own currents
        #: its joints' torques (kinematics.joint_torques) and the force they balance (:meth:`set_forces`)
        self.compliance = compliance
        if compliance and any(r.current_ma is None for r in readings):
            raise InputError("a compliance fit needs every reading's joint currents")
        joints = cfg.joints
        #: each fitted band's prior (deg): its model's stated backlash, None where none is stated
        self.priors = tuple(joints[k].spec.backlash_deg for k in self.bands)
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
                        ticks = np.array([readings[i].ticks for i in sel], dtype=float)
                        if compliance:  # columns: ticks, load signs (set_loads), torques, force (set_forces)
                            torques = kin.joint_torques(f, np.array([readings[i].current_ma for i in sel], dtype=float))
                            ticks = np.hstack([ticks, np.zeros_like(ticks), torques, np.zeros((len(sel), 1))])
                        self.groups.append((pl, fi, kind, ticks))
                        self.members.append(sel)
        unknown = {r.finger for r in readings} - set(names)
        if unknown:
            raise InputError(f"readings name unknown finger(s) {sorted(unknown)}; fingers are {names}")
        bad = {r.kind for r in readings} - {"face", "corner", "heel"}
        if bad:
            raise InputError(f"reading kinds must be 'face', 'corner' or 'heel', got {sorted(bad)}")

    def half_bands(self, v, fi: int) -> np.ndarray:
        """Each joint of finger ``fi``'s half band h (rad): fitted, else as configured."""
        first = 2 * fi
        h = np.radians([j.backlash_deg for j in self.cfg.fingers[fi].joints]) / 2.0
        nf = 5 * len(self.cfg.fingers)
        for slot, k in enumerate(self.bands):
            if first <= k < first + 2:
                h[k - first] = math.radians(v[nf + slot]) / 2.0
        return h

    def compliances(self, v, fi: int) -> tuple[np.ndarray, float]:
        """Finger ``fi``'s joints' compliance c (rad per N·m) and its pad's give k (mm per N) in ``v``."""
        first = 5 * len(self.cfg.fingers) + len(self.bands)
        c = np.radians(v[first + 2 * fi:first + 2 * fi + 2])
        return c, float(v[first + len(self.cfg.joints) + fi])

    def lines(self, v, fi: int, ticks) -> kin.PadLine:
        """The pad lines of readings ``ticks`` (n, 2), or (n, 4) with each joint's load sign
        (set_loads): the link angles are the encoders' less sign·h; or (n, 7) with each joint's
        torque τ and the contact force F too (compliance): the link angles less c·τ as well, and
        less the turns that put the pad's line k·F further in along its normal at the same angle
        (kinematics.yield_turns, the exploration's kinematics.compliance_turns with the fitted
        link, c and k)."""
        f = self.cfg.fingers[fi]
        k = 5 * fi
        zero, links, off = v[k:k + 2], v[k + 2:k + 4], v[k + 4]
        sign = np.array([j.direction for j in f.joints], dtype=float)
        ticks = np.asarray(ticks, dtype=float)
        q = ticks_to_rad(ticks[..., :2], zero, sign, kin.resolutions(f.joints))
        if ticks.shape[-1] >= 4:  # zero_tick: the link's zero under the working load
            q = q - np.where(ticks[..., 2:4] == 0.0, 0.0, ticks[..., 2:4] - kin.working_loads(f)) * self.half_bands(v, fi)
        if ticks.shape[-1] == 7:
            c, give = self.compliances(v, fi)
            q = q - kin.yield_turns(f.base.angle, links[0], f.pad.side_sign, c, give, q, ticks[..., 4:6], ticks[..., 6])
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
                m = kin.unit(a)
                if kind == "face":
                    out += [line.proximal @ m - b, line.distal @ m - b]
                else:
                    out.append((line.distal if kind == "corner" else line.proximal) @ m - b)
        return np.concatenate(out)

    def prior_residuals(self, v) -> np.ndarray:
        """Each fitted band with a stated figure b: (band − b)/(``BAND_PRIOR_FRACTION``·b)."""
        nf = 5 * len(self.cfg.fingers)
        return np.array([(v[nf + i] - b) / (BAND_PRIOR_FRACTION * b) for i, b in enumerate(self.priors)
                         if b], dtype=float)

    def weighted(self, x, nv: int, sig) -> np.ndarray:
        """The fit's residuals at x = (parameters, poses): each reading's by its σ, then the priors."""
        return np.concatenate([self.residuals(x[:nv], x[nv:]) / sig, self.prior_residuals(x[:nv])])

    def _pressing(self, v, w, pl: int, fi: int, kind: str, ticks) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(link angles, contact points, force directions) of a group's readings at (v, w): the
        force the finger applies at its contact, along the pad's normal for a face touch, toward
        the disk's centre for a pad end (module docstring)."""
        f = self.cfg.fingers[fi]
        t2 = np.asarray(ticks, dtype=float)[:, :2]
        line = self.lines(v, fi, t2)
        q = ticks_to_rad(t2, v[5 * fi:5 * fi + 2], np.array([j.direction for j in f.joints], dtype=float),
                         kin.resolutions(f.joints))
        points, directions = [], []
        for i in range(len(t2)):
            ln = line.at(i)
            if self.cls == "circle":
                c = np.array([w[2 * pl], w[2 * pl + 1]])
                if kind == "face":
                    point, direction = c - self.r * ln.normal, ln.normal
                else:
                    point = ln.distal if kind == "corner" else ln.proximal
                    direction = (c - point) / max(float(np.hypot(*(c - point))), 1e-12)
            else:
                m = kin.unit(w[2 * pl])
                direction = m if float(m @ ln.normal) >= 0.0 else -m
                point = (0.5 * (ln.proximal + ln.distal) if kind == "face"
                         else ln.distal if kind == "corner" else ln.proximal)
            points.append(point)
            directions.append(direction)
        return q, np.array(points), np.array(directions)

    def set_loads(self, v, w) -> None:
        """Set each reading's load sign on each joint (the sign of the moment arm of the
        force the finger applies at its contact, module docstring) in its group's ticks."""
        out = []
        for pl, fi, kind, ticks in self.groups:
            q, points, directions = self._pressing(v, w, pl, fi, kind, ticks)
            signs = np.sign(kin.moment_arms(self.cfg.fingers[fi], q, points, directions))
            t = np.asarray(ticks, dtype=float)
            out.append((pl, fi, kind, np.hstack([t[:, :2], signs, t[:, 4:]])))
        self.groups = out

    def set_forces(self, v, w) -> None:
        """Set each reading's contact force F ≥ 0 (N) in its group's ticks: the least squares of its
        joints' torques (from its own currents) against a_j·F, a_j the moment arms at (v, w) (the
        balance a blocked finger's servos hold, hand_driver.sim.errors)."""
        out = []
        for pl, fi, kind, ticks in self.groups:
            q, points, directions = self._pressing(v, w, pl, fi, kind, ticks)
            t = np.array(ticks, dtype=float)
            t[:, 6] = kin.pressed_force(self.cfg.fingers[fi], q, points, t[:, 4:6], directions)
            out.append((pl, fi, kind, t))
        self.groups = out

    def loads_by_joint(self) -> dict[int, tuple[int, int]]:
        """Per joint (index in cfg.joints): how many readings load it (negative, positive)."""
        out: dict[int, list[int]] = {}
        for pl, fi, kind, ticks in self.groups:
            t = np.asarray(ticks)
            if t.shape[-1] < 4:
                continue
            for i in range(2):
                c = out.setdefault(2 * fi + i, [0, 0])
                c[0] += int(np.sum(t[:, 2 + i] < 0))
                c[1] += int(np.sum(t[:, 2 + i] > 0))
        return {k: (a, b) for k, a, b in ((k, *v) for k, v in out.items())}

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
                m = kin.unit(ang)
                w += [ang, float(np.mean(np.concatenate([ln.distal @ m for ln in lines])))]
        return np.array(w)

    def screen(self, v, w, z, readings: list[Reading]) -> tuple[list[Reading], int, int]:
        """Readings the contact model explains at (v, w): a disk face touch whose tangent
        point lies off the pad was a pad-end contact and becomes 'heel'/'corner'; if none
        does, the readings with a normalized residual |z| above OUTLIER_Z (quantization
        alone gives ≤ √6 ≈ 2.45) and above half the largest |z| are dropped (the worst
        first). (v, w) is :func:`fit`'s robust fit, which a bad reading hardly pulls (until
        session 33 a plain fit: on seed 563's readings it was pulled so far that good readings
        were dropped and four passes left 10 of them 55–600 σ off). Returns
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
                dt = np.zeros_like(np.asarray(group[3], dtype=float))
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


def standard_errors(u, s, vt, fun, n_prior: int) -> np.ndarray:
    """Each unknown's standard error from the weighted fit's Jacobian J = U·S·Vᵀ and residuals
    ``fun`` (readings by their quantization σ, then ``n_prior`` prior rows): the leave-one-out
    (HC3) sandwich V·S⁻¹·Uᵀ·diag(wᵢ)·U·S⁻¹·Vᵀ with wᵢ = (rᵢ / (1 − hᵢ))², hᵢ = Σₖ Uᵢₖ² the
    reading's leverage, 1 for a prior row (its stated deviation), and never below the quantization
    model's V·S⁻²·Vᵀ. A parameter that few readings fix (a band loaded against the working load
    by 2–7 touches) then carries those readings' own scatter, each as far off as the fit without
    it would leave it, where the pooled χ²/dof of ~130 readings hid it."""
    h = np.minimum(np.sum(u**2, axis=1), LEVERAGE_MAX)
    w = (fun / (1.0 - h)) ** 2
    w[w.size - n_prior:] = 1.0
    a = (vt.T / s) @ u.T  # (JᵀJ)⁻¹Jᵀ
    return np.sqrt(np.maximum(np.sum(a**2 * w, axis=1), np.sum((vt.T / s) ** 2, axis=1)))


def backlash_matters(cfg: JawConfig) -> bool:
    """Does any joint's model state a backlash (the e-Manual's, control_table.ModelSpec.backlash_deg)?
    ``tactile calibrate`` then models it: even the XM430's 0.25°, under 3 of its ticks, biased the
    links by 0.13–0.17 mm (4–6 standard errors) where 5–9 readings per joint bear against the
    working load (docs/kinematics.md)."""
    return any(j.spec.backlash_deg for j in cfg.joints)


def _bands(cfg: JawConfig, reference, readings: list[Reading]) -> dict[int, tuple[int, int]]:
    """Every joint's load counts (negative, positive) over the readings (judged at the nominal
    geometry and the readings' pose); its band is fitted when both reach ``BAND_MIN_EACH_WAY``."""
    model = ContactModel(cfg, reference, readings)
    v0 = pack_params(cfg)
    w0 = model.pose_start(v0)
    w = least_squares(lambda w: model.residuals(v0, w), w0, method="lm").x
    model.set_loads(v0, w)
    return model.loads_by_joint()


def fit(cfg: JawConfig, reference, readings: list[Reading], tolerances: dict | None = None,
        backlash: bool = False) -> CalibrationResult:
    """Least-squares calibration (module docstring); with ``backlash`` the readings' load
    directions are modelled and the band of every joint loaded both ways is fitted;
    :class:`CalibrationRefused` when a parameter is not determined to its tolerance. When every
    reading carries its joints' currents, the fit with every joint's compliance and pad's give
    as unknowns (each reading's link angles its encoders' less c·τ, its pad k·F behind its line,
    τ and F from its own currents) is kept if some c or k comes out above ``COMPLIANCE_Z``
    standard errors: a jaw that yields measurably; else (or if that fit is refused) the rigid fit."""
    tol = dict(TOLERANCES, **(tolerances or {}))
    counts = _bands(cfg, reference, readings) if backlash else {}
    joints = cfg.joints
    bands = tuple(sorted(k for k, (neg, pos) in counts.items()
                         if min(neg, pos) >= (1 if joints[k].spec.backlash_deg else BAND_MIN_EACH_WAY)))
    if all(r.current_ma is not None for r in readings):
        try:
            yielding = _fit(cfg, reference, readings, tol, backlash, counts, bands, compliance=True)
        except CalibrationRefused:
            yielding = None
        if yielding is not None and any(e.after > COMPLIANCE_Z * e.se for e in yielding.estimates
                                        if e.kind in ("compliance_deg_per_nm", "compliance_mm_per_n")):
            return yielding
    return _fit(cfg, reference, readings, tol, backlash, counts, bands, compliance=False)


def _fit(cfg: JawConfig, reference, readings: list[Reading], tol: dict, backlash: bool, counts: dict,
         bands: tuple[int, ...], compliance: bool) -> CalibrationResult:
    """:func:`fit` with the bands ``bands`` (``counts``: every joint's load counts) and, with
    ``compliance``, every joint's c and pad's k as unknowns."""
    joints = cfg.joints
    v0 = pack_params(cfg, bands, compliance)
    names = _param_names(cfg, bands, compliance)
    nv = v0.size
    used, n_reclassified, n_dropped = list(readings), 0, 0
    for attempt in range(SCREEN_PASSES + 1):
        model = ContactModel(cfg, reference, used, bands, compliance)
        n_pose = 2 * len(model.placements)
        n_res = sum(len(t) * (2 if (model.cls == "line" and kind == "face") else 1)
                    for _, _, kind, t in model.groups)
        if n_res <= nv + n_pose:
            raise CalibrationRefused(f"{n_res} residuals for {nv + n_pose} unknowns: more touches are needed "
                                     f"(face and corner touches of both fingers on every placement)")
        # before: nominal parameters, only the pose fitted
        w0 = model.pose_start(v0)
        before = least_squares(lambda w: model.residuals(v0, w), w0, method="lm")
        if backlash:
            model.set_loads(v0, before.x)
        if compliance:
            model.set_forces(v0, before.x)
        x0 = np.concatenate([v0, before.x])
        # weighted by each reading's quantization σ (at the nominal geometry), so that
        # readings with long lever arms (coarse) count less than fine ones
        sig = np.maximum(model.reading_sigmas(v0, before.x), 1e-4)
        # screened on a robust fit (Cauchy loss, ROBUST_Z): the readings the model explains decide
        robust = _robust_fit(lambda x: model.weighted(x, nv, sig), x0)
        sv = np.linalg.svd(robust.jac, compute_uv=False)
        col = np.linalg.norm(robust.jac, axis=0)
        unseen = np.any(col <= 1e-6 * np.max(col))  # a parameter the readings do not see
        if attempt == SCREEN_PASSES or unseen or sv[-1] <= 1e-9 * sv[0]:  # rank deficient: refused below
            break
        screened, moved, dropped = model.screen(robust.x[:nv], robust.x[nv:], robust.fun, used)
        if not moved and not dropped:
            break
        used, n_reclassified, n_dropped = screened, n_reclassified + moved, n_dropped + dropped
    # the estimates and their standard errors: plain least squares on the readings kept
    res = least_squares(lambda x: model.weighted(x, nv, sig), robust.x, method="lm", x_scale="jac",
                        xtol=1e-12, ftol=1e-12, gtol=1e-12, max_nfev=2000)
    r = res.fun[:sig.size] * sig  # mm
    m = res.fun.size
    jac = res.jac
    u, s, vt = np.linalg.svd(jac, full_matrices=False)
    col = np.linalg.norm(jac, axis=0)
    if np.any(col == 0.0) or s[-1] <= 1e-9 * s[0]:
        weak = int(np.argmax(np.abs(vt[-1])))
        what = names[weak][0] if weak < nv else "the reference pose"
        kind = names[weak][1] if weak < nv else "zero_tick"
        raise CalibrationRefused(f"the touches cannot determine {what} (rank-deficient Jacobian); "
                                 f"it needs {_NEEDS[kind]}")
    se = standard_errors(u, s, vt, res.fun, m - sig.size)
    zero_tol = [max(tol["zero_tick"], ZERO_FLOOR_DEG * j.ticks_per_rev / 360.0) for j in joints]
    # a band with a stated figure is known to its prior at worst: its tolerance is the prior's σ
    prior_tol = {5 * len(cfg.fingers) + i: BAND_PRIOR_FRACTION * b for i, b in enumerate(model.priors) if b}
    tolerance = [zero_tol[2 * (i // 5) + i % 5] if kind == "zero_tick" else max(tol[kind], prior_tol.get(i, 0.0))
                 for i, (_, kind) in enumerate(names)]
    estimates = tuple(Estimate(name, kind, float(v0[i]), float(res.x[i]), float(se[i]), tolerance[i])
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
    spread = _placement_spread(cfg, reference, used, bands, v0, res.x, backlash, compliance)
    return CalibrationResult(config=_with_zero_sigmas(apply_params(cfg, res.x[:nv], bands, compliance), estimates,
                                                      spread),
                             estimates=estimates, reference_poses=poses,
                             rms_before_mm=float(np.sqrt(np.mean(before.fun**2))),
                             rms_after_mm=float(np.sqrt(np.mean(r**2))), max_after_mm=float(np.max(np.abs(r))),
                             n_readings=len(used), n_reclassified=n_reclassified, n_dropped=n_dropped,
                             loads=tuple((f"{f.name}.joint{j.id}", *counts.get(k, (0, 0)), k in bands)
                                         for k, (f, j) in enumerate((f, j) for f in cfg.fingers for j in f.joints)
                                         if counts))


def _robust_fit(fun, x0: np.ndarray):
    """The least squares of ``fun`` (residuals in σ's) under a Cauchy loss of scale ``ROBUST_Z``, by
    iteratively reweighted least squares from the plain fit: each pass weighs every residual by
    1/√(1 + (z/ROBUST_Z)²) of the last pass's, until the weights settle (``ROBUST_PASSES`` at
    most). Returns least_squares' result of the last pass, its ``fun`` the unweighted residuals."""
    weight = np.ones_like(np.asarray(fun(x0), dtype=float))
    res = None
    for _ in range(ROBUST_PASSES):
        res = least_squares(lambda x: fun(x) * weight, x0 if res is None else res.x, method="lm", x_scale="jac",
                            max_nfev=2000)
        z = np.asarray(fun(res.x), dtype=float)
        new = 1.0 / np.sqrt(1.0 + (z / ROBUST_Z) ** 2)
        settled = np.max(np.abs(new - weight)) < ROBUST_SETTLED
        weight = new
        if settled:
            break
    res.fun = np.asarray(fun(res.x), dtype=float)
    return res


def _placement_spread(cfg: JawConfig, reference, used: list[Reading], bands, v0, x, backlash: bool,
                      compliance: bool = False) -> np.ndarray | None:
    """The jackknife standard error of every parameter over the reference's placements: the
    fit repeated leaving out each placement in turn (from the full fit's values, each
    reading's load as judged there), √((k − 1)/k · Σ (v_i − v̄)²). It holds what differs
    from placement to placement (where the disk really sat, the pad-end contacts' geometry,
    the emulator's or the jaw's contact physics) that the quantization model's standard
    errors leave out: on the P-series jaw calibrated against config/jaw-p-truth.yaml the zero
    ticks came out 2–4 of those off. None with fewer than 3 placements, or when a left-out
    fit is not determined (fewer residuals than unknowns, rank deficient) or fails."""
    placements = sorted({r.placement for r in used})
    if len(placements) < 3:
        return None
    nv = len(v0)
    fits = []
    for drop in placements:
        kept = [p for p in placements if p != drop]
        renum = {p: i for i, p in enumerate(kept)}
        sub = [dataclasses.replace(r, placement=renum[r.placement]) for r in used if r.placement != drop]
        try:
            model = ContactModel(cfg, reference, sub, bands, compliance)
        except InputError:
            return None
        w = np.concatenate([x[nv + 2 * p: nv + 2 * p + 2] for p in kept])
        if backlash:
            model.set_loads(v0, w)
        if compliance:
            model.set_forces(v0, w)
        sig = np.maximum(model.reading_sigmas(v0, w), 1e-4)
        if sig.size + len(model.priors) <= nv + w.size:  # fewer residuals than unknowns: not determined
            return None
        res = least_squares(lambda y: model.weighted(y, nv, sig), np.concatenate([x[:nv], w]), method="lm",
                            x_scale="jac", xtol=1e-12, ftol=1e-12, gtol=1e-12, max_nfev=2000)
        sv = np.linalg.svd(res.jac, compute_uv=False)
        if not res.success or sv[-1] <= 1e-9 * sv[0]:
            return None
        fits.append(res.x[:nv])
    fits = np.array(fits)
    k = len(fits)
    return np.sqrt((k - 1) / k * np.sum((fits - fits.mean(axis=0)) ** 2, axis=0))


def _with_zero_sigmas(cfg: JawConfig, estimates, spread: np.ndarray | None = None) -> JawConfig:
    """The calibrated config with the uncertainty of what it fitted: each joint's
    ``zero_sigma_deg`` (in degrees) and ``link_sigma_mm``, each pad's ``offset_sigma_mm``, and
    where the compliance was fitted each joint's ``compliance_sigma_deg_per_nm`` and pad's
    ``compliance_sigma_mm_per_n``: the parameter's standard error, or its spread over the
    placements (:func:`_placement_spread`) where that is larger. What the exploration states as
    each touch's offsets (tactile_jaw.envelope.joint_noise, docs/exploration.md#the-stated-noise):
    a pad offset or link length off by 0.5 µm moves a P-series touch's contacts by 2–5 times
    their quantization's deviation."""
    se = {e.name: e.se if spread is None else max(e.se, float(spread[i]))
          for i, e in enumerate(estimates) if e.kind in ("zero_tick", "link_mm", "offset_mm", "compliance_deg_per_nm",
                                                          "compliance_mm_per_n")}
    fingers = []
    for f in cfg.fingers:
        joints = tuple(dataclasses.replace(j, zero_sigma_deg=float(se[f"{f.name}.joint{j.id}.zero_tick"])
                                           * 360.0 / j.spec.ticks_per_rev,
                                           link_sigma_mm=float(se.get(f"{f.name}.joint{j.id}.link_mm", 0.0)),
                                           compliance_sigma_deg_per_nm=float(
                                               se.get(f"{f.name}.joint{j.id}.compliance_deg_per_nm", 0.0)))
                       for j in f.joints)
        pad = dataclasses.replace(f.pad, offset_sigma_mm=float(se.get(f"{f.name}.pad.offset_mm", 0.0)),
                                  compliance_sigma_mm_per_n=float(se.get(f"{f.name}.pad.compliance_mm_per_n", 0.0)))
        fingers.append(dataclasses.replace(f, joints=joints, pad=pad))
    return dataclasses.replace(cfg, fingers=tuple(fingers))
