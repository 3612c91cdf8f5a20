"""Scenes (CONTRACTS §4): which classes may be answered, and the object the emulator shows.

``load_scene(path_or_mapping, base_dir=None) -> Scene`` validates everything in one place;
bad input raises a one-line :class:`InputError` naming the file and key.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Mapping

from recognizer.curves import CURVES, DEFAULT_SIDE, Pose, validate_params
from tactile_common.errors import InputError
from recognizer.touches import NoiseModel, parse_noise
from tactile_common.yamlfile import read_yaml

__all__ = ["Scene", "SceneObject", "load_scene", "ALL_CLASSES"]

ALL_CLASSES: tuple[str, ...] = tuple(CURVES)
_TOP_KEYS = {"name", "classes", "object", "profile", "noise", "description"}
_OBJECT_KEYS = {"class", "params", "pose", "side"}
_POSE_KEYS = {"theta", "theta_deg", "x", "y"}


@dataclass(frozen=True)
class SceneObject:
    """The object in front of the jaw: a canonical curve placed by ``pose``; the solid
    lies on ``side`` ('left' or 'right') of the curve traversed in increasing t."""

    cls: str
    params: dict
    pose: Pose
    side: str

    def curve(self):
        return CURVES[self.cls](self.params)


@dataclass(frozen=True)
class Scene:
    name: str
    classes: tuple[str, ...] = ALL_CLASSES
    object: SceneObject | None = None
    profile: str | None = None
    noise: NoiseModel | None = None
    source: str = "<inline>"
    extra: dict = field(default_factory=dict)


def _num(value, where: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise InputError(f"{where}: must be a finite number, got {value!r}")
    return float(value)


def _parse_pose(raw, where: str) -> Pose:
    if raw is None:
        return Pose()
    if not isinstance(raw, Mapping):
        raise InputError(f"{where}: must be a mapping with theta (or theta_deg), x, y")
    extra = sorted(map(str, set(raw) - _POSE_KEYS))
    if extra:
        raise InputError(f"{where}: unknown key(s) {', '.join(extra)}; allowed: theta, theta_deg, x, y")
    if "theta" in raw and "theta_deg" in raw:
        raise InputError(f"{where}: give theta or theta_deg, not both")
    theta = _num(raw["theta"], f"{where}.theta") if "theta" in raw else 0.0
    if "theta_deg" in raw:
        theta = math.radians(_num(raw["theta_deg"], f"{where}.theta_deg"))
    return Pose(theta, _num(raw.get("x", 0.0), f"{where}.x"), _num(raw.get("y", 0.0), f"{where}.y"))


def _parse_object(raw, where: str) -> SceneObject:
    if not isinstance(raw, Mapping):
        raise InputError(f"{where}: must be a mapping with class, params, pose")
    extra = sorted(map(str, set(raw) - _OBJECT_KEYS))
    if extra:
        raise InputError(f"{where}: unknown key(s) {', '.join(extra)}; allowed: {', '.join(sorted(_OBJECT_KEYS))}")
    if "class" not in raw:
        raise InputError(f"{where}.class: missing; allowed: {', '.join(CURVES)}")
    cls = raw["class"]
    if cls not in CURVES:
        raise InputError(f"{where}.class: unknown class {cls!r}; allowed: {', '.join(CURVES)}")
    params = validate_params(cls, raw.get("params", {}) or {}, f"{where}.params")
    side = raw.get("side", DEFAULT_SIDE[cls])
    if side not in ("left", "right"):
        raise InputError(f"{where}.side: must be 'left' or 'right', got {side!r}")
    return SceneObject(cls, params, _parse_pose(raw.get("pose"), f"{where}.pose"), side)


def _check_profile(profile, where: str) -> str | None:
    if profile is None:
        return None
    if not isinstance(profile, str):
        raise InputError(f"{where}: must be a profile name (string), got {profile!r}")
    try:
        from recognizer.profiles import PROFILES  # owned by the estimation area
    except ImportError:
        return profile
    if profile not in PROFILES:
        raise InputError(f"{where}: unknown profile {profile!r}; allowed: {', '.join(PROFILES)}")
    return profile


def load_scene(path_or_mapping, base_dir=None, source: str | None = None) -> Scene:
    """Load and validate a scene from a YAML path or an inline mapping.

    A relative path is tried against the current directory first, then ``base_dir``.
    ``source`` names where an inline mapping came from, for error messages.
    """
    if isinstance(path_or_mapping, Mapping):
        raw, source, stem = path_or_mapping, source or "scene", "inline"
    elif isinstance(path_or_mapping, (str, Path)):
        path = Path(path_or_mapping)
        if not path.is_absolute() and not path.exists() and base_dir is not None:
            path = Path(base_dir) / path
        source, stem = str(path), path.stem
        raw = read_yaml(path, "scene")
        if not isinstance(raw, Mapping):
            raise InputError(f"{source}: a scene must be a mapping with classes (and optionally object)")
    else:
        raise InputError(f"scene: must be a path or a mapping, got {type(path_or_mapping).__name__}")

    extra = sorted(map(str, set(raw) - _TOP_KEYS))
    if extra:
        raise InputError(f"{source}: unknown key(s) {', '.join(extra)}; allowed: {', '.join(sorted(_TOP_KEYS))}")
    name = raw.get("name", stem)
    if not isinstance(name, str) or not name:
        raise InputError(f"{source}: name must be a non-empty string")
    classes = raw.get("classes", list(ALL_CLASSES))
    if isinstance(classes, str) or not isinstance(classes, (list, tuple)) or not classes:
        raise InputError(f"{source}: classes must be a non-empty list from {', '.join(CURVES)}")
    for c in classes:
        if c not in CURVES:
            raise InputError(f"{source}: classes: unknown class {c!r}; allowed: {', '.join(CURVES)}")
    ordered = tuple(c for c in ALL_CLASSES if c in set(classes))
    obj = _parse_object(raw["object"], f"{source}: object") if raw.get("object") is not None else None
    profile = _check_profile(raw.get("profile"), f"{source}: profile")
    noise = parse_noise(raw["noise"], f"{source}: noise") if raw.get("noise") is not None else None
    desc = raw.get("description")
    return Scene(name, ordered, obj, profile, noise, source, {"description": desc} if desc else {})
