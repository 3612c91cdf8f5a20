"""CPU per balanced recognition on bench_wide's 3-touch requests, and every answer written
down so that two code versions can be compared answer by answer (not a test).

    python -m tools.bench_cpu [--set wide|hand] [--seed 1] [--trials 16] [--first 0] [--exact] --out A.json
    python -m tools.bench_cpu ... --profile PROF.out      (cProfile of the recognitions only)
    python -m tools.bench_cpu --compare A.json B.json [--rel 1e-9] [--abs 0]

The requests are exactly `tools.bench_wide`'s first recognition of each trial (the same
draws: shape, region, contacts, direction, noise), balanced profile, every class allowed;
``--exact`` also recognizes each trial's touches noise-free (bench_wide's noise-free row).
CPU is the process time of each ``recognize`` call alone (robust to other processes on a
shared machine as long as both versions run under the same conditions: run them side by
side or interleaved). ``--compare`` checks class, parameters, pose, contacts, σ's,
intervals, invariants, ranking (χ², BIC, p), ``also_fits``, ``untested``, the reason and
``next_touch`` of every request: bit-identical, else the largest relative difference, and
fails (exit 1) when a number differs by more than ``--rel`` relative and ``--abs`` absolute (a
``gain`` of χ² between two classes at the same limit, 1e-12, is rounding), or a class, text
or structure differs.
"""

from __future__ import annotations

import argparse
import cProfile
import json
import math
import sys
import time

import numpy as np

from recognizer.classify import recognize
from recognizer.profiles import PROFILES
from recognizer.result import RecognizeOptions
from recognizer.touches import NoiseModel, Request, SamplesTouch
from recognizer import synth
from tools.bench_wide import CLASSES, SAMPLES, SPACING, drawn_trial


def requests(seed: int, trials: int, first: int, dist: str, exact: bool, classes=CLASSES):
    """(name, request, options) of bench_wide's 3-touch recognitions, trials first … first+trials−1
    of every class, in class order; with ``exact`` each trial's noise-free request follows it."""
    for cls in classes:
        for i in range(first, first + trials):
            tr = drawn_trial(cls, i, seed, dist)
            yield f"{cls}/{i}", _request(tr.touches, tr.noise)
            if exact:
                clean, _ = synth.sample_shape(tr.shape, tr.ts, SAMPLES, SPACING * tr.shape.size, tr.direction, None, None,
                                              with_s=False)
                yield f"{cls}/{i}/exact", _request(clean, NoiseModel(0.0, 0.0))


def _request(touches, nm):
    req = Request(tuple(SamplesTouch(t.phi, t.x, t.y, t.s) for t in touches), None, CLASSES, nm, {})
    return req, RecognizeOptions(noise=nm, **PROFILES["balanced"].options())


def run(args) -> int:
    prof = cProfile.Profile() if args.profile else None
    out, cpu = [], []
    for name, (req, opts) in requests(args.seed, args.trials, args.first, args.set, args.exact, args.classes):
        if prof:
            prof.enable()
        t0 = time.process_time()
        rec = recognize(req, opts)
        dt = time.process_time() - t0
        if prof:
            prof.disable()
        answer = rec.to_json()
        nt_ms = answer.pop("timing", {}).get("next_touch_cpu_ms")
        out.append({"name": name, "cpu_ms": 1e3 * dt, "next_touch_ms": nt_ms, "answer": answer})
        if not name.endswith("exact"):
            cpu.append(1e3 * dt)
        sys.stderr.write(f"\r[bench_cpu] {len(out)} {name} {1e3 * dt:.0f} ms   ")
        sys.stderr.flush()
    sys.stderr.write("\n")
    if prof:
        prof.dump_stats(args.profile)
    with open(args.out, "w", encoding="utf-8") as f:
        json.dump({"seed": args.seed, "set": args.set, "trials": args.trials, "first": args.first, "classes": args.classes,
                   "records": out}, f)
    print(summary(out))
    return 0


def summary(records) -> str:
    noisy = [r for r in records if not r["name"].endswith("exact")]
    lines = [f"{len(noisy)} noisy 3-touch recognitions: mean {np.mean([r['cpu_ms'] for r in noisy]):.1f} ms CPU"]
    for cls in CLASSES:
        v = [r["cpu_ms"] for r in noisy if r["name"].split("/")[0] == cls]
        if v:
            lines.append(f"  {cls}: {np.mean(v):.1f} ms ({len(v)})")
    nt = [r["next_touch_ms"] for r in records if r["next_touch_ms"] is not None]
    if nt:
        lines.append(f"next_touch: mean {np.mean(nt):.1f} ms, worst {np.max(nt):.1f} ms ({len(nt)} calls)")
    ex = [r["cpu_ms"] for r in records if r["name"].endswith("exact")]
    if ex:
        lines.append(f"{len(ex)} noise-free recognitions: mean {np.mean(ex):.1f} ms CPU")
    return "\n".join(lines)


def _diff(a, b, path, worst, bad):
    """Walk two JSON values; ``worst`` collects (relative difference, path) of numbers that
    differ, ``bad`` every structural, class or text difference."""
    if isinstance(a, dict) and isinstance(b, dict):
        if a.keys() != b.keys():
            bad.append(f"{path}: keys {sorted(a)} vs {sorted(b)}")
            return
        for k in a:
            _diff(a[k], b[k], f"{path}.{k}", worst, bad)
    elif isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            bad.append(f"{path}: length {len(a)} vs {len(b)}")
            return
        for k, (x, y) in enumerate(zip(a, b)):
            _diff(x, y, f"{path}[{k}]", worst, bad)
    elif isinstance(a, bool) or isinstance(b, bool) or isinstance(a, str) or isinstance(b, str) or a is None or b is None:
        if a != b:
            bad.append(f"{path}: {a!r} vs {b!r}")
    elif isinstance(a, (int, float)) and isinstance(b, (int, float)):
        if a != b:
            rel = abs(a - b) / max(abs(a), abs(b)) if math.isfinite(a) and math.isfinite(b) else math.inf
            worst.append((rel, path, a, b, abs(a - b)))
    elif a != b:
        bad.append(f"{path}: {a!r} vs {b!r}")


def compare(path_a: str, path_b: str, rel: float, tol_abs: float = 0.0) -> int:
    with open(path_a, encoding="utf-8") as f:
        a = json.load(f)
    with open(path_b, encoding="utf-8") as f:
        b = json.load(f)
    ra, rb = a["records"], b["records"]
    if [r["name"] for r in ra] != [r["name"] for r in rb]:
        print("the two files hold different requests")
        return 1
    worst, bad, identical = [], [], 0
    for x, y in zip(ra, rb):
        w0, b0 = len(worst), len(bad)
        _diff(x["answer"], y["answer"], x["name"], worst, bad)
        identical += len(worst) == w0 and len(bad) == b0
    print(f"{len(ra)} answers: {identical} bit-identical; {len(bad)} class / text / structure differences; "
          f"{len(worst)} numbers differ")
    for line in bad[:20]:
        print("  DIFF", line)
    worst.sort(reverse=True)
    for r, p, u, v, d in worst[:10]:
        print(f"  {r:.3g} relative ({d:.3g} absolute) at {p}: {u!r} vs {v!r}")
    for name, recs in (("A", ra), ("B", rb)):
        print(f"{name} ({path_a if name == 'A' else path_b}): " + summary(recs).replace("\n", "\n    "))
    over = [w for w in worst if w[0] > rel and w[4] > tol_abs]
    print(f"largest relative difference {worst[0][0]:.3g}" if worst else "every number bit-identical",
          f"({len(over)} beyond {rel:g} relative" + (f" and {tol_abs:g} absolute)" if tol_abs else ")"))
    return 1 if bad or over else 0


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--set", choices=("wide", "hand"), default="wide")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--trials", type=int, default=16, help="trials per class")
    ap.add_argument("--first", type=int, default=0)
    ap.add_argument("--classes", nargs="+", default=list(CLASSES))
    ap.add_argument("--exact", action="store_true", help="also the noise-free request of every trial")
    ap.add_argument("--out", help="write every answer and its CPU time to this JSON file")
    ap.add_argument("--profile", help="write a cProfile of the recognize calls to this file")
    ap.add_argument("--compare", nargs=2, metavar=("A", "B"), help="compare two --out files")
    ap.add_argument("--rel", type=float, default=1e-9, help="--compare: largest relative difference allowed")
    ap.add_argument("--abs", type=float, default=0.0, help="--compare: ... or absolute difference allowed")
    args = ap.parse_args(argv)
    if args.compare:
        return compare(*args.compare, args.rel, args.abs)
    if not args.out:
        raise SystemExit("bench_cpu: --out FILE.json is required (or --compare A B)")
    return run(args)


if __name__ == "__main__":
    raise SystemExit(main())
