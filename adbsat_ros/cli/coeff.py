"""``adbsat-ros coeff MESH``: aerodynamic coefficients (and newtons) at one or more attitudes."""

from __future__ import annotations

import contextlib
import itertools
import json
import math
import sys

import numpy as np

from adbsat_ros.cli.common import add_setup_arguments, method_and_flow_from_args
from adbsat_ros.cli.options import CommandLineError, flag, option, parse_angle_list
from adbsat_ros.cli.solvers import run_tpmc
from adbsat_ros.physics import special
from adbsat_ros.processes import INTERRUPTED_STATUS, stop_on_signals

#: At most this many panel evaluations (attitudes x panels) compute erf with the math module.
FEW_EVALUATIONS = 1_000_000


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
    add_setup_arguments(p)
    option(p, "--aoa", "angles of attack [deg]: list and/or start:step:stop", default="0")
    option(p, "--aos", "sideslip angles [deg]: list and/or start:step:stop", default="0")
    flag(p, "--json", "print a JSON list, one object per attitude")
    help = (
        "draw the mesh coloured by per-panel pressure coefficient at the first attitude (the "
        "test particles' with --method tpmc or both) into this PNG file"
    )
    option(p, "--plot", help, metavar="PNG")
    help = (
        "with --plot, the camera's elevation and azimuth [deg] (default: chosen to show the "
        "panels the flow reaches)"
    )
    option(p, "--view", help, metavar="ELEV,AZIM")
    flag(p, "--per-panel", "with --json, include per-panel cp, ctau, lit fraction")
    p.set_defaults(func=run)


def run(args) -> int:
    """Run ``adbsat-ros coeff``; on a signal, the attitudes done are written; the exit status."""
    aoa_deg = parse_angle_list(args.aoa, "--aoa")
    aos_deg = parse_angle_list(args.aos, "--aos")
    model, flow, _ = method_and_flow_from_args(args)
    method = model.method
    view = parse_view(args.view) if args.view is not None else None
    results, first, stopped = [], None, False
    few = len(aoa_deg) * len(aos_deg) * model.mesh.n_panels <= FEW_EVALUATIONS
    with special.standard_library() if few else contextlib.nullcontext(), stop_on_signals() as stop:
        for a, b in itertools.product(aoa_deg, aos_deg):
            if stop.is_set():  # (SIGINT or SIGTERM: what is done is written)
                stopped = True
                print(
                    f"adbsat-ros coeff: interrupted: the results are those of the "
                    f"{len(results)} of {len(aoa_deg) * len(aos_deg)} attitudes done",
                    file=sys.stderr,
                )
                break
            r, d = _attitude(args, model, flow, a, b)
            first = (a, b, r) if first is None else first
            results.append(d)
            stopped = args.method != "panel" and r.stopped
            if stopped:  # (the test particles' run said so)
                break
    if args.json:
        try:  # (made whole first: a refused number must not leave half a document)
            text = json.dumps(results, indent=1, allow_nan=False)
        except ValueError:
            raise CommandLineError("a coefficient is not finite for these inputs") from None
        sys.stdout.write(text + "\n")
    else:
        print_table(results, method, flow, args.method)
    if args.plot is not None and first is not None:
        from adbsat_ros.plotting.panels import plot_panel_pressure

        a, b, r = first
        path = plot_panel_pressure(model, flow, a, b, args.plot, view=view, result=r)
        print(f"wrote {path}", file=sys.stderr)
    return INTERRUPTED_STATUS if stopped else 0


def _attitude(args, model, flow, a, b) -> tuple:
    """The result (the last solver's) and the output row at aoa ``a``, aos ``b`` [deg]."""
    aoa, aos = math.radians(a), math.radians(b)
    d = {}
    if args.method != "tpmc":
        r = model.evaluate(flow, angles=(aoa, aos), solver="panel")
        d["panel"] = dict(r.to_dict(flow, per_panel=args.per_panel), shading=args.shading)
        if model.positions is not None:
            articulation = (model.body, model.positions)
            d["panel"].update(articulated_outputs(articulation, model.method, r, flow))
    if args.method != "panel":
        r = run_tpmc(args, model, flow, aoa, aos)
        d["tpmc"] = r.to_dict(flow, per_panel=args.per_panel)
    if args.method == "both":
        d = dict(aoa_deg=float(a), aos_deg=float(b), **d)
        d["difference"] = difference(d["tpmc"], d["panel"])
    else:
        d = d[args.method]
    d["aoa_deg"], d["aos_deg"] = float(a), float(b)  # exact as given
    return r, d


def parse_view(text: str) -> tuple:
    """``ELEV,AZIM`` in degrees, two finite numbers; CommandLineError naming --view."""
    try:
        elev, azim = (float(x) for x in text.split(","))
    except ValueError:
        raise CommandLineError(f"--view: expected two numbers ELEV,AZIM, got {text!r}") from None
    if not (math.isfinite(elev) and math.isfinite(azim)):
        raise CommandLineError(f"--view: expected two finite numbers, got {text!r}")
    return elev, azim


def articulated_outputs(articulation, method, result, flow) -> dict:
    """A URDF body's per-link loads and per-joint efforts (coefficients; with a density N, N m)."""
    from adbsat_ros.physics.panel_loads import panel_loads

    body, positions = articulation
    loads = panel_loads(method.mesh, result)
    split = body.loads(
        loads.force, loads.point, positions, loads.moment_point, loads.reference_length
    )
    links = {
        name: {"Cf_G": split.link_force[i].tolist(), "Cm_G": split.link_moment[i].tolist()}
        for i, name in enumerate(body.links)
    }
    joints = {}
    ref = method.reference
    q = flow.dynamic_pressure() if flow.mass_density is not None else None
    for name, effort in split.joint_effort.items():
        prismatic = body.joints[name].kind == "prismatic"
        entry = {"position": positions[name], "effort_coefficient": effort}
        if q is not None:
            scale = q * ref.area * (1.0 if prismatic else ref.length)
            entry["force_N" if prismatic else "torque_Nm"] = effort * scale
        joints[name] = entry
    return {"links": links, "joints": joints}


def difference(tpmc: dict, panel: dict) -> dict:
    """TPMC less panel method for C_D, C_L, C_Y and Cm_B, with the test-particle standard errors."""
    out = {}
    for name in ("CD", "CL", "CY"):
        out[name] = tpmc[name] - panel[name]
        out[f"{name}_error"] = tpmc[f"{name}_error"]
    out["Cm_B"] = [t - p for t, p in zip(tpmc["Cm_B"], panel["Cm_B"])]
    out["Cm_B_error"] = tpmc["Cm_B_error"]
    return out


def print_table(results, method, flow, solver: str = "panel") -> None:
    """Print the results of :func:`run` as a table, one line per attitude, after set-up lines."""
    mesh = method.mesh
    print(f"mesh {mesh.source}: {mesh.n_panels} panels, materials {', '.join(mesh.material_names)}")
    print(
        f"model {method.model}, V = {flow.speed:.1f} m/s, T = {flow.temperature:.1f} K, "
        f"s = {flow.speed_ratio:.3f}, Aref = {method.reference.area:.4g} m^2, "
        f"Lref = {method.reference.length:.4g} m"
    )
    if solver == "both":
        print_comparison(results)
        return
    if solver == "tpmc":
        print_tpmc(results)
        return
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


def _pm(value, error) -> str:
    return f"{value:9.5f} +- {error:7.5f}"


def print_tpmc(results) -> None:
    """Test-particle results: each coefficient with its standard error."""
    print(f"test-particle Monte Carlo, seed {results[0]['seed']}; +- one standard error")
    print(f"{'aoa':>7} {'aos':>7} {'CD':>20} {'CL':>20} {'CY':>20} {'molecules':>10} {'hits':>10}")
    for d in results:
        print(
            f"{d['aoa_deg']:7.2f} {d['aos_deg']:7.2f} {_pm(d['CD'], d['CD_error']):>20} "
            f"{_pm(d['CL'], d['CL_error']):>20} {_pm(d['CY'], d['CY_error']):>20} "
            f"{d['particles']:10d} {d['hits']:10d}"
        )


def print_comparison(results) -> None:
    """Panel method and test particles side by side, and their difference in standard errors."""
    print(
        "panel method against test-particle Monte Carlo (every reflection); +- one standard error"
    )
    print(
        f"{'aoa':>7} {'aos':>7} {'CD panel':>9} {'CD tpmc':>20} {'difference':>20} {'in %':>7} "
        f"{'sigmas':>7} {'CL panel':>9} {'CL tpmc':>20}"
    )
    for d in results:
        p, t, x = d["panel"], d["tpmc"], d["difference"]
        error = x["CD_error"]
        print(
            f"{d['aoa_deg']:7.2f} {d['aos_deg']:7.2f} {p['CD']:9.5f} "
            f"{_pm(t['CD'], t['CD_error']):>20} {_pm(x['CD'], error):>20} "
            f"{100 * x['CD'] / p['CD']:7.2f} "
            f"{x['CD'] / error if error > 0 else float('inf'):7.1f} {p['CL']:9.5f} "
            f"{_pm(t['CL'], t['CL_error']):>20}"
        )
