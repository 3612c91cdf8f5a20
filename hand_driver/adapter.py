"""The USB serial adapter under a bus: its latency timer (Linux).

FTDI-style USB serial adapters hold received bytes up to their latency timer (default
16 ms) before passing them on, so every status packet waits for it: the most common
cause of slow Dynamixel reads. Linux shows the timer at
``/sys/bus/usb-serial/devices/<tty>/latency_timer``; 1 ms is what Dynamixel tools
recommend. :func:`latency_warning` says, once per adapter, what to do when it is higher.
"""

from __future__ import annotations

import os
from pathlib import Path

#: where Linux lists USB serial adapters
USB_SERIAL_SYSFS = Path("/sys/bus/usb-serial/devices")
#: the highest latency timer (ms) that does not slow the bus
LATENCY_OK_MS = 1

_warned: set[str] = set()


def latency_timer_ms(port: str, sysfs: Path | None = None) -> int | None:
    """The latency timer of the USB serial adapter behind ``port`` (symlinks such as
    /dev/serial/by-id/... followed), or None when the port is no USB serial adapter.
    ``sysfs``: the directory listing adapters (default USB_SERIAL_SYSFS)."""
    tty = Path(os.path.realpath(port)).name
    try:
        return int(((sysfs or USB_SERIAL_SYSFS) / tty / "latency_timer").read_text().strip())
    except (OSError, ValueError):
        return None


def latency_warning(port: str, sysfs: Path | None = None) -> str | None:
    """One line with the fix when the adapter's latency timer is above LATENCY_OK_MS, the
    first time it is asked for this adapter; None otherwise."""
    ms = latency_timer_ms(port, sysfs)
    tty = Path(os.path.realpath(port)).name
    if ms is None or ms <= LATENCY_OK_MS or tty in _warned:
        return None
    _warned.add(tty)
    path = (sysfs or USB_SERIAL_SYSFS) / tty / "latency_timer"
    return (f"{port}: the USB adapter's latency timer is {ms} ms, which delays every servo reply; set it to "
            f"{LATENCY_OK_MS} ms: echo {LATENCY_OK_MS} | sudo tee {path} (lasts until unplugged; for good: a udev "
            f"rule ACTION==\"add\", SUBSYSTEM==\"usb-serial\", DRIVER==\"ftdi_sio\", ATTR{{latency_timer}}=\"{LATENCY_OK_MS}\")")
