"""Extreme shapes under noise (tiny and huge, aspect 1:1000, near-circle and near-parabola
ellipses, contacts at vertices, inflections and near a cusp), with refinement: the answer
is a class with finite parameters or ``unclassified`` with a reason — never an exception
or a NaN."""

import json
import math
import warnings

import numpy as np
import pytest

from recognizer import synth
from recognizer.classify import recognize
from recognizer.curves import CURVES, Pose
from recognizer.result import RecognizeOptions
from recognizer.touches import NoiseModel, Request, SamplesTouch

CASES = [("ellipse", {"a": 1e3, "b": 1.0}, [0.0, 0.4, 1.5707963267948966]),
         ("ellipse", {"a": 2e-3, "b": 1e-3}, [-3.0, -1.0, 0.5]),
         ("ellipse", {"a": 50.0, "b": 49.99}, [-2.0, -0.3, 1.0]),
         ("ellipse", {"a": 5000.0, "b": 50.0}, [-0.01, 0.0, 0.01]),  # near a parabola at its vertex
         ("circle", {"r": 1e3}, [0.0, 0.01, 0.02]),
         ("circle", {"r": 1e-3}, [-2.0, 0.0, 2.0]),
         ("parabola", {"a": 1e-3}, [-0.5, 0.0, 2.0]),
         ("parabola", {"a": 1e3}, [-3.0, 0.0, 0.1]),
         ("hyperbola", {"a": 1.0, "b": 1e3}, [-1.0, 0.0, 2.0]),
         ("hyperbola", {"a": 1e3, "b": 1.0}, [-0.5, 0.0, 0.5]),
         ("cubical_parabola", {"a": 2.0, "c": -1.0}, [-1.0, 0.0, 0.8]),
         ("cubical_parabola", {"a": -1e-6, "c": 0.5}, [-700.0, 0.0, 900.0]),
         ("semicubical_parabola", {"a": 40.0, "b": 0.5}, [-0.02, 0.01, 0.03]),
         ("semicubical_parabola", {"a": 0.05, "b": -2.0}, [-20.0, 5.0, 30.0]),
         ("line", {}, [-1e3, 0.0, 2e3]),
         ("line", {}, [0.0, 1e-3, 3e-3])]


@pytest.mark.parametrize("cls,params,ts", CASES)
def test_noisy_extremes_answer_without_nan(cls, params, ts):
    rng = np.random.default_rng(5)
    c = CURVES[cls](params)
    pose = Pose(1.0, 100.0, -20.0)
    pts = np.array([c.point(t) for t in ts]).T
    size = max(float(np.ptp(pts[0])), float(np.ptp(pts[1])), 1e-9)
    noise = synth.SynthNoise(4 * 1.5e-3, 4e-3 * size)  # four times the standard noise
    touches = [synth.sample_touch(c, pose, t, 9, 0.02 * size / 3, 1, noise, rng, with_s=False)[0] for t in ts]
    nm = NoiseModel(noise.phi, noise.pos)
    req = Request(tuple(SamplesTouch(t.phi, t.x, t.y, t.s) for t in touches), None, tuple(CURVES), nm)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        out = recognize(req, RecognizeOptions(refine=True, noise=nm)).to_json()
    json.dumps(out, allow_nan=False)
    if out["class"] == "unclassified":
        assert out["reason"]
    else:
        assert out["params"].keys() == set(CURVES[out["class"]].param_names)
        assert all(v is not None and math.isfinite(v) for v in out["params"].values())
        assert all(r["chi2"] is not None for r in out["ranking"] if r["consistent"])
