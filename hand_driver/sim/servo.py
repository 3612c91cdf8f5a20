"""One emulated X-series servo: control-table memory and motion toward its goal.

Memory follows the model's control table (hand_driver.control_table): reads return the
bytes; writes check access (read-only items, EEPROM while torque is on → access error),
whole-item coverage (data length error), static ranges (data range error) and the
position/current/velocity limits (data limit error). In position and current-based
position mode the servo follows a trapezoidal profile (Profile Velocity/Acceleration;
0 means unlimited, capped by Velocity Limit) toward Goal Position. The host of the servo
(the emulated bus) may block the motion (a pad touching the object): Present Current
then rises with the gap between trajectory and actual position, clipped at Goal Current
(or Current Limit); it is 0 while the shaft follows its trajectory freely.
A hardware error (set on demand) turns torque off, sets the alert bit of every status
packet and keeps torque off until reboot, as real servos do.
"""

from __future__ import annotations

import math

from hand_driver.control_table import (
    MODE_CURRENT_BASED_POSITION,
    MODE_EXTENDED_POSITION,
    MODE_POSITION,
    ModelSpec,
)
from hand_driver.sim import protocol as P
from hand_driver.units import accel_unit_ticks_s2, to_signed, to_unsigned, velocity_unit_ticks_s

# Present Current per tick of trajectory-following error when blocked (raw current units).
CURRENT_PER_TICK = 8.0
TABLE_SIZE = 228


class EmulatedServo:
    """Control-table memory plus a simple motion model, stepped by the bus."""

    def __init__(self, dxl_id: int, spec: ModelSpec, firmware: int = 46, position: int = 2048,
                 baud_register: int = 3):
        self.spec = spec
        self.firmware = firmware
        self.mem = bytearray(TABLE_SIZE)
        self._eeprom_defaults = {"id": dxl_id, "baud_rate": baud_register}
        self._reset_eeprom()
        self._reset_ram(position)
        self.booting_until = 0.0  # sim time before which the servo does not answer (reboot)
        self.registered: tuple[int, bytes] | None = None

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
        self._put("goal_position", int(round(position)))
        if "goal_current" in self.spec.fields:
            self._put("goal_current", self.spec.current_limit_default)
        self._sync_present(0.0)

    def get(self, name: str) -> int:
        f = self.spec.field(name)
        v = int.from_bytes(self.mem[f.addr : f.addr + f.size], "little")
        return to_signed(v, f.size) if f.signed else v

    def _put(self, name: str, value: int) -> None:
        f = self.spec.field(name)
        self.mem[f.addr : f.addr + f.size] = to_unsigned(int(value), f.size).to_bytes(f.size, "little")

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

    def read(self, addr: int, length: int) -> tuple[int, bytes]:
        """(error code, data) of a Read of ``length`` bytes from ``addr``."""
        if length == 0 or addr + length > TABLE_SIZE:
            return P.ERR_ACCESS, b""
        return 0, bytes(self.mem[addr : addr + length])

    def check_write(self, addr: int, data: bytes) -> int:
        """The error code a Write would get (0: accepted)."""
        end = addr + len(data)
        if not data or end > TABLE_SIZE:
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
            raw = int.from_bytes(data[f.addr - addr : f.addr - addr + f.size], "little")
            v = to_signed(raw, f.size) if f.signed else raw
            if (f.lo is not None and v < f.lo) or (f.hi is not None and v > f.hi):
                return P.ERR_DATA_RANGE
            if self._beyond_limit(f.name, v):
                return P.ERR_DATA_LIMIT
            if f.name == "operating_mode" and v not in self.spec.operating_modes:
                return P.ERR_DATA_RANGE
            if f.name == "torque_enable" and v == 1 and self.hardware_error:
                return P.ERR_RESULT_FAIL
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
        self.mem[addr : addr + len(data)] = data
        goal = self.spec.field("goal_position")
        if addr <= goal.addr < addr + len(data):
            # a new goal starts a new profile from where the shaft is
            self.traj, self.vel = self.pos, self.actual_vel
        return 0

    # -- faults and reboot ----------------------------------------------------------------
    def set_hardware_error(self, bits: int) -> None:
        self._put("hardware_error_status", bits & 0xFF)
        if bits:
            self._put("torque_enable", 0)

    def reboot(self, now: float, boot_time: float) -> None:
        """RAM back to defaults (torque off, hardware error cleared), silent for boot_time."""
        self._reset_ram(self.pos)
        self.booting_until = now + boot_time

    # -- motion ---------------------------------------------------------------------------
    def propose(self, dt: float) -> float:
        """Advance the trajectory by dt; return where the shaft would be if unobstructed."""
        mode = self.get("operating_mode")
        if not self.torque_on or mode not in (MODE_POSITION, MODE_EXTENDED_POSITION, MODE_CURRENT_BASED_POSITION):
            self.traj, self.vel = self.pos, 0.0
            return self.pos
        goal = float(self.get("goal_position"))
        vmax = self.get("profile_velocity") or self.get("velocity_limit") or 1023
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

    def publish(self, dt: float) -> None:
        """Write the Present* items (position, velocity, current, moving) after a step of dt."""
        self._sync_present(dt)

    def _sync_present(self, dt: float) -> None:
        gap = self.traj - self.pos
        if "present_current" in self.spec.fields:
            limit = abs(self.get("goal_current")) if "goal_current" in self.spec.fields else 0
            limit = min(limit, self.get("current_limit")) if self.get("current_limit") else limit
            cur = max(-limit, min(limit, CURRENT_PER_TICK * gap)) if self.torque_on else 0.0
            self._put("present_current", int(round(cur)))
        else:  # XL430: Present Load in 0.1 % of max torque
            self._put("present_load", int(round(max(-1000.0, min(1000.0, 5.0 * gap)))) if self.torque_on else 0)
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
        self._put("realtime_tick", (self.get("realtime_tick") + int(dt * 1000)) % 32768)
