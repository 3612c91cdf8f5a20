"""``tactile recognize``: class, parameters, pose and contacts from touches (docs/formats.md)."""

from __future__ import annotations

import json
import sys
from pathlib import Path

HELP = "recognizes the curve from touches (a JSON file, or - for stdin); --stream serves one request per line"


def add_arguments(parser) -> None:
    parser.add_argument("file", nargs="?", default="-", help="touches JSON file (docs/formats.md), or - for stdin")
    parser.add_argument("--stream", action="store_true",
                        help="recognition service: one request per line in, one compact JSON answer per line out")
    parser.add_argument("--json", action="store_true", help="accepted for symmetry: the output is always JSON")
    parser.add_argument("--refine", action="store_true", help="least-squares refinement over every sample")
    parser.add_argument("--estimator", choices=("auto", "central", "poly"), default=None,
                        help="kappa, kappa_s estimator for samples-touches (default: the request's, else auto)")
    parser.add_argument("--alpha", type=float, default=None,
                        help="false-rejection rate of each consistency test, in (0, 0.5) (default 1e-3)")


def _options(args, request):
    """Explicit command-line options > the request's options > its profile > the scene's
    profile (recognizer.classify.options_for)."""
    from recognizer.classify import options_for

    cli = {"estimator": args.estimator, "alpha": args.alpha, "refine": True if args.refine else None}
    return options_for(request, {k: v for k, v in cli.items() if v is not None})


def _answer(obj, args, base_dir, source):
    from recognizer.classify import recognize
    from recognizer.touches import parse_request

    request = parse_request(obj, base_dir=base_dir, source=source)
    return recognize(request, _options(args, request)).to_json()


def _decode(text: str, source: str):
    from tactile_common.errors import InputError

    try:
        return json.loads(text)
    except json.JSONDecodeError as exc:
        raise InputError(f"{source}: not valid JSON ({exc.msg} at line {exc.lineno} column {exc.colno})") from None
    except RecursionError:
        raise InputError(f"{source}: JSON nested too deeply") from None


def run(args) -> int:
    from tactile_common.errors import InputError

    if args.alpha is not None and not 0.0 < args.alpha < 0.5:
        raise InputError(f"--alpha: must be in (0, 0.5), got {args.alpha}")
    if args.stream:
        src = sys.stdin if args.file == "-" else None
        if src is None:
            try:
                src = open(args.file, encoding="utf-8")
            except OSError as exc:
                raise InputError(f"{args.file}: cannot read ({exc.strerror or exc})") from None
        base = Path.cwd() if args.file == "-" else Path(args.file).resolve().parent
        with src:
            for n, line in enumerate(src, 1):
                if not line.strip():
                    continue
                try:
                    out = _answer(_decode(line, f"line {n}"), args, base, f"line {n}")
                except InputError as exc:
                    out = {"error": str(exc)}
                except (ValueError, ArithmeticError) as exc:  # numerics on valid input: answer, never crash
                    out = {"error": f"line {n}: cannot recognize ({exc})"}
                sys.stdout.write(json.dumps(out, allow_nan=False) + "\n")
                sys.stdout.flush()
        return 0
    if args.file == "-":
        text, base, source = sys.stdin.read(), Path.cwd(), "stdin"
    else:
        path = Path(args.file)
        try:
            text = path.read_text(encoding="utf-8")
        except (OSError, UnicodeDecodeError) as exc:
            raise InputError(f"{args.file}: cannot read ({getattr(exc, 'strerror', None) or exc})") from None
        base, source = path.resolve().parent, args.file
    out = _answer(_decode(text, source), args, base, source)
    sys.stdout.write(json.dumps(out, indent=2, allow_nan=False) + "\n")
    return 0
