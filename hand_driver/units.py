"""Unit conversions between raw control-table values and SI units: pure functions.

The one definition of every unit of the driver and the emulator. Every unit is the joint's
model's (hand_driver.control_table.ModelSpec, from its e-Manual page): encoder
``ticks_per_rev`` pulses per output turn (X-series 4,096; DYNAMIXEL-P 502,834–1,003,846),
joint angle ``q = direction · (tick − zero_tick) · 2π / ticks_per_rev`` (docs/ARCHITECTURE.md);
velocity (X 0.229, P 0.01 rev/min), acceleration (X 214.577, P 1 rev/min²), current (XM430
2.69 mA, XC330 and P 1 mA, XL430 none). A jaw may mix models: each joint converts with its
own. All functions accept scalars or numpy arrays (``ticks_per_rev`` too, one per joint).
"""

from __future__ import annotations

import math

import numpy as np

from hand_driver.control_table import ModelSpec

#: Bus Watchdog unit, ms (X: address 98, P: 546; the same 20 ms on both families)
WATCHDOG_STEP_MS = 20
_RPM_TO_RAD_S = 2.0 * math.pi / 60.0
_RPM2_TO_RAD_S2 = 2.0 * math.pi / 3600.0


def rad_per_tick(ticks_per_rev):
    """One encoder tick in rad (scalar or per joint)."""
    return 2.0 * math.pi / np.asarray(ticks_per_rev, dtype=float)


def half_tick_rad(ticks_per_rev):
    """The encoder's quantization, ±½ tick, in rad."""
    return 0.5 * rad_per_tick(ticks_per_rev)


def ticks_to_rad(ticks, zero_tick, direction, ticks_per_rev):
    """Joint angle in rad from encoder ticks."""
    return direction * (np.asarray(ticks, dtype=float) - zero_tick) * rad_per_tick(ticks_per_rev)


def rad_to_ticks_exact(q, zero_tick, direction, ticks_per_rev):
    """Encoder position (float ticks, not rounded) of a joint angle in rad."""
    return zero_tick + np.asarray(q, dtype=float) / (direction * rad_per_tick(ticks_per_rev))


def rad_to_ticks(q, zero_tick, direction, ticks_per_rev):
    """Nearest encoder tick (int, or int array) for a joint angle in rad."""
    t = np.rint(rad_to_ticks_exact(q, zero_tick, direction, ticks_per_rev)).astype(np.int64)
    return int(t) if t.ndim == 0 else t


def deg_to_ticks_exact(deg, zero_tick, direction, ticks_per_rev):
    """Encoder position (float ticks) of a joint angle in degrees."""
    return zero_tick + direction * np.asarray(deg, dtype=float) * np.asarray(ticks_per_rev, dtype=float) / 360.0


def velocity_unit_ticks_s(spec: ModelSpec) -> float:
    """One raw velocity unit (Present Velocity, Profile Velocity) in encoder ticks/s."""
    return spec.velocity_unit_rpm * (spec.ticks_per_rev / 60.0)


def accel_unit_ticks_s2(spec: ModelSpec) -> float:
    """One raw Profile Acceleration unit in encoder ticks/s²."""
    return spec.accel_unit_rpm2 * (spec.ticks_per_rev / 60.0) / 60.0


def _no_sensing(spec: ModelSpec) -> ValueError:
    load = spec.fields.get("present_load")
    where = f"address {load.addr} is Present Load, not current" if load is not None else "no Present Current"
    return ValueError(f"{spec.name} has no current sensing ({where})")


def current_to_ma(raw, spec: ModelSpec):
    """Present/Goal Current raw value → mA. Refuses models without current sensing."""
    if spec.current_unit_ma is None:
        raise _no_sensing(spec)
    return np.asarray(raw, dtype=float) * spec.current_unit_ma


def ma_to_current(ma, spec: ModelSpec):
    """mA → nearest raw current value (int or int array)."""
    if spec.current_unit_ma is None:
        raise _no_sensing(spec)
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
