"""``tactile explore``: touch the object with the jaw, log every reading, print the recognition."""

from __future__ import annotations

import json
import math
import sys
import tempfile
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
    parser.add_argument("--mcap", metavar="OUT",
                        help="also write the run as a ROS 2 bag (MCAP, CDR messages), record by record as the run "
                             "goes (docs/formats.md#ros-2-bag)")
    parser.add_argument("--json", action="store_true", help="print the recognition as JSON only (docs/formats.md)")
    parser.add_argument("--plot", metavar="PNG", help="write a plot of the pad lines, touches and recognized curve")
    parser.add_argument("--force", action="store_true",
                        help="overwrite an existing --log, --mcap or --plot file (never a file the command reads)")
    parser.add_argument("--moved-as", metavar="LOG",
                        help="the run log of the refusal whose move the object was moved by: this run rolls first "
                             "where that move was for (docs/exploration.md#following-the-advice)")


def moved_for(path: str | None) -> list[dict]:
    """Where the move of ``--moved-as``'s refusal was for (its stop event's ``move['places']``,
    tactile_jaw.choose.moved_places); empty without one. A log whose refusal named no move is
    refused: the object was not moved as it said."""
    if path is None:
        return []
    from hand_driver.log import read_log
    from tactile_common.errors import InputError
    from tactile_jaw.choose import last_stop

    stop = last_stop(read_log(path).events)
    if stop is None or stop.get("move") is None:
        raise InputError(f"{path}: --moved-as: the run's refusal named no move of the object")
    return list(stop["move"].get("places") or [])


def felt_before_move(path: str | None):
    """What the run of ``--moved-as``'s log felt of the object's curvature
    (tactile_jaw.felt_before.felt_in: its touches rebuilt with the jaw config and settings its
    header holds); None without one. A log whose header lacks them is refused (InputError)."""
    if path is None:
        return None
    from hand_driver.log import read_log
    from tactile_common.errors import InputError
    from tactile_jaw.felt_before import felt_in
    from tactile_jaw.settings import ExploreSettings

    contents = read_log(path)
    try:
        settings = ExploreSettings.from_json(contents.header.get("settings") or {})
    except (KeyError, TypeError, ValueError):
        raise InputError(f"{path}: --moved-as: line 1: header settings lack touches/samples_per_touch/roll_span_deg, "
                         f"so what the run felt cannot be rebuilt") from None
    return felt_in(contents.jaw_config(), contents, settings)


def check_outputs(args, log_path: str | None, reads) -> None:
    """Refuse, before the jaw moves, a --log, --mcap or --plot that exists (without --force) or that
    is a file this command reads (tactile_common.files.check_output)."""
    from tactile_common.files import check_output

    if log_path is not None:
        check_output(log_path, force=args.force, reads=reads, flag="--log")
    if args.mcap:
        from tools.ros_bag import require_ros

        require_ros()
        check_output(args.mcap, force=args.force, reads=[*reads, log_path], flag="--mcap")
    if args.plot:
        check_output(args.plot, force=args.force, reads=[*reads, log_path, args.mcap], flag="--plot")


def add_arguments(parser) -> None:
    parser.add_argument("--config", default=None, help="jaw config YAML (default config/jaw.yaml)")
    parser.add_argument("--port", default=None, help="serial port of the servo bus (default: the config's bus.port)")
    add_time_scale_argument(parser)
    add_common_arguments(parser, scene_default=None)


def add_time_scale_argument(parser) -> None:
    """``--time-scale`` of the commands that run on the wall clock (explore, calibrate)."""
    parser.add_argument("--time-scale", type=float, default=None, metavar="X",
                        help="servo seconds per wall-clock second (an emulator's tactile sim --time-scale); "
                             "default: measured from the servos' Realtime Tick, and a given X must agree with it")


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
                force: bool, clock_factory: Callable[[], Any], bus_timeout_s: float, progress: Callable[[str], None],
                mcap_path: str | None = None, moved: list[dict] | None = None, before=None) -> Session:
    """Open the bus, explore, log everything (and with ``mcap_path`` write the bag as the
    run goes, from the log's records: without ``log_path`` the log is a scratch file,
    tools.ros_bag); returns the :class:`Session`. ``clock_factory`` is called once the log
    is open, before the bus is: it may talk to the bus (:func:`bus_time_scale`). ``moved``:
    where the move the object was moved by was for (:func:`moved_for`); ``before``: what the run
    before that move felt (:func:`felt_before_move`)."""
    from tactile_jaw.settings import ExploreSettings

    settings = ExploreSettings.from_profile(profile)
    t0 = time.monotonic()
    if mcap_path is not None and log_path is None:
        with tempfile.TemporaryDirectory(prefix="tactile-") as scratch:
            return _run_session(port, config, scene_mapping, settings, str(Path(scratch) / "run.jsonl"), None,
                                force, clock_factory, bus_timeout_s, progress, mcap_path, t0, moved or [], before)
    return _run_session(port, config, scene_mapping, settings, log_path, log_path, force, clock_factory,
                        bus_timeout_s, progress, mcap_path, t0, moved or [], before)


def _run_session(port, config, scene_mapping, settings, log_path, shown_log, force, clock_factory, bus_timeout_s,
                 progress, mcap_path, t0, moved, before) -> Session:
    """:func:`run_session` once the log's path is known (``shown_log``: the one to print, or None)."""
    from hand_driver.bus import JointBus
    from hand_driver.config import config_to_mapping
    from hand_driver.log import RunLog
    from hand_driver.cycle import Jaw
    from tactile_jaw.explore import explore
    from tactile_jaw.choose import JawReach
    from tactile_jaw.pipeline import make_recognizer, workspace_reach
    from tactile_jaw.settings import NOISE_FROM_TOUCHES

    recognize_touches = make_recognizer(scene_mapping, settings, reach=JawReach(config, settings))
    recognize_anywhere = partial(recognize_touches, reach=workspace_reach(config))
    log = None
    if log_path is not None:
        recorded = config_to_mapping(config)
        recorded["bus"] = {**recorded["bus"], "port": port}  # the port this run used, --port's if given
        if mcap_path is not None:
            from tools.ros_bag import BaggedLog

            log = BaggedLog(log_path, mcap_path, force=force)
        else:
            log = RunLog(log_path)
        log.open(config=recorded, scene=scene_mapping, command=sys.argv,
                 settings={**settings.to_json(), "noise": NOISE_FROM_TOUCHES}, force=force)
    with log if log is not None else nullcontext():
        clock = clock_factory()
        if log is not None and getattr(clock, "time_scale", 1.0) != 1.0:
            log.event("clock", f"robot time runs {clock.time_scale:.3f}x the wall clock (the servos' Realtime Tick)",
                      time_scale=clock.time_scale)
        with JointBus.for_config(config, port, timeout_s=bus_timeout_s,
                                 on_reading=log.reading if log is not None else None) as bus:
            bus.set_profile_raw(config.motion.profile_velocity, config.motion.profile_acceleration)
            if bus.current_sensing:
                bus.set_goal_current(config.motion.goal_current_ma)
            jaw = Jaw(bus, config, log, clock=clock, readings_logged_by_bus=log is not None)
            progress(f"exploring: up to {settings.touches} touches of {settings.samples_per_touch} samples over "
                     f"{settings.to_json()['roll_span_deg']:.0f} deg, profile {settings.profile}")
            exploration = explore(jaw, settings, recognize_touches, emit=log.write if log is not None else None,
                                  progress=progress, recognize_anywhere=recognize_anywhere, moved_for=moved,
                                  felt_before=before)
        recognition = exploration.recognition.to_json() if exploration.recognition is not None else None
        if log is not None:
            log.write({"type": "result", "recognition": recognition, "robot_time_s": exploration.robot_time_s,
                       "touches_used": len(exploration.used),
                       "touches_tried": len(exploration.touches), "time_s": exploration.time_s})
    return Session(exploration, recognition, settings, time.monotonic() - t0, shown_log)


def describe(recognition: dict[str, Any], anchor: tuple[float, float] | None = None) -> str:
    """One line for people: class, parameters and pose, or the refusal's reason. A line's
    pose is printed as its point nearest ``anchor`` (a scene's pose: the two then read in
    one convention), else as the answer's own, the foot of the perpendicular from the hand
    origin (docs/formats.md)."""
    if recognition["class"] == "unclassified":
        return f"unclassified: {recognition['reason']}"
    params = " ".join(f"{k}={v:.3f}" for k, v in recognition["params"].items())
    p = recognition["pose"]
    x, y, note = p["x"], p["y"], ""
    if recognition["class"] == "line":
        ux, uy = math.cos(p["theta"]), math.sin(p["theta"])
        ax, ay = anchor if anchor is not None else (0.0, 0.0)
        along = (ax - x) * ux + (ay - y) * uy
        x, y = x + along * ux, y + along * uy
        note = (" (its point nearest the scene's pose)" if anchor is not None
                else " (the foot of the perpendicular from the hand origin)")
    head = f"{recognition['class']} {params}" if params else recognition["class"]
    return f"{head} | pose theta={p['theta']:.4f} rad x={x:.2f} mm y={y:.2f} mm{note}"


def too_few_reason(used: int, tried: int) -> str:
    """The refusal's reason when too few touches were usable to ask the recognizer."""
    return (f"only {used} usable touches of {tried} tried, too few to recognize (the progress lines and the "
            f"log's events say why)")


def refusal(recognition: dict[str, Any] | None, reason: str | None, stop: dict | None, config) -> dict[str, Any]:
    """The answer of an exploration that ended without a class: the recognizer's
    ``unclassified`` answer (or, when too few touches were usable to ask it, one with
    ``reason``), plus ``advice``, what a person can do, and ``move``, the object move the
    stop named (the log's ``stopped_early``/``budget_spent`` event, tactile_jaw.choose), or null."""
    answer = dict(recognition) if recognition is not None else {
        "class": "unclassified", "params": {}, "pose": None, "contacts": [], "invariants": {}, "uncertainty": {},
        "reason": reason, "next_touch": None, "ranking": []}
    nt = answer.get("next_touch")
    ws = config.workspace
    if stop is not None:
        advice = stop["message"]
    elif recognition is None:
        advice = (f"place the object in the workspace disk (centre ({ws.center_mm[0]:g}, {ws.center_mm[1]:g}) mm, "
                  f"radius {ws.radius_mm:g} mm: the jaw config's workspace) with a curved part facing a finger; "
                  f"the progress lines and the log's touch_rejected events say why each touch was not used")
    elif nt is not None:
        advice = (f"touch again near ({nt['x']:.1f}, {nt['y']:.1f}) mm, the boundary's tangent at "
                  f"{math.degrees(nt['phi']):.0f} deg: {nt['why']}")
    else:
        advice = ("no class of the scene fits the touches: the object may be of a class the scene leaves out "
                  "(--scene), or the jaw may need calibrating (tactile calibrate)")
    answer["advice"] = advice
    answer["move"] = stop.get("move") if stop is not None else None
    return answer


def finish(session: Session, args, *, config, truth=None, extra_lines: list[str] = ()) -> int:
    """Print the session (JSON or for people), write the plot; the exit status: 0
    recognized, 3 explored but refused (tools.cli)."""
    from tools.cli import EXIT_RECOGNIZED, EXIT_REFUSED

    ex = session.exploration
    answer = session.recognition
    if answer is None or answer["class"] == "unclassified":
        reason = None if answer is not None else too_few_reason(len(ex.used), len(ex.touches))
        stop = ex.stopped.event("stopped") if ex.stopped is not None else None
        answer = refusal(answer, reason, stop, config)
    if args.plot and session.recognition is not None:
        from tools.plot import plot_exploration

        plot_exploration(args.plot, touches=ex.request["touches"],
                         pad_segments=[seg for felt in ex.touches for seg in felt.pad_segments()],
                         recognition=session.recognition, truth=truth,
                         workspace=(config.workspace.center_mm, config.workspace.radius_mm),
                         title=f"tactile {args.command}: {session.recognition['class']}")
    status = EXIT_REFUSED if answer["class"] == "unclassified" else EXIT_RECOGNIZED
    if args.json:
        sys.stdout.write(json.dumps(answer, allow_nan=False) + "\n")
        return status
    used = len(ex.used)
    anchor = (truth.pose.x, truth.pose.y) if truth is not None else None
    lines = [*answer_lines(answer, anchor), *extra_lines,
             f"touches: {used} used of {len(ex.touches)} tried ({session.settings.samples_per_touch} samples each), "
             f"{ex.rounds} rounds; robot time {ex.robot_time_s:.1f} s (" + time_breakdown(ex.time_s)
             + f"); wall time {session.wall_time_s:.1f} s"]
    if session.log_path:
        lines.append(f"log: {session.log_path}")
    if getattr(args, "mcap", None):
        lines.append(f"mcap: {args.mcap}")
    if args.plot and session.recognition is not None:
        lines.append(f"plot: {args.plot}")
    sys.stdout.write("\n".join(lines) + "\n")
    return status


def answer_lines(answer: dict[str, Any], anchor: tuple[float, float] | None = None) -> list[str]:
    """The answer's first lines for people: ``recognized: ...`` (``anchor``: see
    :func:`describe`) and its ``note:`` when the answer states one (a close rival, a touch
    left out), or ``refused: reason`` and ``advice: ...``."""
    if answer["class"] != "unclassified":
        note = [f"note:       {answer['reason']}"] if answer.get("reason") else []
        return [f"recognized: {describe(answer, anchor)}", *note]
    return [f"refused:    {answer['reason']}", f"advice:     {answer['advice']}"]


def time_breakdown(time_s: dict[str, float]) -> str:
    """Where an exploration's robot time went, for people."""
    return (f"probes {time_s['probes']:.1f} s of which transits {time_s['probe_transits']:.1f} s, "
            f"touches {time_s['touches']:.1f} s of which transits {time_s['touch_transits']:.1f} s, "
            + (f"flat presses {time_s['presses']:.1f} s of which transits {time_s['press_transits']:.1f} s, "
               if time_s.get("presses") else "")
            + f"retreat {time_s['retreat']:.1f} s")


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
    check_outputs(args, log_path, [args.config or default_path("config/jaw.yaml"), args.scene, args.moved_as])
    moved, before = moved_for(args.moved_as), felt_before_move(args.moved_as)
    scene_mapping = None
    if args.scene:
        from recognizer.scene import load_scene

        scene_mapping, lines = read_yaml_mapping_located(args.scene, "scene")
        with lines.errors(args.scene):
            load_scene(scene_mapping, source=args.scene)  # validate before the jaw moves
    port = args.port or config.bus.port
    say = progress_printer()
    session = run_session(port=port, config=config, scene_mapping=scene_mapping,
                          profile=args.profile, log_path=log_path, force=args.force,
                          clock_factory=lambda: WallClock(bus_time_scale(config, port, say, args.time_scale)),
                          bus_timeout_s=config.bus.timeout_s, progress=say, mcap_path=args.mcap, moved=moved,
                          before=before)
    return finish(session, args, config=config)


#: a bus clock within this fraction of the wall clock's rate is real time (a servo's crystal
#: and CLOCK_WINDOW_S's measurement are good to about 1 %)
REAL_TIME_TOLERANCE = 0.1


def bus_time_scale(config, port: str, say: Callable[[str], None], given: float | None = None) -> float:
    """The robot clock's time scale, learned from the bus (hand_driver.bus.clock_rate): 1
    for real servos, an emulator's ``tactile sim --time-scale`` otherwise, so that robot time,
    motion cycles and waits follow the servos' own clock. ``given`` (``--time-scale``) must
    agree with the measurement: a mismatch is refused here, before anything moves, instead
    of looking like a bad object later."""
    from hand_driver.bus import clock_rate
    from tactile_common.errors import InputError

    if given is not None and not (math.isfinite(given) and given > 0):
        raise InputError(f"--time-scale {given}: must be a number > 0")
    measured = clock_rate(port, config.bus.baudrate, config.joints[0])
    if measured is None:  # a model without Realtime Tick: trust the option, else real time
        return given or 1.0
    if not measured.rate > 0.0:
        raise InputError(f"the bus on {port} has a clock that does not advance ({measured.describe()}): "
                         f"restart the emulator (tactile sim) or power-cycle the servos")
    learned = 1.0 if abs(measured.rate - 1.0) <= REAL_TIME_TOLERANCE else measured.rate
    if given is not None and abs(measured.rate / given - 1.0) > REAL_TIME_TOLERANCE:
        raise InputError(f"--time-scale {given:g} but the bus on {port} runs {measured.rate:.2f}x the wall clock "
                         f"({measured.describe()}): pass --time-scale {learned:.3g} or leave the option out")
    if given is not None:
        return given
    if learned != 1.0:
        say(f"the bus on {port} runs {measured.rate:.2f}x the wall clock ({measured.describe()}): "
            f"robot time follows it")
    return learned


def default_log_path() -> str:
    """runs/explore-YYYYmmdd-HHMMSS.jsonl in the current directory."""
    return str(Path("runs") / time.strftime("explore-%Y%m%d-%H%M%S.jsonl"))
