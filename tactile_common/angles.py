"""The one angle wrap of the project (recognizer and hand driver both use it)."""

from __future__ import annotations

import math

import numpy as np


def wrap_angle(a):
    """Angle(s) to [−π, π): a Python float stays a float (fast scalar path), anything else
    becomes a numpy array of the same shape."""
    if isinstance(a, float):
        return (a + math.pi) % math.tau - math.pi
    return np.remainder(np.asarray(a, dtype=float) + np.pi, 2.0 * np.pi) - np.pi
