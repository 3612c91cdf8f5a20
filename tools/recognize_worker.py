"""Recognition under a deadline: the numerics run in a worker process that is killed when a
request takes longer than its ``options.timeout_s`` (default :data:`DEFAULT_TIMEOUT_S`).

Why a process: the recognizer's time goes to numpy/LAPACK calls that no signal or flag
interrupts, and a cooperative deadline would need checks threaded through every loop of
the recognizer. Killing a forked worker cuts off anything, frees its memory at once, and
the next request gets a fresh worker (forked from this process, which has already imported
the recognizer). The worker's address space is capped (:data:`WORKER_MEMORY`
above what it inherits), so an allocation no input limit foresaw is a ``MemoryError``
answer, not a machine out of memory. Overhead per request: one pickled request and answer
over a pipe: 0.6 ms for 3 exact contacts (1.4 against 0.84 ms in-process, best
of 300) and 1.0 ms for 4 samples-touches (9.8 against 8.9 ms); a fresh worker after a
timeout costs ~0.1 s. Measured on the shared 2-core machine, load ~12.

The parent validates (recognizer.touches.parse_request) before anything is sent; the worker
only computes. Every failure comes back as :class:`InputError` with one line.
"""

from __future__ import annotations

import json
import multiprocessing
import os
import resource
import signal
from typing import Any

from tactile_common.errors import InputError

__all__ = ["Worker", "DEFAULT_TIMEOUT_S", "WORKER_MEMORY"]

#: the slowest valid requests measured (docs/benchmarks.md#recognition-time): 1.7 s CPU (8
#: semicubical touches of 15 samples, accurate), ≤ 0.8 s CPU for bench_fuzz's valid requests;
#: on 2 cores at load 5 that is ~4 s of wall time, and 7–9 s was seen at load 16–19 for
#: 0.6–0.8 s CPU: 10 s left too little margin
DEFAULT_TIMEOUT_S = 30.0
WORKER_MEMORY = 2 * 2 ** 30
_CTX = multiprocessing.get_context("fork")


def _vm_size() -> int:
    try:
        with open("/proc/self/statm") as fh:
            return int(fh.read().split()[0]) * os.sysconf("SC_PAGE_SIZE")
    except (OSError, ValueError):
        return 0


def _serve(conn, parent_end) -> None:
    """The worker's loop: (request, options) in, ("ok", answer) or ("error", line) out;
    ends when the parent closes its end (EOF)."""
    from recognizer.classify import recognize

    parent_end.close()  # the fork's copy: holding it open would hide the parent's EOF
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # the parent answers Ctrl-C; we end on EOF
    vm = _vm_size()
    if vm:
        try:
            resource.setrlimit(resource.RLIMIT_AS, (vm + WORKER_MEMORY, resource.RLIM_INFINITY))
        except (ValueError, OSError):
            pass
    while True:
        try:
            request, options = conn.recv()
        except (EOFError, OSError):
            return
        try:
            answer = recognize(request, options).to_json()
            json.dumps(answer, allow_nan=False)
            reply = ("ok", answer)
        except InputError as exc:
            reply = ("error", str(exc))
        except MemoryError:
            reply = ("error", f"{request.source}: cannot recognize (out of memory: "
                              f"over {WORKER_MEMORY / 2 ** 30:g} GiB)")
        except Exception as exc:  # numerics on valid input: an answer, never a dead service
            reply = ("error", f"{request.source}: cannot recognize ({type(exc).__name__}: "
                              f"{str(exc).splitlines()[0][:200] if str(exc) else ''})")
        conn.send(reply)


class Worker:
    """One recognition worker process, restarted after a timeout or a death; use as a
    context manager (the worker ends with it)."""

    def __init__(self) -> None:
        self._proc = None
        self._conn = None

    def _start(self) -> None:
        parent, child = _CTX.Pipe()
        self._proc = _CTX.Process(target=_serve, args=(child, parent), daemon=True, name="tactile-recognize-worker")
        self._proc.start()
        child.close()
        self._conn = parent

    def _stop(self) -> None:
        if self._proc is not None:
            self._proc.kill()
            self._proc.join()
            self._conn.close()
        self._proc = self._conn = None

    def recognize(self, request, options, timeout_s: float | None = None) -> dict[str, Any]:
        """The recognition's JSON, or :class:`InputError` after ``timeout_s`` (default
        the request's ``options.timeout_s``, else :data:`DEFAULT_TIMEOUT_S`)."""
        timeout = timeout_s or request.options.get("timeout_s") or DEFAULT_TIMEOUT_S
        if self._proc is None or not self._proc.is_alive():
            self._stop()
            self._start()
        try:
            self._conn.send((request, options))
            ready = self._conn.poll(timeout)
            reply = self._conn.recv() if ready else None
        except (EOFError, OSError):
            code = self._proc.exitcode
            self._stop()
            raise InputError(f"{request.source}: cannot recognize (the worker died, exit {code})") from None
        if reply is None:
            self._stop()
            raise InputError(f"{request.source}: recognition cut off after {timeout:g} s (options.timeout_s)")
        kind, value = reply
        if kind != "ok":
            raise InputError(value)
        return value

    def close(self) -> None:
        if self._conn is not None:
            self._conn.close()  # the worker reads EOF and returns
            self._proc.join(timeout=1.0)
        self._stop()

    def __enter__(self) -> "Worker":
        return self

    def __exit__(self, *exc) -> None:
        self.close()
