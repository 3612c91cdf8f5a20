"""Register fields at the byte level: little-endian, two's complement when signed (e-Manual
control tables), one codec for the driver and the emulator."""

import pytest
from hypothesis import given, settings, strategies as st

from hand_driver.control_table import COMMON_FIELDS, FIELD_SIZES, MODELS, Field, decode_field, encode_field

XM = MODELS["XM430-W350"]
GOAL_POSITION = XM.field("goal_position")  # 116, 4 bytes, signed
PRESENT_CURRENT = XM.field("present_current")  # 126, 2 bytes, signed
BUS_WATCHDOG = XM.field("bus_watchdog")  # 98, 1 byte, signed
MODEL_NUMBER = COMMON_FIELDS["model_number"]  # 0, 2 bytes, unsigned
PROFILE_VELOCITY = XM.field("profile_velocity")  # 112, 4 bytes, unsigned
TORQUE_ENABLE = XM.field("torque_enable")  # 64, 1 byte, unsigned


def test_known_bytes():
    # e-Manual examples: Goal Position 512 = 0x00000200 is sent as 00 02 00 00
    assert encode_field(GOAL_POSITION, 512) == bytes([0x00, 0x02, 0x00, 0x00])
    assert encode_field(GOAL_POSITION, -1) == b"\xff\xff\xff\xff"
    assert encode_field(GOAL_POSITION, -(2**31)) == b"\x00\x00\x00\x80"
    assert encode_field(PRESENT_CURRENT, -2) == b"\xfe\xff"
    assert encode_field(BUS_WATCHDOG, -1) == b"\xff"
    assert encode_field(MODEL_NUMBER, 1020) == bytes([0xFC, 0x03])
    assert encode_field(PROFILE_VELOCITY, 2**32 - 1) == b"\xff\xff\xff\xff"
    assert decode_field(GOAL_POSITION, b"\xff\xff\xff\xff") == -1
    assert decode_field(GOAL_POSITION, b"\xff\xff\xff\x7f") == 2**31 - 1
    assert decode_field(PROFILE_VELOCITY, b"\xff\xff\xff\xff") == 2**32 - 1
    assert decode_field(PRESENT_CURRENT, [0x00, 0x80]) == -32768  # a list, as the SDK returns
    assert decode_field(MODEL_NUMBER, bytearray([0xFC, 0x03])) == 1020
    assert decode_field(BUS_WATCHDOG, b"\xff") == -1 and decode_field(TORQUE_ENABLE, b"\xff") == 255


def test_decode_at_offset_reads_only_the_field():
    block = bytes([1, 0x23, 0x01, 0xFE, 0xFF, 0xFF, 0xFF, 9])
    assert decode_field(GOAL_POSITION, block, 3) == -2
    assert decode_field(MODEL_NUMBER, block, 1) == 0x0123
    assert decode_field(TORQUE_ENABLE, block, 7) == 9


def test_bounds_by_width_and_sign():
    assert Field("a", 0, 1, "R").bounds == (0, 255)
    assert Field("a", 0, 1, "R", signed=True).bounds == (-128, 127)
    assert Field("a", 0, 2, "R", signed=True).bounds == (-32768, 32767)
    assert Field("a", 0, 4, "R").bounds == (0, 2**32 - 1)
    assert Field("a", 0, 4, "R", signed=True).bounds == (-(2**31), 2**31 - 1)


@pytest.mark.parametrize("field, value", [
    (GOAL_POSITION, 2**31), (GOAL_POSITION, -(2**31) - 1), (PRESENT_CURRENT, 32768),
    (BUS_WATCHDOG, 128), (MODEL_NUMBER, -1), (MODEL_NUMBER, 65536), (TORQUE_ENABLE, 256),
    (PROFILE_VELOCITY, 2**32), (PROFILE_VELOCITY, -1),
])
def test_out_of_bounds_is_a_clear_error(field, value):
    with pytest.raises(ValueError, match=rf"^{field.name}: {value} does not fit in {field.size} "
                                         rf"({'signed' if field.signed else 'unsigned'}) byte\(s\)"):
        encode_field(field, value)


def test_non_integers_and_short_data_are_clear_errors():
    with pytest.raises(ValueError, match=r"^goal_position: 1\.5 is not an integer$"):
        encode_field(GOAL_POSITION, 1.5)
    with pytest.raises(ValueError, match=r"^goal_position needs 4 byte\(s\) at offset 2, got 2$"):
        decode_field(GOAL_POSITION, b"\x00\x01\x02\x03", 2)
    with pytest.raises(ValueError, match="size 3 is not one of"):
        Field("odd", 0, 3, "R")


def test_numpy_integers_are_accepted():
    np = pytest.importorskip("numpy")
    assert encode_field(GOAL_POSITION, np.int64(-5)) == encode_field(GOAL_POSITION, -5)


@settings(max_examples=300, deadline=None)
@given(st.sampled_from(FIELD_SIZES), st.booleans(), st.data())
def test_round_trip_and_twos_complement(size, signed, data):
    f = Field("x", 0, size, "RW", signed=signed)
    lo, hi = f.bounds
    v = data.draw(st.integers(lo, hi))
    b = encode_field(f, v)
    assert len(b) == size and decode_field(f, b) == v
    assert int.from_bytes(b, "little") == v % (1 << (8 * size))  # two's complement bit pattern


def test_profile_block_is_contiguous():
    # the profile is written as one 8-byte block (X 108..115, P 556..563; JointBus.set_profile_raw)
    for spec in MODELS.values():
        acc, vel = spec.field("profile_acceleration"), spec.field("profile_velocity")
        assert vel.addr == acc.addr + acc.size and acc.size == vel.size == 4
