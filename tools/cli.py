"""The ``tactile`` command line: one console script, one module per subcommand.

Each subcommand module exposes ``HELP`` (one line), ``add_arguments(parser)`` and
``run(args) -> int``. Modules are imported only when their command runs, so
``tactile recognize`` never pays for matplotlib or the serial stack.

Exit status: 0 success, 2 bad input (one line on stderr, no traceback),
1 a fault at run time (bus timeout, unplugged adapter: one line on stderr),
130 interrupted.
"""

from __future__ import annotations

import argparse
import importlib
import sys

from tactile_common.errors import DeviceFault, InputError

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
        sys.stderr.write(f"tactile {self.prog.split()[-1]}: {message}\n")
        raise SystemExit(2)


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
    args = parser.parse_args(argv)
    if not getattr(args, "_run", None):
        parser.print_help()
        return 2
    try:
        return int(args._run(args) or 0)
    except InputError as exc:
        sys.stderr.write(f"tactile {args.command}: {exc}\n")
        return 2
    except DeviceFault as exc:
        sys.stderr.write(f"tactile {args.command}: {exc}\n")
        return 1
    except KeyboardInterrupt:
        sys.stderr.write(f"tactile {args.command}: interrupted\n")
        return 130


if __name__ == "__main__":
    raise SystemExit(main())
