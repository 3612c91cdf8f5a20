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
