"""ADBSat's projection shading: a hand-worked case, and a loop transcription of its algorithm."""

from __future__ import annotations

import math

import numpy as np
import pytest
from shading_scenes import cube_plate, dented_box, satellite

from adbsat_ros.geometry import frames
from adbsat_ros.shading.projection import adbsat_shadowed
from adbsat_ros.shading.shader import make_shader


def test_projection_hand_worked_case():
    # Plate front face split into a 3 x 3 grid of 1 m squares, each cut along its rising
    # diagonal into a lower-right triangle (barycentre at (y0 + 2/3, z0 + 1/3)) and an
    # upper-left one ((y0 + 1/3, z0 + 2/3)). The cube's back faces project onto |y| <= 0.5 and
    # z in [-0.5, 0.5] at aoa 0, and (with its top face, a back face too at aoa > 0) onto
    # z in [-0.5 + 1.45 tan a, 0.5 + 2.45 tan a] = [-0.244, 0.932] at aoa = 10 deg.
    # Barycentres of the middle column sit at y = +/-1/6, inside. At 0 deg the middle square's
    # two barycentres (z = -1/6, +1/6) are shadowed; at 10 deg also the top square's
    # lower-right one (z = 0.833); its upper-left one (z = 1.167) and the bottom row are not.
    mesh = cube_plate(plate_div=3, cube_div=1)
    sh = make_shader(mesh, mode="projection")
    for aoa_deg, expected in [
        (0.0, {(1 / 6, -1 / 6), (-1 / 6, 1 / 6)}),
        (10.0, {(1 / 6, -1 / 6), (-1 / 6, 1 / 6), (1 / 6, 5 / 6)}),
    ]:
        light = sh.lighting(frames.flow_direction(math.radians(aoa_deg), 0.0))
        shaded = np.flatnonzero(light.lit_fraction == 0.0)
        assert np.all(np.isin(light.lit_fraction, (0.0, 1.0)))
        got = {(round(b[1], 4), round(b[2], 4)) for b in mesh.barycentres[shaded]}
        assert got == {(round(y, 4), round(z, 4)) for y, z in expected}
        assert np.allclose(mesh.barycentres[shaded, 0], 0.05)
        assert light.shift_index.size == 0


def _adbsat_loop(mesh, u):
    """Straight transcription of physics.md section 6 with a loop over forward panels."""
    aoa, aos = frames.angles_of_flow(u)
    L = frames.mesh_to_wind(float(aoa), float(aos))
    V = mesh.vertices @ L.T
    bary = mesh.barycentres @ L.T
    delta = np.degrees(np.arccos(np.clip(-(mesh.normals @ u), -1, 1)))
    back = delta > 90.0001
    front = ~back
    xmin = V[:, :, 0].min(axis=1)
    xmax = V[:, :, 0].max(axis=1)
    out = np.zeros(mesh.n_panels, bool)
    if not back.any() or not front.any():
        return out
    fc = np.flatnonzero(front & (xmin < xmin[back].max() + 1e-4))
    bc = np.flatnonzero(back & (xmax > xmin[front].min() + 1e-4))
    for f in fc:
        yz = V[bc][:, :, 1:] - bary[f, 1:]
        ok = ~(np.all(yz[:, :, 0] > 0, axis=1) | np.all(yz[:, :, 0] < 0, axis=1))
        ok &= ~(np.all(yz[:, :, 1] > 0, axis=1) | np.all(yz[:, :, 1] < 0, axis=1))
        A, B, C = yz[ok, 0], yz[ok, 1], yz[ok, 2]
        v0, v1, v2 = C - A, B - A, -A
        d00, d01, d02 = (v0 * v0).sum(1), (v0 * v1).sum(1), (v0 * v2).sum(1)
        d11, d12 = (v1 * v1).sum(1), (v1 * v2).sum(1)
        with np.errstate(divide="ignore", invalid="ignore"):
            inv = 1 / (d00 * d11 - d01 * d01)
            uu = (d11 * d02 - d01 * d12) * inv
            vv = (d00 * d12 - d01 * d02) * inv
            hit = (uu >= 0) & (vv >= 0) & (uu + vv < 1)
        b = bc[ok][hit]
        if b.size and np.any(
            np.einsum("ij,ij->i", mesh.normals[b], mesh.barycentres[f] - mesh.vertices[b, 0]) > 1e-5
        ):
            out[f] = True
    return out


@pytest.mark.parametrize("mesh_factory", [satellite, lambda: cube_plate(plate_div=9), dented_box])
def test_projection_matches_loop_transcription(mesh_factory):
    mesh = mesh_factory()
    rng = np.random.default_rng(5)
    dirs = [frames.flow_direction(0.0, 0.0), frames.flow_direction(math.radians(10), 0.0)]
    dirs += list(frames.flow_direction(rng.uniform(-0.7, 0.7, 6), rng.uniform(-0.7, 0.7, 6)))
    n_shaded = 0
    for u in dirs:
        fast = adbsat_shadowed(mesh, u, max_pairs=5000)  # small chunks on purpose
        ref = _adbsat_loop(mesh, u)
        np.testing.assert_array_equal(fast, ref)
        n_shaded += int(ref.sum())
    assert n_shaded > 0
