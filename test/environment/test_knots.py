"""Flight conditions on knots: interpolation between exact evaluations, and the KnotGrid cache."""

import datetime as dt
import math

import numpy as np
import pytest

from adbsat_ros.environment.atmosphere import SpaceWeather, evaluate_atmosphere
from adbsat_ros.environment.circular_orbit import flight_conditions_circular_orbit
from adbsat_ros.environment.flight_conditions import flight_conditions
from adbsat_ros.environment.geodetic import ecef_to_geodetic, geodetic_to_ecef
from adbsat_ros.environment.interpolation import interpolated_flight_conditions
from adbsat_ros.environment.knots import (
    KNOT_LOOKAHEAD,
    KNOT_SNAP_S,
    KNOTS_KEPT,
    KnotGrid,
    knot_position,
)
from adbsat_ros.physics.constants import BOLTZMANN, EARTH_MU
from adbsat_ros.physics.freestream import FreeStream

TIME = dt.datetime(2015, 1, 19, 6, 30)
LAT, LON = math.radians(45.0), math.radians(10.0)
VECTORS = (
    "position_eci",
    "position_ecef",
    "velocity_eci",
    "velocity_ecef",
    "relative_velocity_eci",
    "relative_velocity_ecef",
)


# ------------------------------------------------------------------ interpolated flight conditions
def _orbit_point(rng, radius, radial_speed):
    """A point on a random inclined circular orbit, with a radial velocity added [m, m/s]."""
    theta, inclination = rng.uniform(0.0, 2.0 * math.pi), rng.uniform(0.0, math.pi)
    along = np.array(
        [
            math.cos(theta),
            math.sin(theta) * math.cos(inclination),
            math.sin(theta) * math.sin(inclination),
        ]
    )
    across = np.array(
        [
            -math.sin(theta),
            math.cos(theta) * math.cos(inclination),
            math.cos(theta) * math.sin(inclination),
        ]
    )
    speed = math.sqrt(EARTH_MU / radius)
    return radius * along, speed * across + radial_speed * along


@pytest.mark.parametrize("step, density_rel", [(0.01, 1e-8), (0.1, 1e-6)])
def test_interpolated_conditions_match_the_exact_ones_between_two_knots(step, density_rel):
    """Between exact conditions h seconds apart along a first-order propagated state, linear
    interpolation errs by about (h v / L)^2 / 8 for fields varying over L along the path: at
    350 km (clear of NRLMSISE-00's steps, see the next test), with up to 150 m/s of radial
    speed, the density error is ~2e-9 at 10 ms and ~2e-7 at 100 ms (h^2, as it should)."""
    rng = np.random.default_rng(7)
    weather = SpaceWeather(150.0, 150.0, 4.0)
    start = dt.datetime(2026, 3, 1, tzinfo=dt.timezone.utc)
    for _ in range(60):
        position, velocity = _orbit_point(rng, 6378137.0 + 350e3, rng.uniform(-150.0, 150.0))
        t0 = start + dt.timedelta(seconds=float(rng.uniform(0.0, 86400.0)))
        a = flight_conditions(t0, position, velocity, weather)
        b = flight_conditions(
            t0 + dt.timedelta(seconds=step), position + velocity * step, velocity, weather
        )
        f = float(rng.uniform())
        exact = flight_conditions(
            t0 + dt.timedelta(seconds=f * step), position + velocity * (f * step), velocity, weather
        )
        mixed = interpolated_flight_conditions(a, b, f, exact.time)
        assert mixed.time == exact.time
        assert mixed.mass_density == pytest.approx(exact.mass_density, rel=density_rel)
        assert mixed.temperature == pytest.approx(exact.temperature, rel=density_rel / 10)
        assert mixed.speed_ratio == pytest.approx(exact.speed_ratio, rel=density_rel / 10)
        assert mixed.speed == pytest.approx(exact.speed, rel=1e-10)
        assert mixed.alpha == pytest.approx(exact.alpha, rel=density_rel)
        assert mixed.mean_molecular_mass == pytest.approx(
            exact.mean_molecular_mass, rel=density_rel
        )
        # positions are linear in time; the ECEF ones differ by the exact path's UTC rounding
        # to 1 us
        np.testing.assert_allclose(mixed.position_eci, exact.position_eci, rtol=0, atol=1e-6)
        np.testing.assert_allclose(mixed.position_ecef, exact.position_ecef, rtol=0, atol=2e-3)
        np.testing.assert_allclose(
            mixed.relative_velocity_eci, exact.relative_velocity_eci, rtol=0, atol=1e-9
        )
        assert mixed.altitude == pytest.approx(exact.altitude, abs=0.02)
        assert mixed.latitude == pytest.approx(exact.latitude, abs=1e-8)
        assert math.remainder(mixed.longitude - exact.longitude, 2 * math.pi) == pytest.approx(
            0.0, abs=1e-7
        )
        flow = mixed.free_stream()  # a free stream of the interpolated gas
        assert flow.density == mixed.mass_density and flow.temperature == mixed.temperature


def test_interpolated_conditions_agree_with_themselves_to_the_last_bit():
    """The interpolated fields are consistent with each other bit for bit: the free stream is the
    one FreeStream makes of the interpolated atmosphere, the speed the norm of the mixed ECEF
    relative velocity, the mean mass and speed ratio those of the mixed gas, alpha the linear mix,
    and the same interpolation twice gives the same numbers."""
    rng = np.random.default_rng(11)
    weather = SpaceWeather(150.0, 150.0, 4.0)
    for case in range(12):
        position, velocity = _orbit_point(rng, 6378137.0 + 350e3, rng.uniform(-150.0, 150.0))
        model = ("fixed", "langmuir", "sesam")[case % 3]
        options = dict(
            anomalous_oxygen=bool(case % 2),
            accommodation_model=model,
            accommodation_options={"alpha": 0.9} if model == "fixed" else None,
        )
        a = flight_conditions(TIME, position, velocity, weather, **options)
        b = flight_conditions(
            TIME + dt.timedelta(seconds=0.01),
            position + 0.01 * velocity,
            velocity,
            weather,
            **options,
        )
        f = float(rng.uniform(0.01, 0.99))
        first, second = (interpolated_flight_conditions(a, b, f, TIME) for _ in range(2))
        flow = first.free_stream()
        atmosphere = first.atmosphere
        reference = FreeStream(
            first.speed,
            atmosphere.temperature,
            dict(zip(atmosphere.mixture_species, atmosphere.mixture_densities)),
            density=atmosphere.mass_density,
        )
        for name in (
            "speed",
            "temperature",
            "density",
            "mean_mass",
            "speed_ratio",
            "number_densities",
        ):
            assert getattr(flow, name) == getattr(reference, name), name
        assert flow.species == atmosphere.mixture_species
        assert first.mean_molecular_mass == atmosphere.mean_mass == flow.mean_mass
        assert first.speed == math.hypot(*first.relative_velocity_ecef.tolist())
        assert first.speed_ratio == first.speed / math.sqrt(
            2.0 * BOLTZMANN * atmosphere.temperature / atmosphere.mean_mass
        )
        assert first.alpha == (1.0 - f) * a.alpha + f * b.alpha
        for name in ("He", "O", "AnO"):
            mixed = (1.0 - f) * a.atmosphere.number_densities[name]
            assert (
                atmosphere.number_densities[name] == mixed + f * b.atmosphere.number_densities[name]
            )
        assert (first.latitude, first.longitude, first.altitude) == ecef_to_geodetic(
            first.position_ecef
        )
        for name in VECTORS:
            vector = getattr(first, name)
            assert not vector.flags.writeable
            np.testing.assert_array_equal(vector, getattr(second, name))
        assert repr(second) == repr(first) and second.as_dict() == first.as_dict()


def test_interpolated_conditions_without_a_relative_velocity_mix_the_speed():
    """Conditions that know only a speed (the circular-orbit recipe) have no vectors to mix for
    the wind: the speed is interpolated linearly, the vectors they lack stay None."""
    weather = SpaceWeather(150.0, 150.0, 4.0)
    a = flight_conditions_circular_orbit(TIME, 300e3, LAT, LON, weather)
    b = flight_conditions_circular_orbit(TIME, 301e3, LAT, LON, weather)
    mixed = interpolated_flight_conditions(a, b, 0.25, TIME)
    assert mixed.relative_velocity_eci is None and mixed.velocity_ecef is None
    assert mixed.speed == 0.75 * a.speed + 0.25 * b.speed
    assert mixed.mass_density == 0.75 * a.mass_density + 0.25 * b.mass_density
    assert mixed.free_stream().density == mixed.mass_density


def test_interpolation_takes_the_short_way_round_the_antimeridian():
    weather = SpaceWeather(150.0, 150.0, 4.0)
    r, v = 6378137.0 + 350e3, 7700.0
    position = np.array([-r, 1.0, 0.0])  # just east of -180 deg in ECEF, moving west across it
    velocity = np.array([0.0, -v, 0.0])
    a = flight_conditions(TIME, position, velocity, weather, frame="ecef")
    b = flight_conditions(
        TIME + dt.timedelta(seconds=0.01),
        position + 0.01 * velocity,
        velocity,
        weather,
        frame="ecef",
    )
    assert a.longitude > 3.0 and b.longitude < -3.0  # the two knots on either side of +-180 deg
    exact = flight_conditions(
        TIME + dt.timedelta(seconds=0.005),
        position + 0.005 * velocity,
        velocity,
        weather,
        frame="ecef",
    )
    mixed = interpolated_flight_conditions(a, b, 0.5, exact.time)
    assert abs(mixed.longitude) > 3.14  # not the mean of +pi and -pi, which would be 0
    assert math.remainder(mixed.longitude - exact.longitude, 2 * math.pi) == pytest.approx(
        0.0, abs=1e-9
    )
    assert -math.pi <= mixed.longitude <= math.pi
    assert mixed.mass_density == pytest.approx(exact.mass_density, rel=1e-9)


def test_interpolation_over_a_pole_keeps_the_geodetic_position_exact():
    """Over a pole the latitude turns back and the longitude jumps by 180 deg between two knots:
    the geodetic position comes from the interpolated ECEF position, not from the knots' angles."""
    weather = SpaceWeather(150.0, 150.0, 4.0)
    r, v = 6378137.0 + 350e3, 7700.0
    position = np.array([-30.0, 0.0, r])  # 30 m short of the north pole, moving over it along +x
    velocity = np.array([v, 0.0, 0.0])
    a = flight_conditions(TIME, position, velocity, weather, frame="ecef")
    b = flight_conditions(
        TIME + dt.timedelta(seconds=0.01),
        position + 0.01 * velocity,
        velocity,
        weather,
        frame="ecef",
    )
    assert abs(math.remainder(a.longitude - b.longitude, 2 * math.pi)) == pytest.approx(math.pi)
    for f in (0.1, 0.3, 0.6):
        exact = flight_conditions(
            TIME + dt.timedelta(seconds=0.01 * f),
            position + 0.01 * f * velocity,
            velocity,
            weather,
            frame="ecef",
        )
        mixed = interpolated_flight_conditions(a, b, f, exact.time)
        assert mixed.latitude == pytest.approx(exact.latitude, abs=1e-12)
        assert math.remainder(mixed.longitude - exact.longitude, 2 * math.pi) == pytest.approx(
            0.0, abs=1e-9
        )
        assert mixed.altitude == pytest.approx(exact.altitude, abs=1e-6)


def test_interpolation_ends_are_the_knots_and_mixed_options_are_refused():
    weather = SpaceWeather(150.0, 150.0, 4.0)
    position, velocity = np.array([6378137.0 + 350e3, 0.0, 0.0]), np.array([0.0, 7700.0, 0.0])
    a = flight_conditions(TIME, position, velocity, weather)
    b = flight_conditions(
        TIME + dt.timedelta(seconds=0.01), position + 0.01 * velocity, velocity, weather
    )
    for weight, end in ((0.0, a), (1.0, b)):
        mixed = interpolated_flight_conditions(a, b, weight, end.time)
        assert mixed.mass_density == end.mass_density
        assert mixed.atmosphere.number_densities == end.atmosphere.number_densities
        assert mixed.speed_ratio == pytest.approx(end.speed_ratio, rel=1e-15)
        np.testing.assert_allclose(mixed.position_eci, end.position_eci, rtol=1e-15)
    other = flight_conditions(
        TIME,
        position,
        velocity,
        weather,
        accommodation_model="fixed",
        accommodation_options={"alpha": 0.9},
    )
    with pytest.raises(ValueError, match="different options"):
        interpolated_flight_conditions(a, other, 0.5, TIME)


def test_nrlmsise00_steps_at_300_km_and_interpolation_stays_between_the_knots():
    """NRLMSISE-00 switches some corrections at fixed altitudes: at exactly 300 km its O density
    steps (here by 3e-5 of itself, ten times its change over the same 0.2 m of altitude below), and
    N and H with it. Evaluated at every stamp the wrench steps at that altitude; interpolated
    between knots, the step is spread over the one knot interval that crosses it."""
    weather = SpaceWeather(150.0, 150.0, 4.0)
    below = evaluate_atmosphere(TIME, 299.9999e3, LAT, LON, weather)
    above = evaluate_atmosphere(TIME, 300.0001e3, LAT, LON, weather)
    smooth = evaluate_atmosphere(TIME, 299.9997e3, LAT, LON, weather)  # the trend just below
    trend = below.number_densities["O"] - smooth.number_densities["O"]  # O change per 0.2 m
    step = above.number_densities["O"] - below.number_densities["O"]
    assert abs(step) > 5.0 * abs(trend)  # a step, not the altitude trend
    # a descending state whose knots straddle 300 km
    position = geodetic_to_ecef(LAT, LON, 300.00005e3)  # 5 cm above 300 km
    down = -position / np.linalg.norm(position)
    velocity = 0.1 * down / 0.01  # 10 cm per 10 ms, straight down (ECEF, at rest otherwise)
    a = flight_conditions(TIME, position, velocity, weather, frame="ecef")
    b = flight_conditions(
        TIME + dt.timedelta(seconds=0.01),
        position + 0.01 * velocity,
        velocity,
        weather,
        frame="ecef",
    )
    assert a.altitude > 300e3 > b.altitude
    for f in (0.25, 0.5, 0.75):
        mixed = interpolated_flight_conditions(a, b, f, TIME)
        o = mixed.atmosphere.number_densities["O"]
        assert min(a.atmosphere.number_densities["O"], b.atmosphere.number_densities["O"]) <= o
        assert o <= max(a.atmosphere.number_densities["O"], b.atmosphere.number_densities["O"])


# ---------------------------------------------------------------------------- the KnotGrid cache
WEATHER = SpaceWeather(150.0, 150.0, 4.0)
EPOCH = dt.datetime(2026, 3, 1, tzinfo=dt.timezone.utc)
R_350 = 6378137.0 + 350e3
V_350 = math.sqrt(EARTH_MU / R_350)


class State:
    """An orbital state as the estimator keeps one: stamp [s], ECI position [m], velocity [m/s];
    equal to another with the same numbers."""

    def __init__(self, stamp, position, velocity):
        self.stamp = stamp
        self.position = np.asarray(position, dtype=float)
        self.velocity = np.asarray(velocity, dtype=float)

    def __eq__(self, other):
        if not isinstance(other, State):
            return NotImplemented
        return (
            self.stamp == other.stamp
            and np.array_equal(self.position, other.position)
            and np.array_equal(self.velocity, other.velocity)
        )


def utc(stamp: float) -> dt.datetime:
    return EPOCH + dt.timedelta(seconds=stamp)


def exact(state: State, stamp: float):
    """The flight conditions of ``state`` propagated at constant velocity to ``stamp``."""
    position = state.position + state.velocity * (stamp - state.stamp)
    return flight_conditions(utc(stamp), position, state.velocity, WEATHER)


def circular(stamp: float = 1.0) -> State:
    """A state on an inclined circular orbit at 350 km (clear of NRLMSISE-00's 300 km step)."""
    c, s = math.cos(0.9), math.sin(0.9)
    return State(stamp, [R_350, 0.0, 0.0], [0.0, V_350 * c, V_350 * s])


def numbers(conditions) -> dict:
    """Every number of some conditions (all fields but the time), for exact comparison."""
    values = conditions.as_dict()
    del values["time"]
    return values


def test_knot_position_and_the_snap_rule():
    j, past = knot_position(1.0137, 0.01)
    assert j == 101 and past == pytest.approx(0.0037, abs=1e-12)
    for stamp in (1.02 - 0.5 * KNOT_SNAP_S, 1.02, 1.02 + 0.5 * KNOT_SNAP_S):
        assert knot_position(stamp, 0.01) == (102, 0.0)
    j, past = knot_position(1.02 + 2 * KNOT_SNAP_S, 0.01)
    assert j == 102 and past == pytest.approx(2 * KNOT_SNAP_S, rel=1e-6)
    j, past = knot_position(-0.0137, 0.01)  # stamps before 0: knots at negative j
    assert j == -2 and past == pytest.approx(0.0063, abs=1e-12)


def test_the_grid_interpolates_within_2e_9_of_the_exact_conditions_at_10_ms():
    """Between knots 10 ms apart (77 m of orbit) the interpolated density is within the documented
    ~2e-9 of an exact evaluation at the stamp, the temperature and speed ratio closer still."""
    state = circular()
    grid = KnotGrid(0.01, exact)
    worst = 0.0
    for k in range(1, 200):
        stamp = 1.0 + 0.000503 * k
        interpolated = grid.conditions(state, stamp, utc(stamp))
        reference = exact(state, stamp)
        assert interpolated.time == reference.time
        worst = max(worst, abs(interpolated.mass_density / reference.mass_density - 1.0))
        assert interpolated.temperature == pytest.approx(reference.temperature, rel=1e-10)
        assert interpolated.speed_ratio == pytest.approx(reference.speed_ratio, rel=1e-10)
        assert interpolated.alpha == pytest.approx(reference.alpha, rel=2e-9)
        assert interpolated.altitude == pytest.approx(reference.altitude, abs=2e-3)
        np.testing.assert_allclose(
            interpolated.position_eci, reference.position_eci, rtol=0, atol=1e-6
        )
        np.testing.assert_allclose(
            interpolated.relative_velocity_eci, reference.relative_velocity_eci, rtol=0, atol=1e-8
        )
    assert 1e-12 < worst < 2e-9  # interpolated (not exact), and within the bound
    assert grid.evaluations == grid.misses == 12  # the knots 100 .. 111, each once


def test_stamps_on_knots_take_that_knot_alone():
    state = circular()
    grid = KnotGrid(0.01, exact)
    knot = exact(state, 1.02)
    for stamp in (1.02 - 0.4 * KNOT_SNAP_S, 1.02, 1.02 + 0.4 * KNOT_SNAP_S):
        on_knot = grid.conditions(state, stamp, utc(stamp))
        assert numbers(on_knot) == numbers(knot)  # the knot's own numbers, bit for bit
        assert on_knot.time == utc(stamp)
    assert grid.knot_stamps == (pytest.approx(1.02),) and grid.evaluations == 1
    assert (grid.hits, grid.misses) == (2, 1)


def test_the_grid_keeps_at_most_its_bound_of_knots_and_counts_its_lookups():
    """1 kHz stamps over ten 10 ms intervals: each stamp looks up the two knots around it; a knot
    is evaluated once, when first needed (a miss), and found afterwards (a hit); the grid keeps
    the latest KNOTS_KEPT knots, oldest first."""
    state = circular()
    grid = KnotGrid(0.01, exact)
    stamps = [1.0005 + 0.001 * k for k in range(99)]  # 1.0005 .. 1.0985, never on a knot
    for stamp in stamps:
        grid.conditions(state, stamp, utc(stamp))
        assert len(grid) <= KNOTS_KEPT
    assert grid.misses == grid.evaluations == 11  # knots 100 .. 110
    assert grid.hits == 2 * len(stamps) - grid.misses
    assert grid.knot_stamps == pytest.approx([0.01 * j for j in range(107, 111)])
    assert grid.key is state and grid.prepared_used == 0
    small = KnotGrid(0.01, exact, kept=3)
    for stamp in stamps[:35]:
        small.conditions(state, stamp, utc(stamp))
    assert small.knot_stamps == pytest.approx([1.02, 1.03, 1.04])


def test_a_new_state_is_a_new_key_and_the_numbers_depend_on_the_stamp_and_state_only():
    """Knots belong to one state, compared by value: the same numbers sent again keep them,
    another state evaluates its own and the old ones go. A stamp gets the same numbers whatever
    was asked before, from a fresh grid, and from interpolated_flight_conditions between the
    exact knots."""
    first, second = circular(), circular(stamp=1.0005)
    grid, fresh = KnotGrid(0.01, exact), KnotGrid(0.01, exact)
    for stamp in (1.0013, 1.0042, 1.0311, 1.0522):
        grid.conditions(first, stamp, utc(stamp))
    before = grid.misses
    grid.conditions(circular(), 1.0522, utc(1.0522))  # equal to the first: its knots serve
    assert grid.misses == before and len(grid) == 4
    again = grid.conditions(second, 1.0137, utc(1.0137))
    assert grid.key is second and grid.misses == before + 2 and len(grid) == 2
    lone = fresh.conditions(second, 1.0137, utc(1.0137))
    assert numbers(again) == numbers(lone)
    reference = interpolated_flight_conditions(
        exact(second, 1.01), exact(second, 1.02), (1.0137 - 1.01) / 0.01, utc(1.0137)
    )
    assert numbers(lone) == numbers(reference)
    back = grid.conditions(first, 1.0137, utc(1.0137))  # the first state's knots went: again
    assert grid.key is first and grid.misses == before + 4
    assert numbers(back) != numbers(lone)
    assert numbers(back) == numbers(KnotGrid(0.01, exact).conditions(first, 1.0137, utc(1.0137)))


def test_prepare_evaluates_the_knots_of_a_stamp_then_the_one_after_next():
    state = circular()
    grid = KnotGrid(0.01, exact)
    assert grid.prepare(state, 1.0005)
    assert grid.misses == 2 and grid.knot_stamps == pytest.approx([1.0, 1.01])
    grid.conditions(state, 1.0005, utc(1.0005))
    assert grid.misses == 2 and grid.prepared_used == 1
    assert grid.prepare(state, 1.0015)  # its knots were there: the look-ahead instead
    assert grid.misses == 3 and grid.knot_stamps[-1] == pytest.approx(0.01 * (100 + KNOT_LOOKAHEAD))
    grid.conditions(state, 1.0015, utc(1.0015))
    assert grid.prepared_used == 2
    grid.conditions(state, 1.0107, utc(1.0107))  # the next interval: its far knot is ready
    assert grid.misses == 3 and grid.prepared_used == 2  # and 1.0107 was not prepared
    other = circular(stamp=1.0001)
    grid.conditions(other, 1.0015, utc(1.0015))  # the prepared stamp, but another state
    assert grid.prepared_used == 2
    grid.prepare(other, 1.0125)
    grid.clear()
    assert len(grid) == 0 and grid.key is None
    grid.conditions(other, 1.0125, utc(1.0125))  # cleared: nothing was prepared any more
    assert grid.prepared_used == 2


def test_a_knot_outside_the_atmosphere_model_falls_back_to_the_stamp_itself():
    """20 m below the model's 1000 km ceiling, climbing at 3 km/s: the stamp 5 ms on is inside,
    its far knot 10 m outside; the stamp is evaluated exactly instead of refused, and a stamp
    outside is refused naming the altitude."""
    top = 6378137.0 + 1000e3 - 20.0
    state = State(1.0, [top, 0.0, 0.0], [3000.0, 7000.0, 0.0])
    grid = KnotGrid(0.01, exact)
    conditions = grid.conditions(state, 1.005, utc(1.005))
    assert numbers(conditions) == numbers(exact(state, 1.005))
    assert grid.misses == 2 and grid.evaluations == 2  # knot 100, then the stamp (101 failed)
    assert not grid.prepare(state, 1.006)  # its knots cannot all be evaluated
    with pytest.raises(ValueError, match="altitude"):
        grid.conditions(state, 1.02, utc(1.02))


def test_step_zero_evaluates_every_stamp_exactly_and_keeps_it():
    state = circular()
    grid = KnotGrid(0.0, exact)
    for stamp in (1.0013, 1.0013, 1.0021):
        conditions = grid.conditions(state, stamp, utc(stamp))
        assert numbers(conditions) == numbers(exact(state, stamp))
    assert (grid.hits, grid.misses, grid.evaluations) == (1, 2, 2)
    assert grid.prepare(state, 1.0031) and grid.evaluations == 3
    grid.conditions(state, 1.0031, utc(1.0031))
    assert grid.evaluations == 3 and grid.prepared_used == 1
    for k in range(10):
        grid.conditions(state, 1.01 + k * 1e-3, utc(1.01 + k * 1e-3))
    assert grid.knot_stamps == pytest.approx([1.016, 1.017, 1.018, 1.019])


def test_new_settings_forget_the_knots_and_keep_the_counters():
    state = circular()
    grid = KnotGrid(0.01, exact)
    grid.conditions(state, 1.0013, utc(1.0013))
    grid.configure(0.02, exact)
    assert len(grid) == 0 and grid.step == 0.02 and grid.misses == 2
    grid.conditions(state, 1.0013, utc(1.0013))
    assert grid.misses == 4 and grid.knot_stamps == pytest.approx([1.0, 1.02])


@pytest.mark.parametrize(
    "step, kept, name",
    [(-0.01, 4, "step"), (float("nan"), 4, "step"), (float("inf"), 4, "step"), (0.01, 2, "kept")],
)
def test_bad_grid_settings_are_refused_naming_them(step, kept, name):
    with pytest.raises(ValueError, match=name):
        KnotGrid(step, exact, kept=kept)
    grid = KnotGrid(0.01, exact)
    if name == "step":
        with pytest.raises(ValueError, match="step"):
            grid.configure(step, exact)
        assert grid.step == 0.01  # unchanged


def _same_free_stream(a: FreeStream, b: FreeStream) -> bool:
    return (
        a.speed == b.speed
        and a.temperature == b.temperature
        and dict(a.number_densities) == dict(b.number_densities)
        and a.density == b.density
        and a.mean_mass == b.mean_mass
    )


@pytest.mark.parametrize("anomalous_oxygen", [True, False])
def test_the_conditions_at_a_stamp_are_the_knots_mixed_with_their_free_stream(anomalous_oxygen):
    """KnotGrid.conditions: on a knot its conditions at the stamp's time, between knots the two
    knots around the stamp mixed (interpolated_flight_conditions), bit for bit; their free
    stream has anomalous oxygen iff the atmosphere has it."""

    def evaluate(state, stamp):
        position = state.position + state.velocity * (stamp - state.stamp)
        return flight_conditions(
            utc(stamp), position, state.velocity, WEATHER, anomalous_oxygen=anomalous_oxygen
        )

    state = circular()
    grid = KnotGrid(0.01, evaluate)
    for stamp in (1.0037, 1.0061, 1.01, 1.0243):
        conditions = grid.conditions(state, stamp, utc(stamp))
        j, past = knot_position(stamp, 0.01)
        a, b = evaluate(state, j * 0.01), evaluate(state, (j + 1) * 0.01)
        want = interpolated_flight_conditions(a, b, past / 0.01, utc(stamp))
        assert conditions.time == utc(stamp)
        assert numbers(conditions) == numbers(want)
        assert _same_free_stream(conditions.free_stream(), want.free_stream())
        assert ("AnO" in conditions.free_stream().number_densities) == anomalous_oxygen


def test_a_stamp_at_rest_in_the_air_has_no_free_stream():
    """With the air moving with the satellite (zero relative speed) the conditions at a stamp
    have no relative velocity and refuse a free stream."""
    state = circular()
    grid = KnotGrid(0.01, exact)
    assert grid.conditions(state, 1.0037, utc(1.0037)).free_stream().speed > 0.0  # an orbit

    def at_rest(state, stamp):  # (a geodetic point with no relative velocity)
        return flight_conditions_circular_orbit(utc(stamp), 350e3, LAT, LON, WEATHER, speed=0.0)

    conditions = KnotGrid(0.01, at_rest).conditions(state, 1.0037, utc(1.0037))
    assert conditions.speed == 0.0 and conditions.relative_velocity_eci is None
    with pytest.raises(ValueError, match="relative speed is 0"):
        conditions.free_stream()
