"""What the estimator returns per message (:class:`WrenchSample`, :class:`Rejection`) and keeps."""

from __future__ import annotations

import datetime as _dt
import functools
from dataclasses import dataclass

import numpy as np

from adbsat_ros.environment.conditions import FlightConditions
from adbsat_ros.physics.articulated_results import ArticulatedCoefficients
from adbsat_ros.physics.coefficients import AeroCoefficients


class Rejection(Exception):
    """An input that produced no wrench: ``reason`` (a key of ``rejections``) and a message."""

    def __init__(self, reason: str, message: str):
        super().__init__(message)
        self.reason = reason
        self.message = message


@dataclass(frozen=True, eq=False)
class OrbitalState:
    """The latest accepted orbital state, in the state frame (ECI or ECEF) [m, m/s]. Equal to
    another with the same stamp, position and velocity (the knots' key); not hashable."""

    stamp: float
    position: np.ndarray
    velocity: np.ndarray

    def __eq__(self, other):
        if self is other:
            return True
        if not isinstance(other, OrbitalState):
            return NotImplemented
        return (
            self.stamp == other.stamp
            and np.array_equal(self.position, other.position)
            and np.array_equal(self.velocity, other.velocity)
        )

    __hash__ = None


@dataclass(frozen=True, eq=False)
class JointSample:
    """An articulated body's joints at one message (``dynamic_pressure`` q [Pa]); loads on read."""

    coefficients: ArticulatedCoefficients
    dynamic_pressure: float
    link_names: tuple

    @property
    def names(self) -> tuple:
        """The moving joints, in the body's order."""
        return self.coefficients.joint_names

    @property
    def positions(self) -> np.ndarray:
        """Their positions used [rad or m] (J,), read-only."""
        return self.coefficients.joint_positions

    @functools.cached_property
    def efforts(self) -> np.ndarray:
        """Effort each drive holds (J,): [N m] about a revolute axis, [N] along a prismatic one."""
        return self.coefficients.efforts(self.dynamic_pressure)

    @functools.cached_property
    def link_forces(self) -> np.ndarray:
        """Every link's force [N] (L, 3), body frame."""
        area = self.coefficients.total.reference.area
        return (self.dynamic_pressure * area) * self.coefficients.link_force

    @functools.cached_property
    def link_torques(self) -> np.ndarray:
        """Each link's torque [N m] (L, 3) about the CoM, body frame (summing to the wrench's)."""
        reference = self.coefficients.total.reference
        scale = self.dynamic_pressure * reference.area * reference.length
        return scale * self.coefficients.link_moment


@dataclass(frozen=True, eq=False)
class SolarSample:
    """The solar radiation pressure wrench at one message, body frame: ``force`` [N], ``torque``
    [N m] about the centre of mass; ``lit_fraction`` of the Sun's disc past the Earth [0, 1];
    ``pressure`` [Pa] and ``area_lit`` (projected normal to the Sun) [m^2] before the shadow."""

    force: np.ndarray
    torque: np.ndarray
    sun_direction_body: np.ndarray
    lit_fraction: float
    pressure: float
    area_lit: float


@dataclass(frozen=True, eq=False)
class WrenchSample:
    """The aerodynamic wrench at one attitude message, body (mesh) frame, about the centre of mass.
    ``stamp`` [s], UTC ``time``; ``force`` [N], ``torque`` [N m]; C_F, C_M by ``reference_area``
    [m^2] and ``reference_length`` [m]; ``dynamic_pressure`` [Pa]; ``flow_direction_body``: unit gas
    motion (zero at rest); ``compute_seconds`` [s]; ``rotation``: body to state frame, row-major."""

    stamp: float
    time: _dt.datetime
    force: np.ndarray
    torque: np.ndarray
    force_coefficients: np.ndarray
    moment_coefficients: np.ndarray
    reference_area: float
    reference_length: float
    dynamic_pressure: float
    conditions: FlightConditions
    coefficients: AeroCoefficients | None
    flow_direction_body: np.ndarray
    compute_seconds: float
    rotation: tuple
    solar: SolarSample | None = None
    joints: JointSample | None = None

    @property
    def solar_diagnostics(self) -> dict | None:
        """The solar wrench's diagnostic key/values, None without."""
        solar = self.solar
        if solar is None:
            return None
        return {
            "solar_lit_fraction": float(solar.lit_fraction),
            "solar_pressure_Pa": float(solar.pressure),
            "solar_force_N": float(np.linalg.norm(solar.force)),
            "solar_torque_N_m": float(np.linalg.norm(solar.torque)),
            "aero_force_N": float(np.linalg.norm(self.force)),
        }

    @property
    def total_force(self) -> np.ndarray:
        """Aerodynamic plus solar radiation force [N], body frame."""
        return self.force if self.solar is None else self.force + self.solar.force

    @property
    def total_torque(self) -> np.ndarray:
        """Aerodynamic plus solar radiation torque [N m] about the centre of mass, body frame."""
        return self.torque if self.solar is None else self.torque + self.solar.torque

    def state_frame_wrench(self, mass: float, inertia) -> tuple:
        """What a propagator takes, of the aerodynamic wrench plus the solar one.
        mass [kg] (0 or less: none); inertia [kg m^2]: 9 floats, row-major, body frame, about CoM.
        Returns (force [N] state frame, torque [N m] body frame, force / mass [m/s^2] state frame or
        None, inertia^-1 torque [rad/s^2] body frame, zero without ``inertia``)."""
        force = np.array(self.rotation).reshape(3, 3) @ self.total_force
        torque = self.total_torque
        if mass <= 0.0:
            return force, torque, None, np.zeros(3)
        angular = np.zeros(3)
        if inertia is not None:
            angular = np.linalg.solve(np.array(inertia).reshape(3, 3), torque)
        return force, torque, force / mass, angular

    @functools.cached_property
    def drag_coefficient(self) -> float:
        """C_D: force coefficient along the gas motion (0 at rest)."""
        return float(self.force_coefficients @ self.flow_direction_body)
