"""A run as a ROS 2 bag: one MCAP file of CDR messages that ``ros2 bag info``/``play`` and
Foxglove open with no plugin (docs/formats.md#ros-2-bag).

The bag is built from the run log's records (hand_driver.log), one at a time, in their
order: ``tactile replay LOG --mcap OUT`` feeds it the records of a log, ``tactile demo`` and
``tactile explore --mcap OUT`` the records as they are written (:class:`BaggedLog`), so a
run's bag and its replay's hold the same messages. Live, every reading's messages are a
chunk of their own, written and fsync'd before the run goes on, like the log's lines.

Messages are the ROS 2 Jazzy definitions (``rosbags``' type store: their text is stored in
the file, and their CDR serialization is rosbags'); the container is written by ``mcap``,
Foxglove's own library. Lengths in m, angles in rad (REP 103), frames: ``hand`` (the jaw's
base, docs/formats.md's hand frame), and per finger ``<f>_base``, ``<f>_link1``,
``<f>_link2``, ``<f>_pad`` (its fingertip end, x along the link).
"""

from __future__ import annotations

import datetime
import io
import json
import math
import os
from types import SimpleNamespace
from typing import Any

import numpy as np

from hand_driver import kinematics as kin
from hand_driver.config import parse_config
from hand_driver.log import RunLog
from recognizer.curves import CURVES, Pose
from recognizer.touches import touch_points
from tactile_common.errors import InputError
from tactile_common.files import atomic_path, create_exclusive

#: every topic and its message type; a topic gets messages as docs/formats.md#ros-2-bag says
TOPICS: dict[str, str] = {
    "/joint_states": "sensor_msgs/msg/JointState",
    "/tf_static": "tf2_msgs/msg/TFMessage",
    "/tf": "tf2_msgs/msg/TFMessage",
    "/jaw/pads": "visualization_msgs/msg/MarkerArray",
    "/jaw/touches": "visualization_msgs/msg/MarkerArray",
    "/recognition/curve": "visualization_msgs/msg/MarkerArray",
    "/recognition/pose": "geometry_msgs/msg/PoseWithCovarianceStamped",
    "/recognition/answer": "std_msgs/msg/String",
}
HAND_FRAME = "hand"
#: mm → m
M_PER_MM = 1e-3
#: length of a touch's tangent-line marker on each side of its contact (mm)
TANGENT_HALF_MM = 6.0
#: the recognized curve beyond its outermost contacts (mm of arc on each side), and its points
CURVE_MARGIN_MM = 20.0
CURVE_POINTS = 200
#: topics whose last message a late subscriber still gets (ROS 2 transient-local durability)
#: how many of a latched topic's messages a late subscriber gets: every touch of a run
LATCHED_DEPTH = 100
LATCHED = ("/tf_static", "/jaw/touches", "/recognition/curve", "/recognition/pose", "/recognition/answer")
_COLORS = {"left": (0.2, 0.5, 1.0, 1.0), "right": (1.0, 0.5, 0.1, 1.0), "contact": (0.1, 0.8, 0.2, 1.0),
           "tangent": (0.1, 0.6, 0.2, 0.8), "curve": (0.9, 0.1, 0.6, 1.0), "link": (0.6, 0.6, 0.6, 1.0)}


def require_ros():
    """The libraries of the ``ros`` extra (imported when a bag is written); without them one
    line saying what to install, before a command does anything."""
    try:
        from mcap.writer import CompressionType, Writer
        from rosbags.interfaces import Qos, QosDurability, QosHistory, QosLiveliness, QosReliability, QosTime
        from rosbags.rosbag2.metadata import dump_qos_v8
        from rosbags.typesys import Stores, get_typestore
    except ImportError as exc:
        raise InputError(f"--mcap needs the packages of the ros extra ({exc.name} is missing): "
                         f"pip install -e '.[ros]'") from None
    return SimpleNamespace(Writer=Writer, CompressionType=CompressionType, Qos=Qos, QosDurability=QosDurability,
                           QosHistory=QosHistory, QosLiveliness=QosLiveliness, QosReliability=QosReliability,
                           QosTime=QosTime, dump_qos_v8=dump_qos_v8, Stores=Stores, get_typestore=get_typestore)


def _qos(ros, latched: bool) -> str:
    """The channel's ``offered_qos_profiles`` (rosbag2's YAML): reliable, keep last 10; latched
    topics transient-local, keep last ``LATCHED_DEPTH``, as ``ros2 bag play`` then offers them
    to late subscribers."""
    never = ros.QosTime(0x7FFFFFFF, 0xFFFFFFFF)  # rmw's "infinite" duration: no deadline, lifespan, lease
    durability = ros.QosDurability.TRANSIENT_LOCAL if latched else ros.QosDurability.VOLATILE
    qos = ros.Qos(ros.QosHistory.KEEP_LAST, LATCHED_DEPTH if latched else 10, ros.QosReliability.RELIABLE, durability,
                  never, never, ros.QosLiveliness.AUTOMATIC, never, False)
    return ros.dump_qos_v8([qos])


def _ns(seconds: float) -> int:
    return int(round(seconds * 1e9))


def _stamp(ns: int) -> dict:
    return {"sec": ns // 1_000_000_000, "nanosec": ns % 1_000_000_000}


def _quat_z(angle: float) -> dict:
    return {"x": 0.0, "y": 0.0, "z": math.sin(angle / 2.0), "w": math.cos(angle / 2.0)}


def _point(x_mm: float, y_mm: float) -> dict:
    return {"x": float(x_mm) * M_PER_MM, "y": float(y_mm) * M_PER_MM, "z": 0.0}


def _transform(ns: int, parent: str, child: str, x_mm: float, y_mm: float, angle: float) -> dict:
    return {"header": {"stamp": _stamp(ns), "frame_id": parent}, "child_frame_id": child,
            "transform": {"translation": _point(x_mm, y_mm), "rotation": _quat_z(angle)}}


def _marker(ns: int, space: str, ident: int, kind: int, points, color: str, width_mm: float) -> dict:
    r, g, b, a = _COLORS[color]
    return {"header": {"stamp": _stamp(ns), "frame_id": HAND_FRAME}, "ns": space, "id": ident, "type": kind,
            "action": 0, "pose": {"orientation": {"w": 1.0}},
            "scale": {"x": width_mm * M_PER_MM, "y": width_mm * M_PER_MM, "z": width_mm * M_PER_MM},
            "color": {"r": r, "g": g, "b": b, "a": a}, "points": [_point(x, y) for x, y in points]}


LINE_STRIP, LINE_LIST, SPHERE_LIST = 4, 5, 7  # visualization_msgs/msg/Marker types


def joint_names(config) -> list[str]:
    """``<finger>_joint<k>`` (k from 1, proximal first), in the config's joint order."""
    return [f"{f.name}_joint{k + 1}" for f in config.fingers for k in range(len(f.joints))]


def curve_points(answer: dict) -> np.ndarray:
    """The recognized curve in the hand frame (mm), ``CURVE_POINTS`` points: a closed curve
    whole, an open one over its contacts' t and ``CURVE_MARGIN_MM`` of arc beyond each."""
    curve = CURVES[answer["class"]](answer["params"])
    if curve.t_period is not None:
        t = np.linspace(curve.t_period[0], curve.t_period[1], CURVE_POINTS)
    else:
        ts = [c["t"] for c in answer["contacts"]] or [0.0]
        lo = float(curve.t_at_arc_length(min(ts), -CURVE_MARGIN_MM))
        hi = float(curve.t_at_arc_length(max(ts), CURVE_MARGIN_MM))
        t = np.linspace(lo, hi, CURVE_POINTS)
    px, py = curve.point(t)
    p = answer["pose"]
    return np.column_stack(Pose(p["theta"], p["x"], p["y"]).apply(px, py))


def pose_covariance(uncertainty: dict) -> list[float]:
    """The 6×6 row-major covariance of (x, y, z, roll, pitch, yaw) in m² and rad² from the
    answer's σ's of ``pose_x``, ``pose_y``, ``pose_theta`` (the answer carries no
    correlations: the off-diagonal terms are 0). z, roll and pitch are 0: the pose lies in
    the hand's plane by construction. A σ the answer lacks (a line has no ``pose_x``: its
    pose is a foot of perpendicular) is -1 on the diagonal, "unknown"."""
    cov = [0.0] * 36
    for k, key, scale in ((0, "pose_x", M_PER_MM), (1, "pose_y", M_PER_MM), (5, "pose_theta", 1.0)):
        sigma = uncertainty.get(key)
        cov[7 * k] = (float(sigma) * scale) ** 2 if sigma is not None else -1.0
    return cov


class BagWriter:
    """Messages of run-log records into one MCAP file (module docstring). ``record(rec)``
    takes the log's records in order, the header first; ``answer(answer)`` writes the
    recognition (the answer the command printed); ``close()`` writes the summary."""

    def __init__(self, stream, *, durable: bool):
        self.ros = require_ros()
        self.store = self.ros.get_typestore(self.ros.Stores.ROS2_JAZZY)
        compression = self.ros.CompressionType.NONE if durable else self.ros.CompressionType.ZSTD
        self.stream = stream
        self.durable = durable
        self.writer = self.ros.Writer(stream, compression=compression)
        self.writer.start(profile="ros2", library="tactile-jaw")
        self.channels: dict[str, int] = {}
        for topic, msgtype in TOPICS.items():
            text, _ = self.store.generate_msgdef(msgtype, ros_version=2)
            schema = self.writer.register_schema(name=msgtype, encoding="ros2msg", data=text.encode())
            self.channels[topic] = self.writer.register_channel(
                topic=topic, message_encoding="cdr", schema_id=schema,
                metadata={"offered_qos_profiles": _qos(self.ros, topic in LATCHED)})
        self.config = None
        self.names: list[str] = []
        self.origin_ns = 0  # epoch ns of the log's monotonic origin
        self.monotonic_origin = 0.0
        self.last_ns = 0
        self.stop: dict | None = None
        self.reading_ns: list[int] = []  # every reading's stamp
        self.touch_ns: dict[int, int] = {}  # a touch's last sample reading's stamp
        self.counts = {topic: 0 for topic in TOPICS}
        self._zeros: dict[str, Any] = {}

    # -- messages ---------------------------------------------------------------------------
    def _build(self, msgtype: str, value: Any):
        """A rosbags message of ``msgtype`` from nested mappings; absent fields take the
        type's zero (empty strings and sequences, 0, false)."""
        consts, fields = self.store.fielddefs[msgtype]
        cls = self.store.types[msgtype]
        kwargs = {}
        for name, (node, desc) in fields:
            v = value.get(name) if isinstance(value, dict) else None
            kwargs[name] = self._field(node, desc, v)
        return cls(**kwargs)

    def _field(self, node, desc, v):
        kind = int(node)
        if kind == 1:  # BASE
            base = desc[0]
            if base == "string":
                return "" if v is None else str(v)
            if base == "bool":
                return bool(v)
            return (float(v) if v is not None else 0.0) if base.startswith("float") else (int(v) if v is not None else 0)
        if kind == 2:  # NAME: a message; an absent one is its type's zero, built once (serializing only reads it)
            if v:
                return self._build(desc, v)
            if desc not in self._zeros:
                self._zeros[desc] = self._build(desc, {})
            return self._zeros[desc]
        (inner_node, inner_desc), size = desc  # ARRAY (3) or SEQUENCE (4)
        items = list(v) if v is not None else ([None] * size if size else [])
        if int(inner_node) == 1 and inner_desc[0] != "string":
            dtype = {"float64": np.float64, "float32": np.float32, "bool": np.bool_, "uint8": np.uint8,
                     "int8": np.int8, "octet": np.uint8, "byte": np.uint8, "char": np.uint8}.get(
                inner_desc[0], np.dtype(inner_desc[0]))
            return np.array([0 if x is None else x for x in items], dtype=dtype)
        return [self._field(inner_node, inner_desc, x) for x in items]

    def _write(self, topic: str, ns: int, value: dict) -> None:
        msgtype = TOPICS[topic]
        data = self.store.serialize_cdr(self._build(msgtype, value), msgtype)
        self.writer.add_message(self.channels[topic], log_time=ns, publish_time=ns, data=bytes(data),
                                sequence=self.counts[topic])
        self.counts[topic] += 1

    def _sync(self) -> None:
        """Live: this record's messages to disk (their own chunk), like the log's line."""
        if self.durable:
            self.writer.flush()
            self.stream.flush()
            os.fsync(self.stream.fileno())

    # -- records ----------------------------------------------------------------------------
    def record(self, rec: dict) -> None:
        kind = rec.get("type")
        if kind == "header":
            self._header(rec)
        elif self.config is None:
            raise ValueError("BagWriter.record before the header")
        elif kind == "reading":
            self._reading(rec)
        elif kind == "sample":
            self.touch_ns[int(rec["touch"])] = self.reading_ns[int(rec["reading"])]
            return
        elif kind == "event" and rec.get("kind") == "touch_used":
            self._touch(rec)
        elif kind == "event" and rec.get("kind") in ("stopped_early", "budget_spent"):
            self.stop = rec
        elif kind == "result":
            self.answer(result_answer(rec, self.stop, self.config))
        else:
            return
        self._sync()

    def _header(self, rec: dict) -> None:
        self.config = parse_config(rec["config"], "log header config", recorded=True)
        self.names = joint_names(self.config)
        start = datetime.datetime.fromisoformat(rec["start_time"])
        self.monotonic_origin = float(rec.get("monotonic_origin") or 0.0)
        self.origin_ns = _ns(start.timestamp())
        self.last_ns = self.origin_ns
        statics = []
        for f in self.config.fingers:
            statics.append(_transform(self.origin_ns, HAND_FRAME, f"{f.name}_base", f.base.x, f.base.y, f.base.angle))
            statics.append(_transform(self.origin_ns, f"{f.name}_link2", f"{f.name}_pad", f.joints[1].link_mm,
                                      f.pad.side_sign * f.pad.offset_mm, 0.0))
        self._write("/tf_static", self.origin_ns, {"transforms": statics})

    def _reading(self, rec: dict) -> None:
        t = rec.get("t")
        ns = self.origin_ns + _ns(t - self.monotonic_origin) if t is not None else self.last_ns
        self.last_ns = ns
        self.reading_ns.append(ns)
        ticks = np.asarray(rec["ticks"], dtype=float)
        q = kin.ticks_to_angles(self.config.joints, ticks)
        self._write("/joint_states", ns, {"header": {"stamp": _stamp(ns)}, "name": self.names, "position": q})
        transforms, markers = [], []
        slices = self.config.joint_slices()
        for k, f in enumerate(self.config.fingers):
            q1, q2 = q[slices[f.name]]
            transforms.append(_transform(ns, f"{f.name}_base", f"{f.name}_link1", 0.0, 0.0, q1))
            transforms.append(_transform(ns, f"{f.name}_link1", f"{f.name}_link2", f.joints[0].link_mm, 0.0, q2))
            line = kin.finger_pad_line(f, np.array([q1, q2]))
            tip = line.joint2 + f.joints[1].link_mm * line.tangent
            markers.append(_marker(ns, "fingers", k, LINE_STRIP, [(f.base.x, f.base.y), line.joint2, tip], "link", 2.0))
            markers.append(_marker(ns, "pads", k, LINE_STRIP, [line.proximal, line.distal], f.name, 4.0))
        self._write("/tf", ns, {"transforms": transforms})
        self._write("/jaw/pads", ns, {"markers": markers})

    def _touch(self, rec: dict) -> None:
        """A touch the recognizer got: its contact points, and its tangent lines through them."""
        points = touch_points(rec.get("samples") or {})  # a flat press's contact touch as one sample
        xs, ys, phis = points["x"], points["y"], points["phi"]
        ident = int(rec["touch"])
        ns = self.touch_ns.get(ident, self.last_ns)
        tangents = []
        for x, y, phi in zip(xs, ys, phis):
            dx, dy = TANGENT_HALF_MM * math.cos(phi), TANGENT_HALF_MM * math.sin(phi)
            tangents += [(x - dx, y - dy), (x + dx, y + dy)]
        self._write("/jaw/touches", ns, {"markers": [
            _marker(ns, "contacts", ident, SPHERE_LIST, list(zip(xs, ys)), "contact", 1.5),
            _marker(ns, "tangents", ident, LINE_LIST, tangents, "tangent", 0.5)]})

    def answer(self, answer: dict) -> None:
        """The recognition: the answer JSON (std_msgs/String), and, for a class, its pose with
        covariance and the curve as a marker."""
        ns = self.last_ns
        if answer["class"] != "unclassified":
            p = answer["pose"]
            self._write("/recognition/pose", ns, {
                "header": {"stamp": _stamp(ns), "frame_id": HAND_FRAME},
                "pose": {"pose": {"position": _point(p["x"], p["y"]), "orientation": _quat_z(p["theta"])},
                         "covariance": pose_covariance(answer.get("uncertainty") or {})}})
            self._write("/recognition/curve", ns, {"markers": [
                _marker(ns, answer["class"], 0, LINE_STRIP, curve_points(answer), "curve", 1.0)]})
        self._write("/recognition/answer", ns, {"data": json.dumps(answer, allow_nan=False)})

    def close(self) -> None:
        self.writer.finish()


def result_answer(rec: dict, stop: dict | None, config) -> dict:
    """The answer a live run printed, from its log's ``result`` record (and its last stop
    event): the recognition, or the refusal with its advice (tools.cmd_explore.refusal)."""
    from tools.cmd_explore import refusal, too_few_reason

    recognition = rec.get("recognition")
    if recognition is not None and recognition["class"] != "unclassified":
        return recognition
    reason = None if recognition is not None else too_few_reason(rec.get("touches_used", 0),
                                                                    rec.get("touches_tried", 0))
    return refusal(recognition, reason, stop, config)


def write_bag(path: str | os.PathLike[str], contents, answer: dict) -> None:
    """The bag of a read log (hand_driver.log.read_log) with ``answer``, written whole
    (tactile_common.files.atomic_path)."""
    records = [contents.header, *_log_records(contents)]
    with atomic_path(path, flag="--mcap") as tmp, open(tmp, "wb") as stream:
        bag = BagWriter(stream, durable=False)
        for rec in records:
            bag.record(rec)
        bag.answer(answer)
        bag.close()


def _log_records(contents) -> list[dict]:
    """The records a bag is built from: every reading, each touch's samples (which stamp its
    markers) and the events. read_log keeps them apart; a bag does not depend on their
    interleaving, as every message's stamp is its reading's."""
    samples = [{"type": "sample", "touch": t.touch, "reading": i} for t in contents.touches for i in t.readings]
    return [*contents.readings, *samples, *contents.events]


class BaggedLog(RunLog):
    """A run log whose every record also goes, as it is written, to a bag (``mcap_path``)."""

    def __init__(self, path, mcap_path, *, force: bool):
        super().__init__(path)
        # create_exclusive's file is unbuffered: a raw write may take part of what it is given,
        # which the MCAP writer does not retry, so its bytes go through a buffer flushed per record
        self.stream = io.BufferedWriter(create_exclusive(mcap_path, force=force, flag="--mcap"))
        try:
            self.bag = BagWriter(self.stream, durable=True)
        except BaseException:
            self.stream.close()
            raise

    def write(self, record: dict) -> None:
        super().write(record)
        self.bag.record(record)

    def close(self) -> None:
        try:
            super().close()
        finally:
            if self.stream is not None:
                try:
                    self.bag.close()
                finally:
                    self.stream.close()
                    self.stream = None
