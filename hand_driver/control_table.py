"""Control tables of the supported Dynamixel X-series models, as data.

Source: ROBOTIS e-Manual control tables of XM430-W350, XC330-T288/M288/T181/M181 and
XL430-W250 (Protocol 2.0). Addresses agree across these models except that the XL430
has no Current Limit (38) nor Goal Current (102), and its address 126 is Present Load
(0.1 % of maximum torque), which is not a current: an XL430 cannot do current-based
guarded touches. XC330 servos measure current at their power input (1 mA units), not
in the motor as the XM430 (2.69 mA units) does.
"""

from __future__ import annotations

import operator
from dataclasses import dataclass

#: the widths a control-table item can have, bytes
FIELD_SIZES = (1, 2, 4)


@dataclass(frozen=True)
class Field:
    """One control-table item. ``lo``/``hi`` is the static value range (None: any); the
    item's bytes are little-endian, two's complement when ``signed`` (e-Manual, Protocol
    2.0 control table): :func:`decode_field` / :func:`encode_field`."""

    name: str
    addr: int
    size: int
    access: str  # "R" or "RW"
    eeprom: bool = False
    signed: bool = False
    lo: int | None = None
    hi: int | None = None
    default: int = 0

    def __post_init__(self) -> None:
        if self.size not in FIELD_SIZES:
            raise ValueError(f"control-table item {self.name}: size {self.size} is not one of {FIELD_SIZES} bytes")

    @property
    def bounds(self) -> tuple[int, int]:
        """The values the item's width and signedness can hold (not its static range)."""
        bits = 8 * self.size
        return (-(1 << (bits - 1)), (1 << (bits - 1)) - 1) if self.signed else (0, (1 << bits) - 1)


def decode_field(f: Field, data, offset: int = 0) -> int:
    """The value of item ``f`` from its ``f.size`` bytes at ``data[offset:]`` (bytes,
    bytearray or a list of byte values, as the SDK returns): little-endian, two's complement
    when ``f.signed``. ValueError when fewer than ``f.size`` bytes are there."""
    raw = data[offset : offset + f.size]
    if len(raw) != f.size:
        raise ValueError(f"{f.name} needs {f.size} byte(s) at offset {offset}, got {len(raw)}")
    return int.from_bytes(raw, "little", signed=f.signed)


def encode_field(f: Field, value) -> bytes:
    """The ``f.size`` little-endian bytes of ``value`` in item ``f`` (two's complement when
    ``f.signed``). ValueError when ``value`` is not an integer or does not fit the item's
    width and signedness (:attr:`Field.bounds`); the static range ``lo``/``hi`` is the
    servo's check, not this one."""
    try:
        v = operator.index(value)
    except TypeError:
        raise ValueError(f"{f.name}: {value!r} is not an integer") from None
    lo, hi = f.bounds
    if not lo <= v <= hi:
        kind = "signed" if f.signed else "unsigned"
        raise ValueError(f"{f.name}: {v} does not fit in {f.size} {kind} byte(s) ({lo}..{hi})")
    return v.to_bytes(f.size, "little", signed=f.signed)


def _common_fields() -> list[Field]:
    return [
        Field("model_number", 0, 2, "R", True),
        Field("model_information", 2, 4, "R", True),
        Field("firmware_version", 6, 1, "R", True),
        Field("id", 7, 1, "RW", True, lo=0, hi=252, default=1),
        Field("baud_rate", 8, 1, "RW", True, lo=0, hi=7, default=1),
        Field("return_delay_time", 9, 1, "RW", True, lo=0, hi=254, default=250),
        Field("drive_mode", 10, 1, "RW", True, lo=0, hi=13),
        Field("operating_mode", 11, 1, "RW", True, lo=0, hi=16, default=3),
        Field("secondary_id", 12, 1, "RW", True, lo=0, hi=255, default=255),
        Field("protocol_type", 13, 1, "RW", True, lo=1, hi=22, default=2),
        Field("homing_offset", 20, 4, "RW", True, True, -1044479, 1044479),
        Field("moving_threshold", 24, 4, "RW", True, lo=0, hi=1023, default=10),
        Field("temperature_limit", 31, 1, "RW", True, lo=0, hi=100, default=80),
        Field("max_voltage_limit", 32, 2, "RW", True, default=160),
        Field("min_voltage_limit", 34, 2, "RW", True, default=95),
        Field("pwm_limit", 36, 2, "RW", True, lo=0, hi=885, default=885),
        Field("velocity_limit", 44, 4, "RW", True, lo=0, hi=1023, default=200),
        Field("max_position_limit", 48, 4, "RW", True, lo=0, hi=4095, default=4095),
        Field("min_position_limit", 52, 4, "RW", True, lo=0, hi=4095, default=0),
        Field("startup_configuration", 60, 1, "RW", True, lo=0, hi=3),
        Field("shutdown", 63, 1, "RW", True, lo=0, hi=255, default=52),
        Field("torque_enable", 64, 1, "RW", lo=0, hi=1),
        Field("led", 65, 1, "RW", lo=0, hi=1),
        Field("status_return_level", 68, 1, "RW", lo=0, hi=2, default=2),
        Field("registered_instruction", 69, 1, "R"),
        Field("hardware_error_status", 70, 1, "R"),
        Field("velocity_i_gain", 76, 2, "RW", lo=0, hi=16383, default=1920),
        Field("velocity_p_gain", 78, 2, "RW", lo=0, hi=16383, default=100),
        Field("position_d_gain", 80, 2, "RW", lo=0, hi=16383),
        Field("position_i_gain", 82, 2, "RW", lo=0, hi=16383),
        Field("position_p_gain", 84, 2, "RW", lo=0, hi=16383, default=800),
        # 20 ms units; 0 disables (and clears the error); reads −1 after it expired
        Field("bus_watchdog", 98, 1, "RW", signed=True, lo=0, hi=127),
        Field("goal_pwm", 100, 2, "RW", signed=True, lo=-885, hi=885),
        Field("goal_velocity", 104, 4, "RW", signed=True),
        Field("profile_acceleration", 108, 4, "RW", lo=0, hi=32767),
        Field("profile_velocity", 112, 4, "RW", lo=0, hi=32767),
        Field("goal_position", 116, 4, "RW", signed=True),
        Field("realtime_tick", 120, 2, "R"),
        Field("moving", 122, 1, "R"),
        Field("moving_status", 123, 1, "R"),
        Field("present_pwm", 124, 2, "R", signed=True),
        Field("present_current", 126, 2, "R", signed=True),
        Field("present_velocity", 128, 4, "R", signed=True),
        Field("present_position", 132, 4, "R", signed=True),
        Field("velocity_trajectory", 136, 4, "R", signed=True),
        Field("position_trajectory", 140, 4, "R", signed=True),
        Field("present_input_voltage", 144, 2, "R", default=120),
        Field("present_temperature", 146, 1, "R", default=30),
        *_indirect_fields(),
    ]


#: Indirect Address k (2 bytes, pointing anywhere in 64..661) and Indirect Data k (the byte
#: at that address, read and written through it): k = 1..28 and 29..56, each Indirect
#: Address defaulting to its own Indirect Data's address
INDIRECT_BLOCKS = ((1, 28, 168, 224), (29, 56, 578, 634))
#: bytes of the control table (the last item is Indirect Data 56 at 661)
TABLE_SIZE = 662


def _indirect_fields() -> list[Field]:
    out = []
    for first, last, addr0, data0 in INDIRECT_BLOCKS:
        for k in range(first, last + 1):
            data = data0 + k - first
            out.append(Field(f"indirect_address_{k}", addr0 + 2 * (k - first), 2, "RW", lo=64, hi=TABLE_SIZE - 1,
                             default=data))
            out.append(Field(f"indirect_data_{k}", data, 1, "RW"))
    return out


@dataclass(frozen=True)
class ModelSpec:
    """Everything the driver and the emulator need to know about one model."""

    name: str
    number: int
    fields: dict[str, Field]
    current_unit_ma: float | None  # None: no current sensing (Present Load instead)
    current_limit_default: int | None  # raw units
    operating_modes: tuple[int, ...]
    baud_rates: dict[int, int]  # register value -> bit/s
    fast_sync_read: bool = True
    velocity_unit_rpm: float = 0.229
    accel_unit_rpm2: float = 214.577

    @property
    def has_current_sensing(self) -> bool:
        return self.current_unit_ma is not None

    def field(self, name: str) -> Field:
        try:
            return self.fields[name]
        except KeyError:
            raise KeyError(f"{self.name} has no control-table item {name!r}") from None

    def baud_register(self, baudrate: int) -> int:
        """The Baud Rate (8) register value selecting ``baudrate`` bit/s; ValueError if none."""
        for reg, bps in self.baud_rates.items():
            if bps == baudrate:
                return reg
        raise ValueError(f"{self.name} cannot talk at {baudrate} bit/s; it knows {sorted(self.baud_rates.values())}")

    def field_at(self, addr: int) -> Field | None:
        for f in self.fields.values():
            if f.addr == addr:
                return f
        return None


# Operating modes (address 11).
MODE_CURRENT = 0
MODE_VELOCITY = 1
MODE_POSITION = 3
MODE_EXTENDED_POSITION = 4
MODE_CURRENT_BASED_POSITION = 5
MODE_PWM = 16

_BAUD_X430 = {0: 9600, 1: 57600, 2: 115200, 3: 1_000_000, 4: 2_000_000, 5: 3_000_000, 6: 4_000_000, 7: 4_500_000}
_BAUD_X330 = {k: v for k, v in _BAUD_X430.items() if k <= 6}

# Hardware Error Status (70) bits.
HARDWARE_ERROR_BITS = {
    0: "input voltage error",
    2: "overheating error",
    3: "motor encoder error",
    4: "electrical shock error",
    5: "overload error",
}

# Protocol 2.0 status packet error codes (low 7 bits); bit 7 is the hardware alert.
STATUS_ERRORS = {
    1: "result fail",
    2: "instruction error",
    3: "CRC error",
    4: "data range error",
    5: "data length error",
    6: "data limit error",
    7: "access error",
}
ALERT_BIT = 0x80


def decode_hardware_error(bits: int) -> list[str]:
    """Names of the set bits of Hardware Error Status (70)."""
    return [name for bit, name in HARDWARE_ERROR_BITS.items() if bits & (1 << bit)]


def _with(fields: list[Field], *extra: Field, drop: tuple[str, ...] = ()) -> dict[str, Field]:
    out = {f.name: f for f in fields if f.name not in drop}
    for f in extra:
        out[f.name] = f
    return dict(sorted(out.items(), key=lambda kv: kv[1].addr))


def _xm430_w350() -> ModelSpec:
    fields = _with(
        _common_fields(),
        Field("current_limit", 38, 2, "RW", True, lo=0, hi=1193, default=1193),
        Field("goal_current", 102, 2, "RW", signed=True, lo=-1193, hi=1193),
    )
    return ModelSpec("XM430-W350", 1020, fields, 2.69, 1193, (0, 1, 3, 4, 5, 16), _BAUD_X430)


def _xc330(name: str, number: int, current_limit: int) -> ModelSpec:
    fields = _with(
        _common_fields(),
        Field("current_limit", 38, 2, "RW", True, lo=0, hi=current_limit, default=current_limit),
        Field("goal_current", 102, 2, "RW", signed=True, lo=-current_limit, hi=current_limit),
        Field("baud_rate", 8, 1, "RW", True, lo=0, hi=6, default=1),
        Field("velocity_limit", 44, 4, "RW", True, lo=0, hi=2047, default=320),
    )
    return ModelSpec(name, number, fields, 1.0, current_limit, (0, 1, 3, 4, 5, 16), _BAUD_X330)


def _xl430_w250() -> ModelSpec:
    fields = _with(
        _common_fields(),
        Field("present_load", 126, 2, "R", signed=True),
        drop=("present_current", "goal_current", "current_limit"),
    )
    return ModelSpec("XL430-W250", 1060, fields, None, None, (1, 3, 4, 16), _BAUD_X430)


MODELS: dict[str, ModelSpec] = {
    m.name: m
    for m in (
        _xm430_w350(),
        _xc330("XC330-T288", 1220, 910),
        _xc330("XC330-M288", 1240, 2352),
        _xc330("XC330-T181", 1210, 910),
        _xc330("XC330-M181", 1230, 2352),
        _xl430_w250(),
    )
}
MODELS_BY_NUMBER: dict[int, ModelSpec] = {m.number: m for m in MODELS.values()}

#: items every model has at the same address (ids, firmware, errors, torque, positions)
COMMON_FIELDS: dict[str, Field] = {f.name: f for f in _common_fields()
                                   if all(f.name in m.fields and m.fields[f.name] == f for m in MODELS.values())}
#: every baud rate any supported model can be set to (bit/s)
BAUD_RATES: frozenset[int] = frozenset(b for m in MODELS.values() for b in m.baud_rates.values())

# The joint-state block read every cycle: Moving (122) .. Present Position (132..135).
STATE_BLOCK_ADDR = COMMON_FIELDS["moving"].addr
STATE_BLOCK_LEN = COMMON_FIELDS["present_position"].addr + COMMON_FIELDS["present_position"].size - STATE_BLOCK_ADDR


def model(name: str) -> ModelSpec:
    """The spec of a model by name (case-insensitive); KeyError lists the known ones."""
    for key, spec in MODELS.items():
        if key.lower() == str(name).lower():
            return spec
    raise KeyError(f"unknown servo model {name!r}; known: {', '.join(MODELS)}")
