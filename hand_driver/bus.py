"""The Dynamixel bus behind a narrow interface, over the vendor SDK (Protocol 2.0).

(Over 400 lines on purpose: one class, whose opening, retry policy, cycle, single-servo
operations and scan all share one port, one lock and one retry state.)

``JointBus(port, baudrate, joints)`` is a context manager. Every address, size and unit is
the joint's model's (hand_driver.control_table: X-series or DYNAMIXEL-P; a jaw may mix
them). Opening it checks every servo (model, hardware error), writes Return Delay Time 0,
the model's guard mode (X-series with current sensing: current-based position, 5;
DYNAMIXEL-P: position, 3, where Goal Current still caps the current; XL430: position), the
joint limits as Min/Max Position Limit and the Current Limit, sets Goal Position to the
present position and turns torque on. Each cycle reads the block Moving .. Present
Position (X 122..135, P 570..583) of every joint in ONE sync read, or one fast sync read
when every servo answers it (probed at open), or one bulk read when the joints' models
keep it at different addresses; and writes every goal in ONE sync write (bulk write when
mixed) after checking all goals against the joint limits. SDK result codes become typed exceptions
(hand_driver.errors), transient ones (timeout, corrupt packet, CRC error at the servo)
are retried ``retries`` times. Torque goes off in ``__exit__`` and on SIGINT/SIGTERM,
best effort, never masking the error that is propagating.

Bus Watchdog (X 98, P 546): opening clears a watchdog error left by a host that died (and says
so), then arms every servo with ``watchdog_ms`` (the jaw config's ``bus.watchdog_ms``,
100 ms by default, 0: off). Each servo then stops by itself when no instruction packet
reaches it for that long, e.g. after ``kill -9`` of the host; every cycle's read and write
keeps it fed. After a longer pause of the host (a recognition between touches)
:meth:`JointBus.rearm_watchdog` clears the error before motion goes on (hand_driver.cycle
does it). A clean close disarms it with torque off.
"""

from __future__ import annotations

import logging
import math
import signal
import termios
import threading
import time
from dataclasses import dataclass
from typing import Callable, Sequence

import numpy as np

from hand_driver import units
from hand_driver.adapter import latency_warning
from hand_driver.config import BusConfig, JawConfig, JointConfig
from hand_driver.control_table import (
    ALERT_BIT,
    BAUD_RATES,
    COMMON_FIELDS,
    MODELS_BY_NUMBER,
    STATUS_ERRORS,
    ModelSpec,
    decode_field,
    encode_field,
)
from hand_driver.control_table import model as model_spec
from hand_driver.errors import (
    BusError,
    BusTimeout,
    CapabilityError,
    CrcError,
    JointLimitError,
    ModelMismatchError,
    PortError,
    ServoHardwareError,
    ServoStatusError,
)
from tactile_common.errors import InputError

log = logging.getLogger(__name__)

BROADCAST_ID = 0xFE
_ERR_CRC = 3
_REBOOT_WAIT_S = 3.0
#: how late an answer may come (the SDK's own status timeout: 2 × 16 ms latency + 2 ms)
_LATE_ANSWER_S = 0.034
#: scan: pings in a row without an answer before an id counts as absent (a lost reply
#: looks like an absent servo), and attempts of the read of a servo found
SCAN_SILENT_PINGS = 4
SCAN_READ_ATTEMPTS = 8
#: a pause of the host longer than this fraction of the Bus Watchdog's time re-arms it
#: before the next goals: a motion cycle (at most half the watchdog, see config) never
#: does, a recognition between touches does
WATCHDOG_REARM_FRACTION = 0.75


@dataclass(frozen=True)
class JointState:
    """One reading of every joint, in config order."""

    t_monotonic: float
    ticks: np.ndarray  # int64, Present Position
    current_ma: np.ndarray | None  # Present Current in mA; None if a joint cannot sense current
    moving: np.ndarray  # bool, Moving
    velocity_rad_s: np.ndarray  # Present Velocity


@dataclass(frozen=True)
class ServoInfo:
    id: int
    model_name: str
    model_number: int
    firmware: int
    baudrate: int


@dataclass(frozen=True)
class HardwareStatus:
    bits: int
    names: tuple[str, ...]


@dataclass
class BusStats:
    """Counters for benchmarks and logs."""

    transactions: int = 0
    retries: int = 0


def tick_limits(joint: JointConfig) -> tuple[int, int]:
    """(min_tick, max_tick): the whole ticks inside the joint's min_deg..max_deg about
    zero_tick along direction."""
    a, b = (float(units.deg_to_ticks_exact(deg, joint.zero_tick, joint.direction, joint.ticks_per_rev))
            for deg in (joint.min_deg, joint.max_deg))
    return int(math.ceil(min(a, b) - 1e-9)), int(math.floor(max(a, b) + 1e-9))


class JointBus:
    """Every joint of the jaw on one Dynamixel bus. See the module docstring."""

    def __init__(self, port: str, baudrate: int, joints: JawConfig | Sequence[JointConfig] = (), *, retries: int = 3,
                 fast_read: bool | None = None, on_reading: Callable[[JointState], None] | None = None,
                 timeout_s: float | None = None, handle_signals: bool = True, torque_on_open: bool = True,
                 watchdog_ms: int = BusConfig.watchdog_ms):
        self.port_name = str(port)
        self.baudrate = int(baudrate)
        self.joints = list(joints.joints if isinstance(joints, JawConfig) else joints)
        self.ids = [int(j.id) for j in self.joints]
        if len(set(self.ids)) != len(self.ids):
            raise InputError(f"joint ids must be unique, got {self.ids}")
        try:
            self.specs: list[ModelSpec] = [model_spec(j.model) for j in self.joints]
        except KeyError as exc:
            raise InputError(str(exc.args[0])) from None
        lim = [tick_limits(j) for j in self.joints]
        self.min_ticks = np.array([a for a, _ in lim], dtype=np.int64)
        self.max_ticks = np.array([b for _, b in lim], dtype=np.int64)
        self.retries = int(retries)
        self.fast_read_requested = fast_read
        self.fast_read = False
        self.on_reading = on_reading
        self.timeout_s = timeout_s
        self.handle_signals = handle_signals
        self.torque_on_open = torque_on_open
        if watchdog_ms < 0 or watchdog_ms % units.WATCHDOG_STEP_MS or watchdog_ms > 127 * units.WATCHDOG_STEP_MS:
            raise InputError(f"watchdog_ms {watchdog_ms} must be a multiple of {units.WATCHDOG_STEP_MS} in "
                             f"0..{127 * units.WATCHDOG_STEP_MS} (0: off)")
        self.watchdog_ms = int(watchdog_ms)
        self.stats = BusStats()
        self.firmware: dict[int, int] = {}
        self._lock = threading.RLock()
        self._port = None
        self._ph = None
        self._old_handlers: dict[int, object] = {}
        self._pending_alerts: list[int] = []  # servos whose last status had the alert bit
        self._vanished = False  # the serial port failed (adapter unplugged)
        self._last_io = 0.0  # time.monotonic() of the last transaction
        self.current_sensing = all(s.has_current_sensing for s in self.specs)
        blocks = {s.state_block() for s in self.specs}
        #: the joints' state blocks lie at one address (sync read), else a bulk read
        self.state_block = blocks.pop() if len(blocks) == 1 else None

    @classmethod
    def for_config(cls, config: JawConfig, port: str | None = None, **options) -> "JointBus":
        """The bus of a jaw config: its joints, baud rate, retries, status timeout and Bus Watchdog
        time; ``port`` (default the config's) and other keyword options as for the constructor."""
        options.setdefault("retries", config.bus.retries)
        options.setdefault("timeout_s", config.bus.timeout_s)
        options.setdefault("watchdog_ms", config.bus.watchdog_ms)
        return cls(port if port is not None else config.bus.port, config.bus.baudrate, config, **options)

    # -- opening and closing ----------------------------------------------------------------
    def __enter__(self) -> "JointBus":
        self.open()
        return self

    def __exit__(self, exc_type, exc, tb) -> None:
        self.close()

    def open(self) -> None:
        """Open the port and configure every joint (see module docstring)."""
        import dynamixel_sdk as sdk
        import serial

        timeout_ms = None if self.timeout_s is None else 1000.0 * self.timeout_s

        class _Port(sdk.PortHandler):
            def setPacketTimeout(self, packet_length):  # noqa: N802 - SDK name
                super().setPacketTimeout(packet_length)
                if timeout_ms is not None:
                    self.packet_timeout = self.tx_time_per_byte * packet_length + timeout_ms

        self._sdk = sdk
        self._serial_errors = (serial.SerialException, OSError, termios.error)
        port = _Port(self.port_name)
        if port.getCFlagBaud(self.baudrate) <= 0:
            usable = [b for b in sorted(BAUD_RATES) if port.getCFlagBaud(b) > 0]
            raise InputError(f"baud rate {self.baudrate} is not supported by the Dynamixel SDK; use one of "
                             f"{', '.join(map(str, usable))}")
        try:
            port.baudrate = self.baudrate
            port.openPort()
        except self._serial_errors as exc:
            raise PortError(f"cannot open serial port {self.port_name}: {exc}; is the adapter plugged in?") from None
        self._port, self._ph = port, sdk.PacketHandler(2.0)
        warning = latency_warning(self.port_name)
        if warning:
            log.warning("%s", warning)
        try:
            if self.joints:
                self._configure()
            self._install_signal_handlers()
        except BaseException:
            self.close()
            raise

    def close(self) -> None:
        """Torque off (best effort), restore signal handlers, close the port. Idempotent.
        A port that vanished is only closed: nothing reaches the servos any more (their
        watchdog stops them) and the PortError already said so, in one line."""
        if self._port is None:
            return
        try:
            if self.joints and not self._vanished:
                self._torque_off_best_effort()
        finally:
            self._restore_signal_handlers()
            try:
                self._port.closePort()
            except Exception as exc:  # closing a vanished port may fail; nothing to do
                log.debug("closing %s: %s", self.port_name, exc)
            self._port = None

    def _configure(self) -> None:
        for j, spec in zip(self.joints, self.specs):
            number = self.first_contact(f"ping of servo {j.id}", lambda i=j.id: self._ph.ping(self._port, i), j.id)[0]
            if number != spec.number:
                found = MODELS_BY_NUMBER.get(number)
                raise ModelMismatchError(
                    f"joint id {j.id} is configured as {spec.name} but the servo reports "
                    f"{found.name if found else 'model number'} ({number})")
            self.firmware[j.id] = self._read(j.id, spec.field("firmware_version"))
            hw = self._read(j.id, spec.field("hardware_error_status"))
            if hw:
                raise ServoHardwareError(j.id, hw, spec.decode_hardware_error(hw))
            if self._read(j.id, spec.field("bus_watchdog")) < 0:
                log.warning("servo %d: its Bus Watchdog had stopped it (the last host stopped talking to it "
                            "mid-run); cleared", j.id)
        self._sync_write_field("bus_watchdog", [0] * len(self.ids))  # clears a watchdog error
        self._sync_write_field("torque_enable", [0] * len(self.ids))
        for j, spec, lo, hi in zip(self.joints, self.specs, self.min_ticks, self.max_ticks):
            wanted = {"return_delay_time": 0, "operating_mode": spec.guard_mode,
                      "min_position_limit": int(lo), "max_position_limit": int(hi)}
            if spec.has_current_sensing:
                wanted["current_limit"] = self._current_limit_raw(j, spec)
            for name, value in wanted.items():  # EEPROM: write only what differs
                f = spec.field(name)
                if self._read(j.id, f) != value:
                    self._write(j.id, f, value)
        if self.current_sensing:
            self._sync_write_field("goal_current", [self._current_limit_raw(j, s)
                                                    for j, s in zip(self.joints, self.specs)])
        state = self._read_state_raw()
        self._sync_write_field("goal_position", np.clip(state.ticks, self.min_ticks, self.max_ticks))
        self._choose_read_mode()
        if self.torque_on_open:
            self.torque(True)
        self._arm_watchdog()

    def _arm_watchdog(self) -> None:
        if self.watchdog_ms:
            self._sync_write_field("bus_watchdog", [self.watchdog_ms // units.WATCHDOG_STEP_MS] * len(self.ids))

    def rearm_watchdog(self) -> None:
        """Clear a Bus Watchdog error (the host paused longer than ``watchdog_ms``: the
        servos stopped and refuse goals until cleared) and arm the watchdog again."""
        if self.watchdog_ms:
            self._sync_write_field("bus_watchdog", [0] * len(self.ids))
            self._arm_watchdog()

    @staticmethod
    def _current_limit_raw(joint: JointConfig, spec: ModelSpec) -> int:
        """The joint's current_limit_ma in raw units, capped at the model's Current Limit."""
        return min(units.ma_to_current(joint.current_limit_ma, spec), spec.current_limit_default)

    def _choose_read_mode(self) -> None:
        capable = all(s.fast_sync_read for s in self.specs) and self.state_block is not None
        if self.fast_read_requested is False or not capable:
            self.fast_read = False
            if self.fast_read_requested and not capable:
                raise CapabilityError("fast sync read requested but not every servo model supports it at one "
                                      "address")
            return
        self.fast_read = True
        try:  # asked for: every retry; automatic: one try, then sync read
            self._read_state_raw(attempts=None if self.fast_read_requested else 1)
        except (BusTimeout, CrcError) as exc:
            if self.fast_read_requested:
                raise BusError(f"fast sync read requested but the servos do not answer it: {exc}") from None
            log.info("fast sync read not answered (%s); using sync read", exc)
            self.fast_read = False

    # -- signals -----------------------------------------------------------------------------
    def _install_signal_handlers(self) -> None:
        if not self.handle_signals or threading.current_thread() is not threading.main_thread():
            return
        for sig in (signal.SIGINT, signal.SIGTERM):
            self._old_handlers[sig] = signal.signal(sig, self._on_signal)

    def _restore_signal_handlers(self) -> None:
        for sig, old in self._old_handlers.items():
            signal.signal(sig, old)
        self._old_handlers.clear()

    def _on_signal(self, signum, frame) -> None:
        self.emergency_torque_off()
        old = self._old_handlers.get(signum)
        if callable(old) and old is not signal.default_int_handler:
            old(signum, frame)
        if signum == signal.SIGINT:
            raise KeyboardInterrupt
        raise SystemExit(128 + signum)

    def emergency_torque_off(self) -> None:
        """One broadcast sync write of Torque Enable 0, usable from a signal handler."""
        if self._port is None or not self.joints:
            return
        try:
            self._port.is_using = False  # the interrupted transaction is abandoned
            self._write_field_raw("torque_enable", [0] * len(self.ids))
        except Exception as exc:
            log.warning("emergency torque off failed: %s", exc)

    def _torque_off_best_effort(self) -> None:
        try:
            self._port.is_using = False
            # broadcast: no status; each sent twice against a lost packet (the disarm too: the
            # clean-clone CI of session 23 once found the watchdog still armed 30 s after close)
            for name in ("torque_enable", "bus_watchdog") if self.watchdog_ms else ("torque_enable",):
                for _ in range(2):
                    self._write_field_raw(name, [0] * len(self.ids))
        except Exception as exc:  # never mask the error that is propagating
            log.warning("torque off on %s failed: %s", self.port_name, exc)

    # -- SDK result handling ---------------------------------------------------------------------
    def _check(self, result: int, error: int, what: str, dxl_id: int | None = None) -> None:
        sdk = self._sdk
        if result == sdk.COMM_SUCCESS:
            code = error & ~ALERT_BIT
            if code == _ERR_CRC:
                raise CrcError(f"{what}: servo {dxl_id} received a corrupt instruction packet")
            if code:
                raise ServoStatusError(dxl_id, code, STATUS_ERRORS.get(code, "unknown error"), what)
            return
        if result == sdk.COMM_RX_TIMEOUT:
            raise BusTimeout(f"{what}: no status packet (timeout)")
        if result == sdk.COMM_RX_CORRUPT:
            raise CrcError(f"{what}: corrupt status packet (CRC or length)")
        if result == sdk.COMM_PORT_BUSY:
            self._port.is_using = False
            raise BusTimeout(f"{what}: port busy")
        if result == sdk.COMM_TX_FAIL:
            raise PortError(f"{what}: could not transmit on {self.port_name}")
        raise BusError(f"{what}: {self._ph.getTxRxResult(result)} ({result})")

    def _attempt(self, what: str, fn: Callable, attempts: int | None = None):
        """Run fn with bounded retries of transient faults; serial errors become PortError.

        A success after a timeout may have taken the late answer to the timed-out attempt:
        the answer to the successful one may still come and would then pass for the answer
        to the next transaction (the SDK matches answers by servo ID only). So the input is
        left to settle for a status timeout and flushed before anything else is sent."""
        n = self.retries + 1 if attempts is None else attempts
        last: BusError | None = None
        timed_out = False
        with self._lock:
            if self._port is None:
                raise PortError(f"{what}: the bus on {self.port_name} is not open")
            for k in range(n):
                self.stats.transactions += 1
                self._last_io = time.monotonic()
                try:
                    out = fn()
                    if timed_out:
                        self._settle()
                    return out
                except (BusTimeout, CrcError) as exc:
                    last = exc
                    timed_out = timed_out or isinstance(exc, BusTimeout)
                    if k + 1 < n:
                        self.stats.retries += 1
                except self._serial_errors as exc:
                    self._vanished = True
                    stop = (f"; the servos stop by themselves within {self.watchdog_ms} ms (Bus Watchdog)"
                            if self.watchdog_ms and self.joints else "")
                    raise PortError(f"{what}: serial port {self.port_name} failed ({exc}); "
                                    f"adapter unplugged?{stop}") from None
        raise type(last)(f"{last} — gave up after {n} attempts")

    def _settle(self) -> None:
        """Let a late answer to a timed-out transaction arrive, then flush it (held lock)."""
        time.sleep(_LATE_ANSWER_S if self.timeout_s is None else max(_LATE_ANSWER_S, self.timeout_s))
        self._port.clearPort()

    def _call(self, what: str, fn: Callable, dxl_id: int | None = None):
        """An SDK TxRx call returning (..., result, error) with retries."""
        def once():
            out = fn()
            self._check(out[-2], out[-1], what, dxl_id)
            return out
        return self._attempt(what, once)

    def first_contact(self, what: str, fn: Callable, dxl_id: int):
        """A first transaction with servo ``dxl_id`` (:meth:`_call`); its timeout says what a
        silent bus usually is (no power, another baud rate or id) and the command that finds out."""
        try:
            return self._call(what, fn, dxl_id)
        except BusTimeout as exc:
            bauds = ",".join(str(b) for b in sorted(BAUD_RATES))
            raise BusTimeout(f"{exc}: nothing answers as servo {dxl_id} at {self.baudrate} baud on {self.port_name}; "
                             f"is the jaw powered, at this baud rate and id? `tactile scan --port {self.port_name} "
                             f"--baud {bauds}` lists the servos that answer and their baud rates "
                             f"(then set the jaw config's bus.baudrate and ids)") from None

    def _read(self, dxl_id: int, f) -> int:
        data = self._call(f"read of {f.name} from servo {dxl_id}",
                          lambda: self._ph.readTxRx(self._port, dxl_id, f.addr, f.size), dxl_id)[0]
        return decode_field(f, data)

    def _write(self, dxl_id: int, f, value: int) -> None:
        data = list(encode_field(f, value))
        self._call(f"write of {f.name}={value} to servo {dxl_id}",
                   lambda: self._ph.writeTxRx(self._port, dxl_id, f.addr, f.size, data), dxl_id)

    def _write_field_raw(self, name: str, values) -> None:
        """Item ``name`` of every joint (``values`` in joint order, each in its model's units),
        one packet, no retries."""
        fields = [s.field(name) for s in self.specs]
        self._write_joint_bytes(name, [f.addr for f in fields], [encode_field(f, v) for f, v in zip(fields, values)])

    def _write_joint_bytes(self, what: str, addrs: Sequence[int], blocks: Sequence[bytes]) -> None:
        """``blocks[k]`` at ``addrs[k]`` of servo ``ids[k]``: one sync write when every address
        and length agree (one model family), else one bulk write (a jaw mixing families)."""
        sdk = self._sdk
        if len(set(addrs)) == 1 and len({len(b) for b in blocks}) == 1:
            g = sdk.GroupSyncWrite(self._port, self._ph, addrs[0], len(blocks[0]))
            for i, b in zip(self.ids, blocks):
                g.addParam(i, list(b))
            kind = "sync"
        else:
            g = sdk.GroupBulkWrite(self._port, self._ph)
            for i, a, b in zip(self.ids, addrs, blocks):
                g.addParam(i, a, len(b), list(b))
            kind = "bulk"
        result = g.txPacket()
        if result != sdk.COMM_SUCCESS:
            self._check(result, 0, f"{kind} write of {what}")

    def _sync_write_field(self, name: str, values) -> None:
        values = list(values)
        self._attempt(f"write of {name}", lambda: self._write_field_raw(name, values))

    # -- the cycle ---------------------------------------------------------------------------
    def _read_state_raw(self, attempts: int | None = None) -> JointState:
        kind = "bulk" if self.state_block is None else "fast sync" if self.fast_read else "sync"
        what = f"{kind} read of servos {','.join(map(str, self.ids))}"
        blocks, errors = self._attempt(what, lambda: self._sync_read_once(what), attempts)
        t = time.monotonic()
        raw = [bytes(blocks[i]) for i in self.ids]

        def field(name: str) -> np.ndarray:
            out = []
            for b, s in zip(raw, self.specs):
                f = s.field(name)
                out.append(decode_field(f, b, f.addr - s.state_block()[0]))
            return np.array(out, dtype=np.int64)

        ticks = field("present_position")
        moving = field("moving").astype(bool)
        vel = np.array([units.velocity_to_rad_s(v, s) for v, s in zip(field("present_velocity"), self.specs)])
        current = (np.array([units.current_to_ma(c, s) for c, s in zip(field("present_current"), self.specs)])
                   if self.current_sensing else None)
        state = JointState(t, ticks, current, moving, vel)
        self._pending_alerts = [i for i in self.ids if errors[i] & ALERT_BIT]
        return state

    def _sync_read_once(self, what: str):
        sdk, ph, port = self._sdk, self._ph, self._port
        n = len(self.ids)
        if self.state_block is None:  # models of both families: one bulk read
            g = sdk.GroupBulkRead(port, ph)
            for i, s in zip(self.ids, self.specs):
                g.addParam(i, *s.state_block())
            lengths = [s.state_block()[1] for s in self.specs]
        else:
            g = sdk.GroupSyncRead(port, ph, *self.state_block)
            for i in self.ids:
                g.addParam(i)
            lengths = [self.state_block[1]] * n
        ln = lengths[0]
        blocks, errors = {}, {}
        if self.fast_read:
            self._check(g.fastSyncReadTxPacket(), 0, what)
            raw, result, _ = ph.fastSyncReadRx(port, BROADCAST_ID, (ln + 4) * n)
            self._check(result, 0, what)
            raw = bytes(raw)
            if len(raw) != (ln + 4) * n:
                raise CrcError(f"{what}: fast sync read status packet has the wrong length")
            for k in range(n):
                slot = raw[k * (ln + 4) : (k + 1) * (ln + 4)]
                err, dxl_id = slot[0], slot[1]
                if dxl_id not in self.ids or dxl_id in blocks:
                    raise CrcError(f"{what}: unexpected servo id {dxl_id} in fast sync read packet")
                self._check(sdk.COMM_SUCCESS, err, what, dxl_id)
                blocks[dxl_id], errors[dxl_id] = slot[2 : 2 + ln], err
        else:
            self._check(g.txPacket(), 0, what)
            for i, ln in zip(self.ids, lengths):
                data, result, err = ph.readRx(port, i, ln)
                self._check(result, err, what, i)
                if len(data) != ln:
                    raise CrcError(f"{what}: short status packet from servo {i}")
                blocks[i], errors[i] = data, err
        return blocks, errors

    def read_state(self) -> JointState:
        """Every joint's position, current, velocity and moving flag in one (fast) sync read.

        The reading goes to ``on_reading`` first; then, if a servo flagged a hardware error
        in its status, :class:`ServoHardwareError` is raised with the decoded bits.
        """
        with self._lock:
            state = self._read_state_raw()
            if self.on_reading is not None:
                self.on_reading(state)
            for i in self._pending_alerts:
                hw = self.read_hardware_error(i)
                raise ServoHardwareError(i, hw.bits, list(hw.names))
            return state

    def check_goal_ticks(self, ticks) -> np.ndarray:
        """The goals as an int array, or JointLimitError naming the first joint out of limits."""
        t = np.asarray(ticks)
        if t.shape != (len(self.ids),):
            raise InputError(f"expected {len(self.ids)} goal ticks (one per joint), got shape {t.shape}")
        if not np.all(np.isfinite(t.astype(float))):
            raise InputError(f"goal ticks must be finite numbers, got {t.tolist()}")
        ti = np.rint(t.astype(float)).astype(np.int64)
        for k, (v, lo, hi) in enumerate(zip(ti, self.min_ticks, self.max_ticks)):
            if not lo <= v <= hi:
                raise JointLimitError(f"joint {k} (servo id {self.ids[k]}): goal tick {v} outside its limits "
                                      f"{lo}..{hi}; nothing was written")
        return ti

    def write_goal_ticks(self, ticks) -> None:
        """Every joint's Goal Position in one sync write, after checking all of them; after
        a pause of the host longer than ¾ of the watchdog's time (wall clock) the watchdog
        is re-armed first (hand_driver.cycle.Jaw does the same in robot time)."""
        ti = self.check_goal_ticks(ticks)
        self._rearm_after_pause()
        self._sync_write_field("goal_position", ti)

    def _rearm_after_pause(self) -> None:
        """Before a goal write: re-arm the watchdog if the host was silent long enough for
        it to expire (the servos would silently refuse the goal)."""
        if self.watchdog_ms and time.monotonic() - self._last_io > WATCHDOG_REARM_FRACTION * self.watchdog_ms / 1000.0:
            self.rearm_watchdog()

    def require_current_sensing(self, what: str = "a current-based guarded touch") -> None:
        """CapabilityError unless every joint's model senses current (XL430 does not)."""
        bad = [(i, s) for i, s in zip(self.ids, self.specs) if not s.has_current_sensing]
        if bad:
            names = ", ".join(f"id {i} ({s.name})" for i, s in bad)
            load = bad[0][1].fields.get("present_load")
            why = f"its address {load.addr} is Present Load, not current" if load is not None else "no Present Current"
            raise CapabilityError(f"{what} needs current sensing, but {names} has none ({why}); use XM430, XC330 "
                                  "or DYNAMIXEL-P servos")

    def set_goal_current(self, ma) -> None:
        """Goal Current (the current cap in the guard mode: X current-based position, P position), mA,
        scalar or per joint."""
        self.require_current_sensing("setting a goal current")
        ma = np.broadcast_to(np.asarray(ma, dtype=float), (len(self.ids),))
        raw = []
        for i, s, m in zip(self.ids, self.specs, ma):
            if not math.isfinite(m) or m < 0:
                raise InputError(f"goal current for servo {i} must be a finite number ≥ 0 mA, got {m}")
            r = units.ma_to_current(m, s)
            if r > s.current_limit_default:
                raise InputError(f"goal current {m:g} mA for servo {i} exceeds {s.name}'s limit "
                                 f"{s.current_limit_default * s.current_unit_ma:g} mA")
            raw.append(r)
        self._rearm_after_pause()
        self._sync_write_field("goal_current", raw)

    def set_profile_raw(self, velocity, accel) -> None:
        """Profile Velocity and Acceleration of all joints (raw, each in its model's units: X
        0.229 rev/min and 214.577 rev/min², P 0.01 rev/min and 1 rev/min²; scalar or per joint)."""
        vel = np.broadcast_to(np.asarray(velocity), (len(self.ids),))
        acc = np.broadcast_to(np.asarray(accel), (len(self.ids),))
        addrs, blocks = [], []
        for i, s, v, a in zip(self.ids, self.specs, vel, acc):
            fa, fv = s.field("profile_acceleration"), s.field("profile_velocity")
            for name, f, x in (("profile velocity", fv, v), ("profile acceleration", fa, a)):
                if not 0 <= int(x) <= f.hi:
                    raise InputError(f"{name} {x} for servo {i} outside 0..{f.hi} ({s.name} raw units; 0 = unlimited)")
            # one write: Profile Velocity follows Profile Acceleration (X 108, 112; P 556, 560)
            addrs.append(fa.addr)
            blocks.append(encode_field(fa, int(a)) + encode_field(fv, int(v)))
        self._attempt("write of profile", lambda: self._write_joint_bytes("profile", addrs, blocks))

    def set_profile(self, velocity_rad_s: float, accel_rad_s2: float) -> None:
        """Profile in SI units (rad/s, rad/s² of the output shaft), each joint in its model's units."""
        self.set_profile_raw([units.rad_s_to_velocity(velocity_rad_s, s) for s in self.specs],
                             [units.rad_s2_to_accel(accel_rad_s2, s) for s in self.specs])

    def torque(self, on: bool) -> None:
        """Torque Enable of every joint in one sync write."""
        self._sync_write_field("torque_enable", [int(bool(on))] * len(self.ids))

    # -- single servos ----------------------------------------------------------------------------
    def ping(self, dxl_id: int) -> ServoInfo:
        """Model and firmware of one servo (BusTimeout if it does not answer)."""
        number = self._call(f"ping of servo {dxl_id}", lambda: self._ph.ping(self._port, dxl_id), dxl_id)[0]
        return self._servo_info(dxl_id, number)

    def scan(self, ids: Sequence[int], baudrates: Sequence[int], silent_pings: int = SCAN_SILENT_PINGS,
             read_attempts: int = SCAN_READ_ATTEMPTS) -> list[ServoInfo]:
        """Every servo that answers a ping, over the given ids and baud rates.

        A noisy bus loses and garbles replies, and a lost reply looks like an absent servo:
        each id is pinged until it answers cleanly, up to ``silent_pings`` times in a row
        without any answer; a garbled answer (a servo is there) earns it ``silent_pings``
        more tries. A servo found is read (firmware) with ``read_attempts`` attempts."""
        found = []
        saved = self.retries
        try:
            for b in baudrates:
                with self._lock:
                    if not self._port.setBaudRate(int(b)):
                        raise InputError(f"baud rate {b} is not supported by the Dynamixel SDK")
                for i in ids:
                    self.retries = 0
                    number = self._scan_ping(int(i), silent_pings)
                    if number is None:
                        continue
                    self.retries = read_attempts - 1
                    try:
                        found.append(self._servo_info(int(i), number))
                    except (BusTimeout, CrcError) as exc:
                        log.warning("servo %d answered a ping but not a read (%s); left out", i, exc)
        finally:
            self.retries = saved
            with self._lock:
                self._port.setBaudRate(self.baudrate)
        return found

    def _scan_ping(self, dxl_id: int, silent_pings: int) -> int | None:
        """The model number of the servo at ``dxl_id``, or None (see :meth:`scan`). An answer
        after a silent ping may be the late answer to that ping: the answer to the last one
        would then pass for the answer to the firmware read (same id), so it is flushed."""
        silent_left, garbled_left = silent_pings, silent_pings
        timed_out = False
        while silent_left > 0 and garbled_left > 0:
            try:
                number = self._call(f"ping of servo {dxl_id}", lambda: self._ph.ping(self._port, dxl_id), dxl_id)[0]
                if timed_out:
                    with self._lock:
                        self._settle()
                return number
            except BusTimeout:
                timed_out = True
                silent_left -= 1
            except CrcError:
                garbled_left -= 1
                silent_left = silent_pings
        return None

    def _servo_info(self, dxl_id: int, number: int) -> ServoInfo:
        fw = self._read(dxl_id, COMMON_FIELDS["firmware_version"])
        spec = MODELS_BY_NUMBER.get(number)
        return ServoInfo(dxl_id, spec.name if spec else f"unknown-{number}", number, fw, self._port.getBaudRate())

    def _spec_of(self, dxl_id: int) -> ModelSpec:
        """The model of servo ``dxl_id``: a joint's, else the one its ping reports."""
        if dxl_id in self.ids:
            return self.specs[self.ids.index(dxl_id)]
        number = self._call(f"ping of servo {dxl_id}", lambda: self._ph.ping(self._port, dxl_id), dxl_id)[0]
        spec = MODELS_BY_NUMBER.get(number)
        if spec is None:
            raise ModelMismatchError(f"servo {dxl_id} reports model number {number}, which no supported model has")
        return spec

    def read_hardware_error(self, dxl_id: int) -> HardwareStatus:
        """Hardware Error Status (X 70, P 518) of one servo, decoded by its model."""
        spec = self._spec_of(dxl_id)
        bits = self._read(dxl_id, spec.field("hardware_error_status"))
        return HardwareStatus(bits, tuple(spec.decode_hardware_error(bits)))

    def reboot(self, dxl_id: int) -> None:
        """Reboot one servo (clears a hardware error) and wait until it answers again.

        RAM comes back at defaults: torque off; Goal Position is set to the present
        position, the goal current re-applied and the watchdog re-armed, torque stays off
        until ``torque(True)``.
        """
        self._call(f"reboot of servo {dxl_id}", lambda: self._ph.reboot(self._port, dxl_id), dxl_id)
        deadline = time.monotonic() + _REBOOT_WAIT_S
        while True:
            try:
                self._attempt(f"ping of servo {dxl_id}", lambda: self._check(
                    *self._ph.ping(self._port, dxl_id)[1:], f"ping of servo {dxl_id}", dxl_id), attempts=1)
                break
            except (BusTimeout, CrcError):
                if time.monotonic() > deadline:
                    raise BusTimeout(f"servo {dxl_id} did not come back within {_REBOOT_WAIT_S:g} s of reboot")
        if dxl_id in self.ids:
            k = self.ids.index(dxl_id)
            spec = self.specs[k]
            pos = self._read(dxl_id, spec.field("present_position"))
            self._write(dxl_id, spec.field("goal_position"), int(np.clip(pos, self.min_ticks[k], self.max_ticks[k])))
            if spec.has_current_sensing:
                self._write(dxl_id, spec.field("goal_current"), self._current_limit_raw(self.joints[k], spec))
            if self.watchdog_ms:
                self._write(dxl_id, spec.field("bus_watchdog"), self.watchdog_ms // units.WATCHDOG_STEP_MS)


def scan(port: str, ids: Sequence[int], baudrates: Sequence[int], timeout_s: float | None = None,
         **attempts) -> list[ServoInfo]:
    """Servos answering on ``port`` (no jaw config needed); ``timeout_s``: the status timeout
    (default the SDK's); ``attempts``: see JointBus.scan."""
    with JointBus(port, int(baudrates[0]), (), handle_signals=False, timeout_s=timeout_s) as bus:
        return bus.scan(ids, baudrates, **attempts)


#: how long :func:`clock_rate` lets the servo's Realtime Tick run (s of wall clock): 1 ms of
#: tick resolution and a few ms of read latency make the rate good to about 1 %
CLOCK_WINDOW_S = 0.3
#: reads of the tick at each end of the window, the one with the shortest round trip kept
CLOCK_READS = 5
#: Realtime Tick (ms) wraps at this
_TICK_WRAP_MS = 32768


@dataclass(frozen=True)
class ClockRate:
    """Servo seconds per wall-clock second (1 for real hardware; an emulator's time scale),
    from ``ticks_ms`` of servo ``dxl_id``'s Realtime Tick over ``wall_s``."""

    rate: float
    dxl_id: int
    ticks_ms: int
    wall_s: float

    def describe(self) -> str:
        return (f"servo {self.dxl_id}'s Realtime Tick counted {self.ticks_ms} ms in {self.wall_s:.3f} s "
                f"of wall clock: {self.rate:.2f}x")


def clock_rate(port: str, baudrate: int, joint: JointConfig, window_s: float = CLOCK_WINDOW_S) -> ClockRate | None:
    """How fast the bus's clock runs against the wall clock, from one servo's Realtime Tick
    (a millisecond counter, mod 32768) read ``window_s`` apart, each end the read of
    ``CLOCK_READS`` with the shortest round trip, timed at its midpoint. Opens the port without configuring anything (no torque, no watchdog), before
    a command's real session. None when the model has no Realtime Tick."""
    field = model_spec(joint.model).fields.get("realtime_tick")
    if field is None:
        return None
    with JointBus(port, int(baudrate), (), handle_signals=False) as bus:
        def timed() -> tuple[int, float]:
            """The tick of the read with the shortest round trip of CLOCK_READS (a loaded host
            answers late; the shortest round trip pins the tick's wall time best)."""
            best = None
            for _ in range(CLOCK_READS):
                t0 = time.monotonic()
                data = bus.first_contact(f"read of realtime_tick from servo {joint.id}", lambda: bus._ph.readTxRx(
                    bus._port, int(joint.id), field.addr, field.size), int(joint.id))[0]
                t1 = time.monotonic()
                if best is None or t1 - t0 < best[0]:
                    best = (t1 - t0, decode_field(field, data), (t0 + t1) / 2.0)
            return best[1], best[2]

        tick0, t0 = timed()
        time.sleep(window_s)
        tick1, t1 = timed()
    ticks = (tick1 - tick0) % _TICK_WRAP_MS
    return ClockRate(ticks / 1000.0 / (t1 - t0), int(joint.id), ticks, t1 - t0)
