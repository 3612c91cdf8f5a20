"""The benchmark's random finite objects: scaling keeps the shape (every boundary point k
times farther from the canonical origin), and every drawn object is a valid scene object
of its class, 0.6–1.5 times its example, inside the workspace, clear of the opened jaw,
its curved part facing a finger; the same seed draws the same objects."""

from __future__ import annotations

import math

import numpy as np
import pytest

from hand_driver.config import load_config
from hand_driver.sim.physics import ContactWorld
from recognizer.scene import load_scene
from tactile_jaw.plan import open_pose
from tools.random_objects import (CLASSES, MIN_FACING_DEG, SIZE_RANGE, example_object, faces_fingers, facing_deg,
                                  random_object, random_scene, scaled)

CFG = load_config("config/jaw.yaml")


@pytest.mark.parametrize("cls", CLASSES)
def test_scaled_is_the_same_shape_k_times_larger(cls):
    raw = example_object(cls)
    k = 1.37
    small = load_scene({"object": {**raw, "pose": {"theta": 0.0, "x": 0.0, "y": 0.0}}}).object
    big = load_scene({"object": {**scaled(raw, k), "pose": {"theta": 0.0, "x": 0.0, "y": 0.0}}}).object
    if small.finite:
        xs, ys = small.outline(samples=201, frame="canonical")
        xb, yb = big.outline(samples=201, frame="canonical")
    else:  # a whole closed curve: the same parameter t
        t = np.linspace(-math.pi, math.pi, 201)
        (xs, ys), (xb, yb) = small.curve().point(t), big.curve().point(t)
    assert np.allclose(xb, k * xs, rtol=1e-12, atol=1e-9) and np.allclose(yb, k * ys, rtol=1e-12, atol=1e-9)
    assert big.side == small.side


def test_example_scenes_face_the_fingers():
    q_open = open_pose(CFG)
    for cls in CLASSES:
        obj = load_scene(f"config/scenes/{cls}.yaml").object
        assert obj.cls == cls and not ContactWorld(CFG, obj).penetrates(q_open)
        spans = facing_deg(CFG, obj, q_open)
        assert max(spans.values()) >= MIN_FACING_DEG + 10.0 if cls != "line" else spans["left"] == 0.0, cls


def test_random_objects_are_valid_and_face_the_fingers():
    rng = np.random.default_rng(7)
    q_open = open_pose(CFG)
    (cx, cy), radius = CFG.workspace.center_mm, CFG.workspace.radius_mm
    for cls in CLASSES:
        raw, k = random_object(cls, rng, CFG)
        assert SIZE_RANGE[0] <= k <= SIZE_RANGE[1]
        obj = load_scene({"object": raw}).object
        assert obj.cls == cls and (obj.finite or cls in ("circle", "ellipse"))
        assert not ContactWorld(CFG, obj).penetrates(q_open)
        assert faces_fingers(CFG, obj, q_open)
        curve = obj.curve()
        lo, hi = obj.extent if obj.finite else curve.t_period
        x, y = obj.pose.apply(*curve.point(np.linspace(lo, hi, 50)))
        assert np.all(np.hypot(x - cx, y - cy) <= radius + 1e-9)
    a = random_scene("parabola", np.random.default_rng(3), CFG)
    b = random_scene("parabola", np.random.default_rng(3), CFG)
    assert a == b and a["classes"] == list(CLASSES)


@pytest.mark.parametrize("cls", CLASSES)
def test_example_scenes_stay_reachable_moved_turned_resized(cls):
    """Each example moved 5 mm, turned 6° and resized 10 % (the corners of that box) stays
    clear of the opened jaw and keeps its curved part facing a finger (a line: touchable flat)."""
    q_open = open_pose(CFG)
    raw = example_object(cls)
    pose = raw["pose"]
    theta = pose.get("theta", math.radians(pose.get("theta_deg", 0.0)))
    for dx, dy, dth, k in [(5, 5, 6, 1.1), (-5, -5, -6, 0.9), (5, -5, -6, 1.1), (-5, 5, 6, 0.9),
                           (5, 5, -6, 0.9), (-5, -5, 6, 1.1)]:
        moved = {**scaled(raw, k), "pose": {"theta": theta + math.radians(dth), "x": pose["x"] + dx, "y": pose["y"] + dy}}
        obj = load_scene({"object": moved}).object
        assert not ContactWorld(CFG, obj).penetrates(q_open), (dx, dy, dth, k)
        spans = [v for v in facing_deg(CFG, obj, q_open).values() if not math.isnan(v)]
        assert spans and (cls == "line" or max(spans) >= 40.0), (dx, dy, dth, k, spans)
