"""Play a rosbag2 bag into the live ROS 2 graph, as ``ros2 bag play`` would (raw CDR, own Context).

A SingleThreadedExecutor: the EventsExecutor busy-waits in the Jazzy wheels.
"""

from __future__ import annotations

import contextlib
import math
import threading
import time
from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path

from rclpy.duration import Duration
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from rosbags.interfaces import QosDurability

from adbsat_ros.bags.io import BagError, open_bag
from adbsat_ros.ros.graph import GRAPH_POLL_S, absolute_topic, message_class, own_node

#: Longest wait [s] at the end of play() for reliable subscribers to acknowledge the last messages.
ACK_TIMEOUT_S = 5.0


@dataclass
class PlaySummary:
    """What :func:`play` published: counts per topic, passes through the bag, wall time [s]."""

    published: Counter = field(default_factory=Counter)
    passes: int = 0
    wall_seconds: float = 0.0
    interrupted: bool = False

    @property
    def total(self) -> int:
        """Messages published, all topics together."""
        return sum(self.published.values())


def _publisher_qos(connection, depth: int) -> QoSProfile:
    """Reliable, volatile (or transient-local if the recording publisher was) with ``depth``."""
    qos = QoSProfile(
        depth=depth, reliability=ReliabilityPolicy.RELIABLE, durability=DurabilityPolicy.VOLATILE
    )
    offered = getattr(connection.ext, "offered_qos_profiles", None) or []
    if offered and all(p.durability == QosDurability.TRANSIENT_LOCAL for p in offered):
        qos.durability = DurabilityPolicy.TRANSIENT_LOCAL
    return qos


def _sleep_until(deadline: float, stop: threading.Event) -> bool:
    """Sleep until ``deadline`` (time.monotonic) or ``stop``; True if stopped."""
    return stop.wait(max(0.0, deadline - time.monotonic()))


def play(
    bag_path,
    rate: float = 1.0,
    loop: bool = False,
    topics=None,
    wait_for_subscribers: int = 0,
    wait_timeout: float = 30.0,
    qos_depth: int = 1000,
    stop: threading.Event | None = None,
    log=None,
    node_name: str = "adbsat_bag_player",
) -> PlaySummary:
    """Publish a bag's messages into the ROS graph with their recorded timing.

    rate: playback speed, > 0 (2 plays twice as fast as recorded).
    topics: play only these topics, each in the bag (default: all).
    wait_for_subscribers: before the first message, wait for this many subscribers per topic,
      for at most ``wait_timeout`` [s].
    qos_depth: history depth of the publishers (reliable; transient-local if recorded so).
    stop: a threading.Event to stop playing from another thread.
    Returns when reliable readers acked the last messages (:data:`ACK_TIMEOUT_S` at most).
    BagError: a missing bag, topic or type, non-CDR messages, or subscribers not there in time.
    """
    if not (isinstance(rate, (int, float)) and math.isfinite(rate) and rate > 0):
        raise BagError(f"rate must be a finite number > 0, got {rate!r}")
    if wait_for_subscribers < 0:
        raise BagError(f"wait_for_subscribers must be >= 0, got {wait_for_subscribers!r}")
    stop = stop or threading.Event()
    log = log or (lambda line: None)
    path = Path(bag_path)
    with contextlib.closing(open_bag(path)) as reader:
        connections = _select_connections(path, reader.connections, topics)
        classes = {c.topic: message_class(c.msgtype, c.topic) for c in connections}
        qos = {c.topic: _publisher_qos(c, qos_depth) for c in connections}
        count = sum(c.msgcount for c in connections)
        # topics with messages: the ones worth waiting for subscribers on
        played = {c.topic for c in connections if c.msgcount > 0}
    summary = PlaySummary()
    start = time.monotonic()
    try:
        with own_node(node_name) as (node, executor):
            publishers = {
                topic: node.create_publisher(cls, topic, qos[topic])
                for topic, cls in classes.items()
            }
            if wait_for_subscribers:
                waited = {t: p for t, p in publishers.items() if t in played}
                _wait_for_subscribers(
                    waited, wait_for_subscribers, wait_timeout, executor, stop, log
                )
            log(
                f"playing {count} messages on {len(publishers)} topics of {path} at rate {rate:g}"
                + (" (looping)" if loop else "")
            )
            start = time.monotonic()
            while not stop.is_set():
                summary.passes += 1
                if not _play_once(path, connections, publishers, rate, stop, summary):
                    break
                if not loop:
                    break
            summary.wall_seconds = time.monotonic() - start
            # Let reliable subscribers acknowledge the last messages before the publishers go
            # (acknowledgements follow Fast DDS heartbeats: up to a few seconds between processes).
            for publisher in publishers.values():
                publisher.wait_for_all_acked(Duration(seconds=ACK_TIMEOUT_S))
    except KeyboardInterrupt:
        summary.interrupted = True
    finally:
        summary.wall_seconds = summary.wall_seconds or time.monotonic() - start
    if stop.is_set():
        summary.interrupted = True
    return summary


def _select_connections(path: Path, connections, topics):
    for c in connections:
        fmt = getattr(c.ext, "serialization_format", None)
        if fmt != "cdr":
            raise BagError(
                f"input bag {path}: topic {c.topic} is serialized as {fmt!r}; "
                "only rosbag2 CDR bags can be played"
            )
    if topics is None:
        return list(connections)
    wanted = [absolute_topic(t) for t in topics]
    available = sorted({c.topic for c in connections})
    unknown = [t for t in wanted if t not in available]
    if unknown:
        raise BagError(
            f"input bag {path}: no topic {', '.join(unknown)} in the bag; "
            f"its topics are {', '.join(available) or '(none)'}"
        )
    return [c for c in connections if c.topic in wanted]


def _wait_for_subscribers(publishers, n, timeout, executor, stop, log) -> None:
    log(f"waiting up to {timeout:g} s for {n} subscriber(s) on each of {', '.join(publishers)}")
    deadline = time.monotonic() + timeout
    while not stop.is_set():
        lacking = [t for t, p in publishers.items() if p.get_subscription_count() < n]
        if not lacking:
            return
        if time.monotonic() > deadline:
            raise BagError(
                f"no {n} subscriber(s) within {timeout:g} s on topic(s) {', '.join(lacking)} "
                "(play only the topics someone listens to with --topics, "
                "or drop --wait-for-subscribers)"
            )
        executor.spin_once(timeout_sec=GRAPH_POLL_S)


def _play_once(path, connections, publishers, rate, stop, summary) -> bool:
    """One pass through the bag; False if stopped."""
    with contextlib.closing(open_bag(path)) as reader:
        wanted = [c for c in reader.connections if c.topic in publishers]
        first_ns = None
        start = time.monotonic()
        for connection, t_ns, raw in reader.messages(connections=wanted):
            if first_ns is None:
                first_ns = t_ns
            if _sleep_until(start + (t_ns - first_ns) * 1e-9 / rate, stop):
                return False
            publishers[connection.topic].publish(bytes(raw))
            summary.published[connection.topic] += 1
    return True
