"""Scenes (docs/formats.md, scene): which classes may be answered, and the object the emulator shows.

``load_scene(path_or_mapping, base_dir=None) -> Scene`` validates everything in one place;
bad input raises a one-line :class:`InputError` naming the file and key.

A finite object (docs/formats.md, scene) is the curve over ``extent`` = [t0, t1] closed by straight
segments from its end P(t1) through the ``closure`` corners (canonical frame, in order)
back to its start P(t0), or by the single chord P(t1) → P(t0). The closed boundary must be
simple: a closing segment that crosses or touches the curve or another segment is refused
(checked on the curve sampled at ``OUTLINE_SAMPLES`` points; the canonical curves never
cross themselves). The solid is the region the boundary encloses, so its ``side`` follows
from the boundary's orientation; a ``side`` that contradicts it is refused.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Mapping

import numpy as np

from recognizer.curves import CURVES, DEFAULT_SIDE, Pose, validate_params
from recognizer.noise import NoiseModel, parse_noise
from recognizer.profiles import PROFILES
from tactile_common.errors import InputError, check_keys
from tactile_common.inputs import check_path_text, finite_number
from tactile_common.yamlfile import read_yaml_located

__all__ = ["Scene", "SceneObject", "load_scene", "check_profile", "ALL_CLASSES"]

ALL_CLASSES: tuple[str, ...] = tuple(CURVES)
_TOP_KEYS = {"name", "classes", "object", "profile", "noise", "description"}
_OBJECT_KEYS = {"class", "params", "pose", "side", "extent", "closure"}
#: curve samples of a finite object's outline (the self-crossing check and plots)
OUTLINE_SAMPLES = 1025
_POSE_KEYS = ("theta", "theta_deg", "x", "y")


@dataclass(frozen=True)
class SceneObject:
    """The object in front of the jaw: a canonical curve placed by ``pose``; the solid
    lies on ``side`` ('left' or 'right') of the curve traversed in increasing t. A finite
    object has ``extent`` (t0, t1) and optionally ``closure`` corners (canonical frame)."""

    cls: str
    params: dict
    pose: Pose
    side: str
    extent: tuple[float, float] | None = None
    closure: tuple[tuple[float, float], ...] | None = None

    def curve(self):
        return CURVES[self.cls](self.params)

    @property
    def finite(self) -> bool:
        return self.extent is not None

    def corners(self) -> np.ndarray:
        """Canonical corners of a finite object's closing path, (k + 2, 2): P(t1), the
        closure points in order, P(t0)."""
        curve = self.curve()
        t0, t1 = self.extent
        ends = np.array(curve.point(np.array([t1, t0]))).T
        return np.vstack([ends[:1], np.array(self.closure or np.zeros((0, 2)), dtype=float).reshape(-1, 2), ends[1:]])

    def outline(self, samples: int = OUTLINE_SAMPLES, frame: str = "hand") -> tuple[np.ndarray, np.ndarray]:
        """The whole boundary of a finite object as a closed polyline (x, y): the curve
        from t0 to t1 at ``samples`` points, then the closing corners back to P(t0)."""
        if not self.finite:
            raise ValueError("outline: the object is unbounded (no extent)")
        x, y = self.curve().point(np.linspace(self.extent[0], self.extent[1], samples))
        c = self.corners()
        x, y = np.r_[x, c[1:, 0]], np.r_[y, c[1:, 1]]
        return self.pose.apply(x, y) if frame == "hand" else (x, y)


@dataclass(frozen=True)
class Scene:
    name: str
    classes: tuple[str, ...] = ALL_CLASSES
    object: SceneObject | None = None
    profile: str | None = None
    noise: NoiseModel | None = None
    source: str = "<inline>"
    extra: dict = field(default_factory=dict)


def _parse_pose(raw, where: str) -> Pose:
    """``{theta | theta_deg, x, y}``, every one required (a pose left out is not the palm)."""
    if not isinstance(raw, Mapping):
        raise InputError(f"{where}: must be a mapping with theta (or theta_deg), x, y")
    check_keys(raw, _POSE_KEYS, where)
    if "theta" in raw and "theta_deg" in raw:
        raise InputError(f"{where}: give theta or theta_deg, not both")
    values = {k: finite_number(v, f"{where}.{k}") for k, v in raw.items()}
    for key in ("x", "y"):
        if key not in raw:
            raise InputError(f"{where}.{key}: missing (required: theta or theta_deg, x, y)")
    if "theta" not in raw and "theta_deg" not in raw:
        raise InputError(f"{where}.theta: missing (required: theta or theta_deg, x, y)")
    theta = values["theta"] if "theta" in raw else math.radians(values["theta_deg"])
    return Pose(theta, values["x"], values["y"])


def _parse_object(raw, where: str) -> SceneObject:
    if not isinstance(raw, Mapping):
        raise InputError(f"{where}: must be a mapping with class, params, pose")
    check_keys(raw, sorted(_OBJECT_KEYS), where)
    if "class" not in raw:
        raise InputError(f"{where}.class: missing; allowed: {', '.join(CURVES)}")
    cls = raw["class"]
    if not isinstance(cls, str) or cls not in CURVES:
        raise InputError(f"{where}.class: unknown class {cls!r}; allowed: {', '.join(CURVES)}")
    params = validate_params(cls, raw.get("params", {}) or {}, f"{where}.params")
    side = raw.get("side", DEFAULT_SIDE[cls])
    if not isinstance(side, str) or side not in ("left", "right"):
        raise InputError(f"{where}.side: must be 'left' or 'right', got {side!r}")
    extent, closure = _parse_bounds(raw, cls, where)
    if "pose" not in raw:
        raise InputError(f"{where}.pose: missing (required: where the object is, {{theta, x, y}} in the hand frame)")
    pose = _parse_pose(raw["pose"], f"{where}.pose")
    if extent is None:
        return SceneObject(cls, params, pose, side)
    obj = SceneObject(cls, params, pose, side, extent, closure)
    enclosed = _check_simple(obj, where)
    if "side" in raw and side != enclosed:
        raise InputError(f"{where}.side: the closed boundary puts the solid on the {enclosed} of the curve "
                         f"(increasing t), not the {side}; drop side or set it to {enclosed}")
    return SceneObject(cls, params, pose, enclosed, extent, closure)


def _parse_bounds(raw, cls: str, where: str):
    """``extent`` (t0 < t1) and ``closure`` (a list of [x, y]) of an object, or None."""
    if CURVES[cls].t_period is not None:
        for key in ("extent", "closure"):
            if key in raw:
                raise InputError(f"{where}.{key}: a {cls} is whole (a closed curve); remove {key}")
        return None, None
    if raw.get("extent") is None:
        if raw.get("closure") is not None:
            raise InputError(f"{where}.closure: needs extent (the curve's parameter range [t0, t1])")
        return None, None
    ext = raw["extent"]
    if isinstance(ext, (str, Mapping)) or not isinstance(ext, (list, tuple)) or len(ext) != 2:
        raise InputError(f"{where}.extent: must be [t0, t1], the curve's parameter range, got {ext!r}")
    t0, t1 = (finite_number(v, f"{where}.extent") for v in ext)
    if not t0 < t1:
        raise InputError(f"{where}.extent: needs t0 < t1, got [{t0:g}, {t1:g}] (a reversed or empty range)")
    closure = raw.get("closure")
    if closure is None:
        if cls == "line":
            raise InputError(f"{where}.closure: a line needs closure corners (a chord would lie on the line itself)")
        return (t0, t1), None
    if isinstance(closure, (str, Mapping)) or not isinstance(closure, (list, tuple)) or not closure:
        raise InputError(f"{where}.closure: must be a non-empty list of [x, y] corners (omit it for the chord)")
    pts = []
    for k, p in enumerate(closure):
        if isinstance(p, (str, Mapping)) or not isinstance(p, (list, tuple)) or len(p) != 2:
            raise InputError(f"{where}.closure[{k}]: must be [x, y] (mm, canonical frame), got {p!r}")
        pts.append((finite_number(p[0], f"{where}.closure[{k}]"), finite_number(p[1], f"{where}.closure[{k}]")))
    return (t0, t1), tuple(pts)


def _check_simple(obj: SceneObject, where: str) -> str:
    """Refuse a finite object's boundary that crosses or touches itself or encloses no
    area; return the side ('left'/'right' of increasing t) on which it encloses the solid."""
    key = f"{where}.closure" if obj.closure else f"{where}.extent"
    x, y = obj.outline(frame="canonical")
    pts = np.stack([x, y], axis=-1)[:-1]  # the outline repeats P(t0) at its end
    scale = float(np.max(np.abs(pts - pts.mean(axis=0))))
    if not np.all(np.isfinite(pts)) or scale > 1e9:
        raise InputError(f"{where}.extent: the curve over the extent is too long to be an object")
    n_curve = OUTLINE_SAMPLES - 1  # curve polyline segments; the closing ones follow
    a, b = pts, np.roll(pts, -1, axis=0)  # segment i runs from pts[i] to pts[i + 1] (cyclic)
    length = np.hypot(*(b - a).T)
    eps = 1e-9 * scale
    for i in range(n_curve, len(a)):
        if length[i] <= eps:
            raise InputError(f"{key}: a closing segment has zero length (a corner repeats its neighbour)")
    area = 0.5 * float(np.sum(a[:, 0] * b[:, 1] - b[:, 0] * a[:, 1]))
    if abs(area) <= 1e-6 * scale * scale:
        raise InputError(f"{key}: the boundary encloses no area")
    n = len(a)
    for i in range(n_curve, n):  # each closing segment against every segment
        j = np.arange(n)
        hit = _segments_meet(a[i], b[i], a[j], b[j], eps)
        adjacent = (j == (i - 1) % n) | (j == (i + 1) % n)
        before = (j == (i - 1) % n)[:, None]  # directions away from the shared vertex
        d_i = np.where(before, b[i] - a[i], a[i] - b[i])
        d_j = np.where(before, a[j] - b[j], b[j] - a[j])
        fold = (np.abs(d_i[:, 0] * d_j[:, 1] - d_i[:, 1] * d_j[:, 0]) <= 1e-9 * np.hypot(*d_i.T) * np.hypot(*d_j.T)
                ) & (np.sum(d_i * d_j, axis=1) > 0)
        bad = np.where(adjacent, fold, hit) & (j != i)
        if bad.any():
            raise InputError(f"{key}: the boundary crosses itself (closing segment {i - n_curve + 1} meets "
                             f"{'the curve' if int(np.argmax(bad)) < n_curve else 'another closing segment'}); "
                             f"the solid must be bounded by one simple closed line")
    return "left" if area > 0 else "right"


def _segments_meet(p, q, a, b, eps: float) -> np.ndarray:
    """Do segment p–q and each segment a[k]–b[k] share a point (touching or overlapping)?"""
    def orient(o, u, v):
        return (u[..., 0] - o[..., 0]) * (v[..., 1] - o[..., 1]) - (u[..., 1] - o[..., 1]) * (v[..., 0] - o[..., 0])

    p, q = np.broadcast_to(p, a.shape), np.broadcast_to(q, a.shape)
    d1, d2 = orient(a, b, p), orient(a, b, q)
    d3, d4 = orient(p, q, a), orient(p, q, b)
    tol = eps * (np.hypot(*(b - a).T) + np.hypot(*(q - p).T))
    proper = (d1 * d2 <= 0) & (d3 * d4 <= 0) & ~((np.abs(d1) <= tol) & (np.abs(d2) <= tol))
    colinear = (np.abs(d1) <= tol) & (np.abs(d2) <= tol)
    axis = np.where((np.abs(b[:, 0] - a[:, 0]) + np.abs(q[:, 0] - p[:, 0]))
                    >= (np.abs(b[:, 1] - a[:, 1]) + np.abs(q[:, 1] - p[:, 1])), 0, 1)
    k = np.arange(len(a))
    lo1, hi1 = np.minimum(a[k, axis], b[k, axis]), np.maximum(a[k, axis], b[k, axis])
    lo2, hi2 = np.minimum(p[k, axis], q[k, axis]), np.maximum(p[k, axis], q[k, axis])
    overlap = colinear & (np.maximum(lo1, lo2) <= np.minimum(hi1, hi2) + eps)
    return proper | overlap


def check_profile(profile, where: str) -> str | None:
    """``profile`` when it names one of recognizer.profiles.PROFILES (or is None)."""
    if profile is None:
        return None
    if not isinstance(profile, str):
        raise InputError(f"{where}: must be a profile name (string), got {profile!r}")
    if profile not in PROFILES:
        raise InputError(f"{where}: unknown profile {profile!r}; allowed: {', '.join(PROFILES)}")
    return profile


def _exists(path: Path) -> bool:
    try:
        return path.exists()
    except OSError:  # e.g. a component over the file system's name limit: read_yaml says so
        return False


def load_scene(path_or_mapping, base_dir=None, source: str | None = None) -> Scene:
    """Load and validate a scene from a YAML path or an inline mapping.

    A relative path is tried against the current directory first, then ``base_dir``.
    ``source`` names where an inline mapping came from, for error messages.
    """
    if isinstance(path_or_mapping, Mapping):
        raw, source, stem = path_or_mapping, source or "scene", "inline"
    elif isinstance(path_or_mapping, (str, Path)):
        path = check_path_text(path_or_mapping, source or "scene")
        if not path.is_absolute() and not _exists(path) and base_dir is not None:
            path = Path(base_dir) / path
        source, stem = str(path), path.stem
        raw, lines = read_yaml_located(path, "scene")
        with lines.errors(source):
            return _parse_scene(raw, source, stem)
    else:
        raise InputError(f"scene: must be a path or a mapping, got {type(path_or_mapping).__name__}")
    return _parse_scene(raw, source, stem)


def _parse_scene(raw, source: str, stem: str) -> Scene:
    if not isinstance(raw, Mapping):
        raise InputError(f"{source}: a scene must be a mapping with classes (and optionally object)")

    check_keys(raw, sorted(_TOP_KEYS), source)
    name = raw.get("name", stem)
    if not isinstance(name, str) or not name:
        raise InputError(f"{source}: name must be a non-empty string")
    classes = raw.get("classes", list(ALL_CLASSES))
    if isinstance(classes, str) or not isinstance(classes, (list, tuple)) or not classes:
        raise InputError(f"{source}: classes must be a non-empty list from {', '.join(CURVES)}")
    for c in classes:
        if not isinstance(c, str) or c not in CURVES:
            raise InputError(f"{source}: classes: unknown class {c!r}; allowed: {', '.join(CURVES)}")
    ordered = tuple(c for c in ALL_CLASSES if c in set(classes))
    obj = _parse_object(raw["object"], f"{source}: object") if raw.get("object") is not None else None
    profile = check_profile(raw.get("profile"), f"{source}: profile")
    noise = parse_noise(raw["noise"], f"{source}: noise") if raw.get("noise") is not None else None
    desc = raw.get("description")
    return Scene(name, ordered, obj, profile, noise, source, {"description": desc} if desc else {})
