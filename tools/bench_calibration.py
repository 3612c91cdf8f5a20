"""Benchmark: why calibration matters. A truth jaw (zero ticks ±20, links ±1 mm, pad offsets
±0.5 mm off the nominal config, seeded) is explored by ``tactile demo`` three times on the
emulated bus: with a perfect config (the truth itself), with the nominal config (before
calibration), and with the config ``hand_driver.calibration`` fits from touches on the
reference disk at the suggested placements (after). Prints the calibration errors and the
demo's parameter and pose errors. Run: ``python -m tools.bench_calibration [--seed N]``."""

from __future__ import annotations

import argparse
import dataclasses
import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np


def perturbed(cfg, seed: int):
    from hand_driver.config import perturbed as perturbed_config

    rng = np.random.default_rng(seed)
    return perturbed_config(cfg, rng), rng


def calibrate(cfg, truth, rng, faces: int, corners: int):
    from hand_driver import calibration as cal
    from hand_driver.bus import JointBus
    from hand_driver.motion import Jaw, LockstepClock
    from hand_driver.sim.server import EmulatedBus
    from recognizer.curves import Pose
    from recognizer.scene import load_scene

    disk = load_scene("config/scenes/calibration.yaml").object
    readings = []
    for k, (x, y) in enumerate(cal.DEFAULT_PLACEMENTS):
        placed = dataclasses.replace(disk, pose=Pose(0.0, x + rng.uniform(-3, 3), y + rng.uniform(-3, 3)))
        with EmulatedBus(cfg, placed, truth_config=truth, time_scale=0.0) as sim, \
                JointBus(sim.port, cfg.bus.baudrate, cfg.joints, handle_signals=False, timeout_s=0.5) as bus:
            got, _, _ = cal.touch_reference(Jaw(bus, cfg, clock=LockstepClock(sim)), disk, (x, y), placement=k,
                                            faces=faces, corners=corners)
        readings += got
    return cal.fit(cfg, disk, readings, tolerances={"zero_tick": 99.0, "link_mm": 99.0, "offset_mm": 99.0})


def demo(config: Path, truth: Path, scene: str) -> dict | str:
    """``tactile demo``'s JSON answer, or why it failed (one line)."""
    out = subprocess.run([sys.executable, "-m", "tools.cli", "demo", "--config", str(config), "--truth-config",
                          str(truth), "--scene", scene, "--json"], capture_output=True, text=True)
    if out.returncode != 0:
        lines = out.stderr.strip().splitlines() or ["no message"]
        return f"demo failed (exit {out.returncode}: {lines[-1]})"
    return json.loads(out.stdout)


def errors(answer: dict | str, obj) -> tuple[float, str]:
    """(largest relative parameter error in %, inf for a wrong class or a failed demo; a
    description)."""
    if isinstance(answer, str):
        return float("inf"), answer
    if answer["class"] != obj.cls:
        return float("inf"), f"wrong class ({answer['class']})"
    rel = 100 * max(abs(answer["params"][k] - v) / abs(v) for k, v in obj.params.items())
    p = answer["pose"]
    return rel, (f"max parameter error {rel:.2f} %, pose offset "
                 f"{np.hypot(p['x'] - obj.pose.x, p['y'] - obj.pose.y):.2f} mm, "
                 f"theta {1e3 * abs(p['theta'] - obj.pose.theta):.1f} mrad")


def main() -> int:
    from hand_driver import calibration as cal
    from hand_driver.config import dump_config, load_config
    from recognizer.scene import load_scene

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--scene", default="config/scenes/default.yaml")
    ap.add_argument("--faces", type=int, default=10)
    ap.add_argument("--corners", type=int, default=6)
    args = ap.parse_args()
    nominal = load_config("config/jaw.yaml")
    truth, rng = perturbed(nominal, args.seed)
    obj = load_scene(args.scene).object
    with tempfile.TemporaryDirectory() as tmp:
        truth_path, after_path = Path(tmp) / "truth.yaml", Path(tmp) / "calibrated.yaml"
        dump_config(truth, truth_path)
        t0, c0 = time.monotonic(), time.process_time()
        result = calibrate(nominal, truth, rng, args.faces, args.corners)
        dump_config(result.config, after_path)
        err = cal._pack(result.config) - cal._pack(truth)
        print(f"calibration: {result.n_readings} touches used ({result.n_reclassified} face touches found to be "
              f"pad-end contacts, {result.n_dropped} dropped), {time.monotonic() - t0:.0f} s wall, "
              f"{time.process_time() - c0:.0f} s CPU, residual RMS {result.rms_before_mm:.3f} -> "
              f"{result.rms_after_mm:.4f} mm")
        for e, d in zip(result.estimates, err):
            print(f"  {e.name:28s} error {d:+7.3f}  (se {e.se:.3f}; nominal was off by {e.before - (e.after - d):+.3f})")
        demo_err = []
        for label, path in (("perfect config", truth_path), ("before calibration", Path("config/jaw.yaml")),
                            ("after calibration", after_path)):
            rel, text = errors(demo(path, truth_path, args.scene), obj)
            demo_err.append(rel)
            print(f"demo, {label:20s}: {text}")
    kinds = [e.kind for e in result.estimates]
    worst_tick = max(abs(d) for d, k in zip(err, kinds) if k == "zero_tick")
    worst_mm = max(abs(d) for d, k in zip(err, kinds) if k != "zero_tick")
    print(f"summary: seed {args.seed}, worst zero tick {worst_tick:.2f} tick, worst length {worst_mm:.3f} mm, "
          f"demo error perfect/before/after {demo_err[0]:.2f} / {demo_err[1]:.2f} / {demo_err[2]:.2f} %, "
          f"after/perfect {demo_err[2] / demo_err[0]:.2f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
