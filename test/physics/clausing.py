"""Clausing's transmission probability of a tube with diffuse walls, the independent reference
of the test-particle tests: Clausing's integral equation solved by the Nystroem method.

A molecule enters a tube of radius 1 and length L through the plane z = 0 from gas at rest
(cosine law), is re-emitted diffusely wherever it meets the wall, and leaves through z = 0 or
z = L. With nu(z) the rate of wall collisions per unit length per entering molecule,

    nu(z) = g(z) + integral_0^L nu(zeta) k(|z - zeta|) d zeta,
    W = F_dd(L) + integral_0^L nu(zeta) F_rd(L - zeta) d zeta,

where the view factors of diffuse (cosine-law) emission are those of radiative transfer (J. R.
Howell, "A Catalog of Radiation Heat Transfer Configuration Factors": two coaxial discs of equal
radius, and a ring on the inside of a cylinder to a disc at its end):

    F_dd(x) = ((2 + x^2) - x sqrt(x^2 + 4)) / 2           (entry disc to the disc at x),
    F_rd(x) = (X^2 + 1/2) / sqrt(X^2 + 1) - X, X = x / 2  (wall ring to a disc at x),
    g(x) = -F_dd'(x) = (2 + x^2) / sqrt(x^2 + 4) - x,
    k(x) = -F_rd'(x) = (1 - (X^3 + 3 X / 2) / (X^2 + 1)^(3/2)) / 2.

The result agrees with the table of Berman (J. Appl. Phys. 36, 3365 (1965)) to its four
digits (test_tpmc.py checks it): L/R = 0.5, 1, 2, 4, 10 give 0.8013, 0.6720, 0.5142, 0.3566, 0.1910.
"""

from __future__ import annotations

import numpy as np

#: Berman's (1965) Clausing factors by L/R, the published cross-check of :func:`transmission`.
BERMAN = {0.5: 0.8013, 1.0: 0.6720, 2.0: 0.5142, 4.0: 0.3566, 10.0: 0.1910}


def disc_to_disc(x):
    return 0.5 * ((2.0 + x * x) - x * np.sqrt(x * x + 4.0))


def ring_to_disc(x):
    big = 0.5 * x
    return (big * big + 0.5) / np.sqrt(big * big + 1.0) - big


def first_hits(x):
    return (2.0 + x * x) / np.sqrt(x * x + 4.0) - x


def next_hits(x):
    big = 0.5 * np.abs(x)
    return 0.5 * (1.0 - (big**3 + 1.5 * big) / (big * big + 1.0) ** 1.5)


def transmission(length: float, intervals: int = 400, order: int = 8) -> float:
    """W of a tube of radius 1 and ``length``: Nystroem on composite Gauss-Legendre nodes."""
    t, w = np.polynomial.legendre.leggauss(order)
    edges = np.linspace(0.0, length, intervals + 1)
    mid, half = 0.5 * (edges[1:] + edges[:-1]), 0.5 * np.diff(edges)
    z = (mid[:, None] + half[:, None] * t[None, :]).ravel()
    weights = (half[:, None] * w[None, :]).ravel()
    kernel = next_hits(z[:, None] - z[None, :]) * weights[None, :]
    nu = np.linalg.solve(np.eye(z.size) - kernel, first_hits(z))
    return float(disc_to_disc(length) + np.sum(weights * nu * ring_to_disc(length - z)))
