"""``tactile scan``: list the servos on a bus (id, model, firmware).

A noisy bus loses and garbles replies: each id is pinged up to 4 times in a row without
an answer before it counts as absent, and a garbled answer earns it 4 more
(hand_driver.bus.JointBus.scan); with 10 % of replies lost and 10 % corrupted every servo
is still found (docs/driver.md)."""

from __future__ import annotations

HELP = "list the Dynamixel servos answering on a port: id, model, firmware"


def parse_ids(text: str) -> list[int]:
    """'1-5,8' → [1, 2, 3, 4, 5, 8]; ids 0..252."""
    from tactile_common.errors import InputError

    ids: list[int] = []
    for part in text.split(","):
        a, _, b = part.strip().partition("-")
        try:
            lo, hi = int(a), int(b or a)
        except ValueError:
            raise InputError(f"--ids: {part!r} is not an id or a range like 1-20") from None
        if not 0 <= lo <= hi <= 252:
            raise InputError(f"--ids: {part!r} outside 0..252")
        ids.extend(range(lo, hi + 1))
    return sorted(set(ids))


def add_arguments(parser) -> None:
    parser.add_argument("--port", required=True, help="serial port, e.g. /dev/ttyUSB0 or the path tactile sim printed")
    parser.add_argument("--baud", default="1000000",
                        help="baud rate(s) to try, comma separated (default: %(default)s)")
    parser.add_argument("--ids", default="1-20", help="ids to ping: ranges and commas (default: %(default)s)")
    parser.add_argument("--json", action="store_true", help="print JSON instead of a table")


def run(args) -> int:
    import json

    from hand_driver.bus import scan
    from tactile_common.errors import InputError

    try:
        bauds = [int(b) for b in args.baud.split(",")]
    except ValueError:
        raise InputError(f"--baud: {args.baud!r} is not a comma-separated list of integers") from None
    found = scan(args.port, parse_ids(args.ids), bauds)
    if args.json:
        print(json.dumps({"port": args.port, "servos": [
            {"id": s.id, "model": s.model_name, "model_number": s.model_number,
             "firmware": s.firmware, "baudrate": s.baudrate} for s in found]}))
        return 0
    if not found:
        print(f"no servo answered on {args.port} (ids {args.ids}, baud {args.baud})")
        return 0
    print(f"{'id':>3}  {'model':<16} {'number':>6}  {'firmware':>8}  {'baud':>8}")
    for s in found:
        print(f"{s.id:>3}  {s.model_name:<16} {s.model_number:>6}  {s.firmware:>8}  {s.baudrate:>8}")
    return 0
