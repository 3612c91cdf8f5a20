"""The benchmark's least-squares ellipse references (tools/bench.py) are right on exact
points, so the refinement-vs-least-squares ratio in docs/bench measures the methods."""

from __future__ import annotations

import numpy as np

from recognizer.curves import CURVES, Pose
from tools.bench import rel_error
from tools.ellipse_reference import _conic_axes, fit_ellipse_halir_flusser, fit_ellipse_reference


def _arc_points(a, b, t0, t1, n=27):
    t = np.linspace(t0, t1, n)
    x, y = Pose(0.7, 120.0, -15.0).apply(*CURVES["ellipse"]({"a": a, "b": b}).point(t))
    return np.asarray(x), np.asarray(y)


def test_halir_flusser_exact_on_a_partial_arc():
    x, y = _arc_points(30.0, 12.0, -0.4, 1.9)
    a, b = fit_ellipse_halir_flusser(x, y)
    assert abs(a - 30.0) < 1e-6 * 30 and abs(b - 12.0) < 1e-6 * 12


def test_reference_fit_exact_and_refuses_non_ellipses():
    x, y = _arc_points(25.0, 20.0, 0.0, 4.0)
    axes, which = fit_ellipse_reference(x, y)
    assert which and rel_error({"a": 25.0, "b": 20.0}, {"a": axes[0], "b": axes[1]}) < 1e-6
    # a hyperbola's conic has no real ellipse axes
    assert _conic_axes(np.array([1.0, 0.0, -1.0, 0.0, 0.0, -1.0]), 1.0) is None
