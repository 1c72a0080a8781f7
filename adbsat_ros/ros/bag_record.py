"""Record topics of the live ROS 2 graph into a rosbag2 bag, as ``ros2 bag record`` would.

Raw CDR stamped with the receive time (UNIX ns), rosbag2 version 9; own rclpy Context, no signal
handlers (Ctrl-C closes the bag); stopped from another thread with a ``threading.Event``.
"""

from __future__ import annotations

import math
import threading
import time
from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path

from rclpy.qos import QoSProfile, ReliabilityPolicy

from adbsat_ros.bags.io import TYPESTORE, BagError, BagWriter
from adbsat_ros.bounds import errors_as
from adbsat_ros.ros.graph import GRAPH_POLL_S, absolute_topic, message_class, own_node

#: rosbag2 storage plugins :func:`record` can write.
STORAGES = ("mcap", "sqlite3")


@dataclass
class RecordSummary:
    """What :func:`record` wrote: the bag path, message counts per topic, topics never seen."""

    path: Path
    storage: str
    recorded: Counter = field(default_factory=Counter)
    types: dict = field(default_factory=dict)
    missing: list = field(default_factory=list)
    wall_seconds: float = 0.0
    interrupted: bool = False

    @property
    def total(self) -> int:
        """Messages recorded, all topics together."""
        return sum(self.recorded.values())


def _topic_type(spec: str):
    """'topic' or 'topic:type' -> (absolute topic, type or None)."""
    name, _, msgtype = spec.partition(":")
    name = name.strip()
    if not name or name == "/":
        raise BagError(f"topic {spec!r}: empty topic name")
    return absolute_topic(name), (msgtype.strip() or None)


def record(
    out_path,
    topics,
    storage: str = "mcap",
    duration: float | None = None,
    qos_depth: int = 1000,
    stop: threading.Event | None = None,
    ready: threading.Event | None = None,
    log=None,
    node_name: str = "adbsat_bag_recorder",
) -> RecordSummary:
    """Record topics of the ROS graph into a new rosbag2 bag (version 9).

    topics: ``/topic`` (type found once a publisher appears) or ``/topic:package/msg/Type``.
    storage: ``'mcap'`` or ``'sqlite3'``.
    duration: stop after this much wall time [s] (default: until ``stop`` or Ctrl-C).
    qos_depth: history depth (reliable unless a publisher offers only best effort).
    stop, ready: threading.Events: set ``stop`` to stop; ``ready`` is set once all are subscribed.
    Returns a RecordSummary with the bag closed and readable, whatever stopped the recording.
    BagError: no or bad topics or types, an existing output path, a type rosbags cannot describe.
    """
    specs = [_topic_type(t) for t in (topics or [])]
    if not specs:
        raise BagError("record: no topics given (name at least one, e.g. --topics /wrench /state)")
    if storage not in STORAGES:
        raise BagError(f"storage {storage!r} is not one of {', '.join(STORAGES)}")
    if duration is not None and not (math.isfinite(duration) and duration > 0):
        raise BagError(f"duration must be a finite number > 0 s, got {duration!r}")
    out = Path(out_path)
    pending = dict(specs)  # topic -> type or None (not subscribed yet)
    for topic, msgtype in pending.items():
        if msgtype is not None:
            message_class(msgtype, topic)
            _check_rosbags_type(msgtype, topic)
    stop = stop or threading.Event()
    log = log or (lambda line: None)
    summary = RecordSummary(path=out, storage=storage)
    with errors_as(BagError, OSError, f"output bag {out}: cannot be created: "):
        writer = BagWriter(out, storage)  # written beside `out`, moved there on commit
    start = time.monotonic()
    deadline = None if duration is None else start + duration
    try:
        with own_node(node_name) as (node, executor):
            log(
                f"recording {', '.join(pending)} into {out} ({storage})"
                + (f" for {duration:g} s" if duration else " until Ctrl-C")
            )
            while not stop.is_set() and (deadline is None or time.monotonic() < deadline):
                if pending:
                    _subscribe_ready_topics(node, writer, pending, summary, qos_depth, log)
                    if not pending and ready is not None:
                        ready.set()
                timeout = GRAPH_POLL_S if deadline is None else deadline - time.monotonic()
                executor.spin_once(timeout_sec=max(0.0, min(GRAPH_POLL_S, timeout)))
            # take what is already in the subscriptions' queues
            for _ in range(10000):
                before = summary.total
                executor.spin_once(timeout_sec=0.0)
                if summary.total == before:
                    break
            summary.wall_seconds = time.monotonic() - start
    except KeyboardInterrupt:
        summary.interrupted = True
    finally:
        summary.wall_seconds = summary.wall_seconds or time.monotonic() - start
        writer.commit()  # whatever stopped us, what was recorded is a complete bag
    summary.missing = sorted(pending)
    if stop.is_set():
        summary.interrupted = True
    return summary


def _check_rosbags_type(msgtype: str, topic: str) -> None:
    if msgtype not in TYPESTORE.types:
        raise BagError(
            f"topic {topic}: message type {msgtype!r} is not in rosbags' ROS 2 Jazzy type store, "
            "so its definition cannot be written to the bag"
        )


def _subscribe_ready_topics(
    node, writer, pending: dict, summary: RecordSummary, depth: int, log
) -> None:
    """Subscribe to every pending topic whose type is known (given, or seen in the graph)."""
    graph = None
    for topic in list(pending):
        msgtype = pending[topic]
        if msgtype is None:
            if graph is None:
                graph = dict(node.get_topic_names_and_types())
            types = graph.get(topic)
            if not types:
                continue
            if len(types) > 1:
                raise BagError(
                    f"topic {topic} has several types in the graph ({', '.join(types)}); "
                    f"give one as {topic}:TYPE"
                )
            msgtype = types[0]
            message_class(msgtype, topic)
            _check_rosbags_type(msgtype, topic)
        connection = writer.connection(topic, msgtype)
        reliability = ReliabilityPolicy.RELIABLE
        offered = node.get_publishers_info_by_topic(topic)
        if offered and all(
            p.qos_profile.reliability == ReliabilityPolicy.BEST_EFFORT for p in offered
        ):
            reliability = ReliabilityPolicy.BEST_EFFORT
        qos = QoSProfile(depth=depth, reliability=reliability)

        def write(raw, connection=connection, topic=topic):
            writer.write_raw(connection, time.time_ns(), raw)
            summary.recorded[topic] += 1

        node.create_subscription(message_class(msgtype, topic), topic, write, qos, raw=True)
        summary.types[topic] = msgtype
        del pending[topic]
        log(f"subscribed to {topic} ({msgtype})")
