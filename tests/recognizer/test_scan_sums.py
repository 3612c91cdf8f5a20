"""The scans' sums over the touches' axis (recognizer.starts.sum_last, all_last): the same
bits as NumPy's reductions, signs of zero, infinities and every layout included."""

import numpy as np
import pytest

from recognizer.starts import SEQUENTIAL_SUM, all_last, sum_last


def _bits(a):
    a = np.ascontiguousarray(np.asarray(a, float))
    return np.where(np.isnan(a), 0.0, a).view(np.int64)


@pytest.mark.parametrize("n", range(1, SEQUENTIAL_SUM + 3))
@pytest.mark.parametrize("shape", [(), (1,), (4, 1), (75, 81)])
def test_sum_last_is_numpys_sum(n, shape):
    rng = np.random.default_rng(n)
    a = rng.standard_normal(shape + (n,)) * np.exp(8 * rng.standard_normal(shape + (n,)))
    a[rng.random(a.shape) < 0.3] = -0.0
    a[rng.random(a.shape) < 0.1] = 0.0
    a[rng.random(a.shape) < 0.02] = np.inf
    for arr in (a, np.asfortranarray(a), np.broadcast_to(a[..., :1], a.shape)):
        with np.errstate(invalid="ignore"):
            want, got = arr.sum(-1), sum_last(arr)
            want_k, got_k = arr.sum(-1, keepdims=True), sum_last(arr, keepdims=True)
        assert np.shape(got) == np.shape(want) and np.shape(got_k) == np.shape(want_k)
        assert np.array_equal(_bits(got), _bits(want)) and np.array_equal(_bits(got_k), _bits(want_k))
        assert np.array_equal(np.isnan(got), np.isnan(want))


def test_sum_last_differs_from_a_pairwise_order():
    """The order matters (the check above can fail): 1e16 + 1 + 1 left to right is 1e16,
    the last two first 1e16 + 2."""
    a = np.array([[1e16, 1.0, 1.0]])
    assert sum_last(a)[0] == 1e16 and a[:, 0] + (a[:, 1] + a[:, 2]) != sum_last(a)


@pytest.mark.parametrize("n", [1, 2, 3, 9])
def test_all_last_is_numpys_all(n):
    b = np.random.default_rng(n).random((75, 81, n)) < 0.9
    assert np.array_equal(all_last(b), np.all(b, axis=-1))
    assert np.array_equal(all_last(b[0, 0]), np.all(b[0, 0], axis=-1))
