"""``adbsat-ros bag``: rosbag2 tools; ``bag analyze`` replays a bag through the node's logic,
``bag play`` and ``bag record`` are live (rclpy imported when they run)."""

from __future__ import annotations

import sys
from pathlib import Path

from adbsat_ros.bags.io import BagError
from adbsat_ros.cli.options import (
    CommandFailed,
    CommandLineError,
    add_qos_depth,
    add_storage,
    errors_as,
    flag,
    is_terminal,
    non_negative_int,
    option,
    positive_float,
    positive_int,
    ros_module,
    warn,
)
from adbsat_ros.processes import stop_on_signals, usable_cpus


def configure(p) -> None:
    """Configure the ``bag`` command group."""
    p.description = "Tools for rosbag2 files (.mcap or .db3)."
    sub = p.add_subparsers(dest="bag_command", metavar="BAG_COMMAND", parser_class=type(p))
    sub.required = True
    for name, (summary, configure_command) in BAG_COMMANDS.items():
        configure_command(sub.add_parser(name, help=summary))


def configure_analyze(a) -> None:
    """Configure ``bag analyze``."""
    a.description = (
        "Replay a rosbag2 through adbsat_node's logic (no ROS needed) and write a new bag with "
        "the input messages plus, per model LABEL, /adbsat/LABEL/wrench and "
        "/adbsat/LABEL/coefficients (geometry_msgs/WrenchStamped, body frame) and /diagnostics; "
        "a CSV (one row per attitude message, one column group per model) and PNG plots of "
        "force, torque, density and drag coefficient. Several --params files compare models in "
        "one run."
    )
    a.add_argument("bag", metavar="BAG", help="input bag: directory, .mcap or .db3 file")
    help = "geometry_msgs/QuaternionStamped topic (default /attitude)"
    option(a, "--attitude-topic", help, default="/attitude")
    option(a, "--state-topic", "nav_msgs/Odometry topic (default /state)", default="/state")
    help = (
        "sensor_msgs/JointState topic of an articulated body's joint positions (default "
        "/joint_states; read only for a URDF model)"
    )
    option(a, "--joint-states-topic", help, default="/joint_states")
    help = (
        "node parameters file (section adbsat_node or /**); repeat to compare models "
        "(default: the node's defaults)"
    )
    option(a, "--params", help, action="append", default=[], metavar="YAML")
    help = "model label, once per --params in order (default: the file's stem)"
    option(a, "--label", help, action="append", default=[], metavar="NAME")
    help = (
        "every model's space_weather: fixed or historical (each stamp's indices from CelesTrak's "
        "record; default: as its --params)"
    )
    option(a, "--space-weather", help, choices=("fixed", "historical"), default=None)
    help = "every model's atmosphere_model (default: as its --params)"
    option(a, "--atmosphere-model", help, choices=("nrlmsise00", "msis2.0", "msis2.1"))
    help = "output bag directory (default: BAG_aero beside the input)"
    option(a, "--out", help, metavar="BAG")
    option(a, "--csv", "CSV file (default: OUT.csv)", metavar="FILE")
    option(a, "--plots", "directory for PNG plots (default: OUT_plots)", metavar="DIR")
    flag(a, "--no-plots", "write no plots")
    add_storage(a, "output bag storage")
    flag(a, "--overwrite", "replace existing outputs")
    help = (
        "leave out the chunks of an MCAP input that fail their CRC, and say how many "
        "messages they held (default: refuse a damaged bag)"
    )
    flag(a, "--skip-damaged", help)
    help = (
        f"processes computing wrenches (at most the usable CPUs, {usable_cpus()} here; default: "
        "this process, and every CPU for what is left once the chunks, timed here, are worth "
        "them); the outputs are the same for any N"
    )
    option(a, "--workers", help, positive_int, default=None, metavar="N")
    flag(a, "--no-progress", "no progress bar (shown only on a terminal anyway)")
    a.set_defaults(func=run_analyze)


def configure_play(play) -> None:
    """Configure ``bag play``."""
    play.description = (
        "Publish the messages of a rosbag2 bag (.mcap or .db3) on their topics, unchanged "
        "(header stamps as recorded), spaced as recorded and scaled by --rate. Needs rclpy. "
        "Discovery stays on this machine unless ROS_AUTOMATIC_DISCOVERY_RANGE is set."
    )
    play.add_argument("bag", help="rosbag2 bag directory (or its .mcap/.db3 file)")
    help = "playback speed factor (default 1: as recorded; 2: twice as fast)"
    option(play, "--rate", help, positive_float, default=1.0)
    help = "start again from the beginning until Ctrl-C (stamps go back in time at each restart)"
    flag(play, "--loop", help)
    option(play, "--topics", "play only these topics (default: all)", nargs="+", metavar="TOPIC")
    help = "wait until every played topic has N subscribers before starting"
    option(play, "--wait-for-subscribers", help, non_negative_int, default=0, metavar="N")
    help = "give up waiting for subscribers after S seconds (default 30)"
    option(play, "--wait-timeout", help, positive_float, default=30.0, metavar="S")
    add_qos_depth(play, "(reliable) publishers")
    play.set_defaults(func=run_play, command="bag play")


def configure_record(record) -> None:
    """Configure ``bag record``."""
    record.description = (
        "Subscribe to the given topics and write their messages (serialized, as received) into "
        "a new rosbag2 bag, stamped with the receive time. A topic's type is taken from the "
        "graph once a publisher appears, or given as TOPIC:TYPE. Stops after --duration or on "
        "Ctrl-C; the bag is complete either way (also on SIGTERM). Needs rclpy."
    )
    record.add_argument("out", metavar="OUT", help="bag directory to create (must not exist)")
    help = "topics to record, each /name or /name:package/msg/Type"
    option(record, "--topics", help, nargs="+", required=True, metavar="TOPIC")
    add_storage(record, "storage format")
    help = "stop after S seconds (default: at Ctrl-C)"
    option(record, "--duration", help, positive_float, default=None, metavar="S")
    add_qos_depth(record, "subscriptions")
    record.set_defaults(func=run_record, command="bag record")


def _log(line: str) -> None:
    print(line, file=sys.stderr, flush=True)


def _counts(counter) -> str:
    return ", ".join(f"{topic} {n}" for topic, n in sorted(counter.items())) or "none"


def _run_live(module: str, function: str, *args, **options):
    """Run ``adbsat_ros.ros.<module>.<function>(*args, **options)``; a BagError is CommandFailed."""
    run = getattr(ros_module(module), function)
    with errors_as(CommandFailed, BagError), stop_on_signals() as stop:
        return run(*args, **options, stop=stop, log=_log)


def run_play(args) -> int:
    """Run ``bag play``; the exit status."""
    summary = _run_live(
        "bag_play",
        "play",
        args.bag,
        rate=args.rate,
        loop=args.loop,
        topics=args.topics,
        wait_for_subscribers=args.wait_for_subscribers,
        wait_timeout=args.wait_timeout,
        qos_depth=max(1, args.qos_depth),
    )
    how = "stopped" if summary.interrupted else "done"
    print(
        f"{how}: published {summary.total} messages ({_counts(summary.published)}) "
        f"in {summary.wall_seconds:.1f} s, {summary.passes} pass(es) through the bag"
    )
    return 0


def run_record(args) -> int:
    """Run ``bag record``; the exit status."""
    summary = _run_live(
        "bag_record",
        "record",
        args.out,
        args.topics,
        storage=args.storage,
        duration=args.duration,
        qos_depth=max(1, args.qos_depth),
    )
    print(
        f"wrote {summary.path} ({summary.storage}): {summary.total} messages "
        f"({_counts(summary.recorded)}) in {summary.wall_seconds:.1f} s"
    )
    if summary.missing:
        print(
            f"warning: no publisher ever appeared on {', '.join(summary.missing)}; nothing "
            "recorded from it",
            file=sys.stderr,
        )
    return 0


#: The ``bag`` group's subcommands: their help and configuring function.
BAG_COMMANDS = {
    "analyze": ("compute the node's wrench at every attitude message of a bag", configure_analyze),
    "play": (
        "publish a bag's messages into the ROS 2 graph with their recorded timing",
        configure_play,
    ),
    "record": ("record topics of the ROS 2 graph into a new bag", configure_record),
}


def models_from_args(args) -> list:
    """[(label, WrenchSettings)] from --params/--label; errors name the file or option."""
    from adbsat_ros.bags.report import NODE_NAME, label_from_name
    from adbsat_ros.estimator.settings import WrenchSettings, settings_from_file

    if args.label and len(args.label) != max(len(args.params), 1):
        raise CommandLineError(
            f"--label: given {len(args.label)} times for {len(args.params)} --params files"
        )
    given = {"space_weather": args.space_weather, "atmosphere_model": args.atmosphere_model}
    overrides = {key: value for key, value in given.items() if value is not None}
    if not args.params:
        label = args.label[0] if args.label else "default"
        return [(_label(label, "--label"), WrenchSettings.from_parameters({}, **overrides))]
    models = []
    for i, path in enumerate(args.params):
        with errors_as(CommandLineError, ValueError, "--params "):  # (the text names the file)
            settings = settings_from_file(path, NODE_NAME)
            if overrides:
                settings = WrenchSettings.from_parameters(settings.as_parameters(), **overrides)
        label = _label(args.label[i], "--label") if args.label else label_from_name(Path(path).stem)
        models.append((label, settings))
    labels = [label for label, _ in models]
    if len(set(labels)) != len(labels):
        raise CommandLineError(
            f"--label: model labels must differ, got {', '.join(labels)} (give --label)"
        )
    return models


def _label(text, option):
    from adbsat_ros.bags.report import check_label

    with errors_as(CommandLineError, ValueError, f"{option}: "):
        return check_label(text)


def default_output(bag) -> Path:
    """BAG_aero beside the input (the suffix of a .mcap/.db3 file dropped)."""
    bag = Path(bag)
    stem = bag.stem if bag.is_file() else bag.name
    return bag.parent / f"{stem}_aero"


def run_analyze(args) -> int:
    """Run ``bag analyze``; the exit status."""
    from adbsat_ros.bags import analysis as bag_analysis
    from adbsat_ros.geometry.mesh import MeshError

    models = models_from_args(args)
    out = Path(args.out) if args.out else default_output(args.bag)
    out_csv = Path(args.csv) if args.csv else out.parent / f"{out.name}.csv"
    plots = (
        None
        if args.no_plots
        else (Path(args.plots) if args.plots else out.parent / f"{out.name}_plots")
    )
    progress = not args.no_progress and is_terminal()
    with (
        errors_as(CommandFailed, BagError),
        errors_as(CommandLineError, MeshError, "MESH: "),
        stop_on_signals() as stop,
    ):
        report = bag_analysis.analyze_bag(
            args.bag,
            args.attitude_topic,
            args.state_topic,
            models,
            out_bag=out,
            out_csv=out_csv,
            plots_dir=plots,
            storage=args.storage,
            progress=progress,
            overwrite=args.overwrite,
            workers=args.workers,
            stop=stop,
            joint_topic=args.joint_states_topic,
            skip_damaged=args.skip_damaged,
        )
    for text in report.warnings:
        warn("bag analyze", text)
    for m in report.models:
        print(
            f"model {m.label}: {m.wrenches} wrenches from {m.triggers} inputs "
            f"-> {m.wrench_topic}, {m.coefficients_topic}"
        )
    for key in ("bag", "csv"):
        if key in report.outputs:
            print(f"wrote {key}: {report.outputs[key]}")
    if report.outputs.get("plots"):
        print(f"wrote plots: {', '.join(str(p) for p in report.outputs['plots'])}")
    seconds = report.seconds.get("total", 0.0)
    print(
        f"{report.messages_read} messages read in {seconds:.2f} s ({report.workers} worker "
        f"process{'es' if report.workers > 1 else ''}, {report.chunks} chunk(s))"
    )
    if report.skipped_chunks:
        print(
            f"skipped {report.skipped_chunks} damaged chunk(s) of the input holding "
            f"{report.skipped_messages} messages"
        )
    if report.error:
        raise CommandFailed(
            f"{report.error}; the outputs above are PARTIAL (so named): they hold the "
            f"{report.messages_read} messages read before it"
        )
    if report.wrenches == 0:
        raise CommandFailed("no wrench could be computed (see the warnings)")
    return 0
