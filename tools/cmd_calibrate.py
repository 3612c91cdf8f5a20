"""``tactile calibrate``: fit zero ticks, link lengths and pad offsets (and, with
``--backlash``, each joint's backlash under the load each touch puts on it) from touches on a
known reference disk (hand_driver.calibration: the touches; calibration_fit: the fit), write
a new jaw config. Either family: zero ticks are in each joint's model's ticks."""

from __future__ import annotations

import json
import sys
from pathlib import Path

from tactile_common.errors import InputError
from tools.cmd_explore import add_time_scale_argument

HELP = "fit the jaw's zero ticks, link lengths and pad offsets from touches on a reference disk; write a new config"


def add_arguments(parser) -> None:
    parser.add_argument("--config", default="config/jaw.yaml", help="the jaw config to start from (never modified)")
    parser.add_argument("--port", action="append", required=True,
                        help="serial port; give it once (you move the disk between placements when asked) "
                             "or once per placement (one emulated bus per placement)")
    parser.add_argument("--reference", default="config/scenes/calibration.yaml",
                        help="scene whose object is the reference disk (class circle, known radius); its pose "
                             "is not used by the fit")
    parser.add_argument("--out", required=True, help="where to write the calibrated config")
    parser.add_argument("--place", action="append", metavar="X,Y",
                        help="expected disk centre (mm, hand frame) of one placement; repeat per placement "
                             "(default: 60,0 85,0 65,30 65,-30)")
    parser.add_argument("--faces", type=int, default=10, help="face touches per finger, IK branch and placement")
    parser.add_argument("--corners", type=int, default=6, help="touches of each pad end per finger, branch, placement")
    parser.add_argument("--backlash", choices=("auto", "on", "off"), default="auto",
                        help="model each touch's load direction on every joint and fit the backlash of every "
                             "joint the touches load both ways (zero_tick: under the joint's working load; a band "
                             "few touches load against the working load is held to the model's stated band ± "
                             "half); auto (default): on when a joint's model states a backlash (DYNAMIXEL-P "
                             "0.1 deg, XM430-W350 0.25 deg)")
    parser.add_argument("--max-se-ticks", type=float, default=0.5,
                        help="refuse if a zero_tick's standard error exceeds this many ticks (never below "
                             "0.005 deg of the joint's model)")
    parser.add_argument("--max-se-mm", type=float, default=0.05, help="refuse if a length's standard error exceeds this")
    parser.add_argument("--max-se-backlash-deg", type=float, default=0.01,
                        help="with --backlash: refuse if a band's standard error exceeds this (deg)")
    add_time_scale_argument(parser)
    parser.add_argument("--force", action="store_true", help="overwrite --out if it exists")
    parser.add_argument("--json", action="store_true", help="print the result as JSON")


def _placements(args, cfg, disk) -> list[tuple[float, float]]:
    from hand_driver.calibration import default_placements

    if not args.place:
        return default_placements(cfg, disk)
    out = []
    for text in args.place:
        try:
            x, y = (float(v) for v in text.split(","))
        except ValueError:
            raise InputError(f"--place {text!r}: expected X,Y in mm, e.g. 60,0") from None
        out.append((x, y))
    return out


def touch_placements(cfg, disk, places, ports, *, faces: int, corners: int, clock_for, say,
                     wait_for_user=None, bus_options: dict | None = None) -> tuple[list, list]:
    """Calibration readings from every placement of the reference disk, and the disk's
    centre as each placement located it. With one port for several placements the fingers
    are parked (opened outward) before each one and ``wait_for_user(k, guess)`` returns
    once the disk is fixed near ``guess``; with one port per placement each bus shows its
    own. ``clock_for(k)`` makes the Jaw's clock for placement k."""
    from hand_driver import calibration as cal
    from hand_driver.bus import JointBus
    from hand_driver.cycle import Jaw

    ask = len(ports) == 1 and len(places) > 1
    if ask and wait_for_user is None:
        raise ValueError("one port for several placements needs wait_for_user")
    readings, centres = [], []
    for k, guess in enumerate(places):
        port = ports[k] if len(ports) > 1 else ports[0]
        with JointBus.for_config(cfg, port, **(bus_options or {})) as bus:
            jaw = Jaw(bus, cfg, clock=clock_for(k))
            if ask:
                cal.park(jaw)
                wait_for_user(k, guess)
            got, center, skipped = cal.touch_reference(jaw, disk, guess, placement=k, faces=faces, corners=corners)
        say(f"placement {k + 1}: disk found at ({center[0]:.2f}, {center[1]:.2f}) mm, "
            f"{len(got)} touches, {len(skipped)} planned touches skipped")
        readings += got
        centres.append(center)
    return readings, centres


def run(args) -> int:
    from hand_driver.calibration_fit import CalibrationRefused, backlash_matters, fit
    from tools.cli import EXIT_REFUSED
    from hand_driver.config import dump_config, load_config
    from hand_driver.cycle import WallClock
    from recognizer.scene import load_scene
    from tactile_common.files import check_output
    from tools.cmd_explore import bus_time_scale

    src = Path(args.config)
    out = check_output(args.out, force=args.force, reads=[src, args.reference], flag="--out")
    cfg = load_config(src)
    scene = load_scene(args.reference)
    if scene.object is None or scene.object.cls != "circle":
        raise InputError(f"{args.reference}: object: the reference must be a disk (class circle) of known radius")
    places = _placements(args, cfg, scene.object)
    if len(args.port) not in (1, len(places)):
        raise InputError(f"--port given {len(args.port)} times for {len(places)} placements; give it once or "
                         f"once per placement")
    if args.faces < 2 or args.corners < 0:
        raise InputError("--faces must be ≥ 2 and --corners ≥ 0")
    tolerances = {"zero_tick": args.max_se_ticks, "link_mm": args.max_se_mm, "offset_mm": args.max_se_mm,
                  "backlash_deg": args.max_se_backlash_deg}

    def say(line: str) -> None:
        sys.stderr.write(line + "\n")
        sys.stderr.flush()

    def wait_for_user(k: int, guess) -> None:
        say(f"placement {k + 1}/{len(places)}: fingers parked; fix the disk near ({guess[0]:g}, {guess[1]:g}) mm "
            f"and press Enter")
        sys.stdin.readline()

    scales = {port: bus_time_scale(cfg, port, say, args.time_scale) for port in dict.fromkeys(args.port)}
    readings, _ = touch_placements(cfg, scene.object, places, args.port, faces=args.faces, corners=args.corners,
                                   clock_for=lambda k: WallClock(scales[args.port[k % len(args.port)]]), say=say,
                                   wait_for_user=wait_for_user)
    backlash = args.backlash == "on" or (args.backlash == "auto" and backlash_matters(cfg))
    try:
        result = fit(cfg, scene.object, readings, tolerances, backlash=backlash)
    except CalibrationRefused as exc:  # touched, but the touches do not determine a parameter
        if args.json:
            print(json.dumps({"refused": True, "reason": str(exc)}))
        sys.stderr.write(f"tactile calibrate: refused: {exc}\n")
        return EXIT_REFUSED
    dump_config(result.config, out, header=f"calibrated by tactile calibrate from {src} "
                                           f"({result.n_readings} touches, residual RMS "
                                           f"{result.rms_before_mm:.3f} -> {result.rms_after_mm:.4f} mm)",
                source=src)
    if args.json:
        print(json.dumps(result.to_json(), indent=2))
    else:
        print(f"touches used: {result.n_readings} ({result.n_reclassified} face touches found to be pad-end "
              f"contacts, {result.n_dropped} left out as unexplained); residual RMS before "
              f"{result.rms_before_mm:.3f} mm, after {result.rms_after_mm:.4f} mm (max {result.max_after_mm:.4f} mm)")
        for name, neg, pos, band in result.loads:
            print(f"{name}: loaded negatively by {neg}, positively by {pos} touches: " + (
                "backlash fitted, zero_tick is the reading at the link's zero under the working load" if band else
                f"loaded one way only: zero_tick is the offset under a {'negative' if neg else 'positive'} load"))
        print(f"{'parameter':32s} {'before':>10s} {'after':>10s} {'± se':>8s}")
        for e in result.estimates:
            print(f"{e.name:32s} {e.before:10.3f} {e.after:10.3f} {e.se:8.3f}")
        print(f"wrote {out}")
    return 0
