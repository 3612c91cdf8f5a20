"""The real dynamixel_sdk and pyserial talking to the emulated bus through its pty."""

import pytest
from dynamixel_sdk import (
    COMM_RX_TIMEOUT,
    COMM_SUCCESS,
    GroupBulkRead,
    GroupBulkWrite,
    GroupSyncRead,
    GroupSyncWrite,
)


@pytest.fixture
def link(sdk_link):
    return sdk_link(time_scale=20.0)


def test_ping_reports_model_numbers_and_missing_id_times_out(link):
    sim, port, ph = link
    assert ph.ping(port, 1) == (1020, COMM_SUCCESS, 0)
    assert ph.ping(port, 2) == (1220, COMM_SUCCESS, 0)
    assert ph.ping(port, 5) == (1060, COMM_SUCCESS, 0)
    assert ph.ping(port, 9)[1] == COMM_RX_TIMEOUT
    found, result = ph.broadcastPing(port)
    assert result == COMM_SUCCESS and found == {1: [1020, 46], 2: [1220, 46], 5: [1060, 46]}


def test_servos_answer_only_at_their_baud_rate(link):
    sim, port, ph = link
    port.setBaudRate(57600)
    assert ph.ping(port, 1)[1] == COMM_RX_TIMEOUT
    port.setBaudRate(1000000)
    assert ph.ping(port, 1)[1] == COMM_SUCCESS


def test_read_write_and_status_errors(link):
    sim, port, ph = link
    assert ph.read4ByteTxRx(port, 2, 132) == (1000, COMM_SUCCESS, 0)
    assert ph.write1ByteTxRx(port, 1, 9, 0) == (COMM_SUCCESS, 0)
    assert sim.servos[1].get("return_delay_time") == 0
    assert ph.write1ByteTxRx(port, 1, 64, 7) == (COMM_SUCCESS, 4)  # data range error
    assert ph.write4ByteTxRx(port, 1, 132, 7) == (COMM_SUCCESS, 7)  # access error: read-only
    assert ph.write1ByteTxRx(port, 1, 64, 1) == (COMM_SUCCESS, 0)
    assert ph.write1ByteTxRx(port, 1, 11, 5) == (COMM_SUCCESS, 7)  # EEPROM with torque on
    assert ph.write4ByteTxRx(port, 1, 116, 9999) == (COMM_SUCCESS, 6)  # beyond position limit
    assert ph.write2ByteTxRx(port, 5, 102, 10) == (COMM_SUCCESS, 7)  # XL430 has no Goal Current
    # broadcast write: applied by every servo, no status packet
    assert ph.write1ByteTxRx(port, 0xFE, 65, 1) == (COMM_SUCCESS, 0)
    sim.wait_idle()
    assert all(s.get("led") == 1 for s in sim.servos.values())


def test_sync_write_then_sync_and_fast_sync_read_see_motion(link):
    sim, port, ph = link
    w = GroupSyncWrite(port, ph, 64, 1)
    for i in (1, 2, 5):
        w.addParam(i, [1])
    assert w.txPacket() == COMM_SUCCESS
    w = GroupSyncWrite(port, ph, 116, 4)
    goals = {1: 2100, 2: 1100, 5: 2900}
    for i, g in goals.items():
        w.addParam(i, list(g.to_bytes(4, "little")))
    assert w.txPacket() == COMM_SUCCESS
    sim.wait_idle()
    sim.step(3.0)  # plenty of simulated time to arrive
    r = GroupSyncRead(port, ph, 122, 14)
    for i in goals:
        r.addParam(i)
    assert r.txRxPacket() == COMM_SUCCESS
    assert {i: r.getData(i, 132, 4) for i in goals} == goals
    assert r.fastSyncRead() == COMM_SUCCESS
    assert {i: r.getData(i, 132, 4) for i in goals} == goals


def test_bulk_read_write_and_fast_bulk_read(link):
    sim, port, ph = link
    w = GroupBulkWrite(port, ph)
    assert w.addParam(1, 65, 1, [1]) and w.addParam(2, 112, 4, list((77).to_bytes(4, "little")))
    assert w.txPacket() == COMM_SUCCESS
    sim.wait_idle()
    assert sim.servos[1].get("led") == 1 and sim.servos[2].get("profile_velocity") == 77
    r = GroupBulkRead(port, ph)
    r.addParam(1, 0, 2)
    r.addParam(2, 112, 4)
    r.addParam(5, 132, 4)
    assert r.txRxPacket() == COMM_SUCCESS
    assert (r.getData(1, 0, 2), r.getData(2, 112, 4), r.getData(5, 132, 4)) == (1020, 77, 3000)
    assert r.fastBulkRead() == COMM_SUCCESS
    assert (r.getData(1, 0, 2), r.getData(2, 112, 4), r.getData(5, 132, 4)) == (1020, 77, 3000)


def test_reboot_clears_hardware_error(link):
    sim, port, ph = link
    ph.write1ByteTxRx(port, 1, 64, 1)
    sim.hardware_error(1, 0x20)
    _, result, error = ph.read1ByteTxRx(port, 1, 64)
    assert result == COMM_SUCCESS and error & 0x80
    assert ph.read1ByteTxRx(port, 1, 70)[0] == 0x20
    assert ph.write1ByteTxRx(port, 1, 64, 1) == (COMM_SUCCESS, 0x80 | 1)  # result fail
    assert ph.reboot(port, 1) == (COMM_SUCCESS, 0x80)
    sim.step(1.0)  # boot time passes
    assert ph.read1ByteTxRx(port, 1, 70) == (0, COMM_SUCCESS, 0)


def test_corrupted_instruction_gets_crc_error_status(link):
    sim, port, ph = link
    sim.faults.corrupt_instruction(1)
    assert ph.read1ByteTxRx(port, 1, 7)[1:] == (COMM_SUCCESS, 3)
    assert ph.read1ByteTxRx(port, 1, 7) == (1, COMM_SUCCESS, 0)
