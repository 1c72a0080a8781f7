"""Message stamps (builtin_interfaces/Time) as float seconds; the next stamp of a stream."""

from __future__ import annotations


def stamp_seconds(stamp) -> float:
    """A builtin_interfaces/Time (rclpy or rosbags message: sec, nanosec) as float seconds."""
    return stamp.sec + 1e-9 * stamp.nanosec


def next_regular_stamp(previous, latest) -> float | None:
    """The stamp [s] after ``latest`` at the interval from ``previous``; None if not positive.

    In integer nanoseconds, so bit-equal to :func:`stamp_seconds` of the message to come.
    """
    latest_ns = latest.sec * 1_000_000_000 + latest.nanosec
    step_ns = latest_ns - (previous.sec * 1_000_000_000 + previous.nanosec)
    if step_ns <= 0:
        return None
    sec, nanosec = divmod(latest_ns + step_ns, 1_000_000_000)
    return sec + 1e-9 * nanosec
