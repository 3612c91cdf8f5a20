"""A line whose face before a pad lies mostly beyond the pad's end: no press seats, and the
refusal names the move of the object after which that face lies under the pad
(tactile_jaw.flat_phase.short_face_stop), checked on exact stops before and after the move."""

import math
from types import SimpleNamespace

import numpy as np
import pytest

from hand_driver.flat_press import FACE_MIN_FRACTION, FlatResult
from hand_driver.motion import Sample
from hand_driver.sim.physics import ContactWorld
from recognizer.scene import load_scene
from tactile_jaw.flat_phase import short_face_stop
from tactile_jaw.pipeline import FeltTouch
from tactile_jaw.rounds import Exploration
from tactile_jaw.settings import ExploreSettings
from tests.hand_driver.test_flat_press import CONFIG, _stop, _walk
from tools.bench_explore import moved_object

#: a block 14.6 mm across (the short face of random block 3 of bench_explore --finite 4
#: --anywhere --seed 11), its face at y = 10 from x = 84 to 98.6: the left pad at its nominal
#: normal spans x 89.9–141.9 there, so 5.9 mm of the face lie beyond its proximal end
BLOCK = {"class": "line", "params": {}, "pose": {"theta": 0.0, "x": 91.3, "y": 10.0},
         "extent": [-7.3, 7.3], "closure": [[7.3, -20.0], [-7.3, -20.0]]}


def _world(obj):
    return ContactWorld(CONFIG, load_scene({"name": "b", "classes": ["line"], "object": obj}).object)


def test_a_face_beyond_the_pad_end_names_the_move_that_seats_it():
    """The left pad's press walk on exact stops finds only the pad end and a corner 8.7 mm
    apart: no seat. The stop names the face and a move (turn and shift); the block moved so,
    the walk seats on both corners of the 14.6 mm face (fails before session 13: no stop)."""
    finger = CONFIG.finger("left")
    world = _world(BLOCK)
    found, lines = _walk(world, finger, -math.pi / 2)
    assert found is None  # the pad end and a corner 8.7 mm apart: under FACE_MIN_FRACTION of the pad
    samples = [Sample(reading=k, psi=float(ln.psi), ticks=np.zeros(2), line=ln, current_ma=None, robot_time=0.0)
               for k, ln in enumerate(lines[s] for s in sorted(lines))]
    press = FlatResult("left", 0, -math.pi / 2, samples, outcome="no_seat", roles=["scan"] * len(samples))
    out = Exploration()
    out.touches = [FeltTouch(press, None, None, None, "no seat", None)]
    stop = short_face_stop(CONFIG, ExploreSettings.from_profile("balanced"), out)
    assert stop is not None and stop.move is not None and "left pad met a face" in stop
    assert 0.1 * finger.pad.length_mm < float(stop.split("over ")[1].split(" mm")[0]) < FACE_MIN_FRACTION * finger.pad.length_mm
    moved = moved_object(BLOCK, stop.move)
    found, _ = _walk(_world(moved), finger, -math.pi / 2)
    assert found is not None  # moved as advised, the press seats on the whole face
    groups, p, q = found
    assert abs(np.linalg.norm(q - p) - 14.6) < 0.2  # both corners: the whole face


def _pad(proximal, angle: float, length: float = 52.0):
    """One pad line whose proximal end is at ``proximal``, the pad along ``angle``."""
    from hand_driver import kinematics as kin
    t = np.array([math.cos(angle), math.sin(angle)])
    n = np.array([-math.sin(angle), math.cos(angle)])
    p = np.asarray(proximal, dtype=float)
    return kin.PadLine(psi=np.array(math.atan2(n[1], n[0])), d=np.array(float(n @ p)), normal=n, tangent=t,
                       proximal=p, distal=p + length * t, joint2=p - 65.0 * t)


def test_a_face_a_pad_end_slid_along():
    """tactile_jaw.flat_phase.sliding_face: three rolls whose proximal end slid along y = 0
    (the pad turning 18° each, 4.5 mm of slide a roll, their envelope concave) show a face of
    the whole 13.5 mm the ends covered, its normal toward the pad's; the same ends under a
    convex envelope (a roll on a curve near the pad's end), rolls turning about a corner 10 mm
    from the proximal end and a single roll's 4.5 mm show none."""
    from hand_driver import kinematics as kin
    from tactile_jaw.flat_phase import sliding_face
    def roll(lines, rho=-30.0, slid=None):  # a felt roll: its pad lines, its envelope's radius of curvature, and
        # the pad end feel found on one line within the lines' deviations (fine encoders)
        return SimpleNamespace(lines=kin.PadLine.stack(lines), fit=SimpleNamespace(rho=rho, sigma_rho=0.01), slid=slid)

    slides = [[_pad((x0 + 0.5 * k, 0.0), math.radians(20.0 + 2.0 * k)) for k in range(10)] for x0 in (0.0, 4.5, 9.0)]
    rolls = [roll(lines) for lines in slides]
    got = sliding_face(rolls, 52.0)
    assert got is not None
    length, p, q, toward = got
    assert length == pytest.approx(13.5, abs=1e-6)
    assert abs(p[1]) < 1e-9 and abs(q[1]) < 1e-9 and sorted([p[0], q[0]]) == pytest.approx([0.0, 13.5])
    assert sliding_face(rolls[:1], 52.0) is None  # 4.5 mm: under FACE_MIN_FRACTION of the pad
    assert sliding_face([roll(lines, rho=25.0) for lines in slides], 52.0) is None  # convex: a curve's roll
    corner = np.array([0.0, 0.0])
    about = [roll([_pad(corner - 10.0 * np.array([math.cos(a), math.sin(a)]), a)
                   for a in np.radians(a0 + 2.0 * np.arange(10))], rho=0.0) for a0 in (0.0, 18.0, 36.0)]
    assert sliding_face(about, 52.0) is None
    # the ends of the convex rolls on one line within the lines' own deviations (tactile_jaw.pipeline.slid_end):
    # a slide whatever the envelope (P-series line 16 of bench_explore --finite 20 --anywhere --seed 173:
    # ρ +14.3 and +3.0 mm, refused naming no move before)
    convex_slides = [roll(lines, rho=25.0, slid="proximal") for lines in slides]
    got = sliding_face(convex_slides, 52.0)
    assert got is not None and got[0] == pytest.approx(13.5, abs=1e-6)
    assert sliding_face([roll(lines, rho=25.0, slid="distal") for lines in slides], 52.0) is None  # the other end
    # ... and whatever the points their lines pass through: the same slides, each turning only 2 deg about
    # a point within 1 mm of the others' (a slide of 0.5 mm a roll beside the face's corner)
    short = [[_pad((x0 + 0.5 * k, 0.0), math.radians(20.0 + 0.2 * k)) for k in range(10)]
             for x0 in (0.0, 0.5, 1.0, 9.0, 9.5)]
    got = sliding_face([roll(lines, rho=25.0, slid="proximal") for lines in short], 52.0)
    assert got is not None and got[0] == pytest.approx(14.0, abs=1e-6)
    assert sliding_face([roll(lines, rho=-30.0) for lines in short], 52.0) is None  # unflagged: pivots


#: held-out block 12 of bench_explore --finite 20 --anywhere --seed 269 (both jaws): a corner toward
#: each pad, every face 42–48° from a pad's nominal normal, x 109–142 mm
CORNERED = {"class": "line", "params": {}, "pose": {"theta": -2.400317147455274, "x": 130.0992665700785,
                                                    "y": 12.534721498661314},
            "extent": [-16.280225189522252, 16.280225189522252],
            "closure": [[16.280225189522252, -13.024180151617802], [-16.280225189522252, -13.024180151617802]]}


def _corners(obj) -> np.ndarray:
    """A block's corners in the hand frame: its line's ends (extent), then its closure's points."""
    c, s = math.cos(obj["pose"]["theta"]), math.sin(obj["pose"]["theta"])
    local = [(obj["extent"][1], 0.0), (obj["extent"][0], 0.0), *obj["closure"][::-1]]
    return np.array([(obj["pose"]["x"] + c * u - s * v, obj["pose"]["y"] + s * u + c * v) for u, v in local])


def _press(finger: str, lines) -> FeltTouch:
    samples = [Sample(reading=k, psi=float(ln.psi), ticks=np.zeros(2), line=ln, current_ma=None, robot_time=0.0)
               for k, ln in enumerate(lines[s] for s in sorted(lines))]
    press = FlatResult(finger, 0, float(samples[0].psi), samples, outcome="no_seat", roles=["scan"] * len(samples))
    return FeltTouch(press, None, None, None, "no seat", None)


def test_a_corner_turned_about_names_the_move_that_seats_its_face():
    """tactile_jaw.flat_phase.corner_faces on exact stops of the P-series left pad at the
    orientations its press on held-out block 12 reached (−89.75…−62.75° about the corner, then
    its distal end 8–19 mm along the face, the face's line 5 mm past the finger's reach, the next
    turn blocked): no seat. The stop names that face, measured from the corner to the farthest
    end (on the face's line within 0.1 mm), and a move; the block moved so, the press walk
    seats (refused naming no move before)."""
    from hand_driver.config import load_config
    from hand_driver.flat_press import seat_split
    from tactile_jaw.flat_phase import corner_faces
    config = load_config("config/jaw-p.yaml")
    finger = config.finger("left")
    world = ContactWorld(config, load_scene({"name": "b", "classes": ["line"], "object": CORNERED}).object)
    reached = (-89.75, -86.75, -83.75, -80.75, -77.75, -74.75, -71.75, -68.75, -65.75, -62.75, -59.75, -56.75,
               -55.25, -54.5)
    lines = {a: _stop(world, finger, math.radians(a)) for a in reached}
    ordered = [lines[a] for a in sorted(lines)]
    assert seat_split(ordered, finger.pad.length_mm) is None
    corner, other = _corners(CORNERED)[[2, 3]]  # the face's ends, (133.3, 33.1) and (109.3, 11.1) mm
    along = (other - corner) / np.linalg.norm(other - corner)
    felt, p, q, _ = max(corner_faces(ordered, finger.pad.length_mm), key=lambda f: f[0])
    assert np.linalg.norm(p - corner) < 0.1
    assert 15.0 < felt < np.linalg.norm(other - corner)
    assert abs(float(along[0] * (q - corner)[1] - along[1] * (q - corner)[0])) < 0.1  # on the face's line
    out = Exploration()
    out.touches = [_press("left", lines)]
    stop = short_face_stop(config, ExploreSettings.from_profile("balanced"), out)
    assert stop is not None and stop.move is not None and "left pad turned about a corner at (133, 33) mm" in stop
    moved = load_scene({"name": "b", "classes": ["line"], "object": moved_object(CORNERED, stop.move)}).object
    found, _ = _walk(ContactWorld(config, moved), finger, -math.pi / 2)
    assert found is not None and np.linalg.norm(found[2] - found[1]) >= FACE_MIN_FRACTION * finger.pad.length_mm


def test_corner_faces_needs_a_corner_and_a_consistent_pad_end():
    """corner_faces on exact pad lines of a pad turned about a corner at (0, 0), 40 mm along it,
    from 30° to 3° short of lying on the face y = 0 (x < 0) beyond its distal part: past either
    end of that turn, the face along the last line over the part turning on lowers (none felt);
    lines past the seat resting on the distal end at x = −12, −16, −20 mm give that face as
    felt, 20 mm; an end 1 mm below that line (past a second corner) ends the face before it."""
    from tactile_jaw.flat_phase import corner_faces

    def pad_through(point, angle, u):  # the pad along ``angle`` with ``point`` u mm from its proximal end
        t = np.array([math.cos(angle), math.sin(angle)])
        return _pad(np.asarray(point, float) - u * t, angle)

    def beside(faces):  # the face found toward x < 0
        return next(f for f in faces if f[2][0] < 0.0)

    about = [pad_through((0.0, 0.0), math.pi + a, 40.0) for a in np.radians(np.arange(-30.0, 0.0, 3.0))]
    felt, p, q, _ = beside(corner_faces(about, 52.0))
    assert felt == 0.0 and np.allclose(p, 0.0, atol=1e-6)
    assert np.linalg.norm(q) == pytest.approx(FACE_MIN_FRACTION * 52.0) and abs(q[1]) < 0.6  # along the -3° line
    ends = [pad_through((-x, 0.0), math.pi + a, 52.0) for x, a in zip((12.0, 16.0, 20.0), np.radians((2.0, 3.0, 4.0)))]
    felt, p, q, _ = beside(corner_faces(about + ends, 52.0))
    assert felt == pytest.approx(20.0, abs=1e-6) and np.allclose(q, (-20.0, 0.0), atol=1e-6)
    # past a second corner at (-16, 0): an end 1 mm below the face's line, the pad steep enough to clear (-16, 0)
    bent = ends[:2] + [pad_through((-20.0, -1.0), math.pi + math.radians(15.0), 52.0)]
    felt, _, _, _ = beside(corner_faces(about + bent, 52.0))
    assert felt == pytest.approx(16.0, abs=1e-6)


def test_a_press_whose_pad_end_slid_along_a_face_beyond_its_seat_turn_names_a_move_that_seats():
    """X line 17 of bench_explore --finite 20 --anywhere --seed 283 (a 40 mm block near the palm, its long
    face 78° from the right pad's nominal normal): the right press's proximal end slid 11.7 mm
    along that face (within 0.04 mm) as the pad turned 48–146°, no seat. Before session 24, seat_split put a
    6.5 mm face at pad normal 98° where the lines cross, one support 4.3 mm outside the block,
    and named a move; moved so, the block was refused again. The face is the end's path
    (flat_phase._slid_path) on the block's face, 78° from the normal, past SEATED_TURN_DEG, and
    sessions 24–26 named no move (only choose.facing_move's 30° turn without a shift was tried,
    which does not reach). Now the same search over the turns that leave the seat within
    SEATED_TURN_DEG, shifts included, names 30° clockwise and a shift (fails before session 27):
    the block moved so, the right press walk seats on its face (followed live, it is answered line).
    The run's probes bound where the face goes on unfelt (session 28, Goal.goes_on): without
    them nothing shows that its line is clear of the opened pads past its felt ends, and no move
    is named."""
    import json
    from pathlib import Path

    from hand_driver.config import load_config
    from hand_driver.motion import TouchResult
    from tactile_jaw.choose import NOT_CLEAR
    from tactile_jaw.flat_phase import SEATED_TURN_DEG, _slid_path
    from tactile_jaw.pipeline import feel, logged_samples
    raw = json.loads((Path(__file__).parent / "data" / "x_line_17_press.json").read_text())
    config = load_config("config/jaw.yaml")
    t = raw["presses"][0]
    samples = logged_samples(config, t["finger"], t["ticks"], t["psi"])
    felt = feel(config, FlatResult(t["finger"], t["touch"], t["psi_center"], samples, outcome=t["outcome"],
                                   roles=t["roles"]), 9)
    pose = raw["truth"]["pose"]
    c, s = math.cos(pose["theta"]), math.sin(pose["theta"])
    p, q, toward = _slid_path(sorted((smp.line for smp in samples), key=lambda ln: float(ln.psi)), 52.0)
    for x in (p, q):  # on the block's face: y = 0 in its frame, within its extent
        u, v = c * (x[0] - pose["x"]) + s * (x[1] - pose["y"]), -s * (x[0] - pose["x"]) + c * (x[1] - pose["y"])
        assert abs(v) < 0.05 and abs(u) < raw["truth"]["extent"][1]
    assert 11.0 < float(np.linalg.norm(q - p)) < 12.5 and float(toward @ np.array([-s, c])) < 0  # into the block
    out = Exploration()
    out.touches = [felt]
    alone = short_face_stop(config, ExploreSettings.from_profile("balanced"), out)
    assert alone is not None and alone.move is None and f"168 deg, over 11.7 mm of the pad: {NOT_CLEAR}" in alone
    out.probes = [feel(config, TouchResult(r["finger"], r["touch"], r["psi_center"],
                                           logged_samples(config, r["finger"], r["ticks"], r["psi"])
                                           if r["ticks"] else [],
                                           outcome=r["outcome"]), 9) for r in raw["probes"]]
    stop = short_face_stop(config, ExploreSettings.from_profile("balanced"), out)
    assert stop is not None and "pad normal 168 deg" in stop and stop.move is not None
    assert stop.move["turn_deg"] == pytest.approx(-30.0) and math.hypot(stop.move["dx"], stop.move["dy"]) <= 22.0
    assert abs(168.0 + stop.move["turn_deg"] - 90.0) <= SEATED_TURN_DEG  # the right pad's nominal normal: +90°
    assert all(place["finger"] == "right" for place in stop.move["places"])
    finger = CONFIG.finger("right")
    moved = load_scene({"name": "b", "classes": ["line"], "object": moved_object(raw["truth"], stop.move)}).object
    found, _ = _walk(ContactWorld(CONFIG, moved), finger, math.pi / 2)
    assert found is not None and np.linalg.norm(found[2] - found[1]) >= FACE_MIN_FRACTION * finger.pad.length_mm


def test_a_press_whose_pad_end_slid_along_a_face_then_turned_about_its_corner_names_a_move():
    """X line 7 of bench_explore --finite 20 --anywhere --seed 499 (a 34.5 mm block near the palm,
    its long face at pad normal −156°, 66° from the left pad's nominal normal), logged: the left
    press's proximal end slid along that face from −105.5° toward the seat, then the pad turned
    on to −165.5° about the face's far corner (its end off the face): no seat, and no straight
    path of every line's end, no corner face a move seats: no move named (fails before session
    32: no stop). The longest run of the press's lines whose end slid straight
    (flat_phase._slid_path with ``part``; the lines through the corner under the pad's middle
    left out) lies on the block's face; the move named for it leaves the seat within
    SEATED_TURN_DEG of the pad's normal, and the block moved so, the press walk on exact stops
    seats (followed live, it is answered line)."""
    import json
    from pathlib import Path

    from hand_driver.config import load_config
    from hand_driver.motion import TouchResult
    from tactile_jaw.flat_phase import SEATED_TURN_DEG, _slid_path
    from tactile_jaw.pipeline import feel, logged_samples
    from tactile_jaw.plan import open_pose
    raw = json.loads((Path(__file__).parent / "data" / "x_line_499_7_touches.json").read_text())
    config = load_config("config/jaw.yaml")

    def felt(r, kind):
        samples = logged_samples(config, r["finger"], r["ticks"], r["psi"]) if r["ticks"] else []
        return feel(config, kind(r["finger"], r["touch"], r["psi_center"], samples, outcome=r["outcome"],
                                 **({"roles": r["roles"]} if kind is FlatResult else {})), 9)

    press = felt(raw["touches"][0], FlatResult)
    lines = sorted((smp.line for smp in press.touch.samples), key=lambda ln: float(ln.psi))
    assert _slid_path(lines, 52.0) is None  # no straight path of every line's end
    p, q, toward = _slid_path(lines, 52.0, part=True)
    pose = raw["truth"]["pose"]
    c, s = math.cos(pose["theta"]), math.sin(pose["theta"])
    for x in (p, q):  # on the block's face: y = 0 in its frame, within its extent
        u, v = c * (x[0] - pose["x"]) + s * (x[1] - pose["y"]), -s * (x[0] - pose["x"]) + c * (x[1] - pose["y"])
        assert abs(v) < 0.1 and abs(u) < raw["truth"]["extent"][1]
    assert 10.4 <= float(np.linalg.norm(q - p)) < 12.0 and float(toward @ np.array([-s, c])) < 0  # into the block
    out = Exploration()
    out.probes = [felt(r, TouchResult) for r in raw["probes"]]
    out.touches = [press]
    stop = short_face_stop(config, ExploreSettings.from_profile("balanced"), out)
    assert stop is not None and "pad normal -156 deg" in stop and stop.move is not None
    assert abs(-156.0 + stop.move["turn_deg"] + 90.0) <= SEATED_TURN_DEG  # the left pad's nominal normal: −90°
    assert all(place["finger"] == "left" for place in stop.move["places"])
    finger = config.finger("left")
    moved = load_scene({"name": "b", "classes": ["line"], "object": moved_object(raw["truth"], stop.move)}).object
    assert not ContactWorld(config, moved).penetrates(open_pose(config))  # clear of the opened jaw
    found, _ = _walk(ContactWorld(config, moved), finger, -math.pi / 2)
    assert found is not None and np.linalg.norm(found[2] - found[1]) >= FACE_MIN_FRACTION * finger.pad.length_mm


def test_a_pad_end_that_moved_straight_while_the_pad_turned_about_a_corner_under_it_is_no_face():
    """Held-out P cubical 113 of bench_explore --finite 20 --anywhere --follow --seed 571: the left
    press's 8 lines all passed within 0.01 mm through the corner its rolls pivoted about,
    (98.37, 39.35) mm, 40.7 → 15.4 mm along the 52 mm pad, as the pad turned 17°; its proximal
    end moved straight (within SEAT_TOL_MM) over 26.4 mm from (70.3, 68.7) to (84.9, 46.8), 15 mm
    and more from the object. flat_phase._slid_path took that path for a face (the longest, over
    the right pad's seated one), for which no move reaches, and the refusal named no move (fails
    before session 33's change). A pad turned about a corner under its middle part touches
    nothing with its ends: no path; the same ends with the pad's lines not through one point
    (an end sliding on a face) still are one."""
    from tactile_jaw.flat_phase import _slid_path
    corner = np.array([98.37, 39.35])
    ends = [np.array([70.3, 68.7]) + k / 7.0 * np.array([14.6, -21.9]) for k in range(8)]
    about = [_pad(p, math.atan2(*(corner - p)[::-1])) for p in ends]  # each pad line through the corner
    assert all(abs(float(ln.normal @ corner - ln.d)) < 1e-9 for ln in about)
    assert _slid_path(about, 52.0) is None
    assert _slid_path(about, 52.0, part=True) is None
    turned = [_pad(p, math.atan2(*(corner - p)[::-1]) + math.radians(3.0 * k * (k % 2 - 0.5)))
              for k, p in enumerate(ends)]  # the same ends, the lines crossing apart: the end slid on a face
    p, q, _ = _slid_path(turned, 52.0)
    assert float(np.linalg.norm(q - p)) == pytest.approx(float(np.linalg.norm(ends[-1] - ends[0])), abs=0.01)
