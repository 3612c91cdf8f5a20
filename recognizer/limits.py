"""What a recognition request may hold (docs/formats.md, "Limits"), checked before any work.

Sizes are checked on the decoded JSON before anything is converted (:func:`check_sizes`);
magnitudes after parsing, relative to the data's own scale (:func:`check_magnitudes`):
``L`` is the largest distance between two positions of the request (contacts and samples),
at least :data:`MIN_SCALE_MM`. A radius of curvature a billionth of ``L`` or a coordinate
beyond a kilometre is not something a jaw measures: such a
request is an input error (exit 2), never a recognition that silently ignores it.
"""

from __future__ import annotations

import math
from typing import Mapping, Sequence

import numpy as np

from tactile_common.errors import InputError

__all__ = ["MAX_TOUCHES", "MAX_SAMPLES_PER_TOUCH", "MAX_SAMPLES", "MAX_COORD_MM", "KAPPA_L", "KAPPA_S_L2",
           "MIN_SCALE_MM", "MIN_NOISE", "MAX_PHI_RAD", "MAX_TIMEOUT_S", "MAX_MISSED", "check_sizes",
           "check_magnitudes"]

MAX_TOUCHES = 64
MAX_SAMPLES_PER_TOUCH = 500
MAX_SAMPLES = 4000
#: |x|, |y|, |s| in mm (1 km): beyond it a float's resolution is no longer a tactile one
MAX_COORD_MM = 1e6
#: |phi| in rad: angles are wrapped by the recognizer; beyond this they lose precision
MAX_PHI_RAD = 1e4
#: |kappa|·L: a radius of curvature of L/1e9 (a 100 mm spread: 0.1 nm) is far below what
#: any touch resolves, yet far above the sharpest curve recognized exactly (an ellipse of
#: aspect 1:1000 touched at its vertices, kappa·L = 1.8e6)
KAPPA_L = 1e9
#: |kappa_s|·L²: every class touched at its extremes stays below 50 (tests' EXTREMES)
KAPPA_S_L2 = 1e12
MIN_SCALE_MM = 1e-3
#: the smallest nonzero entry of a noise factor (mm, rad): below it the whitening's weights
#: (its pseudo-inverse) leave double precision
MIN_NOISE = 1e-12
MAX_TIMEOUT_S = 3600.0
#: places in ``options.missed``: each is a touch sent, and a request holds at most as many touches
MAX_MISSED = MAX_TOUCHES


def check_sizes(raw_touches: Sequence, source: str) -> None:
    """Touch and sample counts of the undecoded touches list (before any conversion)."""
    if len(raw_touches) > MAX_TOUCHES:
        raise InputError(f"{source}: {len(raw_touches)} touches (at most {MAX_TOUCHES} per request)")
    total = 0
    for i, t in enumerate(raw_touches):
        if not isinstance(t, Mapping):
            continue  # parse_request names the wrong type
        n = max((len(t[k]) for k in ("phi", "x", "y", "s") if isinstance(t.get(k), list)), default=0)
        if n > MAX_SAMPLES_PER_TOUCH:
            raise InputError(f"{source}.touches[{i}]: {n} samples (at most {MAX_SAMPLES_PER_TOUCH} per touch)")
        total += n
    if total > MAX_SAMPLES:
        raise InputError(f"{source}: {total} samples in all (at most {MAX_SAMPLES} per request)")


def _scale(touches) -> float:
    xs, ys = [], []
    for t in touches:
        if hasattr(t, "kappa"):
            xs.append(np.array([t.x]))
            ys.append(np.array([t.y]))
        else:
            xs.append(t.x)
            ys.append(t.y)
    x, y = np.concatenate(xs), np.concatenate(ys)
    return max(math.hypot(float(np.ptp(x)), float(np.ptp(y))), MIN_SCALE_MM)


def _bound(value: float, limit: float, where: str, what: str) -> None:
    if abs(value) > limit:
        raise InputError(f"{where}: |{value:.6g}| is beyond {limit:.3g} ({what})")


def check_magnitudes(touches, noise, source: str) -> None:
    """Positions, angles, arc lengths, κ, κ_s and their σ within the limits, relative to
    the request's scale ``L`` (module docstring)."""
    if not touches:
        return
    for i, t in enumerate(touches):
        where = f"{source}.touches[{i}]"
        for k in ("x", "y", "s"):
            v = getattr(t, k, None)
            if v is not None and np.max(np.abs(v)) > MAX_COORD_MM:
                raise InputError(f"{where}.{k}: |{float(np.max(np.abs(v))):.6g}| mm is beyond {MAX_COORD_MM:g} mm")
        if np.max(np.abs(t.phi)) > MAX_PHI_RAD:
            raise InputError(f"{where}.phi: |{float(np.max(np.abs(t.phi))):.6g}| rad is beyond {MAX_PHI_RAD:g} rad")
    scale = _scale(touches)
    k_max, ks_max = KAPPA_L / scale, KAPPA_S_L2 / scale ** 2
    what = f"L = {scale:.4g} mm is the touches' spread"
    for i, t in enumerate(touches):
        if hasattr(t, "kappa"):
            where, (kappa, kappa_s, cov) = f"{source}.touches[{i}].contact", (t.kappa, t.kappa_s, t.cov)
        elif getattr(t, "curvature", None) is not None:  # a samples touch's measured κ, κ_s
            where, (kappa, kappa_s, cov) = f"{source}.touches[{i}].curvature", t.curvature
        else:
            continue
        _bound(kappa, k_max, f"{where}.kappa", f"1e9 / L: a radius of curvature below L/1e9; {what}")
        _bound(kappa_s, ks_max, f"{where}.kappa_s", f"1e12 / L²; {what}")
        _bound(math.sqrt(abs(cov[0, 0])), k_max, f"{where}: sigma of kappa", what)
        _bound(math.sqrt(abs(cov[1, 1])), ks_max, f"{where}: sigma of kappa_s", what)
    if noise is not None:
        _bound(noise.pos, MAX_COORD_MM, f"{source}.noise.pos", "mm")
        _bound(noise.along, MAX_COORD_MM, f"{source}.noise.pos_along", "mm")
        _bound(noise.phi, MAX_PHI_RAD, f"{source}.noise.phi", "rad")
