"""The USB adapter's latency timer, read from a fake sysfs tree."""

import logging
import os

from hand_driver import adapter
from hand_driver.bus import JointBus


def test_high_latency_timer_is_reported_once_with_the_fix(tmp_path, monkeypatch):
    monkeypatch.setattr(adapter, "_warned", set())
    sysfs = tmp_path / "sys"
    (sysfs / "ttyUSB7").mkdir(parents=True)
    (sysfs / "ttyUSB7" / "latency_timer").write_text("16\n")
    dev = tmp_path / "dev"
    dev.mkdir()
    (dev / "ttyUSB7").touch()
    (dev / "usb-FTDI_jaw-if00-port0").symlink_to(dev / "ttyUSB7")  # as /dev/serial/by-id/...
    port = str(dev / "usb-FTDI_jaw-if00-port0")
    assert adapter.latency_timer_ms(port, sysfs) == 16
    line = adapter.latency_warning(port, sysfs)
    assert "latency timer is 16 ms" in line and f"echo 1 | sudo tee {sysfs}/ttyUSB7/latency_timer" in line
    assert "udev" in line and "\n" not in line
    assert adapter.latency_warning(port, sysfs) is None  # once per adapter


def test_low_timer_and_non_usb_ports_say_nothing(tmp_path, monkeypatch):
    monkeypatch.setattr(adapter, "_warned", set())
    sysfs = tmp_path / "sys"
    (sysfs / "ttyUSB0").mkdir(parents=True)
    (sysfs / "ttyUSB0" / "latency_timer").write_text("1\n")
    assert adapter.latency_timer_ms("/dev/ttyUSB0", sysfs) == 1
    assert adapter.latency_warning("/dev/ttyUSB0", sysfs) is None
    assert adapter.latency_timer_ms("/dev/pts/3", sysfs) is None
    assert adapter.latency_warning("/dev/pts/3", sysfs) is None


def test_opening_a_bus_warns_about_a_slow_adapter(sim, bus_joints, tmp_path, monkeypatch, caplog):
    monkeypatch.setattr(adapter, "_warned", set())
    sysfs = tmp_path / "sys"
    tty = os.path.basename(os.path.realpath(sim.port))
    (sysfs / tty).mkdir(parents=True)
    (sysfs / tty / "latency_timer").write_text("16\n")
    monkeypatch.setattr(adapter, "USB_SERIAL_SYSFS", sysfs)
    with caplog.at_level(logging.WARNING, logger="hand_driver.bus"):
        with JointBus(sim.port, 1_000_000, bus_joints, timeout_s=0.25):
            pass
    assert caplog.text.count("latency timer is 16 ms") == 1
