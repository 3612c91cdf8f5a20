"""Faults injected into the emulated bus on demand, at the byte level.

A :class:`FaultPlan` is shared by the test (or ``tactile sim`` user) and the bus thread;
each method arms a fault, counted in status packets: a status packet that would have
been sent is instead dropped (lost), sent with a wrong CRC (corrupt) or sent late
(delay). :meth:`FaultPlan.noise` makes a fraction of all status packets lost or corrupt
at random (seeded), as a noisy bus does. Instruction packets can be made to fail their CRC at the servo (the servo then
answers with status error 3, as a real one does). Hardware errors and a vanished
adapter are applied by :class:`hand_driver.sim.server.EmulatedBus` (``hardware_error``,
``vanish``).
"""

from __future__ import annotations

import random
import threading
from dataclasses import dataclass


@dataclass
class _Counter:
    remaining: int = 0
    ids: frozenset[int] | None = None  # None: any servo

    def take(self, dxl_id: int) -> bool:
        if self.remaining > 0 and (self.ids is None or dxl_id in self.ids):
            self.remaining -= 1
            return True
        return False


class FaultPlan:
    """Thread-safe counters of armed faults; every method returns self for chaining."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._reset()

    def _reset(self) -> None:
        self._drop = _Counter()
        self._corrupt = _Counter()
        self._bad_instruction = 0
        self._delay_s = 0.0
        self._delay_left = 0
        self._loss = self._garble = 0.0
        self._rng = random.Random(0)

    @staticmethod
    def _ids(ids) -> frozenset[int] | None:
        return None if ids is None else frozenset(int(i) for i in ids)

    def drop_status(self, n: int = 1, ids=None) -> "FaultPlan":
        """Lose the next n status packets (of the given servo ids, or any)."""
        with self._lock:
            self._drop = _Counter(int(n), self._ids(ids))
        return self

    def corrupt_status(self, n: int = 1, ids=None) -> "FaultPlan":
        """Flip the CRC of the next n status packets."""
        with self._lock:
            self._corrupt = _Counter(int(n), self._ids(ids))
        return self

    def corrupt_instruction(self, n: int = 1) -> "FaultPlan":
        """Make the next n instruction packets fail their CRC check at the servos."""
        with self._lock:
            self._bad_instruction = int(n)
        return self

    def delay(self, seconds: float, n: int = 1) -> "FaultPlan":
        """Send the next n status transmissions ``seconds`` late."""
        with self._lock:
            self._delay_s, self._delay_left = float(seconds), int(n)
        return self

    def noise(self, loss: float = 0.0, corrupt: float = 0.0, seed: int = 0) -> "FaultPlan":
        """From now on lose a fraction ``loss`` of the status packets and corrupt a fraction
        ``corrupt`` of the others, independently at random (``seed``)."""
        if not (0.0 <= loss <= 1.0 and 0.0 <= corrupt <= 1.0):
            raise ValueError("loss and corrupt are fractions in [0, 1]")
        with self._lock:
            self._loss, self._garble, self._rng = float(loss), float(corrupt), random.Random(seed)
        return self

    def clear(self) -> "FaultPlan":
        with self._lock:
            self._reset()
        return self

    # -- used by the bus thread ---------------------------------------------------------
    def take_drop(self, dxl_id: int) -> bool:
        with self._lock:
            return self._drop.take(dxl_id) or (self._loss > 0.0 and self._rng.random() < self._loss)

    def take_corrupt(self, dxl_id: int) -> bool:
        with self._lock:
            return self._corrupt.take(dxl_id) or (self._garble > 0.0 and self._rng.random() < self._garble)

    def take_bad_instruction(self) -> bool:
        with self._lock:
            if self._bad_instruction > 0:
                self._bad_instruction -= 1
                return True
            return False

    def take_delay(self) -> float:
        with self._lock:
            if self._delay_left > 0:
                self._delay_left -= 1
                return self._delay_s
            return 0.0
