"""A recognition runs its linear algebra on one BLAS thread (tactile_common.blas): its
matrices are small (a refinement's Jacobian is ~100 × 40), where OpenBLAS's threads only
contend: an SVD of 108 × 41 (four touches of 9 samples) took 11 ms of CPU on two threads
against 0.45 ms on one, and a 3-touch recognition on the widened set 1.9 s against 0.6 s."""

from threadpoolctl import threadpool_info, threadpool_limits

import recognizer.classify as classify
from recognizer import synth
from recognizer.classify import recognize
from recognizer.curves import CURVES, Pose
from recognizer.result import RecognizeOptions
from recognizer.touches import NoiseModel, Request, SamplesTouch


def _blas_threads() -> set[int]:
    return {lib["num_threads"] for lib in threadpool_info() if lib["user_api"] == "blas"}


def test_recognition_runs_on_one_blas_thread(monkeypatch):
    inside = []
    own = classify._recognize

    def spy(*args, **kwargs):
        inside.append(_blas_threads())
        return own(*args, **kwargs)

    monkeypatch.setattr(classify, "_recognize", spy)
    curve = CURVES["circle"]({"r": 20.0})
    shape = synth.Shape("circle", {"r": 20.0}, Pose(0.3, 100.0, 5.0), 40.0, (0.0, 1.5), curve)
    touches, _ = synth.sample_shape(shape, [0.2, 0.7, 1.2], 9, 0.8, 1, None, None, with_s=False)
    nm = NoiseModel(1.5e-3, 0.04)
    req = Request(tuple(SamplesTouch(t.phi, t.x, t.y, t.s) for t in touches), None, ("line", "circle"), nm, {})
    with threadpool_limits(limits=2, user_api="blas"):  # as on a 2-core machine, whatever this one has
        rec = recognize(req, RecognizeOptions(noise=nm, refine=True))
        after = _blas_threads()
    assert rec.cls == "circle"
    assert inside == [{1}]
    assert after == {2}  # the caller's setting restored
