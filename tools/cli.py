"""The ``tactile`` command line: one console script, one module per subcommand.

Each subcommand module exposes ``HELP`` (one line), ``add_arguments(parser)`` and
``run(args) -> int``. Modules are imported only when their command runs, so
``tactile recognize`` never pays for matplotlib or the serial stack.

Exit status, the same in every command (README, Commands): 0 recognized (or done), 1 a bus
or hardware fault (bus timeout, unplugged adapter: one line on stderr), 2 bad input (one
line on stderr, no traceback), 3 explored but refused (``--json`` still prints the answer,
class ``unclassified`` with its reason and advice; ``tactile recognize`` answers every valid
request with 0, ``unclassified`` included), 130 interrupted.
"""

from __future__ import annotations

import argparse
import importlib
import sys

from tactile_common.errors import DeviceFault, InputError

EXIT_RECOGNIZED = 0
EXIT_FAULT = 1
EXIT_BAD_INPUT = 2
EXIT_REFUSED = 3
EXIT_INTERRUPTED = 130

COMMANDS = {
    "demo": "tools.cmd_demo",
    "sim": "tools.cmd_sim",
    "scan": "tools.cmd_scan",
    "explore": "tools.cmd_explore",
    "replay": "tools.cmd_replay",
    "recognize": "tools.cmd_recognize",
    "calibrate": "tools.cmd_calibrate",
    "bench": "tools.cmd_bench",
}


class _Parser(argparse.ArgumentParser):
    """argparse that reports usage errors as one line and exit status 2."""

    def error(self, message: str) -> None:  # noqa: D401 - argparse hook
        sys.stderr.write(f"{self.prog}: {message}\n")  # "tactile" or "tactile demo"
        raise SystemExit(EXIT_BAD_INPUT)


def build_parser(command: str | None = None) -> argparse.ArgumentParser:
    parser = _Parser(prog="tactile", description="Tactile shape recognition for a Dynamixel two-finger jaw.")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    for name, module_name in COMMANDS.items():
        if command is not None and name != command:
            sub.add_parser(name, help=f"(see tactile {name} --help)")
            continue
        module = importlib.import_module(module_name)
        p = sub.add_parser(name, help=module.HELP, description=module.HELP)
        module.add_arguments(p)
        p.set_defaults(_run=module.run)
    return parser


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    command = argv[0] if argv and argv[0] in COMMANDS else None
    if command is None and argv and not argv[0].startswith("-"):
        sys.stderr.write(f"tactile: unknown command {argv[0]!r}; choose from {', '.join(COMMANDS)}\n")
        return 2
    parser = build_parser(command)
    args, extra = parser.parse_known_args(argv)
    if extra:  # argparse reports these from the top parser: name the subcommand they were given to
        named = _Parser(prog=f"tactile {command}") if command is not None else parser
        named.error(f"unrecognized arguments: {' '.join(extra)}")
    if not getattr(args, "_run", None):
        parser.print_help()
        return EXIT_BAD_INPUT
    try:
        return int(args._run(args) or EXIT_RECOGNIZED)
    except InputError as exc:
        sys.stderr.write(f"tactile {args.command}: {exc}\n")
        return EXIT_BAD_INPUT
    except DeviceFault as exc:
        sys.stderr.write(f"tactile {args.command}: {exc}\n")
        return EXIT_FAULT
    except KeyboardInterrupt:
        sys.stderr.write(f"tactile {args.command}: interrupted\n")
        return EXIT_INTERRUPTED


if __name__ == "__main__":
    raise SystemExit(main())
