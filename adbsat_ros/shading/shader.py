"""Shading: which part of each panel the flow reaches (a point is shaded if the line upstream, -u,
meets the satellite). Modes (:func:`make_shader`): ``"none"``, ``"projection"`` (ADBSat's
``shadowAnaly``) and ``"raycast"`` (default: exact convex shadows, else sampled rays, refined
where partly lit). Method and accuracy: docs/shading.md. Units: metres, frame G, radians."""

from __future__ import annotations

import math

import numpy as np

from adbsat_ros.geometry import frames
from adbsat_ros.geometry.mesh import PanelMesh
from adbsat_ros.shading.candidates import MAX_COMPONENTS_FILTER, CandidateFilter, forward_mask
from adbsat_ros.shading.convex_shadow import ConvexParts
from adbsat_ros.shading.lighting import PanelLighting
from adbsat_ros.shading.projection import adbsat_shadowed
from adbsat_ros.shading.rays import ray_scene, resolve_backend
from adbsat_ros.shading.sampling import CORNERS, sample_coordinates, sample_points
from adbsat_ros.shading.topology_store import TopologyStore, indexed_topology

MODES = ("none", "projection", "raycast")

#: Default number of sample points (rays) per forward panel that could be shaded.
DEFAULT_SAMPLES = 16
#: Default number of extra rays for panels found partly lit by the first samples.
DEFAULT_REFINE_SAMPLES = 256
#: |cos delta| at or below which a face is grazing: it does not occlude.
DEFAULT_GRAZE_TOL = 1e-6
#: Offset of the ray origins along the panel normal, as a fraction of the bounding-box diagonal.
DEFAULT_OFFSET_FRACTION = 1e-5
#: The counts of :attr:`Shader.last_stats` (raycast and no shading).
STATS = ("forward", "tested", "rays", "exact", "corner_shaded", "partly_lit", "refined", "probed")


class Shader:
    """Shading of one mesh (G, m) for any flow direction; build once, call :meth:`lighting`.
    samples, refine_samples: rays per forward panel that could be shaded, and per partly lit panel.
    graze_tol: |cos delta| at or below which a face is grazing; offset: ray-origin offset [m]
    (default 1e-5 of the bounding-box diagonal). ``last_stats``: latest call's counts (STATS)."""

    def __init__(
        self,
        mesh: PanelMesh,
        mode: str = "raycast",
        samples: int = DEFAULT_SAMPLES,
        backend: str = "auto",
        *,
        refine_samples: int = DEFAULT_REFINE_SAMPLES,
        graze_tol: float = DEFAULT_GRAZE_TOL,
        offset: float | None = None,
        dilate: bool = True,
        prefilter: bool = True,
        convex_shadows: bool = True,
        scene=None,
        candidate_filter: CandidateFilter | None = None,
        hull_corners: dict | None = None,
        topology_store: TopologyStore | str | None = "default",
    ):
        mode = str(mode).lower()
        if mode not in MODES:
            raise ValueError(f"unknown shading mode {mode!r}; choose one of {', '.join(MODES)}")
        samples = int(samples)
        refine_samples = int(refine_samples)
        if samples < 1 or refine_samples < 0:
            raise ValueError("samples must be >= 1 and refine_samples >= 0")
        graze_tol = float(graze_tol)
        if not (0.0 <= graze_tol < 1.0):
            raise ValueError(f"graze_tol must be in [0, 1), got {graze_tol!r}")
        self.mesh = mesh
        self.mode = mode
        self.backend = resolve_backend(backend)
        self.samples = samples
        self.refine_samples = refine_samples
        self.graze_tol = graze_tol
        self.dilate = bool(dilate)
        self.prefilter = bool(prefilter)
        self.convex_shadows = bool(convex_shadows)
        lo, hi = mesh.bounds
        self.diagonal = float(np.linalg.norm(hi - lo)) or 1.0
        self.offset = (
            float(offset) if offset is not None else DEFAULT_OFFSET_FRACTION * self.diagonal
        )
        if not (math.isfinite(self.offset) and self.offset >= 0.0):
            raise ValueError(f"offset must be a finite number >= 0, got {offset!r}")
        self.last_stats: dict = {}
        # A single closed convex body never shades itself: nothing to build.
        self.trivial = mode == "none" or bool(mesh.report.convex)
        self.filter = self.scene = self.parts = self._points = None
        if not self.trivial and mode == "raycast":
            indexed = topology = None
            if candidate_filter is None or scene is None:  # (made once for both, or read back)
                store = TopologyStore.resolve(topology_store, "topology_store")
                indexed, topology = indexed_topology(mesh, self.diagonal, store)
            if candidate_filter is None:
                candidate_filter = CandidateFilter(mesh, topology=topology)
            self.filter = candidate_filter
            self.scene = scene or ray_scene(mesh, self.backend, indexed)
            self.backend = self.scene.backend
            if (
                self.convex_shadows
                and candidate_filter.convex.any()
                and 1 < candidate_filter.n_components <= MAX_COMPONENTS_FILTER
            ):
                self.parts = ConvexParts(
                    mesh, candidate_filter, self.diagonal, graze_tol, hull_corners
                )

    def lighting(self, u_G) -> PanelLighting:
        """Lit fraction and lit-centroid shift [m, G] of each panel at flow ``u_G`` (G, (3,))."""
        u = frames.unit_vector(u_G)
        if self.trivial:
            self.last_stats = dict.fromkeys(STATS, 0)
            return PanelLighting.all_lit(self.mesh.n_panels)
        if self.mode == "projection":
            shadowed = adbsat_shadowed(self.mesh, u)
            self.last_stats = {"rays": 0, "partly_lit": 0, "shaded": int(shadowed.sum())}
            return PanelLighting(np.where(shadowed, 0.0, 1.0))
        convex = None if self.parts is None else self.parts.lighting_many(u[None])
        return self._raycast([u], convex)[0]

    def lighting_many(self, directions) -> list:
        """:meth:`lighting` of each flow direction (M, 3) in G, the convex parts' shadows of all
        made at once (the same numbers); ``last_stats``: the last direction's."""
        us = [frames.unit_vector(u) for u in directions]
        if self.trivial or self.mode != "raycast" or self.parts is None or not us:
            return [self.lighting(u) for u in us]
        return self._raycast(us, self.parts.lighting_many(np.array(us)))

    def lighting_angles(self, aoa: float, aos: float) -> PanelLighting:
        """:meth:`lighting` for angle of attack and sideslip [rad] (frames module)."""
        return self.lighting(frames.flow_direction(aoa, aos))

    __call__ = lighting

    def candidates(self, u: np.ndarray, forward: np.ndarray) -> np.ndarray:
        """Indices of forward panels that could be shaded for unit flow direction ``u`` (G)."""
        if self.filter is None:
            return np.zeros(0, dtype=np.int64)
        if not self.prefilter:
            return np.flatnonzero(forward)
        return self.filter.candidates(u, forward)

    # -------------------------------------------------------------------------- raycast
    def _cast(self, origins, rows, jobs, first_face=False) -> np.ndarray:
        """Whether rays ``origins`` (R, 3) of the jobs ``rows`` (R,) (ascending) meet an occluder
        along their job's flow (or the first occluder they meet, -1 for none)."""
        out = np.zeros(len(rows), dtype=np.int64 if first_face else bool)
        cast = self.scene.first_face if first_face else self.scene.any_hit
        ends = np.searchsorted(rows, np.arange(len(jobs) + 1)).tolist()
        for (_, d, occluder, _), a, b in zip(jobs, ends, ends[1:]):  # (a loop over directions)
            if b > a:
                out[a:b] = cast(origins[a:b], d, occluder)
        return out

    def _cast_sets(self, sets, tri, lift, cand, job, jobs, rays):
        """[(lit (k, count), origins (k, count, 3)), ...] of sample sets [(rows, start, count)],
        each row's rays added to ``rays``."""
        out = []
        for idx, start, count in sets:
            a, b = sample_coordinates(cand[idx], start, count)
            p = sample_points(tri[idx], a, b, lift[idx])
            blocked = self._cast(p.reshape(-1, 3), np.repeat(job[idx], count), jobs)
            out.append((~blocked.reshape(p.shape[:2]), p))
            rays[idx] += count
        return out

    def _first_points(self, cand) -> np.ndarray:
        """The first pass's ray origins (K, 3 + S, 3) of panels ``cand``: 3 near the corners, S
        samples (made once per panel: they do not depend on the flow)."""
        if self._points is None:
            self._points = np.zeros((self.mesh.n_panels, 3 + self.samples, 3))
            self._made = np.zeros(self.mesh.n_panels, dtype=bool)
        new = np.unique(cand[~self._made[cand]])
        if new.size:
            a, b = sample_coordinates(new, 0, self.samples)
            a, b = (
                np.column_stack([np.broadcast_to(x, (new.size, 3)), y])
                for x, y in zip(CORNERS.T, (a, b))
            )
            lift = self.offset * self.mesh.normals[new]
            self._points[new] = sample_points(self.mesh.vertices[new], a, b, lift)
            self._made[new] = True
        return self._points[cand]

    def _corner_rays(self, corners, cand, job, jobs) -> tuple:
        """Corner rays lit (K, 3), and panels wholly shaded (K,) by one closed convex component."""
        n, rows = cand.size, np.repeat(job, 3)
        if not self.convex_shadows or not self.filter.convex.any():
            lit = ~self._cast(corners.reshape(-1, 3), rows, jobs).reshape(n, 3)
            return lit, np.zeros(n, dtype=bool)
        face = self._cast(corners.reshape(-1, 3), rows, jobs, first_face=True).reshape(n, 3)
        component = self.filter.component
        by = np.where(face >= 0, component[np.maximum(face, 0)], -1)
        first = by[:, 0]
        whole = (
            (first >= 0)
            & (by[:, 1] == first)
            & (by[:, 2] == first)
            & (first != component[cand])
            & self.filter.convex[np.maximum(first, 0)]
        )
        return face < 0, whole

    def _raycast(self, us, convex=None) -> list:
        """The lighting at each unit flow direction ``us``; ``convex``: the convex parts'
        shadows (:meth:`ConvexParts.lighting_many`), or None. The panels left to the rays of
        all the directions are cast together, each a row (its direction's job)."""
        mesh, n, m = self.mesh, self.mesh.n_panels, len(us)
        lit, done = np.ones((m, n)), np.zeros((m, n), dtype=bool)
        shifts = [(np.zeros(0, dtype=np.int64),) * 2 + (np.zeros((0, 3)),)]  # (row, panel, shift)
        stats = dict.fromkeys(STATS, 0)  # (the last direction's)
        prefiltered = convex is not None and self.prefilter
        if convex is not None:
            # the panels that only convex parts can shade: lit exactly, no rays
            candidate, n_forward, d, j, fraction, centroid = convex
            lit[d, j], done[d, j] = fraction, True
            partly = (fraction > 0.0) & (fraction < 1.0)
            shifts.append((d[partly], j[partly], centroid[partly] - mesh.barycentres[j[partly]]))
            stats |= dict(forward=int(n_forward[-1]), tested=int(candidate[-1].sum()))
            stats["exact"], rest = int(done[-1].sum()), candidate & ~done
        jobs = []
        todo = np.flatnonzero(rest.any(axis=1)).tolist() if prefiltered else range(m)
        for k in todo:  # (a loop over directions)
            c = -(mesh.normals @ us[k])
            if prefiltered:
                cand = np.flatnonzero(rest[k])
            else:
                forward = forward_mask(c, mesh.normals, self.graze_tol)
                cand = self.candidates(us[k], forward)
                if k == m - 1:
                    stats |= dict(forward=int(forward.sum()), tested=cand.size)
                cand = cand[~done[k, cand]]
            if cand.size:
                occluder = np.abs(c) > self.graze_tol
                jobs.append((cand, -us[k], None if occluder.all() else occluder, k))
        if jobs:
            shifts.append(self._cast_jobs(jobs, lit, stats if jobs[-1][3] == m - 1 else {}))
        self.last_stats = stats
        rows, index, shift = (np.concatenate(x) for x in zip(*shifts))
        order = np.lexsort((index, rows))
        return PanelLighting.many(lit, rows[order], index[order], shift[order])

    def _cast_jobs(self, jobs, fractions, stats) -> tuple:
        """The rays of ``jobs`` [(panels, -u, occluders or None, direction)] (rows: a panel of a
        job): their lit fractions put in ``fractions`` (directions, panels), the last job's
        counts in ``stats``; returns the partly lit ones' (direction, panel, shift [m])."""
        mesh, n = self.mesh, self.mesh.n_panels
        job = np.repeat(np.arange(len(jobs)), [len(j[0]) for j in jobs])
        cand = np.concatenate([j[0] for j in jobs])
        rays, refined = np.full(cand.size, 3), np.zeros(cand.size, dtype=bool)
        probed = np.zeros(0, dtype=np.int64)
        # First pass: 3 rays near the corners plus S interior samples. A shadow edge that
        # crosses a panel separates its corners, so the corner rays catch the partly lit panels
        # whose interior samples all fall on one side; they serve detection only.
        S = self.samples
        tri = mesh.vertices[cand]
        lift = self.offset * mesh.normals[cand]
        points = self._first_points(cand)
        corner_lit, whole = self._corner_rays(points[:, :3], cand, job, jobs)
        # The panels wholly in one convex component's shadow are shaded: their interior rays
        # would all be blocked too. The others cast their interior samples.
        rest = np.flatnonzero(~whole)
        origins = points[rest, 3:]  # (K', S, 3)
        blocked = self._cast(origins.reshape(-1, 3), np.repeat(job[rest], S), jobs).reshape(-1, S)
        rays[rest] += S
        lit = np.zeros((cand.size, S), dtype=bool)
        lit[rest] = ~blocked
        partial = (lit.any(axis=1) | corner_lit.any(axis=1)) & ~(
            lit.all(axis=1) & corner_lit.all(axis=1)
        )
        n_lit = lit.sum(axis=1)
        lit_sum = np.zeros((cand.size, 3))
        lit_sum[rest] = np.einsum("ks,ksj->kj", lit[rest], origins) - n_lit[rest, None] * lift[rest]
        total = np.full(cand.size, S)

        # Refine the panels found partly lit with R rays; probe their edge neighbours with R/8
        # (a shadow corner can slip between a panel's first samples) and refine those found
        # partly lit. Refined panels are estimated from their refinement rays alone: the
        # earlier rays decided the selection, and counting them would bias the estimate.
        R = self.refine_samples
        if partial.any() and R > 0:
            refine = np.flatnonzero(partial)
            probe = np.zeros(0, dtype=np.int64)
            n_probe = max(1, R // 8)
            adjacency = self.filter.adjacency
            if self.dilate and adjacency.size:
                mark = np.zeros((len(jobs), n), dtype=bool)
                mark[job[partial], cand[partial]] = True
                grow = np.zeros((len(jobs), n), dtype=bool)
                for e0, e1 in (adjacency.T, adjacency.T[::-1]):
                    k, e = np.nonzero(mark[:, e0])
                    grow[k, e1[e]] = True
                probe = np.flatnonzero(grow[job, cand] & ~partial)
            sets = [(refine, S, R), (probe, S, n_probe)]
            lit_sets = self._cast_sets(sets, tri, lift, cand, job, jobs, rays)
            lit_p = lit_sets[1][0]
            again = probe[lit_p.any(axis=1) & ~lit_p.all(axis=1)]
            final = [(refine, lit_sets[0])]
            if again.size:
                more = self._cast_sets([(again, S + n_probe, R)], tri, lift, cand, job, jobs, rays)
                final.append((again, more[0]))
            for idx, (lit_r, origins_r) in final:
                n_lit[idx] = lit_r.sum(axis=1)
                lit_sum[idx] = (
                    np.einsum("ks,ksj->kj", lit_r, origins_r) - n_lit[idx, None] * lift[idx]
                )
                total[idx] = R
            refined[refine], refined[again], probed = True, True, probe

        frac = n_lit / total
        part = (n_lit > 0) & (n_lit < total)
        shift = lit_sum[part] / n_lit[part][:, None] - mesh.barycentres[cand[part]]
        last = job == len(jobs) - 1
        counted = dict(rays=rays, corner_shaded=whole, partly_lit=part, refined=refined)
        stats |= {name: int(v[last].sum()) for name, v in counted.items()}
        stats["probed"] = int(last[probed].sum())
        direction = np.array([k for *_, k in jobs])[job]
        fractions[direction, cand] = frac
        return direction[part], cand[part], shift


def make_shader(
    mesh: PanelMesh,
    mode: str = "raycast",
    samples: int = DEFAULT_SAMPLES,
    backend: str = "auto",
    **options,
) -> Shader:
    """Build a :class:`Shader` for ``mesh`` (metres, mesh frame G).
    mode: ``"raycast"``, ``"projection"`` or ``"none"``; samples: rays per panel (raycast), >= 1.
    backend: ``"auto"`` (Embree if installed, else numpy), ``"embree"`` or ``"numpy"``.
    ValueError: a mode, backend or option outside its allowed values (named)."""
    return Shader(mesh, mode=mode, samples=samples, backend=backend, **options)


def shade(mesh: PanelMesh, u_G, mode: str = "raycast", **options) -> PanelLighting:
    """One-shot shading of ``mesh`` for flow direction ``u_G`` (builds a throw-away Shader)."""
    return make_shader(mesh, mode=mode, **options).lighting(u_G)
