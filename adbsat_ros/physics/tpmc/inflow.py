"""Molecules entering a box around the body from a drifting Maxwellian gas, sampled exactly.

Formulas: docs/physics.md, section 12 ("Inflow"). Units: SI; positions in the mesh frame G [m].
"""

from __future__ import annotations

import math

import numpy as np
from scipy.special import erf, erfcx

from adbsat_ros.physics.constants import BOLTZMANN

SQRT_PI = math.sqrt(math.pi)


def flux_factor(s) -> np.ndarray:
    """G(inf) = exp(-s^2) / 2 + sqrt(pi) / 2 s (1 + erf(s)), with erfcx where s < 0 (keeps its
    digits)."""
    s = np.asarray(s, dtype=float)
    with np.errstate(over="ignore", invalid="ignore"):
        up = 0.5 * np.exp(-s * s) + 0.5 * SQRT_PI * s * (1.0 + erf(s))
        down = np.exp(-s * s) * (0.5 + 0.5 * SQRT_PI * s * erfcx(-s))
    return np.where(s >= 0.0, up, down)


def normal_speed_ratios(s, rng: np.random.Generator) -> np.ndarray:
    """Normal speeds over c (P,) of entering molecules, exact by rejection, s = U . n / c."""
    s = np.asarray(s, dtype=float)
    x = np.empty_like(s)
    up = s >= 0.0
    x[up] = _rejection(s[up], rng, _upstream)
    x[~up] = _rejection(s[~up], rng, _downstream)
    return x


def _rejection(s, rng, draw) -> np.ndarray:
    """Draw for every element of ``s`` until each is accepted."""
    x = np.empty_like(s)
    waiting = np.arange(s.size)
    while waiting.size:
        value, accept = draw(s[waiting], rng)
        x[waiting[accept]] = value[accept]
        waiting = waiting[~accept]
    return x


def _upstream(s, rng) -> tuple:
    """One draw of the s >= 0 proposal and its acceptance."""
    count = s.size
    u = 1.0 - rng.random((count, 4))  # (0, 1]
    e = np.exp(-s * s)
    w_abs = 1.0 - 0.5 * e  # weights of the mixture: |y| exp(-y^2) and s exp(-y^2) on y > -s
    w_normal = 0.5 * SQRT_PI * s * (1.0 + erf(s))
    positive = u[:, 1] * w_abs < 0.5  # the upper half of |y| exp(-y^2), weight 1/2
    r = u[:, 2]
    y = np.where(positive, np.sqrt(-np.log(r)), -np.sqrt(-np.log(1.0 - r * (1.0 - e))))
    normal = u[:, 0] * (w_abs + w_normal) >= w_abs
    y[normal] = rng.standard_normal(int(normal.sum())) / math.sqrt(2.0)
    accept = (y > -s) & (u[:, 3] * (np.abs(y) + s) <= y + s)
    return y + s, accept


def _downstream(s, rng) -> tuple:
    """One draw of the s < 0 proposals and their acceptance."""
    count = s.size
    u = 1.0 - rng.random((count, 2))
    near = s > -1.0
    x = np.sqrt(-np.log(u[:, 0]))
    far = ~near
    x[far] = rng.gamma(2.0, 1.0, int(far.sum())) / (-2.0 * s[far])
    accept = np.where(near, u[:, 1] <= np.exp(2.0 * s * x), u[:, 1] <= np.exp(-x * x))
    return x, accept


class InflowBox:
    """The box the molecules enter through, and the free stream's flux through its faces.

    lower, upper: bounding-box corners [m], G; drift: U = V u [m/s], G; temperature: T [K];
    masses [kg], mole_fractions (J,); margin: growth as a fraction of the largest side.
    normals (6, 3): inward face normals (-x, +x, -y, +y, -z, +z); rates (6, J) [m^3/s].
    """

    def __init__(self, lower, upper, drift, temperature, masses, mole_fractions, margin=0.05):
        lower = np.asarray(lower, dtype=float)
        upper = np.asarray(upper, dtype=float)
        grow = margin * float(np.max(upper - lower))
        self.lower, self.upper = lower - grow, upper + grow
        self.drift = np.asarray(drift, dtype=float)
        self.temperature = float(temperature)
        self.masses = np.asarray(masses, dtype=float)
        self.mole_fractions = np.asarray(mole_fractions, dtype=float)
        side = self.upper - self.lower
        self.normals = np.zeros((6, 3))
        self.areas = np.zeros(6)
        for axis in range(3):
            others = [k for k in range(3) if k != axis]
            for end, sign in ((0, 1.0), (1, -1.0)):
                self.normals[2 * axis + end, axis] = sign
                self.areas[2 * axis + end] = side[others[0]] * side[others[1]]
        self.thermal_speeds = np.sqrt(2.0 * BOLTZMANN * self.temperature / self.masses)
        self.speed_ratios = (self.normals @ self.drift)[:, None] / self.thermal_speeds[None, :]
        self.rates = (
            self.mole_fractions[None, :]
            * self.areas[:, None]
            * self.thermal_speeds[None, :]
            * flux_factor(self.speed_ratios)
            / SQRT_PI
        )

    @property
    def rate(self) -> float:
        """Molecules entering per second per unit number density [m^3/s]."""
        return float(self.rates.sum())

    def momentum_flux(self) -> np.ndarray:
        """Momentum entering per second per unit number density [kg m^4 / s^2 per m^3], G, closed
        form."""
        total = np.zeros(3)
        for f in range(6):
            n = self.normals[f]
            tangential = self.drift - (self.drift @ n) * n
            for j, (m, c) in enumerate(zip(self.masses, self.thermal_speeds)):
                s = self.speed_ratios[f, j]
                flux = 0.5 * s * math.exp(-s * s)
                flux += 0.25 * SQRT_PI * (1.0 + 2.0 * s * s) * (1.0 + math.erf(s))
                normal = m * c * c / SQRT_PI * flux
                x_area = self.mole_fractions[j] * self.areas[f]
                total += x_area * normal * n + self.rates[f, j] * m * tangential
        return total

    def sample(self, count: int, rng: np.random.Generator) -> tuple:
        """``count`` molecules: positions [m], velocities [m/s] (count, 3) and species indices."""
        cumulative = np.cumsum(self.rates.ravel())
        pick = np.searchsorted(cumulative, rng.random(count) * cumulative[-1], side="right")
        pick = np.minimum(pick, cumulative.size - 1)
        face, species = np.divmod(pick, self.masses.size)
        axis = face // 2
        n = self.normals[face]
        c = self.thermal_speeds[species]
        x = normal_speed_ratios(self.speed_ratios[face, species], rng)
        thermal = rng.standard_normal((count, 3)) * (c / math.sqrt(2.0))[:, None]
        velocity = self.drift + thermal
        # the normal component replaced by the sampled one (n is +-e_axis)
        rows = np.arange(count)
        velocity[rows, axis] = n[rows, axis] * c * x
        position = self.lower + rng.random((count, 3)) * (self.upper - self.lower)
        position[rows, axis] = np.where(face % 2 == 0, self.lower[axis], self.upper[axis])
        return position, velocity, species
