"""The valid range of every number parameter of the node, with the reason for it.

Physical quantities take theirs from :data:`adbsat_ros.bounds.BOUNDS`; the node's parameter
descriptors, config/adbsat.yaml and the settings' checks all read :data:`PARAMETER_RANGES`.
"""

from __future__ import annotations

from adbsat_ros.bounds import BOUNDS, Bound

#: Largest conditions_step [s]: 770 m of orbit, interpolation error still below about 1e-7.
MAX_CONDITIONS_STEP = 0.1

_REFLECTIVITY = (
    "a fraction of the incident sunlight: 0 absorbed, 1 all reflected (the specular and diffuse "
    "fractions together at most 1)"
)
_ACCOMMODATION = "an accommodation coefficient: 0 none (specular reflection), 1 full (diffuse)"
_DAY = "a day: a longer time is no longer about the live stream"

#: The valid range of every number parameter (of each element of a list of numbers), with its
#: reason; physical quantities take theirs from :data:`adbsat_ros.bounds.BOUNDS`.
PARAMETER_RANGES = {
    "mesh_scale": Bound(
        1e-6,
        1_000.0,
        "",
        "metres per file unit: 1e-6 for micrometres, 1e-3 for millimetres, 0.0254 for inches, "
        "1000 for kilometres",
    ),
    "center_of_mass": BOUNDS["offset"],
    "mass": Bound(
        0.0, 1e6, "kg", "a satellite's mass: the ISS is 420 t; 0 turns the acceleration off"
    ),
    "inertia": Bound(
        -1e9,
        1e9,
        "kg m^2",
        "each element of the tensor: the ISS's largest moment of inertia is about 1e8 kg m^2",
    ),
    "alpha": Bound(0.0, 1.0, "", _ACCOMMODATION),
    "alpha_n": Bound(0.0, 1.0, "", _ACCOMMODATION),
    "sigma_n": Bound(
        0.0,
        2.0,
        "",
        "normal momentum accommodation (p_i - p_r) / (p_i - p_w): 0 specular, 1 diffuse at the "
        "wall temperature; at 2 the re-emitted molecules would push into the wall",
        high_open=True,
    ),
    "sigma_t": Bound(0.0, 1.0, "", _ACCOMMODATION),
    "specular_reflectivity": Bound(0.0, 1.0, "", _REFLECTIVITY),
    "diffuse_reflectivity": Bound(0.0, 1.0, "", _REFLECTIVITY),
    "wall_temperature": BOUNDS["wall_temperature"],
    "shading_samples": Bound(
        1.0,
        4096.0,
        "",
        "rays per panel: 16 give a panel's lit fraction within about 0.03; 4096 (64 x 64) is as "
        "fine as the projection method's grids",
    ),
    "shading_cache_resolution_deg": Bound(
        1e-3,
        10.0,
        "deg",
        "cells finer than 0.001 deg (3.6 arcsec) are below any attitude sensor's accuracy; "
        "coarser than 10 deg they would share one lighting between flows far apart",
    ),
    "shading_cache_size": Bound(
        1.0,
        1e6,
        "",
        "flow directions kept: 660,000 cells of 0.25 deg cover the whole sphere",
    ),
    "f107": BOUNDS["f107"],
    "joint_state_timeout": Bound(0.0, 86_400.0, "s", _DAY, low_open=True),
    "joint_shading_resolution_deg": Bound(
        1e-3,
        10.0,
        "deg",
        "as shading_cache_resolution_deg: a joint turned by d moves its parts' shadows as a "
        "flow turned by d does",
    ),
    "joint_shading_resolution_m": Bound(
        1e-6,
        1.0,
        "m",
        "a micrometre (below any actuator's accuracy) to a metre",
    ),
    "joint_shading_cache_size": Bound(
        1.0, 1e5, "", "configurations kept, each with its own cache of flow directions"
    ),
    "f107a": BOUNDS["f107"],
    "ap": BOUNDS["ap"],
    "ap_history": BOUNDS["ap"],
    "wind_ecef": BOUNDS["wind"],
    "state_timeout": Bound(0.0, 86_400.0, "s", _DAY, low_open=True),
    "min_altitude": Bound(0.0, 1e6, "m", "NRLMSISE-00's altitudes: from the ground to 1,000 km"),
    "knudsen_warning": Bound(
        0.0,
        1e6,
        "",
        "a Knudsen number: the flow is free-molecular above about 10; a threshold of 1e6 would "
        "warn about every satellite",
        low_open=True,
    ),
    "time_jump_reset": Bound(0.0, 86_400.0, "s", _DAY, low_open=True),
    "conditions_step": Bound(
        0.0,
        MAX_CONDITIONS_STEP,
        "s",
        "0.1 s is 770 m of orbit, the interpolation error still below about 1e-7; 0 evaluates "
        "at every stamp",
    ),
    "max_quaternion_norm_error": Bound(
        0.0, 0.5, "", "a quaternion's norm off 1 by half is no rotation to normalise"
    ),
    "min_relative_speed": Bound(
        0.0, BOUNDS["speed"].high, "m/s", "at most the largest speed relative to the gas"
    ),
    "qos_depth": Bound(1.0, 10_000.0, "", "messages kept per topic: 10 s at 1 kHz"),
    "marker_period": Bound(
        0.1,
        3_600.0,
        "s",
        "from 10 Hz (each picture takes tens of milliseconds to build) to once an hour",
    ),
    "diagnostics_period": Bound(
        0.01,
        3_600.0,
        "s",
        "from 100 Hz (faster, the reports would load the node they watch) to once an hour",
    ),
}
#: Number parameters that take whole numbers only.
WHOLE_NUMBER_PARAMETERS = (
    "shading_samples",
    "shading_cache_size",
    "joint_shading_cache_size",
    "qos_depth",
)
