"""Shared command-line machinery: one-line errors and parsers for option values."""

from __future__ import annotations

import argparse
import math
import sys

import numpy as np


class CommandLineError(Exception):
    """A command-line value that is not allowed; the message names the option."""


class OneLineErrorParser(argparse.ArgumentParser):
    """An ArgumentParser whose errors are one line on stderr and exit status 2."""

    def error(self, message):  # noqa: D401 - argparse API
        self.exit(2, f"{self.prog}: error: {message}\n")


def parse_angle_list(text: str, option: str) -> np.ndarray:
    """Parse a list of angles in degrees.

    Accepts comma-separated items, each a number or an inclusive range ``start:step:stop``
    (e.g. ``-180:5:180``), e.g. ``"0,10,20:5:30"``. Returns the values in the order given.

    Raises
    ------
    CommandLineError
        Naming ``option`` and the accepted forms, for anything else.
    """
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


def parse_vector3(text: str, option: str) -> np.ndarray:
    """Parse ``X,Y,Z`` into a finite 3-vector, or raise CommandLineError naming ``option``."""
    try:
        vec = np.array([float(v) for v in str(text).split(",")])
    except ValueError:
        vec = np.zeros(0)
    if vec.shape != (3,) or not np.all(np.isfinite(vec)):
        raise CommandLineError(f"{option}: expected three finite numbers X,Y,Z, got {text!r}")
    return vec


def positive_float(option: str):
    """An argparse ``type`` accepting finite numbers > 0 (error names ``option``)."""

    def convert(text):
        try:
            value = float(text)
        except ValueError:
            value = float("nan")
        if not math.isfinite(value) or value <= 0:
            raise argparse.ArgumentTypeError(f"{option} must be a finite number > 0, got {text!r}")
        return value

    convert.__name__ = option
    return convert


def fraction(option: str):
    """An argparse ``type`` accepting numbers in [0, 1] (error names ``option``)."""

    def convert(text):
        try:
            value = float(text)
        except ValueError:
            value = float("nan")
        if not (0.0 <= value <= 1.0):
            raise argparse.ArgumentTypeError(f"{option} must be a number in [0, 1], got {text!r}")
        return value

    convert.__name__ = option
    return convert


def is_terminal(stream=None) -> bool:
    """True if ``stream`` (default stderr) is an interactive terminal."""
    stream = stream or sys.stderr
    return hasattr(stream, "isatty") and stream.isatty()
