"""The registry of gas-surface interaction models: names, parameters, options.

Every model maps the panel incidence to a pressure coefficient c_p (positive = compressive, along
-n) and a shear coefficient c_tau (along the tangential part of the flow), both normalised by the
free-stream dynamic pressure q = 0.5 rho V^2. The force on panel i is q A_i (c_tau t - c_p n).

A model is a function ``model(c, sigma, surface, flow, options) -> (c_p, c_tau)`` of
``c = cos(delta)`` and ``sigma = sin(delta)``, where delta is the angle between the inward normal
-n and the flow direction (delta = 0: facing the flow; delta > 90 deg: facing away). They may
have any shape (e.g. (N,) panels or (M, N) attitudes x panels); surface parameters
(:class:`~adbsat_ros.physics.surface.PanelSurface`) are floats or (N,) arrays and broadcast
against them; ``flow`` is a :class:`~adbsat_ros.physics.freestream.FreeStream`, ``options`` a
:class:`ModelOptions`.

The formulas, with their sources, are in the family modules of :mod:`adbsat_ros.physics.models`:

* hyperthermal: newton, cook (Cook 1965), storch (Storch 2002);
* diffuse: sentman (Sentman 1961), schaaf (Schaaf & Chambre 1961), dria (Sentman per species);
* maxwell: the specular/diffuse mixture (diffuse fraction alpha);
* cll: Cercignani-Lampis-Lord per species with the Walker et al. (2014) fits.

The temperature of the incident molecules T_i in sentman and dria (Sentman's energy
accommodation) is Koppenwallner's energy-flux form m V^2 / (4 k_B) by default (ADBSat's choice),
or Moe's kinetic form m V^2 / (3 k_B) with ``ModelOptions(incident_temperature="kinetic")``.
"""

from __future__ import annotations

from adbsat_ros.physics.models.cll import CLL_SPECIES, cll
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
from adbsat_ros.physics.models.options import INCIDENT_TEMPERATURE_FORMS, ModelOptions

__all__ = [
    "CLL_SPECIES",
    "INCIDENT_TEMPERATURE_FORMS",
    "MODELS",
    "MODEL_PARAMETERS",
    "SPECIES_MODELS",
    "SPLIT_MODELS",
    "ModelOptions",
    "canonical_model_name",
    "cll",
    "cook",
    "dria",
    "get_model",
    "maxwell",
    "newton",
    "schaaf",
    "sentman",
    "storch",
]

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

#: Models whose (c_p, c_tau) are an elementwise function of c = cos(delta) and a few parameters of
#: the surface and the flow, with c_tau proportional to sin(delta):
#: name -> (parameters(surface, flow, options), plate(c, *parameters) -> (c_p, c_tau / sin(delta))).
#: The model itself is ``c_p, q = plate(c, *parameters(...)); c_tau = q sin(delta)``, so a caller
#: that needs only c_tau / sin(delta) (the facet force along u + c n, PanelMethod) need not form
#: sin(delta) at all. A ``parameters`` that returns None means the split does not apply to these
#: options.
SPLIT_MODELS = {
    "sentman": (sentman_parameters, sentman_plate),
    "schaaf": (schaaf_parameters, schaaf_plate),
    "maxwell": (maxwell_parameters, schaaf_plate),
}

#: Which surface parameters each model reads (for documentation and parameter checks).
MODEL_PARAMETERS = {
    "newton": (),
    "sentman": ("alpha", "wall_temperature"),
    "cook": ("alpha", "wall_temperature"),
    "schaaf": ("sigma_n", "sigma_t", "wall_temperature"),
    "cll": ("alpha_n", "sigma_t", "wall_temperature"),
    "storch": ("sigma_n", "sigma_t", "wall_temperature"),
    "dria": ("alpha", "wall_temperature"),
    "maxwell": ("alpha", "wall_temperature"),
}

#: Models that need the species composition of the gas.
SPECIES_MODELS = ("cll", "dria")


def get_model(name: str):
    """The model function called ``name`` (case-insensitive; ``storchHyp`` = ``storch``).

    Raises
    ------
    ValueError
        For an unknown name, listing the known ones.
    """
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
