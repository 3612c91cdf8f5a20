"""``tactile sim``: run the emulated servo bus until SIGINT or SIGTERM."""

from __future__ import annotations

HELP = "run the emulated Dynamixel bus (Protocol 2.0 on a pseudo-terminal) with the scene's object; prints its port"


def add_arguments(parser) -> None:
    parser.add_argument("--scene", default="config/scenes/default.yaml",
                        help="scene whose object the fingers touch (default: %(default)s)")
    parser.add_argument("--config", default="config/jaw.yaml", help="jaw config: servo ids and models (default: %(default)s)")
    parser.add_argument("--truth-config", default=None,
                        help="jaw config the emulated hardware really has (zero ticks, links); default: --config")
    parser.add_argument("--place", default=None, metavar="X,Y[,THETA_DEG]",
                        help="put the scene's object at (X, Y) mm in the hand frame (turned to THETA_DEG, else "
                             "as the scene turns it) instead of the scene's pose: e.g. one `tactile sim --scene "
                             "config/scenes/calibration.yaml --place X,Y` per `tactile calibrate --place X,Y`")
    parser.add_argument("--time-scale", type=float, default=1.0,
                        help="simulated seconds per wall-clock second (default: %(default)s)")


def placed(obj, text: str):
    """``obj`` (a SceneObject) at the pose ``--place`` gives: "X,Y" (mm, its turn kept) or
    "X,Y,THETA_DEG"."""
    import dataclasses
    import math

    from recognizer.curves import Pose
    from tactile_common.errors import InputError

    try:
        values = [float(v) for v in text.split(",")]
    except ValueError:
        values = []
    if len(values) not in (2, 3) or not all(math.isfinite(v) for v in values):
        raise InputError(f"--place {text!r}: expected X,Y or X,Y,THETA_DEG (mm, mm, deg), e.g. 85,0")
    theta = math.radians(values[2]) if len(values) == 3 else obj.pose.theta
    return dataclasses.replace(obj, pose=Pose(theta, values[0], values[1]))


def run(args) -> int:
    import dataclasses
    import signal
    import sys
    import threading

    from hand_driver.config import load_config
    from hand_driver.sim.server import EmulatedBus
    from tactile_common.errors import InputError
    from recognizer.scene import load_scene

    if not args.time_scale > 0:
        raise InputError(f"--time-scale: {args.time_scale} must be > 0")
    from tactile_jaw.plan import check_in_workspace
    from tools.cmd_explore import read_yaml_mapping_located

    config = load_config(args.config)
    truth = load_config(args.truth_config) if args.truth_config else None
    scene_mapping, lines = read_yaml_mapping_located(args.scene, "scene")
    with lines.errors(args.scene):
        scene = load_scene(scene_mapping, source=args.scene)
    if args.place is not None:
        if scene.object is None:
            raise InputError(f"--place: the scene {args.scene} has no object to place")
        scene = dataclasses.replace(scene, object=placed(scene.object, args.place))
    with lines.errors(args.scene):
        if scene.object is not None:
            check_in_workspace(scene.object, config, args.scene)  # before the emulator serves a jaw
    done = threading.Event()
    old = {s: signal.signal(s, lambda *_: done.set()) for s in (signal.SIGINT, signal.SIGTERM)}
    try:
        with EmulatedBus(config, scene=scene, truth_config=truth, time_scale=args.time_scale,
                         baudrate=config.bus.baudrate) as bus:
            sys.stdout.write(bus.port + "\n")
            sys.stdout.flush()
            while not done.wait(0.2):
                pass
    finally:
        for s, h in old.items():
            signal.signal(s, h)
    return 0
