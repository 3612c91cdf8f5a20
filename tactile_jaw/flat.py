"""Flat-press touches: a pad seated on a straight face, as the recognizer's touch.

A flat press (hand_driver.flat_press) leaves pad lines resting on a first support
P, pad lines resting on a second support Q, and presses at the seat's orientation.
:func:`feel_flat` fits the face through both supports to all of them at once — each
line's offset is min(n·P, n·Q), the support function of a straight face between P and Q
— checks that the seated presses stop where the two supports say (min(n·P, n·Q) from
the P and Q lines alone — a support near a pad end being that end, :func:`seat_supports` —:
their mean within ``SEAT_TOL_MM``, each within twice that; an arc between the supports
bulges toward the pad and stops it early), and hands the recognizer one **contact** touch (docs/formats.md): the middle of
the seated segment PQ, the face's tangent angle φ (travelling with the solid on the
right, as the canonical line: ψ + π/2), κ = κ_s = 0 with the flatness the seat proves as their deviation
(:func:`flat_curvature_sd`). The request of flat touches states ``FLAT_NOISE``, σ_φ by the faces' lengths (:func:`flat_noise`).

What a face touch means for the answer: every flat touch lies on a straight segment of
the boundary. A finite curved object's straight segments are its closing segments, so
flat touches are recognized only when the exploration found no usable rolling touch on
a curved part, and then only one face's touches — those collinear with each other
(:func:`same_face`): a block's faces are each a line, two of them together are no curve
of any class (two parallel faces would pass for a long flat ellipse).
:func:`recognized_touches` makes this choice for the exploration and for replay.
docs/exploration.md#lines-flat-presses.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Sequence

import numpy as np

from hand_driver import kinematics as kin
from hand_driver.flat_press import (END_SUPPORT_MM, FACE_MIN_FRACTION, SEAT_TOL_MM, FlatResult, better_support,
                                   end_support, face_normal)
from recognizer.touches import ContactTouch
from tactile_common.angles import wrap_angle

#: the noise a request of flat touches states (measured, docs/exploration.md#lines-flat-presses):
#: the face's angle from two supports ~40 mm apart whose pad lines the encoders fix to
#: ~0.07 mm: σ_φ ≈ 3 mrad between flat presses of one face (32 presses of the line example
#: turned 0/±5° or moved 3 mm: within ±0.27°, 2.1 mrad rms); the face's offset at the
#: touch ≈ 0.1 mm; along the face (where on the seated segment the "contact" is) the same,
#: the segment's middle being a convention
FLAT_NOISE = {"phi": 3.0e-3, "pos": 0.1}
#: each support of a seat is fixed across the face to about this (mm, 1 σ): a face's angle
#: from supports ℓ mm apart scatters √2 · this / ℓ (:func:`face_phi_sd`), 2.5 mrad at 40 mm
#: (FLAT_NOISE's φ, measured there, is the floor), 9 mrad at 11 mm: held-out X line 7 of seed
#: 241 seated 4 presses on an 11 mm face at ψ −63.4…−62.3°, 19 mrad apart
SUPPORT_SD_MM = 0.07
#: two flat touches are on the same face when their lines differ in angle by less than this
#: many σ of the difference (:func:`face_phi_sd` of each face: 0.01 rad for faces ≥ 33 mm,
#: as before session 23; a press 19 mrad off its long face's others, grouped with them at
#: 0.02, made the line lose to a semicubical) and each one's contact lies SAME_FACE_MM close
#: to the other's line
SAME_FACE_SIGMAS = 2.36
SAME_FACE_MM = 1.0
#: this many flat presses of one finger whose seats stopped, on average, more than
#: SEAT_TOL_MM short of the line through their supports (a bulge toward the pad) show a
#: curved part (:func:`bulged_presses`): on seed 191's logs
#: (bench_explore --finite 20) the line blocks' presses stopped −0.08…+0.09 mm short on
#: average (X-series, 62 presses) and −0.01…+0.07 (P-series, 70); the one 0.22 mm of a face
#: seen (the line example moved 3 mm, X-series, FLAT_TRIES) was one press whose retry
#: seated; P hyperbola 93's left pad, on its curved part, +0.26 and +0.27 mm
BULGED_PRESSES = 2
#: the presses of one face must have stopped, on average over all of them, at most this
#: far (mm) short of their supports: each press's own mean (3 seated stops) is held to
#: ±SEAT_TOL_MM, the rounding of its 9 stops; over a face's presses the bias a flat face
#: can show is smaller (the random blocks' presses, supports at pad ends taken as the end:
#: at most +0.11 mm) while an arc's bulge stays (radius 1000 mm: +0.19…+0.30 mm a press)
FACE_MISS_MM = 0.15


@dataclass(frozen=True)
class Face:
    """A straight face felt by a seated pad: supports P, Q (hand frame, mm) on the line
    n(ψ)·p = d, ψ the pad's outward normal when seated."""

    psi: float
    d: float
    p: np.ndarray
    q: np.ndarray
    miss: float = 0.0  # how far (mm) its seated presses stopped short of the supports, on average
    # ... and the least of that any reading of its supports explains (:func:`feel_flat`: a
    # support near a pad end may be that end or the lines' crossing): what a bulge shows
    bulge: float = 0.0

    @property
    def normal(self) -> np.ndarray:
        """n(ψ), the pad's outward unit normal when seated."""
        return kin.unit(self.psi)

    @property
    def length(self) -> float:
        return float(np.linalg.norm(self.q - self.p))

    @property
    def middle(self) -> np.ndarray:
        return 0.5 * (self.p + self.q)

    @property
    def phi(self) -> float:
        """The face's tangent angle travelling with the solid on the right (ψ + π/2), as
        the canonical line (t, 0) with its solid at y < 0 (docs/formats.md): the answer's
        pose then maps the canonical solid onto the object's."""
        return float(wrap_angle(self.psi + math.pi / 2))


def flat_curvature_sd(length_mm: float, tol_mm: float = SEAT_TOL_MM) -> tuple[float, float]:
    """(σ_κ, σ_κs) of a face seated over ``length_mm``: the pad touches both ends within
    ``tol_mm``, so the boundary between them (convex there: the pad does not cross it)
    bulges at most ``tol_mm`` from the chord: |κ| ≤ 8·tol/ℓ² for an arc; taken uniform
    on ±that, σ_κ = 8·tol/(√3·ℓ²); κ_s changes κ by at most that over ℓ/2 either side of
    the middle: σ_κs = 2·σ_κ/ℓ·√3."""
    sk = 8.0 * tol_mm / (math.sqrt(3.0) * length_mm ** 2)
    return sk, 2.0 * math.sqrt(3.0) * sk / length_mm


def fit_face(lines: kin.PadLine, roles: Sequence[str]) -> Face:
    """The face through two supports fitted to every pad line of a flat press: ``P`` and
    ``Q`` lines through their support, ``seat`` lines through the nearer one
    (min(n·P, n·Q), re-assigned once after a first fit on P and Q lines alone)."""
    n, d = np.atleast_2d(lines.normal), np.atleast_1d(lines.d)
    roles = list(roles)
    groups = np.array([{"P": 0, "Q": 1}.get(r, -1) for r in roles])
    for _ in range(2):
        use = groups >= 0
        a = np.zeros((int(use.sum()), 4))
        rows = np.flatnonzero(use)
        for j, i in enumerate(rows):
            a[j, 2 * groups[i]:2 * groups[i] + 2] = n[i]
        sol = np.linalg.lstsq(a, d[rows], rcond=None)[0]
        p, q = _at_ends(lines, groups, sol[:2], sol[2:])
        seat = np.array([r == "seat" for r in roles])
        groups = np.where(seat, (n @ q < n @ p).astype(int), groups)
    normal = face_normal(p, q, n[-1])
    return Face(float(math.atan2(normal[1], normal[0])), float(0.5 * normal @ (p + q)), p, q)


def _at_ends(lines: kin.PadLine, groups: np.ndarray, p: np.ndarray, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The supports (``p``, ``q``: the points fitted to the ``P`` and ``Q`` lines), each one
    whose lines rest on a pad end sliding along the face (hand_driver.flat_press.end_support:
    their ends on one straight line with the other support, and they fit it better:
    hand_driver.flat_press.better_support, seat_split's choice) replaced by that end of its
    line passing nearest the other support: such lines pass through no one point, and a point
    fitted to them tilts the face."""
    out = [p, q]
    for g, other in ((0, q), (1, p)):
        rows = sorted(np.flatnonzero(groups == g), key=lambda i: abs(float(lines.normal[i] @ other - lines.d[i])))
        through = float(np.max(np.abs(lines.normal[rows] @ out[g] - lines.d[rows]))) if rows else math.inf
        out[g] = better_support((len(rows), out[g], through), end_support([lines.at(i) for i in rows], other))[1]
    return out[0], out[1]


def seat_supports(lines: kin.PadLine, roles: Sequence[str], face: Face, length_mm: float,
                  margin_mm: float = END_SUPPORT_MM) -> tuple[np.ndarray, np.ndarray]:
    """The two supports a seated press is checked against: each group's (``P``, ``Q``)
    common point from ``face`` (:func:`fit_face`), or, when that lies within ``margin_mm``
    (``END_SUPPORT_MM``) of a pad end of the group's line nearest the seat (the one passing
    nearest the other support) or beyond it, that pad end itself, which rests on the face.
    Within the margin either may be true: a pad end sliding along the face, or a corner a
    few mm from the end the pad turned about (then the end, off the object, lies u·sin α
    beyond the face's line, α the line's turn from the seat)."""
    out = []
    for role, point, other in (("P", face.p, face.q), ("Q", face.q, face.p)):
        rows = [i for i, r in enumerate(roles) if r == role]
        near = lines.at(min(rows, key=lambda i: abs(float(lines.normal[i] @ other - lines.d[i]))))
        u = float(near.pad_coordinate(point))
        out.append(np.asarray(near.proximal if u <= margin_mm else
                              near.distal if u >= length_mm - margin_mm else point, dtype=float))
    return out[0], out[1]


def feel_flat(config, touch: FlatResult) -> tuple[kin.PadLine | None, str | None, ContactTouch | None, Face | None]:
    """A flat press felt (tactile_jaw.pipeline.feel dispatches it here): its pad lines,
    why it cannot be used or None, the recognizer's contact touch when usable, and the
    face (:func:`fit_face`) when fitted (module docstring)."""
    finger = touch.finger
    lines = kin.PadLine.stack([s.line for s in touch.samples]) if touch.samples else None

    def out(problem, face=None):
        contact = None
        if problem is None:
            sk, sks = flat_curvature_sd(face.length)
            contact = ContactTouch(float(face.middle[0]), float(face.middle[1]), face.phi, 0.0, 0.0,
                                   np.diag([sk * sk, sks * sks]))
        return lines, problem, contact, face

    if touch.outcome != "ok":
        return out(touch.message or touch.outcome)
    roles = list(touch.roles)
    if not all(roles.count(r) >= need for r, need in (("P", 3), ("Q", 3), ("seat", 1))):
        return out(f"{finger}: a flat press needs 3 pad lines on each support and a seated press")
    supports = fit_face(lines, [r if r in ("P", "Q") else "scan" for r in roles])
    length = config.finger(finger).pad.length_mm
    if supports.length < FACE_MIN_FRACTION * length:
        return out(f"{finger}: the supports are {supports.length:.1f} mm apart, under {FACE_MIN_FRACTION:g} of the pad: "
                   f"a curved boundary, not a face", supports)
    seats = [i for i, r in enumerate(roles) if r == "seat"]

    def stops(margin_mm: float) -> np.ndarray:
        # a straight face's support function is min(n·P, n·Q) at the seat too; an arc between
        # P and Q meets the seated pad before either, by its bulge
        p, q = seat_supports(lines, roles, supports, length, margin_mm)
        return np.array([float(min(lines.normal[i] @ p, lines.normal[i] @ q) - lines.d[i]) for i in seats])

    # the seat test holds the press to the pad ends near its supports (an arc's bulge hides
    # behind a crossing a few mm inside the pad); a bulge is claimed only where the crossing
    # shows it too: X line 19 of seed 283 stopped +0.24 mm short of a pad end 3.8 mm past the
    # block's corner, 0.06 mm of the corner itself
    miss = stops(END_SUPPORT_MM)
    faced = dict(miss=float(np.mean(miss)), bulge=min(float(np.mean(miss)), float(np.mean(stops(0.0)))))
    if abs(float(np.mean(miss))) > SEAT_TOL_MM or np.max(np.abs(miss)) > 2.0 * SEAT_TOL_MM:
        # the miss kept with the supports: two such bulges are a curved part (:func:`bulged_presses`)
        return out(f"{finger}: the pad did not lie flat: its seated presses stopped {float(np.mean(miss)):+.2f} mm "
                   f"(mean; at most {SEAT_TOL_MM:g}) from the line through both supports: a curved boundary, "
                   f"not a face", replace(supports, **faced))
    return out(None, replace(fit_face(lines, roles), **faced))


def face_phi_sd(length_mm: float) -> float:
    """σ of the angle of a face seated over ``length_mm`` (its supports that far apart, each
    fixed to SUPPORT_SD_MM): √2 · SUPPORT_SD_MM / ℓ, at least FLAT_NOISE's φ."""
    return max(FLAT_NOISE["phi"], math.sqrt(2.0) * SUPPORT_SD_MM / length_mm)


def same_face_rad(a: Face, b: Face) -> float:
    """How far (rad) the angles of two faces of one straight face may differ: SAME_FACE_SIGMAS σ
    of the difference (:func:`face_phi_sd` of each)."""
    return SAME_FACE_SIGMAS * math.hypot(face_phi_sd(a.length), face_phi_sd(b.length))


def flat_noise(faces: Sequence[Face]) -> dict[str, float]:
    """The noise a request of flat touches on these ``faces`` states: FLAT_NOISE with σ_φ the
    RMS of each face's :func:`face_phi_sd` (a short face's angle scatters more)."""
    return {**FLAT_NOISE, "phi": float(np.sqrt(np.mean([face_phi_sd(f.length) ** 2 for f in faces])))}


def same_face(a: Face, b: Face) -> bool:
    """Are two felt faces one straight face (:func:`same_face_rad`, SAME_FACE_MM)?"""
    if abs(math.remainder(a.psi - b.psi, 2 * math.pi)) > same_face_rad(a, b):
        return False
    return abs(float(a.normal @ b.middle) - a.d) <= SAME_FACE_MM and abs(float(b.normal @ a.middle) - b.d) <= SAME_FACE_MM


def face_groups(touches: Sequence) -> list[list]:
    """Usable flat touches grouped by face (:func:`same_face` with the group's first),
    in order felt."""
    groups: list[list] = []
    for t in touches:
        for g in groups:
            if same_face(g[0].face, t.face):
                g.append(t)
                break
        else:
            groups.append([t])
    return groups


def is_flat(felt) -> bool:
    """Is a felt touch (tactile_jaw.pipeline.FeltTouch) a flat press?"""
    return isinstance(felt.touch, FlatResult)


def curved_faces(usable: Sequence) -> list[tuple[int, float]]:
    """The groups of flat touches (:func:`face_groups`) that are no face: (touches, mean
    seat miss) of each whose seated presses stopped short of their supports by more than
    ``FACE_MISS_MM`` on average."""
    groups = face_groups([t for t in usable if is_flat(t)])
    means = [float(np.mean([t.face.miss for t in g])) for g in groups]
    return [(len(g), m) for g, m in zip(groups, means) if m > FACE_MISS_MM]


def bulged(felt) -> bool:
    """Did a flat press's seat stop more than SEAT_TOL_MM short of the line through its
    supports, on average, however its supports are read (``Face.bulge``, :func:`feel_flat`:
    an arc between them meets the pad first)?"""
    return is_flat(felt) and felt.problem is not None and felt.face is not None and felt.face.bulge > SEAT_TOL_MM


def bulged_presses(felt: Sequence) -> list | None:
    """The first ``BULGED_PRESSES`` presses of one finger whose seats stopped short of
    their supports (:func:`bulged`), or None: the boundary bulges between the supports, a
    curved part — so a finite object's straight faces are its closing segments, no line
    (tactile_jaw.pipeline.curved_part). Not required on one face (:func:`same_face`): on a
    curve the supports move with where the pad turned from (P hyperbola 93: 1.0° and 1.2 mm
    apart between its two presses)."""
    for finger in dict.fromkeys(t.finger for t in felt):
        presses = [t for t in felt if t.finger == finger and bulged(t)]
        if len(presses) >= BULGED_PRESSES:
            return presses[:BULGED_PRESSES]
    return None


def recognized_touches(usable: Sequence, fewest: int = 1, curved: bool = False) -> list:
    """What the recognizer gets of the usable touches (module docstring): the rolling
    touches if there is any; else, unless a touch rolled on a ``curved`` part of the boundary
    (tactile_jaw.pipeline.curved_part: the faces are then closing segments), the flat
    touches of the face felt most often (the first
    felt on a tie) among those whose presses stopped, on average, within ``FACE_MISS_MM``
    of their supports (:func:`curved_faces`: a gentle curve), if it was felt ``fewest``
    times or more (the profile's ``min_touches``: a face whose other presses failed the
    seat test, as on an arc of 1000 mm, is no line from two that passed)."""
    rolling = [t for t in usable if not is_flat(t)]
    if rolling or curved:
        return rolling
    groups = [g for g in face_groups([t for t in usable if is_flat(t)])
              if float(np.mean([t.face.miss for t in g])) <= FACE_MISS_MM]
    best = max(groups, key=len) if groups else []
    return best if len(best) >= fewest else []


def felt_face(touches: Sequence) -> tuple[np.ndarray, np.ndarray, float] | None:
    """The stretch of one straight face that flat presses felt (``touches``, every one a flat
    press with its face): the two outermost of their supports along the face's tangent (the
    first faces' tangent; the supports lie on one line within ``SEAT_TOL_MM``) and the faces'
    mean pad normal ψ; None unless every touch is such a press."""
    faces = [t.face for t in touches if is_flat(t) and t.face is not None]
    if not faces or len(faces) != len(touches):
        return None
    tangent = np.array([-faces[0].normal[1], faces[0].normal[0]])
    points = np.array([p for f in faces for p in (f.p, f.q)], dtype=float)
    along = points @ tangent
    psi = math.atan2(float(np.mean([math.sin(f.psi) for f in faces])), float(np.mean([math.cos(f.psi) for f in faces])))
    return points[int(np.argmin(along))], points[int(np.argmax(along))], psi


def face_line(recognition, touches: Sequence):
    """A `line` answered from one face's flat presses (``touches``), said to be that face's line
    (docs/formats.md, ``reason``): which face (its pad normal) and the stretch between the
    outermost supports the presses felt (:func:`felt_face`); past them the boundary was not
    felt, so the object may be a block or a finite curved object's closing segment whose
    curved part no pad reached (a P cubical block turned −105°, its curved part facing away
    from both fingers: rolls on its corners only, three presses of its closing segment).
    Any other answer is returned as it is."""
    face = felt_face(touches) if recognition.cls == "line" else None
    if face is None:
        return recognition
    p, q, psi = face
    note = (f"the line of one straight face the pads pressed flat (pad normal {math.degrees(psi):.1f} deg), felt "
            f"from ({p[0]:.1f}, {p[1]:.1f}) to ({q[0]:.1f}, {q[1]:.1f}) mm ({float(np.linalg.norm(q - p)):.1f} mm); "
            f"past those supports the boundary was not felt")
    return replace(recognition, reason=f"{note}; {recognition.reason}" if recognition.reason else note)
