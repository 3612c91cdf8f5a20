"""The answer's shape–pose covariance (recognizer.result.Recognition.cov_pose): its diagonal the
stated σ's squared, in the answer's units (recognizer.scale_free.Unit.answer scales each shape
parameter by its power of length, x and y by U, θ not at all)."""

import numpy as np
import pytest

from recognizer import synth
from recognizer.classify import recognize
from recognizer.curves import CURVES, Pose
from recognizer.result import Ranked, Recognition, RecognizeOptions
from recognizer.scale_free import Unit
from recognizer.touches import NoiseModel, Request, SamplesTouch


def test_unit_answer_scales_the_covariance_by_each_entrys_dimension():
    cov = np.arange(1.0, 26.0).reshape(5, 5)
    rec = Recognition("semicubical_parabola", {"a": 0.3, "b": -1.2}, Pose(0.1, 0.5, -0.25), [],
                      uncertainty={"a": 1.0, "b": 1.0}, ranking=[Ranked("semicubical_parabola", True, 1.0, 5, 2.0, 0.5)],
                      cov_pose=cov)
    got = Unit(4.0, 100.0, 20.0).answer(rec).cov_pose
    f = np.array([4.0 ** -0.5, 1.0, 1.0, 4.0, 4.0])  # a ∝ U^-1/2, b dimensionless, θ, x, y
    assert got == pytest.approx(cov * np.outer(f, f), rel=1e-12)


def test_a_refined_answers_covariance_states_its_sigmas_in_mm():
    params = {"a": 10.0}
    shape = synth.Shape("parabola", params, Pose(0.3, 100.0, 5.0), 40.0, (-3.0, 3.0), CURVES["parabola"](params))
    touches, _ = synth.sample_shape(shape, [-1.0, -0.3, 0.4, 1.0], 9, 0.8, 1, None, None, with_s=False)
    nm = NoiseModel(1e-3, 0.004)
    req = Request(tuple(SamplesTouch(t.phi, t.x, t.y, t.s) for t in touches), None, ("line", "parabola"), nm, {})
    rec = recognize(req, RecognizeOptions(noise=nm, refine=True))
    assert rec.cls == "parabola"
    keys = ["a", "pose_theta", "pose_x", "pose_y"]
    stated = np.array([rec.uncertainty[k] for k in keys])
    assert np.sqrt(np.diag(rec.cov_pose)) == pytest.approx(stated, rel=1e-9)
    assert 1e-4 < stated[2] < 1.0  # x in mm (a σ of the order of the noise), not in units of U
