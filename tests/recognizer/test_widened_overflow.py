"""A σ widened past 1e154 times its linearized one overflows its variance: the answer states it
undetermined without printing NumPy's overflow warning on the user's stderr."""

from __future__ import annotations

import warnings

import numpy as np

from recognizer import synth
from recognizer.classify import recognize
from recognizer.curves import CURVES
from recognizer.profiles import PROFILES
from recognizer.result import RecognizeOptions
from recognizer.touches import NoiseModel, Request
from tools import bench_sigma as S


def test_a_hyperbola_whose_a_walks_off_prints_no_overflow_warning():
    # tools.bench_sigma --fresh seed 1 (development), hyperbola far on an arm, trial 1, 1 mm:
    # `intervals._widened` scaled the covariance by σ_a's factor ~1e250 and NumPy warned
    cls, region, trial, seed, k = "hyperbola", "far arm", 1, 1, 0
    params1, ts1, pose1, direction, noise_seed = S.draw_case(cls, region, trial, seed, k)
    params, ts, pose = S.scaled(cls, params1, ts1, pose1, 1.0)
    shape = synth.Shape(cls, params, pose, 1.0, (float(ts.min()), float(ts.max())), CURVES[cls](params))
    noise = synth.SynthNoise(S.SPEC_PHI, S.SPEC_POS_FRAC)
    touches, _ = synth.sample_shape(shape, ts, S.SAMPLES, S.SPACING, direction, noise,
                                    np.random.default_rng(noise_seed), with_s=False)
    nm = NoiseModel(noise.phi, noise.pos)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        rec = recognize(Request(tuple(touches), None, S.CLASSES, nm),
                        RecognizeOptions(noise=nm, **PROFILES["balanced"].options()))
    assert rec.cls == cls
    assert not float(rec.uncertainty["a"]) < 1e100  # undetermined (∞ or beyond any scale), not small
    assert abs(rec.params["b"] - params["b"]) <= 3.0 * float(rec.uncertainty["b"])
