"""recognizer.solver's scalar curve kernels (kept for speed, see its docstring) against the
closed forms of recognizer.curves over each class's range: point, tangent angle, κ, κ_s and
speed agree to 1e-12 relative, near a semicubical's cusp, across a cubical parabola's
inflection, far out on a hyperbola's arms and a parabola's sides, and all round the closed
curves."""

import numpy as np
import pytest

from recognizer.curves import CURVES
from recognizer.solver import KERNELS


def _both_signs(lo: float, hi: float, n: int = 60) -> np.ndarray:
    m = np.geomspace(lo, hi, n)
    return np.concatenate((-m[::-1], [0.0], m))


ROUND = np.linspace(-np.pi, np.pi, 721)
#: per class: (parameter sets, t values); t = 0 left out where a quantity is infinite there
CASES = {
    "line": ([{}], _both_signs(1e-9, 1e4)),
    "circle": ([{"r": 1e-3}, {"r": 2.5}, {"r": 1e3}], ROUND),
    "ellipse": ([{"a": 3.0, "b": 0.7}, {"a": 1.0, "b": 1e-3}, {"a": 1e3, "b": 999.0}], ROUND),
    "parabola": ([{"a": 1e-3}, {"a": 0.4}, {"a": 1e3}], _both_signs(1e-9, 1e4)),
    "hyperbola": ([{"a": 1.3, "b": 0.2}, {"a": 1e-2, "b": 40.0}, {"a": 1e3, "b": 1e3}], _both_signs(1e-9, 25.0)),
    "cubical_parabola": ([{"a": -0.8, "c": 1.5}, {"a": 3e-4, "c": -0.9}, {"a": 2.0, "c": 0.0}, {"a": -1e-6, "c": 20.0}],
                         _both_signs(1e-10, 1e4)),
    "semicubical_parabola": ([{"a": 0.6, "b": -1.2}, {"a": 1.0, "b": 0.0}, {"a": 0.05, "b": 18.0}, {"a": 40.0, "b": 3.0}],
                             _both_signs(1e-8, 1e3)[np.r_[0:60, 61:121]]),
}
RTOL = 1e-12


def _close(got, want, scale) -> np.ndarray:
    return np.abs(got - want) <= RTOL * (np.abs(want) + scale)


@pytest.mark.parametrize("cls", list(CASES))
def test_kernels_agree_with_curves_over_the_range(cls):
    params_list, t = CASES[cls]
    for params in params_list:
        c = CURVES[cls](params)
        p = tuple(params[k] for k in c.param_names)
        x, y, phi, k, ks = c.frame(t)
        sp = c.speed(t)
        got = np.array([KERNELS[cls](p, float(ti)) for ti in t])
        # positions against the larger of the point's and the curve's own size (a coordinate
        # that crosses 0 keeps the absolute accuracy of its neighbours)
        size = np.hypot(x, y) + max(abs(v) for v in (*p, 1e-300))
        ok = {"x": _close(got[:, 0], x, size), "y": _close(got[:, 1], y, size),
              "phi": np.abs(np.remainder(got[:, 2] - phi + np.pi, 2 * np.pi) - np.pi) <= RTOL * (1 + np.abs(phi)),
              "kappa": _close(got[:, 3], k, 0.0) | (got[:, 3] == k),
              "kappa_s": _close(got[:, 4], ks, 0.0) | (got[:, 4] == ks),
              "speed": _close(got[:, 5], sp, 0.0)}
        for name, good in ok.items():
            bad = np.flatnonzero(~good)
            assert bad.size == 0, f"{cls} {params}: {name} differs at t = {t[bad[:3]]}"
        assert np.all(np.isfinite(got)), f"{cls} {params}: a kernel value is not finite"
