"""Dynamixel Protocol 2.0 framing, byte for byte.

Packet: ``FF FF FD 00 | ID | LEN_L LEN_H | INST | params… | CRC_L CRC_H`` where LEN counts
INST, params and CRC; the CRC-16 (polynomial 0x8005, initial 0, no reflection) covers
every byte from the header to the last parameter, after byte stuffing (any
``FF FF FD`` inside INST/params is sent as ``FF FF FD FD``). A status packet has
INST 0x55 followed by an error byte. Fast Sync Read / Fast Bulk Read answer with one
combined status packet (ID 0xFE): ``55`` then per servo ``ERR ID DATA… CRC`` where each
CRC is the running CRC of the packet so far, so the last one is the packet's CRC; the
combined packet is not stuffed (the SDK reads it positionally).
"""

from __future__ import annotations

from dataclasses import dataclass

HEADER = b"\xff\xff\xfd\x00"
BROADCAST_ID = 0xFE
INST_PING = 0x01
INST_READ = 0x02
INST_WRITE = 0x03
INST_REG_WRITE = 0x04
INST_ACTION = 0x05
INST_FACTORY_RESET = 0x06
INST_REBOOT = 0x08
INST_CLEAR = 0x10
INST_STATUS = 0x55
INST_SYNC_READ = 0x82
INST_SYNC_WRITE = 0x83
INST_FAST_SYNC_READ = 0x8A
INST_BULK_READ = 0x92
INST_BULK_WRITE = 0x93
INST_FAST_BULK_READ = 0x9A

#: Factory Reset (0x06) options: everything; all but the ID; all but the ID and baud rate
FACTORY_RESET_ALL = 0xFF
FACTORY_RESET_KEEP_ID = 0x01
FACTORY_RESET_KEEP_ID_BAUD = 0x02
#: Clear (0x10) parameters that reset the multi-turn revolution count
CLEAR_REVOLUTION = bytes([0x01, 0x44, 0x58, 0x4C, 0x22])

ERR_RESULT_FAIL = 1
ERR_INSTRUCTION = 2
ERR_CRC = 3
ERR_DATA_RANGE = 4
ERR_DATA_LENGTH = 5
ERR_DATA_LIMIT = 6
ERR_ACCESS = 7


def _make_table() -> list[int]:
    table = []
    for i in range(256):
        crc = i << 8
        for _ in range(8):
            crc = ((crc << 1) ^ 0x8005) if crc & 0x8000 else (crc << 1)
        table.append(crc & 0xFFFF)
    return table


_CRC_TABLE = _make_table()


def crc16(data: bytes | bytearray, crc: int = 0) -> int:
    """CRC-16/BUYPASS (poly 0x8005) as Protocol 2.0 uses it; ``crc`` continues a running CRC."""
    for b in data:
        crc = ((crc << 8) ^ _CRC_TABLE[((crc >> 8) ^ b) & 0xFF]) & 0xFFFF
    return crc


def stuff(body: bytes) -> bytes:
    """Insert 0xFD after every ``FF FF FD`` in INST+params."""
    out = bytearray()
    for b in body:
        out.append(b)
        if b == 0xFD and len(out) >= 3 and out[-3] == 0xFF and out[-2] == 0xFF:
            out.append(0xFD)
    return bytes(out)


def unstuff(body: bytes) -> bytes:
    """Remove the 0xFD stuffed after every ``FF FF FD``."""
    out = bytearray()
    i = 0
    while i < len(body):
        out.append(body[i])
        if body[i] == 0xFD and len(out) >= 3 and out[-3] == 0xFF and out[-2] == 0xFF:
            if i + 1 < len(body) and body[i + 1] == 0xFD:
                i += 1
        i += 1
    return bytes(out)


def build_packet(dxl_id: int, body: bytes) -> bytes:
    """Frame INST+params: header, ID, length, stuffed body, CRC."""
    sb = stuff(bytes(body))
    n = len(sb) + 2
    head = HEADER + bytes([dxl_id, n & 0xFF, n >> 8]) + sb
    c = crc16(head)
    return head + bytes([c & 0xFF, c >> 8])


def build_instruction(dxl_id: int, inst: int, params: bytes = b"") -> bytes:
    return build_packet(dxl_id, bytes([inst]) + bytes(params))


def build_status(dxl_id: int, error: int, params: bytes = b"") -> bytes:
    return build_packet(dxl_id, bytes([INST_STATUS, error]) + bytes(params))


def build_fast_status(slots: list[tuple[int, int, bytes]]) -> bytes:
    """Combined Fast Sync/Bulk Read status: ``slots`` = [(error, id, data), …] in order."""
    n = 1 + sum(4 + len(d) for _, _, d in slots)
    out = bytearray(HEADER + bytes([BROADCAST_ID, n & 0xFF, n >> 8, INST_STATUS]))
    for err, dxl_id, data in slots:
        out += bytes([err, dxl_id]) + bytes(data)
        c = crc16(out)
        out += bytes([c & 0xFF, c >> 8])
    return bytes(out)


@dataclass(frozen=True)
class Packet:
    """A received packet. ``crc_ok`` False: framing was fine but the CRC did not match."""

    dxl_id: int
    instruction: int
    params: bytes
    crc_ok: bool = True


class PacketParser:
    """Incremental parser: ``feed(bytes)`` returns the complete packets found so far."""

    MAX_LEN = 1024

    def __init__(self) -> None:
        self._buf = bytearray()

    def feed(self, data: bytes) -> list[Packet]:
        self._buf += data
        out: list[Packet] = []
        while True:
            start = self._buf.find(HEADER)
            if start < 0:
                # keep a possible partial header at the end
                del self._buf[: max(0, len(self._buf) - 3)]
                return out
            del self._buf[:start]
            if len(self._buf) < 7:
                return out
            n = self._buf[5] | (self._buf[6] << 8)
            if n < 3 or n > self.MAX_LEN:
                del self._buf[:1]
                continue
            if len(self._buf) < 7 + n:
                return out
            raw = bytes(self._buf[: 7 + n])
            del self._buf[: 7 + n]
            body = unstuff(raw[7:-2])
            ok = crc16(raw[:-2]) == (raw[-2] | (raw[-1] << 8))
            out.append(Packet(raw[4], body[0], body[1:], ok))


def u16(b: bytes, i: int = 0) -> int:
    return b[i] | (b[i + 1] << 8)


def p16(v: int) -> bytes:
    return bytes([v & 0xFF, (v >> 8) & 0xFF])


def parse_sync_read(params: bytes) -> tuple[int, int, list[int]]:
    """(address, length, ids) of a (Fast) Sync Read."""
    return u16(params, 0), u16(params, 2), list(params[4:])


def parse_sync_write(params: bytes) -> tuple[int, int, dict[int, bytes]]:
    """(address, length, {id: data}) of a Sync Write; ValueError if malformed."""
    addr, n = u16(params, 0), u16(params, 2)
    rest = params[4:]
    if n == 0 or len(rest) % (n + 1):
        raise ValueError("sync write parameter length is not a multiple of 1 + data length")
    return addr, n, {rest[i]: bytes(rest[i + 1 : i + 1 + n]) for i in range(0, len(rest), n + 1)}


def parse_bulk_read(params: bytes) -> list[tuple[int, int, int]]:
    """[(id, address, length), …] of a (Fast) Bulk Read."""
    if len(params) % 5:
        raise ValueError("bulk read parameter length is not a multiple of 5")
    return [(params[i], u16(params, i + 1), u16(params, i + 3)) for i in range(0, len(params), 5)]


def parse_bulk_write(params: bytes) -> list[tuple[int, int, bytes]]:
    """[(id, address, data), …] of a Bulk Write."""
    out, i = [], 0
    while i < len(params):
        if i + 5 > len(params):
            raise ValueError("truncated bulk write entry")
        dxl_id, addr, n = params[i], u16(params, i + 1), u16(params, i + 3)
        data = params[i + 5 : i + 5 + n]
        if len(data) != n:
            raise ValueError("truncated bulk write data")
        out.append((dxl_id, addr, bytes(data)))
        i += 5 + n
    return out
