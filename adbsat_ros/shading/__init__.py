"""Which part of each panel the flow reaches: shaders, ray casting, and the shading cache.

Modules:

- :mod:`~adbsat_ros.shading.lighting`: :class:`PanelLighting`, the result (lit fractions and
  lit-centroid shifts, stored sparsely, read-only, with a content key), and
  :class:`LightingBlend`, a weighted mean of lightings.
- :mod:`~adbsat_ros.shading.shader`: :class:`Shader` and :func:`make_shader`, the three modes
  (none, ADBSat's projection, ray cast) behind one interface.
- :mod:`~adbsat_ros.shading.rays`: ray casting, one interface;
  :mod:`~adbsat_ros.shading.rays_embree`
  (Embree through embreex) and :mod:`~adbsat_ros.shading.rays_numpy` (the reference and fallback)
  behind it.
- :mod:`~adbsat_ros.shading.candidates`, :mod:`~adbsat_ros.shading.sampling`,
  :mod:`~adbsat_ros.shading.flow_plane`: which panels are tested, where their rays start, and the
  geometry of the plane normal to the flow.
- :mod:`~adbsat_ros.shading.projection`: ADBSat's ``shadowAnaly``.
- :mod:`~adbsat_ros.shading.cache` and :mod:`~adbsat_ros.shading.cube_map`: the shading cache,
  keyed by joint configuration and cube-map cell of the flow direction, with a stated error
  bound; :mod:`~adbsat_ros.shading.joint_grid`: the grid of joint configurations;
  :mod:`~adbsat_ros.shading.cell_triangles`: the triangles over the cell centres through which
  it interpolates (:class:`~adbsat_ros.shading.lighting.LightingBlend`).

Imports geometry only. Details and accuracy: docs/shading.md.
"""
