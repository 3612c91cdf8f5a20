"""Typed errors of the servo bus.

Run-time faults derive from :class:`tactile_common.errors.DeviceFault` (the CLI exits 1 with
the message); mistakes a person fixes in a config or a call derive from
:class:`tactile_common.errors.InputError` (exit 2). Every message is one line.
"""

from __future__ import annotations

from tactile_common.errors import DeviceFault, InputError


class BusError(DeviceFault):
    """A fault on the Dynamixel bus."""


class BusTimeout(BusError):
    """No status packet arrived in time (after every bounded retry)."""


class CrcError(BusError):
    """A status packet arrived corrupt (bad CRC, truncated or malformed)."""


class PortError(BusError):
    """The serial port cannot be opened, or vanished while open (adapter unplugged)."""


class ServoStatusError(BusError):
    """A servo answered with an error code in its status packet (data range, access, ...)."""

    def __init__(self, servo_id: int, code: int, name: str, what: str):
        self.servo_id, self.code, self.name = servo_id, code, name
        super().__init__(f"servo {servo_id} refused {what}: {name} (status error {code})")


class ServoHardwareError(BusError):
    """A servo reports a hardware error (alert bit); its torque is off until reboot."""

    def __init__(self, servo_id: int, bits: int, names: list[str]):
        self.servo_id, self.bits, self.names = servo_id, bits, list(names)
        text = ", ".join(names) if names else "unknown"
        super().__init__(
            f"servo {servo_id} hardware error 0x{bits:02X} ({text}); torque is off, "
            f"fix the cause and reboot the servo (tactile scan lists it)"
        )


class JointLimitError(InputError):
    """A goal outside a joint's configured limits; nothing was written."""


class CapabilityError(InputError):
    """The servo model cannot do what was asked (e.g. current sensing on an XL430)."""


class ModelMismatchError(InputError):
    """The servo on the bus is not the model the jaw config names."""
