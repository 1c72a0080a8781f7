"""Choices that change how the gas-surface models are evaluated (not per-material properties)."""

from __future__ import annotations

from dataclasses import dataclass

from adbsat_ros.physics.constants import BOLTZMANN

#: Valid values of :attr:`ModelOptions.incident_temperature`.
INCIDENT_TEMPERATURE_FORMS = ("energy", "kinetic")


@dataclass(frozen=True)
class ModelOptions:
    """Choices that change how models are evaluated (not per-material properties).

    incident_temperature: ``"energy"`` T_i = m V^2 / (4 k_B) (Koppenwallner, ADBSat's code) or
    ``"kinetic"`` T_i = m V^2 / (3 k_B) (Moe), for sentman and dria; they agree when alpha = 1.
    adbsat_compat: reproduce ADBSat's coded behaviour (docs/physics.md, the differences table).
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
