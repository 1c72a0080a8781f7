"""Closed-form free-molecular references shared by the tests (Sentman 1961; Bird 1994, Ch. 7)."""

import math

import trimesh

from adbsat_ros.geometry.loading import panels_from_trimesh
from adbsat_ros.physics.constants import BOLTZMANN

SQRT_PI = math.sqrt(math.pi)


def incident_temperature(flow, form="energy"):
    """T_i = m V^2/(4k) (energy flux, Koppenwallner) or m V^2/(3k) (kinetic, Moe)."""
    return flow.mean_mass * flow.speed**2 / ((4.0 if form == "energy" else 3.0) * BOLTZMANN)


def reemission_temperature(flow, alpha, Tw, form="energy"):
    """T_r = T_i + alpha (T_w - T_i) (Sentman 1961 energy accommodation)."""
    Ti = incident_temperature(flow, form)
    return Ti + alpha * (Tw - Ti)


_SPHERE_CACHE = {}


def unit_sphere_mesh(subdivisions=5, centre=(0.0, 0.0, 0.0)):
    """Icosphere scaled so its total area is exactly 4 pi (a unit sphere's), then translated."""
    key = (subdivisions, tuple(centre))
    if key not in _SPHERE_CACHE:
        ico = trimesh.creation.icosphere(subdivisions=subdivisions, radius=1.0)
        ico.apply_scale(math.sqrt(4.0 * math.pi / ico.area))
        ico.apply_translation(centre)
        _SPHERE_CACHE[key] = panels_from_trimesh(ico)
    return _SPHERE_CACHE[key]


def sentman_sphere_cd(s, Tr_over_Tinf):
    """Sentman (1961) sphere drag, diffuse re-emission at T_r, referenced to pi r^2
    (also Schaaf & Chambre 1961; Bird 1994 Ch. 7):
    C_D = (2 s^2 + 1) e^{-s^2}/(sqrt(pi) s^3) + (4 s^4 + 4 s^2 - 1) erf(s)/(2 s^4)
          + (2 sqrt(pi)/(3 s)) sqrt(T_r/T_inf)."""
    return (
        (2 * s * s + 1) * math.exp(-s * s) / (SQRT_PI * s**3)
        + (4 * s**4 + 4 * s * s - 1) * math.erf(s) / (2 * s**4)
        + 2 * SQRT_PI / (3 * s) * math.sqrt(Tr_over_Tinf)
    )
