"""Do the stated σ's mean what they say at every scale? σ coverage per class, region and
scale decade (not a test).

    python -m tools.bench_sigma [--trials 6] [--seed 1] [--scales -4:5] [--kind samples|contacts|both] [--fresh] [--jobs 1]

Each trial draws a shape of one class and a region of it (``REGIONS``: the ordinary ones
and the extremes of issue 21: near an inflection or a cusp, a steep cubical, far out on a
branch or an arm), scales it so that the touched region spans L = 10^k mm for every k of
``--scales`` (the same shape and noise draw at every scale, in units of L: a figure that
differs between decades is the numerics', not the draw's; with ``--fresh`` each decade draws
its own shape and noise, so that a decade's figure and a class's over the decades count
independent values: without it ``--trials 3`` holds 6 values of a two-parameter class's
region, each counted once per decade), and recognizes three touches of it with every class
allowed:

- ``samples``: 3 touches × 9 samples 2 % of L apart, standard noise (tangent angle
  1.5 mrad, positions 0.1 % of L), the balanced profile (refinement, profile σ's); a
  semicubical's touches moved out along their branches until none reaches across the cusp
  (``clear_of_cusp``);
- ``contacts``: 3 contacts with Gaussian noise at their stated deviations (positions
  0.1 % of L, φ 1.5 mrad, κ ± (1 %·|κ| + 1 %/L), κ_s ± 5 %·(|κ_s| + |κ|/L + 1/L²)), the
  contact stage alone (the invariants and the contact fit, as a contacts-only request is
  answered).

On every answer of the right class, each shape parameter's z = (p̂ − p)/σ (σ the stated
one); the tables give per class and per scale decade the fraction with |z| ≤ 1.96
(calibrated: 95 %, the issue asks 93–97 %) and ≤ 3 (99.7 %, asked ≥ 99 %), the same with
the answer's 95 % interval (``interval``: z taken with σ = the interval's side toward the
truth / 1.96, so |z| ≤ 1.96 where the interval holds the truth), the smallest and median
stated relative σ (relative to |p|, to max(|p|, 1) for the slopes c and b) and the
count below 1e-9 (asked: none on noisy data), and the CPU time (process time) per
recognition. Seeds: development 1 and 5, held-out 37 (docs/benchmarks.md).
"""

from __future__ import annotations

import argparse
import math
import sys
import time

import numpy as np
from scipy import stats

from recognizer import synth
from recognizer.classify import recognize
from recognizer.curves import CURVES, Pose
from recognizer.profiles import PROFILES
from recognizer.result import RecognizeOptions
from recognizer.touches import ContactTouch, NoiseModel, Request
from tools.bench import _pool

CLASSES = tuple(CURVES)
SPEC_PHI, SPEC_POS_FRAC, SPACING, SAMPLES = 1.5e-3, 1e-3, 0.02, 9
SLOPES = {("cubical_parabola", "c"), ("semicubical_parabola", "b")}
#: per class: region → (shape at unit size, its parameters drawn by ``_draw``; range of the contacts' t)
REGIONS = {
    "line": {"segment": (-0.5, 0.5)},
    "circle": {"short arc": "short", "all round": (-np.pi, np.pi)},
    "ellipse": {"long stretch": (-np.pi, np.pi), "short stretch": "short", "thin, at its sharp end": (-0.6, 0.6)},
    "parabola": {"across vertex": (-1.5, 1.5), "far out": (3.0, 8.0)},
    "hyperbola": {"near vertex": (-1.0, 1.0), "far arm": (2.0, 5.0)},
    "cubical_parabola": {"across inflection": (-1.0, 1.0), "near inflection": (-0.05, 0.05),
                         "steep": (-1.0, 1.0), "far one side": (1.0, 3.0)},
    "semicubical_parabola": {"both branches": (0.8, 1.6), "near cusp": (0.05, 0.3), "far branch": (3.0, 10.0)},
}


def _draw(cls: str, region: str, rs: np.random.Generator) -> dict:
    """Shape parameters at unit size for a region."""
    sign = float(rs.choice([-1.0, 1.0]))
    if cls == "circle":
        return {"r": 0.5}
    if cls == "ellipse":
        return {"a": 0.5, "b": 0.5 * (rs.uniform(0.03, 0.08) if region.startswith("thin") else rs.uniform(0.35, 0.9))}
    if cls == "parabola":
        return {"a": 1.0}
    if cls == "hyperbola":
        return {"a": 1.0, "b": rs.uniform(0.4, 2.0)}
    if cls == "cubical_parabola":
        c = 10 ** rs.uniform(1.5, 4.0) if region == "steep" else rs.uniform(0.3, 1.0)
        return {"a": sign * rs.uniform(0.25, 0.75), "c": float(rs.choice([-1.0, 1.0])) * c}
    if cls == "semicubical_parabola":
        return {"a": 1.0, "b": sign * rs.uniform(0.1, 1.5)}
    return {}


def draw_case(cls: str, region: str, i: int, seed: int, decade: int | None = None):
    """(shape at L = 1 mm, its 3 contacts' t, traversal direction, noise draws' rng seed);
    ``decade`` given (``--fresh``): that decade's own draw."""
    key = [seed, CLASSES.index(cls), list(REGIONS[cls]).index(region), i, 41]
    rs = np.random.default_rng(key if decade is None else key + [1000 + decade])
    params = _draw(cls, region, rs)
    span = REGIONS[cls][region]
    if span == "short":
        t0 = rs.uniform(-np.pi, np.pi)
        span = (t0, t0 + rs.uniform(0.5, 1.2))
    curve = CURVES[cls](params)
    k = 1.0 / synth.extent(curve, synth.region(cls, span))
    params, span = synth._scaled(cls, params, span, k)
    edges = np.linspace(*span, 4)
    ts = np.array([rs.uniform(a + 0.05 * (b - a), b - 0.05 * (b - a)) for a, b in zip(edges[:-1], edges[1:])])
    if cls == "semicubical_parabola":
        ts = np.sort(ts * rs.choice([-1.0, 1.0], 3))
    pose = Pose(rs.uniform(-np.pi, np.pi), rs.uniform(-0.5, 0.5), rs.uniform(-0.5, 0.5))
    return params, ts, pose, int(rs.choice([-1, 1])), int(rs.integers(2**31))


def scaled(cls: str, params: dict, ts, pose: Pose, L: float):
    """The unit-size case enlarged L times (the hand's origin 150 mm in front of its centre)."""
    params, (lo, hi) = synth._scaled(cls, params, (float(np.min(ts)), float(np.max(ts))), L)
    f = {"line": L, "cubical_parabola": L, "semicubical_parabola": math.sqrt(L)}.get(cls, 1.0)
    return params, np.asarray(ts, float) * f, Pose(pose.theta, 150.0 + L * pose.x, L * pose.y)


def _contacts(cls, params, ts, pose, direction, L, rs):
    """Noisy contacts with their stated deviations (module docstring), and the noise model."""
    curve = CURVES[cls](params)
    t = np.asarray(ts if direction > 0 else ts[::-1], float)
    x, y, phi, k, ks = curve.frame(t)
    hx, hy = pose.apply(x, y)
    phi = phi + pose.theta + (np.pi if direction < 0 else 0.0)
    k = k * direction
    nm = NoiseModel(SPEC_PHI, SPEC_POS_FRAC * L)
    out = []
    for xi, yi, pi, ki, ksi in zip(hx, hy, phi, k, ks):
        sk = 0.01 * abs(ki) + 0.01 / L
        sks = 0.05 * (abs(ksi) + abs(ki) / L + 1.0 / L**2)
        out.append(ContactTouch(float(xi + rs.normal(0, nm.pos)), float(yi + rs.normal(0, nm.pos)),
                                float(pi + rs.normal(0, nm.phi)), float(ki + rs.normal(0, sk)),
                                float(ksi + rs.normal(0, sks)), np.diag([sk * sk, sks * sks])))
    return out, nm


def case_at(cls: str, region: str, i: int, seed: int, k: int, fresh: bool):
    """A trial's case at decade k (L = 10^k mm): (parameters, contacts' t, pose, traversal
    direction, L, the noise draws' generator: the same draws, in units of L, at every scale;
    ``fresh``: that decade's own shape and noise draw)."""
    params1, ts1, pose1, direction, noise_seed = draw_case(cls, region, i, seed, k if fresh else None)
    L = 10.0 ** k
    params, ts, pose = scaled(cls, params1, ts1, pose1, L)
    return params, ts, pose, direction, L, np.random.default_rng(noise_seed)


def sampled(cls: str, params: dict, ts, pose: Pose, direction: int, L: float, rs: np.random.Generator):
    """The ``samples`` kind's touches (rolls of ``SAMPLES`` readings, ``SPACING``·L apart, clear
    of a semicubical's cusp), their noise model and the balanced profile's options."""
    if cls == "semicubical_parabola":
        ts = clear_of_cusp(CURVES[cls](params), ts, synth.touch_reach(SAMPLES, SPACING * L))
    shape = synth.Shape(cls, params, pose, L, (float(ts.min()), float(ts.max())), CURVES[cls](params))
    noise = synth.SynthNoise(SPEC_PHI, SPEC_POS_FRAC * L)
    touches, _ = synth.sample_shape(shape, ts, SAMPLES, SPACING * L, direction, noise, rs, with_s=False)
    nm = NoiseModel(noise.phi, noise.pos)
    return touches, nm, RecognizeOptions(noise=nm, **PROFILES["balanced"].options())


def run_trial(task) -> list[dict]:
    cls, region, i, seed, scales, kinds, *fresh = task
    fresh = bool(fresh and fresh[0])
    out = []
    for kind in kinds:
        for k in scales:
            params, ts, pose, direction, L, rs = case_at(cls, region, i, seed, k, fresh)
            if kind == "samples":
                touches, nm, opts = sampled(cls, params, ts, pose, direction, L, rs)
            else:
                touches, nm = _contacts(cls, params, ts, pose, direction, L, rs)
                opts = RecognizeOptions(noise=nm)
            req = Request(tuple(touches), None, CLASSES, nm)
            c0 = time.process_time()
            try:
                rec = recognize(req, opts)
                answer, err = rec.cls, None
            except Exception as exc:  # a crash is a result here, counted and shown
                rec, answer, err = None, "error", f"{type(exc).__name__}: {exc}"
            cpu = time.process_time() - c0
            zs, rels, zis = [], [], []
            if answer == "line" == cls:  # a line states its pose: the angle and the offset across it
                zs, rels = _line_z(rec, pose, L)
                zis = list(zs)
            elif answer == cls:
                for name, v in params.items():
                    sd = rec.uncertainty.get(name)
                    ref = max(abs(v), 1.0) if (cls, name) in SLOPES else abs(v)
                    sd = math.inf if sd is None else float(sd)
                    zs.append((rec.params[name] - v) / sd if sd > 0 else math.inf)
                    rels.append(sd / ref)
                    zis.append(interval_z(rec, name, v))
            out.append({"cls": cls, "region": region, "trial": i, "kind": kind, "decade": k, "answer": answer,
                        "z": zs, "zi": zis, "rel": rels, "cpu": cpu, "error": err})
    return out


def clear_of_cusp(curve, ts: np.ndarray, reach: float) -> np.ndarray:
    """A semicubical's contacts moved out along their branches, all by the same Δ|t| (their
    spacing kept), until a touch reaching ``reach`` either side of its contact stays on its
    branch, as bench_wide's do: a pad cannot roll through the cusp. Near the cusp and even
    on the far branch (t 3–10 of a region spanning both branches) a 9-sample touch 2 % of L
    apart reached across it (before session 17: noise-free samples of those regions
    unclassified, a touch's samples on both branches)."""
    clear = synth._clear_of_cusp(curve, 1.02 * reach, max(float(np.max(np.abs(ts))), 1e-9))
    shift = max(clear - float(np.min(np.abs(ts))), 0.0)
    return np.sign(ts) * (np.abs(ts) + shift)


def interval_z(rec, name: str, truth: float) -> float:
    """(p̂ − p)/σ_side: σ_side the answer's 95 % interval (``Recognition.interval``) on the
    truth's side / 1.96, so |z| ≤ 1.96 exactly where the interval holds the truth; ∞ where the
    answer states no interval."""
    p, iv = float(rec.params[name]), rec.interval.get(name)
    if iv is None:
        return math.inf
    side = (iv[1] - p if truth > p else p - iv[0]) / 1.96
    return (p - truth) / side if side > 0 else math.inf


def _line_z(rec, pose: Pose, L: float) -> tuple[list, list]:
    """z of a line answer's angle and offset across it (the truth turned by π when the
    answer runs the other way); the offset's relative σ is taken to L."""
    d_th = (rec.pose.theta - pose.theta + np.pi) % (2 * np.pi) - np.pi
    th, turned = (pose.theta, 1.0) if abs(d_th) < np.pi / 2 else (pose.theta + np.pi, -1.0)
    off = lambda p, t: -p.x * math.sin(t) + p.y * math.cos(t)
    d_th = (rec.pose.theta - th + np.pi) % (2 * np.pi) - np.pi
    d_off = off(rec.pose, rec.pose.theta) - off(pose, th)
    s_th, s_off = (rec.uncertainty.get(k) for k in ("pose_theta", "pose_offset"))
    s_th, s_off = (math.inf if v is None else float(v) for v in (s_th, s_off))
    return ([d_th / s_th if s_th > 0 else math.inf, d_off / s_off if s_off > 0 else math.inf],
            [s_th, s_off / L])


def _pct(k: int, n: int) -> str:
    return f"{100.0 * k / n:.1f}" if n else "–"


def coverage_band(n: int, p: float = 0.95) -> tuple[float, float]:
    """The range (%) that the |z| ≤ 1.96 fraction of n independent values falls in 95 % of
    the time when every stated σ is right (the binomial's 2.5 and 97.5 % quantiles): with 30
    values, 86.7–100 %, so 90 % there says nothing against the σ's."""
    if n <= 0:
        return math.nan, math.nan
    lo, hi = stats.binom.ppf([0.025, 0.975], n, p)
    return 100.0 * float(lo) / n, 100.0 * float(hi) / n


def table(recs: list[dict], key: str, keys: list) -> str:
    """One row per value of ``key``: right answers, coverage at 1.96 and 3 σ and the range
    calibrated σ's give at 1.96 σ (``coverage_band`` over the right answers' trials, not the
    values: a trial's values are correlated — a line's offset at the hand origin is its
    angle's error times the lever, |z_offset| ≈ |z_angle|), smallest stated relative σ,
    answers below 1e-9, CPU per recognition."""
    lines = [f"| {key} | answers | right % | values | |z| ≤ 1.96 % | calibrated: 1.96 % | |z| ≤ 3 % | "
             "interval: |z| ≤ 1.96 % | ≤ 3 % | min rel σ | rel σ < 1e-9 | median rel σ | ms CPU |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for kv in keys:
        rs = [r for r in recs if r[key] == kv]
        if not rs:
            continue
        right = [r for r in rs if r["answer"] == r["cls"]]
        z = np.array([v for r in right for v in r["z"]], float)
        zi = np.array([v for r in right for v in r.get("zi", r["z"])], float)
        rel = np.array([v for r in right for v in r["rel"]], float)
        tiny = sum(1 for r in right if any(v < 1e-9 for v in r["rel"]))
        band = coverage_band(sum(1 for r in right if r["z"]))
        lines.append(f"| {kv} | {len(rs)} | {_pct(len(right), len(rs))} | {z.size} | "
                     f"{_pct(int(np.sum(np.abs(z) <= 1.96)), z.size)} | "
                     f"{'–' if math.isnan(band[0]) else f'{band[0]:.0f}–{band[1]:.0f}'} | "
                     f"{_pct(int(np.sum(np.abs(z) <= 3.0)), z.size)} | "
                     f"{_pct(int(np.sum(np.abs(zi) <= 1.96)), zi.size)} | {_pct(int(np.sum(np.abs(zi) <= 3.0)), zi.size)} | "
                     f"{(f'{rel.min():.2g}' if rel.size else '–')} | {tiny} | "
                     f"{(f'{np.median(rel):.2g}' if rel.size else '–')} | {1e3 * np.mean([r['cpu'] for r in rs]):.0f} |")
    return "\n".join(lines)


def report(recs: list[dict]) -> str:
    out = []
    for kind in ("samples", "contacts"):
        rs = [r for r in recs if r["kind"] == kind]
        if not rs:
            continue
        out.append(f"### {kind}\n\nPer class:\n\n" + table(rs, "cls", list(CLASSES)))
        out.append("Per scale decade (L = 10^k mm):\n\n" + table(rs, "decade", sorted({r["decade"] for r in rs})))
        regions = sorted({(r["cls"], r["region"]) for r in rs})
        for r in rs:
            r["where"] = f"{r['cls']}: {r['region']}"
        out.append("Per region:\n\n" + table(rs, "where", [f"{c}: {g}" for c, g in regions]))
        worst = sorted((r for r in rs if r["z"]), key=lambda r: -max(abs(v) for v in r["z"]))[:8]
        out.append("Largest |z|: " + "; ".join(
            f"{r['cls']} {r['region']} trial {r['trial']} 1e{r['decade']} mm: z {max(r['z'], key=abs):.3g}"
            f" (interval's side: {max(r.get('zi', r['z']), key=abs):.3g})" for r in worst))
        errs = [r for r in rs if r["error"]]
        if errs:
            out.append("Errors: " + "; ".join(f"{r['cls']} {r['region']} {r['trial']} 1e{r['decade']}: {r['error']}"
                                              for r in errs[:10]))
    return "\n\n".join(out)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--trials", type=int, default=6, help="trials per class and region")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--scales", default="-4:5", help="decades k of L = 10^k mm, lo:hi inclusive")
    ap.add_argument("--kind", choices=("samples", "contacts", "both"), default="both")
    ap.add_argument("--classes", nargs="*", default=list(CLASSES))
    ap.add_argument("--fresh", action="store_true",
                    help="each decade its own shape and noise draw (independent values per decade)")
    ap.add_argument("--jobs", type=int, default=1)
    args = ap.parse_args(argv)
    lo, hi = (int(v) for v in args.scales.split(":"))
    kinds = ("samples", "contacts") if args.kind == "both" else (args.kind,)
    tasks = [(c, g, i, args.seed, list(range(lo, hi + 1)), kinds, args.fresh) for c in args.classes for g in REGIONS[c]
             for i in range(args.trials)]
    t0 = time.perf_counter()
    if args.jobs > 1:
        with _pool(args.jobs) as pool:
            results = pool.map(run_trial, tasks, chunksize=1)
    else:
        results = [run_trial(t) for t in tasks]
    recs = [r for rs in results for r in rs]
    print(f"python -m tools.bench_sigma --trials {args.trials} --seed {args.seed} --scales {args.scales} "
          f"--kind {args.kind}{' --fresh' if args.fresh else ''}: {len(recs)} recognitions, {time.perf_counter() - t0:.0f} s wall\n")
    print(report(recs))
    sys.stdout.flush()
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
