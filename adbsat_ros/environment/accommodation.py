"""Energy accommodation coefficient alpha by model (:data:`ACCOMMODATION_MODELS`), SI units.
``langmuir`` (Pilinski, Argrow & Palo 2010, J. Spacecraft Rockets 47(6)), ``goodman``, ``sesam``
(Pilinski, Argrow, Palo & Bowman 2013, 50(3)); SESAM's Langmuir constants in Torr^-1 as
published. docs/physics.md, sections 5.6 and 5.7."""

from __future__ import annotations

import inspect
import math
from typing import TYPE_CHECKING, Callable, Mapping

from adbsat_ros.physics.constants import AMU, BOLTZMANN, species_mass_kg
from adbsat_ros.validation import finite as _finite
from adbsat_ros.validation import non_negative as _non_negative
from adbsat_ros.validation import positive as _positive

if TYPE_CHECKING:  # (the command line's parser takes the names without the atmosphere model)
    from adbsat_ros.environment.atmosphere import AtmosphereState

#: Pilinski et al. (2010) Langmuir constant K [m^3/K], applied as K n_O T.
LANGMUIR_CONSTANT = 7.50e-17
#: Goodman substrate coefficient K_s default and allowed range [-].
SUBSTRATE_COEFFICIENT = 2.4
SUBSTRATE_COEFFICIENT_RANGE = (2.4, 3.6)
#: Default mass of a surface atom [amu] (Goodman, SESAM).
SURFACE_MASS_AMU = 65.0
#: SESAM constants (Pilinski et al. 2013): adsorption energy [J], transition temperature [K],
#: initial and final Langmuir parameters [Torr^-1].
SESAM_ADSORPTION_ENERGY = 5.7 * 1.602176634e-19
SESAM_TRANSITION_TEMPERATURE = 93.31
SESAM_LANGMUIR_INITIAL = 5e6
SESAM_LANGMUIR_FINAL = 3e4
#: Pascal per Torr.
PASCAL_PER_TORR = 101325.0 / 760.0

_OXYGEN_MASS = species_mass_kg("O")


def _substrate(value) -> float:
    value = _finite("substrate_coefficient", value)
    low, high = SUBSTRATE_COEFFICIENT_RANGE
    if not low <= value <= high:
        raise ValueError(f"substrate_coefficient must be in [{low}, {high}], got {value!r}")
    return value


# ----------------------------------------------------------------------------------- models
def langmuir_accommodation(
    oxygen_number_density: float, temperature: float, langmuir_constant: float = LANGMUIR_CONSTANT
) -> float:
    """Langmuir-isotherm alpha = K n_O T / (1 + K n_O T) in [0, 1) (Pilinski et al. 2010). n_O
    [m^-3] >= 0, T [K] > 0, K [m^3/K] > 0."""
    n_o = _non_negative("oxygen_number_density", oxygen_number_density)
    temperature = _positive("temperature", temperature)
    constant = _positive("langmuir_constant", langmuir_constant)
    x = constant * n_o * temperature
    return x / (1.0 + x)


def goodman_accommodation(
    mean_mass: float,
    substrate_coefficient: float = SUBSTRATE_COEFFICIENT,
    surface_mass_amu: float = SURFACE_MASS_AMU,
) -> float:
    """Goodman's alpha_s = K_s mu / (1 + mu)^2, mu = m_gas / m_surface. ``mean_mass`` [kg] > 0,
    K_s in [2.4, 3.6], ``surface_mass_amu`` [amu] > 0."""
    mean_mass = _positive("mean_mass", mean_mass)
    k_s = _substrate(substrate_coefficient)
    mu = mean_mass / (_positive("surface_mass_amu", surface_mass_amu) * AMU)
    return k_s * mu / (1.0 + mu) ** 2


def sesam_sticking_fraction(incident_energy: float) -> float:
    """SESAM's s_o in [0, 1] at ``incident_energy`` E_r [J] >= 0, in closed form with ``erf``
    (docs/physics.md, section 5.6)."""
    energy = _non_negative("incident_energy", incident_energy)
    w2 = BOLTZMANN * SESAM_TRANSITION_TEMPERATURE
    w = math.sqrt(w2)
    a = math.sqrt(SESAM_ADSORPTION_ENERGY)
    r = math.sqrt(energy)
    tail = math.exp(-energy / w2)
    numerator = r * w * math.sqrt(math.pi) * (math.erf((a - r) / w) + math.erf(r / w)) + w2 * (
        tail - math.exp(-((a - r) ** 2) / w2)
    )
    denominator = r * w * math.sqrt(math.pi) * (1.0 + math.erf(r / w)) + w2 * tail
    return min(1.0, max(0.0, numerator / denominator))


def sesam_oxygen_pressure(oxygen_number_density: float, speed: float, speed_ratio: float) -> float:
    """SESAM's atomic-oxygen pressure P_O [Pa] = 1/2 rho_O V^2 f(s), docs/physics.md section 5.6.
    n_O [m^-3], V [m/s], s [-] >= 0; below s = 1e-3 the leading term of f (its two terms cancel)."""
    n_o = _non_negative("oxygen_number_density", oxygen_number_density)
    speed = _non_negative("speed", speed)
    s = _non_negative("speed_ratio", speed_ratio)
    if speed == 0.0:
        return 0.0
    if s == 0.0:
        raise ValueError("speed_ratio must be > 0 when speed > 0")
    half_rho_v2 = 0.5 * n_o * _OXYGEN_MASS * speed**2
    if s < 1e-3:
        return half_rho_v2 * 16.0 / (3.0 * math.sqrt(math.pi) * s)
    s2 = s * s
    f = (2.0 * s2 + 1.0) * math.exp(-s2) / (math.sqrt(math.pi) * s2 * s) + (
        4.0 * s2 * s2 + 4.0 * s2 - 1.0
    ) * math.erf(s) / (2.0 * s2 * s2)
    return half_rho_v2 * f


def sesam_accommodation(
    oxygen_number_density: float,
    mean_mass: float,
    speed: float,
    speed_ratio: float,
    substrate_coefficient: float = SUBSTRATE_COEFFICIENT,
    surface_mass_amu: float = SURFACE_MASS_AMU,
) -> float:
    """SESAM alpha = (1 - theta) alpha_s + theta (Pilinski et al. 2013). n_O [m^-3],
    ``mean_mass`` [kg], ``speed`` V [m/s] >= 0, ``speed_ratio`` s [-]."""
    clean = goodman_accommodation(mean_mass, substrate_coefficient, surface_mass_amu)
    pressure_pa = sesam_oxygen_pressure(oxygen_number_density, speed, speed_ratio)
    pressure_torr = pressure_pa / PASCAL_PER_TORR
    sticking = sesam_sticking_fraction(0.5 * _OXYGEN_MASS * speed**2)
    langmuir = sticking * SESAM_LANGMUIR_INITIAL + SESAM_LANGMUIR_FINAL
    coverage = langmuir * pressure_torr / (1.0 + langmuir * pressure_torr)
    return (1.0 - coverage) * clean + coverage


# --------------------------------------------------------------------------------- registry
def _fixed(atmosphere: AtmosphereState, speed: float, alpha=None) -> float:
    if alpha is None:
        raise ValueError("accommodation model 'fixed' needs alpha (a number in [0, 1])")
    alpha = _finite("alpha", alpha)
    if not 0.0 <= alpha <= 1.0:
        raise ValueError(f"alpha must be in [0, 1], got {alpha!r}")
    return alpha


def _langmuir(
    atmosphere: AtmosphereState, speed: float, langmuir_constant=LANGMUIR_CONSTANT
) -> float:
    return langmuir_accommodation(
        atmosphere.number_densities["O"], atmosphere.temperature, langmuir_constant
    )


def _goodman(
    atmosphere: AtmosphereState,
    speed: float,
    substrate_coefficient=SUBSTRATE_COEFFICIENT,
    surface_mass_amu=SURFACE_MASS_AMU,
) -> float:
    return goodman_accommodation(atmosphere.mean_mass, substrate_coefficient, surface_mass_amu)


def _sesam(
    atmosphere: AtmosphereState,
    speed: float,
    substrate_coefficient=SUBSTRATE_COEFFICIENT,
    surface_mass_amu=SURFACE_MASS_AMU,
) -> float:
    mean_mass = atmosphere.mean_mass
    thermal_speed = math.sqrt(2.0 * BOLTZMANN * atmosphere.temperature / mean_mass)
    return sesam_accommodation(
        atmosphere.number_densities["O"],
        mean_mass,
        speed,
        speed / thermal_speed,
        substrate_coefficient,
        surface_mass_amu,
    )


#: Accommodation models by name: callables ``(atmosphere, speed, **options) -> alpha``.
ACCOMMODATION_MODELS: Mapping[str, Callable[..., float]] = {
    "fixed": _fixed,
    "langmuir": _langmuir,
    "goodman": _goodman,
    "sesam": _sesam,
}

#: Options each model accepts: its function's arguments after the atmosphere and speed.
ACCOMMODATION_OPTIONS: Mapping[str, tuple] = {
    name: tuple(inspect.signature(model).parameters)[2:]
    for name, model in ACCOMMODATION_MODELS.items()
}


def accommodation_model_names() -> tuple:
    """Names accepted by :func:`accommodation` (lower case; matching is case-insensitive)."""
    return tuple(ACCOMMODATION_MODELS)


def normalize_model_name(name) -> str:
    """Lower-cased model name, or ValueError naming the allowed names."""
    key = str(name).strip().lower()
    if key not in ACCOMMODATION_MODELS:
        raise ValueError(
            f"unknown accommodation model {name!r}; allowed: {', '.join(ACCOMMODATION_MODELS)}"
        )
    return key


def accommodation(name: str, atmosphere: AtmosphereState, speed: float, **options) -> float:
    """Energy accommodation coefficient alpha in [0, 1] of the model ``name`` (case-insensitive).
    speed: relative to the atmosphere [m/s], >= 0 (SESAM only).
    options: :data:`ACCOMMODATION_OPTIONS` (``langmuir_constant`` [m^3/K]).
    ValueError: an unknown model or option (listing the allowed), or an invalid value."""
    from adbsat_ros.environment.atmosphere import AtmosphereState

    key = normalize_model_name(name)
    if not isinstance(atmosphere, AtmosphereState):
        raise ValueError(f"atmosphere must be an AtmosphereState, got {type(atmosphere).__name__}")
    return accommodation_of(key, atmosphere, _non_negative("speed", speed), options)


def checked_options(key: str, options: Mapping) -> dict:
    """The options of model ``key`` as a dict; ValueError for one it does not take."""
    allowed = ACCOMMODATION_OPTIONS[key]
    unexpected = sorted(set(options) - set(allowed))
    if unexpected:
        raise ValueError(
            f"accommodation model {key!r} does not take {', '.join(unexpected)}; "
            f"its options are: {', '.join(allowed) or 'none'}"
        )
    return dict(options)


def accommodation_of(
    key: str, atmosphere: AtmosphereState, speed: float, options: Mapping
) -> float:
    """:func:`accommodation` for a normalised name, inputs checked."""
    return ACCOMMODATION_MODELS[key](atmosphere, speed, **checked_options(key, options))
