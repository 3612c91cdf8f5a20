"""The exploration's stopping rule: is the recognizer's answer on the touches so far
decisive (:func:`indecision`), and the answer once exploration ends (:func:`final_answer`:
the class when decisive, else ``unclassified`` with the reason). docs/exploration.md."""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any, Callable, Sequence

import numpy as np
from scipy import stats

from recognizer.class_limits import LIMIT_OF
from recognizer.classify import chi2_limit
from recognizer.profiles import DEFAULT_PROFILE, PROFILES
from recognizer.result import Recognition
from tactile_common.errors import InputError
from tactile_jaw.end_sample import EndDeletion, Refeel, corner_end
from tactile_jaw.flat import same_face
from tactile_jaw.separation import answer_ts, departing_gap, expected_gap, finer_ticks, is_rolling, round_up
from tactile_jaw.settings import ExploreSettings

#: a consistent rival class whose χ² exceeds the answer's by this much (likelihood ratio
#: e^-5, "very strong" evidence on Kass & Raftery's scale) no longer keeps exploration going
DECISIVE_CHI2 = 10.0
#: a simpler answer is decisive only while every richer consistent class's χ² gain stays
#: below the χ²_Δk limit at this level (rule (a)): looser than the recognizer's consistency
#: alpha (1e-3), since here a false alarm costs one more touch, a miss a wrong class. Random
#: hyperbola 96 of bench_explore --finite 20 --seed 13 (a = b = 11.2 mm, touched near its
#: vertex) was answered parabola with the hyperbola 10.81 better on one parameter (the limit
#: at 1e-3 is 10.83); the right answers of that run gained at most 0.40 (parabola, Δk 1),
#: 5.68 (circle, Δk 2) and 0.07 (line, Δk 3) from a richer class, inside the limits at 0.01
#: (6.63, 9.21, 11.34)
DECISIVE_ALPHA = 0.01
#: (answer, rival): the answer is a special case or a limit of the rival (the recognizer's
#: one definition, recognizer.class_limits.LIMIT_OF: a circle of ellipses, a parabola of
#: ellipses, hyperbolas and both cubic families — far from the cubical's inflection or the
#: semicubical's cusp an arc of either tends to a parabola's: the semicubical fitted to the
#: parabola example's touches, a = 0.48, b = 4.3 at t ≈ −6, χ² 51.09 against the parabola's
#: 51.14 on 140 dof —, a line of every curved class). The richer rival always fits at least
#: as well, so its χ² being close is no evidence against the answer: rule (a), the
#: likelihood ratio, decides, once the answer is stable (and a parabola was felt on both
#: sides of its vertex: :func:`vertex_sides`). (Only circle → ellipse until #10's first
#: version: a parabola answer could never be decisive.)
SUBMODELS = frozenset((answer, rival) for answer, rivals in LIMIT_OF.items() for rival in rivals)
#: a parabola answer with a richer rival it is a limit of as close (``SUBMODELS``: an
#: ellipse, a hyperbola, a cubic) needs touches reaching at least this tangent turn (deg) on
#: each side of its vertex: a parabola's curvature falls off alike on both sides
#: (κ₀ cos³α), while on one side only a branch of a semicubical (its curvature growing
#: monotonically toward the cusp), a cubical's hump or a quarter of a long ellipse looks
#: the same (a random hyperbola of bench_explore --finite 3 --seed 2, felt 42° and 19°
#: either side, was refused by this check alone: its parabola was stable and decisive else).
#: Measured on the example scenes' touches (re-recognized from the logs): the parabola felt
#: 28–35° either side of the fitted vertex (its moved, turned, resized variants 26.6–39.7°);
#: the semicubical, answered parabola, 46–48° on one side and 16–17° on the other. At 20°,
#: touches reaching toward its cusp's corner made semicubicals decisive parabolas: the
#: example itself once its short side was aimed at (tactile_jaw.choose: 22° reached) and its
#: variants moved 3–5 mm or resized 1.1× (20.6–22.8°): the object ends about 21–23° past the
#: fitted vertex, so 25° leaves that margin; the aimed touch then meets the corner.
VERTEX_SIDE_DEG = 25.0
#: what an answer of a jaw that states no calibration (hand_driver.config.states_calibration)
#: does not hold. On the P-series jaw's zeros off by 0.06–0.12° (config/jaw-p-truth.yaml, a
#: tick 3.6e-4°) uncalibrated, circle 22 of bench_explore seed 283 was answered ellipse (a
#: 17.331, b 17.256 for r 17.319) with only the base joints' zero errors simulated, and no
#: class fitted with all of them (circles 22, 24, 34): a zero error is common to every touch
#: of its finger, a bias no stated noise of the readings holds (docs/estimation.md)
UNCALIBRATED = ("σ's hold the readings' noise only: the jaw config states no calibration (no joint's zero_sigma_deg), "
                "so its joints' zero errors are in none of them and may make no class fit, or another one; "
                "calibrate the jaw first (tactile calibrate)")
#: an answer is decisive only once every shape parameter's standard deviation is at most
#: the profile's ``decisive_rel_sigma`` of its magnitude (of max(|p|, 1) for the
#: dimensionless ``DIMENSIONLESS``; a run without a profile: balanced's). ``fast`` (5 samples
#: over 12°) states a, b of the default and ellipse examples at ±3.1–3.7 % after its whole
#: budget: at 2 % it refused both (24.5 / 23.3 s) and was slower than balanced; the user who
#: picks it takes a looser answer (5 %)
DIMENSIONLESS = frozenset({("cubical_parabola", "c"), ("semicubical_parabola", "b")})
#: (limit, richer class): the member of the richer class :func:`inseparable` holds the answer
#: against (tactile_jaw.separation.DEPART_FRACTION, recognizer.nested), for its reason
DEPARTURE = {("parabola", "ellipse"): "the end of its minor axis at the touched stretch's half-width",
             ("parabola", "hyperbola"): "its semi-axis b the touched stretch's half-width",
             ("parabola", "cubical_parabola"): "its inflection at the touched stretch's half-width",
             ("parabola", "semicubical_parabola"): "its cusp at the touched stretch's half-width",
             ("circle", "ellipse"): "axes 2:1"}

RecognizeTouches = Callable[..., Recognition]
#: how a refusal says that a jaw with finer angles would settle it (:func:`finer_advice`,
#: :func:`imprecision`), and what :func:`refusal_kind` looks for
FINER = "a jaw with >="
#: the family-wise false-alarm rate of leaving one touch out as the misfit (:func:`without_misfit`),
#: and one roll's end sample as on the end corner (:func:`without_corner_end`)
MISFIT_ALPHA = 1e-3
#: what a refusal asks of a person (:func:`refusal_kind`): move the object where a pad can
#: reach the deciding place; a jaw with finer angles; another placement or exploration; or
#: nothing it can do by moving the object: no class of the scene fits the touches
REFUSAL_KINDS = ("out of reach", "needs finer angles", "needs another move", "no class fits")
#: how the recognizer begins the reason of an answer no class fits (recognizer.classify)
NO_CLASS_FITS = "no class of the scene fits"
#: what keeps an answer from being decisive (:class:`Why`): no class fits; a richer class
#: fits significantly better; a rival fits as well; the answer changed with the last touch
#: (or was not yet checked with one fewer); a parabola felt on one side of its vertex only;
#: parameters not yet determined; a rival the touches of this jaw cannot tell apart however
#: many the budget allows (:func:`inseparable`); a class of the scene too few usable touches
#: (distinct places) could test. The exploration picks its next touch by it
#: (tactile_jaw.choose)
KINDS = ("unclassified", "better", "rival", "unstable", "vertex", "imprecise", "resolution", "untested")


class Why(str):
    """Why an answer is not decisive: the sentence for people, with its ``kind`` (``KINDS``)
    and the ``rival`` class that fits as well, when one does."""

    kind: str
    rival: str | None

    def __new__(cls, message: str, kind: str, rival: str | None = None) -> "Why":
        if kind not in KINDS:
            raise ValueError(f"unknown kind of indecision {kind!r}")
        out = super().__new__(cls, message)
        out.kind = kind
        out.rival = rival
        return out


def indecision(recognition: Recognition, shorter: Recognition | None, settings: ExploreSettings,
               touched: tuple[np.ndarray, np.ndarray] | None = None, ticks_per_rev: int | None = None) -> Why | None:
    """Why a class answer is not yet decisive, or None when it is. ``recognition`` is on
    every usable touch, ``shorter`` on all but the last (None if too few), ``touched`` the
    touches' sample positions (x, y) (None: unknown). Decisive: (a) no
    consistent class with more free parameters fits significantly better (likelihood ratio:
    Δχ² below the χ²_Δk limit at ``DECISIVE_ALPHA``); (b) every other consistent class
    is ruled out by the data, its χ² ``DECISIVE_CHI2`` above the answer's, except a class
    the answer is a special case or limit of (``SUBMODELS``: a circle is an ellipse with
    a = b, a parabola the limit of ellipses and hyperbolas), for which (a) decides once the
    answer is stable, the same class without the last touch, and, for a parabola, it was
    felt ``VERTEX_SIDE_DEG`` on both sides of its vertex; (c) its shape parameters are determined (:func:`imprecision`). A class the
    answer is only a limit of (a parabola of long ellipses and hyperbolas) or that fits as
    well is no evidence either way: BIC's parameter penalty alone would always pick the
    limit. Last, (d): every class of the scene was tested (:func:`untested_rivals`; checked
    last, so an answer undecided for another reason aims its next touch by that reason)."""
    ranked = [r for r in recognition.ranking if r.consistent]
    best = next(r for r in ranked if r.cls == recognition.cls)
    for r in ranked:
        dk = best.dof - r.dof  # same observations: Δdof = Δ free parameters
        if dk > 0 and best.chi2 - r.chi2 > chi2_limit(DECISIVE_ALPHA, dk):
            return Why(f"{r.cls} fits significantly better than {best.cls} (chi2 {r.chi2:.3g} vs {best.chi2:.3g})",
                       "better")
    rivals = [r for r in ranked if r.cls != recognition.cls and r.chi2 - best.chi2 < DECISIVE_CHI2]
    others = [r for r in rivals if (recognition.cls, r.cls) not in SUBMODELS]
    if others:
        runner = min(others, key=lambda r: r.chi2)
        return Why(f"{best.cls} (chi2 {best.chi2:.1f}) and {runner.cls} (chi2 {runner.chi2:.1f}) both "
                   f"fit, less than {DECISIVE_CHI2:g} apart: the touches cannot tell them apart", "rival", runner.cls)
    if rivals and (shorter is None or shorter.cls != recognition.cls):
        return Why(f"{best.cls} and {rivals[0].cls} both fit and the answer "
                   + ("changed with the last touch" if shorter is not None else "was not yet checked with one touch fewer"),
                   "unstable")
    richer = next((r for r in rivals if best.cls == "parabola" and (best.cls, r.cls) in SUBMODELS), None)
    if richer is not None:
        sides = vertex_sides(recognition, touched) if touched is not None else (0.0, 0.0)
        if min(sides) < VERTEX_SIDE_DEG:
            return Why(f"{best.cls} and {richer.cls} both fit and the touches reach {sides[0]:.0f} and {sides[1]:.0f} "
                       f"deg either side of the parabola's vertex (less than {VERTEX_SIDE_DEG:g} on one side, where an "
                       f"arc of the {richer.cls} looks like a parabola's)", "vertex")
    loose = imprecision(recognition, settings.profile, ticks_per_rev)
    return loose if loose is not None else untested_rivals(recognition)


def untested_rivals(recognition: Recognition) -> Why | None:
    """Why a curved answer is not decisive while a class of the scene was not tested (the
    recognizer's ``untested``: fewer usable touches at distinct places than the class has
    free invariants to fit, recognizer.touches.MIN_TOUCHES), or None. Such a class is not
    ruled out, only unseen: with no spare degree of freedom it fits those touches exactly,
    so they cannot tell it from the answer (a P-series semicubical, moved as its refusal advised, answered parabola from its 2 usable
    touches of 18, every richer class untested). A line answer is exempt: on the jaw it
    comes from pads pressed flat on one face (tactile_jaw.flat), whose seat over the pad's
    length rules out a curve of any class (a roll on a face pivots on its corners and is never
    usable)."""
    if recognition.cls == "line" or not recognition.untested:
        return None
    why = "; ".join(f"{cls} {reason}" for cls, reason in recognition.untested.items())
    return Why(f"{recognition.cls} fits, but too few usable touches test the scene's other classes ({why})",
               "untested")


def vertex_sides(recognition: Recognition, touched: tuple[np.ndarray, np.ndarray]) -> tuple[float, float]:
    """How far (deg of tangent turn) the touched positions reach on either side of a
    parabola answer's vertex: the canonical parabola (a t², 2a t) turns by atan(t) from its
    vertex, t = y/(2a) in its own frame."""
    _, cy = recognition.pose.inverse(*touched)
    turn = np.degrees(np.arctan(np.asarray(cy, float) / (2.0 * recognition.params["a"])))
    return max(-float(turn.min()), 0.0), max(float(turn.max()), 0.0)


def imprecision(recognition: Recognition, profile: str | None = None, ticks_per_rev: int | None = None,
                target: bool = False) -> Why | None:
    """Why the answer's shape parameters are not yet determined (a standard deviation above
    the profile's ``decisive_rel_sigma`` of the parameter's magnitude; with ``target``, above
    its ``target_rel_sigma``, which only keeps a decisive exploration touching), or None. Touches that all see one
    short arc fit one class decisively yet leave its parameters loose (an ellipse from 30°
    of its boundary: a ±4 %, b ±9 %), and their errors along the pad are correlated, so such
    an answer can be off by far more than its stated deviation: explore on instead. With the
    jaw's ``ticks_per_rev``, the reason says at which resolution the same touches would
    state them within the limit (every σ is the ticks' quantization, so it shrinks as one
    tick; a jaw with ≥ N ticks per turn, 3 significant digits)."""
    chosen = PROFILES.get(profile or DEFAULT_PROFILE, PROFILES[DEFAULT_PROFILE])
    rel = chosen.target_rel_sigma if target else chosen.decisive_rel_sigma
    loose, worst = [], 0.0
    for name, value in recognition.params.items():
        sd = recognition.uncertainty.get(name)
        if sd is None:
            continue
        ref = max(abs(value), 1.0) if (recognition.cls, name) in DIMENSIONLESS else abs(value)
        if not (math.isfinite(sd) and sd <= rel * ref):
            finite = ref > 0 and math.isfinite(sd)
            loose.append(f"{name} ±{100.0 * sd / ref:.2g} %" if finite else f"{name} undetermined")
            worst = max(worst, sd / (rel * ref) if finite else math.inf)
    if loose:
        advice = ""
        if ticks_per_rev is not None and math.isfinite(worst):
            need = round_up(ticks_per_rev * worst)
            advice = (f": this jaw's angle resolution ({ticks_per_rev:,} ticks per turn) leaves them so; {FINER} "
                      f"{need:,} ticks per turn states them within {100 * rel:g} %")
        return Why(f"{recognition.cls} parameters not yet within {100 * rel:g} %: {', '.join(loose)}{advice}",
                   "imprecise")
    return None


def decide(recognize_touches: RecognizeTouches, touches: Sequence[Any], settings: ExploreSettings,
           ticks_per_rev: int | None = None, refeel: Refeel | None = None,
           emit: Callable[[dict], None] | None = None):
    """(Recognition, why it is not decisive or None): :func:`indecision` on the recognizer's
    answer on ``touches`` (and on all but the last, when it needs that), then, for an answer
    so far decisive, :func:`inseparable` (``ticks_per_rev``: the jaw's encoder resolution,
    for its advice). With ``refeel`` (tactile_jaw.pipeline.feel of the jaw's config), a
    decisive answer's used rolls' end samples are tested (:func:`without_corner_end`): one on
    the object's end corner is left out (its event to ``emit``) and the answer decided again."""
    recognition, why, touches = _decided(recognize_touches, touches, settings, ticks_per_rev)
    if why is None and refeel is not None:
        trimmed = without_corner_end(recognize_touches, touches, recognition, refeel)
        if trimmed is not None:
            deletion, touches = trimmed
            if emit is not None:
                emit(deletion.event())
            recognition, why, touches = _decided(recognize_touches, touches, settings, ticks_per_rev)
            note = deletion.note()
            recognition = replace(recognition, reason=f"{recognition.reason}; {note}" if recognition.reason else note)
    return recognition, why


def without_corner_end(recognize_touches: RecognizeTouches, touches: Sequence[Any], recognition: Recognition,
                       refeel: Refeel) -> tuple[EndDeletion, list] | None:
    """(the end sample left out, the touches with its roll felt without it) or None:
    tactile_jaw.end_sample.corner_end at the family-wise false-alarm rate ``MISFIT_ALPHA``
    over the tested ends. On session 30's and 31's held-out P logs its z's of 992 on-curve
    ends lay within −2.62 … +3.06 (none past the one-sided 10⁻³ limit 3.09), the corner end
    of semicubical 131 (finite 499) at +4.08 against 3.48 for its 4 tested ends
    (docs/exploration.md)."""
    return corner_end(recognize_touches, touches, recognition, refeel, MISFIT_ALPHA)


def _decided(recognize_touches: RecognizeTouches, touches: Sequence[Any], settings: ExploreSettings,
             ticks_per_rev: int | None) -> tuple[Recognition, Why | None, Sequence[Any]]:
    """:func:`decide` without the end-sample test: (the answer, why it is not decisive or
    None, the touches it is on)."""
    recognition = recognize_touches(touches)
    if recognition.cls == "unclassified":
        left_out = without_misfit(recognize_touches, touches, recognition, settings)
        if left_out is None:
            return recognition, Why(recognition.reason or "no class fits", "unclassified"), touches
        recognition, touches = left_out
    shorter = None
    if len(touches) > settings.min_touches or repeats_a_face(touches):
        try:
            shorter = recognize_touches(touches[:-1])
        except InputError:
            shorter = None
    why = indecision(recognition, shorter, settings, sample_positions(touches), ticks_per_rev)
    if why is None:
        why = inseparable(recognize_touches, recognition, touches, ticks_per_rev, settings.touches)
    return recognition, why, touches


def repeats_a_face(touches: Sequence[Any]) -> bool:
    """Is the last of ``touches`` a flat press of a face an earlier one pressed
    (tactile_jaw.flat.same_face)? Then the touches without it touch the same places
    (recognizer.contacts.Contacts.places: a repeated place tells that place more precisely,
    never a second one), so :func:`decide` checks the answer with one touch fewer as soon
    as the profile's ``min_touches`` are felt, not one press later: a line from one face's
    presses was decisive only after a fourth press (about 3 s of robot time) that could
    not change which places were touched."""
    face = getattr(touches[-1], "face", None) if touches else None
    return face is not None and any(getattr(t, "face", None) is not None and same_face(t.face, face)
                                    for t in touches[:-1])


def without_misfit(recognize_touches: RecognizeTouches, touches: Sequence[Any], recognition: Recognition,
                   settings: ExploreSettings) -> tuple[Recognition, list] | None:
    """(the answer, the touches it is on) without the one touch no class of the scene fits
    together with the others, or None. When no class fits (``recognition``), the closest
    class (its ranking's first row) is fitted to the touches without each one in turn; the
    touch whose leaving out lowers its χ² the most significantly, beyond the χ² limit of
    the degrees of freedom it took at ``MISFIT_ALPHA`` over the number of touches
    (Bonferroni), is left out, if at least ``settings.min_touches`` remain and the
    recognizer answers a class on them. A roll that ran a degree past the object's end
    pivots on its corner in its last reading: a polynomial support function of that roll
    follows the kink in d'' (2.5 µm over 17 mrad on a radius of 17 mm, 10 of the P-series
    lines' deviations) and shifts every contact of the touch by 1–64 µm, so the touch passes
    every test of its own (tactile_jaw.pipeline.feel) while no class fits it with the rest
    (random semicubical 26 of bench_explore --finite 4 --anywhere --seed 83 --config
    config/jaw-p.yaml: χ² 101.6 on 33 dof from the truth, 57.4 of it that touch's)."""
    if not (recognition.reason or "").startswith(NO_CLASS_FITS) or not recognition.ranking \
            or len(touches) <= settings.min_touches:
        return None
    closest = recognition.ranking[0]
    limit = MISFIT_ALPHA / len(touches)
    best = None  # (p-value, index, the touches without it)
    for j in range(len(touches)):
        rest = [t for i, t in enumerate(touches) if i != j]
        try:
            fit = recognize_touches(rest, classes=(closest.cls,))
        except InputError:
            continue
        row = next((r for r in fit.ranking if r.cls == closest.cls), None)
        if row is None or closest.dof <= row.dof or not math.isfinite(row.chi2):
            continue
        p = float(stats.chi2.sf(closest.chi2 - row.chi2, closest.dof - row.dof))
        if p < limit and (best is None or p < best[0]):
            best = (p, j, rest)
    if best is None:
        return None
    p, j, rest = best
    answer = recognize_touches(rest)
    if answer.cls == "unclassified":
        return None
    note = (f"{_touch_name(touches[j], j)} left out: no class of the scene fits it with the others "
            f"({closest.cls} chi2 {closest.chi2:.3g} on {closest.dof} dof with it, p = {p:.2g} that leaving it "
            f"out gains this much by chance)")
    return replace(answer, reason=f"{answer.reason}; {note}" if answer.reason else note), rest


def _touch_name(touch: Any, index: int) -> str:
    """How a note names a usable touch: its finger and number when it has them."""
    felt = getattr(touch, "touch", None)
    if felt is not None and hasattr(felt, "finger"):
        return f"{felt.finger}: touch {felt.touch}"
    return f"usable touch {index + 1}"


def inseparable(recognize_touches: RecognizeTouches, recognition: Recognition, touches: Sequence[Any],
                ticks_per_rev: int | None = None, budget: int = 0) -> Why | None:
    """Why an answer that is a limit of a richer class of the scene (``SUBMODELS``: a
    parabola of the ellipse, the hyperbola and both cubic families, a circle of the
    ellipse) is not decisive though the richer class fits no better: a member of that class
    whose own shape shows within the touched stretch (tactile_jaw.separation.departing_gap:
    its inflection, cusp or far vertex at the stretch's half-width) would fit these touches
    within ``DECISIVE_CHI2`` of the answer, so the touches cannot tell the two apart and the
    answer could be that member's limit by chance (random cubical 102 of bench_explore
    --finite 20 --seed 13, moved as its refusal advised: its hump felt 29° and 38° either
    side, answered parabola with every class within 0.1 in χ²; a cubical departing there
    reaches Δχ² 5.6, a semicubical 0.3). The reason says which jaw resolution would tell
    them apart (Δχ² grows as the square of the ticks per turn:
    tactile_jaw.separation.finer_ticks). Kind ``rival`` while touches up to the ``budget``,
    each adding its share of the gap, could reach ``DECISIVE_CHI2``, else ``resolution``
    (exploration stops: this jaw cannot tell them apart). None when every such member is
    ruled out."""
    present = {r.cls for r in recognition.ranking}
    gaps = {rival: departing_gap(recognize_touches, recognition, touches, rival)
            for rival in sorted(LIMIT_OF.get(recognition.cls, frozenset()) & present)}
    close = {rival: gap for rival, gap in gaps.items() if gap is not None and gap < DECISIVE_CHI2}
    if not close:
        return None
    rival = min(close, key=close.get)  # the hardest to tell apart: its resolution tells every other too
    gap = close[rival]
    # each touch adds its own share of the expected gap: the whole budget's touches alike
    # would bring it to gap × budget / touches so far
    reachable = gap * max(budget, len(touches)) / max(len(touches), 1)
    kind = "rival" if reachable >= DECISIVE_CHI2 else "resolution"
    advice = finer_advice(gap, ticks_per_rev)
    return Why(f"{recognition.cls} and {rival} both fit: a {rival} with {DEPARTURE[recognition.cls, rival]} "
               f"would fit these touches as well (expected chi2 gap {gap:.2g}, less than "
               f"{DECISIVE_CHI2:g}){advice.clause() if advice else ''}", kind, rival)


def rivals_gap(recognize_touches: RecognizeTouches, recognition: Recognition, touches: Sequence[Any],
               rival: str) -> float | None:
    """The expected Δχ² between the answer's fit and the ``rival`` class's own fit to the same
    touches (tactile_jaw.separation.expected_gap, each taken as the truth in turn, the
    smaller): what these touches could tell them apart by. None for flat touches or when a
    fit has no contacts."""
    try:
        other = recognize_touches(touches, classes=(rival,))
    except InputError:
        return None
    gaps = []
    for truth, against in ((recognition, rival), (other, recognition.cls)):
        ts = answer_ts(truth, touches) if truth.cls != "unclassified" and is_rolling(touches) else None
        if ts is None:
            return None
        gaps.append(expected_gap(recognize_touches, touches, truth.cls, truth.params, truth.pose, ts, against))
    return min(gaps)


def beyond_resolution(recognize_touches: RecognizeTouches, recognition: Recognition, why: Why,
                      touches: Sequence[Any], budget: int) -> bool:
    """Whether the rival that keeps the answer from being decisive (``why``) is one the
    touches where they were cannot tell apart however many the ``budget`` allows: kind
    ``resolution`` (:func:`inseparable`), or a ``rival`` whose expected Δχ² on these touches
    (:func:`rivals_gap`), each touch up to the budget adding its share, stays below
    ``DECISIVE_CHI2`` (random X-series ellipses 45 and 55 of bench_explore --finite 20
    --anywhere --seed 199: one finger rolled on one end, expected gaps 0.57 and 0.29 after 7
    touches, observed χ² gaps 0.2–7.4). Then only other places, not more of the same, decide
    (tactile_jaw.choose.other_side_stop)."""
    if why.kind == "resolution":
        return True
    if why.kind != "rival" or why.rival is None or not touches:
        return False
    gap = rivals_gap(recognize_touches, recognition, touches, why.rival)
    return gap is not None and gap * max(budget, len(touches)) / len(touches) < DECISIVE_CHI2


@dataclass(frozen=True)
class FinerAdvice:
    """What an expected Δχ² ``gap`` between two fits says about telling them apart
    (:func:`finer_advice`): ``need``, the encoder resolution (ticks per turn) at which it
    reaches ``DECISIVE_CHI2`` (None: no resolution does, the fits are one curve); ``more``,
    how many more usable touches like the ``touches`` it came from are expected to reach it
    when they are borderline (0: not borderline)."""

    gap: float
    ticks_per_rev: int
    need: int | None
    touches: int
    more: int

    @property
    def borderline(self) -> bool:
        """At most as many touches again, each adding its share of the gap, would decide."""
        return self.more > 0

    def clause(self, state_gap: bool = False) -> str:
        """The clause a refusal appends; with ``state_gap`` it states the gap in every case
        (the borderline wording does so itself), for a reason that does not state it before."""
        gap = f"expected chi2 gap {self.gap:.2g}"
        if self.borderline:
            return (f": {self.touches} usable touches come close ({gap} of the {DECISIVE_CHI2:g} that decides; "
                    f"each touch adds its share): about {self.more} more like them "
                    f"{'is' if self.more == 1 else 'are'} expected to tell them apart, as {FINER} {self.need:,} "
                    f"ticks per turn would")
        if self.need is None:
            text = ": no encoder resolution tells them apart on these touches"
        elif self.need <= self.ticks_per_rev:
            text = ""  # these touches could tell them apart: more touches may
        else:
            text = (f": both fit within this jaw's angle resolution ({self.ticks_per_rev:,} ticks per turn); "
                    f"{FINER} {self.need:,} ticks per turn tells them apart")
        return f"{text} ({gap})" if state_gap else text


def finer_advice(gap: float, ticks_per_rev: int | None, touches: int = 0) -> FinerAdvice | None:
    """What an expected Δχ² ``gap`` needs to reach ``DECISIVE_CHI2``: the encoder resolution
    (tactile_jaw.separation.finer_ticks), and, when the ``touches`` it came from are
    borderline — each adds its share of the gap, and at most as many again would reach
    ``DECISIVE_CHI2`` — how many more usable touches like them are expected to, said before
    the resolution (held-out X ellipse 59 of seed 241: gap 8.5 on 3 touches, "a jaw with >=
    4,460 ticks per turn" beside this jaw's 4,096). None without the jaw's resolution."""
    if ticks_per_rev is None:
        return None
    need = finer_ticks(gap, ticks_per_rev, DECISIVE_CHI2)
    more = 0
    if need is not None and need > ticks_per_rev and touches:
        more = math.ceil(touches * (DECISIVE_CHI2 / gap - 1.0) - 1e-9)
        more = more if more <= touches else 0
    return FinerAdvice(gap, ticks_per_rev, need, touches, more)


def sample_positions(touches: Sequence[Any]) -> tuple[np.ndarray, np.ndarray] | None:
    """Every sample position (x, y) of felt touches (tactile_jaw.pipeline.FeltTouch: a rolling
    touch's samples, a flat press's one contact); None for touches without samples."""
    samples = [getattr(t, "samples", None) for t in touches]
    if not samples or any(s is None for s in samples):
        return None
    return (np.concatenate([np.atleast_1d(np.asarray(s.x, float)) for s in samples]),
            np.concatenate([np.atleast_1d(np.asarray(s.y, float)) for s in samples]))


def final_answer(recognize_touches: RecognizeTouches, touches: Sequence[Any], settings: ExploreSettings,
                 stopped: str | None = None, ticks_per_rev: int | None = None, refeel: Refeel | None = None,
                 emit: Callable[[dict], None] | None = None) -> Recognition:
    """The answer on the usable touches once exploration ends: the recognizer's class when
    it is decisive (:func:`decide`), else ``unclassified`` with the reason (and ``stopped``,
    why exploration ended undecided and what a person can do, tactile_jaw.choose) and the
    recognizer's ``next_touch``; a wrong class said confidently is worse than a refusal.
    Replay uses this on the logged touches (and the log's ``stopped_early`` or ``budget_spent``
    event). ``refeel`` and ``emit``: :func:`decide`'s end-sample test. The jaw's calibration
    note is :func:`noted`'s, on every answer."""
    recognition, why = decide(recognize_touches, touches, settings, ticks_per_rev, refeel, emit)
    if recognition.cls == "unclassified" or why is None:
        return recognition
    if why.kind == "rival" and why.rival is not None and ticks_per_rev is not None:
        gap = rivals_gap(recognize_touches, recognition, touches, why.rival)
        if gap is not None:
            finer = finer_advice(gap, ticks_per_rev, len(touches)).clause(state_gap=True)
            why = Why(f"{why}{finer}", why.kind, why.rival)
    reason = f"not decisive after {len(touches)} usable touches: {why}" + (f"; {stopped}" if stopped else "")
    return Recognition("unclassified", reason=reason, ranking=recognition.ranking, timing=recognition.timing,
                       next_touch=recognition.next_touch)


def noted(reason: str | None, calibrated: bool) -> str | None:
    """An answer's ``reason`` as the jaw gives it: a jaw that states no calibration
    (``calibrated`` False: hand_driver.config.states_calibration) ends every answer's reason
    with ``UNCALIBRATED`` — a class, the recognizer's refusal, or the exploration's own
    (too few usable touches, a curved part felt but not measured). The one place that decides
    the note, for the exploration (tactile_jaw.explore.closing_answer) and replay alike."""
    if calibrated:
        return reason
    return f"{reason}; {UNCALIBRATED}" if reason else UNCALIBRATED


def refusal_kind(reason: str, move: dict | None = None) -> str:
    """What a refusal (its ``reason``, and the ``move`` its stop event names, if any) asks
    of a person (``REFUSAL_KINDS``): out of reach when it names a move of the object after
    which a pad rolls where the deciding touch goes (tactile_jaw.choose) — first: a move
    this jaw can make is the more actionable advice, and a reason that also names a finer
    resolution says both; finer angles when it names a resolution that would settle it
    (:func:`finer_advice`, :func:`imprecision`); out of reach when no pad can roll where the
    deciding touch goes; no class fits when the recognizer found none consistent
    (``NO_CLASS_FITS``: no move is advised then); else another move or placement of the object."""
    if reason.startswith(NO_CLASS_FITS):
        return "no class fits"
    if move is not None:
        return "out of reach"
    if FINER in reason:
        return "needs finer angles"
    if "no pad can roll" in reason:
        return "out of reach"
    return "needs another move"
