"""``adbsat-ros atmosphere``: JSON fields in SI units, readable table, one-line errors (exit 2)."""

import json
import math
import os
import subprocess
import sys

import pytest

from adbsat_ros import cli

PAPER = ["--time", "2015-01-19T00:00:00Z", "--f107", "121.7", "--f107a", "138.1", "--ap", "4"]
POINT = ["--altitude", "400", "--lat", "0", "--lon", "0"]


def run(argv, capsys):
    """Run the real ``adbsat-ros`` main.

    Returns (exit status, stdout, stderr). argparse errors raise SystemExit; both paths count.
    """
    try:
        status = cli.main(["atmosphere", *argv])
    except SystemExit as exc:
        status = exc.code
    out, err = capsys.readouterr()
    return status, out, err


def test_json_keys_name_their_units_and_agree_with_the_table(capsys):
    status, out, err = run(
        [*PAPER, "--altitude", "400", "--lat", "10", "--lon", "20", "--json"], capsys
    )
    assert status == 0, err
    data = json.loads(out)
    assert set(data) == {
        "time",
        "latitude_deg",
        "longitude_deg",
        "altitude_m",
        "position_eci_m",
        "position_ecef_m",
        "velocity_eci_m_s",
        "velocity_ecef_m_s",
        "space_weather",
        "anomalous_oxygen",
        "number_densities_per_m3",
        "density_kg_m3",
        "exospheric_temperature_K",
        "temperature_K",
        "mean_molecular_mass_kg",
        "earth_rotation",
        "relative_velocity_eci_m_s",
        "relative_velocity_ecef_m_s",
        "relative_speed_m_s",
        "speed_ratio",
        "accommodation_model",
        "accommodation_coefficient",
    }
    assert data["altitude_m"] == pytest.approx(400e3)  # m, not km
    assert data["latitude_deg"] == pytest.approx(10.0) and data["longitude_deg"] == 20.0  # deg
    assert math.dist(data["position_ecef_m"], (0, 0, 0)) == pytest.approx(6.77e6, rel=2e-3)
    densities = data["number_densities_per_m3"]
    assert set(densities) == {"He", "O", "N2", "O2", "Ar", "H", "N", "AnO"}
    assert 1e13 < densities["O"] < 1e15  # m^-3 at 400 km (cm^-3 would be 1e6 less)
    assert 1e-13 < data["density_kg_m3"] < 1e-11
    # circular-orbit speed sqrt(mu / (R_E + h)) at 400 km above the ellipsoid at 10 deg
    assert 7660 < data["relative_speed_m_s"] < 7680
    assert data["relative_velocity_eci_m_s"] is None
    assert data["accommodation_model"] == "langmuir"
    assert data["anomalous_oxygen"] is True
    assert data["space_weather"]["f107_sfu"] == 121.7
    status, table, err = run([*PAPER, "--altitude", "400", "--lat", "10", "--lon", "20"], capsys)
    assert status == 0, err
    assert f"{data['density_kg_m3']:.6e} kg/m^3" in table


def test_state_in_ecef_at_rest_gives_zero_speed(capsys):
    argv = [*PAPER, "--position", "6778137,0,0", "--velocity", "0,0,0", "--frame", "ecef", "--json"]
    status, out, err = run(argv, capsys)
    assert status == 0, err
    data = json.loads(out)
    assert data["relative_speed_m_s"] == 0.0 and data["relative_velocity_ecef_m_s"] == [
        0.0,
        0.0,
        0.0,
    ]
    assert data["altitude_m"] == pytest.approx(400e3, abs=1e-6)


def test_state_in_eci_and_options(capsys):
    argv = [
        *PAPER,
        "--position",
        "6778137,0,0",
        "--velocity",
        "0,7668.6,0",
        "--json",
        "--accommodation",
        "fixed",
        "--alpha",
        "0.9",
        "--no-anomalous-oxygen",
        "--wind",
        "0,50,0",
    ]
    status, out, err = run(argv, capsys)
    assert status == 0, err
    data = json.loads(out)
    assert data["accommodation_coefficient"] == 0.9
    assert data["anomalous_oxygen"] is False
    speed = math.sqrt(sum(v * v for v in data["relative_velocity_eci_m_s"]))
    assert data["relative_speed_m_s"] == pytest.approx(speed, rel=1e-12)
    assert (
        7000 < data["relative_speed_m_s"] < 7300
    )  # co-rotating air takes ~480 m/s off a prograde orbit


def test_table_output(capsys):
    status, out, err = run([*PAPER, *POINT, "--accommodation", "SESAM"], capsys)
    assert status == 0, err
    assert "alpha (sesam)" in out and "kg/m^3" in out and "m^-3" in out
    assert "{" not in out


@pytest.mark.parametrize(
    "argv, option",
    [
        ([*PAPER, "--altitude", "1200", "--lat", "0", "--lon", "0"], "--altitude"),
        ([*PAPER, "--altitude", "-1", "--lat", "0", "--lon", "0"], "--altitude"),
        ([*PAPER, "--altitude", "nan", "--lat", "0", "--lon", "0"], "--altitude"),
        ([*PAPER, "--altitude", "400", "--lat", "91", "--lon", "0"], "--lat"),
        ([*PAPER, "--altitude", "400", "--lat", "0"], "--lon"),
        ([*PAPER, "--altitude", "400", "--lat", "0", "--lon", "x"], "--lon"),
        ([*PAPER, "--position", "1,2"], "--position"),
        ([*PAPER, "--position", "3e7,0,0"], "--position"),
        ([*PAPER, "--position", "7e6,0,0", "--altitude", "400"], "--position"),
        ([*PAPER, "--position", "7e6,0,0", "--velocity", "0,inf,0"], "--velocity"),
        ([*PAPER, *POINT, "--velocity", "0,7000,0"], "--velocity"),
        ([*PAPER, *POINT, "--frame", "ecef"], "--frame"),
        ([*PAPER, "--position", "7e6,0,0", "--frame", "j2000"], "--frame"),
        ([*PAPER, *POINT, "--accommodation", "cll"], "--accommodation"),
        ([*PAPER, *POINT, "--accommodation", "fixed"], "--alpha"),
        ([*PAPER, *POINT, "--accommodation", "fixed", "--alpha", "1.2"], "--alpha"),
        ([*PAPER, *POINT, "--alpha", "0.5"], "--alpha"),
        ([*PAPER, *POINT, "--f107", "-1"], "--f107"),
        ([*PAPER, *POINT, "--f107a", "nan"], "--f107a"),
        ([*PAPER, *POINT, "--ap", "-3"], "--ap"),
        ([*PAPER, *POINT, "--ap-history", "1,2,3"], "--ap-history"),
        (["--time", "yesterday", *POINT], "--time"),
        (["--time", "1957-12-31T00:00:00", *POINT], "--time"),
        (["--time", "2101-01-01", *POINT], "--time"),
        ([*POINT], "--time"),
    ],
)
def test_bad_values_exit_2_with_one_line_naming_the_option(argv, option, capsys):
    status, out, err = run(argv, capsys)
    assert status == 2
    assert out == ""
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert option in lines[0]
    assert "Traceback" not in err


def test_console_entry_point_runs():
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    result = subprocess.run(
        [sys.executable, "-m", "adbsat_ros.cli", "atmosphere", *PAPER, *POINT, "--json"],
        cwd=root,
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert result.returncode == 0, result.stderr
    assert json.loads(result.stdout)["altitude_m"] == pytest.approx(400e3)


def test_what_nrlmsise00_prints_goes_to_stderr_not_into_the_json(monkeypatch, capfd):
    """NRLMSISE-00's C code prints "dnet log error" lines for space weather far beyond its
    fit. With the range of F10.7 widened to reach it, those lines land on stderr and stdout
    stays one JSON document."""
    from adbsat_ros.bounds import BOUNDS, Bound

    wide = Bound(0.0, 1e5, "sfu", BOUNDS["f107"].reason)
    monkeypatch.setitem(BOUNDS, "f107", wide)
    argv = ["atmosphere", "--time", "2025-03-01T00:00:00", "--altitude", "300", "--lat", "0"]
    argv += ["--lon", "0", "--f107", "20000", "--f107a", "20000", "--json"]
    try:
        code = cli.main(argv)
    except SystemExit as exc:  # (a non-finite number refused)
        code = exc.code
    out, err = capfd.readouterr()
    assert "dnet" in err and "dnet" not in out
    if code == 0:
        assert json.loads(out)["space_weather"]["f107_sfu"] == 20000.0
    else:
        assert out == "" and "Traceback" not in err


def test_historical_space_weather_and_msis21_show_the_indices_in_force(capsys):
    import datetime as dt

    from adbsat_ros.environment.space_weather import HistoricalWeather

    when = ["--time", "2015-01-19T00:00:00Z", "--space-weather", "historical"]
    status, out, err = run([*when, *POINT, "--atmosphere-model", "msis2.1", "--json"], capsys)
    assert status == 0, err
    expected = HistoricalWeather().at(dt.datetime(2015, 1, 19))
    weather = json.loads(out)["space_weather"]
    assert (weather["f107_sfu"], weather["f107a_sfu"], weather["ap"]) == (
        expected.f107,
        expected.f107a,
        expected.ap,
    )
    assert weather["ap_history"] == list(expected.ap_history)
    status, out, err = run([*when, *POINT], capsys)
    assert status == 0 and f"{expected.f107:g} sfu, {expected.f107a:g} sfu" in out
    status, out, err = run(["--time", "2090-01-01T00:00:00Z", *when[2:], *POINT], capsys)
    assert status == 2 and "2090-01-01T00:00:00 is outside the space-weather record" in err
    assert len(err.strip().splitlines()) == 1
