"""The coefficients of a test-particle run (dimensionless) with their standard errors."""

from __future__ import annotations

import numpy as np

from adbsat_ros.geometry import frames
from adbsat_ros.physics.coefficients import AeroCoefficients
from adbsat_ros.physics.freestream import FreeStream


class TpmcCoefficients(AeroCoefficients):
    """:class:`AeroCoefficients` from test particles, with standard errors (the ``*_error``
    properties).

    covariance (6, 6): of the estimates of (Cf_G, Cm_G); hits: molecule-surface collisions;
    trapped: molecules stopped while still bouncing; force_balance: momentum in minus out through
    the box per unit q A_ref (equals Cf_G within errors); stopped: by the ``stop`` event.
    """

    def __init__(
        self, *args, covariance, particles, seed, hits, trapped, force_balance, stopped, **kw
    ):
        super().__init__(*args, **kw)
        self.covariance = covariance
        self.particles, self.seed, self.hits, self.trapped = particles, seed, hits, trapped
        self.force_balance = force_balance
        self.stopped = stopped

    def error_of(self, matrix) -> np.ndarray:
        """Standard errors of ``matrix @ (Cf_G, Cm_G)`` (matrix of shape (K, 6))."""
        a = np.asarray(matrix, dtype=float)
        return np.sqrt(np.maximum(np.einsum("ij,jk,ik->i", a, self.covariance, a), 0.0))

    def _force_error(self, rotation) -> np.ndarray:
        return self.error_of(np.hstack([rotation, np.zeros((3, 3))]))

    @property
    def Cf_G_error(self) -> np.ndarray:
        """Standard errors of Cf_G."""
        return self._force_error(np.eye(3))

    @property
    def Cm_G_error(self) -> np.ndarray:
        """Standard errors of Cm_G."""
        return self.error_of(np.hstack([np.zeros((3, 3)), np.eye(3)]))

    @property
    def Cf_w_error(self) -> np.ndarray:
        """Standard errors of Cf_w."""
        return self._force_error(frames.body_to_wind(self.aoa, self.aos) @ frames.L_GB)

    @property
    def Cf_f_error(self) -> np.ndarray:
        """Standard errors of Cf_f."""
        return self._force_error(frames.L_FB @ frames.L_GB)

    @property
    def Cm_B_error(self) -> np.ndarray:
        """Standard errors of Cm_B."""
        return self.error_of(np.hstack([np.zeros((3, 3)), frames.L_GB]))

    @property
    def drag_error(self) -> float:
        """Standard error of C_D."""
        return float(self.Cf_w_error[0])

    @property
    def side_force_error(self) -> float:
        """Standard error of C_Y."""
        return float(self.Cf_w_error[1])

    @property
    def lift_error(self) -> float:
        """Standard error of C_L."""
        return float(self.Cf_w_error[2])

    def to_dict(self, flow: FreeStream | None = None, per_panel: bool = False) -> dict:
        """AeroCoefficients.to_dict with the standard errors (``*_error``) and the run's counts."""
        out = super().to_dict(flow, per_panel)
        out.update(
            method="tpmc",
            Cf_w_error=self.Cf_w_error.tolist(),
            Cf_f_error=self.Cf_f_error.tolist(),
            Cm_B_error=self.Cm_B_error.tolist(),
            Cf_G_error=self.Cf_G_error.tolist(),
            Cm_G_error=self.Cm_G_error.tolist(),
            CD_error=self.drag_error,
            CL_error=self.lift_error,
            CY_error=self.side_force_error,
            particles=self.particles,
            seed=self.seed,
            hits=self.hits,
            stopped=self.stopped,
        )
        return out
