"""One BLAS thread for a computation of small matrices (``one_blas_thread``).

The recognizer's matrices are small (a refinement's Jacobian is ~100 × 40, a contact fit's
~20 × 10), where OpenBLAS's threads only contend: measured on 2 cores, an SVD of 108 × 41
took 11 ms of CPU on two threads against 0.45 ms on one, and a 3-touch recognition with a
repeated touch 1.9 s against 0.6 s (tools.bench_wide --set wide, development seed 1). The
benchmarks' worker processes already started with ``OPENBLAS_NUM_THREADS=1``
(tools.bench.BLAS_ENV); a library cannot set that variable once NumPy is loaded, so the
limit is set and restored around the computation by threadpoolctl, which finds every BLAS
that NumPy and SciPy each load.
"""

from __future__ import annotations

from contextlib import contextmanager
from functools import lru_cache

__all__ = ["one_blas_thread"]


@lru_cache(maxsize=1)
def _controller():
    """The loaded BLAS libraries, inspected once (~6 ms of CPU); each limit costs ~0.1 ms."""
    from threadpoolctl import ThreadpoolController

    return ThreadpoolController()


@contextmanager
def one_blas_thread():
    """Run the body with every loaded BLAS on one thread; the caller's setting is restored."""
    with _controller().limit(limits=1, user_api="blas"):
        yield
