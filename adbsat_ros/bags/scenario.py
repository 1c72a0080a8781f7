"""Built-in flight scenarios: a two-body Keplerian orbit in ECI (GCRF) and an attitude history.
Attitudes body -> ECI (x, y, z, w): ``nadir`` is LVLH (+z nadir, +x along track), ``tumble`` turns
about a fixed body axis. Stamps [ns]: UNIX(epoch_utc) + t (``time_mode`` 'unix') or t ('epoch')."""

from __future__ import annotations

import datetime as _dt
import math
from dataclasses import dataclass, field, fields

import numpy as np
from scipy.spatial.transform import Rotation

from adbsat_ros.bounds import BOUNDS, check_memory
from adbsat_ros.estimator.parameter_kinds import parse_utc
from adbsat_ros.physics.constants import EARTH_MU

#: Earth's equatorial radius [m] (WGS-84) from which ``altitude_km`` is measured.
EARTH_RADIUS = 6378137.0
ATTITUDE_MODES = ("nadir", "tumble")
TIME_MODES = ("unix", "epoch")
_NS = 1_000_000_000
_UNIX_EPOCH = _dt.datetime(1970, 1, 1, tzinfo=_dt.timezone.utc)
#: Memory :func:`generate` and the writing of a bag take per message [bytes]: its stamp, time,
#: state or attitude, their temporaries, and its entry in the writer's time order.
BYTES_PER_MESSAGE = 1_024


@dataclass(frozen=True)
class Scenario:
    """What to simulate; angles [deg], times [s], rates [Hz]; ``epoch_utc`` is t = 0 (ISO 8601
    UTC). ``altitude_km``: perigee above :data:`EARTH_RADIUS`; elements in ECI; ``tumble_axis``
    None draws one from ``seed``."""

    epoch_utc: str | _dt.datetime = "2026-01-01T00:00:00Z"
    duration_s: float = 600.0
    rate_hz: float = 10.0
    state_rate_hz: float = 10.0
    altitude_km: float = 400.0
    eccentricity: float = 0.0
    inclination_deg: float = 51.6
    raan_deg: float = 0.0
    arg_perigee_deg: float = 0.0
    true_anomaly_deg: float = 0.0
    attitude: str = "nadir"
    tumble_rate_deg_s: float = 1.0
    tumble_axis: tuple | None = None
    seed: int = 0
    time_mode: str = "unix"

    def __post_init__(self):
        def check(name, ok, what):
            if not ok:
                raise ValueError(f"scenario {name}: {what}, got {getattr(self, name)!r}")

        for name in (f.name for f in fields(self) if f.type == "float"):
            value = getattr(self, name)
            ok = isinstance(value, (int, float)) and math.isfinite(value)
            check(name, ok, "must be a finite number")
        check("duration_s", self.duration_s >= 0, "must be >= 0")
        for name in ("rate_hz", "state_rate_hz"):
            BOUNDS["message_rate"].check(f"scenario {name}", getattr(self, name))
        for name, what in (("rate_hz", "attitude"), ("state_rate_hz", "state")):
            BOUNDS["messages"].check(
                f"scenario duration_s x {name}: the {what} messages (duration x rate + 1)",
                self.duration_s * getattr(self, name) + 1.0,
            )
        check("altitude_km", 0 < self.altitude_km <= 100000, "must be in (0, 100000] km")
        check("eccentricity", 0 <= self.eccentricity < 1, "must be in [0, 1)")
        check("inclination_deg", 0 <= self.inclination_deg <= 180, "must be in [0, 180]")
        check(
            "attitude",
            self.attitude in ATTITUDE_MODES,
            f"must be one of {', '.join(ATTITUDE_MODES)}",
        )
        check("time_mode", self.time_mode in TIME_MODES, f"must be one of {', '.join(TIME_MODES)}")
        if self.tumble_axis is not None:
            axis = np.asarray(self.tumble_axis, dtype=float)
            check(
                "tumble_axis",
                axis.shape == (3,) and np.all(np.isfinite(axis)) and np.linalg.norm(axis) > 0,
                "must be three finite numbers, not all zero",
            )
        epoch = self.epoch  # (parsed: a text that is no time is refused here)
        end = (epoch - _UNIX_EPOCH).total_seconds() + self.duration_s
        if self.time_mode == "unix" and epoch < _UNIX_EPOCH:
            raise ValueError(
                f"scenario epoch_utc: {self.epoch_utc} is before 1970-01-01T00:00:00Z, where "
                "UNIX stamps would be negative (time_mode epoch stamps from 0)"
            )
        last = end if self.time_mode == "unix" else self.duration_s
        if last >= 2**31:  # (a ROS stamp, builtin_interfaces/Time, has int32 seconds)
            field = "duration_s" if last - self.duration_s < 2**31 else "epoch_utc"
            raise ValueError(
                f"scenario {field}: {self.duration_s!r} s after {self.epoch_utc} is beyond "
                "2038-01-19T03:14:07Z, the last second of a ROS stamp (int32 seconds; with "
                "time_mode epoch the stamps count from 0)"
            )

    @property
    def epoch(self) -> _dt.datetime:
        """UTC of t = 0 as an aware datetime."""
        if isinstance(self.epoch_utc, _dt.datetime):
            t = (
                self.epoch_utc
                if self.epoch_utc.tzinfo
                else self.epoch_utc.replace(tzinfo=_dt.timezone.utc)
            )
            return t.astimezone(_dt.timezone.utc)
        return parse_utc("epoch_utc", self.epoch_utc)

    @property
    def perigee_radius(self) -> float:
        """r_p [m]."""
        return EARTH_RADIUS + 1e3 * self.altitude_km

    @property
    def semi_major_axis(self) -> float:
        """a [m]."""
        return self.perigee_radius / (1.0 - self.eccentricity)

    @property
    def apogee_radius(self) -> float:
        """r_a [m]."""
        return self.semi_major_axis * (1.0 + self.eccentricity)

    @property
    def period(self) -> float:
        """Orbital period [s]."""
        return 2.0 * math.pi * math.sqrt(self.semi_major_axis**3 / EARTH_MU)


@dataclass(frozen=True, eq=False)
class StateRecords:
    """Orbital states in time order: stamps [ns], ECI position [m] and velocity [m/s]."""

    stamps_ns: np.ndarray
    position_eci: np.ndarray
    velocity_eci: np.ndarray

    @property
    def stamps(self) -> np.ndarray:
        """Stamps [s] as the node reads them (sec + 1e-9 nanosec)."""
        return stamp_seconds_ns(self.stamps_ns)


@dataclass(frozen=True, eq=False)
class AttitudeRecords:
    """Attitudes in time order: stamps [ns], quaternions body -> ECI."""

    stamps_ns: np.ndarray
    quaternion_xyzw: np.ndarray

    @property
    def stamps(self) -> np.ndarray:
        """Stamps [s] as the node reads them (sec + 1e-9 nanosec)."""
        return stamp_seconds_ns(self.stamps_ns)


@dataclass(frozen=True, eq=False)
class ScenarioMessages:
    """What :func:`generate` returns: the scenario, its states and its attitudes."""

    scenario: Scenario
    states: StateRecords
    attitudes: AttitudeRecords
    extra: dict = field(default_factory=dict)


def stamp_seconds_ns(stamps_ns) -> np.ndarray:
    """Integer nanosecond stamps to float seconds exactly as ``sec + 1e-9 * nanosec``."""
    stamps_ns = np.asarray(stamps_ns, dtype=np.int64)
    sec, nanosec = np.divmod(stamps_ns, _NS)
    return sec.astype(float) + 1e-9 * nanosec.astype(float)


def sample_times(duration_s: float, rate_hz: float) -> np.ndarray:
    """Times k / rate [s] for k = 0, 1, ... while <= duration (integer-exact count)."""
    count = int(math.floor(duration_s * rate_hz + 1e-9)) + 1
    return np.arange(count) / rate_hz


def solve_kepler(mean_anomaly, eccentricity: float, tol: float = 1e-14) -> np.ndarray:
    """Eccentric anomaly E [rad] with E - e sin E = M (Newton's method, vectorised over M)."""
    m = np.asarray(mean_anomaly, dtype=float)
    m = np.mod(m, 2.0 * math.pi)
    e = float(eccentricity)
    big_e = m + e * np.sin(m) if e < 0.8 else np.full_like(m, math.pi)
    for _ in range(50):
        f = big_e - e * np.sin(big_e) - m
        step = f / (1.0 - e * np.cos(big_e))
        big_e = big_e - step
        if np.all(np.abs(step) < tol):
            break
    return big_e


def perifocal_to_eci(scenario: Scenario) -> np.ndarray:
    """Rotation matrix from the perifocal frame (P to perigee, Q, W = orbit normal) to ECI."""
    return Rotation.from_euler(
        "ZXZ", [scenario.raan_deg, scenario.inclination_deg, scenario.arg_perigee_deg], degrees=True
    ).as_matrix()


def kepler_states(scenario: Scenario, t) -> tuple[np.ndarray, np.ndarray]:
    """Two-body position [m] and velocity [m/s] in ECI, shape (N, 3), at times t [s]."""
    t = np.atleast_1d(np.asarray(t, dtype=float))
    e = scenario.eccentricity
    a = scenario.semi_major_axis
    n = math.sqrt(EARTH_MU / a**3)
    nu0 = math.radians(scenario.true_anomaly_deg)
    e0 = 2.0 * math.atan2(
        math.sqrt(1 - e) * math.sin(nu0 / 2), math.sqrt(1 + e) * math.cos(nu0 / 2)
    )
    m0 = e0 - e * math.sin(e0)
    big_e = solve_kepler(m0 + n * t, e)
    cos_e, sin_e = np.cos(big_e), np.sin(big_e)
    b = a * math.sqrt(1 - e * e)
    r = a * (1 - e * cos_e)
    pos_pf = np.stack([a * (cos_e - e), b * sin_e, np.zeros_like(t)], axis=-1)
    edot = n * a / r
    vel_pf = np.stack([-a * sin_e * edot, b * cos_e * edot, np.zeros_like(t)], axis=-1)
    rot = perifocal_to_eci(scenario)
    return pos_pf @ rot.T, vel_pf @ rot.T


def nadir_rotation(position, velocity) -> Rotation:
    """Body -> ECI rotations of the LVLH attitude: +z nadir, +y -orbit normal, +x = y x z."""
    r = np.atleast_2d(np.asarray(position, dtype=float))
    v = np.atleast_2d(np.asarray(velocity, dtype=float))
    z = -r / np.linalg.norm(r, axis=-1, keepdims=True)
    h = np.cross(r, v)
    y = -h / np.linalg.norm(h, axis=-1, keepdims=True)
    x = np.cross(y, z)
    return Rotation.from_matrix(np.stack([x, y, z], axis=-1))  # columns: body axes in ECI


def tumble_axis(scenario: Scenario) -> np.ndarray:
    """Unit body axis of the tumble (given, or drawn from the seed)."""
    if scenario.tumble_axis is not None:
        axis = np.asarray(scenario.tumble_axis, dtype=float)
    else:
        axis = np.random.default_rng(scenario.seed).normal(size=3)
    return axis / np.linalg.norm(axis)


def attitude_quaternions(scenario: Scenario, t) -> np.ndarray:
    """Body -> ECI quaternions (x, y, z, w) at times t [s], shape (N, 4), w >= 0."""
    t = np.atleast_1d(np.asarray(t, dtype=float))
    if scenario.attitude == "nadir":
        rot = nadir_rotation(*kepler_states(scenario, t))
    else:
        start = nadir_rotation(*kepler_states(scenario, [0.0]))
        spin = Rotation.from_rotvec(
            np.outer(np.radians(scenario.tumble_rate_deg_s) * t, tumble_axis(scenario))
        )
        rot = start * spin  # body-fixed axis: R(t) = R0 R_axis(w t)
    q = rot.as_quat()
    return np.where(q[:, 3:4] < 0, -q, q)


def message_count(scenario: Scenario) -> int:
    """The state and attitude messages of a scenario (:func:`sample_times` of each rate)."""
    return sum(
        int(math.floor(scenario.duration_s * rate + 1e-9)) + 1
        for rate in (scenario.state_rate_hz, scenario.rate_hz)
    )


def memory_estimate(scenario: Scenario) -> int:
    """Bytes :func:`generate` and the bag writer take: :data:`BYTES_PER_MESSAGE` per message."""
    return message_count(scenario) * BYTES_PER_MESSAGE


def epoch_unix_ns(scenario: Scenario) -> int:
    """Stamp [ns] of t = 0: UNIX time of the epoch (time_mode unix) or 0 (epoch)."""
    if scenario.time_mode == "epoch":
        return 0
    delta = scenario.epoch - _UNIX_EPOCH
    return (delta.days * 86400 + delta.seconds) * _NS + delta.microseconds * 1000


def generate(scenario: Scenario) -> ScenarioMessages:
    """States and attitudes in time order, stamped ``epoch_unix_ns + round(t * 1e9)``."""
    check_memory(f"the scenario ({message_count(scenario)} messages)", memory_estimate(scenario))
    base = epoch_unix_ns(scenario)
    out = []
    for rate in (scenario.state_rate_hz, scenario.rate_hz):
        offsets = np.round(sample_times(scenario.duration_s, rate) * 1e9).astype(np.int64)
        out.append((base + offsets, offsets * 1e-9))
    (state_ns, state_t), (att_ns, att_t) = out
    position, velocity = kepler_states(scenario, state_t)
    states = StateRecords(state_ns, position, velocity)
    attitudes = AttitudeRecords(att_ns, attitude_quaternions(scenario, att_t))
    return ScenarioMessages(scenario, states, attitudes)
