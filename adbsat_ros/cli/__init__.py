"""The ``adbsat-ros`` command line.

Each subcommand lives in its own module of this package and exposes ``register(subparsers)``,
which adds its parser and sets ``func`` (called with the parsed arguments, returns the exit code).
"""

from __future__ import annotations

import argparse
import importlib
import logging
import re
import sys

from adbsat_ros.geometry.mesh import MeshError

from .options import CommandLineError, OneLineErrorParser

#: Subcommand modules, in the order ``--help`` lists them.
SUBCOMMANDS = ("coeff", "atmosphere", "database", "plot", "simulate", "bag", "demo")


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


def build_parser(subcommands=SUBCOMMANDS) -> argparse.ArgumentParser:
    """The top-level parser with the given subcommands registered (default: all)."""
    parser = OneLineErrorParser(
        prog="adbsat-ros",
        description="Free-molecular aerodynamics of satellites (ADBSat's panel method), "
        "as a library, a command line and a ROS 2 node.",
    )
    parser.add_argument("-v", "--verbose", action="store_true", help="log progress and warnings")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=OneLineErrorParser)
    sub.required = True
    for name in subcommands:
        importlib.import_module(f"{__name__}.{name}").register(sub)
    return parser


def main(argv=None, subcommands=SUBCOMMANDS) -> int:
    """Entry point of the ``adbsat-ros`` console script; returns the process exit status."""
    parser = build_parser(subcommands)
    args = parser.parse_args(join_signed_lists(sys.argv[1:] if argv is None else argv))
    logging.basicConfig(
        level=logging.INFO if args.verbose else logging.WARNING,
        format="adbsat-ros: %(levelname)s: %(message)s",
    )
    try:
        return int(args.func(args) or 0)
    except CommandLineError as exc:
        print(f"adbsat-ros {args.command}: error: {exc}", file=sys.stderr)
        return 2
    except MeshError as exc:
        print(f"adbsat-ros {args.command}: error: MESH: {exc}", file=sys.stderr)
        return 2
    except BrokenPipeError:  # e.g. output piped into `head`
        sys.stderr.close()
        return 0
    except (OSError, ValueError) as exc:
        print(f"adbsat-ros {args.command}: error: {exc}", file=sys.stderr)
        return 1


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
