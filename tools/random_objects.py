"""Random finite objects in front of the jaw, for the exploration benchmark.

``random_object(cls, rng)`` draws one scene ``object`` mapping (docs/formats.md, Scene) of a class:
the class's example object (``config/scenes/<class>.yaml``) scaled by a factor drawn from
``SIZE_RANGE`` (0.6–1.5, :func:`scaled`: the same shape, every length times k), turned by
any angle and moved anywhere in the workspace disk (config ``workspace``), kept only
where its curved part lies inside that disk and faces the fingers (:func:`faces_fingers`: one
pad's face can touch at least ``MIN_FACING_DEG`` of its outward normals, or lie flat on
a line, the contact inside the pad's middle 80 %, the pad clear of the rest of the object) and the object stays clear of the
opened jaw's pads. ``random_scene(cls, rng)`` wraps it in a scene with all seven classes
candidates.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from hand_driver import kinematics as kin
from hand_driver.config import JawConfig, load_config
from hand_driver.sim.physics import ContactWorld
from recognizer.curves import CURVES
from recognizer.scene import SceneObject, load_scene
from tactile_common.errors import InputError
from tactile_common.yamlfile import read_yaml
from tactile_jaw.plan import open_pose

__all__ = ["CLASSES", "SIZE_RANGE", "MIN_FACING_DEG", "example_object", "scaled", "facing_deg", "faces_fingers",
           "random_object", "random_scene"]

ROOT = Path(__file__).resolve().parents[1]
CLASSES: tuple[str, ...] = tuple(CURVES)
#: size of a random object relative to its class's example (every length times k)
SIZE_RANGE = (0.6, 1.5)
#: the least span (deg) of outward normals of the curved part that one pad can touch with
#: its face: a random pose is kept only above it (the example scenes offer 70–90°)
MIN_FACING_DEG = 50.0
#: points of the curved part at which :func:`facing_deg` tries a pad
FACING_POINTS = 41
#: a pad counts as touching with its face when the contact is this fraction of its
#: length from either end
PAD_MARGIN = 0.1
#: a random pose's attempts before giving up (a class whose objects never face the fingers)
MAX_TRIES = 2000


def example_object(cls: str, root: Path = ROOT) -> dict:
    """The ``object`` mapping of the class's example scene ``config/scenes/<cls>.yaml``."""
    raw = read_yaml(root / "config" / "scenes" / f"{cls}.yaml", "scene")
    return dict(raw["object"])


def scaled(raw: dict, k: float) -> dict:
    """The object mapping ``raw`` enlarged k times about its canonical origin (the pose
    unchanged): parameters, extent and closure of the same shape, every length times k."""
    if not k > 0:
        raise InputError(f"scale: must be > 0, got {k}")
    cls, params = raw["class"], dict(raw.get("params") or {})
    t_scale = 1.0
    if cls in ("circle", "ellipse", "parabola", "hyperbola"):
        params = {n: v * k for n, v in params.items()}
    elif cls == "cubical_parabola":  # (t, a t³ + c t) × k: t' = k t, a' = a / k²
        params, t_scale = {"a": params["a"] / k**2, "c": params["c"]}, k
    elif cls == "semicubical_parabola":  # (t², a t³ + b t²) × k: t' = √k t, a' = a / √k
        params, t_scale = {"a": params["a"] / math.sqrt(k), "b": params["b"]}, math.sqrt(k)
    else:  # line: (t, 0) × k
        t_scale = k
    out = {**raw, "params": params}
    if raw.get("extent") is not None:
        out["extent"] = [float(t) * t_scale for t in raw["extent"]]
    if raw.get("closure") is not None:
        out["closure"] = [[float(x) * k, float(y) * k] for x, y in raw["closure"]]
    return out


def facing_deg(config: JawConfig, obj: SceneObject, q_open: np.ndarray | None = None) -> dict[str, float]:
    """Per finger, the widest contiguous span (deg) of the curved part's outward normals
    at which the finger's pad can lie tangent to it (NaN: at none): IK within the joint
    limits, the contact within the pad's middle, the pad (0.02 mm off the boundary) not
    penetrating the object anywhere else. The other finger stays opened (``q_open``)."""
    q_open = open_pose(config) if q_open is None else q_open
    world = ContactWorld(config, obj)
    curve = obj.curve()
    lo, hi = obj.extent if obj.extent is not None else curve.t_period
    t = np.linspace(lo, hi, FACING_POINTS)
    x, y = obj.pose.apply(*curve.point(t))
    normal = np.unwrap(np.asarray(curve.tangent_angle(t)) + obj.pose.theta
                       + (math.pi / 2 if obj.side == "right" else -math.pi / 2))
    out = {}
    for i, finger in enumerate(config.fingers):
        ok = [_pad_fits(world, finger, i, q_open, float(x[k]), float(y[k]), float(normal[k]) + math.pi)
              for k in range(len(t))]
        if not any(ok):
            out[finger.name] = math.nan  # nothing of the curved part is touchable
            continue
        best, start = 0.0, None
        for k, good in enumerate(ok + [False]):
            if good and start is None:
                start = k
            elif not good and start is not None:
                best = max(best, abs(math.degrees(normal[k - 1] - normal[start])))
                start = None
        out[finger.name] = best
    return out


def faces_fingers(config: JawConfig, obj: SceneObject, q_open: np.ndarray | None = None) -> bool:
    """Does the curved part face a finger: one pad can touch ``MIN_FACING_DEG`` of its
    normals, or, for a line (a single normal), lie flat on it?"""
    spans = [v for v in facing_deg(config, obj, q_open).values() if not math.isnan(v)]
    if obj.cls == "line":
        return bool(spans)
    return bool(spans) and max(spans) >= MIN_FACING_DEG


def _pad_fits(world: ContactWorld, finger, index: int, q_open: np.ndarray, x: float, y: float, psi: float) -> bool:
    n = kin.unit(psi)
    p = np.array([x, y]) - 0.02 * n  # just off the boundary: touching, not penetrating
    length = finger.pad.length_mm
    for q in kin.ik_line_solutions(finger, psi, float(n @ p)):
        if not kin.within_limits(finger.joints, q, 0.0):
            continue
        if not PAD_MARGIN * length <= float(kin.finger_pad_line(finger, q).pad_coordinate(p)) <= (1 - PAD_MARGIN) * length:
            continue
        qq = q_open.copy()
        qq[2 * index:2 * index + 2] = q
        if not world.penetrates(qq, [index]):
            return True
    return False


def random_object(cls: str, rng: np.random.Generator, config: JawConfig | None = None) -> tuple[dict, float]:
    """One random object of class ``cls`` (module docstring): its scene ``object`` mapping
    and its size relative to the example."""
    config = config or load_config(ROOT / "config" / "jaw.yaml")
    q_open = open_pose(config)
    base = example_object(cls)
    (cx, cy), radius = config.workspace.center_mm, config.workspace.radius_mm
    for _ in range(MAX_TRIES):
        k = float(rng.uniform(*SIZE_RANGE))
        r, a = radius * math.sqrt(float(rng.uniform())), float(rng.uniform(-math.pi, math.pi))
        theta = float(rng.uniform(-math.pi, math.pi))
        raw = scaled(base, k)
        raw["pose"] = _pose_with_anchor_at(raw, theta, (cx + r * math.cos(a), cy + r * math.sin(a)))
        obj = load_scene({"object": raw}).object
        if not _curve_in_disk(obj, (cx, cy), radius) or ContactWorld(config, obj).penetrates(q_open):
            continue
        if faces_fingers(config, obj, q_open):
            return raw, k
    raise RuntimeError(f"random_object: no {cls} facing the fingers in {MAX_TRIES} tries")


def _curve_in_disk(obj: SceneObject, center: tuple[float, float], radius: float) -> bool:
    curve = obj.curve()
    lo, hi = obj.extent if obj.extent is not None else curve.t_period
    x, y = obj.pose.apply(*curve.point(np.linspace(lo, hi, FACING_POINTS)))
    return bool(np.all(np.hypot(x - center[0], y - center[1]) <= radius))


def _pose_with_anchor_at(raw: dict, theta: float, at: tuple[float, float]) -> dict:
    """The pose turning the object by ``theta`` with the middle of its curved part at ``at``."""
    obj = load_scene({"object": {**raw, "pose": {"theta": 0.0, "x": 0.0, "y": 0.0}}}).object
    curve = obj.curve()
    lo, hi = obj.extent if obj.extent is not None else (0.0, 0.0)
    mx, my = (float(v) for v in curve.point(0.5 * (lo + hi)))
    if obj.extent is None:  # a whole closed curve: its centre
        mx, my = 0.0, 0.0
    c, s = math.cos(theta), math.sin(theta)
    return {"theta": theta, "x": at[0] - (c * mx - s * my), "y": at[1] - (s * mx + c * my)}


def random_scene(cls: str, rng: np.random.Generator, config: JawConfig | None = None, name: str = "random") -> dict:
    """A scene mapping: a :func:`random_object` of ``cls``, all seven classes candidates."""
    obj, _ = random_object(cls, rng, config)
    return {"name": name, "classes": list(CLASSES), "object": obj}
