"""The recognizer's input (docs/formats.md, touches), parsed and validated in one place.

A request is ``{"scene": path|mapping (optional), "touches": [...], "noise": {...},
"options": {...}}``. A touch is either samples (``phi``, ``x``, ``y``, optional ``s``;
equal lengths, >= 3 samples) or ``{"contact": {x, y, phi, kappa, kappa_s}}`` with
optional ``cov`` (2×2 covariance of κ, κ_s) or ``sigma_kappa`` / ``sigma_kappa_s``.
Extensions: top-level ``noise: {phi: rad, pos: mm}`` and ``options: {refine, estimator,
profile, alpha, reach: {x, y, radius}, missed: [{x, y, phi}, ...]}``. Every problem raises a
one-line :class:`InputError`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Mapping

import numpy as np

from recognizer import limits
from recognizer.estimate import METHODS
from recognizer.noise import NoiseModel, parse_noise
from recognizer.scene import ALL_CLASSES, check_profile, load_scene
from tactile_common.errors import InputError, check_keys
from tactile_common.inputs import finite_number

__all__ = ["NoiseModel", "Reach", "MissedPlace", "SamplesTouch", "ContactTouch", "Request", "parse_request",
           "parse_noise", "MIN_TOUCHES", "check_touch_count", "finite_number", "touch_points"]

#: touches a class needs before its invariants can be cross-checked (>= 2 pairs for the
#: two-parameter and cubic classes, >= 1 pair for the others)
MIN_TOUCHES: dict[str, int] = {
    "line": 2, "circle": 2, "parabola": 2, "ellipse": 3, "hyperbola": 3,
    "cubical_parabola": 3, "semicubical_parabola": 3,
}
_TOP_KEYS = {"scene", "touches", "noise", "options", "meta"}
_SAMPLE_KEYS = {"phi", "x", "y", "s", "curvature", "noise_factor", "finger", "meta"}
_CURVATURE_KEYS = ("kappa", "kappa_s", "cov", "sigma_kappa", "sigma_kappa_s")
_CONTACT_KEYS = ("x", "y", "phi") + _CURVATURE_KEYS
_OPTION_KEYS = {"refine": bool, "estimator": str, "profile": str, "alpha": float, "timeout_s": float, "reach": dict,
                "missed": list}


@dataclass(frozen=True)
class Reach:
    """Where the robot can touch: a hand-frame disk (mm) around (x, y) of ``radius``."""

    x: float
    y: float
    radius: float

    def contains(self, px, py, phi=None):
        """Whether the points lie in the disk (the tangent angles ``phi`` do not matter to a disk)."""
        return np.hypot(np.asarray(px, float) - self.x, np.asarray(py, float) - self.y) <= self.radius

    def to_json(self) -> dict:
        return {"x": self.x, "y": self.y, "radius": self.radius}


def parse_reach(raw, where: str = "options.reach") -> Reach:
    """A reach disk {x, y, radius}: finite numbers, radius > 0."""
    if not isinstance(raw, Mapping):
        raise InputError(f"{where}: must be a mapping {{x: mm, y: mm, radius: mm}}")
    check_keys(raw, ("x", "y", "radius"), where)
    vals = _required(raw, ("x", "y", "radius"), where, "a reach")
    if vals["radius"] <= 0:
        raise InputError(f"{where}.radius: must be > 0, got {vals['radius']}")
    for k, v in vals.items():
        if abs(v) > limits.MAX_COORD_MM:
            raise InputError(f"{where}.{k}: |{v:.6g}| mm is beyond {limits.MAX_COORD_MM:g} mm")
    return Reach(**vals)


@dataclass(frozen=True)
class MissedPlace:
    """A place a touch was sent to and lost (the pad met nothing it could roll on): the
    hand-frame point (mm) and the pad's orientation ``phi`` (rad), as a ``next_touch`` gives
    them (recognizer.next_touch keeps its suggestions off the stretch a pad sent there meets)."""

    x: float
    y: float
    phi: float

    def to_json(self) -> dict:
        return {"x": self.x, "y": self.y, "phi": self.phi}


def parse_missed(raw, where: str = "options.missed") -> tuple[MissedPlace, ...]:
    """A list of at most ``limits.MAX_MISSED`` places {x, y, phi}: finite numbers, |x|, |y|
    within ``limits.MAX_COORD_MM``, |phi| within ``limits.MAX_PHI_RAD``."""
    if not isinstance(raw, list):
        raise InputError(f"{where}: must be a list of places {{x: mm, y: mm, phi: rad}}")
    if len(raw) > limits.MAX_MISSED:
        raise InputError(f"{where}: {len(raw)} places; at most {limits.MAX_MISSED}")
    out = []
    for i, place in enumerate(raw):
        at = f"{where}[{i}]"
        if not isinstance(place, Mapping):
            raise InputError(f"{at}: must be a mapping {{x: mm, y: mm, phi: rad}}")
        check_keys(place, ("x", "y", "phi"), at)
        vals = _required(place, ("x", "y", "phi"), at, "a missed place")
        for k, bound, unit in (("x", limits.MAX_COORD_MM, "mm"), ("y", limits.MAX_COORD_MM, "mm"),
                               ("phi", limits.MAX_PHI_RAD, "rad")):
            if abs(vals[k]) > bound:
                raise InputError(f"{at}.{k}: |{vals[k]:.6g}| {unit} is beyond {bound:g} {unit}")
        out.append(MissedPlace(**vals))
    return tuple(out)


@dataclass(frozen=True)
class SamplesTouch:
    """Samples of one local rolling move, ordered along the boundary."""

    phi: np.ndarray
    x: np.ndarray
    y: np.ndarray
    s: np.ndarray | None = None
    #: (κ, κ_s, 2×2 covariance) at the contact sample when the instrument measured them
    #: itself (the jaw's envelope fit); None: estimated from the samples (recognizer.estimate)
    curvature: tuple[float, float, np.ndarray] | None = None
    #: (3n, k) factor F of the samples' error covariance F·Fᵀ (rows x…, y…, φ…; mm, rad) when
    #: the instrument states it (the jaw: each joint angle's quantization through its fit)
    noise_factor: np.ndarray | None = None

    @property
    def contact_index(self) -> int:
        return len(self.phi) // 2

    def to_json(self) -> dict:
        """The touch in the input's samples form (docs/formats.md)."""
        out = {"phi": self.phi.tolist(), "x": self.x.tolist(), "y": self.y.tolist()}
        if self.s is not None:
            out["s"] = self.s.tolist()
        if self.curvature is not None:
            k, ks, cov = self.curvature
            out["curvature"] = {"kappa": float(k), "kappa_s": float(ks), "cov": np.asarray(cov, float).tolist()}
        if self.noise_factor is not None:
            out["noise_factor"] = np.asarray(self.noise_factor, float).tolist()
        return out


@dataclass(frozen=True)
class ContactTouch:
    """An already estimated contact; ``cov`` is the 2×2 covariance of (κ, κ_s) (zeros = exact)."""

    x: float
    y: float
    phi: float
    kappa: float
    kappa_s: float
    cov: np.ndarray = field(default_factory=lambda: np.zeros((2, 2)))

    def to_json(self) -> dict:
        """The touch in the input's contact form (docs/formats.md)."""
        return {"contact": {"x": self.x, "y": self.y, "phi": self.phi, "kappa": self.kappa, "kappa_s": self.kappa_s,
                            "cov": np.asarray(self.cov, float).tolist()}}


@dataclass(frozen=True)
class Request:
    touches: tuple
    scene: object | None  # recognizer.scene.Scene
    classes: tuple[str, ...]
    noise: NoiseModel | None = None
    options: dict = field(default_factory=dict)
    source: str = "<request>"


def _vec(v, where: str) -> np.ndarray:
    if not isinstance(v, (list, tuple)):
        raise InputError(f"{where}: must be a list of numbers")
    return np.array([finite_number(e, f"{where}[{i}]") for i, e in enumerate(v)], dtype=float)


def _parse_samples(raw: Mapping, where: str) -> SamplesTouch:
    check_keys(raw, _SAMPLE_KEYS, where, "a samples touch has phi, x, y, optional s")
    for k in ("phi", "x", "y"):
        if k not in raw:
            raise InputError(f"{where}: missing key {k!r} (a samples touch has phi, x, y, optional s)")
    arrs = {k: _vec(raw[k], f"{where}.{k}") for k in ("phi", "x", "y")}
    if raw.get("s") is not None:
        arrs["s"] = _vec(raw["s"], f"{where}.s")
    lens = {k: len(v) for k, v in arrs.items()}
    if len(set(lens.values())) != 1:
        raise InputError(f"{where}: unequal lengths " + ", ".join(f"{k}={n}" for k, n in lens.items()))
    n = lens["phi"]
    if n < 3:
        raise InputError(f"{where}: needs at least 3 samples, got {n}")
    if "s" in arrs and np.any(np.diff(arrs["s"]) <= 0):
        raise InputError(f"{where}.s: arc length must increase strictly along the samples")
    if "s" not in arrs and np.any(np.hypot(np.diff(arrs["x"]), np.diff(arrs["y"])) == 0):
        raise InputError(f"{where}: two consecutive samples at the same position (give s, or distinct x, y)")
    curvature = None
    if raw.get("curvature") is not None:  # the instrument's own κ, κ_s at the contact sample
        curvature = _parse_curvature(raw["curvature"], f"{where}.curvature")
    factor = _parse_noise_factor(raw["noise_factor"], n, f"{where}.noise_factor") \
        if raw.get("noise_factor") is not None else None
    return SamplesTouch(arrs["phi"], arrs["x"], arrs["y"], arrs.get("s"), curvature, factor)


def _parse_noise_factor(raw, n: int, where: str) -> np.ndarray:
    """A samples touch's noise factor F: 3n rows (x…, y…, φ…) of k ≤ 3n finite numbers each,
    not all zero (the samples' error covariance is F·Fᵀ)."""
    if not isinstance(raw, (list, tuple)) or len(raw) != 3 * n:
        raise InputError(f"{where}: must be a list of 3n = {3 * n} rows (x..., y..., phi... of the {n} samples)")
    rows = [_vec(r, f"{where}[{i}]") for i, r in enumerate(raw)]
    k = len(rows[0])
    if not 1 <= k <= 3 * n or any(len(r) != k for r in rows):
        raise InputError(f"{where}: rows must all have the same length, 1 to {3 * n}")
    factor = np.array(rows)
    if np.max(np.abs(factor)) > limits.MAX_COORD_MM or not np.any(factor):
        raise InputError(f"{where}: entries must be within {limits.MAX_COORD_MM:g} and not all zero")
    tiny = np.abs(factor[(factor != 0) & (np.abs(factor) < limits.MIN_NOISE)])
    if tiny.size:
        raise InputError(f"{where}: an entry of {float(tiny[0]):.3g} is below {limits.MIN_NOISE:g} (mm, rad): no "
                         f"instrument resolves errors that small; write 0 for none")
    return factor


def _required(raw: Mapping, keys, where: str, what: str) -> dict[str, float]:
    """The finite numbers at ``keys`` of ``raw``; a missing one names ``what`` has."""
    vals = {}
    for k in keys:
        if k not in raw:
            raise InputError(f"{where}: missing key {k!r} ({what} has {', '.join(keys)})")
        vals[k] = finite_number(raw[k], f"{where}.{k}")
    return vals


def _parse_curvature(raw, where: str) -> tuple[float, float, np.ndarray]:
    """A samples touch's measured ``{kappa, kappa_s, cov | sigma_kappa, sigma_kappa_s}``."""
    if not isinstance(raw, Mapping):
        raise InputError(f"{where}: must be a mapping with kappa, kappa_s and cov or sigma_kappa, sigma_kappa_s")
    check_keys(raw, _CURVATURE_KEYS, where)
    vals = _required(raw, ("kappa", "kappa_s"), where, "a curvature")
    return vals["kappa"], vals["kappa_s"], _parse_cov(raw, where)


def _parse_contact(raw, where: str) -> ContactTouch:
    if not isinstance(raw, Mapping):
        raise InputError(f"{where}: must be a mapping with x, y, phi, kappa, kappa_s")
    check_keys(raw, sorted(_CONTACT_KEYS), where)
    vals = _required(raw, ("x", "y", "phi", "kappa", "kappa_s"), where, "a contact")
    return ContactTouch(cov=_parse_cov(raw, where), **vals)


def _parse_cov(raw: Mapping, where: str) -> np.ndarray:
    """The 2×2 covariance of (κ, κ_s) from ``cov`` or ``sigma_kappa``/``sigma_kappa_s`` (zeros: exact)."""
    cov = np.zeros((2, 2))
    if "cov" in raw:
        if "sigma_kappa" in raw or "sigma_kappa_s" in raw:
            raise InputError(f"{where}: give cov or sigma_kappa/sigma_kappa_s, not both")
        c = raw["cov"]
        shape = f"{where}.cov: must be a 2x2 list [[var_k, cov], [cov, var_ks]]"
        if not isinstance(c, (list, tuple)) or len(c) != 2:
            raise InputError(shape)
        rows = [_vec(r, f"{where}.cov[{i}]") for i, r in enumerate(c)]
        if any(len(r) != 2 for r in rows):
            raise InputError(shape)
        cov = np.array(rows)
        if abs(cov[0, 1] - cov[1, 0]) > 1e-12 * (abs(cov[0, 1]) + 1e-300):
            raise InputError(f"{where}.cov: must be a symmetric 2x2 matrix")
        # c01² ≤ c00·c11 compared as square roots: no product of two large variances overflows
        if cov[0, 0] < 0 or cov[1, 1] < 0 or \
                abs(cov[0, 1]) > math.sqrt(cov[0, 0]) * math.sqrt(cov[1, 1]) * (1.0 + 1e-12) + 1e-300:
            raise InputError(f"{where}.cov: must be positive semi-definite")
    for i, k in enumerate(("sigma_kappa", "sigma_kappa_s")):
        if k in raw:
            sig = finite_number(raw[k], f"{where}.{k}")
            if sig < 0:
                raise InputError(f"{where}.{k}: must be >= 0, got {sig}")
            cov[i, i] = sig * sig
    return cov


def _parse_options(raw, where: str = "options") -> dict:
    if not isinstance(raw, Mapping):
        raise InputError(f"{where}: must be a mapping; allowed keys: {', '.join(_OPTION_KEYS)}")
    out = {}
    for k, v in raw.items():
        if k not in _OPTION_KEYS:
            raise InputError(f"{where}: unknown key {k!r}; allowed: {', '.join(_OPTION_KEYS)}")
        if _OPTION_KEYS[k] is bool and not isinstance(v, bool):
            raise InputError(f"{where}.{k}: must be true or false")
        if _OPTION_KEYS[k] is str and not isinstance(v, str):
            raise InputError(f"{where}.{k}: must be a string")
        if _OPTION_KEYS[k] is float:
            v = finite_number(v, f"{where}.{k}")
        if _OPTION_KEYS[k] is dict:
            v = parse_reach(v, f"{where}.{k}")
        if _OPTION_KEYS[k] is list:
            v = parse_missed(v, f"{where}.{k}")
        out[k] = v
    if "estimator" in out and out["estimator"] not in METHODS:
        raise InputError(f"{where}.estimator: unknown {out['estimator']!r}; allowed: {', '.join(METHODS)}")
    if "alpha" in out and not 0.0 < out["alpha"] < 0.5:
        raise InputError(f"{where}.alpha: must be in (0, 0.5), got {out['alpha']}")
    if "timeout_s" in out and not 0.0 < out["timeout_s"] <= limits.MAX_TIMEOUT_S:
        raise InputError(f"{where}.timeout_s: must be in (0, {limits.MAX_TIMEOUT_S:g}] s, got {out['timeout_s']}")
    return out


def touch_points(touch: Mapping) -> dict[str, list[float]]:
    """The ``x``, ``y``, ``phi`` lists of a touch mapping as written (module docstring): a
    samples touch's own, a contact touch's (a flat press's seat) as one sample. Not
    validated: for drawing what a run recorded (tools.plot, tools.ros_bag)."""
    if "contact" in touch:
        return {k: [touch["contact"][k]] for k in ("x", "y", "phi")}
    return {k: list(touch.get(k) or []) for k in ("x", "y", "phi")}


def check_touch_count(n: int, classes, source: str = "request") -> None:
    """InputError unless ``n`` touches suffice for at least one of ``classes`` (MIN_TOUCHES)."""
    need = min(MIN_TOUCHES[c] for c in classes)
    if n < need:
        raise InputError(f"{source}: {n} touch(es); the scene's classes need at least {need}")


def parse_request(obj, base_dir=None, source: str = "request") -> Request:
    """Validate a decoded JSON request; ``base_dir`` resolves a relative scene path
    after the current directory."""
    if not isinstance(obj, Mapping):
        raise InputError(f"{source}: must be a JSON object with 'touches'")
    check_keys(obj, sorted(_TOP_KEYS), source)
    scene = None
    if obj.get("scene") is not None:
        sc = obj["scene"]
        if not isinstance(sc, (str, Mapping)):
            raise InputError(f"{source}.scene: must be a path or a scene mapping")
        scene = load_scene(sc, base_dir=Path(base_dir) if base_dir is not None else None, source=f"{source}.scene")
    classes = scene.classes if scene is not None else ALL_CLASSES
    raw_touches = obj.get("touches")
    if not isinstance(raw_touches, list):
        raise InputError(f"{source}: missing 'touches' (a list of touches)")
    limits.check_sizes(raw_touches, source)
    touches = []
    for i, t in enumerate(raw_touches):
        where = f"{source}.touches[{i}]"
        if not isinstance(t, Mapping):
            raise InputError(f"{where}: must be an object (samples phi/x/y or contact)")
        if "contact" in t:
            check_keys(t, ("contact", "finger", "meta"), where, "beside 'contact' only finger and meta")
            touches.append(_parse_contact(t["contact"], f"{where}.contact"))
        else:
            touches.append(_parse_samples(t, where))
    check_touch_count(len(touches), classes, source)
    noise = parse_noise(obj["noise"], f"{source}.noise") if obj.get("noise") is not None else None
    if noise is None and scene is not None:
        noise = scene.noise
    limits.check_magnitudes(touches, noise, source)
    options = _parse_options({} if obj.get("options") is None else obj["options"], f"{source}.options")
    if "profile" in options:
        check_profile(options["profile"], f"{source}.options.profile")
    return Request(tuple(touches), scene, classes, noise, options, source)
