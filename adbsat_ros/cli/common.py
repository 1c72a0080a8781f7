"""The options shared by ``coeff`` and ``database``, and the set-up, model and gas they give."""

from __future__ import annotations

import argparse
import functools
import math

from adbsat_ros.bounds import bounded
from adbsat_ros.cli.atmosphere import add_flight_arguments
from adbsat_ros.cli.atmosphere import compute as compute_flight_conditions
from adbsat_ros.cli.options import (
    CommandLineError,
    checked,
    errors_as,
    flag,
    fraction,
    number,
    option,
    parse_vector3,
    positive_float,
)
from adbsat_ros.cli.solvers import add_solver_arguments
from adbsat_ros.geometry.loading import is_urdf
from adbsat_ros.geometry.mesh import MeshError
from adbsat_ros.physics.coefficients import Reference
from adbsat_ros.physics.constants import species_mass_kg
from adbsat_ros.physics.freestream import FreeStream
from adbsat_ros.physics.gsi_models import (
    INCIDENT_TEMPERATURE_FORMS,
    MODELS,
    SPECIES_MODELS,
    ModelOptions,
)
from adbsat_ros.physics.model import Model, build_model
from adbsat_ros.physics.models.cll import CLL_SPECIES
from adbsat_ros.physics.setup import BodySpec, Setup, ShadingPolicy, SolverSpec
from adbsat_ros.physics.surface import SurfaceProperties
from adbsat_ros.shading.shader import MODES as SHADING_MODES


def add_setup_arguments(parser: argparse.ArgumentParser, **solver) -> None:
    """Add the options of ``coeff`` and ``database``: MESH, model, gas, reference, shading..."""
    help = (
        "mesh file (.obj .stl .ply .off ...), a URDF (.urdf; joints at --joint, else 0), or a "
        "bundled body: 'example' (the example satellite), 'example-articulated' (its URDF, "
        "wings on hinges), 'example-finned' (four steerable fins), 'grooved-cylinder', "
        "'cylinder', 'intake-box'"
    )
    parser.add_argument("mesh", metavar="MESH", help=help)
    help = "factor from file units to metres (1e-3 for millimetres)"
    option(parser, "--scale", help, positive_float, default=1.0)
    help = (
        "take a mesh (at --scale 1) that is under 1 mm or over 200 m across, which is "
        "otherwise refused as probably not in metres"
    )
    flag(parser, "--accept-size", help)
    help = (
        "with a URDF MESH (a .urdf file, 'example-articulated', 'example-finned'): a joint's "
        "position, degrees for revolute and continuous joints, metres for prismatic ones "
        "(repeatable; others at 0)"
    )
    option(parser, "--joint", help, action="append", default=[], metavar="NAME=VALUE")

    g = parser.add_argument_group("gas-surface model")
    help = "gas-surface interaction model (default sentman)"
    option(g, "--gsim", help, default="sentman", type=str.lower, choices=list(MODELS))
    help = "energy accommodation (sentman, cook, dria; maxwell diffuse fraction)"
    option(g, "--alpha", help, fraction, default=1.0)
    option(g, "--alpha-n", "CLL normal energy accommodation", fraction, default=1.0)
    help = "normal momentum accommodation (schaaf, storch), in [0, 2)"
    below_two = functools.partial(
        number, low=0.0, high=math.nextafter(2.0, 0.0), what="a number in [0, 2)"
    )
    option(g, "--sigma-n", help, below_two, default=1.0)
    help = "tangential momentum accommodation (schaaf, storch, cll)"
    option(g, "--sigma-t", help, fraction, default=1.0)
    help = "wall temperature [K] (default 300)"
    option(g, "--wall-temperature", help, bound="wall_temperature", default=300.0)
    help = "per-material override, e.g. solar_array:alpha=0.9,wall_temperature=350"
    option(g, "--material", help, action="append", default=[], metavar="NAME:KEY=VALUE[,KEY=VALUE]")
    help = "incident temperature form for sentman/dria (default energy, as ADBSat)"
    option(g, "--incident-temperature", help, choices=INCIDENT_TEMPERATURE_FORMS, default="energy")
    help = "reproduce ADBSat's coded quirks (maxwell two-sided plate, cll weights)"
    flag(g, "--adbsat-compat", help)

    g = parser.add_argument_group("free stream (given directly)")
    option(g, "--speed", "relative wind speed [m/s]", bound="speed")
    option(g, "--temperature", "gas temperature [K]", bound="temperature")
    comp = g.add_mutually_exclusive_group()
    option(comp, "--mean-mass", "mean molecular mass [amu]", bound="mean_mass_amu")
    help = "species number densities [m^-3] (He O N2 O2 Ar H N AnO)"
    option(comp, "--species", help, metavar="He=N,O=N,...")
    help = "mass density [kg/m^3] for forces in newtons (default: from --species)"
    option(g, "--density", help, bound="mass_density")
    add_flight_arguments(parser, time_required=False, with_alpha=False)

    g = parser.add_argument_group("reference quantities")
    option(g, "--aref", "reference area [m^2] (default: half the total area)", bound="area")
    option(g, "--lref", "reference length [m] (default: x extent)", bound="length")
    help = "moment reference point in the mesh frame [m] (default origin)"
    option(g, "--moment-ref", help, metavar="X,Y,Z", default="0,0,0")
    g = parser.add_argument_group("shading")
    option(
        g, "--shading", "shading mode (default raycast)", choices=SHADING_MODES, default="raycast"
    )
    option(g, "--samples", "ray samples per panel for raycast (default 16)", type=int, default=16)
    add_solver_arguments(parser, **solver)


def parse_species(text: str) -> dict:
    """Parse ``He=1e12,O=3e15`` into a dict, or raise CommandLineError naming --species."""
    out = {}
    for item in text.split(","):
        name, sep, value = item.partition("=")
        name = name.strip()
        try:
            number = float(value)
        except ValueError:
            number = None
        if not sep or number is None:
            raise CommandLineError(f"--species: expected NAME=NUMBER items, got {item!r}")
        if name in out:
            raise CommandLineError(f"--species: {name} given twice ({text})")
        out[name] = checked(f"--species: {name}", number, "number_density")
    return out


def freestream_from_args(args, model: str) -> FreeStream:
    """The FreeStream given by --speed/--temperature/--mean-mass/--species/--density."""
    missing = [f"--{name}" for name in ("speed", "temperature") if getattr(args, name) is None]
    if args.mean_mass is None and args.species is None:
        missing.append("--mean-mass or --species")
    if missing:
        raise CommandLineError(f"the free stream needs {', '.join(missing)}")
    if model in SPECIES_MODELS and args.species is None:
        raise CommandLineError(f"--gsim {model} needs the composition: give --species")
    species = parse_species(args.species) if args.species else None
    try:
        if species is not None:  # (what the composition implies, given --density or not)
            implied = sum(n * species_mass_kg(name) for name, n in species.items())
            bounded("--species: the mass density they imply", implied, "mass_density")
        flow = FreeStream(
            speed=args.speed,
            temperature=args.temperature,
            number_densities=species,
            mean_mass_amu=args.mean_mass,
            density=args.density,
        )
    except (KeyError, ValueError) as exc:
        text = str(exc.args[0]) if isinstance(exc, KeyError) else str(exc)
        raise CommandLineError(
            text if text.startswith("--") or not species else f"--species: {text}"
        ) from None
    if model == "cll" and not any(species.get(name, 0.0) > 0.0 for name in CLL_SPECIES):
        raise CommandLineError(
            f"--species: the cll model needs one of the species {', '.join(CLL_SPECIES)} with "
            f"n > 0, got {args.species}"
        )
    return flow


def _joint(text: str) -> tuple:
    """``NAME=VALUE`` of ``--joint`` as ``(name, value)``; CommandLineError naming --joint."""
    name, sep, value = str(text).partition("=")
    name = name.strip()
    if not sep or not name:
        raise CommandLineError(f"--joint: expected NAME=VALUE, got {text!r}")
    try:
        return name, float(value)
    except ValueError:
        raise CommandLineError(f"--joint: {name}: {value!r} is not a number") from None


def setup_from_args(args) -> Setup:
    """The set-up the options give (a URDF posed at ``--joint``); errors name the option."""
    joints = None
    if args.joint or is_urdf(args.mesh):
        if not is_urdf(args.mesh):
            raise CommandLineError(
                f"--joint: MESH {args.mesh!r} is no URDF (a .urdf file, 'example-articulated' or "
                "'example-finned')"
            )
        if args.scale != 1.0:
            raise CommandLineError("--scale: a URDF is in metres; scale applies to mesh files only")
        joints = tuple(_joint(text) for text in args.joint)
    labels = (
        ("materials", "--material"),
        ("moment_point", "--moment-ref"),
        ("joints", f"--joint {' '.join(args.joint)}"),
        ("samples", "--samples"),
        ("solver", f"--method {args.method}"),
    )
    with errors_as(CommandLineError, ValueError, "--material: "):
        surface = SurfaceProperties(
            alpha=args.alpha,
            alpha_n=args.alpha_n,
            sigma_n=args.sigma_n,
            sigma_t=args.sigma_t,
            wall_temperature=args.wall_temperature,
        )
    point = tuple(parse_vector3(args.moment_ref, "--moment-ref"))
    with errors_as(CommandLineError, ValueError):
        return Setup(
            body=BodySpec(
                args.mesh, args.scale, args.accept_size, joints=joints, joint_degrees=True
            ),
            model=args.gsim,
            options=ModelOptions(args.incident_temperature, args.adbsat_compat),
            surface=surface,
            overrides=tuple(args.material),
            reference=Reference(area=args.aref, length=args.lref, moment_point=point),
            shading=ShadingPolicy(args.shading, args.samples, exact_offline=1),
            solver=SolverSpec(args.method, args.particles, args.tolerance, args.seed),
            labels=labels,
        )


def model_from_setup(setup: Setup) -> Model:
    """:func:`build_model` of ``setup``; a mesh error is a CommandLineError starting ``MESH:``."""
    with errors_as(CommandLineError, ValueError), errors_as(CommandLineError, MeshError, "MESH: "):
        return build_model(setup)


def method_and_flow_from_args(args):
    """``(model, flow, conditions)`` of the options: a gas given, or by ``--time`` and place.

    An accommodation model's alpha is set as alpha and alpha_n of every material.
    """
    if args.time is None:
        model = model_from_setup(setup_from_args(args))
        return model, freestream_from_args(args, model.setup.model), None
    given = [
        o
        for o in ("speed", "temperature", "mean_mass", "species", "density")
        if getattr(args, o) is not None
    ]
    if given:
        raise CommandLineError(
            f"--{given[0].replace('_', '-')}: give the gas either directly or by --time and a "
            "place, not both"
        )
    options = {"alpha": args.alpha} if args.accommodation == "fixed" else {}
    with errors_as(CommandLineError, ValueError):
        conditions = compute_flight_conditions(args, accommodation_options=options)
    setup = setup_from_args(args)
    if args.accommodation != "fixed":  # alpha and alpha_n on every panel
        setup = setup.with_accommodation(conditions.alpha)
    model = model_from_setup(setup)
    summary = {
        "time": args.time,
        "accommodation_model": args.accommodation,
        "alpha": float(conditions.alpha),
        "altitude_m": float(conditions.altitude),
        "latitude_deg": float(args.lat) if args.lat is not None else None,
        "longitude_deg": float(args.lon) if args.lon is not None else None,
        "position": args.position,
        "velocity": args.velocity,
        "frame": args.frame,
        "f107": conditions.space_weather.f107,  # (the indices in force)
        "f107a": conditions.space_weather.f107a,
        "ap": conditions.space_weather.ap,
        "space_weather": args.space_weather,
        "atmosphere_model": args.atmosphere_model,
    }
    return model, conditions.free_stream(), summary
