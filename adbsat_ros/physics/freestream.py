"""The undisturbed gas a satellite flies through: speed, temperature and composition.

A :class:`FreeStream` is built by hand (``coeff --speed/--temperature/--species``) or from an
atmosphere model and an orbital state (:mod:`adbsat_ros.environment.flight_conditions`).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field
from typing import Mapping

import numpy as np

from adbsat_ros.physics.constants import AMU, BOLTZMANN, MOLAR_MASS_G, SPECIES, species_mass_kg


def _check_positive(name: str, value: float) -> float:
    value = float(value)
    if not math.isfinite(value) or value <= 0.0:
        raise ValueError(f"{name} must be a finite number > 0, got {value!r}")
    return value


_SPECIES_MASS_KG = {name: species_mass_kg(name) for name in MOLAR_MASS_G}


def _species_masses(species: tuple) -> list | None:
    """Particle masses [kg] of ``species`` names, or None if one is unknown."""
    try:
        return [_SPECIES_MASS_KG[name] for name in species]
    except KeyError:
        return None


def _checked_number_densities(number_densities: Mapping) -> list:
    """The number densities as floats; ValueError naming the first one not allowed."""
    values = []
    for name, value in number_densities.items():
        if name not in MOLAR_MASS_G:
            raise ValueError(
                f"unknown species {name!r} in number_densities; "
                f"known species are {', '.join(SPECIES)}"
            )
        try:
            number = float(value)
        except (TypeError, ValueError):
            number = math.nan
        if not 0.0 <= number < math.inf:
            raise ValueError(f"number density of {name} must be finite and >= 0, got {value!r}")
        values.append(number)
    if not any(value > 0.0 for value in values):
        raise ValueError("number_densities: at least one species must have n > 0")
    return values


def _sums(values: list, masses: list) -> tuple:
    """``(sum n_j, sum n_j m_j)`` in species order, as ADBSat's ``environment.m``."""
    total = 0.0
    weighted = 0.0
    for n, m in zip(values, masses):
        total += n
        weighted += n * m
    return total, weighted


@dataclass(frozen=True, init=False)
class FreeStream:
    """Free-stream state of the gas relative to the spacecraft (a frozen value); speed ratio
    s = V / sqrt(2 k_B T_inf / m), number-weighted mean mass as ADBSat's ``environment.m``.

    Parameters
    ----------
    speed : float
        Magnitude of the relative wind V [m/s], > 0.
    temperature : float
        Local (translational) gas temperature T_inf [K], > 0.
    number_densities : mapping of str to float, optional
        Species number densities [m^-3] by :data:`~.constants.SPECIES` name, >= 0, not all 0;
        needed by cll and dria.
    mean_mass_amu : float, optional
        Mean molecular mass [amu]; exactly one of this and ``number_densities``.
    density : float, optional
        Total mass density rho [kg/m^3] (default sum of n_j m_j), only for newtons.

    Attributes
    ----------
    mean_mass : float
        Number-weighted mean molecular mass [kg] (equal to ``AtmosphereState.mean_mass``).

    Raises
    ------
    ValueError
        Naming the input that is not allowed.
    """

    speed: float
    temperature: float
    number_densities: Mapping[str, float] | None = None
    mean_mass_amu: float | None = None
    density: float | None = None
    mean_mass: float = field(init=False, repr=False, compare=False)
    _species: tuple = field(init=False, repr=False, compare=False)

    def __init__(
        self,
        speed: float,
        temperature: float,
        number_densities: Mapping[str, float] | None = None,
        mean_mass_amu: float | None = None,
        density: float | None = None,
    ):
        # (the checked fields written once into the instance's dict: a frozen dataclass's own
        # __init__ would set each through object.__setattr__, and the node makes one per message)
        speed = _check_positive("speed", speed)
        temperature = _check_positive("temperature", temperature)
        if (number_densities is None) == (mean_mass_amu is None):
            raise ValueError("give exactly one of number_densities and mean_mass_amu")
        if number_densities is not None:
            species = tuple(number_densities)
            masses = _species_masses(species)
            try:
                values = list(map(float, number_densities.values()))
            except (TypeError, ValueError):
                values = None
            total = weighted = math.nan
            if masses and values and min(values) >= 0.0:
                total, weighted = _sums(values, masses)
            # one test of the usual case (known species, densities >= 0 with a finite positive
            # total); anything else is checked density by density, for the error naming it
            if not 0.0 < total < math.inf:
                values = _checked_number_densities(number_densities)  # (or a total overflowing)
                total, weighted = _sums(values, masses)
            if not weighted > 0.0:  # (densities so small that n m underflows to 0)
                raise ValueError(
                    f"number_densities: the mass density sum(n_j m_j) of {number_densities!r} is "
                    "0 in floating point: the densities are too small"
                )
            number_densities = dict(zip(species, values))
            mean_mass = weighted / total
        else:
            species = ()
            mean_mass = _check_positive("mean_mass_amu", mean_mass_amu) * AMU
        if density is not None:
            density = _check_positive("density", density)
        self.__dict__.update(
            speed=speed,
            temperature=temperature,
            number_densities=number_densities,
            mean_mass_amu=mean_mass_amu,
            density=density,
            mean_mass=mean_mass,
            _species=species,
        )

    # ----------------------------------------------------------------------------- derived values
    @property
    def has_species(self) -> bool:
        """True if the composition (species number densities) is known."""
        return bool(self._species)

    @property
    def species(self) -> tuple:
        """Names of the species given, in the order of :attr:`species_number_densities`."""
        return self._species

    @functools.cached_property
    def species_number_densities(self) -> np.ndarray:
        """Number densities n_j [m^-3] of :attr:`species` (an array made on first read)."""
        return np.array(list(self.number_densities.values()) if self._species else [], dtype=float)

    @functools.cached_property
    def species_masses(self) -> np.ndarray:
        """Particle masses m_j [kg] of :attr:`species` (an array made on first read)."""
        return np.array(_species_masses(self._species) or (), dtype=float)

    @property
    def mass_density(self) -> float | None:
        """Mass density [kg/m^3]: ``density`` if given, else sum(n_j m_j), else None."""
        if self.density is not None:
            return self.density
        if self.has_species:
            return float(np.dot(self.species_number_densities, self.species_masses))
        return None

    @property
    def specific_gas_constant(self) -> float:
        """R = k_B / m [J/(kg K)] of the mixture."""
        return BOLTZMANN / self.mean_mass

    @property
    def thermal_speed(self) -> float:
        """Most probable thermal speed sqrt(2 k_B T / m) [m/s]."""
        return math.sqrt(2.0 * BOLTZMANN * self.temperature / self.mean_mass)

    @property
    def speed_ratio(self) -> float:
        """Molecular speed ratio s = V / sqrt(2 k_B T / m) [-]."""
        return self.speed / self.thermal_speed

    def species_speed_ratios(self) -> np.ndarray:
        """Per-species speed ratios s_j = V / sqrt(2 k_B T / m_j) [-]."""
        return self.speed / np.sqrt(2.0 * BOLTZMANN * self.temperature / self.species_masses)

    def mass_fractions(self) -> np.ndarray:
        """Mass fractions rho_j / sum(rho_k) of :attr:`species` [-] (they sum to 1)."""
        rho = self.species_number_densities * self.species_masses
        return rho / rho.sum()

    def dynamic_pressure(self) -> float:
        """q = 0.5 rho V^2 [Pa]; raises ValueError if no density is known."""
        rho = self.mass_density
        if rho is None:
            raise ValueError(
                "no density: give density or number_densities to get forces in newtons"
            )
        return 0.5 * rho * self.speed**2
