"""Unit conversions against the e-Manual's units, in closed form."""

import math

import numpy as np
from hypothesis import given, settings, strategies as st

from hand_driver import units
from hand_driver.control_table import MODELS, model

XM, XC, XL = model("XM430-W350"), model("XC330-T288"), model("XL430-W250")
PH54, PH42, PM54, PM42 = (model(n) for n in ("PH54-200-S500-R", "PH42-020-S300-R", "PM54-040-S250-R",
                                            "PM42-010-S260-R"))


def test_ticks_and_angles():
    assert units.ticks_to_rad(2048 + 1024, 2048, 1, 4096) == math.pi / 2
    assert units.ticks_to_rad(2048 + 1024, 2048, -1, 4096) == -math.pi / 2
    assert math.degrees(XM.rad_per_tick) == 360 / 4096  # 0.088° per tick
    assert units.rad_to_ticks(-math.pi / 2, 2048, -1, 4096) == 3072
    # e-Manual: PH54 ±501,923 pulses = ±180° (1,003,846 per turn), PH42 607,500, PM54 502,834, PM42 526,374
    assert units.ticks_to_rad(501_923, 0, 1, PH54.ticks_per_rev) == math.pi
    assert units.ticks_to_rad(-303_750, 0, 1, PH42.ticks_per_rev) == -math.pi
    assert units.ticks_to_rad(251_417, 0, -1, PM54.ticks_per_rev) == -math.pi
    assert units.ticks_to_rad(263_187, 0, 1, PM42.ticks_per_rev) == math.pi
    assert units.rad_to_ticks(math.pi / 2, 0, 1, PH54.ticks_per_rev) == 250_962  # 1,003,846 / 4 = 250,961.5
    # per joint: a jaw may mix models
    q = units.ticks_to_rad([3072, 151_875], [2048, 0], [1, 1], [4096, PH42.ticks_per_rev])
    assert np.allclose(q, [math.pi / 2, math.pi / 2], rtol=0, atol=1e-15)


@settings(max_examples=100, deadline=None)
@given(st.sampled_from([XM, PH54, PH42, PM54, PM42]), st.data(), st.sampled_from([1, -1]))
def test_tick_angle_round_trip(spec, data, direction):
    lo, hi = spec.position_range
    tick, zero = data.draw(st.integers(lo, hi)), data.draw(st.integers(lo, hi))
    n = spec.ticks_per_rev
    assert units.rad_to_ticks(units.ticks_to_rad(tick, zero, direction, n), zero, direction, n) == tick


def test_current_units_per_model():
    assert units.current_to_ma(100, XM) == 269.0
    assert units.current_to_ma(100, XC) == 100.0
    assert units.ma_to_current(1000.0, XM) == 372  # 1000 / 2.69 = 371.7
    try:
        units.current_to_ma(1, XL)
    except ValueError as exc:
        assert "Present Load, not current" in str(exc)
    else:
        raise AssertionError("XL430 has no current sensing")


def test_velocity_and_acceleration_units():
    assert math.isclose(units.velocity_to_rad_s(1, XM), 0.229 * 2 * math.pi / 60)
    assert math.isclose(units.accel_to_rad_s2(1, XM), 214.577 * 2 * math.pi / 3600)
    # DYNAMIXEL-P: 0.01 rev/min, 1 rev/min² (e-Manual Profile Velocity(560), Acceleration Limit(40))
    assert math.isclose(units.velocity_to_rad_s(100, PH54), 1.0 * 2 * math.pi / 60)
    assert math.isclose(units.accel_to_rad_s2(3600, PM42), 2 * math.pi)
    assert math.isclose(units.velocity_unit_ticks_s(PH54), 0.01 * 1_003_846 / 60)
    assert units.current_to_ma(550, PH42) == 550.0 and units.ma_to_current(300.4, PM54) == 300
    w = np.array([0.5, 1.0, 2.0])
    assert np.array_equal(units.rad_s_to_velocity(w, XM), np.rint(w / (0.229 * 2 * math.pi / 60)))


def test_control_table_facts():
    x_addresses = (("torque_enable", 64), ("goal_position", 116), ("present_position", 132), ("moving", 122),
                   ("hardware_error_status", 70), ("return_delay_time", 9), ("bus_watchdog", 98))
    # e-Manual DYNAMIXEL-P control table (RAM area from 512)
    p_addresses = (("torque_enable", 512), ("hardware_error_status", 518), ("bus_watchdog", 546),
                   ("goal_current", 550), ("profile_acceleration", 556), ("profile_velocity", 560),
                   ("goal_position", 564), ("moving", 570), ("present_current", 574), ("present_velocity", 576),
                   ("present_position", 580), ("current_limit", 38), ("max_position_limit", 48),
                   ("min_position_limit", 52), ("return_delay_time", 9), ("operating_mode", 11))
    for spec in MODELS.values():
        for name, addr in x_addresses if spec.family == "X" else p_addresses:
            assert spec.field(name).addr == addr, (spec.name, name)
    assert "present_current" not in XL.fields and XL.field("present_load").addr == 126
    assert {m.number: m.name for m in MODELS.values() if m.family == "P"} == {
        2020: "PH54-200-S500-R", 2010: "PH54-100-S500-R", 2000: "PH42-020-S300-R",
        2120: "PM54-060-S250-R", 2110: "PM54-040-S250-R", 2100: "PM42-010-S260-R"}
    assert {m.number for m in MODELS.values() if m.family == "X"} == {1020, 1060, 1210, 1220, 1230, 1240}
    for spec in MODELS.values():
        if spec.family == "P":  # no current-based position mode: position mode, Goal Current caps it
            assert 5 not in spec.operating_modes and spec.guard_mode == 3 in spec.current_capped_modes
            lo, hi = spec.position_range
            assert hi - lo == spec.ticks_per_rev - (spec.ticks_per_rev % 2) and lo == -hi
            assert spec.backlash_deg == 0.1 and spec.current_unit_ma == 1.0
        else:
            assert spec.ticks_per_rev == 4096 and spec.position_range == (0, 4095)
