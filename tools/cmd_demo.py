"""``tactile demo``: the emulated servo bus with the scene's object, explored by the jaw.

The emulator (hand_driver.sim.server.EmulatedBus) runs in this process on a
pseudo-terminal that the Dynamixel SDK opens like a USB adapter; the exploration talks
Protocol 2.0 to it exactly as to a real jaw. The emulator runs in lockstep with the
exploration's cycles (hand_driver.cycle.LockstepClock): robot time is its simulated
time, the same on any host, and wall time is only the computation. The emulated jaw starts
opened (tactile_jaw.plan.open_pose: every pad outside the workspace disk); an object
that overlaps those pads is refused (exit 2).
"""

from __future__ import annotations

import math
import sys

from tools.cmd_explore import (
    add_common_arguments,
    check_outputs,
    default_path,
    felt_before_move,
    finish,
    moved_for,
    progress_printer,
    read_yaml_mapping_located,
    run_session,
)

HELP = "explores a scene's object on an emulated servo bus (Protocol 2.0 on a pty) and prints the recognition"
#: the emulated bus answers in lockstep, so only a stalled host delays it this long
EMULATED_BUS_TIMEOUT_S = 1.0


def add_arguments(parser) -> None:
    parser.add_argument("--config", default=None, help="jaw config YAML (default config/jaw.yaml)")
    parser.add_argument("--truth-config", default=None,
                        help="jaw config the emulated jaw really has (default: the same as --config)")
    add_common_arguments(parser, scene_default="config/scenes/default.yaml")


def truth_lines(recognition: dict, obj) -> list[str]:
    """The true object and the relative parameter error, when the classes agree."""
    params = " ".join(f"{k}={v:.3f}" for k, v in obj.params.items())
    p = obj.pose
    head = f"{obj.cls} {params}" if params else obj.cls
    lines = [f"true:       {head} | pose theta={p.theta:.4f} rad x={p.x:.2f} mm y={p.y:.2f} mm"]
    if recognition["class"] == "unclassified":
        lines.append(f"error:      no answer to compare: refused (the truth is {obj.cls})")
        return lines
    if recognition["class"] != obj.cls:
        lines.append(f"error:      wrong class ({recognition['class']} for {obj.cls})")
        return lines
    errs = [f"{k} {100.0 * (recognition['params'][k] - v) / abs(v):+.2f} %" for k, v in obj.params.items()]
    r = recognition["pose"]
    if obj.cls == "line":
        lines.append(f"error:      {line_pose_error(r, obj)}")
        return lines
    lines.append(f"error:      {', '.join(errs) or 'no parameters'}; pose offset "
                 f"{math.hypot(r['x'] - p.x, r['y'] - p.y):.2f} mm")
    return lines


def line_pose_error(pose: dict, obj) -> str:
    """How far a line answer (canonical pose: the foot of the perpendicular from the
    origin, θ the direction with the solid on the right) lies from the object's nearest
    straight edge: its line, or a closing segment of the block (each one a line; the jaw
    recognizes one face, docs/exploration.md#lines-flat-presses)."""
    xs, ys = obj.pose.apply(*obj.corners().T)  # P(t1), closure..., P(t0): the solid on the right
    corners = [(float(x), float(y)) for x, y in zip(xs, ys)]
    edges = [("the line", corners[-1], corners[0])]
    edges += [(f"closing segment {k + 1}", corners[k], corners[k + 1]) for k in range(len(corners) - 1)]
    best = None
    for name, (ax, ay), (bx, by) in edges:
        theta = math.atan2(by - ay, bx - ax)
        ux, uy = math.cos(theta), math.sin(theta)
        along = ax * ux + ay * uy
        turn = math.remainder(pose["theta"] - theta, 2 * math.pi)
        offset = math.hypot(pose["x"] - (ax - along * ux), pose["y"] - (ay - along * uy))
        if best is None or offset + 100.0 * abs(turn) < best[0]:
            best = (offset + 100.0 * abs(turn), name, offset, turn)
    _, name, offset, turn = best
    return f"no parameters; pose offset {offset:.2f} mm, angle {1000.0 * turn:+.1f} mrad from {name}"


def run(args) -> int:
    import numpy as np

    from hand_driver import kinematics as kin
    from hand_driver.config import load_config
    from hand_driver.cycle import LockstepClock
    from hand_driver.sim.server import EmulatedBus
    from tactile_common.errors import InputError
    from recognizer.scene import load_scene
    from tactile_jaw.plan import check_in_workspace, open_pose

    scene_path = default_path(args.scene)
    config_path = args.config or default_path("config/jaw.yaml")
    check_outputs(args, args.log, [config_path, args.truth_config, scene_path, args.moved_as])
    moved, before = moved_for(args.moved_as), felt_before_move(args.moved_as)
    scene_mapping, lines = read_yaml_mapping_located(scene_path, "scene")
    config = load_config(config_path)
    with lines.errors(scene_path):
        scene = load_scene(scene_mapping, source=scene_path)
        if scene.object is None:
            raise InputError(f"{scene_path}: object: missing: the scene has no object for the emulator to show")
        check_in_workspace(scene.object, config, scene_path)
    truth = load_config(args.truth_config) if args.truth_config else None
    say = progress_printer()
    sys.setswitchinterval(5e-4)  # the emulator thread answers sooner while the SDK polls
    say(f"emulated bus: {scene.object.cls} {scene.object.params} in scene {scene.name}")
    q_open = open_pose(config)
    ticks = np.rint(kin.angles_to_ticks(config.joints, q_open)).astype(int)
    with EmulatedBus(config, scene, truth_config=truth, time_scale=0.0, initial_ticks=ticks.tolist()) as sim:
        if sim.world is not None and sim.world.penetrates(q_open):
            raise InputError(f"{scene_path}: the object overlaps the opened jaw's pads (each on the workspace "
                             f"disk's edge, config 'workspace'): place it clear of them")
        session = run_session(port=sim.port, config=config, scene_mapping=scene_mapping, profile=args.profile,
                              log_path=args.log, force=args.force, clock_factory=lambda: LockstepClock(sim),
                              bus_timeout_s=EMULATED_BUS_TIMEOUT_S, progress=say, mcap_path=args.mcap, moved=moved,
                              before=before)
    extra = truth_lines(session.recognition or {"class": "unclassified"}, scene.object)
    return finish(session, args, config=config, truth=scene.object, extra_lines=extra)
