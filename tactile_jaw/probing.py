"""The probe phase: before any rolling touch, probes locate the boundary.

Every finger probes the orientations tactile_jaw.plan.probe_psis lists, both fingers in the
same bus cycles, each probe a short rolling touch (``PROBE_SAMPLES`` over
``PROBE_SPAN_DEG``) from the workspace edge across the whole workspace disk. A probe whose
samples lie on the pad's face (tactile_jaw.plan.probe_face_contact) adds its pad lines to
the object model; a finger stops probing once its face contacts span ``PROBE_ENOUGH_DEG``.
A finger with a single face contact probes once more ``PROBE_REFINE_DEG`` either side of
it. A finger without any face contact after ``PROBE_IDLE_AFTER`` probes stops once another
finger has felt enough, unless its last probe met the object at a pad end: then the object
is there, beside the pad's face, and its next probe turns the pad the way that brings the
contact toward the pad's middle (:func:`toward_middle`). Once one finger has felt enough, the other's probes left go on
beside its rolling touches (tactile_jaw.explore), one a round, instead of the finger that
felt enough waiting for them (the semicubical of dev seed 83: 14 s). A probe whose transit
or approach left the joint limits before it met the object rules out every probe of that
finger turned as far as or farther from its nominal normal on that side (:meth:`Probes._reachable`):
of the 147 such probes in sessions 30–32's held-out logs (both jaws, every class) not one met
the object (P line 19 of bench_explore --finite 20 --anywhere --seed 541: 70°, 50° and 30°
all out of reach, 28.1 -> 27.6 s). docs/exploration.md.
"""

from __future__ import annotations

import math
from typing import Callable

import numpy as np

from hand_driver.cycle import Jaw
from hand_driver.motion import TouchResult, contact_on_pad, roll_angles, rolling_touch
from tactile_jaw.pipeline import feel
from tactile_jaw.plan import (
    PROBE_ENOUGH_DEG,
    PROBE_PAD_MARGIN,
    PROBE_REFINE_DEG,
    PROBE_SAMPLES,
    PROBE_SPAN_DEG,
    ObjectModel,
    nominal_psi,
    probe_face_contact,
    probe_psis,
)
from tactile_jaw.rounds import Exploration, timed_round, transit_or_problem

#: a finger that found no face contact in this many probes stops probing once another
#: finger's face contacts span ``PROBE_ENOUGH_DEG``: its pad met only corners, pad ends or
#: nothing near its own normals (the parabola example's right finger: its flat bottom's
#: corners, 7 probes, 4 rounds after the left finger had enough: 12 s of robot time)
PROBE_IDLE_AFTER = 2


def pad_contact(felt) -> float | None:
    """Where along the pad (mm from its proximal end) a probe that met the object last
    touched it: the crossing of its last two pad lines (hand_driver.motion.contact_on_pad),
    beyond the pad's ends when a pad end rested on the object; None with fewer than 2 samples."""
    samples = felt.touch.samples
    return contact_on_pad(samples)[1] if len(samples) >= 2 else None


def toward_middle(met: list[tuple[float, float]], length: float) -> float | None:
    """The sign of the turn of ψ that brings a finger's contact toward the pad's middle, from
    its last two probes that met the object (``met``: (ψ, contact along the pad), the last
    near or beyond a pad end: outside ``PROBE_PAD_MARGIN`` of the pad's ``length`` from either
    end); None when it lies on the face, or one probe cannot tell. Measured, not modelled:
    how far the contact moves along the pad for a turn is the boundary's radius of curvature
    (dp/dψ = −ρ·t(ψ)) and the finger's own motion along its pad line, of either sign. (Random
    X-series ellipses 41 and 49 of bench_explore --finite 20 --anywhere --seed 107: the right
    pad met the ellipse's far end at its proximal end at ψ 90° and 70°, and the finger stopped
    probing; at 110° the contact is on its face, 12.8 and 20.0 mm along it.)"""
    if len(met) < 2:
        return None
    (psi0, u0), (psi1, u1) = met[-2:]
    if PROBE_PAD_MARGIN * length <= u1 <= (1.0 - PROBE_PAD_MARGIN) * length:
        return None
    rate = (u1 - u0) * math.remainder(psi1 - psi0, 2 * math.pi)
    if rate == 0.0:
        return None
    return math.copysign(1.0, (0.5 * length - u1) * rate)


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


class Probes:
    """What the probes did and have left to do, per finger (module docstring): the queue of
    each finger's probe orientations, its face contacts' ψ, and how many it made."""

    def __init__(self, config, model: ObjectModel):
        self.config, self.model = config, model
        self.queues = {f.name: probe_psis(f, model) for f in config.fingers}
        self.faces: dict[str, list[float]] = {f.name: [] for f in config.fingers}
        self.probed = {f.name: 0 for f in config.fingers}
        #: per finger: (ψ, the contact along the pad) of its probes that met the object
        self.met: dict[str, list[tuple[float, float]]] = {f.name: [] for f in config.fingers}
        #: per finger without a face contact: the sign of the turn toward the pad's middle when
        #: its last probe met the object at a pad end (:func:`toward_middle`)
        self.nudge: dict[str, float] = {}
        self.refined = False
        #: per finger: the ψ of every probe it made
        self.tried: dict[str, list[float]] = {f.name: [] for f in config.fingers}
        #: per finger: the turns from its nominal normal (rad) of its probes that left the joint limits
        self.unreached: dict[str, list[float]] = {f.name: [] for f in config.fingers}

    def _offset(self, name: str, psi: float) -> float:
        return math.remainder(psi - nominal_psi(self.config.finger(name)), 2 * math.pi)

    def _reachable(self, name: str, psi: float) -> bool:
        """Whether a probe of ``name`` at ψ may reach: not turned as far as or farther from the
        pad's nominal normal, on the same side, than one of its probes whose transit or approach left
        the joint limits (module docstring)."""
        o = self._offset(name, psi)
        return not any(o * u > 0 and abs(o) >= abs(u) - 1e-9 for u in self.unreached[name])

    def _keep_reachable(self) -> None:
        self.queues = {name: [a for a in queue if self._reachable(name, a)] for name, queue in self.queues.items()}

    def _enough(self, name: str) -> bool:
        return bool(self.faces[name]) and np.ptp(self.faces[name]) >= math.radians(PROBE_ENOUGH_DEG) - 1e-9

    def next(self) -> dict[str, float]:
        """Each finger's next probe orientation (fingers with none left are absent); once
        every queue is empty, one more pass around a finger's only face contact,
        ``PROBE_REFINE_DEG`` either side where the finger has not probed already (then
        nothing): a probe turned toward the pad's middle that found the face probes there
        first (:meth:`record`), and the pass made both again (P-series block 8 of
        bench_explore --finite 20 --anywhere --seed 157: 100° and 120° twice each, 4 rounds of
        ~2.5 s while the other finger pressed beside them). Neither pass keeps an orientation
        :meth:`_reachable` rules out."""
        self._keep_reachable()
        if not any(self.queues.values()) and not self.refined:
            self.refined = True
            self.queues = {name: [a for a in (faces[0] + math.radians(sign * PROBE_REFINE_DEG) for sign in (-1, 1))
                                  if not any(abs(math.remainder(a - t, 2 * math.pi)) < 1e-6 for t in self.tried[name])]
                           if len(faces) == 1 else [] for name, faces in self.faces.items()}
            self._keep_reachable()
        return {name: queue[0] for name, queue in self.queues.items() if queue}

    def plan(self, jaw: Jaw, name: str, touch_index: int, emit, spent: dict[str, float]):
        """The motion of ``name``'s next probe (:meth:`next`), taken off its queue."""
        return _probe_plan(jaw, name, self.model, self.queues[name].pop(0), touch_index, emit, spent)

    def record(self, felt, out: Exploration, say) -> None:
        """A probe felt (tactile_jaw.pipeline.feel): to ``out.probes``, its pad lines to the
        model if on the pad's face; a finger whose face contacts span ``PROBE_ENOUGH_DEG``
        stops probing."""
        name, probe = felt.finger, felt.touch
        out.probes.append(felt)
        self.tried[name].append(probe.psi_center)
        if probe.outcome == "unreachable" and not probe.samples:
            self.unreached[name].append(self._offset(name, probe.psi_center))
        u = probe_face_contact(self.config, felt)
        at = pad_contact(felt)
        if at is not None:
            self.met[name].append((probe.psi_center, at))
        nudged = self.nudge.pop(name, None)
        if u is not None and nudged is not None and not self.faces[name]:
            # the turn toward the pad's middle found the face: the rest of this finger's probes
            # around it, on the far side first (the queue's others met the pad end or less)
            self.queues[name] = [probe.psi_center + nudged * s * math.radians(PROBE_REFINE_DEG) for s in (1, -1)]
        sign = None if u is not None or self.faces[name] or at is None else toward_middle(
            self.met[name], self.config.finger(name).pad.length_mm)
        if sign is not None:  # met the object beside the pad's face: probe next where the contact moves onto it
            ahead = [a for a in self.queues[name] if sign * math.remainder(a - probe.psi_center, 2 * math.pi) > 0]
            if ahead:
                ahead.sort(key=lambda a: abs(math.remainder(a - probe.psi_center, 2 * math.pi)))
                self.queues[name] = ahead + [a for a in self.queues[name] if a not in ahead]
                self.nudge[name] = sign
        if u is not None:
            self.model.add([s.psi_measured for s in probe.samples], [s.d for s in probe.samples])
            self.faces[name].append(probe.psi_center)
            if self._enough(name):
                self.queues[name] = []  # enough felt to plan this finger's touches
        self.probed[name] += 1
        say(f"probe {len(out.probes)}: {name} at psi {math.degrees(probe.psi_center):.1f} deg: "
            + (f"pad face {u:.1f} mm from its proximal end" if u is not None else
               probe.message or f"{len(probe.samples)} samples, not on the pad's face"))

    def done(self, say) -> list[str]:
        """The fingers that felt enough; after a round, a finger without any face contact in
        ``PROBE_IDLE_AFTER`` probes stops probing once another finger has, unless its last
        probe met the object at a pad end (``nudge``: its next probe turns toward the face)."""
        done = [n for n in self.faces if self._enough(n)]
        for name, queue in self.queues.items():
            if (done and name not in done and not self.faces[name] and self.probed[name] >= PROBE_IDLE_AFTER and queue
                    and name not in self.nudge):
                self.queues[name] = []
                say(f"{name}: no face contact in {self.probed[name]} probes while {done[0]} felt enough: its side "
                    f"offers the pads no curved part near them; the touches plan from what the other finger felt")
        return done


def probe_boundary(jaw: Jaw, model: ObjectModel, out: Exploration, emit, say,
                   beside: Callable | None = None) -> tuple[int, Probes]:
    """The probe phase (module docstring) until every finger is done or one has felt
    enough: every probe goes to ``out.probes`` and its robot time to ``out.time_s``, the
    face contacts' pad lines to ``model``. A finger whose probes are done while another's go
    on may make another motion in the same rounds: ``beside(finger, touch_index, spent)``, a
    plan or None (tactile_jaw.explore: a flat press at a seat its lines show), its result
    handed back as ``beside(finger, result=...)``; so does a finger with probes left but no
    face contact whose lines already show a seat, its probes left undone. Returns the next touch index and the
    :class:`Probes`, whose probes left (:meth:`Probes.next`) go on beside the rolls."""
    cfg = jaw.config
    index = 0
    probes = Probes(cfg, model)
    while True:
        upcoming = probes.next()
        if not upcoming:
            break
        plans, spent, pressing = {}, {}, set()
        for name in upcoming:
            # probes that met no face but whose pad lines pivot about two supports a face apart (a seat:
            # flat_phase._felt_seat) found a face too wide for a probe to lie on: the pad is pressed flat
            # there instead of probing on (P line 0 of seed 313: 3 more rounds of pad ends and lines out
            # of reach, 21.9 -> 18.1 s, the same seat)
            plan = None if beside is None or probes.faces[name] else beside(name, index + len(plans), spent)
            if plan is None:
                plans[name] = probes.plan(jaw, name, index + len(plans), emit, spent)
                continue
            probes.queues[name] = []
            say(f"{name}: its probes met no face but its pad lines show a seat: pressing there instead of probing on")
            plans[name] = plan
            pressing.add(name)
        for f in cfg.fingers:
            plan = None if beside is None or f.name in plans else beside(f.name, index + len(plans), spent)
            if plan is not None:
                plans[f.name] = plan
                pressing.add(f.name)
        results = timed_round(jaw, plans, spent, out.time_s, "probes", "probe_transits")
        for name in plans:
            index += 1
            if name in pressing:
                beside(name, result=results[name])
                continue
            probes.record(feel(cfg, results[name], PROBE_SAMPLES, curve_checks=False), out, say)
        done = probes.done(say)
        if done and len(done) < len(cfg.fingers) and probes.next():
            say(f"{done[0]} felt enough: its rolling touches start while the other finger's probes go on")
            break
    return index, probes
