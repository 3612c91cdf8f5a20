"""Benchmark: what the whole reachable curved part of a scene's object tells (a benchmark, not a test).

For a finite object (a scene with ``object``), every pad orientation the planner could roll
at if it knew the object exactly: ``tactile_jaw.plan.feasible`` on an object model holding
the object's exact support lines (the first line of each normal that meets its outline), per
finger, every degree, keeping the rolls whose every contact is on the curved part (not a
corner or a closing segment). Then ``--touches N`` rolls spread evenly over that reach, each
the exact tangents of the object quantized to whole encoder ticks (as the encoders read
them), are felt (tactile_jaw.pipeline.feel) and recognized with the scene's classes, and the
exploration's stopping rule (tactile_jaw.decide) says whether the answer is decisive. It
separates what the reach limits from what the measurement limits: docs/exploration.md#what-
the-pads-reach-on-the-open-examples. Run: ``python -m tools.bench_reach SCENE [--touches 5 8]
[--profile balanced]``.
"""

from __future__ import annotations

import argparse
import math
import sys

import numpy as np

from hand_driver import kinematics as kin
from hand_driver.cycle import LIMIT_MARGIN_RAD
from hand_driver.config import load_config
from hand_driver.motion import Sample, TouchResult, roll_angles
from recognizer.scene import load_scene
from tactile_common.errors import InputError
from tactile_common.yamlfile import read_yaml
from tactile_jaw.decide import decide
from tactile_jaw.pipeline import FeltTouch, feel, make_recognizer, workspace_reach
from tactile_jaw.plan import ObjectModel, feasible
from tactile_jaw.settings import ExploreSettings

#: pad normals (deg) tried, every STEP_DEG; the curve's outline sampled at OUTLINE points
STEP_DEG = 1.0
OUTLINE = 20001
#: a roll's contact this far (mm) from every corner and off the closing segments is on the curved part
CORNER_CLEAR_MM = 0.05


class ExactObject:
    """The object's outline: support lines and the contact of a pad of normal ψ."""

    def __init__(self, obj):
        x, y = obj.outline(OUTLINE)
        self.points = np.stack([x, y], axis=-1)
        self.on_curve = np.zeros(len(x), bool)
        self.on_curve[1:OUTLINE - 1] = True  # the curve's ends are corners

    def contact(self, psi: float) -> tuple[float, np.ndarray, bool]:
        """(d, the point, whether it lies on the curved part) of the first line of normal ψ
        meeting the object."""
        proj = self.points @ kin.unit(psi)
        k = int(np.argmin(proj))
        return float(proj[k]), self.points[k], bool(self.on_curve[k])

    def model(self, workspace) -> ObjectModel:
        m = ObjectModel(workspace.center_mm, workspace.radius_mm)
        psis = np.radians(np.arange(-180.0, 180.0, STEP_DEG))
        m.add(psis, [self.contact(float(p))[0] for p in psis])
        return m


def reach(config, exact: ExactObject, settings: ExploreSettings) -> list[tuple[float, str]]:
    """Every (ψ, finger) the planner could roll at on the curved part, by increasing ψ."""
    model = exact.model(config.workspace)
    out = []
    for psi in np.radians(np.arange(-180.0, 180.0, STEP_DEG)):
        if not all(exact.contact(float(a))[2] for a in roll_angles(psi, settings.roll_span_rad, 5)):
            continue
        for f in config.fingers:
            if feasible(f, model, float(psi), settings):
                out.append((float(psi), f.name))
                break
    return out


def exact_touch(config, exact: ExactObject, finger: str, psi: float, settings: ExploreSettings) -> FeltTouch:
    """A roll of ``finger`` about ψ on the exact tangents, each reading rounded to whole ticks."""
    f = config.finger(finger)
    samples = []
    for i, a in enumerate(roll_angles(psi, settings.roll_span_rad, settings.samples_per_touch)):
        _, p, _ = exact.contact(float(a))
        ticks = np.rint(kin.angles_to_ticks(f.joints, kin.ik_tangent(f, p, float(a), margin_rad=LIMIT_MARGIN_RAD)))
        samples.append(Sample(reading=i, psi=float(a), ticks=ticks,
                              line=kin.finger_pad_line_from_ticks(config, finger, ticks), current_ma=None,
                              robot_time=0.0))
    return feel(config, TouchResult(finger, 0, psi, samples), settings.samples_per_touch)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("scene")
    ap.add_argument("--config", default="config/jaw.yaml")
    ap.add_argument("--touches", type=int, nargs="+", default=[5, 8])
    ap.add_argument("--profile", default="balanced")
    args = ap.parse_args(argv)
    try:
        raw = read_yaml(args.scene, "scene")
        scene = load_scene(raw)
        if scene.object is None or not scene.object.finite:
            raise InputError(f"{args.scene}: needs a finite object (object with extent)")
        config = load_config(args.config)
        settings = ExploreSettings.from_profile(args.profile)
    except InputError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    exact = ExactObject(scene.object)
    where = reach(config, exact, settings)
    if not where:
        print("no roll of either pad stays on the curved part")
        return 0
    obj = scene.object
    curve = obj.curve()
    ends = np.degrees(np.asarray(curve.tangent_angle(np.array(obj.extent)), float) + obj.pose.theta)
    print(f"{args.scene}: the curve's tangent turns {abs(math.remainder(math.radians(ends[1] - ends[0]), 2 * math.pi)) * 180 / math.pi:.1f} deg "
          f"over its extent; the planner reaches roll centres {math.degrees(where[0][0]):.1f} ... "
          f"{math.degrees(where[-1][0]):.1f} deg of pad normal ({len(where)} every {STEP_DEG:g} deg, fingers "
          f"{', '.join(sorted({f for _, f in where}))}; a roll covers ±{math.degrees(settings.roll_span_rad) / 2:g} deg)")
    recognize = make_recognizer(raw, settings, reach=workspace_reach(config))
    print(f"| touches | answer | parameters ± σ | runner-up (χ²) | decisive? ({args.profile}) |")
    print("|---|---|---|---|---|")
    for n in args.touches:
        pick = np.unique(np.rint(np.linspace(0, len(where) - 1, n)).astype(int))
        felt = [exact_touch(config, exact, where[i][1], where[i][0], settings) for i in pick]
        felt = [t for t in felt if t.problem is None]
        try:
            rec, why = decide(recognize, felt, settings)
        except InputError as exc:  # too few touches at distinct places for the scene's classes
            print(f"| {len(felt)} | — | — | — | no: {exc} |", flush=True)
            continue
        params = ", ".join(f"{k} {v:.4g} ± {100 * rec.uncertainty.get(k, math.nan) / abs(v):.1f} %"
                           for k, v in rec.params.items())
        ranked = [r for r in rec.ranking if r.consistent]
        best = next((r for r in ranked if r.cls == rec.cls), None)
        runner = next((r for r in ranked if r.cls != rec.cls), None)
        rival = "—" if runner is None else f"{runner.cls} ({runner.chi2:.1f} vs {best.chi2 if best else math.nan:.1f})"
        print(f"| {len(felt)} | {rec.cls} | {params or '—'} | {rival} | {'yes' if why is None else why} |", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
