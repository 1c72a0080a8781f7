"""Test particles followed through the body's panels until they leave, and the momentum they give
(no molecule-molecule collisions; docs/physics.md, section 12, "Tracing"). Units: SI, frame G."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from adbsat_ros.physics.tpmc.kernels import reemit, tangents

#: A re-emitted molecule starts this fraction of the scene's size off the panel, on the side it
#: leaves into: clear of float32 rounding of the Embree scene (7.6e-8 of its size) by 13 times.
LIFT_OFF = 1e-6
#: A molecule still bouncing after this many hits is stopped and counted as ``trapped``.
MAX_BOUNCES = 100_000


@dataclass
class Tally:
    """What a batch did: per molecule ``impulse`` [kg m/s], ``moment`` [kg m^2/s], ``exit_velocity``
    [m/s]; per panel ``panel_impulse`` [kg m/s]; ``trapped`` after :data:`MAX_BOUNCES` hits."""

    impulse: np.ndarray
    moment: np.ndarray
    exit_velocity: np.ndarray
    panel_impulse: np.ndarray
    panel_hits: np.ndarray
    hits: int = 0
    trapped: int = 0


def surface_at(surface, faces) -> dict:
    """The scattering parameters of the panels ``faces`` from a PanelSurface."""
    out = {}
    for name in ("alpha", "alpha_n", "sigma_t", "wall_temperature"):
        value = getattr(surface, name)
        out[name] = value if np.isscalar(value) else value[faces]
    return out


def trace(scene, mesh, kernel, surface, positions, velocities, masses, rng, moment_point):
    """Follow molecules from entry until they leave: positions [m], velocities [m/s], masses [kg],
    G."""
    count = len(positions)
    n_panels = mesh.n_panels
    size = float(np.max(mesh.bounds[1] - mesh.bounds[0]))
    lift = LIFT_OFF * size
    ref = np.asarray(moment_point, dtype=float)
    tally = Tally(
        impulse=np.zeros((count, 3)),
        moment=np.zeros((count, 3)),
        exit_velocity=np.array(velocities, dtype=float),
        panel_impulse=np.zeros((n_panels, 3)),
        panel_hits=np.zeros(n_panels, dtype=np.int64),
    )
    index = np.arange(count)
    pos = np.array(positions, dtype=float)
    vel = np.array(velocities, dtype=float)
    mass = np.asarray(masses, dtype=float)
    last = np.full(count, -1, dtype=np.int64)
    normals = mesh.normals
    t1_all, t2_all = tangents(normals)
    bounces = 0
    while index.size:
        # the rays along the velocities: a hit is at pos + t vel, t the time of flight [s]
        face, flight = scene.first_hit(pos, vel)
        # a panel met again straight after leaving it is float rounding (a plane cannot be
        # met twice by a line leaving it): step past the point and look again
        again = (face == last) & (face >= 0)
        gone = (face < 0) & ~again
        tally.exit_velocity[index[gone]] = vel[gone]
        hit = (face >= 0) & ~again
        stay = hit | again
        if again.any():
            step = flight[again] + lift / np.linalg.norm(vel[again], axis=1)
            pos[again] += step[:, None] * vel[again]
        if hit.any():
            f = face[hit]
            v_in = vel[hit]
            point = pos[hit] + flight[hit, None] * v_in
            normal = normals[f]
            # the side the molecule came from; (t1, -t2, -n) is right-handed as (t1, t2, n) is
            sign = np.where(np.einsum("ij,ij->i", v_in, normal) < 0.0, 1.0, -1.0)[:, None]
            side = sign * normal
            frame = (side, t1_all[f], sign * t2_all[f])
            v_out = reemit(kernel, v_in, frame, mass[hit], surface_at(surface, f), rng)
            dp = mass[hit, None] * (v_in - v_out)
            who = index[hit]
            tally.impulse[who] += dp
            tally.moment[who] += np.cross(point - ref, dp)
            for k in range(3):
                tally.panel_impulse[:, k] += np.bincount(f, weights=dp[:, k], minlength=n_panels)
            tally.panel_hits += np.bincount(f, minlength=n_panels)
            tally.hits += int(f.size)
            pos[hit] = point + lift * side
            vel[hit] = v_out
            last[hit] = f
        index, pos, vel, mass, last = index[stay], pos[stay], vel[stay], mass[stay], last[stay]
        bounces += 1
        if bounces >= MAX_BOUNCES and index.size:
            tally.trapped = int(index.size)
            tally.exit_velocity[index] = vel
            break
    return tally
