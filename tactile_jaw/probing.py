"""The probe phase: before any rolling touch, probes locate the boundary.

Every finger probes the orientations tactile_jaw.plan.probe_psis lists, both fingers in the
same bus cycles, each probe a short rolling touch (``PROBE_SAMPLES`` over
``PROBE_SPAN_DEG``) from the workspace edge across the whole workspace disk. A probe whose
samples lie on the pad's face (tactile_jaw.plan.probe_face_contact) adds its pad lines to
the object model; a finger stops probing once its face contacts span ``PROBE_ENOUGH_DEG``.
A finger with a single face contact probes once more ``PROBE_REFINE_DEG`` either side of
it. A finger without any face contact after ``PROBE_IDLE_AFTER`` probes stops once another
finger has felt enough. docs/exploration.md.
"""

from __future__ import annotations

import math

import numpy as np

from hand_driver.cycle import Jaw
from hand_driver.motion import TouchResult, roll_angles, rolling_touch
from tactile_jaw.pipeline import feel
from tactile_jaw.plan import (
    PROBE_ENOUGH_DEG,
    PROBE_REFINE_DEG,
    PROBE_SAMPLES,
    PROBE_SPAN_DEG,
    ObjectModel,
    probe_face_contact,
    probe_psis,
)
from tactile_jaw.rounds import Exploration, timed_round, transit_or_problem

#: a finger that found no face contact in this many probes stops probing once another
#: finger's face contacts span ``PROBE_ENOUGH_DEG``: its pad met only corners, pad ends or
#: nothing near its own normals (the parabola example's right finger: its flat bottom's
#: corners, 7 probes, 4 rounds after the left finger had enough: 12 s of robot time)
PROBE_IDLE_AFTER = 2


def _probe_plan(jaw: Jaw, finger: str, model: ObjectModel, psi: float, touch_index: int, emit,
                spent: dict[str, float]):
    """Transit, then a short rolling touch (``PROBE_SAMPLES`` over ``PROBE_SPAN_DEG``) from
    the workspace edge across the whole workspace disk, its first approach at the free
    stretch's speed all the way (still guarded every cycle; the object met at that speed,
    the sample is taken again at the normal speed: hand_driver.motion.guarded_approach);
    returns the TouchResult."""
    span = math.radians(PROBE_SPAN_DEG)
    start = float(roll_angles(psi, span, PROBE_SAMPLES)[0])
    problem = yield from transit_or_problem(jaw, finger, model, start, spent)
    if problem is not None:
        return TouchResult(finger, touch_index, psi, outcome="unreachable", message=problem)
    travel = 2.0 * model.workspace_radius
    return (yield from rolling_touch(jaw, finger, touch_index, psi, span, PROBE_SAMPLES, model.edge(start),
                                     travel, on_event=emit, free_mm=travel))


def probe_boundary(jaw: Jaw, model: ObjectModel, out: Exploration, emit, say) -> int:
    """The probe phase (module docstring): every probe goes to ``out.probes`` and its robot
    time to ``out.time_s``, the face contacts' pad lines to ``model``. Returns the next
    touch index."""
    cfg = jaw.config
    index = 0
    queues = {f.name: probe_psis(f, model) for f in cfg.fingers}
    faces: dict[str, list[float]] = {f.name: [] for f in cfg.fingers}
    probed = {f.name: 0 for f in cfg.fingers}
    refined = False
    while True:
        if not any(queues.values()):
            if refined:
                break
            refined = True  # one more pass: around a finger's only face contact, PROBE_REFINE_DEG either side
            queues = {f.name: [faces[f.name][0] + math.radians(sign * PROBE_REFINE_DEG) for sign in (-1, 1)]
                      if len(faces[f.name]) == 1 else [] for f in cfg.fingers}
            if not any(queues.values()):
                break
        plans, spent = {}, {}
        for name, queue in queues.items():
            if queue:
                plans[name] = _probe_plan(jaw, name, model, queue.pop(0), index + len(plans), emit, spent)
        results = timed_round(jaw, plans, spent, out.time_s, "probes", "probe_transits")
        for name in plans:
            felt = feel(cfg, results[name], PROBE_SAMPLES, curve_checks=False)
            probe = felt.touch
            out.probes.append(felt)
            index += 1
            u = probe_face_contact(cfg, felt)
            if u is not None:
                model.add([s.psi_measured for s in probe.samples], [s.d for s in probe.samples])
                faces[name].append(probe.psi_center)
                if np.ptp(faces[name]) >= math.radians(PROBE_ENOUGH_DEG) - 1e-9:
                    queues[name] = []  # enough felt to plan this finger's touches
            probed[name] += 1
            say(f"probe {len(out.probes)}: {name} at psi {math.degrees(probe.psi_center):.1f} deg: "
                + (f"pad face {u:.1f} mm from its proximal end" if u is not None else
                   probe.message or f"{len(probe.samples)} samples, not on the pad's face"))
        done = [n for n in faces if faces[n] and np.ptp(faces[n]) >= math.radians(PROBE_ENOUGH_DEG) - 1e-9]
        for name in queues:
            if done and name not in done and not faces[name] and probed[name] >= PROBE_IDLE_AFTER and queues[name]:
                queues[name] = []
                say(f"{name}: no face contact in {probed[name]} probes while {done[0]} felt enough: its side "
                    f"offers the pads no curved part near them; the touches plan from what the other finger felt")
    return index
