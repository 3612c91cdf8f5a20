"""Unit conversions against the e-Manual's units, in closed form."""

import math

import numpy as np
from hypothesis import given, settings, strategies as st

from hand_driver import units
from hand_driver.control_table import MODELS, model

XM, XC, XL = model("XM430-W350"), model("XC330-T288"), model("XL430-W250")


def test_ticks_and_angles():
    assert units.ticks_to_rad(2048 + 1024, 2048, 1) == math.pi / 2
    assert units.ticks_to_rad(2048 + 1024, 2048, -1) == -math.pi / 2
    assert math.degrees(units.RAD_PER_TICK) == 360 / 4096  # 0.088° per tick
    assert units.rad_to_ticks(-math.pi / 2, 2048, -1) == 3072


@settings(max_examples=100, deadline=None)
@given(st.integers(0, 4095), st.integers(0, 4095), st.sampled_from([1, -1]))
def test_tick_angle_round_trip(tick, zero, direction):
    assert units.rad_to_ticks(units.ticks_to_rad(tick, zero, direction), zero, direction) == tick


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
    w = np.array([0.5, 1.0, 2.0])
    assert np.array_equal(units.rad_s_to_velocity(w, XM), np.rint(w / (0.229 * 2 * math.pi / 60)))


def test_control_table_facts():
    for spec in MODELS.values():
        for name, addr in (("torque_enable", 64), ("goal_position", 116), ("present_position", 132),
                           ("moving", 122), ("hardware_error_status", 70), ("return_delay_time", 9)):
            assert spec.field(name).addr == addr
    assert "present_current" not in XL.fields and XL.field("present_load").addr == 126
    assert {m.number for m in MODELS.values()} == {1020, 1060, 1210, 1220, 1230, 1240}
