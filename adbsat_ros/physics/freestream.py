"""The undisturbed gas a satellite flies through: speed, temperature and composition.

A :class:`FreeStream` is what every gas-surface interaction model needs besides the panel
geometry. It can be built by hand (the ``coeff`` command's ``--speed/--temperature/--species``)
or from an atmosphere model and an orbital state (:mod:`adbsat_ros.environment.flight_conditions`).
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


@functools.lru_cache(maxsize=64)
def _species_masses(species: tuple):
    """Read-only particle masses [kg] of distinct known ``species``, or None if they are not."""
    if (
        not species
        or len(set(species)) != len(species)
        or not all(s in MOLAR_MASS_G for s in species)
    ):
        return None
    masses = np.array([species_mass_kg(s) for s in species])
    masses.setflags(write=False)
    return masses


@dataclass(frozen=True)
class FreeStream:
    """Free-stream state of the gas relative to the spacecraft.

    Parameters
    ----------
    speed : float
        Magnitude of the relative wind V [m/s], > 0.
    temperature : float
        Local (translational) gas temperature T_inf [K], > 0.
    number_densities : mapping of str to float, optional
        Species number densities [m^-3], keys from :data:`adbsat_ros.physics.constants.SPECIES`
        (``He O N2 O2 Ar H N AnO``). Needed by the per-species models (``cll``, ``dria``); the
        mean molecular mass and, unless ``density`` is given, the mass density follow from it.
    mean_mass_amu : float, optional
        Mean molecular mass [amu] when no composition is given. Exactly one of
        ``number_densities`` and ``mean_mass_amu`` must be given.
    density : float, optional
        Total mass density rho [kg/m^3], used only to turn coefficients into newtons. If omitted
        and ``number_densities`` is given, it is the sum of n_j m_j.

    Notes
    -----
    The mean molecular mass is number-weighted, m = sum(n_j m_j) / sum(n_j), as in ADBSat's
    ``environment.m``; the speed ratio is s = V / sqrt(2 k_B T_inf / m).
    """

    speed: float
    temperature: float
    number_densities: Mapping[str, float] | None = None
    mean_mass_amu: float | None = None
    density: float | None = None
    _species: tuple = field(init=False, repr=False, compare=False)
    _n: np.ndarray = field(init=False, repr=False, compare=False)
    _m: np.ndarray = field(init=False, repr=False, compare=False)

    def __post_init__(self):
        object.__setattr__(self, "speed", _check_positive("speed", self.speed))
        object.__setattr__(self, "temperature", _check_positive("temperature", self.temperature))
        if (self.number_densities is None) == (self.mean_mass_amu is None):
            raise ValueError("give exactly one of number_densities and mean_mass_amu")
        if self.number_densities is not None:
            names, values = [], []
            for name, value in self.number_densities.items():
                if name not in MOLAR_MASS_G:
                    raise ValueError(
                        f"unknown species {name!r} in number_densities; "
                        f"known species are {', '.join(SPECIES)}"
                    )
                value = float(value)
                if not math.isfinite(value) or value < 0.0:
                    raise ValueError(
                        f"number density of {name} must be finite and >= 0, got {value!r}"
                    )
                names.append(name)
                values.append(value)
            n = np.array(values)
            if not np.any(n > 0):
                raise ValueError("number_densities: at least one species must have n > 0")
            object.__setattr__(self, "number_densities", dict(zip(names, values)))
            object.__setattr__(self, "_species", tuple(names))
            object.__setattr__(self, "_values", tuple(values))
            object.__setattr__(self, "_n", n)
            object.__setattr__(self, "_m", np.array([species_mass_kg(s) for s in names]))
        else:
            _check_positive("mean_mass_amu", self.mean_mass_amu)
            object.__setattr__(self, "_species", ())
            object.__setattr__(self, "_values", ())
            object.__setattr__(self, "_n", np.zeros(0))
            object.__setattr__(self, "_m", np.zeros(0))
        if self.density is not None:
            object.__setattr__(self, "density", _check_positive("density", self.density))

    @classmethod
    def of_mixture(cls, speed, temperature, species: tuple, values, density) -> FreeStream:
        """A free stream from a gas mixture, with checks cheap enough for every message.

        Equal to ``FreeStream(speed, temperature, dict(zip(species, values)), density=density)``
        (the same fields, species order and arrays); the inputs are checked with a few scalar
        comparisons, and anything those do not pass goes to that constructor, which builds it
        or raises its error naming the input.

        Parameters
        ----------
        speed : float
            Relative speed V [m/s], > 0.
        temperature : float
            Gas temperature T_inf [K], > 0.
        species : tuple of str
            Species names from :data:`adbsat_ros.physics.constants.SPECIES`.
        values : sequence of float
            Their number densities [m^-3], >= 0 and not all 0.
        density : float
            Total mass density [kg/m^3], > 0.
        """
        if type(values) is not list:
            values = list(values)
        masses = _species_masses(species) if type(species) is tuple else None
        if not (
            masses is not None
            and len(values) == len(species)
            and type(speed) is float
            and type(temperature) is float
            and type(density) is float
            and 0.0 < speed < math.inf
            and 0.0 < temperature < math.inf
            and 0.0 < density < math.inf
            and 0.0 < sum(values) < math.inf
            and min(values) >= 0.0
            and list(map(type, values)).count(float) == len(values)
        ):
            return cls(
                speed=speed,
                temperature=temperature,
                number_densities=dict(zip(species, values)),
                density=density,
            )
        flow = object.__new__(cls)
        # the fields __post_init__ would set, from values that pass its checks (but the array of
        # number densities, made when first read: see __getattr__)
        flow.__dict__.update(
            {
                "speed": speed,
                "temperature": temperature,
                "number_densities": dict(zip(species, values)),
                "mean_mass_amu": None,
                "density": density,
                "_species": species,
                "_values": tuple(values),
                "_m": masses,
            }
        )
        return flow

    @classmethod
    def _of_checked_mixture(cls, speed, temperature, species, values, density, mean_mass):
        """:meth:`of_mixture` for inputs known to pass its checks (floats; speed, temperature,
        density and the total of ``values`` finite and > 0, ``values`` >= 0), with the mixture's
        :attr:`mean_mass` (as it computes it)."""
        flow = object.__new__(cls)
        flow.__dict__.update(
            {
                "speed": speed,
                "temperature": temperature,
                "number_densities": dict(zip(species, values)),
                "mean_mass_amu": None,
                "density": density,
                "_species": species,
                "_values": values,
                "_m": _species_masses(species),
                "mean_mass": mean_mass,
            }
        )
        return flow

    # ----------------------------------------------------------------------------- derived values
    @property
    def has_species(self) -> bool:
        """True if the composition (species number densities) is known."""
        return bool(self._species)

    @property
    def species(self) -> tuple:
        """Names of the species given, in the order of :attr:`species_number_densities`."""
        return self._species

    @property
    def species_number_densities(self) -> np.ndarray:
        """Number densities n_j [m^-3] of :attr:`species`."""
        return self._n

    @property
    def species_masses(self) -> np.ndarray:
        """Particle masses m_j [kg] of :attr:`species`."""
        return self._m

    @functools.cached_property
    def mean_mass(self) -> float:
        """Number-weighted mean molecular mass [kg] (computed on first access, then kept).

        sum(n_j m_j) / sum(n_j), both summed in the order of :attr:`species` in float arithmetic
        (as :attr:`adbsat_ros.environment.atmosphere.AtmosphereState.mean_mass`, which it equals for the same
        mixture).
        """
        if self._species:
            total = 0.0
            weighted = 0.0
            for name, n in zip(self._species, self._values):
                total += n
                weighted += n * _SPECIES_MASS_KG[name]
            return weighted / total
        return float(self.mean_mass_amu) * AMU

    @property
    def mass_density(self) -> float | None:
        """Mass density [kg/m^3]: ``density`` if given, else sum(n_j m_j), else None."""
        if self.density is not None:
            return self.density
        if self.has_species:
            return float(np.dot(self._n, self._m))
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
        return self.speed / np.sqrt(2.0 * BOLTZMANN * self.temperature / self._m)

    def mass_fractions(self) -> np.ndarray:
        """Mass fractions rho_j / sum(rho_k) of :attr:`species` [-] (they sum to 1)."""
        rho = self._n * self._m
        return rho / rho.sum()

    def dynamic_pressure(self) -> float:
        """q = 0.5 rho V^2 [Pa]; raises ValueError if no density is known."""
        rho = self.mass_density
        if rho is None:
            raise ValueError(
                "no density: give density or number_densities to get forces in newtons"
            )
        return 0.5 * rho * self.speed**2


class _NumberDensityArray:
    """``FreeStream._n`` of a free stream made by :meth:`FreeStream.of_mixture`: the array of its
    number densities, made from the ``_values`` tuple when first read (few models read it), then
    an ordinary instance attribute (a non-data descriptor: the instance's value takes precedence)."""

    def __get__(self, instance, owner=None):
        if instance is None:
            return self
        fields = instance.__dict__
        try:
            values = fields["_values"]
        except KeyError:
            raise AttributeError(
                f"{type(instance).__name__!r} object has no attribute '_n'"
            ) from None
        return fields.setdefault("_n", np.array(values, dtype=float))


FreeStream._n = _NumberDensityArray()
