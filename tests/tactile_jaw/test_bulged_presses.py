"""Flat presses whose seats stopped short of their supports by a bulge, twice with one
finger, are a curved part (tactile_jaw.flat.bulged_presses): the faces the pads pressed
are then a finite object's closing segments, and the exploration refuses instead of
answering ``line`` (tactile_jaw.pipeline.curved_part, curve_refusal; flat_phase.curve_stop).
P hyperbola 93 of bench_explore --finite 20 --anywhere --seed 191 (session 18's held-out
run): its rolls fell on the corners, the left pad's two presses on the curved part stopped
+0.26 and +0.27 mm short of their supports, the right pad's three presses on the closing
segment seated and were answered ``line`` — the one wrong answer of that run. The presses
as logged (their joint ticks)."""

from __future__ import annotations

import json
from pathlib import Path
from types import SimpleNamespace

import pytest

from hand_driver.config import load_config
from hand_driver.flat_press import SEAT_TOL_MM, FlatResult
from tactile_jaw.flat import BULGED_PRESSES, bulged, bulged_presses, recognized_touches
from tactile_jaw.flat_phase import _curve_felt, curve_stop
from tactile_jaw.pipeline import curve_refusal, curved_part, feel, logged_samples
from tactile_jaw.settings import ExploreSettings

DATA = Path(__file__).parent / "data" / "p_hyperbola_93_presses.json"
RAW = json.loads(DATA.read_text())


def felt_presses(config_path: str, raw: dict):
    """Every logged press of ``raw`` felt as the exploration felt it: (config, {touch index: FeltTouch})."""
    config = load_config(config_path)
    out = {}
    for t in raw["presses"]:
        samples = logged_samples(config, t["finger"], t["ticks"], t["psi"])
        touch = FlatResult(t["finger"], t["touch"], t["psi_center"], samples, outcome=t["outcome"], roles=t["roles"])
        out[t["touch"]] = feel(config, touch, 9)
    return config, out


@pytest.fixture(scope="module")
def presses():
    """P hyperbola 93's logged presses felt as the exploration felt them."""
    return felt_presses("config/jaw-p.yaml", RAW)


def test_the_presses_on_the_curve_bulged_and_those_on_the_closing_segment_seated(presses):
    _, felt = presses
    for k in (8, 10):
        assert felt[k].problem is not None and "did not lie flat" in felt[k].problem
        assert 0.25 < felt[k].face.miss < 0.28  # the bulge kept with the supports
        assert bulged(felt[k])
    for k in (12, 13, 14):
        assert felt[k].problem is None and abs(felt[k].face.miss) < 0.01
        assert not bulged(felt[k])


def test_two_bulged_presses_of_one_finger_make_the_seated_faces_closing_segments(presses):
    """Before: curved_part found nothing (the presses' scans have one line each), the right
    pad's three seated presses were recognized, answered line."""
    config, felt = presses
    every = [felt[k] for k in (8, 10, 12, 13, 14)]
    assert BULGED_PRESSES == 2 and bulged_presses(every) == [felt[8], felt[10]]
    curve = curved_part(config, every)
    assert curve is felt[10]
    assert recognized_touches([t for t in every if t.problem is None], 3, curved=curve is not None) == []
    refusal = curve_refusal(curve)
    assert refusal.cls == "unclassified"
    assert "closing segments, not a line" in refusal.reason and "+0.27 mm" in refusal.reason
    stop = curve_stop(config, ExploreSettings.from_profile("balanced"), curve, curve)
    assert "(112.7, 40.5) mm" in stop  # the middle of the bulged press's supports


def test_one_bulged_press_is_no_curve(presses):
    """One press's seat may miss by the encoders' rounding (X-series: 0.22 mm once on a
    face, FLAT_TRIES): one bulge alone leaves the faces a line."""
    config, felt = presses
    one = [felt[k] for k in (10, 12, 13, 14)]
    assert bulged_presses(one) is None and curved_part(config, one) is None
    assert len(recognized_touches([t for t in one if t.problem is None], 3)) == 3


def test_the_flat_phase_feels_a_bulged_press_again_when_the_second_comes(presses):
    """The flat phase feels each touch once (``checked``), but a bulged press shows a curve
    only with the next: the first is felt again in the round of the second."""
    config, felt = presses
    out = SimpleNamespace(touches=[felt[8], felt[12]], probes=[], used=None, recognition=None, stopped=None)
    checked: set[int] = set()
    said: list[str] = []
    settings = ExploreSettings.from_profile("balanced")
    assert not _curve_felt(config, settings, out, lambda rec: None, said.append, checked)
    out.touches += [felt[10], felt[13]]
    assert _curve_felt(config, settings, out, lambda rec: None, said.append, checked)
    assert out.recognition.cls == "unclassified" and out.used == []
    assert f"at most {SEAT_TOL_MM:g}" in said[-1] and out.stopped is not None


X_LINE_19 = json.loads((Path(__file__).parent / "data" / "x_line_19_presses.json").read_text())


@pytest.fixture(scope="module")
def block_presses():
    """X line 19 of seed 283's presses felt as the exploration felt them."""
    return felt_presses("config/jaw.yaml", X_LINE_19)


def test_a_seat_short_of_a_pad_end_past_a_corner_is_no_bulge(block_presses):
    """X line 19 of seed 283 (a 42.7 mm block face, the 52 mm pad turned about its corners
    3.1–3.8 mm from the pad ends): the right pad's presses 11 and 20 stopped +0.24 / +0.23 mm
    short of the pad ends its supports were read as (within END_SUPPORT_MM of the crossing),
    0.06 mm of the crossings, the block's corners. Their seats still fail (the end reading
    holds an arc's bulge), but they show no curved part: before, both counted as bulged and
    the block was refused ("closing segments, not a line")."""
    config, felt = block_presses
    for k in (11, 20):
        assert felt[k].problem is not None and "did not lie flat" in felt[k].problem
        assert 0.2 < felt[k].face.miss < 0.26  # short of the pad ends
        assert abs(felt[k].face.bulge) < 0.1  # at the corners the lines cross at
        assert not bulged(felt[k])
    for k in (17, 18, 19):
        assert felt[k].problem is None and abs(felt[k].face.miss) < 0.06 and felt[k].face.bulge <= felt[k].face.miss
    every = [felt[k] for k in sorted(felt)]
    assert bulged_presses(every) is None and curved_part(config, every) is None
    assert recognized_touches([t for t in every if t.problem is None], 2) == [felt[17], felt[19]]


def test_a_bulge_shows_however_the_supports_are_read(presses):
    """P hyperbola 93's presses on its curved part: their crossings lie mid-pad, the bulge
    is the same either way."""
    _, felt = presses
    for k in (8, 10):
        assert felt[k].face.bulge == pytest.approx(felt[k].face.miss) and felt[k].face.bulge > 0.25
