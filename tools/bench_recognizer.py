"""Accuracy and speed of the recognizer on exact contact data (not a test).

    python -m tools.bench_recognizer [--cases N] [--seed S] [--repeats R]

For every class: N random shapes (scales 1e-3..1e3 mm, aspect ratios up to 1:1000),
3-5 contacts anywhere (a vertex or inflection included in a third of the cases), random
pose, either traversal direction; every class allowed. Prints a table:
right-class rate, median and worst relative parameter error, worst contact error
relative to the curve's size, and compute time per request and per touch pair (CPU
time of this process, time.process_time, so other load on the machine does not count):
``mean`` is each request's first run, ``min`` each request's fastest of ``--repeats`` runs
(what is left when the machine's other load slows the caches and the shared core).
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np

from recognizer.curves import CURVES, Pose

SIZE_RANGE = (-3.0, 3.0)  # log10 of the curve's size, mm


def _sorted_spread(rng, lo, hi, n, min_gap):
    for _ in range(100):
        t = np.sort(rng.uniform(lo, hi, n))
        if np.all(np.diff(t) > min_gap):
            return t
    return np.linspace(lo, hi, n)


def random_case(cls: str, rng: np.random.Generator, n: int | None = None):
    """(params, t per touch, pose, reverse, size) of a random exact case."""
    n = n or int(rng.integers(3, 6))
    size = 10 ** rng.uniform(*SIZE_RANGE)
    vertex = rng.random() < 1 / 3
    if cls == "line":
        params, t = {}, _sorted_spread(rng, -size, size, n, 0.05 * size)
    elif cls == "circle":
        params, t = {"r": size}, _sorted_spread(rng, -np.pi, np.pi, n, 0.1)
    elif cls == "ellipse":
        b = size * 10 ** rng.uniform(-3, -0.005)
        params = {"a": size, "b": b}
        t = _sorted_spread(rng, -np.pi, np.pi, n, 0.1)
        if vertex:
            t[0] = rng.choice([-np.pi / 2, 0.0, -np.pi])
            t = np.sort(t)
    elif cls == "parabola":
        params, t = {"a": size}, _sorted_spread(rng, -3, 3, n, 0.1)
        if vertex:
            t[np.argmin(np.abs(t))] = 0.0
    elif cls == "hyperbola":
        aspect = 10 ** rng.uniform(-3, 3)  # b / a; the larger semi-axis is the size
        params = {"a": size, "b": size * aspect} if aspect <= 1 else {"a": size / aspect, "b": size}
        t = _sorted_spread(rng, -2.5, 2.5, n, 0.1)
        if vertex:
            t[np.argmin(np.abs(t))] = 0.0
    elif cls == "cubical_parabola":
        a = rng.choice([-1, 1]) * 10 ** rng.uniform(-1, 1) / size**2
        c = rng.uniform(-3, 3)
        params, t = {"a": a, "c": c}, _sorted_spread(rng, -size, size, n, 0.05 * size)
        if vertex:
            t[np.argmin(np.abs(t))] = 0.0
    elif cls == "semicubical_parabola":
        params = {"a": 10 ** rng.uniform(-1, 1) / math.sqrt(size), "b": rng.uniform(-3, 3)}
        r = math.sqrt(size)
        t = _sorted_spread(rng, -1.5 * r, 1.5 * r, n, 0.1 * r)
        t = np.where(np.abs(t) < 0.05 * r, 0.05 * r * np.sign(t + 1e-300), t)
        t = np.sort(t)
    else:
        raise ValueError(cls)
    pose = Pose(rng.uniform(-np.pi, np.pi), 110 + rng.normal() * 10 * size, rng.normal() * 10 * size)
    return params, t, pose, bool(rng.random() < 0.5), size


def exact_request(cls: str, params: dict, t, pose: Pose, reverse: bool, classes=None) -> dict:
    """A touches request (docs/formats.md) of exact contacts on the posed curve (reverse: decreasing t)."""
    c = CURVES[cls](params)
    t = np.asarray(t, float)
    if reverse:
        t = t[::-1]
    x, y, phi, k, ks = c.frame(t)
    hx, hy = pose.apply(x, y)
    phi = phi + pose.theta
    if reverse:
        phi, k = phi + np.pi, -k
    touches = [{"contact": {"x": float(a), "y": float(b), "phi": float(p), "kappa": float(q), "kappa_s": float(r)}}
               for a, b, p, q, r in zip(hx, hy, phi, k, ks)]
    out = {"touches": touches}
    if classes is not None:
        out["scene"] = {"classes": list(classes)}
    return out


def errors(cls: str, params: dict, t, pose: Pose, reverse: bool, size: float, answer: dict):
    """(relative parameter error, contact error / size) of one answer."""
    rel = 0.0
    for k, v in params.items():
        ref = abs(v) if (cls, k) not in (("cubical_parabola", "c"), ("semicubical_parabola", "b")) else max(abs(v), 1.0)
        rel = max(rel, abs(answer["params"][k] - v) / ref)
    c = CURVES[cls](params)
    tt = np.asarray(t, float)[::-1] if reverse else np.asarray(t, float)
    hx, hy = pose.apply(*c.point(tt))
    got = np.array([[q["x"], q["y"]] for q in answer["contacts"]])
    cerr = float(np.max(np.hypot(got[:, 0] - hx, got[:, 1] - hy))) / size
    return rel, cerr


def main(argv=None) -> int:
    from recognizer.classify import recognize
    from recognizer.touches import parse_request

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cases", type=int, default=2000)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--repeats", type=int, default=3, help="runs per request; the fastest is the min column")
    args = ap.parse_args(argv)
    rng = np.random.default_rng(args.seed)
    print(f"{'class':22s} {'cases':>6s} {'right':>7s} {'med rel':>9s} {'worst rel':>9s} {'worst ct':>9s} "
          f"{'ms/req':>7s} {'ms/pair':>7s} {'min/req':>7s} {'min/pair':>8s}")
    all_dt, all_min, all_pairs, all_cases = 0.0, 0.0, 0, 0
    for cls in CURVES:
        right, rels, cts, dt, dmin, pairs = 0, [], [], 0.0, 0.0, 0
        wrong = []
        for _ in range(args.cases):
            params, t, pose, rev, size = random_case(cls, rng)
            req = parse_request(exact_request(cls, params, t, pose, rev))
            runs = []
            for _ in range(max(args.repeats, 1)):
                t0 = time.process_time()
                ans = recognize(req).to_json()
                runs.append(time.process_time() - t0)
            dt += runs[0]
            dmin += min(runs)
            pairs += len(t) * (len(t) - 1) // 2
            if ans["class"] != cls:
                wrong.append(ans["class"])
                continue
            right += 1
            r, c = errors(cls, params, t, pose, rev, size, ans)
            rels.append(r)
            cts.append(c)
        rels = np.array(rels) if rels else np.array([math.nan])
        cts = np.array(cts) if cts else np.array([math.nan])
        all_dt, all_min, all_pairs, all_cases = all_dt + dt, all_min + dmin, all_pairs + pairs, all_cases + args.cases
        print(f"{cls:22s} {args.cases:6d} {right / args.cases:7.2%} {np.median(rels):9.1e} {rels.max():9.1e} "
              f"{cts.max():9.1e} {1e3 * dt / args.cases:7.2f} {1e3 * dt / pairs:7.3f} {1e3 * dmin / args.cases:7.2f} "
              f"{1e3 * dmin / pairs:8.3f}" + (f"  wrong: {sorted(set(wrong))}" if wrong else ""))
    print(f"{'all':22s} {all_cases:6d} {'':7s} {'':9s} {'':9s} {'':9s} {1e3 * all_dt / all_cases:7.2f} "
          f"{1e3 * all_dt / all_pairs:7.3f} {1e3 * all_min / all_cases:7.2f} {1e3 * all_min / all_pairs:8.3f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
