"""ROS 2 bags (tools/ros_bag.py) read back by readers that did not write them: the MCAP
container by rosbags' own MCAP reader (the bag's writer is the mcap package), every
message decoded by mcap-ros2-support's CDR decoder from the definition stored in the file
(the writer serialized with rosbags). Every topic, type, count and value is checked
against the run log, with the jaw's kinematics written out here from docs/formats.md."""

from __future__ import annotations

import datetime
import json
import math
from pathlib import Path

import numpy as np
import pytest

from hand_driver.log import read_log
from tools.ros_bag import TOPICS

mcap_ros2_dynamic = pytest.importorskip("mcap_ros2._dynamic")
rosbag2 = pytest.importorskip("rosbags.rosbag2")


class Bag(dict):
    """topic → [Message] in log-time order; a message is decoded when first looked at
    (decoding thousands of markers in pure Python is what would make these tests slow)."""


class Message:
    def __init__(self, msgtype: str, ns: int, raw: bytes, decoder):
        self.msgtype, self.ns, self.raw, self._decoder, self._msg = msgtype, ns, raw, decoder, None

    @property
    def msg(self):
        if self._msg is None:
            self._msg = self._decoder(self.raw)
        return self._msg


def read_bag(path: Path) -> Bag:
    out = Bag()
    decoders = {}
    with rosbag2.Reader(path) as reader:
        for conn in reader.connections:
            assert conn.ext.serialization_format == "cdr"
            out[conn.topic] = []
            decoders.setdefault(conn.msgtype, mcap_ros2_dynamic.generate_dynamic(conn.msgtype, conn.msgdef.data)[
                conn.msgtype])
        for conn, ns, raw in reader.messages():
            out[conn.topic].append(Message(conn.msgtype, ns, bytes(raw), decoders[conn.msgtype]))
    return out


def ns_of(stamp) -> int:
    return stamp.sec * 1_000_000_000 + stamp.nanosec


def yaw(q) -> float:
    assert q.x == 0.0 and q.y == 0.0
    return 2.0 * math.atan2(q.z, q.w)


@pytest.fixture(scope="module")
def run(default_demo, tactile_in_process):
    d = default_demo["dir"]
    replayed = d / "replay.mcap"
    rc, out, err = tactile_in_process(["replay", str(default_demo["log"]), "--json", "--mcap", str(replayed)])
    assert rc == 0, err
    contents = read_log(default_demo["log"])
    return {"answer": contents.result["recognition"], "replayed": json.loads(out), "log": contents,
            "log_path": default_demo["log"], "live": read_bag(default_demo["mcap"]), "replay": read_bag(replayed),
            "dir": d, "live_path": default_demo["mcap"]}


def _without_timing(answer: dict) -> dict:
    return {k: v for k, v in answer.items() if k != "timing"}


def test_every_topic_with_its_type_and_count(run):
    contents, answer = run["log"], run["answer"]
    n = len(contents.readings)
    used = [e for e in contents.events if e["kind"] == "touch_used"]
    expected = {"/joint_states": n, "/tf": n, "/jaw/pads": n, "/tf_static": 1, "/jaw/touches": len(used),
                "/recognition/curve": 1, "/recognition/pose": 1, "/recognition/answer": 1}
    for bag in (run["live"], run["replay"]):
        assert set(bag) == set(TOPICS) == set(expected)
        for topic, msgs in bag.items():
            assert len(msgs) == expected[topic], topic
            assert {m.msgtype for m in msgs} == {TOPICS[topic]}
    assert answer["class"] == "ellipse" and n > 100 and len(used) >= 3


def _config(contents) -> dict:
    return contents.header["config"]


def _angles(config: dict, ticks) -> list[float]:
    """q = direction · (tick − zero_tick) · 2π/4096 (docs/formats.md, jaw config)."""
    joints = [j for f in config["fingers"] for j in f["joints"]]
    return [j["direction"] * (t - j["zero_tick"]) * 2 * math.pi / 4096 for j, t in zip(joints, ticks)]


def _epoch_ns(contents, t: float) -> int:
    start = datetime.datetime.fromisoformat(contents.header["start_time"]).timestamp()
    return round((start + t - contents.header["monotonic_origin"]) * 1e9)


def test_joint_states_are_every_reading_in_radians_at_its_own_stamp(run):
    contents = run["log"]
    config = _config(contents)
    names = [f"{f['name']}_joint{k + 1}" for f in config["fingers"] for k in range(len(f["joints"]))]
    assert names == ["left_joint1", "left_joint2", "right_joint1", "right_joint2"]
    for reading, message in zip(contents.readings, run["live"]["/joint_states"]):
        log_ns, msg = message.ns, message.msg
        assert list(msg.name) == names
        assert np.allclose(msg.position, _angles(config, reading["ticks"]), rtol=0, atol=1e-12)
        assert list(msg.velocity) == [] and list(msg.effort) == []
        assert abs(ns_of(msg.header.stamp) - _epoch_ns(contents, reading["t"])) <= 1000  # 1 µs: float seconds
        assert log_ns == ns_of(msg.header.stamp)


def _finger_geometry(finger: dict, q1: float, q2: float):
    """Base, distal joint, fingertip and the pad's two ends (mm), docs/formats.md."""
    b = finger["base"]
    a1 = math.radians(b["angle_deg"]) + q1
    a2 = a1 + q2
    l1, l2 = finger["joints"][0]["link_mm"], finger["joints"][1]["link_mm"]
    base = np.array([b["x"], b["y"]])
    j2 = base + l1 * np.array([math.cos(a1), math.sin(a1)])
    e2 = np.array([math.cos(a2), math.sin(a2)])
    side = 1 if finger["pad"]["side"] == "left" else -1
    n = np.array([math.cos(a2 + side * math.pi / 2), math.sin(a2 + side * math.pi / 2)])
    tip = j2 + l2 * e2
    distal = tip + finger["pad"]["offset_mm"] * n
    return base, j2, tip, distal - finger["pad"]["length_mm"] * e2, distal


def _xy(points) -> np.ndarray:
    assert all(p.z == 0.0 for p in points)
    return np.array([[p.x, p.y] for p in points]) * 1000.0  # m → mm


def test_tf_and_pad_markers_follow_the_jaw(run):
    contents = run["log"]
    config = _config(contents)
    static = run["live"]["/tf_static"][0].msg
    frames = {(t.header.frame_id, t.child_frame_id): t.transform for t in static.transforms}
    for f in config["fingers"]:
        base = frames[("hand", f"{f['name']}_base")]
        assert base.translation.x * 1000 == pytest.approx(f["base"]["x"]) and \
            base.translation.y * 1000 == pytest.approx(f["base"]["y"])
        assert yaw(base.rotation) == pytest.approx(math.radians(f["base"]["angle_deg"]), abs=1e-12)
        pad = frames[(f"{f['name']}_link2", f"{f['name']}_pad")]
        side = 1 if f["pad"]["side"] == "left" else -1
        assert pad.translation.x * 1000 == pytest.approx(f["joints"][1]["link_mm"])
        assert pad.translation.y * 1000 == pytest.approx(side * f["pad"]["offset_mm"])
    step = max(1, len(contents.readings) // 50)  # every 50th reading: the values, all of them: the count
    for k in range(0, len(contents.readings), step):
        q = _angles(config, contents.readings[k]["ticks"])
        tf = run["live"]["/tf"][k].msg
        pads = run["live"]["/jaw/pads"][k].msg
        by_child = {t.child_frame_id: t for t in tf.transforms}
        markers = {(m.ns, m.id): m for m in pads.markers}
        for i, f in enumerate(config["fingers"]):
            q1, q2 = q[2 * i], q[2 * i + 1]
            link1, link2 = by_child[f"{f['name']}_link1"], by_child[f"{f['name']}_link2"]
            assert link1.header.frame_id == f"{f['name']}_base" and link2.header.frame_id == f"{f['name']}_link1"
            assert yaw(link1.transform.rotation) == pytest.approx(q1, abs=1e-12)
            assert yaw(link2.transform.rotation) == pytest.approx(q2, abs=1e-12)
            assert link2.transform.translation.x * 1000 == pytest.approx(f["joints"][0]["link_mm"])
            base, j2, tip, proximal, distal = _finger_geometry(f, q1, q2)
            assert np.allclose(_xy(markers[("fingers", i)].points), [base, j2, tip], atol=1e-9)
            pad = markers[("pads", i)]
            assert pad.header.frame_id == "hand" and pad.type == 4  # LINE_STRIP
            assert np.allclose(_xy(pad.points), [proximal, distal], atol=1e-9)


def test_touch_markers_are_the_recognizers_samples_and_their_tangents(run):
    contents = run["log"]
    used = [e for e in contents.events if e["kind"] == "touch_used"]
    stamps = {t.touch: _epoch_ns(contents, contents.readings[t.readings[-1]]["t"]) for t in contents.touches
              if t.readings}
    bag = {m.msg.markers[0].id: (m.ns, m.msg) for m in run["live"]["/jaw/touches"]}
    assert sorted(bag) == sorted(e["touch"] for e in used)
    for event in used:
        log_ns, msg = bag[event["touch"]]
        contacts, tangents = msg.markers
        assert (contacts.ns, contacts.id, contacts.type) == ("contacts", event["touch"], 7)  # SPHERE_LIST
        assert (tangents.ns, tangents.id, tangents.type) == ("tangents", event["touch"], 5)  # LINE_LIST
        s = event["samples"]
        assert np.allclose(_xy(contacts.points), np.column_stack([s["x"], s["y"]]), atol=1e-9)
        ends = _xy(tangents.points).reshape(-1, 2, 2)
        assert np.allclose(ends.mean(axis=1), np.column_stack([s["x"], s["y"]]), atol=1e-9)
        d = ends[:, 1] - ends[:, 0]
        assert np.allclose(np.arctan2(d[:, 1], d[:, 0]), np.remainder(np.array(s["phi"]) + np.pi, 2 * np.pi) - np.pi,
                           atol=1e-9)
        assert abs(log_ns - stamps[event["touch"]]) <= 1000


def test_recognition_pose_covariance_curve_and_answer(run):
    answer, contents = run["answer"], run["log"]
    last = _epoch_ns(contents, contents.readings[-1]["t"])
    ns, pose = run["live"]["/recognition/pose"][0].ns, run["live"]["/recognition/pose"][0].msg
    assert abs(ns - last) <= 1000 and pose.header.frame_id == "hand"
    p, u = answer["pose"], answer["uncertainty"]
    assert pose.pose.pose.position.x * 1000 == pytest.approx(p["x"], abs=1e-9)
    assert pose.pose.pose.position.y * 1000 == pytest.approx(p["y"], abs=1e-9)
    assert math.remainder(yaw(pose.pose.pose.orientation) - p["theta"], 2 * math.pi) == pytest.approx(0, abs=1e-12)
    cov = np.array(pose.pose.covariance).reshape(6, 6)
    assert cov[0, 0] == pytest.approx((u["pose_x"] / 1000) ** 2) and cov[1, 1] == pytest.approx((u["pose_y"] / 1000) ** 2)
    assert cov[5, 5] == pytest.approx(u["pose_theta"] ** 2)
    assert np.count_nonzero(cov) == 3
    curve = run["live"]["/recognition/curve"][0].msg
    (marker,) = curve.markers
    assert marker.type == 4 and marker.ns == "ellipse" and len(marker.points) == 200
    xy = _xy(marker.points)
    c, s = math.cos(p["theta"]), math.sin(p["theta"])
    u_, v_ = ((xy - [p["x"], p["y"]]) @ np.array([[c, -s], [s, c]])).T  # into the canonical frame
    a, b = answer["params"]["a"], answer["params"]["b"]
    assert np.allclose((u_ / a) ** 2 + (v_ / b) ** 2, 1.0, atol=1e-9)  # on the answered ellipse
    for contact in answer["contacts"]:  # and through every contact
        assert np.min(np.hypot(xy[:, 0] - contact["x"], xy[:, 1] - contact["y"])) < 0.6
    text = run["live"]["/recognition/answer"][0].msg
    assert json.loads(text.data) == answer  # the run's answer, as its log holds it
    replayed = run["replay"]["/recognition/answer"][0].msg
    assert json.loads(replayed.data) == run["replayed"]  # the replay's, as it printed it


def test_the_runs_bag_and_its_replays_hold_the_same_messages(run):
    for topic in TOPICS:
        live, replay = run["live"][topic], run["replay"][topic]
        if topic == "/recognition/answer":
            assert [_without_timing(json.loads(m.msg.data)) for m in live] == \
                [_without_timing(json.loads(m.msg.data)) for m in replay]
            continue
        # the same bytes: the same message (one reader decoded them above)
        assert sorted((m.ns, m.raw) for m in live) == sorted((m.ns, m.raw) for m in replay), topic


def test_bag_is_a_ros2_mcap_with_qos(run):
    from mcap.reader import make_reader

    with open(run["live_path"], "rb") as fh:
        reader = make_reader(fh)
        assert reader.get_header().profile == "ros2"
        summary = reader.get_summary()
    assert {s.encoding for s in summary.schemas.values()} == {"ros2msg"}
    for channel in summary.channels.values():
        assert channel.message_encoding == "cdr" and "durability" in channel.metadata["offered_qos_profiles"]
    assert summary.statistics.chunk_count > len(run["log"].readings)  # every reading its own chunk, live


def test_a_refusal_exits_3_with_its_advice_and_its_bag_has_no_pose(run, tactile_in_process):
    """The demo's log cut after its first used touch: too few to recognize an ellipse (its
    second round's two touches are both logged before their ``touch_used`` events, so a cut
    after the second would hold three). replay refuses (exit 3, the JSON answer unclassified
    with reason and advice), and the bag holds the refusal and no pose or curve."""
    lines = run["log_path"].read_text().splitlines(keepends=True)
    used = [k for k, line in enumerate(lines) if '"kind":"touch_used"' in line]
    cut = run["dir"] / "cut.jsonl"
    cut.write_text("".join(lines[:used[0] + 1]))
    rc, out, err = tactile_in_process(["replay", str(cut), "--json", "--mcap", str(run["dir"] / "cut.mcap")])
    assert rc == 3, err
    answer = json.loads(out)
    assert answer["class"] == "unclassified" and answer["reason"] and answer["advice"]
    assert answer["params"] == {} and answer["pose"] is None
    bag = read_bag(run["dir"] / "cut.mcap")
    assert bag["/recognition/pose"] == [] and bag["/recognition/curve"] == []
    assert json.loads(bag["/recognition/answer"][0].msg.data) == answer
    rc, out, _ = tactile_in_process(["replay", str(cut)])
    assert rc == 3 and out.startswith("refused:    ") and "\nadvice:     " in out


def test_a_killed_demo_leaves_its_readings_in_the_bag(tmp_path, killed_demo):
    """Written as the run goes: after SIGKILL, the bag's chunks hold every reading logged
    before the last (read record by record; the unfinished file has no summary)."""
    from mcap.exceptions import McapError
    from mcap.records import Channel, Message
    from mcap.stream_reader import StreamReader

    log, bag = tmp_path / "killed.jsonl", tmp_path / "killed.mcap"
    killed_demo(log, "--mcap", str(bag))
    readings = len(read_log(log).readings)
    topics, joint_states = {}, 0
    with open(bag, "rb") as fh:
        try:
            for record in StreamReader(fh, skip_magic=False).records:
                if isinstance(record, Channel):
                    topics[record.id] = record.topic
                elif isinstance(record, Message) and topics[record.channel_id] == "/joint_states":
                    joint_states += 1
        except (McapError, EOFError, ValueError):
            pass  # the cut end
    assert readings >= 60 and readings - 1 <= joint_states <= readings


def test_demo_writes_the_bag_without_a_log(tmp_path, tactile_in_process):
    """--mcap alone: the bag is built from the records of a scratch log, which is not left behind."""
    bag_path = tmp_path / "only.mcap"
    rc, out, err = tactile_in_process(["demo", "--json", "--mcap", str(bag_path)])
    assert rc == 0, err
    bag = read_bag(bag_path)
    n = len(bag["/joint_states"])
    assert n > 100 and len(bag["/tf"]) == len(bag["/jaw/pads"]) == n
    assert json.loads(bag["/recognition/answer"][0].msg.data) == json.loads(out)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["only.mcap"]
