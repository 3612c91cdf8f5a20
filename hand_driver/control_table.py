"""Control tables of the supported Dynamixel models, as data: the X-series and DYNAMIXEL-P.

Every number here is the ROBOTIS e-Manual's (Protocol 2.0 control tables), cited per model
by its page (``ModelSpec.page``). The two families differ in everything the driver uses:

- **X-series** (XM430-W350, XC330-T288/M288/T181/M181, XL430-W250): 4,096 pulses per turn,
  position 0..4,095 in position mode, RAM from 64 (Torque Enable 64, Hardware Error Status
  70, Bus Watchdog 98, Goal Current 102, Goal Position 116, Present Current 126, Present
  Position 132), velocity 0.229 rev/min, acceleration 214.577 rev/min². The XL430 has no
  Current Limit (38) nor Goal Current (102), and its address 126 is Present Load (0.1 % of
  maximum torque), not a current; XC330 servos measure current at their power input (1 mA
  units), the XM430 in the motor (2.69 mA units). The guarded touch uses current-based
  position control (mode 5), where Goal Current caps the current.
- **DYNAMIXEL-P** (PH54-200-S500-R, PH54-100-S500-R, PH42-020-S300-R, PM54-060-S250-R,
  PM54-040-S250-R, PM42-010-S260-R; model numbers 2,000–2,120; the earlier "Pro+" names
  H54P-200-S500-R etc. are the same servos with the same numbers): 502,834 to 1,003,846
  pulses per turn counted on the motor side through the gear, position −half..+half turn
  in position mode, RAM from 512 (Torque Enable 512, Hardware Error Status 518, Bus
  Watchdog 546, Goal Current 550, Goal Position 564, Present Current 574, Present Position
  580), current 1 mA, velocity 0.01 rev/min, acceleration 1 rev/min². There is no
  current-based position mode (operating modes 0, 1, 3, 4, 16); the e-Manual's Goal
  Current (550) "sets a current limit of the current controller in Velocity Control Mode,
  Position Control Mode and Extended Position Control Mode", so the guarded touch runs in
  position mode (3) with Goal Current as the force limit. Stated backlash < 6 arcmin
  (0.1°).
"""

from __future__ import annotations

import math
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



# Operating modes (address 11), the same values on both families.
MODE_CURRENT = 0
MODE_VELOCITY = 1
MODE_POSITION = 3
MODE_EXTENDED_POSITION = 4
MODE_CURRENT_BASED_POSITION = 5
MODE_PWM = 16

# Hardware Error Status bits (X: 70, P: 518), e-Manual "Shutdown(63)".
_HW_BITS_X = {
    0: "input voltage error",
    2: "overheating error",
    3: "motor encoder error",
    4: "electrical shock error",
    5: "overload error",
}
_HW_BITS_P = dict(sorted({**_HW_BITS_X, 1: "motor hall sensor error"}.items()))

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


@dataclass(frozen=True)
class IndirectBlock:
    """Indirect Address k (2 bytes each from ``address``) and Indirect Data k (1 byte each from
    ``data``) for k = first..last; each address may point anywhere in ``target_lo..target_hi``
    and defaults to its own data byte."""

    first: int
    last: int
    address: int
    data: int
    target_lo: int
    target_hi: int


@dataclass(frozen=True)
class ModelSpec:
    """Everything the driver and the emulator need to know about one model (e-Manual page
    ``page``)."""

    name: str
    number: int
    family: str  # "X" or "P"
    page: str
    fields: dict[str, Field]
    ticks_per_rev: int  # encoder pulses per output turn (Resolution)
    position_range: tuple[int, int]  # Present/Goal Position of one turn in position mode
    current_unit_ma: float | None  # None: no current sensing (Present Load instead)
    current_limit_default: int | None  # raw units: the model's maximum Current Limit
    operating_modes: tuple[int, ...]
    #: the mode the driver sets for guarded touches, and the modes in which Goal Current
    #: caps the current (e-Manual "Goal Current")
    guard_mode: int
    current_capped_modes: tuple[int, ...]
    baud_rates: dict[int, int]  # register value -> bit/s
    velocity_unit_rpm: float
    accel_unit_rpm2: float
    table_size: int
    indirect: tuple[IndirectBlock, ...]
    hardware_error_bits: dict[int, str]
    #: output torque per motor current (N·m/A): the e-Manual's stall torque / stall current at
    #: the recommended voltage (X), continuous torque / continuous current (P); the emulator's
    #: joint torque under load (declared compliance)
    torque_nm_per_a: float
    #: the e-Manual's stated backlash (deg), None where it states none
    backlash_deg: float | None = None
    fast_sync_read: bool = True

    @property
    def has_current_sensing(self) -> bool:
        return self.current_unit_ma is not None

    @property
    def rad_per_tick(self) -> float:
        return 2.0 * math.pi / self.ticks_per_rev

    @property
    def position_center(self) -> int:
        """The middle of one turn's positions (X: 2,048; P: 0)."""
        lo, hi = self.position_range
        return (lo + hi + 1) // 2

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

    def state_block(self) -> tuple[int, int]:
        """(address, length) of the joint-state block read every cycle: Moving .. the last
        byte of Present Position (X: 122..135, P: 570..583)."""
        lo = self.field("moving").addr
        pos = self.field("present_position")
        return lo, pos.addr + pos.size - lo

    def decode_hardware_error(self, bits: int) -> list[str]:
        """Names of the set bits of this model's Hardware Error Status."""
        return [name for bit, name in self.hardware_error_bits.items() if bits & (1 << bit)]


def _with(fields: list[Field], *extra: Field, drop: tuple[str, ...] = ()) -> dict[str, Field]:
    out = {f.name: f for f in fields if f.name not in drop}
    for f in extra:
        out[f.name] = f
    return dict(sorted(out.items(), key=lambda kv: kv[1].addr))


def _indirect_fields(blocks: tuple[IndirectBlock, ...]) -> list[Field]:
    out = []
    for b in blocks:
        for k in range(b.first, b.last + 1):
            data = b.data + k - b.first
            out.append(Field(f"indirect_address_{k}", b.address + 2 * (k - b.first), 2, "RW", lo=b.target_lo,
                             hi=b.target_hi, default=data))
            out.append(Field(f"indirect_data_{k}", data, 1, "RW"))
    return out


# ----------------------------------------------------------------------------- X-series
# https://emanual.robotis.com/docs/en/dxl/x/xm430-w350/ (and xc330-*, xl430-w250): the
# control table below, Resolution 4,096 [pulse/rev], Goal Position 0..4,095 in position mode.
_X_PAGE = "https://emanual.robotis.com/docs/en/dxl/x/{}/"
_X_TICKS_PER_REV = 4096
_X_POSITION_RANGE = (0, _X_TICKS_PER_REV - 1)
#: X-series: Indirect Address 1–28 (168…) and 29–56 (578…), pointing anywhere in 64..661
_X_INDIRECT = (IndirectBlock(1, 28, 168, 224, 64, 661), IndirectBlock(29, 56, 578, 634, 64, 661))
#: bytes of the X-series control table (the last item is Indirect Data 56 at 661)
_X_TABLE_SIZE = 662
_BAUD_X430 = {0: 9600, 1: 57600, 2: 115200, 3: 1_000_000, 4: 2_000_000, 5: 3_000_000, 6: 4_000_000, 7: 4_500_000}
_BAUD_X330 = {k: v for k, v in _BAUD_X430.items() if k <= 6}


def _x_fields() -> list[Field]:
    lo, hi = _X_POSITION_RANGE
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
        Field("max_position_limit", 48, 4, "RW", True, lo=lo, hi=hi, default=hi),
        Field("min_position_limit", 52, 4, "RW", True, lo=lo, hi=hi, default=lo),
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
        *_indirect_fields(_X_INDIRECT),
    ]


def _x_model(name: str, number: int, fields: dict[str, Field], current_unit_ma: float | None,
             current_limit: int | None, modes: tuple[int, ...], bauds: dict[int, int], stall: tuple[float, float],
             backlash_deg: float | None = None) -> ModelSpec:
    sensing = current_unit_ma is not None
    return ModelSpec(
        name, number, "X", _X_PAGE.format(name.lower()),
        fields, _X_TICKS_PER_REV, _X_POSITION_RANGE, current_unit_ma, current_limit, modes,
        guard_mode=MODE_CURRENT_BASED_POSITION if sensing else MODE_POSITION,
        current_capped_modes=(MODE_CURRENT, MODE_CURRENT_BASED_POSITION) if sensing else (),
        baud_rates=bauds, velocity_unit_rpm=0.229, accel_unit_rpm2=214.577, table_size=_X_TABLE_SIZE,
        indirect=_X_INDIRECT, hardware_error_bits=_HW_BITS_X, torque_nm_per_a=stall[0] / stall[1],
        backlash_deg=backlash_deg)


def _xm430_w350() -> ModelSpec:
    fields = _with(
        _x_fields(),
        Field("current_limit", 38, 2, "RW", True, lo=0, hi=1193, default=1193),
        Field("goal_current", 102, 2, "RW", signed=True, lo=-1193, hi=1193),
    )
    # stall torque 4.1 N·m at 12.0 V, 2.3 A; backlash 15 arcmin (0.25°)
    return _x_model("XM430-W350", 1020, fields, 2.69, 1193, (0, 1, 3, 4, 5, 16), _BAUD_X430, (4.1, 2.3), 0.25)


def _xc330(name: str, number: int, current_limit: int, stall: tuple[float, float]) -> ModelSpec:
    fields = _with(
        _x_fields(),
        Field("current_limit", 38, 2, "RW", True, lo=0, hi=current_limit, default=current_limit),
        Field("goal_current", 102, 2, "RW", signed=True, lo=-current_limit, hi=current_limit),
        Field("baud_rate", 8, 1, "RW", True, lo=0, hi=6, default=1),
        Field("velocity_limit", 44, 4, "RW", True, lo=0, hi=2047, default=320),
    )
    return _x_model(name, number, fields, 1.0, current_limit, (0, 1, 3, 4, 5, 16), _BAUD_X330, stall)


def _xl430_w250() -> ModelSpec:
    fields = _with(
        _x_fields(),
        Field("present_load", 126, 2, "R", signed=True),
        drop=("present_current", "goal_current", "current_limit"),
    )
    # stall torque 1.4 N·m at 11.1 V, 1.3 A
    return _x_model("XL430-W250", 1060, fields, None, None, (1, 3, 4, 16), _BAUD_X430, (1.4, 1.3))


# ----------------------------------------------------------------------------- DYNAMIXEL-P
# https://emanual.robotis.com/docs/en/dxl/p/<model>/ : "Control Table of EEPROM Area" and
# "... of RAM Area" (the same addresses on every P model), "Model Number(0)" (2,000–2,120),
# "Baud Rate(8)" (0..9: 9,600 bps .. 10.5 Mbps), "Goal Current(550)" (caps the current in
# velocity, position and extended position mode), "Profile Velocity(560)" (0.01 rev/min;
# 0 = no profile), "Shutdown(63)" (bit 1 motor hall sensor error), Specifications
# (Resolution [pulse/rev], Backlash < 6 arcmin = 0.1°).
_P_PAGE = "https://emanual.robotis.com/docs/en/dxl/p/{}/"
#: Indirect Address 1–128 (168…422) pointing anywhere in 512..1,023; Indirect Data 1–128 (634…761)
_P_INDIRECT = (IndirectBlock(1, 128, 168, 634, 512, 1023),)
#: bytes of the P-series control table (Indirect Address may point up to 1,023)
_P_TABLE_SIZE = 1024
_BAUD_P = {0: 9600, 1: 57600, 2: 115200, 3: 1_000_000, 4: 2_000_000, 5: 3_000_000, 6: 4_000_000, 7: 4_500_000,
           8: 6_000_000, 9: 10_500_000}
_P_BACKLASH_DEG = 0.1  # "< 6 [arcmin], 0.1 [°]"


@dataclass(frozen=True)
class _PRow:
    """The numbers that differ between P models (each from its e-Manual page)."""

    name: str
    number: int
    resolution: int  # pulses per turn; Min/Max Position Limit range is ± resolution / 2
    current_limit: int  # Current Limit (38) maximum and initial value, mA
    accel_limit: tuple[int, int]  # Acceleration Limit (40): initial value, maximum (rev/min²)
    velocity_limit: int  # Velocity Limit (44) maximum and initial value (0.01 rev/min)
    position_limit: int  # Max Position Limit (48) initial value (Min: its negative)
    shutdown: int  # Shutdown (63) initial value
    continuous: tuple[float, float]  # Continuous Torque (N·m), Continuous Current (A)
    startup_configuration: bool = False  # the page lists Startup Configuration (60)


_P_ROWS = (
    _PRow("PH54-200-S500-R", 2020, 1_003_846, 22_740, (9_982, 3_992_644), 2_900, 501_433, 52, (44.7, 9.3), True),
    _PRow("PH54-100-S500-R", 2010, 1_003_846, 15_900, (10_639, 4_255_632), 2_920, 501_433, 58, (25.3, 5.5)),
    _PRow("PH42-020-S300-R", 2000, 607_500, 4_500, (10_765, 4_306_173), 2_920, 303_454, 58, (5.1, 1.5)),
    _PRow("PM54-060-S250-R", 2120, 502_834, 7_980, (11_145, 4_457_932), 2_830, 251_173, 58, (10.1, 3.0)),
    _PRow("PM54-040-S250-R", 2110, 502_834, 4_470, (11_037, 4_414_976), 2_840, 251_173, 58, (3.9, 1.9)),
    _PRow("PM42-010-S260-R", 2100, 526_374, 1_461, (10_867, 4_346_756), 2_600, 262_931, 58, (1.7, 0.6)),
)


def _p_model(r: _PRow) -> ModelSpec:
    half = r.resolution // 2
    accel0, accel_max = r.accel_limit
    fields = _with([
        Field("model_number", 0, 2, "R", True),
        Field("model_information", 2, 4, "R", True),
        Field("firmware_version", 6, 1, "R", True),
        Field("id", 7, 1, "RW", True, lo=0, hi=252, default=1),
        Field("baud_rate", 8, 1, "RW", True, lo=0, hi=9, default=1),
        Field("return_delay_time", 9, 1, "RW", True, lo=0, hi=254, default=250),
        Field("drive_mode", 10, 1, "RW", True, lo=0, hi=1),
        Field("operating_mode", 11, 1, "RW", True, lo=0, hi=16, default=3),
        Field("secondary_id", 12, 1, "RW", True, lo=0, hi=255, default=255),
        Field("protocol_type", 13, 1, "RW", True, lo=2, hi=10, default=2),
        Field("homing_offset", 20, 4, "RW", True, True),
        Field("moving_threshold", 24, 4, "RW", True, lo=0, hi=r.velocity_limit, default=20),
        Field("temperature_limit", 31, 1, "RW", True, lo=0, hi=100, default=80),
        Field("max_voltage_limit", 32, 2, "RW", True, lo=150, hi=350, default=350),
        Field("min_voltage_limit", 34, 2, "RW", True, lo=150, hi=350, default=150),
        Field("pwm_limit", 36, 2, "RW", True, lo=0, hi=2009, default=2009),
        Field("current_limit", 38, 2, "RW", True, lo=0, hi=r.current_limit, default=r.current_limit),
        Field("acceleration_limit", 40, 4, "RW", True, lo=0, hi=accel_max, default=accel0),
        Field("velocity_limit", 44, 4, "RW", True, lo=0, hi=r.velocity_limit, default=r.velocity_limit),
        Field("max_position_limit", 48, 4, "RW", True, True, -half, half, r.position_limit),
        Field("min_position_limit", 52, 4, "RW", True, True, -half, half, -r.position_limit),
        *(Field(f"external_port_mode_{k}", 55 + k, 1, "RW", True, lo=0, hi=3, default=3) for k in range(1, 5)),
        *([Field("startup_configuration", 60, 1, "RW", True, lo=0, hi=3)] if r.startup_configuration else []),
        Field("shutdown", 63, 1, "RW", True, lo=0, hi=255, default=r.shutdown),
        Field("torque_enable", 512, 1, "RW", lo=0, hi=1),
        Field("led_red", 513, 1, "RW", lo=0, hi=255),
        Field("led_green", 514, 1, "RW", lo=0, hi=255),
        Field("led_blue", 515, 1, "RW", lo=0, hi=255),
        Field("status_return_level", 516, 1, "RW", lo=0, hi=2, default=2),
        Field("registered_instruction", 517, 1, "R"),
        Field("hardware_error_status", 518, 1, "R"),
        Field("velocity_i_gain", 524, 2, "RW", lo=0, hi=32767),
        Field("velocity_p_gain", 526, 2, "RW", lo=0, hi=32767),
        Field("position_d_gain", 528, 2, "RW", lo=0, hi=32767),
        Field("position_i_gain", 530, 2, "RW", lo=0, hi=32767),
        Field("position_p_gain", 532, 2, "RW", lo=0, hi=32767),
        Field("feedforward_2nd_gain", 536, 2, "RW", lo=0, hi=32767),
        Field("feedforward_1st_gain", 538, 2, "RW", lo=0, hi=32767),
        # 20 ms units; 0 disables (and clears the error); reads −1 after it expired
        Field("bus_watchdog", 546, 1, "RW", signed=True, lo=0, hi=127),
        Field("goal_pwm", 548, 2, "RW", signed=True, lo=-2009, hi=2009),
        Field("goal_current", 550, 2, "RW", signed=True, lo=-r.current_limit, hi=r.current_limit),
        Field("goal_velocity", 552, 4, "RW", signed=True, lo=-r.velocity_limit, hi=r.velocity_limit),
        Field("profile_acceleration", 556, 4, "RW", lo=0, hi=accel_max),
        Field("profile_velocity", 560, 4, "RW", lo=0, hi=r.velocity_limit),
        Field("goal_position", 564, 4, "RW", signed=True),
        Field("realtime_tick", 568, 2, "R"),
        Field("moving", 570, 1, "R"),
        Field("moving_status", 571, 1, "R"),
        Field("present_pwm", 572, 2, "R", signed=True),
        Field("present_current", 574, 2, "R", signed=True),
        Field("present_velocity", 576, 4, "R", signed=True),
        Field("present_position", 580, 4, "R", signed=True),
        Field("velocity_trajectory", 584, 4, "R", signed=True),
        Field("position_trajectory", 588, 4, "R", signed=True),
        Field("present_input_voltage", 592, 2, "R", default=240),
        Field("present_temperature", 594, 1, "R", default=30),
        *(Field(f"external_port_data_{k}", 598 + 2 * k, 2, "RW", lo=0, hi=4095) for k in range(1, 5)),
        *_indirect_fields(_P_INDIRECT),
        Field("backup_ready", 878, 1, "R"),
    ])
    return ModelSpec(
        r.name, r.number, "P", _P_PAGE.format(r.name.lower()), fields, r.resolution, (-half, half), 1.0,
        r.current_limit, (MODE_CURRENT, MODE_VELOCITY, MODE_POSITION, MODE_EXTENDED_POSITION, MODE_PWM),
        guard_mode=MODE_POSITION,
        current_capped_modes=(MODE_CURRENT, MODE_VELOCITY, MODE_POSITION, MODE_EXTENDED_POSITION),
        baud_rates=_BAUD_P, velocity_unit_rpm=0.01, accel_unit_rpm2=1.0, table_size=_P_TABLE_SIZE,
        indirect=_P_INDIRECT, hardware_error_bits=_HW_BITS_P, torque_nm_per_a=r.continuous[0] / r.continuous[1],
        backlash_deg=_P_BACKLASH_DEG)


MODELS: dict[str, ModelSpec] = {
    m.name: m
    for m in (
        _xm430_w350(),
        # stall torque at the recommended voltage: T 11.1 V, M 5.0 V
        _xc330("XC330-T288", 1220, 910, (0.92, 0.80)),
        _xc330("XC330-M288", 1240, 2352, (0.93, 1.80)),
        _xc330("XC330-T181", 1210, 910, (0.76, 0.80)),
        _xc330("XC330-M181", 1230, 2352, (0.60, 1.80)),
        _xl430_w250(),
        *(_p_model(r) for r in _P_ROWS),
    )
}
MODELS_BY_NUMBER: dict[int, ModelSpec] = {m.number: m for m in MODELS.values()}
#: the models of each family
FAMILIES: dict[str, tuple[str, ...]] = {fam: tuple(n for n, m in MODELS.items() if m.family == fam) for fam in "XP"}

#: items every model has at the same address with the same range (ids, firmware, baud rate...)
COMMON_FIELDS: dict[str, Field] = {f.name: f for f in MODELS["XM430-W350"].fields.values()
                                   if all(f.name in m.fields and m.fields[f.name] == f for m in MODELS.values())}
#: every baud rate any supported model can be set to (bit/s)
BAUD_RATES: frozenset[int] = frozenset(b for m in MODELS.values() for b in m.baud_rates.values())


def model(name: str) -> ModelSpec:
    """The spec of a model by name (case-insensitive); KeyError lists the known ones."""
    for key, spec in MODELS.items():
        if key.lower() == str(name).lower():
            return spec
    raise KeyError(f"unknown servo model {name!r}; known: {', '.join(MODELS)}")
