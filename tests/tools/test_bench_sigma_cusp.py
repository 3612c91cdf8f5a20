"""tools.bench_sigma's samples of a semicubical never reach across its cusp (a pad cannot roll
through it), and there noise-free samples are answered exactly. Before, near the cusp and on
the far branch a 9-sample touch 2 % of L apart had samples on both branches (seed 167, trial 0
with --fresh at 1 mm: t −0.04 and 0.07 in one touch), and noise-free samples went
unclassified (χ² ~1e17 for every class)."""

from __future__ import annotations

import numpy as np
import pytest

from recognizer import synth
from recognizer.classify import recognize
from recognizer.curves import CURVES
from recognizer.profiles import PROFILES
from recognizer.result import RecognizeOptions
from recognizer.touches import NoiseModel, Request
from tools import bench_sigma as S

CLS = "semicubical_parabola"


def _touches(region: str, i: int, seed: int, k: int):
    params1, ts1, pose1, direction, _ = S.draw_case(CLS, region, i, seed, k)
    L = 10.0 ** k
    params, ts, pose = S.scaled(CLS, params1, ts1, pose1, L)
    ts = S.clear_of_cusp(CURVES[CLS](params), ts, synth.touch_reach(S.SAMPLES, S.SPACING * L))
    shape = synth.Shape(CLS, params, pose, L, (float(ts.min()), float(ts.max())), CURVES[CLS](params))
    touches, sample_ts = synth.sample_shape(shape, ts, S.SAMPLES, S.SPACING * L, direction, None, None, with_s=False)
    return params, touches, sample_ts


@pytest.mark.parametrize("region", list(S.REGIONS[CLS]))
def test_no_touch_reaches_across_the_cusp(region):
    for i in range(6):
        for k in (-4, 0, 5):
            _, _, sample_ts = _touches(region, i, 167, k)
            for t in sample_ts:
                assert np.all(t > 0) or np.all(t < 0), (region, i, k, t)


def test_noise_free_samples_clear_of_the_cusp_are_exact():
    params, touches, _ = _touches("far branch", 0, 167, 0)
    nm = NoiseModel(0.0, 0.0)
    rec = recognize(Request(tuple(touches), None, S.CLASSES, nm), RecognizeOptions(noise=nm, **PROFILES["balanced"].options()))
    assert rec.cls == CLS
    for name, v in params.items():
        assert abs(rec.params[name] - v) <= 1e-6 * max(abs(v), 1.0)
