"""``adbsat-ros coeff MESH``: aerodynamic coefficients (and newtons) at one or more attitudes."""

from __future__ import annotations

import json
import math
import sys

import numpy as np

from adbsat_ros.cli.atmosphere import add_flight_arguments
from adbsat_ros.cli.common import (
    add_flow_arguments,
    add_mesh_arguments,
    add_model_arguments,
    add_reference_arguments,
    add_shading_arguments,
    make_shader_from_args,
    method_and_flow_from_args,
)
from adbsat_ros.cli.options import CommandLineError, parse_angle_list
from adbsat_ros.geometry import frames


def configure(p) -> None:
    """Give the ``coeff`` subcommand's parser ``p`` its description and options."""
    p.description = (
        "Compute ADBSat-convention coefficients (Cf_w, Cf_f, Cm_B, Aref, Lref, AreaProj, "
        "CD/CL/CY) for every pair of --aoa x --aos; with a density, also the force [N] and "
        "torque [N m] in the mesh frame about --moment-ref. The gas is given either directly "
        "(--speed --temperature --mean-mass|--species [--density]) or by flight conditions "
        "(--time with --altitude/--lat/--lon or --position/--velocity, space weather): "
        "NRLMSISE-00 then gives density, temperature and composition, as ADBSat's environment "
        "path."
    )
    add_mesh_arguments(p)
    add_model_arguments(p)
    add_flow_arguments(p)
    add_flight_arguments(p, time_required=False, with_alpha=False)
    add_reference_arguments(p)
    add_shading_arguments(p)
    p.add_argument("--aoa", default="0", help="angles of attack [deg]: list and/or start:step:stop")
    p.add_argument("--aos", default="0", help="sideslip angles [deg]: list and/or start:step:stop")
    p.add_argument("--json", action="store_true", help="print a JSON list, one object per attitude")
    p.add_argument(
        "--per-panel",
        action="store_true",
        help="with --json, include per-panel cp, ctau, lit fraction",
    )
    p.set_defaults(func=run)


def run(args) -> int:
    """Run ``adbsat-ros coeff``; returns the exit status."""
    aoa_deg = parse_angle_list(args.aoa, "--aoa")
    aos_deg = parse_angle_list(args.aos, "--aos")
    method, flow, _ = method_and_flow_from_args(args)
    shader = make_shader_from_args(args, method.mesh)
    results = []
    for a in aoa_deg:
        for b in aos_deg:
            u = frames.flow_direction(math.radians(a), math.radians(b))
            lighting = shader.lighting(u) if shader is not None else None
            r = method.coefficients(flow, math.radians(a), math.radians(b), lighting=lighting)
            d = r.to_dict(flow, per_panel=args.per_panel)
            d["aoa_deg"], d["aos_deg"] = float(a), float(b)  # exact as given
            d["shading"] = args.shading
            results.append(d)
    if args.json:
        try:  # (made whole first: a refused number must not leave half a document)
            text = json.dumps(results, indent=1, allow_nan=False)
        except ValueError:
            raise CommandLineError("a coefficient is not finite for these inputs") from None
        sys.stdout.write(text + "\n")
    else:
        print_table(results, method, flow)
    return 0


def print_table(results, method, flow) -> None:
    """Print the results of :func:`run` as a table, one line per attitude, after a set-up line."""
    mesh = method.mesh
    print(f"mesh {mesh.source}: {mesh.n_panels} panels, materials {', '.join(mesh.material_names)}")
    print(
        f"model {method.model}, V = {flow.speed:.1f} m/s, T = {flow.temperature:.1f} K, "
        f"s = {flow.speed_ratio:.3f}, Aref = {method.reference.area:.4g} m^2, "
        f"Lref = {method.reference.length:.4g} m"
    )
    has_force = "force_N" in results[0]
    head = (
        f"{'aoa':>7} {'aos':>7} {'CD':>9} {'CL':>9} {'CY':>9} "
        f"{'Cm_B x':>10} {'Cm_B y':>10} {'Cm_B z':>10} {'AreaProj':>9}"
    )
    if has_force:
        head += f" {'|F| [N]':>10} {'|T| [Nm]':>10}"
    print(head)
    for d in results:
        line = (
            f"{d['aoa_deg']:7.2f} {d['aos_deg']:7.2f} {d['CD']:9.5f} {d['CL']:9.5f} {d['CY']:9.5f} "
            f"{d['Cm_B'][0]:10.5f} {d['Cm_B'][1]:10.5f} {d['Cm_B'][2]:10.5f} {d['AreaProj']:9.5f}"
        )
        if has_force:
            line += f" {np.linalg.norm(d['force_N']):10.4e} {np.linalg.norm(d['torque_Nm']):10.4e}"
        print(line)
