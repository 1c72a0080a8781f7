"""Re-emission of a molecule from a surface: the gas-surface scattering kernels.

Molecules leave into the half-space they came from. Formulas: docs/physics.md, section 12
("Surfaces"). Sources: Maxwell, Phil. Trans. R. Soc. 170 (1879); Lord, Phys. Fluids A 3 (1991)
706-710; Bird, "Molecular Gas Dynamics and the Direct Simulation of Gas Flows" (1994).
"""

from __future__ import annotations

import math

import numpy as np

from adbsat_ros.physics.constants import BOLTZMANN

#: Kernel of each gas-surface model the test-particle solver can run.
KERNEL_OF_MODEL = {"sentman": "diffuse", "dria": "diffuse", "maxwell": "maxwell", "cll": "cll"}


def tangents(n: np.ndarray) -> tuple:
    """Two unit vectors t1, t2 with (t1, t2, n) right-handed, for each row of ``n``."""
    helper = np.zeros_like(n)
    use_x = np.abs(n[:, 0]) < 0.9
    helper[use_x, 0] = 1.0
    helper[~use_x, 1] = 1.0
    t1 = np.cross(n, helper)
    t1 /= np.linalg.norm(t1, axis=1)[:, None]
    return t1, np.cross(n, t1)


def _open_uniform(rng, count) -> np.ndarray:
    """Uniform numbers in (0, 1] (so that log(u) is finite)."""
    return 1.0 - rng.random(count)


def diffuse(v, frame, mass, alpha, wall_temperature, rng) -> np.ndarray:
    """Cosine-law re-emission with energy accommodation ``alpha`` (sentman, dria)."""
    count = len(v)
    incident = mass * np.einsum("ij,ij->i", v, v) / (4.0 * BOLTZMANN)  # T_i = E_i / (2 k_B)
    emitted = incident + alpha * (wall_temperature - incident)
    return _wall_flux(frame, np.sqrt(2.0 * BOLTZMANN * emitted / mass), rng, count)


def _wall_flux(frame, c, rng, count) -> np.ndarray:
    """Velocities from the flux Maxwellian of most probable speed ``c`` leaving along n."""
    n, t1, t2 = frame
    normal = np.sqrt(-np.log(_open_uniform(rng, count)))
    g = rng.standard_normal((count, 2)) / math.sqrt(2.0)
    return c[:, None] * (normal[:, None] * n + g[:, :1] * t1 + g[:, 1:] * t2)


def maxwell(v, frame, mass, alpha, wall_temperature, rng) -> np.ndarray:
    """A fraction ``alpha`` re-emitted diffusely at T_w, the rest specularly."""
    count = len(v)
    n = frame[0]
    c = np.broadcast_to(np.sqrt(2.0 * BOLTZMANN * wall_temperature / mass), (count,))
    out = _wall_flux(frame, c, rng, count)
    specular = rng.random(count) >= alpha
    mirrored = v - 2.0 * np.einsum("ij,ij->i", v, n)[:, None] * n
    out[specular] = mirrored[specular]
    return out


def cll(v, frame, mass, alpha_n, sigma_t, wall_temperature, rng) -> np.ndarray:
    """Cercignani-Lampis-Lord re-emission (Lord 1991), in units of c_w = sqrt(2 k_B T_w / m)."""
    count = len(v)
    n, t1, t2 = frame
    c = np.broadcast_to(np.sqrt(2.0 * BOLTZMANN * wall_temperature / mass), (count,))
    alpha_n = np.broadcast_to(alpha_n, (count,))
    alpha_t = np.broadcast_to(sigma_t * (2.0 - sigma_t), (count,))
    w = v / c[:, None]
    w_n = -np.einsum("ij,ij->i", w, n)  # > 0: towards the surface
    r = np.sqrt(-alpha_n * np.log(_open_uniform(rng, count)))
    theta = 2.0 * math.pi * rng.random(count)
    kept = np.sqrt(1.0 - alpha_n) * w_n
    normal = np.sqrt(np.maximum(r * r + kept * kept + 2.0 * r * kept * np.cos(theta), 0.0))
    r_t = np.sqrt(-alpha_t * np.log(_open_uniform(rng, count)))
    theta_t = 2.0 * math.pi * rng.random(count)
    keep_t = np.sqrt(1.0 - alpha_t)
    w1 = keep_t * np.einsum("ij,ij->i", w, t1) + r_t * np.cos(theta_t)
    w2 = keep_t * np.einsum("ij,ij->i", w, t2) + r_t * np.sin(theta_t)
    return c[:, None] * (normal[:, None] * n + w1[:, None] * t1 + w2[:, None] * t2)


def reemit(kernel: str, v, frame, mass, surface, rng) -> np.ndarray:
    """Velocities (H, 3) [m/s] of molecules leaving the panels they hit with ``v`` [m/s].

    frame: (n, t1, t2), the side hit's normal into the gas and two tangents; mass (H,) [kg].
    """
    t_w = surface["wall_temperature"]
    if kernel == "diffuse":
        return diffuse(v, frame, mass, surface["alpha"], t_w, rng)
    if kernel == "maxwell":
        return maxwell(v, frame, mass, surface["alpha"], t_w, rng)
    if kernel == "cll":
        return cll(v, frame, mass, surface["alpha_n"], surface["sigma_t"], t_w, rng)
    raise ValueError(f"unknown kernel {kernel!r}; choose one of diffuse, maxwell, cll")
