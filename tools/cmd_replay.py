"""``tactile replay LOG``: the recognition of a recorded run, without hardware.

The touches are rebuilt from the log's joint readings and touch boundaries with the
jaw config and settings of the log's header (tactile_jaw.pipeline.logged_run), then
recognized exactly as during the run. The log is verified first (hand_driver.log.read_log:
record numbers, hash chain, cross-checks): damage is "line N: ..." (exit 2); a log cut by a
crash replays up to its last whole record and says it was cut; a version 1 log says it
cannot be verified. ``--verify`` only checks.
"""

from __future__ import annotations

import json
import sys
from dataclasses import replace
from functools import partial

from tactile_common.errors import InputError
from tactile_common.files import atomic_write, check_output
from tools.cli import EXIT_RECOGNIZED, EXIT_REFUSED
from tools.cmd_explore import answer_lines, refusal

HELP = "recognizes from a recorded run log (tactile explore/demo --log), no hardware"


def add_arguments(parser) -> None:
    parser.add_argument("log", help="run log (JSON Lines) written by tactile explore or tactile demo --log")
    parser.add_argument("--json", action="store_true", help="print the recognition as JSON only (docs/formats.md)")
    parser.add_argument("--touches", metavar="FILE",
                        help="also write the rebuilt touches as a touches request (docs/formats.md; for tactile recognize)")
    parser.add_argument("--mcap", metavar="OUT",
                        help="also write the run as a ROS 2 bag (MCAP, CDR messages: docs/formats.md#ros-2-bag)")
    parser.add_argument("--force", action="store_true",
                        help="overwrite an existing --touches or --mcap file (never the log)")
    parser.add_argument("--verify", action="store_true",
                        help="only check the log (record numbers, hash chain, cross-checks) and say whether it is "
                             "whole, cut or cannot be verified; no recognition")


def run(args) -> int:
    from hand_driver.log import read_log
    from tools.ros_bag import require_ros

    if args.touches:
        check_output(args.touches, force=args.force, reads=[args.log], flag="--touches")
    if args.mcap:
        require_ros()
        check_output(args.mcap, force=args.force, reads=[args.log, args.touches], flag="--mcap")
    contents = read_log(args.log)
    if args.verify:
        sys.stdout.write(f"{args.log}: {contents.integrity()}\n")
        return 0
    caveat = contents.truncated or not contents.verified
    try:
        answer, lines = _replay(args, contents)
    except InputError as exc:
        if caveat:  # one line still: what went wrong, and that the log was cut or is unverified
            raise InputError(f"{exc}; {contents.integrity()}") from None
        raise
    if args.json:
        sys.stdout.write(json.dumps(answer, allow_nan=False) + "\n")
        if caveat:
            sys.stderr.write(f"tactile replay: {args.log}: {contents.integrity()}\n")
    else:
        sys.stdout.write("\n".join(lines) + "\n")
    return EXIT_REFUSED if answer["class"] == "unclassified" else EXIT_RECOGNIZED


def _replay(args, contents) -> tuple[dict, list[str]]:
    """Recognize from the log's contents (read and verified): the answer (a refusal with its
    advice when no class is answered) and the lines for people; writes ``--touches`` and
    ``--mcap``."""
    # here, not at the top: tactile --help imports every command module (tools.cli), and these
    # pull numpy and scipy in (3-4 s measured on the shared 2-core machine at load 15)
    from hand_driver.config import states_calibration
    from tactile_jaw.choose import JawReach, last_stop
    from tactile_jaw.decide import final_answer, noted
    from tactile_jaw.felt_before import FeltBefore, not_a_line
    from tactile_jaw.flat import face_line, is_flat
    from tactile_jaw.pipeline import curve_refusal, feel, logged_run, make_recognizer, stated_noise, too_few_clear, \
        workspace_reach
    from tactile_jaw.separation import jaw_ticks_per_rev
    from tactile_jaw.settings import ExploreSettings
    from tools.ros_bag import write_bag

    header = contents.header
    config = contents.jaw_config()
    try:
        settings = ExploreSettings.from_json(header.get("settings") or {})
    except (KeyError, TypeError, ValueError):
        raise InputError(f"{args.log}: line 1: header settings lack touches/samples_per_touch/roll_span_deg") from None
    run = logged_run(config, contents, settings)  # the exploration's own checks, in its order
    usable, curve, touches = run.usable, run.curve, run.touches
    logged_noise = header["settings"].get("noise")
    fixed_noise = logged_noise if isinstance(logged_noise, dict) else None  # an older run's fixed noise
    recognize_touches = make_recognizer(header.get("scene"), settings, fixed_noise,
                                        reach=JawReach(config, settings)) if touches else None
    if args.touches:
        # the run's recognizer options (its profile's) travel with the touches: tactile recognize
        # then answers with the same settings as this replay; pooled once, by the recognizer
        # that answers below (tactile_jaw.pipeline.make_recognizer)
        request = {"scene": header.get("scene"),
                   "touches": [t.to_json() for t in (recognize_touches.pooled(touches) if touches else [])],
                   "noise": (fixed_noise if fixed_noise and not all(is_flat(t) for t in touches)
                             else stated_noise(touches).to_json() if touches else None),
                   "options": {**settings.recognize, "reach": workspace_reach(config).to_json()}}
        atomic_write(args.touches, json.dumps(request), flag="--touches")
    stop = last_stop(contents.events)
    recognition, too_few = None, None
    if not touches and curve is not None:  # the exploration's flat phase stopped there (tactile_jaw.flat_phase)
        recognition = curve_refusal(curve)
    elif not touches:
        too_few = f"no usable touch in the log ({len(contents.touches)} touches logged): too few to recognize"
    else:
        try:
            recognition = final_answer(recognize_touches, touches, settings,
                                       stop.get("message") if stop is not None else None, jaw_ticks_per_rev(config),
                                       partial(feel, config))
        except InputError as exc:  # fewer usable touches than any class needs: the exploration refused
            recognition = too_few_clear(touches, len(usable), exc) if len(touches) < len(usable) else None
            too_few = str(exc)
    if recognition is not None:  # a line after a move whose run before felt curvature: refused as the run did
        recognition = not_a_line(face_line(recognition, touches), FeltBefore.from_events(contents.events))
    calibrated = states_calibration(config)  # every answer carries the jaw's calibration note, as the exploration's
    too_few = noted(too_few, calibrated) if too_few is not None else None
    if recognition is not None:
        recognition = replace(recognition, reason=noted(recognition.reason, calibrated)).to_json()
    answer = recognition
    if recognition is None or recognition["class"] == "unclassified":
        answer = refusal(recognition, too_few, stop, config)
    if args.mcap:
        write_bag(args.mcap, contents, answer)
    faults = [e for e in contents.events if e.get("kind") == "fault"]
    lines = [*answer_lines(answer),
             f"from {len(touches)} usable touches of {len(contents.touches)} in {len(contents.readings)} readings",
             f"log: {contents.integrity()}"]
    if faults:
        lines.append(f"the run ended with a fault: {faults[-1]['message']}")
    if args.mcap:
        lines.append(f"mcap: {args.mcap}")
    return answer, lines
