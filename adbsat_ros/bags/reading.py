"""Reading an input bag for the analysis: its topics checked, every message once, in bag order.

The analysis holds every message's CDR bytes in memory (about the bag's size): they are copied
to the output bag, and the state and attitude ("trigger") messages are replayed through the
estimators. A fault of the reader part-way (a corrupt or truncated file) ends the reading; what
came before is kept and the fault is reported.
"""

from __future__ import annotations

import collections
from dataclasses import dataclass, field

from adbsat_ros.bags.io import BagError
from adbsat_ros.messages.cdr import header_stamp

#: Kinds of trigger message.
STATE, ATTITUDE = 0, 1


def read_messages(reader, path, connections):
    """``reader.messages()``, with any failure of the reader turned into a BagError naming the
    file."""
    iterator = reader.messages(connections=connections)
    count = 0
    while True:
        try:
            item = next(iterator)
        except StopIteration:
            return
        except Exception as exc:  # rosbags raises many kinds (ReaderError, struct, zstd, apsw ...)
            raise BagError(
                f"input bag {path}: corrupt or truncated after {count} messages "
                f"({type(exc).__name__}: {exc})"
            ) from None
        count += 1
        yield item


def check_topics(reader, path, topics_types) -> dict:
    """Every (option, topic, msgtype) required must be in the bag with that type only and have
    messages; returns {topic: set of msgtypes} of the bag.

    Raises
    ------
    BagError
        Naming the topic and the option that gave it.
    """
    by_topic = collections.defaultdict(set)
    counts = collections.Counter()
    for conn in reader.connections:
        by_topic[conn.topic].add(conn.msgtype)
        counts[conn.topic] += conn.msgcount
    listing = (
        ", ".join(f"{t} ({', '.join(sorted(ty))})" for t, ty in sorted(by_topic.items())) or "none"
    )
    for option, topic, msgtype in topics_types:
        if topic not in by_topic:
            raise BagError(
                f"input bag {path}: no topic {topic} (given by {option}); the bag has: {listing}"
            )
        other = by_topic[topic] - {msgtype}
        if other:
            raise BagError(
                f"input bag {path}: topic {topic} (given by {option}) has message type "
                f"{', '.join(sorted(other))}; expected {msgtype}"
            )
        if counts[topic] == 0:
            raise BagError(f"input bag {path}: topic {topic} (given by {option}) has no messages")
    return by_topic


@dataclass
class BagMessages:
    """Every message of a bag, and its trigger messages.

    Attributes
    ----------
    connections : dict
        The reader's connections by id.
    messages : list of (int, int, bytes)
        (connection id, log time [ns], CDR bytes) of every message, in bag order.
    kind_of : dict
        {connection id: STATE or ATTITUDE} of the trigger topics.
    trigger_kinds : list of int
        STATE or ATTITUDE of each trigger message, in bag order.
    trigger_raws : list of bytes
        Their CDR bytes.
    trigger_stamps : list of float
        Their header stamps [s] as the estimator reads them (sec + 1e-9 nanosec), up to the
        first message whose stamp cannot be read (no chunk starts after it).
    error : str or None
        Why the reading stopped before the end.
    """

    connections: dict
    messages: list = field(default_factory=list)
    kind_of: dict = field(default_factory=dict)
    trigger_kinds: list = field(default_factory=list)
    trigger_raws: list = field(default_factory=list)
    trigger_stamps: list = field(default_factory=list)
    error: str | None = None


def read_bag_messages(reader, path, state_topic: str, attitude_topic: str | None) -> BagMessages:
    """Every message of an open bag (raw CDR) in bag order, and the trigger messages: those on
    ``state_topic``, and on ``attitude_topic`` unless it is None (no model uses attitudes)."""
    read = BagMessages({c.id: c for c in reader.connections})
    for c in reader.connections:
        if c.topic == state_topic:
            read.kind_of[c.id] = STATE
        elif attitude_topic is not None and c.topic == attitude_topic:
            read.kind_of[c.id] = ATTITUDE
    stamps_ok = True
    try:
        for conn, t_ns, raw in read_messages(reader, path, reader.connections):
            raw = bytes(raw)
            read.messages.append((conn.id, t_ns, raw))
            kind = read.kind_of.get(conn.id)
            if kind is None:
                continue
            read.trigger_kinds.append(kind)
            read.trigger_raws.append(raw)
            if stamps_ok:
                try:
                    sec, nanosec = header_stamp(raw)
                except ValueError:  # the worker reports it when decoding; no split after it
                    stamps_ok = False
                else:
                    read.trigger_stamps.append(sec + 1e-9 * nanosec)  # as stamp_seconds()
    except BagError as exc:
        read.error = str(exc)
    return read
