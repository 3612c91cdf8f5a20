"""``tactile explore``: touch the object with the jaw, log every reading, print the recognition."""

from __future__ import annotations

import json
import sys
import time
from contextlib import nullcontext
from dataclasses import dataclass
from functools import partial
from pathlib import Path
from typing import Any, Callable

HELP = "touches the object with the jaw on a serial port, logs joint readings, prints the recognition"

REPO = Path(__file__).resolve().parents[1]


def default_path(relative: str) -> str:
    """A default file: relative to the current directory if it is there, else to the repository."""
    return relative if Path(relative).exists() else str(REPO / relative)


def add_common_arguments(parser, *, scene_default: str | None) -> None:
    """Options shared by ``explore`` and ``demo``."""
    parser.add_argument("--scene", default=scene_default,
                        help="scene YAML (docs/formats.md): the classes that may be answered"
                             + (f" (default {scene_default})" if scene_default else ""))
    parser.add_argument("--profile", default="balanced",
                        help="speed/accuracy profile: fast, balanced (default), accurate (docs/estimation.md)")
    parser.add_argument("--log", metavar="L", help="write the run log (JSON Lines) to L; `tactile replay L` reads it")
    parser.add_argument("--json", action="store_true", help="print the recognition as JSON only (docs/formats.md)")
    parser.add_argument("--plot", metavar="PNG", help="write a plot of the pad lines, touches and recognized curve")
    parser.add_argument("--force", action="store_true",
                        help="overwrite an existing --log or --plot file (never a file the command reads)")


def check_outputs(args, log_path: str | None, reads) -> None:
    """Refuse, before the jaw moves, a --log or --plot that exists (without --force) or that
    is a file this command reads (tactile_common.files.check_output)."""
    from tactile_common.files import check_output

    if log_path is not None:
        check_output(log_path, force=args.force, reads=reads, flag="--log")
    if args.plot:
        check_output(args.plot, force=args.force, reads=[*reads, log_path], flag="--plot")


def add_arguments(parser) -> None:
    parser.add_argument("--config", default=None, help="jaw config YAML (default config/jaw.yaml)")
    parser.add_argument("--port", default=None, help="serial port of the servo bus (default: the config's bus.port)")
    add_common_arguments(parser, scene_default=None)


@dataclass
class Session:
    """One exploration's outcome, for printing."""

    exploration: Any
    recognition: dict[str, Any] | None
    settings: Any
    wall_time_s: float
    log_path: str | None


def read_yaml_mapping_located(path: str, what: str):
    """A YAML file that must be a mapping, and where its keys were written (YamlLines: its
    ``errors(path)`` adds the line to a format's refusal)."""
    from tactile_common.errors import InputError
    from tactile_common.yamlfile import read_yaml_located

    obj, lines = read_yaml_located(path, what)
    if not isinstance(obj, dict):
        raise InputError(f"{path}: line 1: {what} must be a YAML mapping")
    return obj, lines


def run_session(*, port: str, config, scene_mapping: dict | None, profile: str, log_path: str | None,
                force: bool, clock_factory: Callable[[], Any], bus_timeout_s: float, progress: Callable[[str], None]) -> Session:
    """Open the bus, explore, log everything; returns the :class:`Session`."""
    from hand_driver.bus import JointBus
    from hand_driver.config import config_to_mapping
    from hand_driver.log import RunLog
    from hand_driver.cycle import Jaw
    from tactile_jaw.explore import explore
    from tactile_jaw.choose import JawReach
    from tactile_jaw.pipeline import make_recognizer, workspace_reach
    from tactile_jaw.settings import NOISE_FROM_TOUCHES, ExploreSettings

    settings = ExploreSettings.from_profile(profile)
    recognize_touches = make_recognizer(scene_mapping, settings, reach=JawReach(config, settings))
    recognize_anywhere = partial(recognize_touches, reach=workspace_reach(config))
    t0 = time.monotonic()
    log = None
    if log_path is not None:
        log = RunLog(log_path).open(config=config_to_mapping(config), scene=scene_mapping, command=sys.argv,
                                    settings={**settings.to_json(), "noise": NOISE_FROM_TOUCHES}, force=force)
    with log if log is not None else nullcontext():
        with JointBus.for_config(config, port, timeout_s=bus_timeout_s,
                                 on_reading=log.reading if log is not None else None) as bus:
            bus.set_profile_raw(config.motion.profile_velocity, config.motion.profile_acceleration)
            if bus.current_sensing:
                bus.set_goal_current(config.motion.goal_current_ma)
            jaw = Jaw(bus, config, log, clock=clock_factory(), readings_logged_by_bus=log is not None)
            progress(f"exploring: up to {settings.touches} touches of {settings.samples_per_touch} samples over "
                     f"{settings.to_json()['roll_span_deg']:.0f} deg, profile {settings.profile}")
            exploration = explore(jaw, settings, recognize_touches, emit=log.write if log is not None else None,
                                  progress=progress, recognize_anywhere=recognize_anywhere)
        recognition = exploration.recognition.to_json() if exploration.recognition is not None else None
        if log is not None:
            log.write({"type": "result", "recognition": recognition, "robot_time_s": exploration.robot_time_s,
                       "touches_used": len(exploration.used),
                       "touches_tried": len(exploration.touches), "time_s": exploration.time_s})
    return Session(exploration, recognition, settings, time.monotonic() - t0, log_path)


def describe(recognition: dict[str, Any]) -> str:
    """One line for people: class, parameters and pose."""
    if recognition["class"] == "unclassified":
        return f"unclassified: {recognition['reason']}"
    params = " ".join(f"{k}={v:.3f}" for k, v in recognition["params"].items())
    p = recognition["pose"]
    return f"{recognition['class']} {params} | pose theta={p['theta']:.4f} rad x={p['x']:.2f} mm y={p['y']:.2f} mm"


def finish(session: Session, args, *, config, truth=None, extra_lines: list[str] = ()) -> int:
    """Print the session (JSON or for people), write the plot; exit status."""
    from tactile_common.errors import DeviceFault

    ex = session.exploration
    if session.recognition is None:
        raise DeviceFault(f"only {len(ex.used)} usable touches of {len(ex.touches)} tried after "
                          f"{len(ex.probes)} probes ({ex.robot_time_s:.1f} s robot time), too few to recognize "
                          f"(progress lines and the log's events say why)")
    if args.plot:
        from tools.plot import plot_exploration

        plot_exploration(args.plot, touches=ex.request["touches"],
                         pad_segments=[seg for felt in ex.touches for seg in felt.pad_segments()],
                         recognition=session.recognition, truth=truth,
                         workspace=(config.workspace.center_mm, config.workspace.radius_mm),
                         title=f"tactile {args.command}: {session.recognition['class']}")
    if args.json:
        sys.stdout.write(json.dumps(session.recognition, allow_nan=False) + "\n")
        return 0
    used = len(ex.used)
    lines = [f"recognized: {describe(session.recognition)}", *extra_lines,
             f"touches: {used} used of {len(ex.touches)} tried ({session.settings.samples_per_touch} samples each), "
             f"{ex.rounds} rounds; robot time {ex.robot_time_s:.1f} s (" + time_breakdown(ex.time_s)
             + f"); wall time {session.wall_time_s:.1f} s"]
    if session.log_path:
        lines.append(f"log: {session.log_path}")
    if args.plot:
        lines.append(f"plot: {args.plot}")
    sys.stdout.write("\n".join(lines) + "\n")
    return 0


def time_breakdown(time_s: dict[str, float]) -> str:
    """Where an exploration's robot time went, for people."""
    return (f"probes {time_s['probes']:.1f} s of which transits {time_s['probe_transits']:.1f} s, "
            f"touches {time_s['touches']:.1f} s of which transits {time_s['touch_transits']:.1f} s, "
            f"retreat {time_s['retreat']:.1f} s")


def progress_printer(quiet: bool = False) -> Callable[[str], None]:
    def say(msg: str) -> None:
        if not quiet:
            sys.stderr.write(f"  {msg}\n")
            sys.stderr.flush()
    return say


def run(args) -> int:
    from hand_driver.config import load_config
    from hand_driver.cycle import WallClock

    config = load_config(args.config or default_path("config/jaw.yaml"))
    log_path = args.log or default_log_path()
    check_outputs(args, log_path, [args.config or default_path("config/jaw.yaml"), args.scene])
    scene_mapping = None
    if args.scene:
        from recognizer.scene import load_scene

        scene_mapping, lines = read_yaml_mapping_located(args.scene, "scene")
        with lines.errors(args.scene):
            load_scene(scene_mapping, source=args.scene)  # validate before the jaw moves
    session = run_session(port=args.port or config.bus.port, config=config, scene_mapping=scene_mapping,
                          profile=args.profile, log_path=log_path, force=args.force,
                          clock_factory=WallClock, bus_timeout_s=config.bus.timeout_s,
                          progress=progress_printer())
    return finish(session, args, config=config)


def default_log_path() -> str:
    """runs/explore-YYYYmmdd-HHMMSS.jsonl in the current directory."""
    return str(Path("runs") / time.strftime("explore-%Y%m%d-%H%M%S.jsonl"))
