"""``tactile recognize``: class, parameters, pose and contacts from touches (docs/formats.md)."""

from __future__ import annotations

import contextlib
import json
import sys
from pathlib import Path

from tools.recognize_worker import DEFAULT_TIMEOUT_S

#: bytes of one request (a stream line or a file): 64 touches of 500 samples fit in ~2 MB
MAX_LINE_BYTES = 2 * 2 ** 20
#: after an over-long line the stream looks this far for its end; a line longer still never
#: ends as far as the service can tell (``cat /dev/zero``): the stream stops, exit 2
MAX_SKIP_BYTES = 8 * MAX_LINE_BYTES

HELP = "recognizes the curve from touches (a JSON file, or - for stdin); --stream serves one request per line"


def add_arguments(parser) -> None:
    parser.add_argument("file", nargs="?", default="-", help="touches JSON file (docs/formats.md), or - for stdin")
    parser.add_argument("--stream", action="store_true",
                        help="recognition service: one request per line in, one compact JSON answer per line out")
    parser.add_argument("--json", action="store_true", help="accepted for symmetry: the output is always JSON")
    parser.add_argument("--profile", choices=("fast", "balanced", "accurate"), default=None,
                        help="speed/accuracy profile (estimator, refinement, alpha); default: the request's, else "
                             "its scene's, else balanced for samples-touches (contacts only: invariants, no refinement)")
    parser.add_argument("--refine", action="store_true", help="least-squares refinement over every sample")
    parser.add_argument("--estimator", choices=("auto", "central", "poly"), default=None,
                        help="kappa, kappa_s estimator for samples-touches (default: the request's, else auto)")
    parser.add_argument("--alpha", type=float, default=None,
                        help="false-rejection rate of each consistency test, in (0, 0.5) (default 1e-3)")
    parser.add_argument("--timeout", type=float, default=None, metavar="S",
                        help="cut a recognition off after S seconds with an error answer "
                             f"(default: the request's options.timeout_s, else {DEFAULT_TIMEOUT_S:g})")


def _options(args, request):
    """Explicit command-line options (--profile sets all of its profile's) > the request's
    options > its profile > the scene's profile > balanced for samples-touches
    (recognizer.classify.options_for)."""
    from recognizer.classify import options_for

    cli = {"profile": args.profile, "estimator": args.estimator, "alpha": args.alpha,
           "refine": True if args.refine else None}
    return options_for(request, {k: v for k, v in cli.items() if v is not None})


def _answer(obj, args, base_dir, source, worker):
    """Validate (here), then recognize in the worker under the deadline."""
    from recognizer.touches import parse_request

    request = parse_request(obj, base_dir=base_dir, source=source)
    return worker.recognize(request, _options(args, request), args.timeout)


class _Endless(Exception):
    """A line with no end within MAX_SKIP_BYTES: the stream cannot find its next request."""


def _lines(src, limit: int, skip: int = MAX_SKIP_BYTES):
    """(line number, bytes or None when the line is over ``limit`` bytes) of a binary
    stream. An over-long line is answered as soon as ``limit`` bytes are read (None), then
    skipped without being held in memory, up to ``skip`` bytes more; past that
    :class:`_Endless` ends the stream (bounded CPU and memory whatever comes in)."""
    n = 0
    while True:
        line = src.readline(limit + 1)
        if not line:
            return
        n += 1
        if len(line) > limit and not line.endswith(b"\n"):
            yield n, None
            skipped = 0
            while line and not line.endswith(b"\n"):
                if skipped > skip:
                    raise _Endless(f"line {n}: no end of line within {limit + skipped} bytes; the stream cannot "
                                   f"find its next request: stopped")
                line = src.readline(1 << 16)
                skipped += len(line)
        else:
            yield n, line


def _serve(src, args, base, worker) -> None:
    """One compact JSON answer per non-blank line; every failure is an ``{"error": ...}``."""
    from tactile_common.errors import InputError
    from tactile_common.inputs import decode_utf8, loads_json

    lines = _lines(src, MAX_LINE_BYTES)
    while True:
        try:
            n, raw = next(lines)
        except StopIteration:
            return
        except _Endless as exc:
            sys.stdout.write(json.dumps({"error": str(exc)}) + "\n")
            sys.stdout.flush()
            raise InputError(str(exc)) from None
        where = f"line {n}"
        try:
            if raw is None:
                raise InputError(f"{where}: longer than {MAX_LINE_BYTES} bytes (the request limit)")
            text = decode_utf8(raw, where)
            if not text.strip():
                continue
            out = _answer(loads_json(text, where), args, base, where, worker)
        except InputError as exc:
            out = {"error": str(exc)}
        except RecursionError:
            out = {"error": f"{where}: nested too deeply"}
        except MemoryError:
            out = {"error": f"{where}: out of memory reading the request"}
        except Exception as exc:  # a validation bug must not end the service: answer it, name it
            out = {"error": f"{where}: cannot handle the request ({type(exc).__name__}: {str(exc)[:200]})"}
        sys.stdout.write(json.dumps(out, allow_nan=False) + "\n")
        sys.stdout.flush()


def run(args) -> int:
    from tactile_common.errors import InputError
    from tactile_common.inputs import decode_utf8, loads_json, read_bounded
    from recognizer.limits import MAX_TIMEOUT_S
    from tools.recognize_worker import Worker

    if args.alpha is not None and not 0.0 < args.alpha < 0.5:
        raise InputError(f"--alpha: must be in (0, 0.5), got {args.alpha}")
    if args.timeout is not None and not 0.0 < args.timeout <= MAX_TIMEOUT_S:
        raise InputError(f"--timeout: must be in (0, {MAX_TIMEOUT_S:g}] s, got {args.timeout}")
    if args.stream:
        with contextlib.ExitStack() as stack:
            if args.file == "-":
                src, base = sys.stdin.buffer, Path.cwd()
            else:
                try:
                    src = stack.enter_context(open(args.file, "rb"))
                except OSError as exc:
                    raise InputError(f"{args.file}: cannot read ({exc.strerror or exc})") from None
                base = Path(args.file).resolve().parent
            _serve(src, args, base, stack.enter_context(Worker()))
        return 0
    if args.file == "-":
        raw = sys.stdin.buffer.read(MAX_LINE_BYTES + 1)
        if len(raw) > MAX_LINE_BYTES:
            raise InputError(f"stdin: longer than {MAX_LINE_BYTES} bytes (the request limit)")
        base, source = Path.cwd(), "stdin"
    else:
        raw = read_bounded(args.file, MAX_LINE_BYTES, "the request", regular_only=False)
        base, source = Path(args.file).resolve().parent, args.file
    obj = loads_json(decode_utf8(raw, source), source)
    with Worker() as worker:
        out = _answer(obj, args, base, source, worker)
    sys.stdout.write(json.dumps(out, indent=2, allow_nan=False) + "\n")
    return 0
