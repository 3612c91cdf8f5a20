"""A finger whose probes met the object at a pad end turns the pad the way that brings the
contact toward the pad's middle (tactile_jaw.probing.toward_middle), on exact pad lines
tangent to a circle: the turn it names from two probes moves the exact contact toward the
middle, the other way away; and such a finger keeps probing (tactile_jaw.probing.Probes)."""

from __future__ import annotations

import math
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from hand_driver import kinematics as kin
from hand_driver.config import load_config
from hand_driver.motion import Sample
from tactile_jaw.plan import ObjectModel, nominal_psi
from tactile_jaw.probing import Probes, pad_contact, toward_middle

ROOT = Path(__file__).resolve().parents[2]
RADIUS = 15.0


def _pad(finger, psi: float, center: np.ndarray, q_near: np.ndarray) -> tuple[kin.PadLine, np.ndarray, float]:
    """The pad tangent to the circle (``center``, RADIUS) with normal ψ on the joint branch
    nearest ``q_near``: its line, joint angles and the exact contact's distance along it."""
    n = kin.unit(psi)
    contact = center - RADIUS * n  # the tangent point of a line with normal n (pointing into the disk)
    sols = [q for q in kin.ik_line_solutions(finger, psi, float(n @ contact)) if kin.within_limits(finger.joints, q)]
    q = min(sols, key=lambda s: float(np.sum((s - q_near) ** 2)))
    line = kin.finger_pad_line(finger, q)
    return line, q, float(line.pad_coordinate(contact))


def _probe(finger, psi0: float, center: np.ndarray, q0: np.ndarray):
    samples, q = [], q0
    for k, psi in enumerate(psi0 + np.radians([-2.0, 0.0])):
        line, q, _ = _pad(finger, float(psi), center, q)
        samples.append(Sample(k, float(psi), np.zeros(2), line, None, 0.0))
    return SimpleNamespace(finger=finger.name, touch=SimpleNamespace(samples=samples, psi_center=psi0))


def _setup(config: str, name: str, at: float, psi_off: float = 10.0):
    finger = load_config(ROOT / "config" / config).finger(name)
    psi0 = nominal_psi(finger) + math.radians(psi_off)
    n = kin.unit(psi0)
    q0 = kin.ik_line(finger, psi0, float(n @ np.array([110.0, 0.0])) - 20.0)
    line0 = kin.finger_pad_line(finger, q0)
    return finger, psi0, q0, line0.proximal + at * line0.tangent + RADIUS * n  # the contact `at` mm along the pad


@pytest.mark.parametrize("config", ["jaw.yaml", "jaw-p.yaml"])
@pytest.mark.parametrize("name", ["left", "right"])
@pytest.mark.parametrize("at", [1.5, -2.0])  # the proximal end (at the distal one u(ψ) has its minimum near 90 % here)
@pytest.mark.parametrize("before", [-20.0, 20.0])
def test_the_named_turn_moves_the_contact_toward_the_pad_middle(config, name, at, before):
    finger, psi0, q0, center = _setup(config, name, at)
    length = finger.pad.length_mm
    earlier = _probe(finger, psi0 + math.radians(before), center, q0)  # the probe before, on either side
    last = _probe(finger, psi0, center, q0)
    met = [(psi0 + math.radians(before), pad_contact(earlier)), (psi0, pad_contact(last))]
    # two exact lines 2° apart cross near the tangent point 1° back: within ρ·2° of it
    assert met[1][1] == pytest.approx(at, abs=RADIUS * math.radians(2.0))
    sign = toward_middle(met, length)
    assert sign in (-1.0, 1.0)
    step = math.radians(5.0)
    toward = _pad(finger, psi0 + sign * step, center, q0)[2]
    away = _pad(finger, psi0 - sign * step, center, q0)[2]
    assert abs(toward - 0.5 * length) < abs(at - 0.5 * length) - 0.1
    assert abs(away - 0.5 * length) > abs(at - 0.5 * length) + 0.1


def test_a_contact_on_the_face_or_a_single_probe_names_no_turn():
    finger, psi0, q0, center = _setup("jaw.yaml", "right", 26.0)
    earlier = _probe(finger, psi0 - math.radians(20.0), center, q0)
    met = [(psi0 - math.radians(20.0), pad_contact(earlier)), (psi0, pad_contact(_probe(finger, psi0, center, q0)))]
    assert toward_middle(met, finger.pad.length_mm) is None
    assert toward_middle([(psi0, -2.0)], finger.pad.length_mm) is None


def test_a_finger_met_at_its_pad_end_keeps_probing_on_that_side():
    """Probes.record puts the finger's queued orientations on the named side first and
    Probes.done does not stop it for want of a face contact (it did after 2 probes)."""
    cfg = load_config(ROOT / "config" / "jaw.yaml")
    finger = cfg.finger("right")
    probes = Probes(cfg, ObjectModel(cfg.workspace.center_mm, cfg.workspace.radius_mm))
    probes.faces["left"] = [0.0, math.radians(30.0)]  # the other finger felt enough
    first, second = probes.queues["right"][:2]
    q0 = kin.ik_line(finger, second, float(kin.unit(second) @ np.array([110.0, 0.0])) - 20.0)
    line0 = kin.finger_pad_line(finger, q0)
    center = line0.proximal - 2.0 * line0.tangent + RADIUS * kin.unit(second)  # 2 mm beyond the proximal end
    out = SimpleNamespace(probes=[])
    for psi in (first, second):
        felt = _probe(finger, probes.queues["right"].pop(0), center, q0)
        felt.lines = None
        felt.touch.outcome, felt.touch.message = "edge", "a pad end"
        probes.record(felt, out, lambda msg: None)
        probes.done(lambda msg: None)
    sign = toward_middle(probes.met["right"], finger.pad.length_mm)
    assert sign is not None and probes.nudge["right"] == sign
    assert sign * math.remainder(probes.queues["right"][0] - second, 2 * math.pi) > 0
    assert probes.queues["right"], "stopped probing though the object lies beside its pad's end"
