"""The node with ``space_weather: historical``: /diagnostics carries the indices of the stamp's
date from CelesTrak's record, on the demo's orbit and date."""

import pytest

pytestmark = pytest.mark.ros
pytest.importorskip("rclpy")

import datetime as dt

from rclpy.parameter import Parameter
from ros_harness import circular_orbit_state, node_and_peer

from adbsat_ros.environment.space_weather import HistoricalWeather
from adbsat_ros.ros.demo import ALTITUDE_KM, EPOCH_UTC


def test_historical_space_weather_reaches_diagnostics_with_the_demos_date():
    epoch = EPOCH_UTC.rstrip("Z")
    overrides = [
        Parameter("mesh", value="cylinder"),
        Parameter("shading", value="none"),
        Parameter("time_mode", value="epoch"),
        Parameter("epoch_utc", value=epoch),
        Parameter("space_weather", value="historical"),
        Parameter("atmosphere_model", value="msis2.1"),
        Parameter("diagnostics_period", value=0.2),
    ]
    expected = HistoricalWeather().at(dt.datetime.fromisoformat(epoch) + dt.timedelta(seconds=1))
    with node_and_peer(overrides) as (node, peer):
        pos, vel = circular_orbit_state(ALTITUDE_KM * 1e3)
        peer.send_state(0.0, pos, vel)
        peer.spin_for(0.05)
        peer.send_attitude(1.0, (0.0, 0.0, 0.0, 1.0))
        assert peer.spin_until(lambda: len(peer.wrenches) == 1)

        def reported():
            for array in peer.diagnostics:
                for status in array.status:
                    values = {kv.key: kv.value for kv in status.values}
                    if "f107" in values:
                        return values
            return None

        assert peer.spin_until(lambda: reported() is not None)
        values = reported()
    assert values["space_weather"] == "historical"
    assert values["atmosphere_model"] == "msis2.1"
    for key in ("f107", "f107a", "ap"):
        assert float(values[key]) == getattr(expected, key)
    assert float(values["density_kg_m3"]) > 0.0
