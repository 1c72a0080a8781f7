"""How a :class:`~adbsat_ros.physics.model.Model` evaluates: its one shading cache and each
backend's coefficients from the cache's cells. A cell holds a lighting and what the panel
method sums of it (facet sums, or an articulated body's link rows); a message's sums are its
cells' sums blended in the kernels' own operations, so the numbers equal the kernels'."""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from adbsat_ros.physics.articulated_results import Configuration
from adbsat_ros.physics.coefficients import AeroCoefficients
from adbsat_ros.physics.facets import blend_sums
from adbsat_ros.physics.posed_facets import PosedSums
from adbsat_ros.shading.cache import Cell, ShadingCache
from adbsat_ros.shading.lighting import LightingBlend
from adbsat_ros.shading.posed_scene import LinkScenes
from adbsat_ros.shading.shader import make_shader

#: Posed shaders an offline job's articulated cache keeps (exact mode).
OFFLINE_SHADERS = 8


class Joints(NamedTuple):
    """An articulated body's joint positions made ready once per joint state: ``positions`` [rad or
    m],
    their ``configuration`` and the cache's ``vertices`` (None without a cache)."""

    positions: dict
    configuration: Configuration
    vertices: list | None


def unit_of_array(direction: np.ndarray) -> np.ndarray | None:
    """``direction`` / |direction| of a finite non-zero float (3,) array, as
    :func:`~adbsat_ros.geometry.frames.unit_vector` makes it; None for any other value."""
    if direction.shape != (3,) or direction.dtype != np.float64:
        return None
    norm = math.sqrt(direction.dot(direction))
    if not (math.isfinite(norm) and norm > 0.0):
        return None
    return direction / norm


def make_cache(model) -> ShadingCache | None:
    """The one shading cache of ``model`` by its set-up's policy (None when nothing can be
    occluded)."""
    policy, method = model.setup.shading, model.method
    if policy.mode == "none":
        return None
    offline = policy.exact_offline
    if not model.articulated:
        shader, facets = model.shader, method.facets
        summarise = None if facets is None else facets.lit_sums_of
        if offline:
            if shader.trivial:
                return None
            return ShadingCache.exact_mode(shader, max_entries=offline, summarise=summarise)
        return ShadingCache(
            shader,
            resolution_deg=policy.cache_resolution_deg,
            max_entries=policy.cache_size,
            interpolate=policy.interpolation,
            summarise=summarise,
        )
    posed = {
        "body": model.body,
        "posed_shader": posed_shader(model.body, policy),
        "summarise": None if method.facets is None else method.facets.link_rows,
    }
    if offline:
        shaders = min(offline, OFFLINE_SHADERS)
        return ShadingCache.exact_mode(max_entries=offline, max_configurations=shaders, **posed)
    if policy.joint_exact:
        return ShadingCache.exact_mode(**posed)
    return ShadingCache(
        resolution_deg=policy.cache_resolution_deg,
        max_entries=policy.cache_size,
        interpolate=policy.interpolation,
        angle_step=math.radians(policy.joint_resolution_deg),
        length_step=policy.joint_resolution_m,
        joint_interpolate=policy.joint_interpolation,
        max_configurations=policy.joint_cache_size,
        **posed,
    )


def posed_shader(body, policy):
    """``posed_shader(positions)``: the shader of ``body`` posed at joint ``positions``, by
    ``policy``."""
    scenes = []

    def shader_at(positions: dict):
        poses = body.link_poses(positions)
        panels = body.posed_mesh(poses)
        if policy.mode != "raycast":
            return make_shader(panels, mode=policy.mode, samples=policy.samples)
        if not scenes:
            scenes.append(LinkScenes(body))
        made = scenes[0]
        return make_shader(
            panels,
            mode=policy.mode,
            samples=policy.samples,
            scene=made.scene(panels, poses),
            candidate_filter=made.candidate_filter(panels),
            hull_corners=made.hull_corners(poses),
        )

    return shader_at


def all_lit_cell(method, articulated: bool) -> Cell:
    """The cell of a body without shading: no lighting, and the all-lit sums (or rows)."""
    facets = method.facets
    if facets is None:
        return Cell(None)
    return Cell(None, facets.link_rows if articulated else facets.lit_sums_of)


def blended_lighting(parts):
    """The lighting of the cells ``parts`` [(weight, Cell)]: one cell's own, or their blend."""
    return LightingBlend.of([(w, cell.lighting) for w, cell in parts])


def facet_sums(method, parts):
    """The cells' ``parts`` facet sums (a rigid body's) or link rows (an articulated body's),
    blended; None without facets."""
    if method.facets is None:
        return None
    if len(parts) == 1:
        return parts[0][1].sums
    return blend_sums([(w, cell.sums) for w, cell in parts])


def rigid_coefficients(method, flow, u, angles, parts, surface) -> AeroCoefficients:
    """The panel method's coefficients at unit flow direction ``u`` from the cells ``parts``."""
    sums = facet_sums(method, parts)
    return method.coefficients_of_sums(flow, u, angles, sums, blended_lighting(parts), surface)


def articulated_coefficients(method, flow, u, angles, configuration, parts, surface):
    """The articulated panel method's coefficients at ``configuration`` from the cells ``parts``."""
    rows = facet_sums(method, parts)  # (the cells' link rows, blended)
    sums = None if rows is None else PosedSums(rows, configuration.posing)
    lighting = blended_lighting(parts)
    return method.coefficients_of_rows(flow, u, angles, configuration, sums, lighting, surface)


def looked_up_coefficients(lookup, method, u, angles) -> AeroCoefficients:
    """The coefficients ``lookup(u)`` gives, with the method's reference."""
    cf, cm = lookup(u)
    return AeroCoefficients(
        u, cf, cm, method.reference, math.nan, method.model, _no_panel_values, angles=angles
    )


def _no_panel_values():
    raise ValueError("a database lookup has no per-panel values")


def solar_of_cells(method, sun_direction, parts):
    """:func:`~adbsat_ros.physics.solar.solar_coefficients` with cells read along minus the Sun."""
    from adbsat_ros.physics.solar import solar_coefficients  # (not at a command's start-up)

    sums = facet_sums(method, parts)
    return solar_coefficients(method, sun_direction, lighting=blended_lighting(parts), sums=sums)
