"""One emulated servo of any supported model (X-series or DYNAMIXEL-P): control-table memory
and motion toward its goal.

Memory follows the model's control table (hand_driver.control_table): reads return the
bytes; writes check access (read-only items, EEPROM while torque is on → access error),
whole-item coverage (data length error), static ranges (data range error) and the
position/current/velocity limits (data limit error). In position and current-based
position mode the servo follows a trapezoidal profile (Profile Velocity/Acceleration;
0 means unlimited, capped by Velocity Limit) toward Goal Position. The host of the servo
(the emulated bus) may block the motion (a pad touching the object): Present Current
then rises with the gap between trajectory and actual position, clipped at Goal Current
in the modes where the e-Manual says Goal Current caps it (X: current and current-based
position; P: current, velocity, position and extended position), else at Current Limit;
it is 0 while the shaft follows its trajectory freely. The rise is the same for every model
in physical units (``BLOCKED_MA_PER_RAD``), so a P-series joint lags by the same angle as an
X-series one at the same current.
A hardware error (set on demand, or the overload error after a sustained stall) turns
torque off, sets the alert bit of every status packet and keeps torque off until reboot,
as real servos do.

What the ROBOTIS e-Manual describes and other tools rely on (docs/driver.md):

- **Bus Watchdog** (X 98, P 546), 20 ms units: while torque is on and the watchdog is set, a
  gap between instruction packets longer than it stops the servo where it is and the item
  reads −1; the goal items (PWM, current, velocity, position) then refuse writes with a
  data range error until 0 is written to it. The servo holds its position until a new goal.
- **Indirect addressing**: Indirect Data k reads and writes the byte that Indirect Address
  k points to (X: 168…/224…, 578…/634…; P: 168…/634…), with that item's own checks.
- **Factory reset** (all / all but ID / all but ID and baud rate) and **clear** (the
  multi-turn revolution count; refused while moving), **Startup Configuration (60)** bit 0
  (torque on after a reboot), **Secondary ID (12)** (handled by the bus).
- **Overload**: the e-Manual gives no numbers for "a persistent load exceeding the maximum
  output"; the model here: the servo is blocked (its trajectory ahead of the shaft) while
  its current (XL430: load) is at least a third of the model's maximum for
  ``OVERLOAD_TIME_S``; with Shutdown (63) bit 5 set (the default) it raises bit 5 of
  Hardware Error Status and drops torque. Pressing at the jaw's goal current (≤ 1 A of
  XM430's 3.2 A) never reaches it.
"""

from __future__ import annotations

import math

from hand_driver.control_table import (
    MODE_CURRENT_BASED_POSITION,
    MODE_EXTENDED_POSITION,
    MODE_POSITION,
    MODELS,
    ModelSpec,
    decode_field,
    encode_field,
)
from hand_driver.sim import protocol as P
from hand_driver.units import WATCHDOG_STEP_MS, accel_unit_ticks_s2, velocity_unit_ticks_s

_XM430 = MODELS["XM430-W350"]
#: Present Current of a blocked servo per angle of its shaft's lag behind its trajectory
#: (mA/rad): 8 XM430 units (21.5 mA) per XM430 tick, 14.0 A/rad, the same for every model
BLOCKED_MA_PER_RAD = 8.0 * _XM430.current_unit_ma / _XM430.rad_per_tick
#: Present Load (XL430, 0.1 % of maximum torque) per tick of lag
LOAD_PER_TICK = 5.0


def current_per_tick(spec: ModelSpec) -> float:
    """A blocked servo's Present Current per tick of lag, in its model's raw units."""
    return BLOCKED_MA_PER_RAD * spec.rad_per_tick / spec.current_unit_ma

#: the goal items a Bus Watchdog error makes read-only
_GOALS = ("goal_pwm", "goal_current", "goal_velocity", "goal_position")
#: overload model (module docstring): blocked at ≥ this fraction of the maximum current or
#: load for this long
OVERLOAD_FRACTION = 1.0 / 3.0
OVERLOAD_TIME_S = 5.0
#: Hardware Error Status (70) / Shutdown (63) bit of the overload error
OVERLOAD_BIT = 0x20
_MOTION_MODES = (MODE_POSITION, MODE_EXTENDED_POSITION, MODE_CURRENT_BASED_POSITION)


def _indirect_map(spec: ModelSpec) -> dict:
    """Indirect Data address → the Indirect Address item pointing for it."""
    return {spec.field(f"indirect_data_{k}").addr: spec.field(f"indirect_address_{k}")
            for b in spec.indirect for k in range(b.first, b.last + 1)}


class EmulatedServo:
    """Control-table memory plus a simple motion model, stepped by the bus."""

    def __init__(self, dxl_id: int, spec: ModelSpec, firmware: int = 46, position: int | None = None,
                 baud_register: int = 3):
        self.spec = spec
        self.firmware = firmware
        self.table_size = spec.table_size
        self._indirect = _indirect_map(spec)
        self._current_per_tick = current_per_tick(spec) if spec.has_current_sensing else 0.0
        self.mem = bytearray(self.table_size)
        if position is None:
            position = spec.position_center
        self._eeprom_defaults = {"id": dxl_id, "baud_rate": baud_register}
        self._reset_eeprom()
        self._reset_ram(position)
        self.booting_until = 0.0  # sim time before which the servo does not answer (reboot)
        self.registered: tuple[int, bytes] | None = None
        self.last_rx = 0.0  # sim time of the last instruction packet this servo received
        self.watchdog_tripped_at: float | None = None  # sim time the Bus Watchdog last expired
        self.overload_s = 0.0  # how long the servo has been blocked at overload current

    # -- memory -------------------------------------------------------------------------
    def _reset_eeprom(self) -> None:
        for f in self.spec.fields.values():
            if f.eeprom:
                self._put(f.name, f.default)
        self._put("model_number", self.spec.number)
        self._put("firmware_version", self.firmware)
        for k, v in self._eeprom_defaults.items():
            self._put(k, v)

    def _reset_ram(self, position: float) -> None:
        for f in self.spec.fields.values():
            if not f.eeprom:
                self._put(f.name, f.default)
        self.pos = float(position)  # actual shaft position, ticks
        self.traj = float(position)  # commanded trajectory position, ticks
        self.vel = 0.0  # trajectory velocity, ticks/s
        self.actual_vel = 0.0
        self.halted = False  # stopped by the Bus Watchdog until a new goal position
        self.uptime_s = 0.0  # since power-up or reboot: Realtime Tick is its milliseconds mod 32768
        self._put("goal_position", int(round(position)))
        if "goal_current" in self.spec.fields:
            self._put("goal_current", self.spec.current_limit_default)
        self._sync_present(0.0)

    def get(self, name: str) -> int:
        f = self.spec.field(name)
        return decode_field(f, self.mem, f.addr)

    def _put(self, name: str, value: int) -> None:
        f = self.spec.field(name)
        self.mem[f.addr : f.addr + f.size] = encode_field(f, value)

    @property
    def dxl_id(self) -> int:
        return self.get("id")

    @property
    def torque_on(self) -> bool:
        return bool(self.get("torque_enable"))

    @property
    def hardware_error(self) -> int:
        return self.get("hardware_error_status")

    def status_error(self, code: int = 0) -> int:
        """The error byte of a status packet: code plus the alert bit on hardware error."""
        return code | (0x80 if self.hardware_error else 0)

    def _target(self, addr: int) -> int:
        """Where a byte access at ``addr`` lands: through Indirect Data, the address its
        Indirect Address points to; elsewhere ``addr`` itself."""
        ptr = self._indirect.get(addr)
        return addr if ptr is None else decode_field(ptr, self.mem, ptr.addr)

    def read(self, addr: int, length: int) -> tuple[int, bytes]:
        """(error code, data) of a Read of ``length`` bytes from ``addr``."""
        if length == 0 or addr + length > self.table_size:
            return P.ERR_ACCESS, b""
        return 0, bytes(self.mem[self._target(a)] for a in range(addr, addr + length))

    def _runs(self, addr: int, data: bytes) -> list[tuple[int, bytes]]:
        """A write split into contiguous runs of target addresses (indirection resolved)."""
        runs: list[tuple[int, bytearray]] = []
        for i, b in enumerate(data):
            t = self._target(addr + i)
            if runs and runs[-1][0] + len(runs[-1][1]) == t:
                runs[-1][1].append(b)
            else:
                runs.append((t, bytearray([b])))
        return [(a, bytes(d)) for a, d in runs]

    def check_write(self, addr: int, data: bytes) -> int:
        """The error code a Write would get (0: accepted)."""
        if not data or addr + len(data) > self.table_size:
            return P.ERR_ACCESS
        for a, d in self._runs(addr, data):
            code = self._check_direct(a, d)
            if code:
                return code
        return 0

    def _check_direct(self, addr: int, data: bytes) -> int:
        end = addr + len(data)
        if not data or end > self.table_size:
            return P.ERR_ACCESS
        touched = [f for f in self.spec.fields.values() if f.addr < end and addr < f.addr + f.size]
        if not touched:
            return P.ERR_ACCESS
        for f in touched:
            if f.addr < addr or f.addr + f.size > end:
                return P.ERR_DATA_LENGTH
            if f.access != "RW" or (f.eeprom and self.torque_on):
                return P.ERR_ACCESS
        for f in touched:
            v = decode_field(f, data, f.addr - addr)
            if (f.lo is not None and v < f.lo) or (f.hi is not None and v > f.hi):
                return P.ERR_DATA_RANGE
            if self._beyond_limit(f.name, v):
                return P.ERR_DATA_LIMIT
            if f.name == "operating_mode" and v not in self.spec.operating_modes:
                return P.ERR_DATA_RANGE
            if f.name == "torque_enable" and v == 1 and self.hardware_error:
                return P.ERR_RESULT_FAIL
            if f.name in _GOALS and self.get("bus_watchdog") < 0:
                return P.ERR_DATA_RANGE
        return 0

    def _beyond_limit(self, name: str, v: int) -> bool:
        if name == "goal_position" and self.get("operating_mode") != MODE_EXTENDED_POSITION:
            return not self.get("min_position_limit") <= v <= self.get("max_position_limit")
        if name == "goal_current":
            return abs(v) > self.get("current_limit")
        if name == "goal_velocity":
            return abs(v) > self.get("velocity_limit")
        return False

    def write(self, addr: int, data: bytes) -> int:
        """Apply a Write; returns its error code (nothing is written on error)."""
        err = self.check_write(addr, data)
        if err:
            return err
        goal = self.spec.field("goal_position")
        for a, d in self._runs(addr, data):
            self.mem[a : a + len(d)] = d
            if a <= goal.addr < a + len(d):
                # a new goal starts a new profile from where the shaft is
                self.traj, self.vel = self.pos, self.actual_vel
                self.halted = False
        return 0

    # -- bus watchdog ---------------------------------------------------------------------
    def received(self, now: float) -> None:
        """An instruction packet for this servo arrived at sim time ``now``."""
        self.last_rx = now

    def watchdog_due(self) -> float | None:
        """Sim time at which the Bus Watchdog expires unless a packet arrives (None: not armed)."""
        wd = self.get("bus_watchdog")
        if wd <= 0 or not self.torque_on:
            return None
        return self.last_rx + wd * WATCHDOG_STEP_MS / 1000.0

    def trip_watchdog(self, now: float) -> None:
        """The host went quiet: stop where the shaft is; Bus Watchdog reads −1."""
        self._put("bus_watchdog", -1)
        self.watchdog_tripped_at = now
        self.halted = True
        self.traj, self.vel = self.pos, 0.0
    # -- faults and reboot ----------------------------------------------------------------
    def set_hardware_error(self, bits: int) -> None:
        self._put("hardware_error_status", bits & 0xFF)
        if bits:
            self._put("torque_enable", 0)

    def reboot(self, now: float, boot_time: float) -> None:
        """RAM back to defaults (torque off, hardware error cleared), silent for boot_time;
        torque on again if Startup Configuration (60) bit 0 is set."""
        self._reset_ram(self.pos)
        self.overload_s = 0.0
        self.booting_until = now + boot_time
        if "startup_configuration" in self.spec.fields and self.get("startup_configuration") & 1:
            self._put("torque_enable", 1)

    def factory_reset(self, option: int, now: float, boot_time: float) -> int:
        """Factory Reset (0x06): EEPROM to the factory defaults (ID 1, 57600 bit/s) except the
        ID (option 0x01) or the ID and baud rate (0x02), then a reboot. Returns the error code."""
        if option not in (P.FACTORY_RESET_ALL, P.FACTORY_RESET_KEEP_ID, P.FACTORY_RESET_KEEP_ID_BAUD):
            return P.ERR_DATA_RANGE
        keep = {"id": self.get("id")} if option != P.FACTORY_RESET_ALL else {}
        if option == P.FACTORY_RESET_KEEP_ID_BAUD:
            keep["baud_rate"] = self.get("baud_rate")
        self._eeprom_defaults = keep
        self._reset_eeprom()
        self.reboot(now, boot_time)
        return 0

    def clear_revolutions(self, params: bytes) -> int:
        """Clear (0x10): Present Position back into one turn (X: 0..4,095), only while stopped."""
        if params != P.CLEAR_REVOLUTION:
            return P.ERR_DATA_RANGE
        if abs(self.actual_vel) > 0.0 or abs(self.vel) > 0.0:
            return P.ERR_RESULT_FAIL
        lo, _ = self.spec.position_range
        n = self.spec.ticks_per_rev
        turns = math.floor((self.pos - lo) / n) * n
        self.pos -= turns
        self.traj -= turns
        self._put("goal_position", self.get("goal_position") - turns)
        self._sync_present(0.0)
        return 0
    # -- motion ---------------------------------------------------------------------------
    def propose(self, dt: float) -> float:
        """Advance the trajectory by dt; return where the shaft would be if unobstructed."""
        mode = self.get("operating_mode")
        if not self.torque_on or self.halted or mode not in _MOTION_MODES:
            self.traj, self.vel = self.pos, 0.0
            return self.pos
        goal = float(self.get("goal_position"))
        vmax = self.get("profile_velocity") or self.get("velocity_limit") or self.spec.field("velocity_limit").hi
        vmax *= velocity_unit_ticks_s(self.spec)
        amax = self.get("profile_acceleration") * accel_unit_ticks_s2(self.spec)
        err = goal - self.traj
        if amax > 0:
            # fastest speed from which a discrete-time deceleration at amax stops at the goal
            ad = amax * dt
            v_stop = ad * (math.sqrt(0.25 + 2.0 * abs(err) / (ad * dt)) - 0.5)
            v_des = math.copysign(min(vmax, v_stop), err)
            dv = max(-amax * dt, min(amax * dt, v_des - self.vel))
            self.vel += dv
        else:
            self.vel = math.copysign(vmax, err) if err else 0.0
        step = self.vel * dt
        if abs(step) >= abs(err):
            self.traj, self.vel = goal, 0.0
        else:
            self.traj += step
        return self.traj

    def settle(self, actual: float, dt: float) -> None:
        """Accept the (possibly obstructed) shaft position after a substep."""
        self.actual_vel = (actual - self.pos) / dt if dt > 0 else 0.0
        self.pos = actual

    def publish(self, dt: float, current: float | None = None) -> None:
        """Write the Present* items (position, velocity, current, moving) after a step of dt,
        and judge overload over it; ``current`` (raw units): the Present Current a torque
        balance sets (hand_driver.sim.errors, declared compliance), else the lag's."""
        self._sync_present(dt, current)
        self._judge_overload(dt)

    def drive_current(self, pos: float) -> float:
        """The Present Current (raw units, unrounded) the servo draws with its shaft at ``pos``
        ticks: its trajectory's lead times ``current_per_tick``, within :meth:`current_cap`; 0
        with torque off."""
        if not self.torque_on:
            return 0.0
        limit = self.current_cap()
        return max(-limit, min(limit, self._current_per_tick * (self.traj - pos)))

    def current_cap(self) -> int:
        """The largest |Present Current| (raw units) the servo draws: Goal Current in the modes
        where the e-Manual says it caps the current, else Current Limit."""
        limit = self.get("current_limit")
        if self.get("operating_mode") in self.spec.current_capped_modes:
            limit = min(limit, abs(self.get("goal_current")))
        return limit

    def _judge_overload(self, dt: float) -> None:
        if "present_current" in self.spec.fields:
            level, top = abs(self.get("present_current")), self.spec.current_limit_default
        else:
            level, top = abs(self.get("present_load")), 1000
        blocked = self.torque_on and abs(self.traj - self.pos) >= 1.0
        self.overload_s = self.overload_s + dt if blocked and level >= OVERLOAD_FRACTION * top else 0.0
        if self.overload_s >= OVERLOAD_TIME_S and self.get("shutdown") & OVERLOAD_BIT:
            self.set_hardware_error(self.hardware_error | OVERLOAD_BIT)

    def _sync_present(self, dt: float, current: float | None = None) -> None:
        gap = self.traj - self.pos
        if "present_current" in self.spec.fields:
            cur = self.drive_current(self.pos) if current is None else current
            self._put("present_current", int(round(cur)))
        else:  # XL430: Present Load in 0.1 % of max torque
            self._put("present_load", int(round(max(-1000.0, min(1000.0, LOAD_PER_TICK * gap)))) if self.torque_on else 0)
        vunit = velocity_unit_ticks_s(self.spec)
        pv = int(round(self.actual_vel / vunit))
        self._put("present_velocity", pv)
        self._put("present_position", int(round(self.pos)))
        self._put("position_trajectory", int(round(self.traj)))
        self._put("velocity_trajectory", int(round(self.vel / vunit)))
        moving = abs(pv) > self.get("moving_threshold")
        self._put("moving", int(moving))
        in_pos = abs(self.get("goal_position") - self.pos) <= 1.0
        profiling = abs(self.get("goal_position") - self.traj) > 0.5
        self._put("moving_status", int(in_pos) | (int(profiling) << 1))
        self.uptime_s += dt  # kept in seconds: a packet every 0.3 ms must not round each step to 0 ms
        self._put("realtime_tick", int(self.uptime_s * 1000.0) % 32768)
