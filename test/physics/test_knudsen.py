"""Mean free path and Knudsen number against the U.S. Standard Atmosphere 1976."""

import datetime as dt
import math

import pytest

from adbsat_ros.environment.atmosphere import SpaceWeather, evaluate_atmosphere
from adbsat_ros.physics.knudsen import COLLISION_DIAMETER, knudsen_number, mean_free_path


def test_the_hard_sphere_mean_free_path():
    """lambda n is a constant, 1 / (sqrt(2) pi sigma^2); Kn scales as 1 / L."""
    for n in (1e14, 1e17, 1e20):
        assert mean_free_path(n) * n == pytest.approx(
            1.0 / (math.sqrt(2.0) * math.pi * COLLISION_DIAMETER**2), rel=1e-15
        )
    assert knudsen_number(1e17, 2.0) == pytest.approx(mean_free_path(1e17) / 2.0, rel=1e-15)
    for bad in (0.0, -1.0, math.nan):
        with pytest.raises(ValueError, match="number_density must be > 0"):
            mean_free_path(bad)
    with pytest.raises(ValueError, match="length must be > 0"):
        knudsen_number(1e17, 0.0)


@pytest.mark.parametrize("altitude_km, ussa_m", [(100.0, 0.142), (150.0, 32.6), (200.0, 240.0)])
def test_the_mean_free_path_of_nrlmsise00_is_that_of_the_standard_atmosphere(altitude_km, ussa_m):
    """With NRLMSISE-00's number density (moderate activity) the mean free path is within a
    factor 1.6 of the U.S. Standard Atmosphere 1976's tabulated one (a different atmosphere
    model, so only the order of magnitude is common)."""
    t = dt.datetime(2025, 3, 1, 12, tzinfo=dt.timezone.utc)
    state = evaluate_atmosphere(t, altitude_km * 1e3, 0.3, 0.0, SpaceWeather(150.0, 150.0, 4.0))
    path = mean_free_path(state.total_number_density)
    assert 1 / 1.6 < path / ussa_m < 1.6
