"""Profile-likelihood σ's (recognizer.intervals): far out on a hyperbola's arm the
linearized σ's were several times too small (the truth 5.3 σ away); the profile ones put it
within 3 σ. A well-determined answer keeps its linearized σ's."""

import numpy as np

from recognizer.touches import NoiseModel
from tools import bench_wide as B


def _answer(cls, i):
    region, shape, ts, _, rs = B.draw_case(cls, i, 1)
    direction = int(rs.choice([-1, 1]))
    touches, noise = B._touches(shape, ts, rs, direction)
    rec, _, _ = B._recognize(touches, NoiseModel(noise.phi, noise.pos))
    return region, shape, rec


def test_far_arm_hyperbola_sigmas_nearly_cover_the_truth():
    region, shape, rec = _answer("hyperbola", 25)  # linearized: a 2.17 ± 1.79, b 18.3 ± 4.4 (truth 11.6, 6.5)
    assert region == "out on an arm" and rec.cls == "hyperbola"
    z = {k: (rec.params[k] - v) / rec.uncertainty[k] for k, v in shape.params.items()}
    assert all(abs(v) <= 3.0 for v in z.values()), z  # linearized: a -5.3 σ, b 2.7 σ
    assert rec.uncertainty["a"] > 3.0 and rec.uncertainty["b"] > 4.5


def test_well_determined_answer_keeps_linearized_sigmas():
    region, shape, rec = _answer("hyperbola", 5)  # both arms: a, b to ~1 %
    assert rec.cls == "hyperbola"
    for k, v in shape.params.items():
        assert rec.uncertainty[k] < 0.02 * v
