"""The registry of gas-surface interaction models: names, parameters, options.

``model(c, sigma, surface, flow, options) -> (c_p, c_tau)``, c = cos(delta), sigma = sin(delta),
per q = 0.5 rho V^2; panel i's force is q A_i (c_tau t - c_p n). Formulas: docs/physics.md, sec. 3.
"""

from __future__ import annotations

from adbsat_ros.physics.models.cll import cll
from adbsat_ros.physics.models.diffuse import (
    dria,
    schaaf,
    schaaf_parameters,
    schaaf_plate,
    sentman,
    sentman_parameters,
    sentman_plate,
)
from adbsat_ros.physics.models.hyperthermal import cook, newton, storch
from adbsat_ros.physics.models.maxwell import maxwell, maxwell_parameters
from adbsat_ros.physics.models.options import INCIDENT_TEMPERATURE_FORMS, ModelOptions  # noqa: F401

#: Model name -> function(c, sigma, surface, flow, options) -> (c_p, c_tau).
MODELS = {
    "newton": newton,
    "sentman": sentman,
    "cook": cook,
    "schaaf": schaaf,
    "cll": cll,
    "storch": storch,
    "dria": dria,
    "maxwell": maxwell,
}

#: Models with c_tau proportional to sin(delta), split as
#: name -> (parameters(surface, flow, options), plate(c, *parameters) -> (c_p, c_tau / sin(delta))):
#: the model is ``c_p, q = plate(c, *parameters(...)); c_tau = q sin(delta)``, so the facet force
#: needs no sin(delta). ``parameters`` returning None: the split does not apply to these options.
SPLIT_MODELS = {
    "sentman": (sentman_parameters, sentman_plate),
    "schaaf": (schaaf_parameters, schaaf_plate),
    "maxwell": (maxwell_parameters, schaaf_plate),
}

#: Models that need the species composition of the gas.
SPECIES_MODELS = ("cll", "dria")


def get_model(name: str):
    """The model called ``name`` (case-insensitive; ``storchHyp`` = ``storch``); ValueError if
    unknown."""
    key = str(name).lower()
    if key == "storchhyp":
        key = "storch"
    if key == "schaaf_chambre":
        key = "schaaf"
    try:
        return MODELS[key]
    except KeyError:
        raise ValueError(
            f"unknown gas-surface model {name!r}; choose from {', '.join(MODELS)}"
        ) from None


def canonical_model_name(name: str) -> str:
    """The registry key for ``name`` (validates it)."""
    fn = get_model(name)
    return next(k for k, v in MODELS.items() if v is fn)
