"""Physical constants and species data, SI. The set follows ADBSat's ``environment.m`` so that
numbers compare; where CODATA 2018 differs (k_B), by under 1e-6 relative."""

from __future__ import annotations

#: Boltzmann constant [J/K] (ADBSat's value).
BOLTZMANN = 1.3806503e-23
#: Avogadro constant [1/mol].
AVOGADRO = 6.02214076e23
#: Atomic mass unit [kg] (CODATA 2018).
AMU = 1.66053906660e-27
#: Earth's gravitational parameter [m^3/s^2] (WGS-84 / EGM, as ADBSat).
EARTH_MU = 3.986004418e14
#: Earth's equatorial radius [m] as used by ADBSat for the circular-orbit speed.
EARTH_RADIUS_ADBSAT = 6.37813649e6

#: Species of the NRLMSISE-00 output that the gas-surface models know, in ADBSat's order.
SPECIES = ("He", "O", "N2", "O2", "Ar", "H", "N", "AnO")

#: Molar masses [g/mol] (ADBSat's values; anomalous oxygen "AnO" is atomic oxygen).
MOLAR_MASS_G = {
    "He": 4.002602,
    "O": 15.9994,
    "N2": 28.0134,
    "O2": 31.9988,
    "Ar": 39.948,
    "H": 1.0079,
    "N": 14.0067,
    "AnO": 15.99,
}


def species_mass_kg(name: str) -> float:
    """Mass of one particle of species ``name`` [kg]; KeyError naming the allowed species."""
    try:
        molar = MOLAR_MASS_G[name]
    except KeyError:
        raise KeyError(
            f"unknown species {name!r}; known species are {', '.join(SPECIES)}"
        ) from None
    return molar / (1000.0 * AVOGADRO)
