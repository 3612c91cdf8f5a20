"""Unit conversions between raw control-table values and SI units: pure functions.

The one definition of every unit of the driver and the emulator. Encoder: 4096 ticks per
turn, joint angle ``q = direction · (tick − zero_tick) · 2π/4096`` (docs/ARCHITECTURE.md).
The per-model units live in the model's :class:`~hand_driver.control_table.ModelSpec`:
velocity 0.229 rev/min, acceleration 214.577 rev/min², current (XM430: 2.69 mA, XC330:
1 mA, XL430: none). All functions accept scalars or numpy arrays.
"""

from __future__ import annotations

import math

import numpy as np

from hand_driver.control_table import ModelSpec

TICKS_PER_REV = 4096
RAD_PER_TICK = 2.0 * math.pi / TICKS_PER_REV
#: the encoder's quantization: ±½ tick per joint
HALF_TICK_RAD = 0.5 * RAD_PER_TICK
#: Bus Watchdog (98) unit, ms
WATCHDOG_STEP_MS = 20
_RPM_TO_RAD_S = 2.0 * math.pi / 60.0
_RPM2_TO_RAD_S2 = 2.0 * math.pi / 3600.0


def ticks_to_rad(ticks, zero_tick, direction):
    """Joint angle in rad from encoder ticks."""
    return direction * (np.asarray(ticks, dtype=float) - zero_tick) * RAD_PER_TICK


def rad_to_ticks_exact(q, zero_tick, direction):
    """Encoder position (float ticks, not rounded) of a joint angle in rad."""
    return zero_tick + np.asarray(q, dtype=float) / (direction * RAD_PER_TICK)


def rad_to_ticks(q, zero_tick, direction):
    """Nearest encoder tick (int, or int array) for a joint angle in rad."""
    t = np.rint(rad_to_ticks_exact(q, zero_tick, direction)).astype(np.int64)
    return int(t) if t.ndim == 0 else t


def deg_to_ticks_exact(deg, zero_tick, direction):
    """Encoder position (float ticks) of a joint angle in degrees."""
    return zero_tick + direction * np.asarray(deg, dtype=float) * TICKS_PER_REV / 360.0


def velocity_unit_ticks_s(spec: ModelSpec) -> float:
    """One raw velocity unit (Present Velocity, Profile Velocity) in encoder ticks/s."""
    return spec.velocity_unit_rpm * (TICKS_PER_REV / 60.0)


def accel_unit_ticks_s2(spec: ModelSpec) -> float:
    """One raw Profile Acceleration unit in encoder ticks/s²."""
    return spec.accel_unit_rpm2 * (TICKS_PER_REV / 60.0) / 60.0


def current_to_ma(raw, spec: ModelSpec):
    """Present/Goal Current raw value → mA. Refuses models without current sensing."""
    if spec.current_unit_ma is None:
        raise ValueError(f"{spec.name} has no current sensing (address 126 is Present Load, not current)")
    return np.asarray(raw, dtype=float) * spec.current_unit_ma


def ma_to_current(ma, spec: ModelSpec):
    """mA → nearest raw current value (int or int array)."""
    if spec.current_unit_ma is None:
        raise ValueError(f"{spec.name} has no current sensing (address 126 is Present Load, not current)")
    r = np.rint(np.asarray(ma, dtype=float) / spec.current_unit_ma).astype(np.int64)
    return int(r) if r.ndim == 0 else r


def velocity_to_rad_s(raw, spec: ModelSpec):
    """Present Velocity / Profile Velocity raw value → rad/s (of the output shaft)."""
    return np.asarray(raw, dtype=float) * spec.velocity_unit_rpm * _RPM_TO_RAD_S


def rad_s_to_velocity(w, spec: ModelSpec):
    """rad/s → nearest raw velocity value (int or int array)."""
    r = np.rint(np.asarray(w, dtype=float) / (spec.velocity_unit_rpm * _RPM_TO_RAD_S)).astype(np.int64)
    return int(r) if r.ndim == 0 else r


def accel_to_rad_s2(raw, spec: ModelSpec):
    """Profile Acceleration raw value → rad/s²."""
    return np.asarray(raw, dtype=float) * spec.accel_unit_rpm2 * _RPM2_TO_RAD_S2


def rad_s2_to_accel(a, spec: ModelSpec):
    """rad/s² → nearest raw Profile Acceleration value (int or int array)."""
    r = np.rint(np.asarray(a, dtype=float) / (spec.accel_unit_rpm2 * _RPM2_TO_RAD_S2)).astype(np.int64)
    return int(r) if r.ndim == 0 else r

