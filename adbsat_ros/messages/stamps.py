"""Message stamps (builtin_interfaces/Time: sec, nanosec) as float seconds, and the next stamp of
a fixed-rate stream."""

from __future__ import annotations


def stamp_seconds(stamp) -> float:
    """A builtin_interfaces/Time (rclpy or rosbags message: sec, nanosec) as float seconds."""
    return stamp.sec + 1e-9 * stamp.nanosec


def next_regular_stamp(previous, latest) -> float | None:
    """The stamp [s] after ``latest`` at the interval from ``previous`` to ``latest`` (two
    builtin_interfaces/Time), as :func:`stamp_seconds` of that Time would give it; None when the
    interval is not positive. Worked in integer nanoseconds, so a fixed-rate stream's next stamp
    comes out bit-equal to the one its message will carry."""
    latest_ns = latest.sec * 1_000_000_000 + latest.nanosec
    step_ns = latest_ns - (previous.sec * 1_000_000_000 + previous.nanosec)
    if step_ns <= 0:
        return None
    sec, nanosec = divmod(latest_ns + step_ns, 1_000_000_000)
    return sec + 1e-9 * nanosec
