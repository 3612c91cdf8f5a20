"""Benchmark: why calibration matters. A truth jaw (zero ticks ±20, links ±1 mm, pad offsets
±0.5 mm off the nominal config, seeded) is explored by ``tactile demo`` with a perfect config
(the truth itself), with the nominal config (before calibration) and with the config
``hand_driver.calibration_fit`` fits from touches on the reference disk at the suggested
placements (after), each on the scene's object at ``--placements`` poses (the scene's own
and sub-millimetre jitters of it, the same for the three configs). One demo's error is one
draw of the exploration's quantization noise (a config 0.05 tick off the truth moves it by
0.25–1.2 %), so configs are compared by their mean error over the placements (12 by
default: over 4 the mean's standard error was about a quarter of the mean, and one truth
jaw's after/perfect ratio read 2.08 on 4 placements and 0.93 on 12). Prints the
calibration errors, every demo's parameter and pose errors, the means and their
standard errors.
Run: ``python -m tools.bench_calibration [--seed N] [--placements K]``; with ``--config C
--truth-config T`` the truth jaw is T instead of a perturbed C (e.g. ``--config
config/jaw-p.yaml --truth-config config/jaw-p-truth.yaml``: its backlash is fitted when C's
servos state one, as ``tactile calibrate --backlash auto`` does)."""

from __future__ import annotations

import argparse
import contextlib
import dataclasses
import json
import math
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
    """``tactile calibrate``'s touches (one emulated bus per default placement, the disk
    off it by up to ±3 mm) and fit."""
    from hand_driver.calibration_fit import backlash_matters, fit
    from hand_driver.calibration import default_placements
    from hand_driver.cycle import LockstepClock
    from hand_driver.sim.server import EmulatedBus
    from recognizer.curves import Pose
    from recognizer.scene import load_scene
    from tools.cmd_calibrate import touch_placements

    disk = load_scene("config/scenes/calibration.yaml").object
    places = default_placements(cfg, disk)
    placed = [dataclasses.replace(disk, pose=Pose(0.0, x + rng.uniform(-3, 3), y + rng.uniform(-3, 3)))
              for x, y in places]
    with contextlib.ExitStack() as stack:
        sims = [stack.enter_context(EmulatedBus(cfg, d, truth_config=truth, time_scale=0.0)) for d in placed]
        readings, _ = touch_placements(cfg, disk, places, [s.port for s in sims], faces=faces, corners=corners,
                                       clock_for=lambda k: LockstepClock(sims[k]), say=lambda line: None,
                                       bus_options={"handle_signals": False, "timeout_s": 0.5})
    return fit(cfg, disk, readings, tolerances={"zero_tick": 99.0, "link_mm": 99.0, "offset_mm": 99.0,
                                                "backlash_deg": 99.0}, backlash=backlash_matters(cfg))


#: object placements relative to the scene's pose: (dx mm, dy mm, dθ rad). Sub-millimetre
#: jitter re-draws the encoder quantization of every reading while the exploration sees
#: the same part of the same object (offsets of 4 mm and 0.15 rad already change which
#: finger can roll where on a perturbed jaw, and so the demo's coverage)
PLACEMENT_OFFSETS = ((0.0, 0.0, 0.0), (0.5, 0.3, 0.01), (-0.4, -0.5, -0.01), (0.3, -0.4, 0.02),
                     (-0.5, 0.4, -0.02), (0.2, 0.2, 0.0), (-0.3, 0.1, 0.015), (0.4, -0.2, -0.015),
                     (-0.1, -0.3, 0.005), (0.1, 0.5, -0.005), (-0.2, -0.1, -0.02), (0.3, 0.4, 0.02))


def placed_scenes(scene_path: str, k: int, tmp: Path) -> list[tuple[Path, object]]:
    """The scene at its first ``k`` placements (PLACEMENT_OFFSETS): (scene file, object)."""
    import yaml

    from recognizer.scene import load_scene
    from tactile_common.yamlfile import read_yaml

    raw = read_yaml(scene_path, "scene")
    out = []
    for i, (dx, dy, dth) in enumerate(PLACEMENT_OFFSETS[:k]):
        pose = dict(raw["object"]["pose"])
        pose.update(theta=float(pose.get("theta", 0.0)) + dth, x=float(pose["x"]) + dx, y=float(pose["y"]) + dy)
        placed = dict(raw, object=dict(raw["object"], pose=pose))
        path = tmp / f"scene_{i}.yaml"
        path.write_text(yaml.safe_dump(placed, sort_keys=False))
        out.append((path, load_scene(str(path)).object))
    return out


def demo(config: Path, truth: Path, scene: Path) -> dict | str:
    """``tactile demo``'s JSON answer, or why it failed (one line)."""
    out = subprocess.run([sys.executable, "-m", "tools.cli", "demo", "--config", str(config), "--truth-config",
                          str(truth), "--scene", str(scene), "--json"], capture_output=True, text=True)
    if out.returncode not in (0, 3):  # 3: a refusal, whose answer is printed (tools.cli)
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
    period = math.pi if obj.cls == "ellipse" else 2 * math.pi  # the ellipse's half-turn symmetry
    p = answer["pose"]
    return rel, (f"max parameter error {rel:.2f} %, pose offset "
                 f"{np.hypot(p['x'] - obj.pose.x, p['y'] - obj.pose.y):.2f} mm, "
                 f"theta {1e3 * abs(math.remainder(p['theta'] - obj.pose.theta, period)):.1f} mrad")


def _mean_se(errs: list[float]) -> tuple[float, str]:
    """Mean of the answered demos' errors (%), and it as text with its standard error and
    the number of failed demos (wrong class, refusal, fault)."""
    ok = np.array([e for e in errs if math.isfinite(e)])
    if ok.size == 0:
        return math.inf, "no answer"
    mean = float(ok.mean())
    text = f"{mean:.2f} %" + (f" ± {ok.std(ddof=1) / math.sqrt(ok.size):.2f}" if ok.size > 1 else "")
    failed = len(errs) - ok.size
    return (mean if not failed else math.inf), text + (f" ({failed} failed)" if failed else "")


def main() -> int:
    from hand_driver.calibration_fit import pack_params
    from hand_driver.config import dump_config, load_config

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--config", default="config/jaw.yaml", help="the nominal jaw (default %(default)s)")
    ap.add_argument("--truth-config", default=None, help="the truth jaw (default: the nominal one perturbed by --seed)")
    ap.add_argument("--scene", default="config/scenes/default.yaml")
    ap.add_argument("--faces", type=int, default=10)
    ap.add_argument("--corners", type=int, default=6)
    ap.add_argument("--placements", type=int, default=len(PLACEMENT_OFFSETS),
                    choices=range(1, len(PLACEMENT_OFFSETS) + 1),
                    help=f"object placements per config (default and most {len(PLACEMENT_OFFSETS)})")
    args = ap.parse_args()
    nominal = load_config(args.config)
    truth, rng = perturbed(nominal, args.seed)
    if args.truth_config:
        truth = load_config(args.truth_config)
    with tempfile.TemporaryDirectory() as tmp:
        truth_path, after_path = Path(tmp) / "truth.yaml", Path(tmp) / "calibrated.yaml"
        dump_config(truth, truth_path)
        t0, c0 = time.monotonic(), time.process_time()
        result = calibrate(nominal, truth, rng, args.faces, args.corners)
        dump_config(result.config, after_path)
        bands = tuple(k for k, (*_, fitted) in enumerate(result.loads) if fitted)
        err = pack_params(result.config, bands) - pack_params(truth, bands)
        print(f"calibration: {result.n_readings} touches used ({result.n_reclassified} face touches found to be "
              f"pad-end contacts, {result.n_dropped} dropped), {time.monotonic() - t0:.0f} s wall, "
              f"{time.process_time() - c0:.0f} s CPU, residual RMS {result.rms_before_mm:.3f} -> "
              f"{result.rms_after_mm:.4f} mm")
        for e, d in zip(result.estimates, err):
            print(f"  {e.name:28s} error {d:+7.3f}  (se {e.se:.3f}; nominal was off by {e.before - (e.after - d):+.3f})")
        configs = (("perfect config", truth_path), ("before calibration", Path(args.config)),
                   ("after calibration", after_path))
        demo_err: dict[str, list[float]] = {label: [] for label, _ in configs}
        for i, (scene, obj) in enumerate(placed_scenes(args.scene, args.placements, Path(tmp))):
            p = obj.pose
            print(f"placement {i}: {obj.cls} at theta={p.theta:.2f} rad x={p.x:.1f} mm y={p.y:.1f} mm")
            for label, path in configs:
                rel, text = errors(demo(path, truth_path, scene), obj)
                demo_err[label].append(rel)
                print(f"  demo, {label:20s}: {text}")
    kinds = [e.kind for e in result.estimates]
    worst_tick = max(abs(d) for d, k in zip(err, kinds) if k == "zero_tick")
    worst_mm = max(abs(d) for d, k in zip(err, kinds) if k in ("link_mm", "offset_mm"))
    stats = {label: _mean_se(v) for label, v in demo_err.items()}
    perfect, after = stats["perfect config"][0], stats["after calibration"][0]
    print(f"summary: seed {args.seed}, worst zero tick {worst_tick:.2f} tick, worst length {worst_mm:.3f} mm, "
          f"demo mean error over {args.placements} placements perfect/before/after "
          f"{' / '.join(text for *_, text in stats.values())}, after/perfect "
          f"{f'{after / perfect:.2f}' if math.isfinite(perfect) else 'n/a (a perfect-config demo failed)'}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
