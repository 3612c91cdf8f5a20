"""The real dynamixel_sdk on the emulated bus's pty: three servos of three models."""

from __future__ import annotations

import contextlib

import pytest
from dynamixel_sdk import PacketHandler, PortHandler

from hand_driver.config import JointConfig
from hand_driver.sim.server import EmulatedBus

SDK_JOINTS = (JointConfig(1, "XM430-W350", 2048, 50.0), JointConfig(2, "XC330-T288", 1000, 50.0),
              JointConfig(5, "XL430-W250", 3000, 50.0))


class SlackPort(PortHandler):
    """The SDK's port with ``slack_ms`` of timeout margin beyond its own (34 ms at 1 Mbps):
    the emulator's thread shares a loaded host with the tests (216 ms was missed at load 16).
    Bounded: every answer a test expects to be missing costs it."""

    slack_ms = 1000.0

    def setPacketTimeout(self, packet_length):  # noqa: N802 - SDK name
        super().setPacketTimeout(packet_length)
        self.packet_timeout += self.slack_ms


@pytest.fixture
def sdk_link():
    """``sdk_link(time_scale, slack_ms)`` → (sim, port, packet handler) over ``SDK_JOINTS``,
    port closed and bus stopped after the test."""
    with contextlib.ExitStack() as stack:
        def open_link(time_scale: float, slack_ms: float = SlackPort.slack_ms):
            sim = stack.enter_context(EmulatedBus(list(SDK_JOINTS), time_scale=time_scale))
            port = SlackPort(sim.port)
            port.slack_ms = slack_ms
            assert port.openPort()
            stack.callback(port.closePort)
            return sim, port, PacketHandler(2.0)
        yield open_link
