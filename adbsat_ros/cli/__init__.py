"""The ``adbsat-ros`` command line: one module per subcommand, imported only when chosen.

Each module's ``configure(parser)`` sets ``func``, which returns the exit status or raises
CommandLineError (status 2) or CommandFailed (status 1), printed by :func:`main` as one line.
"""

from __future__ import annotations

import argparse
import importlib
import logging
import re
import sys

from adbsat_ros._version import __version__
from adbsat_ros.cli.options import CommandFailed, CommandLineError, OneLineErrorParser
from adbsat_ros.processes import (
    INTERRUPTED_STATUS,
    Interrupted,
    exit_now,
    handle_signals,
    raising_signals,
    signal_name,
)

#: The subcommands in ``--help`` order, with their help; each is the module of that name.
SUBCOMMANDS = {
    "coeff": "force and moment coefficients at given attitudes",
    "atmosphere": "flight conditions: NRLMSISE-00 atmosphere, relative wind, accommodation",
    "database": "coefficients over a grid of angle of attack and sideslip (npz + csv)",
    "plot": "PNG figures of an aerodynamic database",
    "sweep": "coefficients over N axes (attitude, gas, surface, joints) on Dask, into Zarr",
    "simulate": "write a bag of a simulated flight (orbit state + attitude)",
    "bag": "analyse (and play or record) rosbag2 files",
    "demo": "run adbsat_node live on a simulated orbit and print, plot and save its wrenches",
    "param": "list, get or set a running node's parameters (as ros2 param)",
    "echo": "print a topic's messages (as ros2 topic echo)",
}

#: The subcommands that run until they are stopped: SIGINT or SIGTERM is their normal end (exit
#: status 0); it stops any other before it finished (:data:`INTERRUPTED_STATUS`).
RUN_UNTIL_STOPPED = ("bag play", "bag record", "echo")

#: Options whose value is an angle list or range, which may begin with a minus sign.
SIGNED_LIST_OPTIONS = ("--aoa", "--aos")
#: A list or range that begins with a minus sign ("-180:5:180", "-10,0,10"): argparse would read it
#: as an option of its own (it takes only plain negative numbers such as "-10" for values).
_SIGNED_LIST = re.compile(r"-\.?\d[0-9.eE+-]*[:,]")


def join_signed_lists(argv):
    """``argv`` with ``--aoa -180:5:180`` written as ``--aoa=-180:5:180`` (and so for --aos)."""
    out = []
    for token in argv:
        if out and out[-1] in SIGNED_LIST_OPTIONS and _SIGNED_LIST.match(token):
            out[-1] = f"{out[-1]}={token}"
        else:
            out.append(token)
    return out


def chosen_subcommand(argv) -> str | None:
    """The subcommand named in ``argv`` (its first word that is not an option), or None."""
    for token in argv:
        if not token.startswith("-"):
            return token if token in SUBCOMMANDS else None
    return None


def build_parser(configured=None) -> argparse.ArgumentParser:
    """The top-level parser, with the options of the ``configured`` subcommands (default all)."""
    configured = set(SUBCOMMANDS if configured is None else configured)
    unknown = configured - set(SUBCOMMANDS)
    if unknown:
        raise ValueError(f"configured: unknown subcommands {', '.join(sorted(unknown))}")
    parser = OneLineErrorParser(
        prog="adbsat-ros",
        description="Free-molecular aerodynamics of satellites (ADBSat's panel method), "
        "as a library, a command line and a ROS 2 node.",
    )
    parser.add_argument(
        "-v",
        "--verbose",
        action="store_true",
        help="log progress, and the traceback of an error a library logs",
    )
    parser.add_argument(
        "--version", action="version", version=f"adbsat-ros {__version__}", help="print the version"
    )
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=OneLineErrorParser)
    sub.required = True
    for name, summary in SUBCOMMANDS.items():
        subparser = sub.add_parser(name, help=summary)
        if name in configured:
            importlib.import_module(f"{__name__}.{name}").configure(subparser)
    return parser


class OneLineFormatter(logging.Formatter):
    """Log records as ``adbsat-ros: LEVEL: message``, one line (tracebacks: ``--verbose``)."""

    def __init__(self, tracebacks: bool = False):
        super().__init__("adbsat-ros: %(levelname)s: %(message)s")
        self.tracebacks = bool(tracebacks)

    def format(self, record: logging.LogRecord) -> str:
        """The record's line (with ``tracebacks``, its traceback too)."""
        if self.tracebacks:
            return super().format(record)
        saved = record.exc_info, record.exc_text, record.stack_info
        record.exc_info = record.exc_text = record.stack_info = None
        try:
            return super().format(record)
        finally:
            record.exc_info, record.exc_text, record.stack_info = saved


def main(argv=None) -> int:
    """Entry point of the ``adbsat-ros`` console script; the exit status.

    Outside long work a signal ends it with ``adbsat-ros COMMAND: stopped by SIGINT``.
    """
    command = None
    with handle_signals():
        try:
            with raising_signals():
                command = command_name(sys.argv[1:] if argv is None else argv)
                status = _run(argv, command)
        except (Interrupted, Exception) as exc:  # (or the error a C extension's import made of it)
            if not isinstance(exc, Interrupted) and signal_name() is None:
                raise
            return _stopped(command, argv is None)
        if status == 0 and signal_name() is not None and command not in RUN_UNTIL_STOPPED:
            return _stopped(command)  # (a library swallowed the signal: not finished as asked)
        return status


def _stopped(command, program: bool = False) -> int:
    """Say that a signal stopped ``command``; its exit status (``program``: the process ends)."""
    name = signal_name() or "a signal"
    print(f"adbsat-ros{' ' + command if command else ''}: stopped by {name}", file=sys.stderr)
    status = 0 if command in RUN_UNTIL_STOPPED else INTERRUPTED_STATUS
    if program:
        exit_now(status)
    return status


def command_name(argv) -> str | None:
    """The subcommand ``argv`` names, with its own subcommand for ``bag`` (``bag play``)."""
    command = chosen_subcommand(argv)
    if command == "bag":
        words = [w for w in argv if not w.startswith("-")]
        return " ".join(words[:2])
    return command


def _run(argv, command) -> int:
    """Parse ``argv`` and run the subcommand (``command``: for a stop's line); its exit status."""
    argv = join_signed_lists(sys.argv[1:] if argv is None else argv)
    chosen = chosen_subcommand(argv)
    parser = build_parser(() if chosen is None else (chosen,))
    args = parser.parse_args(argv)
    handler = logging.StreamHandler()
    handler.setFormatter(OneLineFormatter(tracebacks=args.verbose))
    logging.basicConfig(level=logging.INFO if args.verbose else logging.WARNING, handlers=[handler])
    try:
        return int(args.func(args) or 0)
    except CommandLineError as exc:
        print(f"adbsat-ros {args.command}: error: {exc}", file=sys.stderr)
        return 2
    except CommandFailed as exc:
        print(f"adbsat-ros {command}: error: {exc}", file=sys.stderr)
        return 1
    except BrokenPipeError:  # e.g. output piped into `head`
        sys.stderr.close()
        return 0
    except Exception as exc:
        if signal_name() is not None:  # (the signal's doing, seen through a library)
            return _stopped(command)
        if not isinstance(exc, (OSError, ValueError)):
            raise
        print(f"adbsat-ros {args.command}: error: {exc}", file=sys.stderr)
        return 1
