"""A rolling touch's sample taken before its pad reached the orientation it was commanded to
is not one of the roll's samples (tactile_jaw.pipeline.at_orientation): the roll's first
approach met the object while the pad still turned to its start."""

import json
import math
from pathlib import Path

import numpy as np

from hand_driver import kinematics as kin
from hand_driver.config import load_config
from hand_driver.motion import Sample, TouchResult
from recognizer.curves import CURVES, Pose
from tactile_jaw.pipeline import ORIENTATION_STEP_SHARE, at_orientation, feel, logged_samples

DATA = Path(__file__).parent / "data" / "p_cubical_first_sample_off.json"
#: random cubical 115 of bench_explore --finite 20 --anywhere --seed 139 --config config/jaw-p.yaml
#: (a development seed since session 16)
TRUTH = ("cubical_parabola", {"a": 0.0005522150849600728, "c": -0.5},
         Pose(0.027890694008744887, 130.42602471897615, 38.74503355338456), (-28.886977431461755, 2.4072481192884796))


def _logged_roll(commanded_as_measured: bool = False):
    raw = json.loads(DATA.read_text())
    config = load_config("config/jaw-p.yaml")
    psis = (kin.finger_pad_line_from_ticks(config, raw["finger"], np.array(raw["ticks"], dtype=float)).psi
            if commanded_as_measured else raw["psi"])
    samples = logged_samples(config, raw["finger"], raw["ticks"], psis)
    return config, TouchResult(raw["finger"], 4, raw["psi_center"], samples, outcome="ok")


def _along_misfit(felt) -> np.ndarray:
    """Each contact's distance from the point where the true curve's tangent is the contact's
    tangent (the pad line's point of tangency), in its stated deviation along the pad."""
    cls, params, pose, extent = TRUTH
    curve = CURVES[cls](params)
    t = np.linspace(*extent, 400001)
    px, py = pose.apply(*curve.point(t))
    angle = curve.tangent_angle(t) + pose.theta
    c, out = felt.contacts, []
    for x, y, phi in zip(c.x, c.y, c.phi):
        off = np.abs(np.remainder(angle - phi + math.pi / 2, math.pi) - math.pi / 2)
        off[np.hypot(px - x, py - y) > 3.0] = np.inf  # the tangency near the contact
        j = int(np.argmin(off))
        out.append(math.hypot(px[j] - x, py[j] - y))
    return np.array(out) / felt.fit.sigma_along


def test_the_sample_off_its_orientation_is_left_out():
    """The roll's first sample lay 12.9° from its commanded orientation (the others within
    0.001°): it is left out, and the 8 left are felt usable, every contact within 1.5 of its
    deviations along the pad from the curve's point of tangency (measured: ≤ 0.9)."""
    config, touch = _logged_roll()
    off = np.degrees([abs(math.remainder(s.psi_measured - s.psi, 2 * math.pi)) for s in touch.samples])
    assert off[0] > 12.0 and np.all(off[1:] < 1e-3)
    kept = at_orientation(touch)
    assert kept.samples == touch.samples[1:]
    felt = feel(config, touch, len(touch.samples))
    assert felt.problem is None and len(felt.contacts.x) == 8
    assert np.all(_along_misfit(felt) < 1.5)


def test_with_that_sample_the_envelope_misplaces_its_contact():
    """The same readings as if the pad had been commanded where it was: kept, the envelope fit
    across the 12.9° gap puts that contact 0.19 mm along the pad from its point of tangency,
    7.4 of its deviations (what made the cubical "no class fits", χ² 5.9e3 on 30 dof)."""
    config, touch = _logged_roll(commanded_as_measured=True)
    assert at_orientation(touch) is touch
    felt = feel(config, touch, len(touch.samples))
    assert len(felt.contacts.x) == 9
    assert _along_misfit(felt)[0] > 5.0


def test_every_sample_at_its_orientation_is_kept():
    config, touch = _logged_roll()
    rest = TouchResult(touch.finger, touch.touch, touch.psi_center, touch.samples[1:], outcome="ok")
    assert at_orientation(rest) is rest
    step = math.radians(2.25)
    late = [Sample(s.reading, s.psi + (0.9 * ORIENTATION_STEP_SHARE * step if k == 3 else 0.0), s.ticks, s.line,
                   None, 0.0) for k, s in enumerate(rest.samples)]
    assert len(at_orientation(TouchResult(touch.finger, 4, touch.psi_center, late)).samples) == len(late)
