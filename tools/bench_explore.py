"""Benchmark: exploration robustness on random reachable scenes (a benchmark, not a test).

Seeded random objects in front of the jaw: ellipses with a in 12–35 mm, b/a in 0.3–1,
any orientation, centre (105 ± 8, 0 ± 6) mm; circles r 8–25 mm at the same centres. Each
scene is explored by ``tactile demo --scene S --json --log L`` (balanced profile unless
``--profile``), two at a time. Scenes whose object overlaps the opened jaw (exit 2) are
redrawn. Per scene: the answer, right class or not, parameter error, usable/tried
touches, robot and wall time. With ``--chi2 POS [POS ...]`` it also re-recognizes every
scene's logged touches with each stated position deviation (φ as ``TOUCH_NOISE``) and
prints the true class's χ² tail probability, to calibrate the stated noise
(docs/exploration.md). Run: ``python -m tools.bench_explore [--n 12] [--seed 1]``.
"""

from __future__ import annotations

import argparse
import json
import math
import subprocess
import sys
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np
import yaml

CLASSES = ["line", "circle", "ellipse", "parabola", "hyperbola"]


def random_object(rng) -> dict:
    """One object mapping (scene ``object``): 2 ellipses to 1 circle."""
    pose = {"theta": float(rng.uniform(-math.pi, math.pi)), "x": float(105 + rng.uniform(-8, 8)),
            "y": float(rng.uniform(-6, 6))}
    if rng.uniform() < 1 / 3:
        return {"class": "circle", "params": {"r": float(rng.uniform(8, 25))}, "pose": {**pose, "theta": 0.0}}
    a = float(rng.uniform(12, 35))
    return {"class": "ellipse", "params": {"a": a, "b": a * float(rng.uniform(0.3, 1.0))}, "pose": pose}


def run_scene(path: Path, log: Path, profile: str) -> dict:
    t0 = time.monotonic()
    out = subprocess.run([sys.executable, "-m", "tools.cli", "demo", "--scene", str(path), "--json", "--log", str(log),
                          "--profile", profile], capture_output=True, text=True)
    wall = time.monotonic() - t0
    result = {"rc": out.returncode, "wall_s": wall, "stderr": out.stderr.strip().splitlines()[-1:] or [""]}
    if out.returncode == 0:
        result["recognition"] = json.loads(out.stdout)
    if log.exists():
        from hand_driver.log import read_log

        res = read_log(str(log)).result or {}
        result.update(robot_s=res.get("robot_time_s"), used=res.get("touches_used"), tried=res.get("touches_tried"))
    return result


def param_error(obj: dict, rec: dict) -> str:
    if rec["class"] != obj["class"]:
        return "—"
    return ", ".join(f"{k} {100 * (rec['params'][k] - v) / v:+.2f} %" for k, v in obj["params"].items())


def true_chi2(log: Path, obj: dict, pos_values: list[float]) -> list[float | None]:
    """The true class's χ² tail probability on the log's usable touches, per stated pos σ."""
    from hand_driver.config import parse_config
    from hand_driver.log import read_log
    from tactile_jaw.pipeline import logged_touches, make_recognizer
    from tactile_jaw.settings import TOUCH_NOISE, ExploreSettings

    contents = read_log(str(log))
    header = contents.header
    config = parse_config(header["config"], str(log))
    settings = ExploreSettings.from_json(header["settings"])
    touches = logged_touches(config, contents, settings)
    out = []
    for pos in pos_values:
        if len(touches) < 3:
            out.append(None)
            continue
        scene = {**header["scene"], "classes": [obj["class"]]}
        rec = make_recognizer(scene, settings, {"phi": TOUCH_NOISE["phi"], "pos": pos})(touches)
        out.append(rec.ranking[0].p_value if rec.ranking else None)
    return out


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=12, help="scenes (default 12)")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--profile", default="balanced")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--chi2", type=float, nargs="*", default=[], metavar="POS",
                    help="stated position deviations (mm) at which to report the true class's χ² p-value")
    ap.add_argument("--keep", default=None, help="directory for the scenes and logs (default: a temporary one)")
    args = ap.parse_args(argv)
    from hand_driver.config import load_config
    from hand_driver.sim.physics import ContactWorld
    from recognizer.scene import load_scene
    from tactile_jaw.plan import open_pose

    rng = np.random.default_rng(args.seed)
    work = Path(args.keep or tempfile.mkdtemp(prefix="bench_explore_"))
    work.mkdir(parents=True, exist_ok=True)
    config = load_config("config/jaw.yaml")
    q_open = open_pose(config)
    scenes = []
    while len(scenes) < args.n:
        obj = random_object(rng)
        mapping = {"name": f"rand{len(scenes)}", "classes": CLASSES, "object": obj}
        scene = load_scene(mapping)
        if ContactWorld(config, scene.object).penetrates(q_open):
            continue  # overlaps the opened jaw: not a reachable scene for the demo
        path = work / f"rand{len(scenes)}.yaml"
        path.write_text(yaml.safe_dump(mapping))
        scenes.append((path, obj))
    with ThreadPoolExecutor(args.jobs) as pool:
        results = list(pool.map(lambda s: run_scene(s[0], s[0].with_suffix(".log"), args.profile), scenes))
    print("| # | object | answer | right | parameter error | touches used/tried | robot time | wall time |"
          + "".join(f" p(χ²) pos {p:g} |" for p in args.chi2))
    print("|---" * (8 + len(args.chi2)) + "|")
    right = 0
    for k, ((path, obj), res) in enumerate(zip(scenes, results)):
        rec = res.get("recognition")
        params = " ".join(f"{n} {v:.1f}" for n, v in obj["params"].items())
        p = obj["pose"]
        desc = f"{obj['class']} {params} θ {p['theta']:.2f} at ({p['x']:.0f}, {p['y']:.0f})"
        answer = rec["class"] if rec else f"exit {res['rc']}: {res['stderr'][0][:60]}"
        ok = rec is not None and rec["class"] == obj["class"]
        right += ok
        verdict = "yes" if ok else ("refused" if rec is None or rec["class"] == "unclassified" else "**WRONG**")
        robot = f"{res['robot_s']:.1f} s" if res.get("robot_s") is not None else "—"
        row = (f"| {k} | {desc} | {answer} | {verdict} | {param_error(obj, rec) if rec else '—'} | "
               f"{res.get('used')}/{res.get('tried')} | {robot} | {res['wall_s']:.1f} s |")
        if args.chi2:
            ps = true_chi2(path.with_suffix(".log"), obj, args.chi2)
            row += "".join(f" {'—' if v is None else f'{v:.3g}'} |" for v in ps)
        print(row, flush=True)
    print(f"right class on {right} of {len(scenes)} scenes; scenes and logs in {work}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
