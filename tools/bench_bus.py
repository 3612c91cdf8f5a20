"""Benchmark (not a test) of the bus: joint-state cycles per second and bytes per cycle.

Reads the joint-state block (Moving 122 .. Present Position 135, 14 bytes per servo)
of N servos by sync read, fast sync read and one read per servo, through the real
dynamixel_sdk and pyserial, against the emulated bus running in its own process (as
``tactile sim`` does). Bytes per cycle are counted by the emulator and checked against
the Protocol 2.0 formula; the protocol minimum is bytes × 10 bits at 1 Mbps with return
delay 0. Run: ``python -m tools.bench_bus [--cycles 300] [--servos 2,4,8]``.

``--scan-noise RUNS``: instead, ``tactile scan`` of ids 1-20 on a bus of 4 servos that
loses 10 % of its replies and corrupts 10 % (seeded per run, emulator in its own process),
with the scan's retries and with one ping and one read per id (no retries): servos found.
"""

from __future__ import annotations

import argparse
import multiprocessing as mp
import time

from hand_driver.config import JointConfig
from hand_driver.control_table import COMMON_FIELDS, MODELS

#: the joint-state block of the benchmark's XM430 servos (Moving 122 .. Present Position 135)
ADDR, LEN = MODELS["XM430-W350"].state_block()

BAUD = 1_000_000


def _serve(n: int, wire_timing: bool, conn) -> None:
    from hand_driver.sim.server import EmulatedBus

    joints = [JointConfig(i + 1, "XM430-W350", 2048, 50.0) for i in range(n)]
    with EmulatedBus(joints, wire_timing=wire_timing) as bus:
        for i in bus.servos:
            bus.servos[i].write(COMMON_FIELDS["return_delay_time"].addr, b"\x00")  # as JointBus sets it
        conn.send(bus.port)
        while conn.recv() == "stats":
            bus.wait_idle()
            conn.send((bus.bytes_in, bus.bytes_out))


def _serve_noisy(n: int, seed: int, loss: float, corrupt: float, conn) -> None:
    from hand_driver.sim.server import EmulatedBus

    joints = [JointConfig(i + 1, "XM430-W350", 2048, 50.0) for i in range(n)]
    with EmulatedBus(joints) as bus:
        bus.faults.noise(loss=loss, corrupt=corrupt, seed=seed)
        conn.send(bus.port)
        conn.recv()


def scan_noise(runs: int, loss: float = 0.1, corrupt: float = 0.1, servos: int = 4) -> None:
    """Print the servos a scan finds on a noisy bus, with and without its retries."""
    from hand_driver.bus import scan

    print(f"| scan of ids 1-20, {servos} servos, {loss:.0%} lost, {corrupt:.0%} corrupt | runs | every servo found "
          f"| servos found | s per scan |")
    print("|---|---:|---:|---:|---:|")
    for label, attempts in (("with retries (4 silent pings, 8 reads)", {}),
                            ("one ping, one read (no retries)", {"silent_pings": 1, "read_attempts": 1})):
        complete = found = 0
        seconds = 0.0
        for seed in range(runs):
            parent, child = mp.Pipe()
            proc = mp.Process(target=_serve_noisy, args=(servos, seed, loss, corrupt, child), daemon=True)
            proc.start()
            try:
                port = parent.recv()
                t0 = time.perf_counter()
                ids = {s.id for s in scan(port, range(1, 21), [BAUD], **attempts)}
                seconds += time.perf_counter() - t0
            finally:
                parent.send("stop")
                proc.join(timeout=5)
            found += len(ids & set(range(1, servos + 1)))
            complete += ids == set(range(1, servos + 1))
        print(f"| {label} | {runs} | {complete} | {found}/{servos * runs} | {seconds / runs:.2f} |", flush=True)


def formula_bytes(method: str, n: int) -> int:
    """Bytes on the wire per cycle (instruction + status packets), Protocol 2.0."""
    sync_inst = 14 + n
    if method == "sync read":
        return sync_inst + n * (11 + LEN)
    if method == "fast sync read":
        return sync_inst + 8 + n * (LEN + 4)
    return n * (14 + 11 + LEN)  # one read per servo


def measure(method: str, n: int, cycles: int, wire_timing: bool, repeats: int = 3) -> tuple[float, float, int]:
    """(best of ``repeats`` runs in cycles per second, bytes per cycle counted by the
    emulator, failed cycles: a status packet later than the SDK's timeout on a loaded host)."""
    from dynamixel_sdk import COMM_SUCCESS, GroupSyncRead, PacketHandler, PortHandler

    parent, child = mp.Pipe()
    proc = mp.get_context("spawn").Process(target=_serve, args=(n, wire_timing, child), daemon=True)
    proc.start()
    try:
        port = PortHandler(parent.recv())
        port.openPort()
        ph = PacketHandler(2.0)
        g = GroupSyncRead(port, ph, ADDR, LEN)
        for i in range(1, n + 1):
            g.addParam(i)

        def once() -> bool:
            if method == "sync read":
                return g.txRxPacket() == COMM_SUCCESS
            if method == "fast sync read":
                return g.fastSyncRead() == COMM_SUCCESS
            return all(ph.readTxRx(port, i, ADDR, LEN)[1] == COMM_SUCCESS for i in range(1, n + 1))

        failed = sum(not once() for _ in range(20))
        parent.send("stats")
        b0 = sum(parent.recv())
        best = 0.0
        for _ in range(repeats):
            t0 = time.perf_counter()
            failed += sum(not once() for _ in range(cycles))
            best = max(best, cycles / (time.perf_counter() - t0))
        parent.send("stats")
        b1 = sum(parent.recv())
        port.closePort()
        return best, (b1 - b0) / (cycles * repeats), failed
    finally:
        parent.send("stop")
        proc.join(timeout=5)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cycles", type=int, default=300)
    ap.add_argument("--servos", default="2,4,8")
    ap.add_argument("--scan-noise", type=int, metavar="RUNS", help="measure scan on a noisy bus instead")
    args = ap.parse_args(argv)
    if args.scan_noise:
        scan_noise(args.scan_noise)
        return 0
    print("| servos | method | bytes/cycle | protocol minimum at 1 Mbps | measured, wire timing emulated | measured, no wire timing |")
    print("|---:|---|---:|---:|---:|---:|")
    for n in [int(s) for s in args.servos.split(",")]:
        for method in ("sync read", "fast sync read", "one read per servo"):
            hz_wire, bytes_wire, fail_wire = measure(method, n, args.cycles, True)
            hz_fast, bytes_fast, fail_fast = measure(method, n, args.cycles, False)
            expected = formula_bytes(method, n)
            if not fail_wire + fail_fast and not bytes_wire == bytes_fast == expected:
                raise RuntimeError(f"{method}: counted {bytes_wire}/{bytes_fast} bytes, formula {expected}")
            note = f" ({fail_wire + fail_fast} late cycles)" if fail_wire + fail_fast else ""
            t_min = expected * 10 / BAUD
            print(f"| {n} | {method} | {expected} | {t_min * 1e6:.0f} µs = {1 / t_min:.0f} cycles/s "
                  f"| {hz_wire:.0f} cycles/s | {hz_fast:.0f} cycles/s{note} |", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
