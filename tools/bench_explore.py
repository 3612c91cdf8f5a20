"""Benchmark: exploration robustness on random reachable scenes (a benchmark, not a test).

Seeded random objects in front of the jaw: ellipses with a in 12–35 mm, b/a in 0.3–1,
any orientation, centre (105 ± 8, 0 ± 6) mm; circles r 8–25 mm at the same centres; or,
with ``--finite N``, N finite objects per class drawn from the example scenes
(:func:`finite_object`), all seven classes candidates. Each
scene is explored by ``tactile demo --scene S --json --log L`` (balanced profile unless
``--profile``), two at a time. Scenes whose object overlaps the opened jaw (exit 2) are
redrawn. Per scene: the answer, right class or not, parameter error, usable/tried
touches, robot and wall time. With ``--chi2 [POS ...]`` it also re-recognizes every
scene's logged touches with the true class only, with the noise the jaw states and with
each isotropic position deviation POS (φ as the jaw's ``phi_sigma``), and prints the true class's χ²
tail probability (χ²/dof), to calibrate the stated noise (docs/exploration.md). With
``--follow``, every refused object whose refusal names a move (the log's ``stopped_early`` or
``budget_spent`` event, tactile_jaw.choose.move_advice) is moved so (:func:`moved_object`) and explored once
more, as a person following the advice would, and the last table counts those answered right
then in a column of their own (right after the advised move). ``--config C`` builds the emulated jaw from C
and explores with it (config/jaw-p.yaml: the P-series jaw); ``--anywhere`` draws each finite
object anywhere in the workspace where its curved part faces a finger
(tools.random_objects.random_object) instead of near its example's place. ``--truth-config T``
builds the emulated jaw from T (the jaw as it really is: its zero errors and backlash) while the
exploration uses ``--config``; with ``--calibrate`` the exploration's config is instead the one
``tactile calibrate`` fits once per run against T through the emulated bus (tools.bench_calibration.
calibrate: the default plan at the four suggested placements, each disk off it by up to ±3 mm; its
draws come from their own generator, so the objects are those of a run without it): the lab's
workflow, calibrate then explore. The σ table then says how well the answers' stated σ's cover the
truth: per class, the share of shape parameters of the right answers with |z| ≤ 1.96 and ≤ 3
(z = error / stated σ) and the largest |z|. The last table
says what the jaw can tell, per class: right / refused / wrong, median error, median robot
time, each refusal's kind (tactile_jaw.decide.refusal_kind: out of reach, needs finer
angles, needs another move) and the median robot time per phase. Run: ``python -m
tools.bench_explore [--n 12] [--seed 1]``, ``python -m tools.bench_explore --finite 10
--anywhere --config config/jaw-p.yaml --seed 29``, ``python -m tools.bench_explore --finite 4
--anywhere --config config/jaw-p.yaml --truth-config config/jaw-p-truth.yaml --calibrate --seed 11``.
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
from dataclasses import replace
from pathlib import Path

import numpy as np
import yaml

from tactile_common.errors import DeviceFault, InputError

CLASSES = ["line", "circle", "ellipse", "parabola", "hyperbola", "cubical_parabola", "semicubical_parabola"]
DEFAULT_CONFIG = "config/jaw.yaml"
#: the robot time's phases as the run log's result splits it (tactile_jaw.rounds): probes,
#: rolling touches and flat presses, each including its transits (the next column), and the
#: final retreat (logs older than the split book flat presses under touches)
PHASES = ("probes", "probe_transits", "touches", "touch_transits", "presses", "press_transits", "retreat")
PHASE_HEADS = ("probes", "of which transits", "rolling touches", "of which transits", "flat presses",
               "of which transits", "retreat")
#: how a finite object of each class scales by s: factors of its parameters and of its
#: canonical extent (the curve's points all scale by s; closure points scale by s)
SCALING = {"line": ({}, 1.0), "circle": ({"r": 1.0}, None), "ellipse": ({"a": 1.0, "b": 1.0}, None),
           "parabola": ({"a": 1.0}, 0.0), "hyperbola": ({"a": 1.0, "b": 1.0}, 0.0),
           "cubical_parabola": ({"a": -2.0, "c": 0.0}, 1.0), "semicubical_parabola": ({"a": -0.5, "b": 0.0}, 0.5)}


def random_object(rng) -> dict:
    """One object mapping (scene ``object``): 2 ellipses to 1 circle."""
    pose = {"theta": float(rng.uniform(-math.pi, math.pi)), "x": float(105 + rng.uniform(-8, 8)),
            "y": float(rng.uniform(-6, 6))}
    if rng.uniform() < 1 / 3:
        return {"class": "circle", "params": {"r": float(rng.uniform(8, 25))}, "pose": {**pose, "theta": 0.0}}
    a = float(rng.uniform(12, 35))
    return {"class": "ellipse", "params": {"a": a, "b": a * float(rng.uniform(0.3, 1.0))}, "pose": pose}


def finite_object(rng, example: dict) -> dict:
    """A random finite object like ``example`` (an example scene's object): sizes 0.6–1.5×,
    turned by up to ±20° and moved by up to ±8 mm, the curved part still facing the finger
    it faces. Parameters scale by s to their length dimension (``SCALING``: exponent of s),
    the canonical extent by s to the power the class's parametrization needs."""
    size = float(rng.uniform(0.6, 1.5))
    exps, ext_exp = SCALING[example["class"]]
    pose = dict(example["pose"])
    if "theta_deg" in pose:
        pose["theta"] = math.radians(pose.pop("theta_deg"))
    obj = {"class": example["class"],
           "params": {k: float(v) * size ** (1.0 if exps.get(k) is None else exps[k])
                      for k, v in example["params"].items()},
           "pose": {"theta": float(pose["theta"] + rng.uniform(-1, 1) * math.radians(20.0)),
                    "x": float(pose["x"] + rng.uniform(-8, 8)), "y": float(pose["y"] + rng.uniform(-8, 8))}}
    if "extent" in example:
        obj["extent"] = [float(t) * size ** ext_exp for t in example["extent"]]
    if "closure" in example:
        obj["closure"] = [[float(x) * size, float(y) * size] for x, y in example["closure"]]
    return obj


def run_scene(path: Path, log: Path, profile: str, config: str = DEFAULT_CONFIG, truth: str | None = None,
              moved_as: Path | None = None) -> dict:
    """``tactile demo`` of one scene with ``config`` (on the emulated jaw ``truth``, default
    ``config``; ``moved_as``: the log of the refusal whose move the scene's object was moved by,
    ``--moved-as``): its answer, exit status and what its log says."""
    from tools.cli import EXIT_RECOGNIZED, EXIT_REFUSED

    t0 = time.monotonic()
    out = subprocess.run([sys.executable, "-m", "tools.cli", "demo", "--scene", str(path), "--json", "--log", str(log),
                          "--profile", profile, "--config", config]
                         + (["--truth-config", truth] if truth else [])
                         + (["--moved-as", str(moved_as)] if moved_as is not None else []), capture_output=True, text=True)
    wall = time.monotonic() - t0
    result = {"rc": out.returncode, "wall_s": wall, "stderr": out.stderr.strip().splitlines()[-1:] or [""]}
    if out.returncode in (EXIT_RECOGNIZED, EXIT_REFUSED):  # a refusal prints its answer too
        result["recognition"] = json.loads(out.stdout)
    if log.exists():
        from hand_driver.log import read_log
        from tactile_jaw.choose import last_stop

        contents = read_log(str(log))
        res = contents.result or {}
        result.update(robot_s=res.get("robot_time_s"), used=res.get("touches_used"), tried=res.get("touches_tried"),
                      time_s=res.get("time_s") or {})
        stop = last_stop(contents.events)
        result["move"] = stop.get("move") if stop is not None else None
    return result


def logged_move(log: Path) -> dict | None:
    """The move a run's refusal advises (its ``stopped_early`` or ``budget_spent`` event's
    ``move``), or None."""
    from hand_driver.log import read_log
    from tactile_jaw.choose import last_stop

    stop = last_stop(read_log(str(log)).events) if log.exists() else None
    return stop.get("move") if stop is not None else None


def verdict(obj: dict, rec: dict | None) -> str:
    """The answer ``rec`` (None: no answer) to the object ``obj``: 'yes' (its class),
    'refused' (none, or ``unclassified``) or '**WRONG**'."""
    if rec is not None and rec["class"] == obj["class"]:
        return "yes"
    return "refused" if rec is None or rec["class"] == "unclassified" else "**WRONG**"


def moved_object(obj: dict, move: dict) -> dict:
    """``obj`` (a scene ``object`` mapping) turned by ``move['turn_deg']`` about ``move['about']``,
    then shifted by (dx, dy) mm (tactile_jaw.choose.Stop)."""
    pose = dict(obj["pose"])
    turn = math.radians(move["turn_deg"])
    theta = math.radians(pose.pop("theta_deg")) if "theta_deg" in pose else pose["theta"]
    (px, py), c, s = move["about"], math.cos(turn), math.sin(turn)
    x, y = pose["x"] - px, pose["y"] - py
    pose.update(theta=theta + turn, x=px + c * x - s * y + move["dx"], y=py + s * x + c * y + move["dy"])
    return {**obj, "pose": pose}


def param_error(obj: dict, rec: dict) -> str:
    if rec["class"] != obj["class"]:
        return "—"
    return ", ".join(f"{k} {100 * (rec['params'][k] - v) / v:+.2f} %" for k, v in obj["params"].items())


def true_chi2(log: Path, obj: dict, pos_values: list[float]) -> list[tuple[float, float, int] | None]:
    """The true class's (χ² tail probability, χ², dof) on the log's usable touches: first with
    the noise the jaw states (tactile_jaw.pipeline.stated_noise), then per stated pos σ
    (φ as ``phi_sigma`` of the coarser finger, isotropic positions)."""
    from hand_driver.log import read_log
    from tactile_jaw.pipeline import logged_touches, make_recognizer
    from tactile_jaw.settings import ExploreSettings, phi_sigma

    contents = read_log(str(log))
    header = contents.header
    config = contents.jaw_config()
    settings = ExploreSettings.from_json(header["settings"])
    touches = logged_touches(config, contents, settings)
    out = []
    for pos in [None, *pos_values]:
        if len(touches) < 3:
            out.append(None)
            continue
        scene = {**header["scene"], "classes": [obj["class"]]}
        phi = max(phi_sigma(f.joints) for f in config.fingers)
        rec = make_recognizer(scene, settings, None if pos is None else {"phi": phi, "pos": pos})(touches)
        top = rec.ranking[0] if rec.ranking else None
        out.append(None if top is None or top.cls != obj["class"] else (top.p_value, top.chi2, top.dof))
    return out


def true_geometry(obj: dict, x: float, y: float) -> tuple[float, float]:
    """κ, κ_s of the scene's curve (over its ``extent`` when it has one) at the point nearest (x, y)."""
    from recognizer.curves import CURVES, Pose

    curve = CURVES[obj["class"]](obj["params"])
    cx, cy = Pose(**obj["pose"]).inverse(x, y)
    t = np.linspace(*(obj.get("extent") or curve.t_period), 200001)
    px, py = curve.point(t)
    k = int(np.argmin(np.hypot(px - cx, py - cy)))
    return float(curve.kappa(t[k])), float(curve.kappa_s(t[k]))


def kappa_comparison(log: Path, obj: dict) -> dict:
    """The logged usable touches' κ, κ_s two ways against the truth (errors and z-scores):
    the jaw's envelope fit with its quantization covariance (tactile_jaw.pipeline.
    envelope.fit_envelope, what the jaw hands the recognizer) and the recognizer's own
    estimate from the samples; and the final answer both ways."""
    from hand_driver.log import read_log
    from recognizer.estimate import estimate_local
    from tactile_jaw.curvature_pool import pooled
    from tactile_jaw.decide import final_answer
    from tactile_jaw.pipeline import logged_touches, make_recognizer, stated_noise
    from tactile_jaw.settings import ExploreSettings

    contents = read_log(str(log))
    header = contents.header
    config = contents.jaw_config()
    settings = ExploreSettings.from_json(header["settings"])
    felt = logged_touches(config, contents, settings)
    if not felt:
        return {"rows": []}
    noise = stated_noise(felt)
    rows = []
    for t in pooled(felt):  # as the recognizer is handed them (tactile_jaw.curvature_pool)
        if getattr(t.samples, "curvature", None) is None:  # a flat press's contact: no roll, no κ to compare
            continue
        k_env, ks_env, cov = t.samples.curvature
        g = estimate_local(t.samples, method=settings.recognize.get("estimator", "auto"), noise=noise)
        m = len(t.samples.phi) // 2
        k_true, ks_true = true_geometry(obj, float(t.samples.x[m]), float(t.samples.y[m]))
        k_true = math.copysign(k_true, k_env)  # the touch's direction of travel: κ flips with it, κ_s = dκ/ds not
        rows.append({"k_true": k_true, "ks_true": ks_true, "k_env": k_env, "ks_env": ks_env,
                     "sk_env": math.sqrt(cov[0, 0]), "sks_env": math.sqrt(cov[1, 1]),
                     "k_smp": g.kappa, "ks_smp": g.kappa_s, "sk_smp": math.sqrt(g.cov[0][0]),
                     "sks_smp": math.sqrt(g.cov[1][1])})
    out = {"rows": rows}
    if len(felt) >= 2:
        recognize = make_recognizer(header["scene"], settings)
        without = [replace(t, samples=replace(t.samples, curvature=None)) if getattr(t.samples, "curvature", None)
                   is not None else t for t in felt]
        try:
            out["envelope"] = final_answer(recognize, felt, settings)
            out["samples"] = final_answer(recognize, without, settings)
        except InputError:
            pass
    return out


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=12, help="scenes (default 12)")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--profile", default="balanced")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--chi2", type=float, nargs="*", default=None, metavar="POS",
                    help="report the true class's χ² p-value with the noise the jaw states and, with "
                         "values, with each of these isotropic position deviations (mm)")
    ap.add_argument("--kappa", action="store_true",
                    help="compare each usable touch's κ, κ_s from the envelope fit (with its quantization "
                         "covariance) and from the samples against the truth, and recognize both ways")
    ap.add_argument("--finite", type=int, default=0, metavar="N",
                    help="instead: N random finite objects per class, drawn from config/scenes/<class>.yaml")
    ap.add_argument("--keep", default=None, help="directory for the scenes and logs (default: a temporary one)")
    ap.add_argument("--classes", nargs="+", choices=CLASSES, default=None, metavar="CLASS",
                    help="with --finite: run only these classes' objects (the same objects, numbered as in a "
                         "run of every class with the same seed)")
    ap.add_argument("--follow", action="store_true",
                    help="re-run every refused object moved as its refusal advises, once")
    ap.add_argument("--config", default=DEFAULT_CONFIG,
                    help=f"the jaw config the emulated jaw is built from and explores with (default {DEFAULT_CONFIG})")
    ap.add_argument("--truth-config", default=None,
                    help="the jaw the emulator really is (its declared errors simulated), default --config")
    ap.add_argument("--calibrate", action="store_true",
                    help="with --truth-config: calibrate --config against it once (tactile calibrate's touches "
                         "through the emulated bus) and explore with the calibrated config")
    ap.add_argument("--anywhere", action="store_true",
                    help="with --finite: each object anywhere in the workspace where its curved part faces a finger "
                         "(tools.random_objects), not near its example's place")
    args = ap.parse_args(argv)
    if args.calibrate and not args.truth_config:
        ap.error("--calibrate needs --truth-config (the jaw to calibrate against)")
    from hand_driver.config import load_config
    from hand_driver.sim.physics import ContactWorld
    from recognizer.scene import load_scene
    from tactile_jaw.plan import open_pose

    rng = np.random.default_rng(args.seed)
    work = Path(args.keep or tempfile.mkdtemp(prefix="bench_explore_"))
    work.mkdir(parents=True, exist_ok=True)
    config = load_config(args.config)
    q_open = open_pose(config)
    scenes = []
    if args.finite and args.anywhere:
        from tools.random_objects import random_object as anywhere_object

        draws = [lambda c=c: anywhere_object(c, rng, config)[0] for c in CLASSES for _ in range(args.finite)]
    elif args.finite:
        draws = [lambda c=c: finite_object(rng, yaml.safe_load(Path(f"config/scenes/{c}.yaml").read_text())["object"])
                 for c in CLASSES for _ in range(args.finite)]
    else:
        draws = [lambda: random_object(rng)] * args.n
    for draw in draws:
        while True:
            obj = draw()
            mapping = {"name": f"rand{len(scenes)}", "classes": CLASSES, "object": obj}
            try:
                scene = load_scene(mapping)
            except InputError:
                continue  # a closure the resized curve crosses: draw again
            if not ContactWorld(config, scene.object).penetrates(q_open):
                break  # else it overlaps the opened jaw: not a reachable scene for the demo
        path = work / f"rand{len(scenes)}.yaml"
        path.write_text(yaml.safe_dump(mapping))
        scenes.append((path, obj))
    numbers = [k for k, (_, obj) in enumerate(scenes) if args.classes is None or obj["class"] in args.classes]
    scenes = [scenes[k] for k in numbers]
    explore_config = args.config
    if args.calibrate:
        try:
            explore_config = str(calibrated_config(args.config, args.truth_config, args.seed, work))
        except (InputError, DeviceFault) as exc:  # refused, or a servo's fault: one line and tactile's exit status
            from hand_driver.calibration_fit import CalibrationRefused
            from tools.cli import EXIT_BAD_INPUT, EXIT_FAULT, EXIT_REFUSED

            print(f"bench_explore: calibration of {args.config} against {args.truth_config}: {exc}", file=sys.stderr)
            return (EXIT_FAULT if isinstance(exc, DeviceFault) else EXIT_REFUSED if isinstance(exc, CalibrationRefused)
                    else EXIT_BAD_INPUT)
    with ThreadPoolExecutor(args.jobs) as pool:
        results = list(pool.map(lambda s: run_scene(s[0], s[0].with_suffix(".log"), args.profile, explore_config,
                                                    args.truth_config), scenes))
    chi2_columns = [] if args.chi2 is None else ["stated"] + [f"pos {p:g}" for p in args.chi2]
    print("| # | object | answer | right | parameter error | touches used/tried | robot time | wall time |"
          + "".join(f" p(χ²) {p} |" for p in chi2_columns))
    print("|---" * (8 + len(chi2_columns)) + "|")
    right = 0
    for k, ((path, obj), res) in enumerate(zip(scenes, results)):
        rec = res.get("recognition")
        params = " ".join(f"{n} {v:.1f}" for n, v in obj["params"].items())
        p = obj["pose"]
        desc = f"{obj['class']} {params} θ {p['theta']:.2f} at ({p['x']:.0f}, {p['y']:.0f})"
        answer = rec["class"] if rec else f"exit {res['rc']}: {res['stderr'][0][:60]}"
        said = verdict(obj, rec)
        right += said == "yes"
        robot = f"{res['robot_s']:.1f} s" if res.get("robot_s") is not None else "—"
        z = z_scores(obj, rec)
        zs = f" (z {' '.join(f'{v:+.1f}' for v in z)})" if z and args.truth_config else ""
        row = (f"| {numbers[k]} | {desc} | {answer} | {said} | {param_error(obj, rec) if rec else '—'}{zs} | "
               f"{res.get('used')}/{res.get('tried')} | {robot} | {res['wall_s']:.1f} s |")
        if args.chi2 is not None:
            ps = true_chi2(path.with_suffix(".log"), obj, args.chi2)
            row += "".join(" — |" if v is None else f" {v[0]:.3g} ({v[1]:.1f}/{v[2]}) |" for v in ps)
        print(row, flush=True)
    print(f"right class on {right} of {len(scenes)} scenes; scenes and logs in {work}")
    print_class_summary(scenes, results)
    followed = (follow_advice(scenes, results, args.profile, args.jobs, explore_config, args.truth_config)
                if args.follow else None)
    print_tell_table(scenes, results, explore_config, followed)
    print_sigma_table(scenes, results)
    if args.kappa:
        print_kappa_table([(path.with_suffix(".log"), obj) for path, obj in scenes])
    return 0


def calibrated_config(config: str, truth: str, seed: int, work: Path) -> Path:
    """``config`` calibrated once against the jaw ``truth`` through the emulated bus
    (tools.bench_calibration.calibrate, the command's default plan and its ``--backlash
    auto``; the placements' offsets drawn from a generator of their own, seeded by ``seed``),
    written beside the scenes; prints what the calibration found against the truth."""
    from hand_driver.calibration_fit import pack_params
    from hand_driver.config import dump_config, load_config
    from tools.bench_calibration import calibrate

    nominal, real = load_config(config), load_config(truth)
    t0 = time.monotonic()
    result = calibrate(nominal, real, np.random.default_rng([seed, 1]), faces=10, corners=6)
    path = work / "calibrated.yaml"
    dump_config(result.config, path, source=config,
                header=f"calibrated by bench_explore against {truth} (seed {seed})")
    bands = tuple(k for k, (*_, fitted) in enumerate(result.loads) if fitted)
    err = pack_params(result.config, bands) - pack_params(real, bands)
    worst = {kind: max((abs(d) / e.se if e.se > 0 else math.inf for e, d in zip(result.estimates, err)
                        if e.kind == kind), default=0.0) for kind in ("zero_tick", "link_mm", "offset_mm", "backlash_deg")}
    print(f"calibrated {config} against {truth}: {result.n_readings} touches, {result.n_dropped} left out, "
          f"{time.monotonic() - t0:.0f} s; errors against the truth, worst in standard errors: "
          + ", ".join(f"{k} {v:.1f}" for k, v in worst.items())
          + "; zero ticks off by " + ", ".join(f"{d:+.2f}" for e, d in zip(result.estimates, err)
                                               if e.kind == "zero_tick") + f"; wrote {path}", flush=True)
    return path


def z_scores(obj: dict, rec: dict | None) -> list[float]:
    """Each shape parameter's error over its stated σ, for a right answer (none otherwise; a
    σ of 0 or unknown gives ±inf or is left out)."""
    if rec is None or rec["class"] != obj["class"]:
        return []
    sigma = rec.get("uncertainty") or {}
    out = []
    for k, v in obj["params"].items():
        s = sigma.get(k)
        if s is None:
            continue
        err = rec["params"][k] - v
        out.append(err / s if s > 0 else math.copysign(math.inf, err))
    return out


def print_sigma_table(scenes, results) -> None:
    """Per class: how well the right answers' stated σ's cover the truth (shape parameters)."""
    print("\nσ coverage of the right answers' shape parameters (z = error / stated σ)")
    print("| class | parameters | |z| ≤ 1.96 | |z| ≤ 3 | largest |z| |")
    print("|---|---|---|---|---|")
    every = []
    for cls in CLASSES:
        z = [v for (_, obj), res in zip(scenes, results) if obj["class"] == cls
             for v in z_scores(obj, res.get("recognition"))]
        every += z
        if z:
            a = np.abs(z)
            print(f"| {cls} | {a.size} | {100 * np.mean(a <= 1.96):.0f} % | {100 * np.mean(a <= 3.0):.0f} % | "
                  f"{a.max():.1f} |", flush=True)
    if every:
        a = np.abs(every)
        print(f"| all | {a.size} | {100 * np.mean(a <= 1.96):.0f} % | {100 * np.mean(a <= 3.0):.0f} % | "
              f"{a.max():.1f} |", flush=True)


def follow_advice(scenes, results, profile: str, jobs: int, config: str = DEFAULT_CONFIG,
                  truth: str | None = None) -> list[str | None]:
    """Every refused scene whose refusal names a move, moved so and explored once more (with
    ``--moved-as`` its first run's log: it rolls first where the move was for); per class: refusals, those naming a move, and the second runs' right / refused / wrong.
    Returns, per scene, the second run's verdict (:func:`verdict`; 'refused' also when the
    moved object could not be explored, such as one the move put across the opened jaw), or
    None where no move was named."""
    again, index = [], []
    for k, ((path, obj), res) in enumerate(zip(scenes, results)):
        rec = res.get("recognition")
        move = logged_move(path.with_suffix(".log")) if rec is not None and rec["class"] == "unclassified" else None
        if move is not None:
            moved = path.with_name(path.stem + "_moved.yaml")
            mapping = yaml.safe_load(path.read_text())
            mapping["object"] = moved_object(mapping["object"], move)
            moved.write_text(yaml.safe_dump(mapping))
            again.append((moved, obj, move, path.with_suffix(".log")))
            index.append(k)
    with ThreadPoolExecutor(jobs) as pool:
        second = list(pool.map(lambda s: run_scene(s[0], s[0].with_suffix(".log"), profile, config, truth,
                                                   s[3]), again))
    print("\n| object moved as advised | move | answer | right | parameter error | robot time |")
    print("|---|---|---|---|---|---|")
    for (path, obj, move, _), res in zip(again, second):
        rec = res.get("recognition")
        said = verdict(obj, rec)
        print(f"| {path.stem} | ({move['dx']:.0f}, {move['dy']:.0f}) mm, {move['turn_deg']:.0f}° | "
              f"{rec['class'] if rec else 'exit ' + str(res['rc'])} | {said} | "
              f"{param_error(obj, rec) if said == 'yes' else '—'} | "
              + (f"{res['robot_s']:.1f} s |" if res.get("robot_s") is not None else "— |"), flush=True)
    print("\n| class | refused | naming a move | moved: right | moved: refused | moved: wrong | "
          "moved: robot time median |")
    print("|---|---|---|---|---|---|---|")
    for cls in CLASSES:
        refused = sum(verdict(obj, res.get("recognition")) == "refused"
                      for (_, obj), res in zip(scenes, results) if obj["class"] == cls)
        mine = [res for (_, obj, _, _), res in zip(again, second) if obj["class"] == cls]
        said = [verdict(obj, res.get("recognition")) for (_, obj, _, _), res in zip(again, second)
                if obj["class"] == cls]
        robot = [res["robot_s"] for res in mine if res.get("robot_s") is not None]
        if refused:
            print(f"| {cls} | {refused} | {len(said)} | {said.count('yes')} | {said.count('refused')} | "
                  f"{said.count('**WRONG**')} | " + (f"{np.median(robot):.1f} s |" if robot else "— |"), flush=True)
    out: list[str | None] = [None] * len(scenes)
    for k, (_, obj, _, _), res in zip(index, again, second):
        out[k] = verdict(obj, res.get("recognition"))
    return out


def print_class_summary(scenes, results) -> None:
    """Per class: right / refused / wrong, median worst relative parameter error of the
    right answers, wrong answers above 5 % error, median robot time and touches used/tried."""
    print("\n| class | scenes | right | refused | wrong | median param error | robot time median (max) | "
          "touches used/tried (median) |")
    print("|---|---|---|---|---|---|---|---|")
    for cls in CLASSES:
        rows = [(obj, res) for (_, obj), res in zip(scenes, results) if obj["class"] == cls]
        if not rows:
            continue
        answers = [res.get("recognition") for _, res in rows]
        right = [(obj, a) for (obj, _), a in zip(rows, answers) if a is not None and a["class"] == cls]
        refused = sum(a is None or a["class"] == "unclassified" for a in answers)
        errs = [max((abs(a["params"][k] - v) / abs(v) for k, v in obj["params"].items()), default=0.0)
                for obj, a in right]
        robot = [res["robot_s"] for _, res in rows if res.get("robot_s") is not None]
        used = [res.get("used") or 0 for _, res in rows]
        tried = [res.get("tried") or 0 for _, res in rows]
        print(f"| {cls} | {len(rows)} | {len(right)} | {refused} | {len(rows) - len(right) - refused} | "
              + (f"{100 * float(np.median(errs)):.2f} % |" if errs else "— |")
              + (f" {np.median(robot):.1f} s ({max(robot):.1f} s) |" if robot else " — |")
              + f" {np.median(used):g}/{np.median(tried):g} |", flush=True)


def print_tell_table(scenes, results, config: str, followed: list[str | None] | None = None) -> None:
    """What the jaw ``config`` can tell, per class: right / refused / wrong, the median worst
    relative parameter error of the right answers, the median robot time, each refusal's
    kind (tactile_jaw.decide.refusal_kind: out of reach, needs finer angles, needs another
    move) and the median robot time per phase (``PHASES``). With ``followed`` (the second
    runs' verdicts, :func:`follow_advice`), right / right after the advised move / refused /
    wrong, each object counted once: a refusal whose advised move was answered right counts
    in the second column, a wrong answer after the move as wrong; the error and time
    columns are the first runs'."""
    from tactile_jaw.decide import REFUSAL_KINDS, refusal_kind

    head = "right / refused / wrong" if followed is None else "right / right after the advised move / refused / wrong"
    print(f"\nWhat the jaw {config} can tell (robot time per phase: medians, s)")
    print(f"| class | objects | {head} | median error | robot time median | "
          + " | ".join(f"refused: {k}" for k in REFUSAL_KINDS) + " | " + " | ".join(PHASE_HEADS) + " |")
    print("|---" * (5 + len(REFUSAL_KINDS) + len(PHASES)) + "|")
    for cls in CLASSES:
        picked = [k for k, (_, obj) in enumerate(scenes) if obj["class"] == cls]
        rows = [(scenes[k][1], results[k]) for k in picked]
        if not rows:
            continue
        said = [verdict(obj, res.get("recognition")) for obj, res in rows]
        counts = f"{said.count('yes')} / {said.count('refused')} / {said.count('**WRONG**')}"
        if followed is not None:
            second = [followed[k] if v == "refused" else None for k, v in zip(picked, said)]
            after, wrong_after = second.count("yes"), second.count("**WRONG**")
            counts = (f"{said.count('yes')} / {after} / {said.count('refused') - after - wrong_after} / "
                      f"{said.count('**WRONG**') + wrong_after}")
        errs = [max((abs(res["recognition"]["params"][k] - v) / abs(v) for k, v in obj["params"].items()), default=0.0)
                for (obj, res), v in zip(rows, said) if v == "yes"]
        kinds = [refusal_kind((res.get("recognition") or {}).get("reason") or res["stderr"][0], res.get("move"))
                 for (obj, res), v in zip(rows, said) if v == "refused"]
        robot = [res["robot_s"] for _, res in rows if res.get("robot_s") is not None]
        phases = [float(np.median([(res.get("time_s") or {}).get(p, 0.0) for _, res in rows])) for p in PHASES]
        print(f"| {cls} | {len(rows)} | {counts} | "
              + (f"{100 * float(np.median(errs)):.2f} % | " if errs else "— | ")
              + (f"{np.median(robot):.1f} s | " if robot else "— | ")
              + " | ".join(str(kinds.count(k)) for k in REFUSAL_KINDS) + " | "
              + " | ".join(f"{p:.1f}" for p in phases) + " |", flush=True)


def print_kappa_table(runs: list[tuple[Path, dict]]) -> None:
    """Per estimator: median |relative error| of κ and median |error| of κ_s, RMS z-score
    against the stated σ; and the final answers with and without the envelope's κ (right
    class, refusals, median worst relative parameter error)."""
    rows, answers = [], {"envelope": [], "samples": []}
    for log, obj in runs:
        if not log.exists():
            continue
        res = kappa_comparison(log, obj)
        rows += res["rows"]
        for way in answers:
            if way in res:
                rec = res[way]
                err = (max(abs(rec.params[k] - v) / abs(v) for k, v in obj["params"].items())
                       if rec.cls == obj["class"] else None)
                answers[way].append((rec.cls == obj["class"], rec.cls == "unclassified", err))
    print(f"\nκ at the contact, {len(rows)} usable touches of {len(runs)} scenes")
    print("| estimate | median abs rel err κ | median abs err κ_s (1/mm²) | RMS z κ | RMS z κ_s | |z| ≤ 3 κ | |z| ≤ 3 κ_s |")
    print("|---|---|---|---|---|---|---|")
    for way, name in (("env", "envelope fit d(ψ) + quantization covariance"), ("smp", "samples (recognizer.estimate)")):
        ek = np.array([(r[f"k_{way}"] - r["k_true"]) for r in rows])
        eks = np.array([(r[f"ks_{way}"] - r["ks_true"]) for r in rows])
        zk = ek / np.array([r[f"sk_{way}"] for r in rows])
        zks = eks / np.array([r[f"sks_{way}"] for r in rows])
        rel = np.abs(ek) / np.abs([r["k_true"] for r in rows])
        print(f"| {name} | {100 * np.median(rel):.2f} % | {np.median(np.abs(eks)):.2e} | "
              f"{np.sqrt(np.mean(zk**2)):.2f} | {np.sqrt(np.mean(zks**2)):.2f} | "
              f"{100 * np.mean(np.abs(zk) <= 3.0):.1f} % | {100 * np.mean(np.abs(zks) <= 3.0):.1f} % |")
    print("\n| recognizer input | right class | refused | median worst param error |")
    print("|---|---|---|---|")
    for way, name in (("envelope", "samples + envelope κ, κ_s, covariance (the jaw's)"),
                      ("samples", "samples only (κ estimated by the recognizer)")):
        a = answers[way]
        errs = [e for ok, _, e in a if ok]
        print(f"| {name} | {sum(ok for ok, _, _ in a)}/{len(a)} | {sum(r for _, r, _ in a)} | "
              f"{100 * float(np.median(errs)) if errs else float('nan'):.2f} % |")


if __name__ == "__main__":
    sys.exit(main())
