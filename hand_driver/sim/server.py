"""The emulated servo bus: servos of any supported model behind a pseudo-terminal.

(Just over 400 lines: every instruction of Protocol 2.0 is served here, beside the
simulated clock it advances.)

``EmulatedBus(config, scene)`` opens a pty; ``.port`` is the slave path that pyserial and
the Dynamixel SDK open like a USB adapter. A thread parses Protocol 2.0 instruction
packets from the master side and answers byte for byte like a bus of real servos (ping,
read, write, reg write/action, reboot, sync/fast sync read, sync write, bulk/fast bulk
read, bulk write; status errors; no status for broadcast writes; servos answer only at
the baud rate their Baud Rate register selects). Motion is integrated on demand in
simulated time (``time_scale`` × wall clock) before each packet is served; when the
scene has an object and ``hand_driver.sim.physics.ContactWorld`` is available, every
step is constrained so that no pad penetrates the object (unbounded or finite: curve,
closing segments and corners) (joint angles from ticks use
the *truth* config: zero_tick, direction), and a blocked servo's current rises. The errors
the truth config declares (backlash, link and pad compliance: hand_driver.sim.errors) lie
between the servos' encoders and the links the contact world moves; none declared, none.
"""

from __future__ import annotations

import fcntl
import math
import os
import select
import struct
import termios
import threading
import time
import tty
from typing import Sequence

import numpy as np

from hand_driver import kinematics as kin
from hand_driver.config import JawConfig, JointConfig, declares_errors
from hand_driver.control_table import BAUD_RATES
from hand_driver.control_table import model as model_spec
from hand_driver.sim import protocol as P
from hand_driver.sim.errors import ServoErrors
from hand_driver.sim.faults import FaultPlan
from hand_driver.sim.servo import EmulatedServo
from hand_driver.units import rad_to_ticks_exact, ticks_to_rad
from tactile_common.errors import InputError

_MAX_SUBSTEP_S = 0.002
_MAX_SUBSTEPS = 25  # per packet: bounds the physics work done before an answer
_TERMIOS_SPEED = {getattr(termios, f"B{b}"): b for b in BAUD_RATES if hasattr(termios, f"B{b}")}


def joints_of(config: JawConfig | Sequence[JointConfig]) -> list[JointConfig]:
    """Joints in config order, of a jaw config or a sequence of joints."""
    return list(config.joints if isinstance(config, JawConfig) else config)


def _contact_world(truth_config, scene):
    obj = getattr(scene, "object", scene)
    if obj is None:
        return None
    try:
        from hand_driver.sim.physics import ContactWorld
    except ModuleNotFoundError as exc:
        if exc.name != "hand_driver.sim.physics":
            raise
        return None
    return ContactWorld(truth_config, obj)


class EmulatedBus:
    """Servos of ``config`` on a pty; context manager; ``stop()`` joins and closes."""

    def __init__(self, config, scene=None, truth_config=None, faults: FaultPlan | None = None,
                 time_scale: float = 1.0, *, firmware: int = 46, baudrate: int = 1_000_000,
                 initial_ticks=None, wire_timing: bool = True, boot_time_s: float = 0.1):
        self.joints = joints_of(config)
        truth = truth_config if truth_config is not None else config
        self.truth_joints = joints_of(truth)
        if len(self.truth_joints) != len(self.joints):
            raise InputError("truth config and config have different numbers of joints")
        for j, t in zip(self.joints, self.truth_joints):
            if j.model != t.model:
                raise InputError(f"joint id {j.id} is {j.model} in the config but {t.model} in the truth config: "
                                 f"the emulated servos are the config's")
        self.faults = faults if faults is not None else FaultPlan()
        self.time_scale = float(time_scale)
        self.wire_timing = wire_timing
        self.boot_time_s = boot_time_s
        if initial_ticks is None:
            initial_ticks = [j.zero_tick for j in self.truth_joints]
        self.servos: dict[int, EmulatedServo] = {}
        for j, t in zip(self.joints, initial_ticks):
            spec = model_spec(j.model)
            self.servos[int(j.id)] = EmulatedServo(int(j.id), spec, firmware, int(t), spec.baud_register(baudrate))
        self._order = [int(j.id) for j in self.joints]
        self._zero = np.array([float(j.zero_tick) for j in self.truth_joints])
        self._dir = np.array([float(j.direction) for j in self.truth_joints])
        self._per_rev = np.array([float(j.ticks_per_rev) for j in self.truth_joints])
        self._truth = truth
        #: the declared errors of the truth jaw (None: it declares none)
        self.errors = ServoErrors(truth) if isinstance(truth, JawConfig) and declares_errors(truth) else None
        if self.errors is not None:  # zero_tick is the link's zero under the working load: the motors'
            # zero lies half a band the other way (kinematics.working_loads)
            work = np.concatenate([kin.working_loads(f) for f in truth.fingers])
            half_ticks = np.array([j.backlash_deg / 2.0 * j.ticks_per_rev / 360.0 for j in self.truth_joints])
            self._zero = self._zero - self._dir * work * half_ticks
        self.lock = threading.RLock()
        self.world = None
        self.place(scene)
        self.sim_time = 0.0
        self.bytes_in = 0
        self.bytes_out = 0
        self._master, self._slave = os.openpty()
        tty.setraw(self._slave)
        self.port = os.ttyname(self._slave)
        self._t0 = time.monotonic()
        self._offset = 0.0
        self._stop = threading.Event()
        self._busy = False
        self._thread = threading.Thread(target=self._serve, name="emulated-dxl-bus", daemon=True)
        self._thread.start()

    # -- lifecycle ------------------------------------------------------------------------
    def __enter__(self) -> "EmulatedBus":
        return self

    def __exit__(self, *exc) -> None:
        self.stop()

    def stop(self) -> None:
        """Stop serving, join the thread, close the pty (idempotent)."""
        self._stop.set()
        if self._thread.is_alive() and threading.current_thread() is not self._thread:
            self._thread.join(timeout=2.0)
        for fd in (self._master, self._slave):
            if fd is not None:
                try:
                    os.close(fd)
                except OSError:
                    pass
        self._master = self._slave = None

    def place(self, scene) -> None:
        """Put an object (a scene or a SceneObject) in front of the jaw, or take it away
        (None): what a person does between calibration placements."""
        with self.lock:
            self.world = _contact_world(self._truth, scene) if scene is not None else None

    def link_angles(self) -> np.ndarray:
        """The truth jaw's link angles now (rad, config order): the encoders' angles less the
        declared errors' gap (backlash and compliance; for tests against exact geometry)."""
        with self.lock:
            motor = ticks_to_rad([self.servos[i].pos for i in self._order], self._zero, self._dir, self._per_rev)
            return motor if self.errors is None else motor - self.errors.gap

    def vanish(self) -> None:
        """The adapter disappears: the pty is closed, the port path stops existing."""
        self.stop()

    def hardware_error(self, dxl_id: int, bits: int = 0x20) -> None:
        """Raise Hardware Error Status bits on a servo (default: overload); torque drops."""
        with self.lock:
            self.servos[dxl_id].set_hardware_error(bits)

    # -- simulation -------------------------------------------------------------------------
    def now(self) -> float:
        """Simulated time now (the clock the servos, their motion and watchdogs run on)."""
        return (time.monotonic() - self._t0) * self.time_scale + self._offset

    def advance_to_now(self) -> None:
        with self.lock:
            self._integrate(self.now() - self.sim_time)

    def step(self, dt: float) -> None:
        """Serve everything already sent, then jump simulated time dt seconds ahead of the
        clock, integrating motion (for tests)."""
        self.wait_idle()
        with self.lock:
            self.advance_to_now()
            self.advance(dt)

    def advance(self, dt: float) -> None:
        """Jump simulated time dt seconds ahead of the clock, integrating motion, without
        waiting for the pty to go quiet: for a client in lockstep that has had every
        answer it waits for (hand_driver.cycle.LockstepClock)."""
        with self.lock:
            self._offset += dt
            self._integrate(dt)

    def _integrate(self, dt: float) -> None:
        """Integrate dt of motion; a servo's Bus Watchdog expiring within it stops that servo
        at the exact instant (the span is split there)."""
        with self.lock:
            remaining = dt
            while remaining > 0:
                due = [(t, s) for s in self.servos.values() if (t := s.watchdog_due()) is not None]
                t_next = min((t for t, _ in due), default=math.inf)
                if t_next <= self.sim_time + 1e-12:
                    for t, s in due:
                        if t <= self.sim_time + 1e-12:
                            s.trip_watchdog(t)
                    continue
                span = remaining if t_next >= self.sim_time + remaining else t_next - self.sim_time
                self._integrate_span(span)
                remaining -= span

    def _integrate_span(self, dt: float) -> None:
        with self.lock:
            if dt <= 0:
                return
            n = min(_MAX_SUBSTEPS, max(1, int(np.ceil(dt / _MAX_SUBSTEP_S))))
            h = dt / n
            servos = [self.servos[i] for i in self._order]
            for _ in range(n):
                pos = [s.pos for s in servos]
                prop = [s.propose(h) for s in servos]
                if self.errors is not None:
                    prop = self._step_with_errors(pos, prop)
                elif self.world is not None and prop != pos:
                    q_from = ticks_to_rad(pos, self._zero, self._dir, self._per_rev)
                    q_to = ticks_to_rad(prop, self._zero, self._dir, self._per_rev)
                    q = np.asarray(self.world.constrain(q_from, q_to), dtype=float)
                    prop = list(rad_to_ticks_exact(q, self._zero, self._dir, self._per_rev))
                for s, p in zip(servos, prop):
                    s.settle(float(p), h)
            if self.errors is not None and self.errors.balanced:
                for s, cur in zip(servos, self._balance(servos)):
                    s.publish(dt, cur)
            else:
                for s in servos:
                    s.publish(dt)
            self.sim_time += dt
            if self.errors is not None and not self.errors.balanced:
                self._judge_load(servos)

    def _step_with_errors(self, pos: list[float], prop: list[float]) -> list[float]:
        """One substep through the declared errors: the motors' proposed angles become the
        links' (play, load side, compliance), the contact world constrains those, and the
        motors end where the links let them (hand_driver.sim.errors)."""
        e = self.errors
        world_from = e.world_angles(ticks_to_rad(pos, self._zero, self._dir, self._per_rev))
        world_to, gap = e.target(world_from, ticks_to_rad(prop, self._zero, self._dir, self._per_rev))
        world = (np.asarray(self.world.constrain(world_from, world_to), dtype=float)
                 if self.world is not None else world_to)
        return list(rad_to_ticks_exact(e.settle(world, gap), self._zero, self._dir, self._per_rev))

    def _balance(self, servos: list[EmulatedServo]) -> list[float | None]:
        """Declared compliance: the torque balance of this instant (hand_driver.sim.errors): the
        motors moved to where the links and their deflection put them; returns each servo's
        Present Current (raw units) of the balance, None where it draws its lag current."""
        kt = self.errors.kt

        def drive(motor: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
            ticks = rad_to_ticks_exact(motor, self._zero, self._dir, self._per_rev)
            push = [k * d * s.drive_current(float(t)) * s.spec.current_unit_ma / 1000.0 if s.spec.has_current_sensing
                    else math.nan for s, t, d, k in zip(servos, ticks, self._dir, kt)]
            cap = [k * s.current_cap() * s.spec.current_unit_ma / 1000.0 if s.spec.has_current_sensing else 0.0
                   for s, k in zip(servos, kt)]
            return np.array(push), np.array(cap)

        motor = ticks_to_rad([s.pos for s in servos], self._zero, self._dir, self._per_rev)
        motor, torque = self.errors.balance(self.world, self.errors.world_angles(motor), drive)
        for s, t in zip(servos, rad_to_ticks_exact(motor, self._zero, self._dir, self._per_rev)):
            s.pos = float(t)
        return [None if math.isnan(t) else t * 1000.0 / (k * d * s.spec.current_unit_ma)
                for s, t, d, k in zip(servos, torque, self._dir, kt)]

    def _judge_load(self, servos: list[EmulatedServo]) -> None:
        """The pads' contact forces from the servos' present currents (for the next span)."""
        currents = [None if not s.spec.has_current_sensing
                    else d * s.get("present_current") * s.spec.current_unit_ma for s, d in zip(servos, self._dir)]
        motor = ticks_to_rad([s.pos for s in servos], self._zero, self._dir, self._per_rev)
        self.errors.judge_load(self.world, self.errors.world_angles(motor), currents)

    def wait_idle(self, quiet_s: float = 0.02, timeout: float = 10.0) -> None:
        """Return once the bus has had nothing to serve for ``quiet_s`` (for tests: the pty
        hands bytes over asynchronously); TimeoutError after ``timeout`` s still busy (bounded
        and generous: the thread serving the bus may be starved on a loaded host)."""
        deadline = time.monotonic() + timeout
        quiet_since = time.monotonic()
        while time.monotonic() < deadline:
            if self._master is None:
                return
            pending = struct.unpack("i", fcntl.ioctl(self._master, termios.FIONREAD, b"\0\0\0\0"))[0]
            if pending or self._busy:
                quiet_since = time.monotonic()
            elif time.monotonic() - quiet_since >= quiet_s:
                return
            time.sleep(0.001)
        raise TimeoutError("emulated bus still busy")

    def wait_until(self, condition, timeout: float = 10.0) -> bool:
        """Whether ``condition()`` came true within ``timeout`` s (for tests: a host's last
        broadcast writes reach the emulator late on a loaded host — the pty's flip buffer is
        pushed by a kernel worker, so a quiet bus (``wait_idle``) is no proof that every byte
        written has arrived), then the bus idle."""
        deadline = time.monotonic() + timeout
        while not condition():
            if time.monotonic() >= deadline:
                return False
            time.sleep(0.005)
        self.wait_idle(timeout=max(deadline - time.monotonic(), 0.1))
        return bool(condition())

    # -- serving --------------------------------------------------------------------------
    def _line_baud(self) -> int | None:
        try:
            return _TERMIOS_SPEED.get(termios.tcgetattr(self._slave)[5])
        except (termios.error, TypeError):
            return None

    def _serve(self) -> None:
        parser = P.PacketParser()
        while not self._stop.is_set():
            try:
                ready, _, _ = select.select([self._master], [], [], 0.05)
                if not ready:
                    continue
                self._busy = True
                data = os.read(self._master, 4096)
            except (OSError, ValueError, TypeError):
                self._busy = False
                return
            self.bytes_in += len(data)
            t_rx = time.monotonic()
            for pkt in parser.feed(data):
                with self.lock:
                    self.advance_to_now()
                    replies = self._handle(pkt)
                self._transmit(replies, t_rx, pkt)
            self._busy = False

    def _live(self, baud: int | None) -> list[EmulatedServo]:
        """Servos that hear the line now: booted and set to the line's baud rate."""
        out = []
        for s in self.servos.values():
            if s.booting_until > self.sim_time:
                continue
            if baud is not None and s.spec.baud_rates.get(s.get("baud_rate")) != baud:
                continue
            out.append(s)
        return out

    def _handle(self, pkt: P.Packet) -> list[tuple[EmulatedServo | None, bytes]]:
        """Apply one instruction; return [(replying servo, status packet bytes), …] to send
        (servo None: a combined fast-read status)."""
        live = self._live(self._line_baud())
        bad = not pkt.crc_ok or self.faults.take_bad_instruction()
        if pkt.dxl_id == P.BROADCAST_ID:
            if bad:
                return []
            for s in live:
                s.received(self.sim_time)
            return self._broadcast(pkt, live)
        primary = [s for s in live if s.dxl_id == pkt.dxl_id]
        if bad:
            return [(s, P.build_status(pkt.dxl_id, s.status_error(P.ERR_CRC))) for s in primary]
        out = []
        for s in primary:
            s.received(self.sim_time)
            out += self._unicast(s, pkt)
        for s in live:  # addressed by its Secondary ID (12): obeys, never answers
            if s.dxl_id != pkt.dxl_id and s.get("secondary_id") == pkt.dxl_id:
                s.received(self.sim_time)
                self._unicast(s, pkt)
        return out

    def _status(self, s: EmulatedServo, pkt: P.Packet, code: int,
                data: bytes = b"") -> list[tuple[EmulatedServo | None, bytes]]:
        """The status of a unicast instruction, from the ID it was addressed to (after a
        write of a new ID the servo answers this packet under its old one)."""
        level = s.get("status_return_level")
        inst = pkt.instruction
        if inst != P.INST_PING and (level == 0 or (level == 1 and inst != P.INST_READ)):
            return []
        return [(s, P.build_status(pkt.dxl_id, s.status_error(code), data))]

    def _unicast(self, s: EmulatedServo, pkt: P.Packet) -> list[tuple[EmulatedServo | None, bytes]]:
        inst, prm = pkt.instruction, pkt.params
        if inst == P.INST_PING:
            return self._status(s, pkt, 0, P.p16(s.spec.number) + bytes([s.firmware]))
        if inst == P.INST_READ:
            if len(prm) != 4:
                return self._status(s, pkt, P.ERR_DATA_LENGTH)
            code, data = s.read(P.u16(prm, 0), P.u16(prm, 2))
            return self._status(s, pkt, code, data)
        if inst in (P.INST_WRITE, P.INST_REG_WRITE):
            if len(prm) < 3:
                return self._status(s, pkt, P.ERR_DATA_LENGTH)
            addr, data = P.u16(prm, 0), bytes(prm[2:])
            if inst == P.INST_WRITE:
                return self._status(s, pkt, s.write(addr, data))
            code = s.check_write(addr, data)
            if not code:
                s.registered = (addr, data)
                s._put("registered_instruction", 1)
            return self._status(s, pkt, code)
        if inst == P.INST_ACTION:
            self._action(s)
            return self._status(s, pkt, 0)
        if inst == P.INST_REBOOT:
            out = self._status(s, pkt, 0)
            s.reboot(self.sim_time, self.boot_time_s)
            return out
        if inst == P.INST_FACTORY_RESET:
            if len(prm) != 1:
                return self._status(s, pkt, P.ERR_DATA_LENGTH)
            out = self._status(s, pkt, 0)  # answered before the reset, as the servo then reboots
            code = s.factory_reset(prm[0], self.sim_time, self.boot_time_s)
            return out if not code else self._status(s, pkt, code)
        if inst == P.INST_CLEAR:
            return self._status(s, pkt, s.clear_revolutions(bytes(prm)))
        return self._status(s, pkt, P.ERR_INSTRUCTION)

    @staticmethod
    def _action(s: EmulatedServo) -> None:
        if s.registered is not None:
            s.write(*s.registered)
            s.registered = None
            s._put("registered_instruction", 0)

    def _broadcast(self, pkt: P.Packet, servos: list[EmulatedServo]) -> list[tuple[EmulatedServo | None, bytes]]:
        inst, prm = pkt.instruction, pkt.params
        live = {s.dxl_id: s for s in sorted(servos, key=lambda s: s.dxl_id)}
        try:
            if inst == P.INST_PING:
                return [(s, P.build_status(i, s.status_error(), P.p16(s.spec.number) + bytes([s.firmware])))
                        for i, s in live.items()]
            if inst == P.INST_WRITE and len(prm) >= 3:
                for s in live.values():
                    s.write(P.u16(prm, 0), bytes(prm[2:]))
                return []
            if inst == P.INST_ACTION:
                for s in live.values():
                    self._action(s)
                return []
            if inst == P.INST_FACTORY_RESET and len(prm) == 1 and prm[0] != P.FACTORY_RESET_ALL:
                # firmware ≥ 42 ignores a broadcast reset of everything (every servo would become ID 1)
                for s in live.values():
                    s.factory_reset(prm[0], self.sim_time, self.boot_time_s)
                return []
            if inst == P.INST_CLEAR:
                for s in live.values():
                    s.clear_revolutions(bytes(prm))
                return []
            if inst == P.INST_SYNC_WRITE:
                addr, _, items = P.parse_sync_write(prm)
                for i, data in items.items():
                    if i in live:
                        live[i].write(addr, data)
                return []
            if inst == P.INST_BULK_WRITE:
                for i, addr, data in P.parse_bulk_write(prm):
                    if i in live:
                        live[i].write(addr, data)
                return []
            if inst in (P.INST_SYNC_READ, P.INST_FAST_SYNC_READ):
                addr, n, ids = P.parse_sync_read(prm)
                reqs = [(i, addr, n) for i in ids]
            elif inst in (P.INST_BULK_READ, P.INST_FAST_BULK_READ):
                reqs = P.parse_bulk_read(prm)
            else:
                return []
        except ValueError:
            return []
        if inst in (P.INST_SYNC_READ, P.INST_BULK_READ):
            out = []
            for i, addr, n in reqs:
                if i in live:
                    code, data = live[i].read(addr, n)
                    out.append((live[i], P.build_status(i, live[i].status_error(code), data)))
            return out
        slots = []
        for i, addr, n in reqs:
            if i not in live or self.faults.take_drop(i):
                break  # the chain stops at a silent servo: the packet is cut short
            code, data = live[i].read(addr, n)
            slots.append((live[i].status_error(code), i, data if not code else bytes(n)))
        if not slots:
            return []
        packet = P.build_fast_status(slots)
        if len(slots) < len(reqs):
            packet = packet[:-2]  # truncated: no final CRC arrives
        return [(None, packet)]

    def _transmit(self, replies: list[tuple[EmulatedServo | None, bytes]], t_rx: float, pkt: P.Packet) -> None:
        if not replies:
            return
        baud = self._line_baud() or 1_000_000
        byte_s = 10.0 / baud
        t = t_rx + (len(P.build_instruction(pkt.dxl_id, pkt.instruction, pkt.params)) * byte_s
                    if self.wire_timing else 0.0)
        for s, packet in replies:
            dxl_id = packet[4]  # the ID the status carries
            if s is not None and self.faults.take_drop(dxl_id):
                continue
            if self.faults.take_corrupt(dxl_id):
                packet = packet[:-1] + bytes([packet[-1] ^ 0xFF])
            if self.wire_timing:
                delay_reg = s.get("return_delay_time") if s is not None else 0
                t += delay_reg * 2e-6 + len(packet) * byte_s
            t += self.faults.take_delay()
            wait = t - time.monotonic()
            if wait > 0:
                time.sleep(wait)
            try:
                os.write(self._master, packet)
            except (OSError, TypeError):
                return
            self.bytes_out += len(packet)
