"""One emulated servo: control-table access rules and motion toward its goal."""

import math

import pytest

from hand_driver.control_table import MODELS, model
from hand_driver.sim import protocol as P
from hand_driver.sim.servo import EmulatedServo, current_per_tick


def le(v, n):
    return (v & ((1 << (8 * n)) - 1)).to_bytes(n, "little")


def servo(name="XM430-W350"):
    return EmulatedServo(1, model(name), firmware=46, position=2048)


def test_memory_holds_model_number_and_firmware():
    for name, spec in MODELS.items():
        s = EmulatedServo(7, spec, firmware=45)
        assert s.read(0, 2) == (0, le(spec.number, 2))
        assert s.read(6, 2) == (0, bytes([45, 7]))


def test_access_rules():
    s = servo()
    assert s.write(132, le(0, 4)) == P.ERR_ACCESS  # read-only
    assert s.write(117, b"\x00") == P.ERR_DATA_LENGTH  # half of Goal Position
    assert s.write(64, b"\x02") == P.ERR_DATA_RANGE
    assert s.write(11, b"\x02") == P.ERR_DATA_RANGE  # no operating mode 2
    assert s.write(9, b"\x00") == 0  # EEPROM while torque off
    assert s.write(64, b"\x01") == 0
    assert s.write(9, b"\x05") == P.ERR_ACCESS  # EEPROM while torque on
    assert s.get("return_delay_time") == 0
    assert s.write(116, le(5000, 4)) == P.ERR_DATA_LIMIT  # beyond Max Position Limit
    assert s.read(660, 4)[0] == P.ERR_ACCESS  # past the table (662 bytes)


def test_xl430_has_no_current_items():
    s = servo("XL430-W250")
    assert s.write(102, le(10, 2)) == P.ERR_ACCESS
    assert s.write(11, b"\x05") == P.ERR_DATA_RANGE  # no current-based position mode


def test_profile_motion_reaches_goal_in_trapezoid_time():
    s = servo()
    s.write(112, le(100, 4))  # 22.9 rev/min
    s.write(108, le(20, 4))  # 4291.54 rev/min²
    s.write(64, b"\x01")
    s.write(116, le(3072, 4))
    v = 100 * 0.229 / 60 * 4096  # ticks/s
    a = 20 * 214.577 / 3600 * 4096  # ticks/s²
    dist = 1024
    t_expected = dist / v + v / a  # trapezoid: accelerate, cruise, decelerate
    t, dt = 0.0, 0.001
    while s.traj != 3072 and t < 10:
        s.settle(s.propose(dt), dt)
        s.publish(dt)
        t += dt
    assert t == pytest.approx(t_expected, abs=0.003)
    assert s.get("present_position") == 3072 and s.get("moving") == 0


def test_blocked_servo_current_rises_to_goal_current_and_free_is_zero():
    s = servo()
    s.write(11, b"\x05")
    s.write(102, le(100, 2))  # 269 mA cap
    s.write(64, b"\x01")
    s.write(116, le(2148, 4))
    for _ in range(50):  # free motion: the shaft follows the trajectory
        s.settle(s.propose(0.002), 0.002)
        s.publish(0.002)
        assert s.get("present_current") == 0
    wall = s.pos
    s.write(116, le(2500, 4))
    for k in range(400):  # blocked at the wall
        s.propose(0.002)
        s.settle(wall, 0.002)
        s.publish(0.002)
        gap = s.traj - wall
        assert s.get("present_current") == min(100, round(current_per_tick(s.spec) * gap))
        assert s.get("moving") == 0
    assert s.get("present_current") == 100


def test_hardware_error_drops_torque_until_reboot():
    s = servo()
    s.write(64, b"\x01")
    s.set_hardware_error(0x24)
    assert not s.torque_on and s.status_error() == 0x80
    assert s.write(64, b"\x01") == P.ERR_RESULT_FAIL
    s.reboot(now=0.0, boot_time=0.1)
    assert s.hardware_error == 0 and s.write(64, b"\x01") == 0


def test_units_of_velocity_match_emanual():
    # Present Velocity 1 unit = 0.229 rev/min
    s = servo()
    s.actual_vel = 0.229 / 60 * 4096 * 37
    s.publish(0.001)
    assert s.get("present_velocity") == 37
    assert math.isclose(model("XM430-W350").current_unit_ma, 2.69)
