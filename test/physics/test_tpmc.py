"""The test-particle Monte Carlo solver against what is known exactly.

On a convex body no molecule meets the body twice, so the panel method is exact there, and the
test-particle answer must equal it within its statistics (three standard errors, with runs long
enough that this is within 0.2 % of C_D). Multiple reflections are checked against Clausing's
transmission probabilities of tubes (clausing.py). Seeds are fixed: each test is deterministic.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import trimesh
from clausing import BERMAN, transmission
from scipy.special import erf
from scipy.stats import kstest

from adbsat_ros.geometry.mesh import panels_from_arrays
from adbsat_ros.physics.freestream import FreeStream
from adbsat_ros.physics.panel_method import PanelMethod
from adbsat_ros.physics.surface import SurfaceProperties
from adbsat_ros.physics.tpmc.inflow import InflowBox, normal_speed_ratios
from adbsat_ros.physics.tpmc.method import TestParticleMethod
from adbsat_ros.physics.tpmc.tracing import trace
from adbsat_ros.shading.rays import has_embree, ray_scene

FLOW = FreeStream(speed=7800.0, temperature=1000.0, mean_mass_amu=16.0)


def mesh_of(tm):
    return panels_from_arrays(tm.vertices, tm.faces)


BODIES = {
    "sphere": lambda: mesh_of(trimesh.creation.icosphere(subdivisions=4, radius=0.5)),
    "thin plate": lambda: mesh_of(trimesh.creation.box((0.01, 1.0, 1.0))),
    "cube": lambda: mesh_of(trimesh.creation.box((1.0, 1.0, 1.0))),
    "cylinder": lambda: mesh_of(trimesh.creation.cylinder(radius=0.5, height=1.5, sections=64)),
}


def within_errors(tp, pm, sigmas=3.0):
    """Every force and moment coefficient of ``tp`` within ``sigmas`` standard errors of ``pm``."""
    for name in ("Cf_G", "Cm_G"):
        got, want = getattr(tp, name), getattr(pm, name)
        error = getattr(tp, f"{name}_error")
        assert np.all(np.abs(got - want) <= sigmas * error + 1e-12), (name, got, want, error)


@pytest.mark.parametrize(
    "body, aoa_deg",
    [("sphere", 0.0), ("thin plate", 20.0), ("cube", 0.0), ("cube", 30.0), ("cylinder", 30.0)],
)
def test_diffuse_full_accommodation_on_a_convex_body_is_the_panel_method(body, aoa_deg):
    mesh = BODIES[body]()
    surface = SurfaceProperties(alpha=1.0, wall_temperature=300.0)
    aoa, aos = math.radians(aoa_deg), math.radians(10.0)
    pm = PanelMethod(mesh, "sentman", surface).coefficients(FLOW, aoa, aos)
    tp = TestParticleMethod(mesh, "sentman", surface).coefficients(
        FLOW, aoa, aos, tolerance=0.002 / 3, seed=7
    )
    assert 3 * tp.drag_error <= 0.002 * tp.drag  # three errors are within 0.2 %
    assert tp.drag == pytest.approx(pm.drag, rel=0.002)
    within_errors(tp, pm)
    assert tp.area_projected == pytest.approx(pm.area_projected, rel=1e-9)


@pytest.mark.parametrize(
    "model, surface, species",
    [
        ("maxwell", SurfaceProperties(alpha=0.6), None),
        ("maxwell", SurfaceProperties(alpha=0.0), None),  # specular
        ("cll", SurfaceProperties(alpha_n=1.0, sigma_t=0.6), {"O": 1e15}),
        ("dria", SurfaceProperties(alpha=1.0), {"O": 6e14, "N2": 3e14, "He": 1e14}),
    ],
    ids=["maxwell", "specular", "cll", "dria-mixture"],
)
def test_the_kernels_reduce_to_the_closed_forms_on_a_convex_body(model, surface, species):
    """Maxwell's kernel is Schaaf and Chambre's plate with sigma_n = sigma_t = alpha; CLL with
    alpha_n = 1 is Schaaf and Chambre with sigma_n = 1 (the panel model's exact branch); a
    mixture's species enter by their own fluxes, which is Sentman per species mixed by mass
    fraction (dria)."""
    mesh = BODIES["cube"]()
    flow = FLOW if species is None else FreeStream(7800.0, 1000.0, number_densities=species)
    aoa, aos = math.radians(30.0), math.radians(15.0)
    pm = PanelMethod(mesh, model, surface).coefficients(flow, aoa, aos)
    tp = TestParticleMethod(mesh, model, surface).coefficients(
        flow, aoa, aos, tolerance=0.002 / 3, seed=11
    )
    within_errors(tp, pm)
    assert tp.drag == pytest.approx(pm.drag, rel=0.002)


@pytest.mark.parametrize("length", sorted(BERMAN))
def test_a_tube_transmits_clausings_fraction(length):
    """Gas at rest entering an open tube (radius 1, 128 sides) through one end, diffuse walls:
    the fraction leaving through the other end is Clausing's factor within 0.5 %."""
    reference = transmission(length)
    assert reference == pytest.approx(BERMAN[length], abs=6e-5)
    sections = 128
    angle = np.linspace(0.0, 2.0 * np.pi, sections, endpoint=False)
    ring = np.column_stack([np.cos(angle), np.sin(angle)])
    vertices = np.vstack(
        [
            np.column_stack([ring, np.zeros(sections)]),
            np.column_stack([ring, np.full(sections, length)]),
        ]
    )
    i = np.arange(sections)
    j = (i + 1) % sections
    faces = np.vstack(
        [np.column_stack([i, j, j + sections]), np.column_stack([i, j + sections, i + sections])]
    )
    mesh = panels_from_arrays(vertices, faces, fix_normals=False)
    surface = PanelMethod(mesh, "sentman", SurfaceProperties()).surface
    rng = np.random.default_rng(3)
    # enough molecules that three standard errors are within 0.45 % of the reference
    count = math.ceil(9.0 * (1.0 - reference) / (reference * 0.0045**2))
    # entering molecules: uniform on the inscribed disc, cosine-law directions into the tube
    radius = np.cos(np.pi / sections) * np.sqrt(rng.random(count))
    phi = 2.0 * np.pi * rng.random(count)
    start = np.column_stack([radius * np.cos(phi), radius * np.sin(phi), np.zeros(count)])
    sin_theta = np.sqrt(rng.random(count))
    psi = 2.0 * np.pi * rng.random(count)
    cos_theta = np.sqrt(1.0 - sin_theta**2)
    velocity = 1000.0 * np.column_stack(
        [sin_theta * np.cos(psi), sin_theta * np.sin(psi), cos_theta]
    )
    scene = ray_scene(mesh)
    passed = 0
    for k in range(0, count, 100_000):
        tally = trace(
            scene,
            mesh,
            "diffuse",
            surface,
            start[k : k + 100_000],
            velocity[k : k + 100_000],
            np.full(min(100_000, count - k), 16 * 1.6605e-27),
            rng,
            np.zeros(3),
        )
        assert tally.trapped == 0
        passed += int(np.count_nonzero(tally.exit_velocity[:, 2] > 0.0))
    w = passed / count
    error = math.sqrt(w * (1.0 - w) / count)
    assert abs(w - reference) <= 3.0 * error <= 0.005 * reference


@pytest.mark.parametrize("s", [-3.0, -0.5, 0.0, 1.5, 7.6])
def test_entering_normal_speeds_follow_the_flux_distribution(s):
    """x = v_n / c of molecules entering through a face has the density x exp(-(x - s)^2) on
    x > 0, whose distribution function is closed-form (Kolmogorov-Smirnov, 200,000 draws)."""
    x = normal_speed_ratios(np.full(200_000, s), np.random.default_rng(5))

    def cdf(v):
        partial = 0.5 * (math.exp(-s * s) - np.exp(-((v - s) ** 2))) + 0.5 * math.sqrt(
            math.pi
        ) * s * (erf(v - s) + math.erf(s))
        total = 0.5 * math.exp(-s * s) + 0.5 * math.sqrt(math.pi) * s * (1.0 + math.erf(s))
        return partial / total

    assert np.all(x > 0.0)
    assert kstest(x, cdf).pvalue > 1e-3


def test_the_sampled_inflow_carries_the_closed_form_fluxes():
    """The molecules entering the box carry, per molecule times the entry rate, the momentum
    flux of the drifting Maxwellian through its faces (closed form), within three errors."""
    u = np.array([math.cos(0.3), math.sin(0.3), 0.2])
    u /= np.linalg.norm(u)
    masses = np.array([16.0, 28.0, 4.0]) * 1.66053907e-27
    box = InflowBox([-1, -1, -1], [1, 2, 1], 7500.0 * u, 900.0, masses, [0.6, 0.3, 0.1])
    pos, vel, species = box.sample(400_000, np.random.default_rng(9))
    momentum = masses[species, None] * vel
    mean = momentum.mean(axis=0) * box.rate
    error = momentum.std(axis=0) / math.sqrt(len(vel)) * box.rate
    assert np.all(np.abs(mean - box.momentum_flux()) <= 3.0 * error)
    # every molecule starts on the box, moving into it
    at_lower, at_upper = pos == box.lower, pos == box.upper
    assert np.all((at_lower | at_upper).sum(axis=1) == 1)
    assert np.all(vel[at_lower] > 0.0) and np.all(vel[at_upper] < 0.0)


def test_a_body_symmetric_about_the_flow_has_no_side_or_lift_force():
    mesh = BODIES["cylinder"]()  # axis along z; the flow along x at aoa = aos = 0
    tp = TestParticleMethod(mesh, "maxwell", SurfaceProperties(alpha=0.7)).coefficients(
        FLOW, 0.0, 0.0, particles=300_000, seed=4
    )
    assert abs(tp.side_force) <= 3.0 * tp.side_force_error
    assert abs(tp.lift) <= 3.0 * tp.lift_error
    assert tp.drag > 30.0 * tp.drag_error


def test_the_force_is_the_momentum_flux_in_less_the_momentum_flux_out():
    """Momentum conservation over the box: the closed-form inflow less the traced outflow equals
    the force the panels received."""
    mesh = BODIES["cube"]()
    tp = TestParticleMethod(mesh, "sentman", SurfaceProperties(alpha=0.5)).coefficients(
        FLOW, math.radians(25.0), math.radians(-10.0), particles=300_000, seed=8
    )
    assert np.all(np.abs(tp.force_balance - tp.Cf_G) <= 3.0 * tp.Cf_G_error)


def test_a_seed_gives_the_same_numbers_for_one_and_two_workers():
    mesh = BODIES["cube"]()
    method = TestParticleMethod(mesh, "cll", SurfaceProperties(alpha_n=0.5, sigma_t=0.8))
    flow = FreeStream(7600.0, 800.0, number_densities={"O": 1e15, "N2": 2e14})
    runs = [
        method.coefficients(flow, 0.4, 0.1, particles=300_000, seed=21, workers=w) for w in (1, 2)
    ]
    for name in ("Cf_G", "Cm_G", "covariance", "cp", "ctau"):
        np.testing.assert_array_equal(getattr(runs[0], name), getattr(runs[1], name))
    assert runs[0].particles == runs[1].particles == 5 * 65_536  # whole batches
    other = method.coefficients(flow, 0.4, 0.1, particles=300_000, seed=22)
    assert not np.array_equal(other.Cf_G, runs[0].Cf_G)


@pytest.mark.skipif(not has_embree, reason="needs embreex")
def test_the_numpy_rays_give_the_embree_answers():
    mesh = BODIES["cube"]()
    runs = [
        TestParticleMethod(mesh, "sentman", backend=b).coefficients(
            FLOW, 0.3, 0.2, particles=20_000, seed=3
        )
        for b in ("embree", "numpy")
    ]
    np.testing.assert_allclose(runs[0].Cf_G, runs[1].Cf_G, rtol=1e-6)
    np.testing.assert_allclose(runs[0].Cm_G, runs[1].Cm_G, rtol=1e-5, atol=1e-9)
    assert runs[0].hits == runs[1].hits


def test_a_precision_target_stops_the_run_early():
    mesh = BODIES["cube"]()
    tp = TestParticleMethod(mesh).coefficients(FLOW, tolerance=0.01, seed=1)
    assert tp.drag_error <= 0.01 * tp.drag
    assert tp.particles <= 4 * 65_536  # one block was enough


@pytest.mark.parametrize(
    "kwargs, message",
    [
        (dict(particles=0), "particles must be a whole number >= 1"),
        (dict(particles=2.5), "particles must be a whole number >= 1"),
        (dict(tolerance=0.0), r"tolerance must be in \(0, 1\)"),
        (dict(tolerance=math.nan), r"tolerance must be in \(0, 1\)"),
        (dict(seed=-1), "seed must be a whole number >= 0"),
        (dict(workers=0), "workers must be a whole number >= 1"),
    ],
)
def test_bad_run_settings_are_named(kwargs, message):
    method = TestParticleMethod(BODIES["cube"]())
    with pytest.raises(ValueError, match=message):
        method.coefficients(FLOW, **kwargs)


def test_a_model_without_a_kernel_is_refused_by_name():
    with pytest.raises(ValueError, match="model 'newton' has no test-particle kernel; choose"):
        TestParticleMethod(BODIES["cube"](), "newton")


def test_a_stopped_run_is_the_run_of_the_molecules_it_traced():
    import threading

    stop = threading.Event()
    stop.set()  # already set: the run ends after its first block
    method = TestParticleMethod(BODIES["cube"]())
    stopped = method.coefficients(FLOW, particles=10**8, seed=6, stop=stop)
    whole = method.coefficients(FLOW, particles=4 * 65_536, seed=6)
    assert stopped.stopped and not whole.stopped
    assert stopped.particles == whole.particles == 4 * 65_536
    np.testing.assert_array_equal(stopped.Cf_G, whole.Cf_G)
