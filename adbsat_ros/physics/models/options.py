"""Choices that change how the gas-surface models are evaluated (not per-material properties)."""

from __future__ import annotations

from dataclasses import dataclass

from adbsat_ros.physics.constants import BOLTZMANN

#: Valid values of :attr:`ModelOptions.incident_temperature`.
INCIDENT_TEMPERATURE_FORMS = ("energy", "kinetic")


@dataclass(frozen=True)
class ModelOptions:
    """Choices that change how models are evaluated (not per-material properties).

    Parameters
    ----------
    incident_temperature : {"energy", "kinetic"}
        Incident temperature used by sentman and dria for the re-emission temperature:
        "energy" is T_i = m V^2 / (4 k_B) (Koppenwallner, ADBSat's code), "kinetic" is
        T_i = m V^2 / (3 k_B) (Moe). They agree when alpha = 1.
    adbsat_compat : bool
        Reproduce ADBSat's coded behaviour where it differs from the physics: maxwell uses the
        two-sided flat-plate formula (zeroed for back faces) instead of a one-sided surface; cll
        weights species by M_j n_j^2 instead of mass fraction and uses its fit only if every
        panel has alpha_n < 1; dria divides by the given total density instead of normalising
        the mass fractions.

    Raises
    ------
    ValueError
        For an ``incident_temperature`` not in :data:`INCIDENT_TEMPERATURE_FORMS`.
    """

    incident_temperature: str = "energy"
    adbsat_compat: bool = False

    def __post_init__(self):
        if self.incident_temperature not in INCIDENT_TEMPERATURE_FORMS:
            raise ValueError(
                f"incident_temperature must be one of {', '.join(INCIDENT_TEMPERATURE_FORMS)}, "
                f"got {self.incident_temperature!r}"
            )

    def incident_temperature_of(self, particle_mass, speed):
        """Incident temperature T_i [K] of particles of mass [kg] at speed [m/s]."""
        divisor = 4.0 if self.incident_temperature == "energy" else 3.0
        return particle_mass * speed**2 / (divisor * BOLTZMANN)
