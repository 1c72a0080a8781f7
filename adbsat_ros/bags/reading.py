"""Reading an input bag in two passes in bounded memory: trigger kinds and stamps to plan the
chunks, then a stream to the workers and the merge. A reader fault ends both at the same place.
"""

from __future__ import annotations

import array
import collections
import itertools
from dataclasses import dataclass, field

from adbsat_ros.bags.checksums import check_bag, drop_chunks
from adbsat_ros.bags.io import BagError, open_bag
from adbsat_ros.messages.cdr import header_stamp

#: Kinds of trigger message (joint states are history, as states are: handled in order too).
STATE, ATTITUDE, JOINTS = 0, 1, 2


def read_messages(reader, path, connections):
    """``reader.messages()``, any failure of the reader a BagError naming the file."""
    count = 0
    try:
        for item in reader.messages(connections=connections):
            yield item
            count += 1
    except Exception as exc:  # rosbags raises many kinds (ReaderError, struct, zstd, apsw ...)
        raise BagError(
            f"input bag {path}: corrupt or truncated after {count} messages "
            f"({type(exc).__name__}: {exc})"
        ) from None


def check_damage(reader, path, skip_damaged: bool = False) -> tuple[list, list]:
    """Check an open bag's checksums: ``(skipped chunks, warning lines)``.

    BagError: damage, unless ``skip_damaged`` and only chunks; always for a damaged summary.
    """
    check = check_bag(reader)
    warnings = []
    if check.unchecked_chunks:
        warnings.append(
            f"input bag {path}: {check.unchecked_chunks} of {check.chunks} chunks carry no CRC "
            "(damage to them cannot be found)"
        )
    damaged = check.damaged
    refused = [d for d in damaged if d.fatal or not skip_damaged]
    if refused:
        more = f"; {len(damaged)} damaged parts in all" if len(damaged) > 1 else ""
        hint = (
            " (--skip-damaged analyses the rest without its messages)"
            if all(not d.fatal for d in damaged)
            else ""
        )
        raise BagError(f"input bag {path}: {refused[0]}: the file is damaged{more}{hint}")
    skipped = [d for d in damaged if d.skippable]
    drop_chunks(reader, skipped)
    for d in damaged:
        action = f"skipped its {d.messages} messages" if d.skippable else "no message is in it"
        warnings.append(f"input bag {path}: {d}: {action}")
    return skipped, warnings


def check_topics(reader, path, topics_types) -> dict:
    """Check the required topics (present, one type, messages); {topic: msgtypes}."""
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
    """The first pass: trigger kinds and stamps [s], states' CDR bytes, why it stopped."""

    path: object
    connections: dict
    count: int = 0
    kind_of: dict = field(default_factory=dict)
    trigger_kinds: array.array = field(default_factory=lambda: array.array("b"))
    trigger_stamps: array.array = field(default_factory=lambda: array.array("d"))
    state_raws: dict = field(default_factory=dict)
    error: str | None = None
    skipped: list = field(default_factory=list)

    def stream(self) -> "MessageStream":
        """The second pass: the same :attr:`count` messages again, in bag order."""
        return MessageStream(self)


def read_bag_messages(
    reader,
    path,
    state_topic: str,
    attitude_topic: str | None,
    joint_topic: str | None = None,
    skipped=(),
) -> BagMessages:
    """The first pass over an open bag (:class:`BagMessages`)."""
    read = BagMessages(path, {c.id: c for c in reader.connections}, skipped=list(skipped))
    for c in reader.connections:
        if c.topic == state_topic:
            read.kind_of[c.id] = STATE
        elif attitude_topic is not None and c.topic == attitude_topic:
            read.kind_of[c.id] = ATTITUDE
        elif joint_topic is not None and c.topic == joint_topic:
            read.kind_of[c.id] = JOINTS
    stamps_ok = True
    try:
        for conn, _, raw in read_messages(reader, path, reader.connections):
            read.count += 1
            kind = read.kind_of.get(conn.id)
            if kind is None:
                continue
            if kind == STATE:
                read.state_raws[len(read.trigger_kinds)] = bytes(raw)
            read.trigger_kinds.append(kind)
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


class MessageStream:
    """The second pass, read once for the workers and the merge, queued between them."""

    def __init__(self, read: BagMessages):
        self._kind_of = read.kind_of
        self._reader = open_bag(read.path)
        drop_chunks(self._reader, read.skipped)
        self._source = itertools.islice(
            read_messages(self._reader, read.path, self._reader.connections), read.count
        )
        self._unmerged = collections.deque()  # (connection id, log time, CDR bytes)
        self._unchunked = collections.deque()  # (kind, CDR bytes) of trigger messages

    def _pull(self) -> bool:
        """Read the next message into both queues; False at the end."""
        try:
            conn, t_ns, raw = next(self._source)
        except StopIteration:
            return False
        raw = bytes(raw)
        self._unmerged.append((conn.id, t_ns, raw))
        kind = self._kind_of.get(conn.id)
        if kind is not None:
            self._unchunked.append((kind, raw))
        return True

    def chunks(self, bounds):
        """``(kinds, CDR bytes)`` of the trigger messages of each chunk of ``bounds``."""
        queue = self._unchunked
        for start, stop in bounds:
            kinds, raws = [], []
            while len(kinds) < stop - start:
                if not queue and not self._pull():
                    break
                if queue:
                    kind, raw = queue.popleft()
                    kinds.append(kind)
                    raws.append(raw)
            yield kinds, raws

    def messages(self):
        """Every message, ``(connection id, log time [ns], CDR bytes)``, in bag order."""
        queue = self._unmerged
        while queue or self._pull():
            yield queue.popleft()

    def close(self) -> None:
        """Close the bag."""
        self._reader.close()
