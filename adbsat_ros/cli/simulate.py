"""``adbsat-ros simulate``: write a rosbag2 of a Keplerian orbit and an attitude history."""

from __future__ import annotations

from adbsat_ros.bags import io as bag_io
from adbsat_ros.bags import scenario
from adbsat_ros.bags.io import BagError
from adbsat_ros.cli.options import (
    CommandLineError,
    add_storage,
    errors_as,
    flag,
    non_negative_float,
    option,
    parse_vector3,
    positive_float,
    topic_name,
)


def configure(p) -> None:
    """Configure ``adbsat-ros simulate``."""
    p.description = (
        "Write a rosbag2 holding a two-body (Keplerian) orbit in ECI as nav_msgs/Odometry "
        "(frame_id and child_frame_id 'eci', twist = ECI velocity) and the attitude as "
        "geometry_msgs/QuaternionStamped (body -> ECI, x y z w). Point-mass Earth only: no J2, "
        "no drag. Attitude 'nadir': body +x along-track (the velocity direction), +z to nadir, "
        "+y = -orbit normal (the example satellite then flies nose first); 'tumble': that "
        "attitude at t = 0 turning about a fixed body axis. Stamps are UNIX time of --epoch + t, "
        "as adbsat_node reads them by default."
    )
    option(p, "--out", "output bag directory (must not exist)", required=True, metavar="BAG")
    option(p, "--duration", "length [s] (default 600)", non_negative_float, default=600.0)
    help = "perigee height above the equatorial radius 6378.137 km [km] (default 400)"
    option(p, "--altitude", help, positive_float, default=400.0)
    help = "orbit eccentricity in [0, 1) (default 0)"
    option(p, "--eccentricity", help, type=float, default=0.0)
    option(p, "--inclination", "inclination [deg] (default 51.6)", type=float, default=51.6)
    help = "right ascension of the ascending node [deg]"
    option(p, "--raan", help, type=float, default=0.0)
    option(p, "--arg-perigee", "argument of perigee [deg]", type=float, default=0.0)
    help = "true anomaly at the epoch [deg] (0: perigee)"
    option(p, "--true-anomaly", help, type=float, default=0.0)
    help = "UTC of t = 0, ISO 8601 (default 2026-01-01T00:00:00Z)"
    option(p, "--epoch", help, default="2026-01-01T00:00:00Z")
    help = "attitude messages per second (default 10)"
    option(p, "--rate", help, bound="message_rate", default=10.0)
    help = "state messages per second (default 10; keep >= 1 for the node's state_timeout 1 s)"
    option(p, "--state-rate", help, bound="message_rate", default=10.0)
    help = "attitude law (default nadir)"
    option(p, "--attitude", help, choices=scenario.ATTITUDE_MODES, default="nadir")
    option(p, "--tumble-rate", "tumble rate [deg/s] (default 1)", type=float, default=1.0)
    help = "body axis of the tumble (default: random from --seed)"
    option(p, "--tumble-axis", help, default=None, metavar="X,Y,Z")
    option(p, "--seed", "seed of the random tumble axis", type=int, default=0)
    help = "stamps as UNIX time (default) or seconds since --epoch (node time_mode epoch)"
    option(p, "--time-mode", help, choices=scenario.TIME_MODES, default="unix")
    add_storage(p, "bag storage")
    help = "attitude topic (default /attitude)"
    option(p, "--attitude-topic", help, topic_name, default="/attitude")
    help = "state topic (default /state; not the attitude topic)"
    option(p, "--state-topic", help, topic_name, default="/state")
    flag(p, "--overwrite", "replace an existing output bag")
    p.set_defaults(func=run)


#: The scenario's fields and the options that give them.
FIELDS = {
    "epoch_utc": "--epoch",
    "duration_s": "--duration",
    "rate_hz": "--rate",
    "state_rate_hz": "--state-rate",
    "altitude_km": "--altitude",
    "eccentricity": "--eccentricity",
    "inclination_deg": "--inclination",
    "raan_deg": "--raan",
    "arg_perigee_deg": "--arg-perigee",
    "true_anomaly_deg": "--true-anomaly",
    "attitude": "--attitude",
    "tumble_rate_deg_s": "--tumble-rate",
    "seed": "--seed",
    "time_mode": "--time-mode",
}


def scenario_from_args(args) -> scenario.Scenario:
    """The Scenario the options describe (CommandLineError naming the option if not valid)."""
    axis = None
    if args.tumble_axis is not None:
        axis = tuple(parse_vector3(args.tumble_axis, "--tumble-axis"))
    values = {field: getattr(args, name[2:].replace("-", "_")) for field, name in FIELDS.items()}
    try:
        return scenario.Scenario(**values, tumble_axis=axis)
    except ValueError as exc:
        text = str(exc)
        names = [
            ("duration_s x rate_hz", "--duration x --rate"),
            ("duration_s x state_rate_hz", "--duration x --state-rate"),
            *FIELDS.items(),
            ("tumble_axis", "--tumble-axis"),
        ]
        for field, option in names:
            text = text.replace(f"scenario {field}", option).replace(f"parameter {field}", option)
        raise CommandLineError(text) from None


def run(args) -> int:
    """Run ``adbsat-ros simulate``; the exit status."""
    if args.attitude_topic.lstrip("/") == args.state_topic.lstrip("/"):
        raise CommandLineError(
            f"--state-topic: {args.state_topic} is also the --attitude-topic; the two streams "
            "need two topics"
        )
    sc = scenario_from_args(args)
    with errors_as(CommandLineError, ValueError, "--duration x --rate: "):  # (memory it takes)
        messages = scenario.generate(sc)
    with errors_as(CommandLineError, BagError, "--out: "):
        path = bag_io.write_scenario_bag(
            messages,
            args.out,
            args.attitude_topic,
            args.state_topic,
            storage=args.storage,
            overwrite=args.overwrite,
        )
    print(
        f"wrote {path} ({args.storage}): {len(messages.states.stamps_ns)} Odometry on "
        f"{args.state_topic}, {len(messages.attitudes.stamps_ns)} QuaternionStamped on "
        f"{args.attitude_topic}"
    )
    print(
        f"orbit: perigee {sc.perigee_radius / 1e3:.3f} km, apogee {sc.apogee_radius / 1e3:.3f} "
        f"km (radius), period {sc.period:.1f} s, epoch {sc.epoch.isoformat()}, attitude "
        f"{sc.attitude}, stamps {sc.time_mode}"
    )
    return 0
