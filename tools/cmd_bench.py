"""``tactile bench``: measure the speed–accuracy trade and write a table and a plot."""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from pathlib import Path

from tactile_common.errors import InputError
from tactile_common.files import atomic_write, check_output

HELP = "measures the speed–accuracy trade (noise, samples, span, touches, estimator, refinement) and writes a table and a plot"


OUTPUTS = ("bench.csv", "bench.md", "bench.png")
WIDE_OUTPUT = "bench_wide.md"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--quick", action="store_true",
                        help="a smoke run of about 20-60 s (few shapes); the committed numbers come from the default run")
    parser.add_argument("--out", default=None,
                        help="output directory for bench.csv, bench.md, bench.png (default: a new scratch directory, "
                             "printed; the committed results are written with --out docs/bench --force)")
    parser.add_argument("--force", action="store_true", help="overwrite the three files if --out already holds them")
    parser.add_argument("--shapes", type=int, default=None,
                        help="random shapes per class for the baseline and noise-free rows (default 100, quick 3)")
    parser.add_argument("--sweep-shapes", type=int, default=None,
                        help="random shapes per class for every other sweep row (default 3, quick 1)")
    parser.add_argument("--profile-shapes", type=int, default=None,
                        help="random shapes per class for the profile rows (default: as --sweep-shapes)")
    parser.add_argument("--table-shapes", type=int, default=None,
                        help="shapes (points) per class for the paper's Tables 1 and 3 (default 100, quick 4)")
    parser.add_argument("--seed", type=int, default=1, help="random seed (default 1)")
    parser.add_argument("--classes", nargs="+", default=None, metavar="CLASS",
                        help="classes to draw and answer among (default: all seven)")
    parser.add_argument("--jobs", type=int, default=None, help="worker processes (default: min(2, CPUs))")
    parser.add_argument("--wide-trials", type=int, default=0, metavar="N",
                        help="also run the widened distribution (tools/bench_wide.py: regions per class, oracle, "
                             "suggested vs random touches, sigma coverage), N trials per class, into OUT/bench_wide.md")


def _positive(value: int | None, default: int, name: str) -> int:
    if value is None:
        return default
    if value < 1:
        raise InputError(f"{name} must be >= 1, got {value}")
    return value


def run(args: argparse.Namespace) -> int:
    from recognizer.curves import CURVES
    from tools import bench, bench_report

    classes = tuple(args.classes) if args.classes else bench.CLASSES
    unknown = [c for c in classes if c not in CURVES]
    if unknown:
        raise InputError(f"--classes: unknown {', '.join(unknown)}; allowed: {', '.join(CURVES)}")
    shapes = _positive(args.shapes, 3 if args.quick else 100, "--shapes")
    sweep = _positive(args.sweep_shapes, 1 if args.quick else 3, "--sweep-shapes")
    table = _positive(args.table_shapes, 4 if args.quick else 100, "--table-shapes")
    if args.wide_trials < 0:
        raise InputError(f"--wide-trials must be >= 0, got {args.wide_trials}")
    profile = _positive(args.profile_shapes, sweep, "--profile-shapes")
    jobs = _positive(args.jobs, bench.default_jobs(), "--jobs")
    if args.out is None:
        out = Path(tempfile.mkdtemp(prefix="tactile-bench-"))
    else:
        out = Path(args.out)
        try:
            out.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise InputError(f"--out {out}: cannot create ({exc.strerror})") from exc
        for name in OUTPUTS + ((WIDE_OUTPUT,) if args.wide_trials else ()):
            check_output(out / name, force=args.force, flag="--out")

    def progress(msg: str, final: bool) -> None:
        sys.stderr.write(f"\r[bench] {msg}   " + ("\n" if final else ""))
        sys.stderr.flush()

    t0 = time.perf_counter()
    result = bench.run_bench(bench.default_configs(), classes, shapes, sweep, args.seed, jobs, table, progress,
                             profile_shapes=profile)
    command = "tactile bench" + (" --quick" if args.quick else "") + \
        (f" --shapes {args.shapes}" if args.shapes else "") + \
        (f" --sweep-shapes {args.sweep_shapes}" if args.sweep_shapes else "") + \
        (f" --profile-shapes {args.profile_shapes}" if args.profile_shapes else "") + \
        (f" --table-shapes {args.table_shapes}" if args.table_shapes else "") + \
        (f" --seed {args.seed}" if args.seed != 1 else "") + \
        (f" --classes {' '.join(args.classes)}" if args.classes else "")
    bench_report.write_csv(result, out / OUTPUTS[0])
    bench_report.write_markdown(result, out / OUTPUTS[1], command)
    bench_report.write_plot(result, out / OUTPUTS[2])
    for c in result.checks:
        print(f"{'met ' if c['pass'] else 'MISS'}  {c['target']}: {c['measured']}")
    if args.wide_trials:
        from tools import bench_wide

        t1 = time.perf_counter()
        recs = bench_wide.run_wide(classes, args.wide_trials, args.seed, jobs, progress)
        atomic_write(out / WIDE_OUTPUT, bench_wide.markdown(
            recs, f"tactile bench --wide-trials {args.wide_trials} --seed {args.seed}", time.perf_counter() - t1, jobs) + "\n")
        print(f"wrote {out / WIDE_OUTPUT}")
    print(f"wrote {out / 'bench.csv'}, {out / 'bench.md'}, {out / 'bench.png'} in {time.perf_counter() - t0:.0f} s")
    return 0
