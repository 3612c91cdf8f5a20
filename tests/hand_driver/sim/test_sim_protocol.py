"""Protocol 2.0 framing against the e-Manual's example packets and the SDK's own code."""

from hypothesis import given, settings, strategies as st

from dynamixel_sdk import PacketHandler

from hand_driver.sim import protocol as P

# ROBOTIS e-Manual, Protocol 2.0 examples (instruction and status packets of ID 1).
VECTORS = [
    (P.build_instruction(1, P.INST_PING), "FF FF FD 00 01 03 00 01 19 4E"),
    (P.build_status(1, 0, bytes([0x06, 0x04, 0x26])), "FF FF FD 00 01 07 00 55 00 06 04 26 65 5D"),
    (P.build_instruction(1, P.INST_READ, bytes([0x84, 0, 4, 0])), "FF FF FD 00 01 07 00 02 84 00 04 00 1D 15"),
    (P.build_status(1, 0, bytes([0xA6, 0, 0, 0])), "FF FF FD 00 01 08 00 55 00 A6 00 00 00 8C C0"),
    (P.build_instruction(1, P.INST_WRITE, bytes([0x74, 0, 0, 2, 0, 0])), "FF FF FD 00 01 09 00 03 74 00 00 02 00 00 CA 89"),
    (P.build_status(1, 0), "FF FF FD 00 01 04 00 55 00 A1 0C"),
]


def test_packets_match_emanual_examples_byte_for_byte():
    for packet, expected in VECTORS:
        assert packet == bytes.fromhex(expected)


@settings(max_examples=200, deadline=None)
@given(st.binary(min_size=0, max_size=64))
def test_crc_equals_sdk_table_crc(data):
    assert P.crc16(data) == PacketHandler(2.0).updateCRC(0, list(data), len(data))


def test_crc_runs_incrementally():
    data = bytes(range(40))
    assert P.crc16(data[20:], P.crc16(data[:20])) == P.crc16(data)


def test_stuffing_known_vector():
    assert P.stuff(bytes.fromhex("03 FF FF FD 01")) == bytes.fromhex("03 FF FF FD FD 01")
    assert P.unstuff(bytes.fromhex("03 FF FF FD FD 01")) == bytes.fromhex("03 FF FF FD 01")


@settings(max_examples=200, deadline=None)
@given(st.integers(0, 252), st.lists(st.sampled_from([0xFF, 0xFD, 0x00, 0x55]), max_size=40))
def test_stuffed_packet_equals_sdk_and_parses_back(dxl_id, params):
    body = bytes([P.INST_WRITE]) + bytes(params)
    ours = P.build_packet(dxl_id, body)
    sdk = PacketHandler(2.0)
    tx = [0] * 7 + list(body) + [0, 0]
    tx[4], tx[5], tx[6] = dxl_id, (len(body) + 2) & 0xFF, (len(body) + 2) >> 8
    tx = sdk.addStuffing(tx)
    n = tx[5] | (tx[6] << 8)
    tx[0:4] = [0xFF, 0xFF, 0xFD, 0x00]
    crc = sdk.updateCRC(0, tx, n + 5)
    assert ours == bytes(tx[: n + 5]) + bytes([crc & 0xFF, crc >> 8])
    (pkt,) = P.PacketParser().feed(b"\x00\xff" + ours)
    assert (pkt.dxl_id, pkt.instruction, pkt.params, pkt.crc_ok) == (dxl_id, P.INST_WRITE, bytes(params), True)


def test_parser_handles_split_input_and_flags_bad_crc():
    good = P.build_instruction(3, P.INST_PING)
    bad = good[:-1] + bytes([good[-1] ^ 1])
    parser = P.PacketParser()
    stream = good + bad
    got = []
    for i in range(len(stream)):
        got += parser.feed(stream[i : i + 1])
    assert [(p.dxl_id, p.crc_ok) for p in got] == [(3, True), (3, False)]


def test_fast_status_layout_and_running_crcs():
    pkt = P.build_fast_status([(0, 1, b"\x10\x20"), (0x80, 2, b"\x30\x40")])
    assert pkt[:8] == bytes.fromhex("FF FF FD 00 FE") + bytes([1 + 2 * 6, 0, 0x55])
    assert pkt[8:12] == bytes([0, 1, 0x10, 0x20])
    assert P.u16(pkt, 12) == P.crc16(pkt[:12])  # first slot's CRC: running CRC so far
    assert pkt[14:18] == bytes([0x80, 2, 0x30, 0x40])
    assert P.u16(pkt, 18) == P.crc16(pkt[:18])  # last one is the packet CRC
    assert len(pkt) == 7 + 13


def test_group_parameter_decoders():
    assert P.parse_sync_read(bytes([122, 0, 14, 0, 1, 2])) == (122, 14, [1, 2])
    assert P.parse_sync_write(bytes([116, 0, 2, 0, 1, 5, 6, 2, 7, 8])) == (116, 2, {1: b"\x05\x06", 2: b"\x07\x08"})
    assert P.parse_bulk_read(bytes([1, 132, 0, 4, 0])) == [(1, 132, 4)]
    assert P.parse_bulk_write(bytes([2, 64, 0, 1, 0, 1])) == [(2, 64, b"\x01")]
