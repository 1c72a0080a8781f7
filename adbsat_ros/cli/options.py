"""Shared command-line machinery: one-line errors, value parsers, option helpers, ROS import.
Imported at every start: only the standard library at the top."""

from __future__ import annotations

import argparse
import functools
import importlib
import math
import os
import re
import sys

from adbsat_ros.bounds import bounded, errors_as


class CommandLineError(Exception):
    """A command-line value that is not allowed; the message names the option."""


class CommandFailed(Exception):
    """A command that could not do its work: ``adbsat-ros COMMAND: error: message``, status 1."""


#: A word that reads as a negative number to ``float`` (``-5``, ``-1e5``, ``-.5``, ``-inf``,
#: ``-nan``): an option's value, not an option (argparse itself takes only ``-5`` and ``-.5``).
NEGATIVE_NUMBER = re.compile(
    r"^-(\d+\.?\d*(e[+-]?\d+)?|\.\d+(e[+-]?\d+)?|inf|infinity|nan)$", re.IGNORECASE
)


class OneLineErrorParser(argparse.ArgumentParser):
    """An ArgumentParser with one-line errors (status 2) taking ``-inf``, ``-1e5`` as values."""

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self._negative_number_matcher = NEGATIVE_NUMBER

    def error(self, message):
        """Print ``prog: error: message`` on stderr; exit with status 2."""
        self.exit(2, f"{self.prog}: error: {message}\n")


def parse_angle_list(text: str, option: str):
    """The angles [deg] of ``"0,10,20:5:30"`` (inclusive ranges); CommandLineError else."""
    import numpy as np

    values = []
    for item in str(text).split(","):
        item = item.strip()
        if not item:
            raise CommandLineError(f"{option}: empty item in {text!r}")
        parts = item.split(":")
        try:
            numbers = [float(p) for p in parts]
        except ValueError:
            raise CommandLineError(
                f"{option}: {item!r} is not a number or a start:step:stop range (degrees)"
            ) from None
        if not all(math.isfinite(x) for x in numbers):
            raise CommandLineError(f"{option}: {item!r} is not finite")
        if len(numbers) == 1:
            values.append(numbers[0])
        elif len(numbers) == 3:
            start, step, stop = numbers
            if step == 0 or (stop - start) * step < 0:
                raise CommandLineError(
                    f"{option}: range {item!r} has a zero step or a step of the wrong sign"
                )
            count = int(math.floor((stop - start) / step + 1e-9)) + 1
            if count > 100000:
                raise CommandLineError(f"{option}: range {item!r} has {count} values (max 100000)")
            values.extend(start + step * np.arange(count))
        else:
            raise CommandLineError(
                f"{option}: {item!r} is not a number or a start:step:stop range (degrees)"
            )
    return np.asarray(values, dtype=float)


def parse_vector3(text: str, option: str, bound: str | None = None):
    """Parse ``X,Y,Z`` into a finite 3-vector, within ``BOUNDS[bound]`` if given."""
    import numpy as np

    try:
        vec = np.array([float(v) for v in str(text).split(",")])
    except ValueError:
        vec = np.zeros(0)
    if vec.shape != (3,) or not np.all(np.isfinite(vec)):
        raise CommandLineError(f"{option}: expected three finite numbers X,Y,Z, got {text!r}")
    if bound is not None:
        for axis, x in zip("xyz", vec.tolist()):
            checked(f"{option} {axis}", x, bound)
    return vec


def checked(what: str, value, bound: str) -> float:
    """``value`` checked by :func:`adbsat_ros.bounds.bounded`; CommandLineError if outside."""
    with errors_as(CommandLineError, ValueError):
        return bounded(what, value, bound)


def number(
    option: str, *, integer: bool = False, low=None, high=None, low_open: bool = False, what=None
):
    """An argparse ``type`` for a finite number in [``low``, ``high``], errors naming ``option``."""
    if what is None:
        kind = "a whole number" if integer else "a finite number"
        if low is not None and high is not None:
            what = f"{kind} in {'(' if low_open else '['}{low:g}, {high:g}]"
        elif low is not None:
            what = f"{kind} {'>' if low_open else '>='} {low:g}"
        else:
            what = kind

    def convert(text):
        try:
            value = float(text)  # (a whole number may be written 1e6)
        except ValueError:
            value = float("nan")
        if integer and math.isfinite(value) and not value.is_integer():
            value = float("nan")
        ok = math.isfinite(value)
        ok = ok and (low is None or (value > low if low_open else value >= low))
        ok = ok and (high is None or value <= high)
        if not ok:
            raise argparse.ArgumentTypeError(f"{option} must be {what}, got {text!r}")
        return int(value) if integer else value

    convert.__name__ = option
    return convert


#: argparse ``type`` makers of :func:`number`'s common ranges (called with the option's name).
positive_float = functools.partial(number, low=0.0, low_open=True)
non_negative_float = functools.partial(number, low=0.0)
fraction = functools.partial(number, low=0.0, high=1.0, what="a number in [0, 1]")
positive_int = functools.partial(number, integer=True, low=1)
non_negative_int = functools.partial(number, integer=True, low=0)


def within(option: str, bound: str):
    """An argparse ``type`` for the range ``BOUNDS[bound]``; errors name option and reason."""

    def convert(text):
        with errors_as(argparse.ArgumentTypeError):
            return bounded(option, text, bound)

    convert.__name__ = option
    return convert


#: A ROS 2 topic name, by the rules of ROS 2's "Topic and Service name mapping" design article
#: for names without substitutions: tokens of letters, digits and '_', not starting with a
#: digit, separated by single '/', an optional leading '/' (absolute), no trailing '/', no '__'.
TOPIC_NAME = re.compile(r"^/?[A-Za-z_][A-Za-z0-9_]*(/[A-Za-z_][A-Za-z0-9_]*)*$")


def topic_name(option: str):
    """An argparse ``type`` accepting a ROS 2 topic name (:data:`TOPIC_NAME`)."""

    def convert(text):
        if not TOPIC_NAME.match(text) or "__" in text:
            raise argparse.ArgumentTypeError(
                f"{option} must be a ROS topic name (tokens of letters, digits and '_', not "
                f"starting with a digit, separated by '/'; no '__'), got {text!r}"
            )
        return text

    convert.__name__ = option
    return convert


def option(parser, name: str, help: str, kind=None, bound: str | None = None, **settings):
    """Add the option ``name`` to ``parser``, read so that an error names it."""
    if kind is not None:
        settings["type"] = kind(name)
    elif bound is not None:
        settings["type"] = within(name, bound)
    return parser.add_argument(name, help=help, **settings)


def flag(parser, name: str, help: str):
    """Add ``name``, an option without a value (True when given), with ``help``."""
    return parser.add_argument(name, action="store_true", help=help)


#: The storage formats of a bag written by the command line.
STORAGES = ("mcap", "sqlite3")


def add_storage(parser, what: str) -> None:
    """Add ``--storage mcap|sqlite3`` (default mcap) of the bag ``what`` describes."""
    option(parser, "--storage", f"{what} (default mcap)", choices=STORAGES, default="mcap")


def add_qos_depth(parser, what: str) -> None:
    """Add ``--qos-depth N`` (default 1000), the history depth of the live tool's ``what``."""
    help = f"history depth of the {what} (default 1000)"
    option(parser, "--qos-depth", help, type=int, default=1000, metavar="N")


def add_timeout(parser, what: str) -> None:
    """Add ``--timeout`` [s] (default 5), how long a live tool waits for ``what``."""
    help = f"seconds to wait for {what} (default 5)"
    option(parser, "--timeout", help, positive_float, default=5.0)


class RosNotAvailable(CommandFailed):
    """rclpy or the message packages cannot be imported."""


def ros_module(name: str):
    """``adbsat_ros.ros.<name>``, or RosNotAvailable naming what is missing."""
    os.environ.setdefault("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST")
    try:
        return importlib.import_module(f"adbsat_ros.ros.{name}")
    except ImportError as exc:
        raise RosNotAvailable(
            "needs the ROS 2 Python packages (rclpy and messages), which cannot be imported: "
            f"{exc}; install them with: pip install 'adbsat_ros[ros]'"
        ) from None


def warn(command: str, text: str) -> None:
    """Print ``adbsat-ros COMMAND: warning: text`` on stderr."""
    print(f"adbsat-ros {command}: warning: {text}", file=sys.stderr)


def is_terminal() -> bool:
    """True if stderr is an interactive terminal."""
    return hasattr(sys.stderr, "isatty") and sys.stderr.isatty()
