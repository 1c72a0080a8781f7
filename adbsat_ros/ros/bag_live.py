"""Live rosbag tools: play a bag into the ROS 2 graph, record topics of the graph into a bag.

There is no ``ros2 bag`` with the PyPI ROS 2 wheels; these two functions stand in for it with
rclpy and rosbags (pure Python):

* :func:`play` reads the raw CDR bytes of a rosbag2 bag (mcap or sqlite3) and publishes them
  unchanged (rclpy publishes serialized bytes), keeping the recorded spacing in time scaled by
  ``rate``. Header stamps are not touched: a node sees the stamps that were recorded.
* :func:`record` subscribes with ``raw=True`` to the given topics and writes the CDR bytes with
  rosbags (rosbag2 version 9), stamping each message with its receive time (UNIX ns), as
  ``ros2 bag record`` does.

Both run their own rclpy Context and a SingleThreadedExecutor (the EventsExecutor busy-waits in
the Jazzy wheels), install no signal handlers (Ctrl-C arrives as KeyboardInterrupt and stops
them cleanly), and can be stopped from another thread with a ``threading.Event``. The ROS domain
and discovery range come from the environment (ROS_DOMAIN_ID, ROS_AUTOMATIC_DISCOVERY_RANGE).
"""

from __future__ import annotations

import contextlib
import importlib
import math
import threading
import time
from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path

import rclpy
from rclpy.context import Context
from rclpy.duration import Duration
from rclpy.executors import SingleThreadedExecutor
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from rosbags.interfaces import QosDurability

from adbsat_ros.bags.io import TYPESTORE, BagError, BagWriter, open_bag

#: rosbag2 storage plugins :func:`record` can write.
STORAGES = ("mcap", "sqlite3")
#: Seconds between two looks at the ROS graph while waiting for topics or subscribers.
GRAPH_POLL_S = 0.05
#: Longest wait [s] at the end of play() for reliable subscribers to acknowledge the last messages.
ACK_TIMEOUT_S = 5.0


@dataclass
class PlaySummary:
    """What :func:`play` published: message counts per topic, passes through the bag, wall time [s]."""

    published: Counter = field(default_factory=Counter)
    passes: int = 0
    wall_seconds: float = 0.0
    interrupted: bool = False

    @property
    def total(self) -> int:
        return sum(self.published.values())


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
        return sum(self.recorded.values())


def message_class(msgtype: str, topic: str = ""):
    """The rclpy message class of a ROS type name, e.g. ``geometry_msgs/msg/WrenchStamped``.

    Raises
    ------
    BagError
        Naming the topic and the type when the type name is malformed or its Python package is not
        installed.
    """
    where = f"topic {topic}: " if topic else ""
    parts = msgtype.split("/")
    if len(parts) == 2:  # 'pkg/Type' (ROS 1 style) -> pkg/msg/Type
        parts = [parts[0], "msg", parts[1]]
    if len(parts) != 3 or not all(parts):
        raise BagError(f"{where}message type {msgtype!r} is not of the form package/msg/Type")
    package, kind, name = parts
    try:
        module = importlib.import_module(f"{package}.{kind}")
        cls = getattr(module, name)
    except (ImportError, AttributeError):
        raise BagError(
            f"{where}message type {msgtype!r} is not installed in this Python environment "
            f"(no {package}.{kind}.{name}; install the package's ROS 2 wheel, e.g. ros-jazzy-{package.replace('_', '-')})"
        ) from None
    return cls


def _start_context():
    context = Context()
    rclpy.init(context=context)  # own context: rclpy installs no signal handlers
    return context


def _close(node, executor, context) -> None:
    if executor is not None:
        executor.shutdown(timeout_sec=1.0)
    if node is not None:
        node.destroy_node()
    rclpy.try_shutdown(context=context)


def _absolute(topic: str) -> str:
    topic = topic.strip()
    return topic if topic.startswith("/") else "/" + topic


def _publisher_qos(connection, depth: int) -> QoSProfile:
    """Reliable, volatile (or transient-local if the recording publisher was) with ``depth``."""
    qos = QoSProfile(depth=depth, reliability=ReliabilityPolicy.RELIABLE, durability=DurabilityPolicy.VOLATILE)
    offered = getattr(connection.ext, "offered_qos_profiles", None) or []
    if offered and all(p.durability == QosDurability.TRANSIENT_LOCAL for p in offered):
        qos.durability = DurabilityPolicy.TRANSIENT_LOCAL
    return qos


def _sleep_until(deadline: float, stop: threading.Event) -> bool:
    """Sleep until ``deadline`` (time.monotonic) or ``stop``; True if stopped."""
    remaining = deadline - time.monotonic()
    if remaining > 0:
        return stop.wait(remaining)
    return stop.is_set()


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

    Parameters
    ----------
    bag_path : path-like
        A rosbag2 bag (directory with metadata.yaml, mcap or sqlite3 storage) with CDR messages.
    rate : float
        Playback speed: 2 plays twice as fast as recorded. Must be > 0.
    loop : bool
        Start again from the beginning after the last message, until stopped. Header stamps then go
        back in time; subscribers must cope (adbsat_node resets its history).
    topics : iterable of str, optional
        Play only these topics (default: all). Each must be in the bag.
    wait_for_subscribers : int
        Before the first message, wait until every played topic that has messages has at least
        this many subscribers, so they miss nothing (0: start at once).
    wait_timeout : float
        Give up waiting for subscribers after this many seconds (BagError).
    qos_depth : int
        History depth of the publishers (reliable; transient-local if recorded so).
    stop : threading.Event, optional
        Set it (from another thread) to stop playing.
    log : callable, optional
        Called with progress lines (e.g. ``print``).

    Returns
    -------
    PlaySummary
        Returned after reliable subscribers acknowledged the last messages (at most
        :data:`ACK_TIMEOUT_S` later), so a subscriber in another process misses none of them.

    Raises
    ------
    BagError
        Missing or unreadable bag, a requested topic not in the bag, a message type that is not
        installed, a non-CDR serialization, or subscribers that did not appear in time.
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
    context = _start_context()
    node = executor = None
    start = time.monotonic()
    try:
        node = rclpy.create_node(node_name, context=context)
        executor = SingleThreadedExecutor(context=context)
        executor.add_node(node)
        publishers = {topic: node.create_publisher(cls, topic, qos[topic]) for topic, cls in classes.items()}
        if wait_for_subscribers:
            waited = {t: p for t, p in publishers.items() if t in played}
            _wait_for_subscribers(waited, wait_for_subscribers, wait_timeout, executor, stop, log)
        log(f"playing {count} messages on {len(publishers)} topics of {path} at rate {rate:g}"
            + (" (looping)" if loop else ""))
        start = time.monotonic()
        while not stop.is_set():
            summary.passes += 1
            if not _play_once(path, connections, publishers, rate, stop, summary):
                break
            if not loop:
                break
        summary.wall_seconds = time.monotonic() - start
        # Let reliable subscribers acknowledge the last messages before the publishers go away
        # (acknowledgements follow Fast DDS heartbeats: up to a few seconds between processes).
        for publisher in publishers.values():
            publisher.wait_for_all_acked(Duration(seconds=ACK_TIMEOUT_S))
    except KeyboardInterrupt:
        summary.interrupted = True
    finally:
        summary.wall_seconds = summary.wall_seconds or time.monotonic() - start
        _close(node, executor, context)
    if stop.is_set():
        summary.interrupted = True
    return summary


def _select_connections(path: Path, connections, topics):
    for c in connections:
        fmt = getattr(c.ext, "serialization_format", None)
        if fmt != "cdr":
            raise BagError(f"input bag {path}: topic {c.topic} is serialized as {fmt!r}; only rosbag2 CDR bags can be played")
    if topics is None:
        return list(connections)
    wanted = [_absolute(t) for t in topics]
    available = sorted({c.topic for c in connections})
    unknown = [t for t in wanted if t not in available]
    if unknown:
        raise BagError(
            f"input bag {path}: no topic {', '.join(unknown)} in the bag; its topics are {', '.join(available) or '(none)'}"
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
                "(play only the topics someone listens to with --topics, or drop --wait-for-subscribers)"
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


def _topic_type(spec: str):
    """'topic' or 'topic:type' -> (absolute topic, type or None)."""
    name, _, msgtype = spec.partition(":")
    name = name.strip()
    if not name or name == "/":
        raise BagError(f"topic {spec!r}: empty topic name")
    return _absolute(name), (msgtype.strip() or None)


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

    Parameters
    ----------
    out_path : path-like
        The bag directory to create; it must not exist.
    topics : iterable of str
        ``/topic`` (type discovered from the graph once a publisher appears) or
        ``/topic:package/msg/Type`` (subscribed at once). At least one.
    storage : {'mcap', 'sqlite3'}
        rosbag2 storage plugin.
    duration : float, optional
        Stop after this many seconds [s] of wall time (default: until ``stop`` or Ctrl-C).
    qos_depth : int
        History depth of the subscriptions. They are reliable unless a publisher on the topic
        offers only best effort.
    stop : threading.Event, optional
        Set it (from another thread) to stop recording.
    ready : threading.Event, optional
        Set once every topic is subscribed (useful to start a publisher after the recorder).
    log : callable, optional
        Called with progress lines.

    Returns
    -------
    RecordSummary
        The bag is closed and readable whatever stopped the recording (including Ctrl-C).

    Raises
    ------
    BagError
        No topics, a bad topic or type, an unknown storage, an existing output path, a topic
        with several types in the graph, or a type rosbags cannot describe.
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
    try:
        writer = BagWriter(out, storage)  # written beside `out`, moved there on commit
    except OSError as exc:
        raise BagError(f"output bag {out}: cannot be created: {exc}") from None
    context = _start_context()
    node = executor = None
    start = time.monotonic()
    try:
        node = rclpy.create_node(node_name, context=context)
        executor = SingleThreadedExecutor(context=context)
        executor.add_node(node)
        deadline = None if duration is None else start + duration
        log(f"recording {', '.join(pending)} into {out} ({storage})"
            + (f" for {duration:g} s" if duration else " until Ctrl-C"))
        while not stop.is_set() and (deadline is None or time.monotonic() < deadline):
            if pending:
                _subscribe_ready_topics(node, writer, pending, summary, qos_depth, log)
                if not pending and ready is not None:
                    ready.set()
            timeout = GRAPH_POLL_S if deadline is None else max(0.0, min(GRAPH_POLL_S, deadline - time.monotonic()))
            executor.spin_once(timeout_sec=timeout)
        # take what is already in the subscriptions' queues
        for _ in range(10000):
            before = summary.total
            executor.spin_once(timeout_sec=0.0)
            if summary.total == before:
                break
    except KeyboardInterrupt:
        summary.interrupted = True
    finally:
        summary.wall_seconds = time.monotonic() - start
        _close(node, executor, context)
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


def _subscribe_ready_topics(node, writer, pending: dict, summary: RecordSummary, depth: int, log) -> None:
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
                raise BagError(f"topic {topic} has several types in the graph ({', '.join(types)}); "
                               f"give one as {topic}:TYPE")
            msgtype = types[0]
            message_class(msgtype, topic)
            _check_rosbags_type(msgtype, topic)
        connection = writer.connection(topic, msgtype)
        reliability = ReliabilityPolicy.RELIABLE
        offered = node.get_publishers_info_by_topic(topic)
        if offered and all(p.qos_profile.reliability == ReliabilityPolicy.BEST_EFFORT for p in offered):
            reliability = ReliabilityPolicy.BEST_EFFORT
        qos = QoSProfile(depth=depth, reliability=reliability)

        def write(raw, connection=connection, topic=topic):
            writer.write_raw(connection, time.time_ns(), raw)
            summary.recorded[topic] += 1

        node.create_subscription(message_class(msgtype, topic), topic, write, qos, raw=True)
        summary.types[topic] = msgtype
        del pending[topic]
        log(f"subscribed to {topic} ({msgtype})")


__all__ = ["STORAGES", "PlaySummary", "RecordSummary", "message_class", "play", "record"]
