"""Noise-free samples-touches (exact positions, angles and arc length; κ, κ_s estimated with
a truncation covariance): the invariant stage must not reject the right class. Hyperbolas
whose estimator's smoothed tangent angle was off by up to 1e-2 rad (judged at the 1e-7
floor) or whose closed-form start missed the exact positions by 1e5 σ were unclassified."""

from dataclasses import replace

import pytest

from recognizer.classify import recognize
from recognizer.result import RecognizeOptions
from recognizer.touches import NoiseModel, Request, SamplesTouch
from tools import bench

NOISE_FREE = replace(bench.Config("baseline", "baseline"), label="noise-free", noise=0.0)


@pytest.mark.parametrize("cls,i", [("hyperbola", 1), ("hyperbola", 2), ("hyperbola", 15), ("hyperbola", 16),
                                   ("ellipse", 1), ("ellipse", 2)])
def test_noise_free_samples_recognized_without_refine(cls, i):
    shape, touches, _ = bench._shape_and_touches(cls, i, 1, NOISE_FREE)
    nm = NoiseModel(0.0, 0.0)
    req = Request(tuple(SamplesTouch(t.phi, t.x, t.y, t.s) for t in touches), None, tuple(bench.CLASSES), nm)
    out = recognize(req, RecognizeOptions(refine=False, noise=nm))
    assert out.cls == cls, out.reason
    assert bench.rel_error(shape.params, out.params) < 1e-2  # invariants-only: estimator-limited
