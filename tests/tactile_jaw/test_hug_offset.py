"""A transit between rolling touches hugs the object only where the felt lines interpolate
(tactile_jaw.plan.hug_offset)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from hand_driver.config import load_config
from tactile_jaw.plan import APPROACH_MARGIN_MM, HUG_EXTEND_DEG, ObjectModel, hug_offset

CONFIG = load_config("config/jaw.yaml")
LEFT = CONFIG.finger("left")
CENTER, R = np.array([110.0, 0.0]), 20.0  # a disk in front of the jaw


def _support(psi: float) -> float:
    """The disk's support line offset for a pad of outward normal ψ: n·c − R."""
    return float(np.array([math.cos(psi), math.sin(psi)]) @ CENTER) - R


def _model(psis) -> ObjectModel:
    ws = CONFIG.workspace
    model = ObjectModel(ws.center_mm, ws.radius_mm)
    model.add(list(psis), [_support(p) for p in psis])
    return model


def test_nothing_felt_no_hugging():
    ws = CONFIG.workspace
    assert hug_offset(LEFT, ObjectModel(ws.center_mm, ws.radius_mm), -math.pi / 2) is None


def test_inside_the_felt_span_the_margin_outside_the_support_beyond_it_none():
    felt = np.radians(np.linspace(-100.0, -80.0, 9))
    model = _model(felt)
    for deg in (-95.0, -90.0, -80.0 - 0.5 * HUG_EXTEND_DEG):
        d = hug_offset(LEFT, model, math.radians(deg))
        # the disk's support is predicted within 0.5 mm; the line keeps the margin outside it
        assert d == pytest.approx(_support(math.radians(deg)) - APPROACH_MARGIN_MM, abs=0.5)
        assert d > model.edge(math.radians(deg))  # nearer than the workspace edge: the time saved
    assert hug_offset(LEFT, model, math.radians(-80.0 + HUG_EXTEND_DEG + 1.0)) is None
    assert hug_offset(LEFT, model, math.radians(-100.0 - HUG_EXTEND_DEG - 1.0)) is None
