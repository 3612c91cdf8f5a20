"""options.missed: places where sent touches were lost, validated with the other options, and
next_touch's suggestions kept off the stretch a pad sent there meets (recognizer.next_touch,
``_on_missed_stretch``)."""

import math

import numpy as np
import pytest

from recognizer import synth
from recognizer.classify import options_for, recognize
from recognizer.curves import CURVES, Pose
from recognizer.limits import MAX_MISSED
from recognizer.next_touch import PAD_ROLLS, SEAT_RAD, _on_missed_stretch
from recognizer.result import RecognizeOptions
from recognizer.touches import MissedPlace, NoiseModel, Request, SamplesTouch, parse_request
from tactile_common.errors import InputError

ELLIPSE = {"a": 40.0, "b": 22.0}
POSE = Pose(0.4, 120.0, -10.0)
TOUCH = {"phi": [0.0, 0.1, 0.2], "x": [0.0, 1.0, 2.0], "y": [0.0, 0.05, 0.2]}


def _touches(ts, seed=3):
    curve = CURVES["ellipse"](ELLIPSE)
    shape = synth.Shape("ellipse", ELLIPSE, POSE, 80.0, (-math.pi, math.pi), curve)
    touches, _ = synth.sample_shape(shape, ts, 9, 1.5, 1, synth.SynthNoise(1.5e-3, 0.05), np.random.default_rng(seed),
                                    with_s=False)
    return tuple(SamplesTouch(t.phi, t.x, t.y, t.s) for t in touches)


def _recognize(touches, missed=()):
    nm = NoiseModel(1.5e-3, 0.05)
    req = Request(touches, None, tuple(CURVES), nm, {"missed": tuple(missed)} if missed else {})
    return recognize(req, RecognizeOptions(noise=nm, missed=tuple(missed)))


def _request(missed):
    return {"touches": [TOUCH] * 3, "options": {"missed": missed}}


def test_missed_places_are_parsed_and_reach_the_options():
    req = parse_request(_request([{"x": 1.5, "y": -2, "phi": 0.25}]))
    assert req.options["missed"] == (MissedPlace(1.5, -2.0, 0.25),)
    assert options_for(req).missed == (MissedPlace(1.5, -2.0, 0.25),)
    assert options_for(parse_request(_request([]))).missed == ()


@pytest.mark.parametrize("missed, says", [
    ({"x": 1, "y": 2, "phi": 0}, "must be a list"),
    ([[1, 2, 0]], "must be a mapping"),
    ([{"x": 1, "y": 2}], "missing key 'phi'"),
    ([{"x": 1, "y": 2, "phi": 0, "z": 3}], "unknown key(s) z"),
    ([{"x": "1", "y": 2, "phi": 0}], "options.missed[0].x"),
    ([{"x": math.nan, "y": 2, "phi": 0}], "options.missed[0].x"),
    ([{"x": 1, "y": 2e7, "phi": 0}], "beyond"),
    ([{"x": 1, "y": 2, "phi": 2e4}], "beyond"),
    ([{"x": 1, "y": 2, "phi": 0}] * (MAX_MISSED + 1), f"at most {MAX_MISSED}"),
])
def test_bad_missed_places_are_one_clear_line(missed, says):
    with pytest.raises(InputError) as err:
        parse_request(_request(missed))
    assert says in str(err.value) and "\n" not in str(err.value)


def test_the_missed_stretch_is_a_pad_length_along_the_same_normal():
    roll = 3.0
    m = MissedPlace(10.0, 5.0, 0.3)
    u = np.array([math.cos(0.3), math.sin(0.3)])
    n = np.array([-u[1], u[0]])
    pad = 2 * PAD_ROLLS * roll
    along = np.array([0.0, pad * (1 - 1e-9), pad * (1 + 1e-9), -pad * (1 - 1e-9), 0.0, 0.0, 0.0, 0.0])
    across = np.array([0.0, 0.0, 0.0, 0.0, 50.0, 0.0, 0.0, 0.0])  # the pad sweeps its whole normal strip
    phi = 0.3 + np.array([0.0, 0.0, 0.0, 0.0, 0.0, SEAT_RAD * (1 - 1e-9), SEAT_RAD * (1 + 1e-6), 2 * math.pi])
    px, py = (np.array([m.x, m.y])[:, None] + np.outer(u, along) + np.outer(n, across))
    straight = np.zeros(px.size)  # a pad turns SEAT_RAD to seat
    assert _on_missed_stretch(px, py, phi, straight, [m], roll).tolist() == [True, True, False, True, True, True, False,
                                                                            True]
    assert not _on_missed_stretch(px, py, phi + math.pi, straight, [m], roll).any()  # the other side: another approach
    assert not _on_missed_stretch(px, py, phi, straight, [], roll).any()


def test_on_a_curve_the_tilt_tolerance_is_a_rolls_room_along_the_pad():
    """A tilt δφ puts a pad's contact δφ/|κ| along it: within (PAD_ROLLS − ½)·roll, the same stretch."""
    roll, kappa = 3.0, 0.1
    tol = kappa * roll * (PAD_ROLLS - 0.5)
    assert tol > SEAT_RAD
    m = MissedPlace(0.0, 0.0, 1.0)
    phi = 1.0 + np.array([0.99 * tol, -0.99 * tol, 1.01 * tol, 1.6, np.nan])  # beyond π/2: from the solid side
    got = _on_missed_stretch(np.zeros(5), np.zeros(5), phi, np.array([kappa, -kappa, kappa, np.inf, kappa]), [m], roll)
    assert got.tolist() == [True, True, False, False, False]
    assert _on_missed_stretch(np.zeros(1), np.zeros(1), np.array([1.0 + 1.5]), np.array([np.inf]), [m], roll).all()


def test_a_lost_suggestion_sent_back_is_not_suggested_again():
    touches = _touches([0.2, 0.5, 0.8])  # bunched on one side: a suggestion elsewhere
    first = _recognize(touches)
    nt = first.next_touch
    assert first.cls == "ellipse" and nt is not None
    miss = MissedPlace(nt["x"], nt["y"], nt["phi"])
    again = _recognize(touches, [miss])
    assert again.cls == first.cls and again.params == first.params  # the miss changes the suggestion only
    nt2 = again.next_touch
    assert nt2 is not None
    roll = float(np.median([np.sum(np.hypot(np.diff(t.x), np.diff(t.y))) for t in touches]))
    along = (nt2["x"] - miss.x) * math.cos(miss.phi) + (nt2["y"] - miss.y) * math.sin(miss.phi)
    tilt = abs(math.remainder(nt2["phi"] - miss.phi, 2 * math.pi))
    assert abs(along) >= 2 * PAD_ROLLS * roll or tilt > SEAT_RAD
