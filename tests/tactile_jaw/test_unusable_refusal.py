"""An exploration with no usable touch ends refused with a reason and what would help
(tactile_jaw.flat_phase.unusable_refusal): P semicubical 134 of bench_explore --finite 20
--anywhere --seed 227 ended with no recognition, no reason and no move."""

from hand_driver.flat_press import FlatResult
from hand_driver.motion import TouchResult
from tactile_jaw.choose import Stop
from tactile_jaw.decide import refusal_kind
from tactile_jaw.flat_phase import unusable_refusal
from tactile_jaw.pipeline import FeltTouch
from tactile_jaw.rounds import Exploration


def _felt(touch, corner=None) -> FeltTouch:
    return FeltTouch(touch, None, None, None, "not usable", None, corner=corner)


def _roll(k: int, finger: str, corner) -> FeltTouch:
    return _felt(TouchResult(finger, k, 0.0, [object()] * 9, outcome="ok"), corner)


def test_corners_named_and_why_no_move():
    out = Exploration(touches=[_roll(6, "left", (109.08, 43.75)), _roll(7, "right", (94.65, 14.29)),
                               _roll(8, "right", (94.66, 14.28)),  # the same corner again: named once
                               _felt(FlatResult("left", 9, -1.57, [], outcome="no_seat", roles=[]))])
    recognition, stop = unusable_refusal(out)
    assert recognition.cls == "unclassified"
    assert recognition.reason.startswith("no usable touch of 4: rolls pivoted about corners at (109, 44) mm and "
                                         "(95, 14) mm; 1 flat press found no seat")
    assert stop.move is None
    assert "between (109, 44) mm and (95, 14) mm" in stop and stop.startswith("no move is named")
    assert refusal_kind(recognition.reason, stop.move) == "needs another move"


def test_a_named_stop_is_kept():
    named = Stop("no flat press seated; ...", {"dx": 6.0, "dy": -4.0, "turn_deg": 10.0, "about": [79.0, -10.0]})
    out = Exploration(touches=[_felt(TouchResult("right", 3, 0.0, [], outcome="unreachable"))], stopped=named)
    recognition, stop = unusable_refusal(out)
    assert stop is named
    assert recognition.reason.startswith("no usable touch of 1: 1 took no contact sample")


def test_too_few_usable_says_so():
    usable = _roll(2, "left", None)
    out = Exploration(touches=[usable, _roll(3, "right", (100.0, 5.0))], used=[usable])
    recognition, stop = unusable_refusal(out)
    assert recognition.reason.startswith("only 1 usable of 2 touches, too few to recognize: rolls pivoted about "
                                         "corner at (100, 5) mm")
    assert "beside (100, 5) mm, clear of it" in stop


def test_seated_presses_split_by_their_angles_are_named():
    """Seated presses on one 11 mm face whose angles scatter more than such a face's presses
    may (tactile_jaw.flat.same_face_rad, 1.7° at 11 mm) are grouped as two faces and none is
    recognized: the refusal names the split (session 22: held-out X line 7 of seed 241 said
    only "1 flat press found no seat"). Its presses at −63.4…−62.3° are one face since
    session 23 (0.57° for every face before)."""
    import math

    import numpy as np

    from tactile_jaw.flat import Face, face_groups

    def seated(k: int, psi_deg: float) -> FeltTouch:
        psi = math.radians(psi_deg)
        t = np.array([-math.sin(psi), math.cos(psi)])
        mid = np.array([82.5, -5.6])
        face = Face(psi, float(np.array([math.cos(psi), math.sin(psi)]) @ mid), mid - 5.5 * t, mid + 5.5 * t)
        return FeltTouch(FlatResult("left", k, psi, [object()] * 30, outcome="ok", roles=[]), None, None, None, None,
                         None, face=face)

    line7 = [seated(13, -63.37), seated(14, -62.65), seated(15, -63.31), seated(16, -62.31)]
    assert [len(g) for g in face_groups(line7)] == [4]
    presses = [seated(13, -64.37), seated(14, -64.25), seated(15, -62.31), seated(16, -62.2)]
    assert [len(g) for g in face_groups(presses)] == [2, 2]
    out = Exploration(touches=[_felt(FlatResult("right", 11, 0.85, [object()] * 31, outcome="stopped", roles=[]))]
                      + presses)
    recognition, _ = unusable_refusal(out)
    assert recognition.reason == ("no usable touch of 5: 4 flat presses seated, on 2 faces by their angles (pad normal "
                                  "-64.4 to -62.2 deg; one face's presses agree within 1.7 deg), none felt often "
                                  "enough: over 11.0 mm of the pad the seats' angles scatter more than that; 1 flat "
                                  "press found no seat (the log's touch_rejected events say why each)")
    recognition, _ = unusable_refusal(Exploration(touches=presses[:2]))  # -64.37, -64.25: one face, too few
    assert recognition.reason.startswith("no usable touch of 2: 2 flat presses seated on one face, too few for an answer")



def test_too_few_clear_of_the_corners_names_a_move():
    """Usable rolls of which too few stay clear of the corners other rolls pivoted about
    (tactile_jaw.explore.closing_answer) end with the move short_face_stop finds from the corners and
    faces the touches met, not with no stop: X line 8 of held-out finite 541 on 657c034 (the logged
    probes and rolls, tests/tactile_jaw/data/x_line_541_8_touches.json; 1 of its 2 usable rolls clear
    of a corner near (102, 17) mm) was refused with none, the command's advice saying no class of the
    scene fits. The right pad turned about the block's corner (91.5, -11.9) mm; the move named clears
    the opened jaw (followed live, the block is answered line)."""
    import json
    from pathlib import Path

    from hand_driver.config import load_config
    from hand_driver.sim.physics import ContactWorld
    from recognizer.scene import load_scene
    from tactile_common.errors import InputError
    from tactile_jaw.explore import closing_answer
    from tactile_jaw.pipeline import feel, logged_samples
    from tactile_jaw.plan import open_pose
    from tactile_jaw.settings import ExploreSettings
    from tools.bench_explore import moved_object

    root = Path(__file__).resolve().parents[2]
    raw = json.loads((root / "tests" / "tactile_jaw" / "data" / "x_line_541_8_touches.json").read_text())
    config = load_config(root / "config" / "jaw.yaml")

    def felt(r):
        samples = logged_samples(config, r["finger"], r["ticks"], r["psi"]) if r["ticks"] else []
        return feel(config, TouchResult(r["finger"], r["touch"], r["psi_center"], samples, outcome=r["outcome"]), 9)

    def too_few(touches):
        raise InputError("exploration: 1 touch(es); the scene's classes need at least 2")

    rolls = [felt(r) for r in raw["touches"]]
    used = [t for t in rolls if t.problem is None]
    assert [t.touch.touch for t in used] == [4, 11]
    out = Exploration(probes=[felt(r) for r in raw["probes"]], touches=rolls, used=used)
    events: list[dict] = []
    closing_answer(config, out, lambda: used[1:], too_few, ExploreSettings.from_profile("balanced"), events.append,
                   lambda msg: None)
    assert out.recognition.reason.startswith("only 1 of the 2 usable touches are clear of the corners")
    assert out.stopped is not None and out.stopped.move is not None
    assert out.stopped.startswith("only 1 usable touch(es) clear of the corners; the right pad turned about a corner "
                                  "at (92, -12) mm")
    assert [e["message"] for e in events if e.get("kind") == "stopped_early"] == [str(out.stopped)]
    moved = load_scene({"name": "b", "classes": ["line"], "object": moved_object(raw["truth"], out.stopped.move)}).object
    assert not ContactWorld(config, moved).penetrates(open_pose(config))  # clear of the opened jaw
