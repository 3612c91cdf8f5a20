"""Jaw configuration: YAML → typed dataclasses, validated once (docs/formats.md, jaw config).

A jaw is a bus plus fingers; a finger is a planar chain of revolute joints fixed at a
base pose in the hand frame, with a flat pad on the side of its distal link that ends at
the fingertip. Joint angle (ARCHITECTURE "Units and frames")::

    q = direction · (tick − zero_tick) · 2π/ticks_per_rev   (rad, counter-clockwise; hand_driver.units)

with ``ticks_per_rev`` the joint's model's resolution (hand_driver.control_table: X-series
4,096, DYNAMIXEL-P 502,834–1,003,846); ``zero_tick`` and the joint limits are held to the
positions of one turn of that model in position mode (X 0..4,095, P ±half a turn).

The errors a real servo puts between its encoder and its link may be declared (docs/driver.md,
declared errors): a joint's ``backlash_deg`` (the gear's dead band, full width) and
``compliance_deg_per_nm`` (link and gear deflection per N·m of joint torque), a pad's
``compliance_mm_per_n`` (its face yielding along its normal per N of contact force). The
emulator simulates exactly the errors its truth config declares (none: none); a zero error is
the truth config's ``zero_tick`` differing from the nominal one. All default to 0 and are
written out only when declared.

Link i starts at joint i and points along ``base.angle + q_1 + … + q_i``; its length is
``link_mm``. The pad is a segment parallel to the distal link, ``pad.offset_mm`` from
its axis on ``pad.side`` (seen looking from the joint toward the tip), covering the last
``pad.length_mm`` of the link up to the fingertip. Every check happens in
:func:`load_config`; a bad file raises :class:`InputError` with one line naming the file,
the key and the allowed range.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path
from typing import Any

import yaml

from hand_driver.control_table import BAUD_RATES, MODELS, ModelSpec
from hand_driver.control_table import model as model_spec
from hand_driver.units import WATCHDOG_STEP_MS, deg_to_ticks_exact
from tactile_common.errors import InputError
from tactile_common.files import atomic_write
from tactile_common.yamlfile import read_yaml_located


@dataclass(frozen=True)
class BusConfig:
    port: str = "/dev/ttyUSB0"
    baudrate: int = 1_000_000
    protocol: float = 2.0
    retries: int = 3
    timeout_s: float = 0.05
    #: Bus Watchdog: a servo stops when the host is silent this long (0: off; 20 ms steps)
    watchdog_ms: int = 100


@dataclass(frozen=True)
class JointConfig:
    id: int
    model: str
    zero_tick: float
    link_mm: float
    direction: int = 1
    min_deg: float = -90.0
    max_deg: float = 90.0
    current_limit_ma: float = 1000.0
    backlash_deg: float = 0.0  # gear dead band, full width (declared error)
    compliance_deg_per_nm: float = 0.0  # link and gear deflection per joint torque (declared error)
    zero_sigma_deg: float = 0.0  # standard error of zero_tick after calibration (tactile calibrate writes it)
    link_sigma_mm: float = 0.0  # and of link_mm (tactile calibrate writes it)
    compliance_sigma_deg_per_nm: float = 0.0  # and of compliance_deg_per_nm (tactile calibrate writes it)

    @property
    def spec(self) -> ModelSpec:
        """The joint's model (its control table, units and resolution)."""
        return model_spec(self.model)

    @property
    def ticks_per_rev(self) -> int:
        return self.spec.ticks_per_rev

    @property
    def rad_per_tick(self) -> float:
        return self.spec.rad_per_tick

    @property
    def min_rad(self) -> float:
        return math.radians(self.min_deg)

    @property
    def max_rad(self) -> float:
        return math.radians(self.max_deg)


@dataclass(frozen=True)
class PadConfig:
    """Flat pad on the distal link: ``side`` 'left'/'right' of the link (looking from the
    joint to the tip), ``offset_mm`` from the link axis, the last ``length_mm`` of the link."""

    side: str
    offset_mm: float
    length_mm: float
    compliance_mm_per_n: float = 0.0  # the face yields along its normal per N (declared error)
    offset_sigma_mm: float = 0.0  # standard error of offset_mm after calibration (tactile calibrate writes it)
    compliance_sigma_mm_per_n: float = 0.0  # and of compliance_mm_per_n (tactile calibrate writes it)

    @property
    def side_sign(self) -> int:
        """+1: the pad's outward normal is the link direction turned +90° (left)."""
        return 1 if self.side == "left" else -1


@dataclass(frozen=True)
class BasePose:
    x: float
    y: float
    angle_deg: float

    @property
    def angle(self) -> float:
        return math.radians(self.angle_deg)


@dataclass(frozen=True)
class FingerConfig:
    name: str
    base: BasePose
    joints: tuple[JointConfig, ...]
    pad: PadConfig


@dataclass(frozen=True)
class MotionConfig:
    """How the jaw moves and how it feels a contact (used by hand_driver.motion)."""

    profile_velocity: int = 100  # raw, in each joint's model's unit (X 0.229, P 0.01 rev/min)
    profile_acceleration: int = 100  # raw, each model's unit (X 214.577, P 1 rev/min²)
    approach_speed_mm_s: float = 25.0
    approach_step_mm: float = 0.5
    move_speed_mm_s: float = 60.0  # Cartesian moves (hand_driver.motion.move_line): pad shift
    turn_speed_deg_s: float = 100.0  # ... and pad turn
    contact_current_ma: float = 150.0
    goal_current_ma: float = 300.0
    backoff_mm: float = 3.0
    max_touch_s: float = 10.0


#: motion keys earlier versions read but no exploration used (the profile sets the samples
#: per touch and the roll span): a config file carrying one is refused, naming it and why; a
#: run log's header config written then carries them and is read without them (nothing
#: recorded is lost: those logs replay as they did)
RETIRED_MOTION_KEYS = ("roll_step_deg", "roll_samples")


@dataclass(frozen=True)
class WorkspaceConfig:
    """Where the object is expected: a disk in the hand frame."""

    center_mm: tuple[float, float] = (110.0, 0.0)
    radius_mm: float = 45.0


@dataclass(frozen=True)
class JawConfig:
    bus: BusConfig
    fingers: tuple[FingerConfig, ...]
    motion: MotionConfig
    workspace: WorkspaceConfig
    source: str = field(default="<memory>", compare=False)

    @property
    def joints(self) -> tuple[JointConfig, ...]:
        """Every joint in config order (finger by finger, base to tip)."""
        return tuple(j for f in self.fingers for j in f.joints)

    def finger(self, name: str) -> FingerConfig:
        for f in self.fingers:
            if f.name == name:
                return f
        raise InputError(f"{self.source}: no finger named {name!r}; fingers are "
                         f"{', '.join(f.name for f in self.fingers)}")

    def joint_slices(self) -> dict[str, slice]:
        """Finger name → slice of that finger's joints in :attr:`joints` order."""
        out, k = {}, 0
        for f in self.fingers:
            out[f.name] = slice(k, k + len(f.joints))
            k += len(f.joints)
        return out


# ----------------------------------------------------------------------------- loading


class _Checker:
    """Reads typed, range-checked values; errors name file and dotted key."""

    def __init__(self, source: str):
        self.source = source

    def fail(self, key: str, what: str) -> None:
        raise InputError(f"{self.source}: {key}: {what}")

    def mapping(self, obj: Any, key: str, allowed: tuple[str, ...], required: tuple[str, ...] = ()) -> dict:
        if not isinstance(obj, dict):
            self.fail(key or "<top>", f"expected a mapping with keys {', '.join(allowed)}")
        for k in obj:
            if k not in allowed:
                name = str(k) if str(k).isprintable() else repr(str(k))  # the message stays one line
                self.fail(f"{key}.{name}" if key else name, f"unknown key; allowed: {', '.join(allowed)}")
        for k in required:
            if k not in obj:
                self.fail(f"{key}.{k}" if key else k, "missing (required)")
        return obj

    def number(self, obj: dict, key: str, name: str, default: Any, lo: float, hi: float,
               integer: bool = False, lo_open: bool = False) -> Any:
        full = f"{key}.{name}" if key else name
        value = obj.get(name, default)
        rng = f"{'(' if lo_open else '['}{lo:g}, {hi:g}]"
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            self.fail(full, f"{value!r} is not a number; allowed range {rng}")
        if integer and (not float(value).is_integer()):
            self.fail(full, f"{value!r} is not an integer; allowed range {rng}")
        if not math.isfinite(value) or value < lo or value > hi or (lo_open and value == lo):
            self.fail(full, f"{value!r} out of range {rng}")
        return int(value) if integer else float(value)

    def string(self, obj: dict, key: str, name: str, default: Any, choices: tuple[str, ...] | None = None) -> str:
        full = f"{key}.{name}" if key else name
        value = obj.get(name, default)
        if not isinstance(value, str) or not value:
            self.fail(full, f"{value!r} is not a non-empty string")
        if choices is not None and value not in choices:
            self.fail(full, f"{value!r} not allowed; choose from {', '.join(choices)}")
        return value


def _baudrate(c: _Checker, m: dict, default: int) -> int:
    value = m.get("baudrate", default)
    if isinstance(value, bool) or not isinstance(value, int) or value not in BAUD_RATES:
        c.fail("bus.baudrate", f"{value!r} is not a Dynamixel baud rate; choose from "
                               f"{', '.join(map(str, sorted(BAUD_RATES)))}")
    return value


def _bus(c: _Checker, obj: Any) -> BusConfig:
    d = BusConfig()
    m = c.mapping(obj if obj is not None else {}, "bus",
                  ("port", "baudrate", "protocol", "retries", "timeout_s", "watchdog_ms"))
    protocol = c.number(m, "bus", "protocol", d.protocol, 2.0, 2.0)
    return BusConfig(
        port=c.string(m, "bus", "port", d.port),
        baudrate=_baudrate(c, m, d.baudrate),
        protocol=protocol,
        retries=c.number(m, "bus", "retries", d.retries, 0, 10, integer=True),
        timeout_s=c.number(m, "bus", "timeout_s", d.timeout_s, 0.001, 5.0),
        watchdog_ms=_watchdog_ms(c, m, d.watchdog_ms),
    )


def _watchdog_ms(c: _Checker, m: dict, default: int) -> int:
    value = c.number(m, "bus", "watchdog_ms", default, 0, 127 * WATCHDOG_STEP_MS, integer=True)
    if value % WATCHDOG_STEP_MS:
        c.fail("bus.watchdog_ms", f"{value} is not a multiple of {WATCHDOG_STEP_MS} ms (the servos' Bus Watchdog "
                                  f"unit); 0 turns it off")
    return value


def _joint(c: _Checker, obj: Any, key: str, models: tuple[str, ...]) -> JointConfig:
    allowed = ("id", "model", "zero_tick", "link_mm", "direction", "min_deg", "max_deg", "current_limit_ma",
               "backlash_deg", "compliance_deg_per_nm", "zero_sigma_deg", "link_sigma_mm",
               "compliance_sigma_deg_per_nm")
    m = c.mapping(obj, key, allowed, required=("id", "model", "zero_tick", "link_mm"))
    d = JointConfig(0, "", 0, 0)
    model = c.string(m, key, "model", None, models)
    direction = m.get("direction", d.direction)
    if direction not in (1, -1) or isinstance(direction, bool):
        c.fail(f"{key}.direction", f"{direction!r} not allowed; choose 1 or -1")
    spec = model_spec(model)
    lo_tick, hi_tick = spec.position_range
    j = JointConfig(
        id=c.number(m, key, "id", None, 0, 252, integer=True),
        model=model,
        zero_tick=c.number(m, key, "zero_tick", None, lo_tick, hi_tick),
        link_mm=c.number(m, key, "link_mm", None, 0.0, 1000.0, lo_open=True),
        direction=int(direction),
        min_deg=c.number(m, key, "min_deg", d.min_deg, -180.0, 0.0),
        max_deg=c.number(m, key, "max_deg", d.max_deg, 0.0, 180.0),
        current_limit_ma=c.number(m, key, "current_limit_ma", d.current_limit_ma, 0.0, 10_000.0, lo_open=True),
        backlash_deg=c.number(m, key, "backlash_deg", d.backlash_deg, 0.0, 5.0),
        compliance_deg_per_nm=c.number(m, key, "compliance_deg_per_nm", d.compliance_deg_per_nm, 0.0, 10.0),
        zero_sigma_deg=c.number(m, key, "zero_sigma_deg", d.zero_sigma_deg, 0.0, 5.0),
        link_sigma_mm=c.number(m, key, "link_sigma_mm", d.link_sigma_mm, 0.0, 10.0),
        compliance_sigma_deg_per_nm=c.number(m, key, "compliance_sigma_deg_per_nm", d.compliance_sigma_deg_per_nm,
                                             0.0, 10.0),
    )
    # Limits must stay inside one encoder turn of position mode (the model's Min/Max
    # Position Limit range).
    per_deg = spec.ticks_per_rev / 360.0
    for name, deg in (("min_deg", j.min_deg), ("max_deg", j.max_deg)):
        tick = float(deg_to_ticks_exact(deg, j.zero_tick, j.direction, spec.ticks_per_rev))
        if not lo_tick <= tick <= hi_tick:
            lo = (lo_tick - j.zero_tick) / per_deg
            hi = (hi_tick - j.zero_tick) / per_deg
            if j.direction < 0:
                lo, hi = -hi, -lo
            c.fail(f"{key}.{name}", f"{deg:g}° puts the encoder at tick {tick:.0f}, outside {lo_tick}..{hi_tick} "
                                    f"({spec.name}); with zero_tick {j.zero_tick:g} allowed range [{lo:.1f}, {hi:.1f}]")
    return j


def _finger(c: _Checker, obj: Any, key: str, models: tuple[str, ...]) -> FingerConfig:
    m = c.mapping(obj, key, ("name", "base", "joints", "pad"), required=("name", "base", "joints", "pad"))
    name = c.string(m, key, "name", None)
    base_obj = c.mapping(m["base"], f"{key}.base", ("x", "y", "angle_deg"), required=("x", "y", "angle_deg"))
    base = BasePose(
        x=c.number(base_obj, f"{key}.base", "x", 0.0, -1000.0, 1000.0),
        y=c.number(base_obj, f"{key}.base", "y", 0.0, -1000.0, 1000.0),
        angle_deg=c.number(base_obj, f"{key}.base", "angle_deg", 0.0, -180.0, 180.0),
    )
    joints_obj = m["joints"]
    if not isinstance(joints_obj, list) or len(joints_obj) != 2:
        c.fail(f"{key}.joints", "expected a list of exactly 2 joints (a 2-joint planar chain)")
    joints = tuple(_joint(c, j, f"{key}.joints[{i}]", models) for i, j in enumerate(joints_obj))
    pm = c.mapping(m["pad"], f"{key}.pad", ("side", "offset_mm", "length_mm", "compliance_mm_per_n",
                                                    "offset_sigma_mm", "compliance_sigma_mm_per_n"),
                   required=("side", "offset_mm", "length_mm"))
    distal = joints[-1].link_mm
    pad = PadConfig(
        side=c.string(pm, f"{key}.pad", "side", None, ("left", "right")),
        offset_mm=c.number(pm, f"{key}.pad", "offset_mm", None, 0.0, 100.0),
        length_mm=c.number(pm, f"{key}.pad", "length_mm", None, 0.0, distal, lo_open=True),
        compliance_mm_per_n=c.number(pm, f"{key}.pad", "compliance_mm_per_n", 0.0, 0.0, 5.0),
        offset_sigma_mm=c.number(pm, f"{key}.pad", "offset_sigma_mm", 0.0, 0.0, 10.0),
        compliance_sigma_mm_per_n=c.number(pm, f"{key}.pad", "compliance_sigma_mm_per_n", 0.0, 0.0, 5.0),
    )
    return FingerConfig(name=name, base=base, joints=joints, pad=pad)


def _motion(c: _Checker, obj: Any, recorded: bool) -> MotionConfig:
    d = MotionConfig()
    if isinstance(obj, dict) and any(k in obj for k in RETIRED_MOTION_KEYS):
        if not recorded:
            key = next(k for k in RETIRED_MOTION_KEYS if k in obj)
            c.fail(f"motion.{key}", "no longer a setting (the profile sets the samples per touch and the roll span, "
                                    "--profile); delete it")
        obj = {k: v for k, v in obj.items() if k not in RETIRED_MOTION_KEYS}
    m = c.mapping(obj if obj is not None else {}, "motion", tuple(asdict(d)))
    k = "motion"
    cfg = MotionConfig(
        profile_velocity=c.number(m, k, "profile_velocity", d.profile_velocity, 0, 2**31 - 1, integer=True),
        profile_acceleration=c.number(m, k, "profile_acceleration", d.profile_acceleration, 0, 2**31 - 1,
                                      integer=True),
        approach_speed_mm_s=c.number(m, k, "approach_speed_mm_s", d.approach_speed_mm_s, 0.0, 200.0, lo_open=True),
        approach_step_mm=c.number(m, k, "approach_step_mm", d.approach_step_mm, 0.0, 10.0, lo_open=True),
        move_speed_mm_s=c.number(m, k, "move_speed_mm_s", d.move_speed_mm_s, 0.0, 1000.0, lo_open=True),
        turn_speed_deg_s=c.number(m, k, "turn_speed_deg_s", d.turn_speed_deg_s, 0.0, 1000.0, lo_open=True),
        contact_current_ma=c.number(m, k, "contact_current_ma", d.contact_current_ma, 0.0, 5000.0, lo_open=True),
        goal_current_ma=c.number(m, k, "goal_current_ma", d.goal_current_ma, 0.0, 5000.0, lo_open=True),
        backoff_mm=c.number(m, k, "backoff_mm", d.backoff_mm, 0.0, 50.0),
        max_touch_s=c.number(m, k, "max_touch_s", d.max_touch_s, 0.0, 600.0, lo_open=True),
    )
    if cfg.goal_current_ma < cfg.contact_current_ma:
        c.fail("motion.goal_current_ma", f"{cfg.goal_current_ma:g} must be ≥ motion.contact_current_ma "
                                         f"({cfg.contact_current_ma:g}) or a contact is never felt")
    return cfg


def _check_profile(c: _Checker, motion: MotionConfig, fingers: tuple[FingerConfig, ...]) -> None:
    """The raw profile values are in each joint's model's units: each must fit every model's item."""
    for name in ("profile_velocity", "profile_acceleration"):
        value = getattr(motion, name)
        for f in fingers:
            for j in f.joints:
                hi = j.spec.field(name).hi
                if hi is not None and value > hi:
                    c.fail(f"motion.{name}", f"{value} is beyond {j.model}'s {name} range 0..{hi} (raw units of "
                                             f"each joint's model; joint id {j.id})")


def _workspace(c: _Checker, obj: Any) -> WorkspaceConfig:
    d = WorkspaceConfig()
    m = c.mapping(obj if obj is not None else {}, "workspace", ("center_mm", "radius_mm"))
    center = m.get("center_mm", list(d.center_mm))
    if (not isinstance(center, (list, tuple)) or len(center) != 2
            or not all(isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v) for v in center)):
        c.fail("workspace.center_mm", f"{center!r} is not a pair of finite numbers [x, y] (mm)")
    return WorkspaceConfig(
        center_mm=(float(center[0]), float(center[1])),
        radius_mm=c.number(m, "workspace", "radius_mm", d.radius_mm, 0.0, 1000.0, lo_open=True),
    )


def parse_config(obj: Any, source: str = "<memory>", recorded: bool = False) -> JawConfig:
    """Validate a config mapping (as read from YAML) into a :class:`JawConfig`; ``recorded``:
    a run log's header config, which may carry ``RETIRED_MOTION_KEYS``."""
    c = _Checker(source)
    m = c.mapping(obj, "", ("bus", "fingers", "motion", "workspace"), required=("fingers",))
    fingers_obj = m["fingers"]
    if not isinstance(fingers_obj, list) or len(fingers_obj) != 2:
        c.fail("fingers", "expected a list of exactly 2 fingers")
    models = tuple(MODELS)
    fingers = tuple(_finger(c, f, f"fingers[{i}]", models) for i, f in enumerate(fingers_obj))
    names = [f.name for f in fingers]
    if len(set(names)) != len(names):
        c.fail("fingers", f"duplicate finger names {names}")
    seen: dict[int, str] = {}
    for i, f in enumerate(fingers):
        for k, j in enumerate(f.joints):
            key = f"fingers[{i}].joints[{k}].id"
            if j.id in seen:
                c.fail(key, f"id {j.id} is used twice (also {seen[j.id]}); ids must be unique on the bus")
            seen[j.id] = key
    bus, motion = _bus(c, m.get("bus")), _motion(c, m.get("motion"), recorded)
    _check_profile(c, motion, fingers)
    period_ms = 1000.0 * motion.approach_step_mm / motion.approach_speed_mm_s
    if bus.watchdog_ms and bus.watchdog_ms < 2.0 * period_ms:
        if isinstance(m.get("bus"), dict) and "watchdog_ms" in m["bus"]:
            c.fail("bus.watchdog_ms", f"{bus.watchdog_ms} ms is less than two motion cycles ({period_ms:g} ms each: "
                                      f"motion.approach_step_mm / motion.approach_speed_mm_s); the servos would "
                                      f"stop between cycles")
        # not given: the default stretches to two cycles (slow approaches)
        two_cycles = WATCHDOG_STEP_MS * math.ceil(2.0 * period_ms / WATCHDOG_STEP_MS)
        if two_cycles > 127 * WATCHDOG_STEP_MS:
            c.fail("motion.approach_speed_mm_s", f"a motion cycle of {period_ms:g} ms is longer than half the "
                                                 f"longest Bus Watchdog ({127 * WATCHDOG_STEP_MS} ms); approach faster "
                                                 f"or in smaller steps, or set bus.watchdog_ms: 0")
        bus = replace(bus, watchdog_ms=two_cycles)
    return JawConfig(bus=bus, fingers=fingers, motion=motion, workspace=_workspace(c, m.get("workspace")),
                     source=source)


def load_config(path: str | Path) -> JawConfig:
    """Read and validate a jaw YAML file; :class:`InputError` (one line) if it is bad."""
    obj, lines = read_yaml_located(path, "jaw config")
    with lines.errors(str(path)):
        return parse_config(obj, str(path))


def perturbed(cfg: JawConfig, rng, zero_deg: float = 1.75, link_mm: float = 1.0,
              pad_mm: float = 0.5) -> JawConfig:
    """A jaw that differs from ``cfg`` as a real one does: every joint's zero (``zero_tick``,
    by up to ``zero_deg`` degrees in its model's ticks) and ``link_mm`` and every pad's
    ``offset_mm`` off by uniform errors within ± the given bounds, drawn from the numpy
    Generator ``rng`` (for ``tactile sim --truth-config`` experiments, the calibration tests
    and benchmark)."""
    fingers = []
    for f in cfg.fingers:
        joints = tuple(replace(j, zero_tick=j.zero_tick + rng.uniform(-zero_deg, zero_deg) * j.ticks_per_rev / 360.0,
                               link_mm=j.link_mm + rng.uniform(-link_mm, link_mm)) for j in f.joints)
        pad = replace(f.pad, offset_mm=f.pad.offset_mm + rng.uniform(-pad_mm, pad_mm))
        fingers.append(replace(f, joints=joints, pad=pad))
    return replace(cfg, fingers=tuple(fingers))


def _num(v: float) -> float | int:
    """Integers stay integers in YAML; other floats round-trip exactly (repr)."""
    return int(v) if float(v).is_integer() else float(v)


def _declared(obj, keys: tuple[str, ...]) -> dict:
    """The declared errors among ``keys`` (nonzero ones only: a config without errors is
    written as before)."""
    return {k: _num(getattr(obj, k)) for k in keys if getattr(obj, k)}


def states_calibration(cfg: JawConfig) -> bool:
    """Whether the jaw states what a calibration left of its zeros' errors (some joint's
    ``zero_sigma_deg``, written by ``tactile calibrate``): without it the stated noise holds the
    encoders' ticks and backlash only, not the zeros' errors (docs/estimation.md)."""
    return any(j.zero_sigma_deg > 0.0 for j in cfg.joints)


def declares_errors(cfg: JawConfig) -> bool:
    """Whether the jaw declares any servo error (backlash, compliance) for the emulator."""
    return any(j.backlash_deg or j.compliance_deg_per_nm for j in cfg.joints) or any(
        f.pad.compliance_mm_per_n for f in cfg.fingers)


def config_to_mapping(cfg: JawConfig) -> dict:
    """The YAML mapping of a config (inverse of :func:`parse_config`)."""
    return {
        "bus": {"port": cfg.bus.port, "baudrate": cfg.bus.baudrate, "protocol": cfg.bus.protocol,
                "retries": cfg.bus.retries, "timeout_s": cfg.bus.timeout_s, "watchdog_ms": cfg.bus.watchdog_ms},
        "fingers": [{
            "name": f.name,
            "base": {"x": _num(f.base.x), "y": _num(f.base.y), "angle_deg": _num(f.base.angle_deg)},
            "joints": [{"id": j.id, "model": j.model, "zero_tick": _num(j.zero_tick), "link_mm": _num(j.link_mm),
                        "direction": j.direction, "min_deg": _num(j.min_deg), "max_deg": _num(j.max_deg),
                        "current_limit_ma": _num(j.current_limit_ma),
                        **_declared(j, ("backlash_deg", "compliance_deg_per_nm", "zero_sigma_deg", "link_sigma_mm",
                                        "compliance_sigma_deg_per_nm"))}
                       for j in f.joints],
            "pad": {"side": f.pad.side, "offset_mm": _num(f.pad.offset_mm), "length_mm": _num(f.pad.length_mm),
                    **_declared(f.pad, ("compliance_mm_per_n", "offset_sigma_mm", "compliance_sigma_mm_per_n"))},
        } for f in cfg.fingers],
        "motion": {k: _num(v) if isinstance(v, float) else v for k, v in asdict(cfg.motion).items()},
        "workspace": {"center_mm": [_num(v) for v in cfg.workspace.center_mm],
                      "radius_mm": _num(cfg.workspace.radius_mm)},
    }


def dump_config(cfg: JawConfig, path: str | Path, header: str | None = None, source: str | Path | None = None) -> None:
    """Write ``cfg`` as YAML that :func:`load_config` reads back to an equal config, whole
    or not at all (tactile_common.files.atomic_write). With ``source``, the config file
    ``cfg`` was made from (a calibration's), its text is kept, comments and layout included,
    and only the values that differ are rewritten (:func:`_rewritten`)."""
    text = _rewritten(cfg, Path(source)) if source is not None else None
    if text is None:
        text = yaml.safe_dump(config_to_mapping(cfg), sort_keys=False, default_flow_style=None, width=120)
    if header:
        text = "".join(f"# {line}\n" for line in header.splitlines()) + text
    atomic_write(path, text)


def _rewritten(cfg: JawConfig, source: Path) -> str | None:
    """``source``'s text with the values of ``cfg`` that differ from the config it holds
    written in place (ruamel.yaml's round trip keeps comments, flow style and key order),
    or None when the source cannot be read back so (then the config is written plainly)."""
    from io import StringIO

    from ruamel.yaml import YAML

    rt = YAML()
    rt.width = 4096  # keep each flow mapping on its line
    rt.indent(mapping=2, sequence=4, offset=2)  # config/jaw.yaml's "  - " lists
    try:
        doc = rt.load(source.read_text(encoding="utf-8"))
        old = config_to_mapping(load_config(source))
    except Exception:  # noqa: BLE001 - any failure only loses the comments
        return None
    _set_changed(doc, old, config_to_mapping(cfg))
    out = StringIO()
    rt.dump(doc, out)
    return out.getvalue()


def _set_changed(doc, old, new) -> None:
    """Set in ``doc`` (the source's round-trip tree) every leaf where ``new`` differs from
    ``old`` (the source's own values, defaults included), recursing through mappings and lists;
    a key ``new`` adds (a calibration's ``backlash_deg``, ``zero_sigma_deg``) is appended, a
    key it drops (an optional value now zero) removed."""
    if isinstance(new, dict):
        for key in [k for k in old if k not in new and k in doc]:
            del doc[key]
    for key in (new.keys() if isinstance(new, dict) else range(len(new))):
        was, now = (old.get(key) if isinstance(old, dict) else old[key]), new[key]
        if isinstance(now, (dict, list)) and isinstance(doc.get(key) if isinstance(doc, dict) else doc[key],
                                                        (dict, list)):
            _set_changed(doc[key], was, now)
        elif was != now:
            doc[key] = now
