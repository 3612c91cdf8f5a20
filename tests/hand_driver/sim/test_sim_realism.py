"""The emulated servos behave as the ROBOTIS e-Manual describes where other tools look,
checked through the real dynamixel_sdk: ID and baud changes, factory reset, clear,
indirect addressing, Startup Configuration, Secondary ID, Bus Watchdog, overload."""

import pytest
from dynamixel_sdk import COMM_RX_TIMEOUT, COMM_SUCCESS, GroupSyncWrite

from hand_driver.sim import protocol as P
from hand_driver.sim.servo import OVERLOAD_TIME_S
from hand_driver.units import ticks_to_rad

ERR_RESULT_FAIL, ERR_DATA_RANGE = 1, 4


class WallAtTick2100:
    """The world of the overload tests: joint 1 (servo 1, zero tick 2048) cannot pass tick 2100."""

    def constrain(self, q_from, q_to):
        q = list(q_to)
        q[0] = min(q[0], float(ticks_to_rad(2100, 2048, 1, 4096)))
        return q


@pytest.fixture
def link(sdk_link):
    return sdk_link(time_scale=0.0, slack_ms=1000.0)  # simulated time moves only by sim.step


def test_new_id_answers_this_packet_under_the_old_id_then_only_the_new(link):
    sim, port, ph = link
    assert ph.write1ByteTxRx(port, 2, 7, 9) == (COMM_SUCCESS, 0)
    assert ph.ping(port, 2)[1] == COMM_RX_TIMEOUT
    assert ph.ping(port, 9) == (1220, COMM_SUCCESS, 0)
    assert ph.read4ByteTxRx(port, 9, 132) == (1000, COMM_SUCCESS, 0)
    assert ph.write1ByteTxRx(port, 9, 64, 1) == (COMM_SUCCESS, 0)
    assert sim.servos[2].torque_on  # the servo created as id 2


def test_new_baud_rate_takes_effect_after_the_status(link):
    sim, port, ph = link
    assert ph.write1ByteTxRx(port, 5, 8, 1) == (COMM_SUCCESS, 0)  # 57600, answered at 1 Mbit/s
    assert ph.ping(port, 5)[1] == COMM_RX_TIMEOUT
    port.setBaudRate(57600)
    assert ph.ping(port, 5) == (1060, COMM_SUCCESS, 0)
    assert ph.ping(port, 1)[1] == COMM_RX_TIMEOUT


@pytest.mark.parametrize("option, then_id, then_baud", [(P.FACTORY_RESET_ALL, 1, 57600),
                                                        (P.FACTORY_RESET_KEEP_ID, 2, 57600),
                                                        (P.FACTORY_RESET_KEEP_ID_BAUD, 2, 1_000_000)])
def test_factory_reset_options(link, option, then_id, then_baud):
    sim, port, ph = link
    assert ph.write1ByteTxRx(port, 2, 65, 1) == (COMM_SUCCESS, 0)  # LED (RAM)
    assert ph.write1ByteTxRx(port, 2, 9, 7) == (COMM_SUCCESS, 0)  # Return Delay Time (EEPROM)
    assert ph.factoryReset(port, 2, option) == (COMM_SUCCESS, 0)
    sim.step(1.0)  # it reboots
    port.setBaudRate(then_baud)
    assert ph.ping(port, then_id)[:2] == (1220, COMM_SUCCESS)
    assert ph.read1ByteTxRx(port, then_id, 9) == (250, COMM_SUCCESS, 0)
    assert ph.read1ByteTxRx(port, then_id, 65) == (0, COMM_SUCCESS, 0)


def test_broadcast_factory_reset_of_everything_is_ignored(link):
    sim, port, ph = link
    assert ph.factoryReset(port, 0xFE, P.FACTORY_RESET_ALL)[0] == COMM_SUCCESS
    sim.wait_idle()
    sim.step(1.0)
    assert [ph.ping(port, i)[1] for i in (1, 2, 5)] == [COMM_SUCCESS] * 3


def test_clear_puts_a_multi_turn_position_back_into_one_turn(link):
    sim, port, ph = link
    assert ph.write1ByteTxRx(port, 1, 11, 4) == (COMM_SUCCESS, 0)  # extended position mode
    assert ph.write1ByteTxRx(port, 1, 64, 1) == (COMM_SUCCESS, 0)
    assert ph.write4ByteTxRx(port, 1, 116, 2048 + 2 * 4096 + 100) == (COMM_SUCCESS, 0)
    sim.step(0.05)
    assert ph.clearMultiTurn(port, 1) == (COMM_SUCCESS, ERR_RESULT_FAIL)  # refused while moving
    sim.step(10.0)
    assert ph.read4ByteTxRx(port, 1, 132)[0] == 2048 + 2 * 4096 + 100
    assert ph.clearMultiTurn(port, 1) == (COMM_SUCCESS, 0)
    assert ph.read4ByteTxRx(port, 1, 132)[0] == 2148
    sim.step(1.0)
    assert ph.read4ByteTxRx(port, 1, 132)[0] == 2148  # and it stays there


def test_indirect_addresses_map_items_into_one_block(link):
    sim, port, ph = link
    assert ph.read2ByteTxRx(port, 1, 168) == (224, COMM_SUCCESS, 0)  # default: its own data byte
    # Present Position (132..135) then Moving (122) into Indirect Data 1..5
    for k, addr in enumerate((132, 133, 134, 135, 122)):
        assert ph.write2ByteTxRx(port, 1, 168 + 2 * k, addr) == (COMM_SUCCESS, 0)
    data, result, error = ph.readTxRx(port, 1, 224, 5)
    assert (result, error) == (COMM_SUCCESS, 0) and int.from_bytes(bytes(data[:4]), "little") == 2048
    # Goal Position written through Indirect Data 29..32 (address 578.., data 634..)
    for k, addr in enumerate((116, 117, 118, 119)):
        assert ph.write2ByteTxRx(port, 1, 578 + 2 * k, addr) == (COMM_SUCCESS, 0)
    assert ph.write4ByteTxRx(port, 1, 634, 2100) == (COMM_SUCCESS, 0)
    assert ph.read4ByteTxRx(port, 1, 116) == (2100, COMM_SUCCESS, 0)
    assert ph.write2ByteTxRx(port, 1, 634, 7) == (COMM_SUCCESS, 5)  # half an item: data length error
    assert ph.write2ByteTxRx(port, 1, 168, 700) == (COMM_SUCCESS, ERR_DATA_RANGE)  # beyond the table


def test_startup_configuration_turns_torque_on_after_reboot(link):
    sim, port, ph = link
    assert ph.read1ByteTxRx(port, 2, 60) == (0, COMM_SUCCESS, 0)
    assert ph.write1ByteTxRx(port, 2, 60, 1) == (COMM_SUCCESS, 0)
    assert ph.reboot(port, 2) == (COMM_SUCCESS, 0)
    sim.step(1.0)
    assert ph.read1ByteTxRx(port, 2, 64) == (1, COMM_SUCCESS, 0)
    assert ph.write1ByteTxRx(port, 2, 60, 4) == (COMM_SUCCESS, 7)  # EEPROM with torque on


def test_secondary_id_obeys_without_answering(link):
    sim, port, ph = link
    for i in (1, 2):
        assert ph.write1ByteTxRx(port, i, 12, 20) == (COMM_SUCCESS, 0)
    assert ph.write1ByteTxRx(port, 20, 65, 1)[0] == COMM_RX_TIMEOUT  # no status from a secondary ID
    assert [sim.servos[i].get("led") for i in (1, 2, 5)] == [1, 1, 0]


def test_bus_watchdog_stops_motion_and_locks_goals_until_cleared(link):
    sim, port, ph = link
    assert ph.write1ByteTxRx(port, 1, 64, 1) == (COMM_SUCCESS, 0)
    assert ph.write1ByteTxRx(port, 1, 98, 5) == (COMM_SUCCESS, 0)  # 5 × 20 ms
    assert ph.write4ByteTxRx(port, 1, 116, 3000) == (COMM_SUCCESS, 0)
    t_last = sim.sim_time
    sim.step(1.0)  # the host is silent for 1 s
    s = sim.servos[1]
    assert s.watchdog_tripped_at == pytest.approx(t_last + 0.1, abs=1e-9)
    stopped = ph.read4ByteTxRx(port, 1, 132)[0]
    assert 2048 < stopped < 3000
    assert ph.read1ByteTxRx(port, 1, 98)[0] == 0xFF  # −1
    assert ph.write4ByteTxRx(port, 1, 116, 2500) == (COMM_SUCCESS, ERR_DATA_RANGE)
    assert ph.write1ByteTxRx(port, 1, 98, 0) == (COMM_SUCCESS, 0)  # clears the error
    sim.step(0.5)
    assert ph.read4ByteTxRx(port, 1, 132)[0] == stopped  # holds until a new goal
    assert ph.write4ByteTxRx(port, 1, 116, 2500) == (COMM_SUCCESS, 0)
    sim.step(2.0)
    assert ph.read4ByteTxRx(port, 1, 132)[0] == 2500


def test_packets_keep_the_bus_watchdog_fed(link):
    sim, port, ph = link
    ph.write1ByteTxRx(port, 1, 64, 1)
    ph.write1ByteTxRx(port, 1, 98, 5)
    ph.write4ByteTxRx(port, 1, 116, 3000)
    for _ in range(40):  # a read every 60 ms of simulated time: under 100 ms
        sim.step(0.06)
        assert ph.read1ByteTxRx(port, 1, 98)[0] == 5
    assert ph.read4ByteTxRx(port, 1, 132)[0] == 3000


def test_sustained_stall_raises_the_overload_error(link):
    sim, port, ph = link
    sim.world = WallAtTick2100()
    assert ph.write1ByteTxRx(port, 1, 64, 1) == (COMM_SUCCESS, 0)  # position mode (3): no current cap
    assert ph.write4ByteTxRx(port, 1, 116, 2100 + 60) == (COMM_SUCCESS, 0)  # 60 ticks short: 480 units, 1.3 A
    sim.step(OVERLOAD_TIME_S - 0.5)
    assert ph.read1ByteTxRx(port, 1, 70) == (0, COMM_SUCCESS, 0)
    sim.step(1.0)
    value, result, error = ph.read1ByteTxRx(port, 1, 70)
    assert (value, result, error) == (0x20, COMM_SUCCESS, 0x80)
    assert ph.read1ByteTxRx(port, 1, 64)[0] == 0  # torque dropped


def test_pressing_at_a_low_goal_current_never_overloads(link):
    sim, port, ph = link
    sim.world = WallAtTick2100()
    assert ph.write1ByteTxRx(port, 1, 11, 5) == (COMM_SUCCESS, 0)  # current-based position
    assert ph.write2ByteTxRx(port, 1, 102, 111) == (COMM_SUCCESS, 0)  # 300 mA cap
    w = GroupSyncWrite(port, ph, 64, 1)
    w.addParam(1, [1])
    assert w.txPacket() == COMM_SUCCESS
    assert ph.write4ByteTxRx(port, 1, 116, 2400) == (COMM_SUCCESS, 0)
    sim.step(3 * OVERLOAD_TIME_S)
    assert ph.read2ByteTxRx(port, 1, 126)[0] == 111
    assert ph.read1ByteTxRx(port, 1, 70) == (0, COMM_SUCCESS, 0)
