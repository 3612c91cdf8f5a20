"""The flat press: seat a pad flat on a straight face of the object and press it there
(docs/driver.md#flat-press).

A pad cannot roll on a flat face: turned, it pivots about one of its ends resting on the
face or about a corner of the face under it. What a guarded approach at pad normal ψ
measures is the support d(ψ) of what the pad can reach (hand_driver.motion); over a
straight face between supports P and Q it is min(n(ψ)·P, n(ψ)·Q): the pad lines pass
through P on one side of the face's normal ψ_f and through Q on the other, and the pad
lies flat at ψ_f. The press finds that kink from any start the finger can turn from:

1. Guarded approaches at ψ_start + k·``FLAT_STEP_DEG``, k = 0, then ±1 (``first_turn``).
2. Each further approach goes where the seat is: the two newest lines at each end of the
   turned range cross at the point the pad pivots about (``kinematics.crossing``); turning about it
   brings the longer part of the pad down (:func:`lowering_turn`). Pad lines through P
   lower toward the seat, those through Q too (from the other side): the range grows on
   the side the seat lies beyond, and once it lies between the ends, on the side with
   fewer lines through its support. A pivot over the middle of the pad (a corner with
   faces either side) may lower the wrong face first: at ``FLAT_MAX_TURN_DEG`` or the
   joint limits that way, the range grows the other way (where the object blocks that turn
   back and backing off is beyond the finger, back along the scan's own stops:
   :func:`_press_across`). Where a whole step would pass
   a joint limit, the range grows by part of one (``FILL_PARTS``), and when it cannot grow
   at all its outermost gap is halved: a seat close to the limit still gets its three lines.
3. Once ≥ 3 lines pass through P and ≥ 3 through Q at least ``FACE_MIN_FRACTION`` of the
   pad apart (:func:`seat_split`), the pad is pressed at the normal of PQ (and at
   ``SEAT_PRESSES_DEG`` of it); whether those presses are seated is judged when the
   touch is felt (tactile_jaw.flat.feel_flat). Lines of the range far from the seat, where
   a pad end sliding along a long face no longer passes through one point, stay ``scan``.

A curved boundary moves the contact along the pad steadily and bulges between two
supports: it never seats, and the press ends ``no_seat``. Nothing of the scene is read:
only the servos' positions and currents, as in the guarded approach.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from hand_driver import kinematics as kin
from hand_driver.cycle import Jaw, Motion
from hand_driver.motion import ROLL_CLEARANCE_MM, ApproachResult, TouchResult, guarded_approach, move_line, turn_to

#: a flat press turns the pad in steps of this many degrees between its guarded
#: approaches. An arc that offers two supports ℓ apart bulges ~ℓ·Δψ/8 between them, Δψ ≥ 3
#: steps: with 3° steps arcs of radius 100–1000 mm stopped seated presses 0.25–0.98 mm
#: early (2° steps: from 0.15 mm, within the encoders' scatter of a flat seat)
FLAT_STEP_DEG = 3.0
#: ... at most this far (deg) either way from where it started: a block placed anywhere its
#: face lies flat under a pad (tools.random_objects) may be turned 30° and more from the
#: pad's nominal normal, and the press turns three steps past the seat (at 36°, until this
#: version, a block of bench_explore --finite 3 --anywhere --seed 11 turned 31.5° was never
#: seated: refused; at 60° seated at 31.9°, answered line); a face turned 25° is seated from
#: the nominal
FLAT_MAX_TURN_DEG = 60.0
#: a pad line passes through a support point when the point is within this (mm) of it;
#: the mean of a press's seated stops must be this close to where its two supports say
#: (tactile_jaw.flat): on 32 presses of the emulated jaw's line example 0.043 mm rms, at
#: most 0.124 (single stops 0.06 rms, at most 0.22); arcs of radius 100–1000 mm that
#: offered two supports stopped them 0.30–0.93 mm early on average (docs/driver.md#flat-press)
SEAT_TOL_MM = 0.2
#: the lines either side of a seat miss the other side's support by more than this many
#: SEAT_TOL_MM: a line 0.84° from the seat of a 34 mm face passed 0.23 mm from its own
#: support (three stops' rounding) and 0.5 mm from the other, and with 1× it was taken
#: into the wrong support, the face 1.1° off (bench_explore --finite 20 --seed 11, rand8);
#: a line that near the seat is left between the supports instead (up to two:
#: :func:`seat_split`)
SPLIT_APART = 2.0
#: the two supports of a seat are at least this fraction of the pad's length apart: the
#: lines a step (FLAT_STEP_DEG) beyond the lines nearest the seat must miss the other
#: support by SPLIT_APART · SEAT_TOL_MM, ℓ·sin(3°) > 0.4 mm, ℓ > 7.6 mm, here 10.4 mm
#: (0.54 mm). 0.35 until session 13: the short faces of the random blocks (12–30 mm, 0.23–0.58
#: of the pad) were never seated, and a face that the finger met within 45° of its nominal
#: normal was refused when its other faces lay beyond FLAT_MAX_TURN_DEG (bench_explore
#: --finite 4 --anywhere --seed 11, block 3: faces of 14.6 mm at 19°, of 36.5 mm at 71°).
#: An arc between supports ℓ apart bulges ℓ²/8R: the seat test (tactile_jaw.flat) tells it
#: from a face up to R ≈ ℓ²/(8·SEAT_TOL_MM), 68 mm at 10.4 mm, and the touch states that
#: flatness as its κ's deviation (tactile_jaw.flat.flat_curvature_sd)
FACE_MIN_FRACTION = 0.2
#: about a corner under the pad with at least this fraction of the pad either side, the part
#: turned down is the one toward the object (:func:`lowering_turn`), else the longer part
PIVOT_PART_FRACTION = 0.35
#: each support is fitted to this many pad lines, those nearest the seat: over a long face
#: a pad end resting on it slides as the pad turns, and on an arc of large radius a run
#: of pad-end lines reaching far from the seat fits a support that hides the arc's bulge
#: (radius 500 and 1000 mm turned 15° passed the seat test, 0.10 mm, with every line of
#: the run)
SUPPORT_LINES = 3
#: where a whole step would turn the joints past their limits (or FLAT_MAX_TURN_DEG), the
#: press turns by these fractions of a step instead: a seat near a joint limit leaves room
#: for fewer than the three whole steps its second support needs (bench_explore --finite 8
#: --anywhere --seed 11, block 1 turned 31.6°: its left pad seats at 31.6° from the nominal
#: normal and its joints stop at 36°, two lines through the second support; refused before)
FILL_PARTS = (1.0, 0.5, 0.25)
#: next to a seat whose second support is a pad end sliding along the face
#: (:func:`sliding_fill`), approaches at these fractions of a step from the first line beyond
#: the seat (negative: on, away from the first support; positive: back toward it), in this
#: order: the end slides ~2 mm a degree within a few degrees of the seat (random block 6 of
#: bench_explore --seed 127), where the lines resting on it miss the first support by the
#: split's margin (SPLIT_APART); back toward the first support, a line 0.75° from the seat
#: passed within that margin of both supports and made no split
SLIDE_PARTS = (-0.25, -0.5, -0.75, 0.25, 0.5, 0.75)
#: a support whose pad lines cross this close (mm) to a pad end, or beyond it, is that pad
#: end resting on the face (tactile_jaw.flat.seat_supports, :func:`better_support`): the end slides
#: along the face as the pad turns, so its lines cross up to a few mm inside the pad and up to
#: ~0.14 mm off the face, and that bias hid part of an arc's bulge (radius 1000 mm turned 15°:
#: its seated presses stopped 0.07 mm early from the crossing, 0.21 from the end). Corners
#: 5–8 mm from a pad end exist on the random blocks (taken for the end they were 0.26 mm off)
END_SUPPORT_MM = 4.0
#: the seated presses, at the seat's orientation ψ_f plus these (deg): re-pressing at a
#: slightly different goal reads the same seat through different encoder roundings
SEAT_PRESSES_DEG = (0.0, -0.1, 0.1)


@dataclass
class FlatResult(TouchResult):
    """One flat press: every guarded approach's sample with its role — ``P`` (the pad
    rested on the first support), ``Q`` (on the second), ``seat`` (a press at the seat's
    orientation), ``scan`` (none of these) — and the supports found (hand frame, mm);
    ``seek_limit_s``: the robot time (s) without a seat after which the caller's ``give_up``
    ended the press (outcome ``stopped``; tactile_jaw.flat_phase sets it), else None."""

    roles: list[str] = field(default_factory=list)
    supports: tuple[np.ndarray, np.ndarray] | None = None
    kind: str = "flat"
    seek_limit_s: float | None = None


def line_point(lines: list[kin.PadLine]) -> tuple[np.ndarray, float]:
    """The point nearest every pad line (least squares, ≥ 2 lines of distinct ψ) and the
    largest distance (mm) from it to one of them."""
    a = np.array([ln.normal for ln in lines], dtype=float)
    b = np.array([float(ln.d) for ln in lines])
    p = kin.nearest_point(a, b)
    return p, float(np.max(np.abs(a @ p - b)))


def clear_of_pad_ends(line: kin.PadLine, point: np.ndarray, length_mm: float) -> bool:
    """Whether ``point`` lies along the pad of ``line`` more than ``SEAT_TOL_MM`` from either
    end of its ``length_mm``: the pad's face there, not a pad end resting on it."""
    return SEAT_TOL_MM < float(line.pad_coordinate(np.asarray(point, dtype=float))) < length_mm - SEAT_TOL_MM


def face_normal(p: np.ndarray, q: np.ndarray, toward: np.ndarray) -> np.ndarray:
    """Unit outward normal of the face through supports ``p`` and ``q``: of the line PQ's
    two normals, the one along ``toward`` (a pad line's normal)."""
    t = (q - p) / np.linalg.norm(q - p)
    normal = np.array([-t[1], t[0]])
    return -normal if normal @ toward < 0 else normal


def _run(lines: list[kin.PadLine], start: int, step: int, tol_mm: float,
         most: int | None = None) -> tuple[int, np.ndarray, float]:
    """The longest run (at most ``most`` lines) of ``lines`` from index ``start`` in
    direction ``step`` (±1) through one point within ``tol_mm``: (its length, the point,
    its residual); length 0 if fewer than 3 lines."""
    best, n = (0, np.zeros(2), 0.0), 3
    while most is None or n <= most:
        lo, hi = (start, start + n) if step > 0 else (start - n + 1, start + 1)
        if lo < 0 or hi > len(lines):
            return best
        p, res = line_point(lines[lo:hi])
        if res > tol_mm:
            return best
        best, n = (n, p, res), n + 1
    return best


def end_support(lines: list[kin.PadLine], other: np.ndarray, tol_mm: float = SEAT_TOL_MM,
                least: int = 3) -> tuple[int, np.ndarray, float] | None:
    """A pad end resting on the face, as a seat's support: when the same end (distal, else
    proximal) of each of ≥ 3 ``lines`` (the nearest the seat first) lies within ``tol_mm`` of
    one straight line through the other support ``other``, (their count, the end of the first
    line, the largest distance), else None (``least``: fewer lines than 3 may say where to
    press next, :func:`sliding_fill`). Beyond the seat of a face that runs on past the
    pad's end the pad rests on that end, and the end slides along the face as the pad turns
    (2 mm a degree: random block 6 of bench_explore --finite 20 --anywhere --seed 127): its
    lines pass through no one point (their crossings lie a few mm inside the pad, and a point
    fitted to them 13 mm from the end tilted the face 1.4°), but the ends themselves lie on the
    face; they must have slid along it by more than SPLIT_APART · ``tol_mm`` (ends that stay
    put are one point: a corner near the pad end, :func:`_run`'s), and lie at least
    FACE_MIN_FRACTION of the pad from the other support (ends 1.5 mm from it lay within
    0.02 mm of a line through it: a seat at a corner 43 mm away was lost, X-series block 1 of
    --seed 13). Which of the two a seat takes: :func:`better_support`."""
    if len(lines) < least:
        return None
    pad = float(np.linalg.norm(np.asarray(lines[0].distal) - np.asarray(lines[0].proximal)))
    for end in ("distal", "proximal"):
        ends = np.array([getattr(ln, end) for ln in lines], dtype=float)
        v = ends - np.asarray(other, dtype=float)
        far = np.linalg.norm(v, axis=1) >= FACE_MIN_FRACTION * pad
        n = len(far) if bool(np.all(far)) else int(np.argmin(far))  # the ends nearest the seat, while far
        if n < least:
            continue  # ends beside the other support lie on any line through it: no evidence of a face
        face = kin.straight_line(ends[:n], through=other)  # the line through ``other`` nearest the ends
        if face.worst <= tol_mm and float(np.ptp(face.u)) > SPLIT_APART * tol_mm:
            return n, np.asarray(getattr(lines[0], end), dtype=float), face.worst
    return None


def better_support(point: tuple[int, np.ndarray, float],
                   end: tuple[int, np.ndarray, float] | None) -> tuple[int, np.ndarray, float]:
    """Of a support through which ≥ 3 lines pass (``point``, :func:`_run`: count, point,
    largest distance) and a pad end sliding along the face (``end``, :func:`end_support`), the
    one the lines fit better, the end only when more than ``END_SUPPORT_MM`` from the point.
    Lines resting on a sliding end passed within 0.05 mm of a point 11 mm from it, on none of
    the object, while their ends lay on the face's line within 0.01 mm (random block 6 of seed
    127: that point tilted the face 1.4°); a pad turned about a corner slides along its line,
    and near the seat its end, a few mm beyond the corner, lies within the tolerance of the
    face's line too (a corner 2.4 mm from the end; 7 mm on a face turned 25°: 0.14 mm, the
    lines through the corner 0.00)."""
    if end is None or (point[0] >= 3 and (end[2] >= point[2]
                                          or float(np.linalg.norm(point[1] - end[1])) <= END_SUPPORT_MM)):
        return point
    return end


def seat_split(lines: list[kin.PadLine], length_mm: float,
               tol_mm: float = SEAT_TOL_MM) -> tuple[list[int], np.ndarray, np.ndarray] | None:
    """Where pad lines in order of ψ rest on two supports: a run of ≥ 3 lines through P
    ending at the seat and one of ≥ 3 through Q starting there, every line within ``tol_mm``
    of its point, with the smallest such residual; as (the group of each line: 0 for P, 1
    for Q, −1 for the rest — a line close to the seat that passes through both, lines far
    from it), P, Q; None if there is no such split. The support function of a flat face is
    min(n·P, n·Q): it kinks where the pad lies flat. The split must be unambiguous: the
    last line of P misses Q and the first line of Q misses P by more than
    ``SPLIT_APART`` · ``tol_mm``, at most one line between them (two when both pass within
    that of both supports: on a face shorter than SPLIT_APART · tol_mm / sin(step / 2), 15 mm,
    the lines either side of the seat may both), and each support lowers the pad toward the other
    (:func:`lowering_turn`: +1 about P, −1 about Q; two runs of one pad end sliding along
    a long face, each within ``tol_mm`` of a point, both lower it the same way). Each
    support is fitted to the ``SUPPORT_LINES`` lines nearest the seat; lines beyond are
    left out: a pad end resting on a long face slides along it as the pad turns, and
    lines far from the seat no longer pass through one point."""
    best = None
    for k in range(3, len(lines) - 2):
        run_p = _run(lines, k - 1, -1, tol_mm, SUPPORT_LINES)
        for gap in (0, 1, 2):
            (np_, p, rp), (nq, q, rq) = run_p, _run(lines, k + gap, 1, tol_mm, SUPPORT_LINES)
            if np_ >= 3:  # a pad end resting on the face beyond the seat is the second support
                beyond = lines[k + gap:k + gap + SUPPORT_LINES]
                nq, q, rq = better_support((nq, q, rq), end_support(beyond, p, tol_mm))
            if nq >= 3:  # ... or before it, the first
                before = lines[max(k - SUPPORT_LINES, 0):k][::-1]
                np_, p, rp = better_support((np_, p, rp), end_support(before, q, tol_mm))
            if np_ < 3 or nq < 3:
                continue
            if gap == 2 and any(max(abs(float(ln.normal @ p - ln.d)), abs(float(ln.normal @ q - ln.d)))
                                > SPLIT_APART * tol_mm for ln in lines[k:k + 2]):
                continue  # two lines between the supports: both near the seat, through both
            first, last = lines[k + gap], lines[k - 1]
            apart = min(abs(float(last.normal @ q - last.d)), abs(float(first.normal @ p - first.d)))
            worst = max(rp, rq)
            # about each support, the part of the pad toward the other goes down, however short
            # (a face of 0.2 of the pad seats on that part: FACE_MIN_FRACTION)
            toward_seat = (lowering_turn(last, p, length_mm, q, 0.0), lowering_turn(first, q, length_mm, p, 0.0)) == (1, -1)
            if SPLIT_APART * tol_mm < apart and toward_seat and (best is None or worst < best[0]):
                groups = [-1] * len(lines)
                groups[k - np_:k] = [0] * np_
                groups[k + gap:k + gap + nq] = [1] * nq
                best = (worst, groups, p, q)
    return None if best is None else best[1:]


def lowering_turn(line: kin.PadLine, about: np.ndarray | None, length_mm: float,
                  toward: np.ndarray | None = None, least: float = PIVOT_PART_FRACTION) -> int | None:
    """The turn (+1: ψ increasing, −1: decreasing) that brings a part of the pad ``line``
    down toward the object about the point ``about`` on it, or None without a point on
    the pad. The part lowered is the one that can seat: of two parts of at least ``least``
    (PIVOT_PART_FRACTION) of the pad (a corner under the pad's middle, a face either side) the
    one toward ``toward`` (a point of the object, e.g. the workspace centre), else the longer;
    with ``least`` 0, the part toward ``toward`` whenever the point lies on the pad.
    Turning by δ about the point moves the pad point s along the tangent t from it by
    s·δ·R90·t, toward the object when along n."""
    if about is None:
        return None
    u = float(line.pad_coordinate(about))
    if not -0.5 * length_mm <= u <= 1.5 * length_mm:
        return None
    s = length_mm - u if u < 0.5 * length_mm else -u  # from the point to the farther pad end
    if toward is not None and min(u, length_mm - u) >= least * length_mm:
        s = length_mm - u if float(line.pad_coordinate(toward)) > u else -u
    t = np.asarray(line.tangent, dtype=float)
    return 1 if s * float(np.array([-t[1], t[0]]) @ line.normal) > 0 else -1


def sliding_fill(ks: list[float], lines: list[kin.PadLine], allowed: Callable[[float], bool],
                 tol_mm: float = SEAT_TOL_MM) -> float | None:
    """The step index of an approach between whole steps next to a seat whose second support
    slides (module docstring, step 2), or None. At one end of the range a run of ≥ 3 lines
    passes through one support P and the lines beyond it rest on a pad end that slides along
    the face as the pad turns (their ends on one line with P, or three of them through no one
    point): the pad lies flat between the last line through P and the first beyond (the face
    runs on past the pad's end: random block 6 of bench_explore --finite 20 --anywhere --seed
    127, the left pad's end slid 6 mm along the face in the 3° after its seat, 12 mm in 6°;
    whole steps never put three lines through it, and the press turned its 60° to the finger's
    reach without a seat). Lines a fraction of a step either side of the first beyond
    (``SLIDE_PARTS``) make the third that rests on the end (:func:`end_support`) before the
    press turns on to the finger's reach."""
    for seq, kseq in ((lines[::-1], ks[::-1]), (lines, ks)):  # the high end of the range, then the low
        beyond = next((b for b in range(2, len(seq) - 2) if _slid_past(seq, b, tol_mm)), None)
        if beyond is None:
            continue
        first, toward_p = kseq[beyond - 1], math.copysign(1.0, kseq[beyond] - kseq[beyond - 1])
        for part in SLIDE_PARTS:
            if allowed(first + part * toward_p):
                return first + part * toward_p
    return None


def _slid_past(seq: list[kin.PadLine], b: int, tol_mm: float) -> bool:
    """Do ``seq[b:]`` start with a run of ≥ 3 lines through one point P, the line before it
    miss P by more than SPLIT_APART · ``tol_mm``, and the lines before it rest on a pad end
    sliding along the face (the ends of the two nearest P on one line with it,
    :func:`end_support`), or the three nearest P pass through no point?"""
    n, p, _ = _run(seq, b, 1, tol_mm, SUPPORT_LINES)
    last = seq[b - 1]
    if n < 3 or abs(float(last.normal @ p - last.d)) <= tol_mm:
        return False
    return (end_support(seq[max(b - SUPPORT_LINES, 0):b][::-1], p, tol_mm, least=2) is not None
            or (b >= 3 and _run(seq, b - 1, -1, tol_mm)[0] < 3))


def _turn_about(line: kin.PadLine, about: np.ndarray | None, length_mm: float, toward: np.ndarray | None,
                face: tuple[np.ndarray, np.ndarray] | None, tol_mm: float) -> int | None:
    """:func:`lowering_turn` about ``about``; about one of the supports of the ``face`` the
    finger seated on before (a later press), the part of the pad toward the other support,
    wherever that lies on the pad: the face is there, and the longer part may hang past
    the face's corner over nothing."""
    if about is not None and face is not None:
        for here, other in (face, face[::-1]):
            if float(np.linalg.norm(about - here)) <= SPLIT_APART * tol_mm:
                return lowering_turn(line, about, length_mm, other, least=0.0)
    return lowering_turn(line, about, length_mm, toward)


def next_step(ks: list[float], lines: list[kin.PadLine], length_mm: float, first_turn: int,
              allowed: Callable[[float], bool], toward: np.ndarray | None = None,
              tol_mm: float = SEAT_TOL_MM, face: tuple[np.ndarray, np.ndarray] | None = None) -> float | None:
    """The step index of the press's next approach (module docstring, step 2), given the
    steps ``ks`` taken (increasing) and their pad lines; ``allowed(k)`` says whether step k
    may be tried; ``face`` the supports (P, Q) of the face the finger seated on before.
    None when neither end can grow."""
    fill = sliding_fill(ks, lines, allowed, tol_mm)
    if fill is not None:
        return fill
    through_lo = _run(lines, 0, 1, tol_mm)[0]
    if len(ks) == 1:
        order = [first_turn, -first_turn]
    elif len(ks) == 2 or through_lo == len(ks):  # all through one point: turn about it
        turn = _turn_about(lines[-1], line_point(lines)[0], length_mm, toward, face, tol_mm) or first_turn
        order = [turn, -turn]
    else:
        hi = _turn_about(lines[-1], kin.crossing(lines[-2], lines[-1]), length_mm, toward, face, tol_mm)
        lo = _turn_about(lines[0], kin.crossing(lines[0], lines[1]), length_mm, toward, face, tol_mm)
        if hi == 1:
            order = [1, -1]
        elif lo == -1:
            order = [-1, 1]
        else:  # the seat lies between the ends: the side with fewer lines through its support
            through_hi = _run(lines, len(lines) - 1, -1, tol_mm)[0]
            order = [1, -1] if max(through_hi, 2) <= max(through_lo, 2) else [-1, 1]
            if (through_lo if order[0] > 0 else through_hi) >= SUPPORT_LINES:
                order = order[:1]  # the other side has its lines: growing it leads away from the seat
    for direction in order:
        for part in FILL_PARTS:  # a whole step; short of a block, part of one (module docstring, step 2)
            k = ks[-1] + part if direction > 0 else ks[0] - part
            if allowed(k):
                return k
    for direction in order:  # neither end can grow: halve the outermost gap on that side
        if len(ks) >= 2:
            k = 0.5 * (ks[-1] + ks[-2]) if direction > 0 else 0.5 * (ks[0] + ks[1])
            if abs(ks[-1] - ks[-2] if direction > 0 else ks[1] - ks[0]) >= 2 * FILL_PARTS[-1] and allowed(k):
                return k
    return None


def flat_press(jaw: Jaw, finger: str, touch: int, psi_start: float, first_turn: int, d_start: float,
               travel_mm: float, toward=None, on_event: Callable[[dict], None] | None = None,
               give_up: Callable[[], str | None] | None = None,
               interrupt: Callable[[], str | None] | None = None,
               face: tuple[np.ndarray, np.ndarray] | None = None) -> Motion:
    """Seat the pad flat on the face of the object before it and press it there (module
    docstring): a guarded approach at ``psi_start`` from ``d_start`` (at most
    ``travel_mm``), the pad turned in FLAT_STEP_DEG steps toward the seat (the first one by
    ``first_turn``, ±1; about a corner under the pad's middle, the part toward the point
    ``toward`` lowered: :func:`lowering_turn`), backed off and re-approached as in a
    rolling touch, until two supports are found, then the seated presses. Outcome ``no_seat`` when the pad turned
    FLAT_MAX_TURN_DEG either way (or to its joint limits) without seating; ``stopped`` when
    ``give_up()`` (asked before each turn while no seat is found) returns a reason, or
    ``interrupt()`` (asked every cycle of those turns and approaches), such as another pad
    having seated in the same cycles. ``face``: the supports (P, Q) of the face the finger
    seated on before, about which the pad turns toward the other (:func:`next_step`)."""
    m = jaw.config.motion
    emit = on_event or (lambda rec: None)
    length = jaw.config.finger(finger).pad.length_mm
    step = math.radians(FLAT_STEP_DEG)
    most = round(FLAT_MAX_TURN_DEG / FLAT_STEP_DEG)
    toward = None if toward is None else np.asarray(toward, dtype=float)
    result = FlatResult(finger, touch, psi_start)
    emit({"type": "touch_start", "touch": touch, "finger": finger, "psi": float(psi_start), "kind": "flat",
          "reading": jaw.log_index()})

    def take(approach: ApproachResult, psi: float, role: str) -> bool:
        if approach.contact is None:
            result.outcome = approach.reason
            result.message = (f"{finger}: no contact within the approach at psi={math.degrees(psi):.1f} deg"
                              if approach.reason == "no_contact" else f"{finger}: flat press: {approach.reason}")
            return False
        result.samples.append(approach.contact)
        result.roles.append(role)
        emit({"type": "sample", "touch": touch, "finger": finger, "psi": psi,
              "reading": approach.contact.reading, "by": approach.reason})
        return True

    try:
        yield from move_line(jaw, finger, psi_start, d_start)
        if not take((yield from guarded_approach(jaw, finger, psi_start, d_start, travel_mm)), psi_start, "scan"):
            return result
        steps: list[float] = [0.0]  # each sample's turn from psi_start, in steps
        blocked: dict[int, float] = {}  # per direction, the least turn (steps) the joints could not make

        def allowed(k: float) -> bool:
            side = 1 if k > 0 else -1
            return abs(k) <= most and abs(k) < abs(blocked.get(side, math.inf)) and k not in steps

        while True:
            order = np.argsort(steps)
            lines = [result.samples[i].line for i in order]
            found = seat_split(lines, length)
            if found is not None and np.linalg.norm(found[2] - found[1]) >= FACE_MIN_FRACTION * length:
                break
            why = None if give_up is None else give_up()
            if why is not None:
                result.outcome, result.message = "stopped", f"{finger}: flat press stopped: {why}"
                return result
            k = next_step(sorted(steps), lines, length, first_turn, allowed, toward, face=face)
            if k is None:
                result.outcome = "no_seat"
                result.message = (f"{finger}: turned {math.degrees(step * (max(steps) - min(steps))):.0f} deg about "
                                  f"psi={math.degrees(psi_start):.1f} deg without the pad seating: no flat face there")
                return result
            psi = psi_start + k * step
            try:
                approach = yield from _unless(_press_across(jaw, finger, psi, result.samples), interrupt)
            except kin.Unreachable:
                side = 1 if k > 0 else -1
                blocked[side] = min(abs(k), abs(blocked.get(side, math.inf))) * side
                continue
            if isinstance(approach, str):  # given up during this turn and approach
                result.outcome, result.message = "stopped", f"{finger}: flat press stopped: {approach}"
                return result
            if not take(approach, psi, "scan"):
                return result
            steps.append(k)
        groups, p, q = found
        for group, i in zip(groups, order):
            result.roles[i] = ("scan", "P", "Q")[group + 1]
        result.supports = (p, q)
        normal = face_normal(p, q, result.samples[-1].line.normal)
        psi_f = math.atan2(normal[1], normal[0])
        for extra in SEAT_PRESSES_DEG:
            a = psi_f + math.radians(extra)
            approach = yield from _press_across(jaw, finger, a, result.samples)
            if not take(approach, a, "seat"):
                return result
        last = result.samples[-1]
        yield from move_line(jaw, finger, last.psi, last.d - m.backoff_mm)
    except kin.Unreachable as exc:
        result.outcome, result.message = "unreachable", str(exc)
    finally:
        emit({"type": "touch_end", "touch": touch, "finger": finger, "reading": jaw.log_index(),
              "samples": len(result.samples), "outcome": result.outcome, "roles": list(result.roles)})
    return result


def _press_across(jaw: Jaw, finger: str, psi: float, samples) -> Motion:
    """:func:`_press` at ψ; where that one move is blocked by the object and backing off there
    is beyond the joints (kin.Unreachable) while stops of the press's scan (``samples``) lie
    between the pad and ψ, back along those stops, each ROLL_CLEARANCE_MM off (:func:`_back_along`),
    then press. A pad whose end slid along a face, or that turned about a corner until the corner
    met its end, stands at the finger's reach: the turn back across the range it scanned (to the
    seat, or to grow the range the other way) sweeps the pad through the object, and backing off
    along its own normal leaves the joints' limits, while every stop it made on the way there was
    within them and clear of the object. A turn whose goal itself lies beyond the joints is beyond
    the finger's reach, whatever the object: kin.Unreachable at once, as before. Random P block 1 of bench_explore --finite 20 --anywhere
    --seed 599: the left pad met the face's corner 14 mm from its proximal end and lowered its
    longer part (:func:`lowering_turn`) 49° to its reach, where the corner met its distal end; the
    face lay the other way, 7° from the start, and every turn back raised kin.Unreachable: no seat."""
    # the turn's goal beyond the joints: ψ lies beyond the finger's reach, whatever the object (raises)
    jaw.solve(finger, psi, _press_goal(jaw, finger, jaw.pad_line(jaw.last_state, finger), psi)[0],
              jaw.finger_q(jaw.last_state, finger))
    try:
        return (yield from _press(jaw, finger, psi))
    except kin.Unreachable:
        path = _back_along(samples, psi, ROLL_CLEARANCE_MM)
        if not path:
            raise
        yield from move_line(jaw, finger, *path[-1], via=path[:-1])
        return (yield from _press(jaw, finger, psi))


def _back_along(samples, psi_f: float, off_mm: float) -> list[tuple[float, float]]:
    """The pad lines (ψ, d) ``off_mm`` off the press's stops from the pad's newest one to the one
    nearest ψ_f, the seat or a step beyond the range's other end (the turn back across the range
    the press scanned, every line a stop the finger reached, so within its joints and clear of
    the object), in that order."""
    here = float(samples[-1].line.psi)
    turn = math.remainder(psi_f - here, 2 * math.pi)
    on_way = sorted((s for s in samples if 1e-6 < math.remainder(float(s.line.psi) - here, 2 * math.pi) * np.sign(turn)
                     <= abs(turn) + 0.5 * math.radians(FLAT_STEP_DEG)),
                    key=lambda s: abs(math.remainder(float(s.line.psi) - here, 2 * math.pi)))
    return [(float(s.line.psi), float(s.line.d) - off_mm) for s in on_way]


def _unless(motion: Motion, interrupt: Callable[[], str | None] | None) -> Motion:
    """Run ``motion`` (a turn and approach of the seek), asking ``interrupt`` every cycle: its
    reason as soon as it gives one (the motion left where it is: the next move starts from
    the pad's measured line), else the motion's result. A turn back across the range the
    press scanned (42° on a random block, 2.1 s) no longer runs to its end after another pad
    seated in the same round."""
    if interrupt is None:
        return (yield from motion)
    goal = motion.send(None)
    while True:
        why = interrupt()
        if why is not None:
            motion.close()
            return why
        reading = yield goal
        try:
            goal = motion.send(reading)
        except StopIteration as stop:
            return stop.value


def _press(jaw: Jaw, finger: str, psi: float) -> Motion:
    """From the pad's last contact, in one move, off the object by ROLL_CLEARANCE_MM plus
    what turning to ψ about the pad's middle can sweep (the pad line is interpolated, so
    the end the turn lowers stays clear all the way), then a guarded approach."""
    m = jaw.config.motion
    d_goal, clearance = _press_goal(jaw, finger, jaw.pad_line(jaw.last_state, finger), psi)
    d_from = yield from turn_to(jaw, finger, psi, d_goal)
    return (yield from guarded_approach(jaw, finger, psi, d_from, 2.0 * clearance + 3.0 * ROLL_CLEARANCE_MM + m.backoff_mm))


def _press_goal(jaw: Jaw, finger: str, here: kin.PadLine, psi: float) -> tuple[float, float]:
    """The offset d of the pad line of normal ψ :func:`_press` turns to from the pad line ``here``,
    and its clearance (mm): off the object by ROLL_CLEARANCE_MM plus what turning to ψ about the
    pad's middle can sweep."""
    turn = abs(math.remainder(psi - float(here.psi), 2 * math.pi))
    clearance = ROLL_CLEARANCE_MM + 0.5 * jaw.config.finger(finger).pad.length_mm * turn
    return float(kin.unit(psi) @ (0.5 * (here.proximal + here.distal))) - clearance, clearance
