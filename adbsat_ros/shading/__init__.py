"""Which part of each panel the flow reaches: shaders, ray casting, and the shading cache.

Modules:

- :mod:`~adbsat_ros.shading.lighting`: :class:`PanelLighting` (lit fractions and lit-centroid
  shifts) and :class:`LightingBlend`, a weighted mean of lightings.
- :mod:`~adbsat_ros.shading.shader`: :class:`Shader` and :func:`make_shader`, the three modes.
- :mod:`~adbsat_ros.shading.rays`: ray casting, one interface over
  :mod:`~adbsat_ros.shading.rays_embree` and :mod:`~adbsat_ros.shading.rays_numpy`.
- :mod:`~adbsat_ros.shading.candidates`, :mod:`~adbsat_ros.shading.sampling`,
  :mod:`~adbsat_ros.shading.flow_plane`: which panels are tested, where their rays start, and
  the plane normal to the flow.
- :mod:`~adbsat_ros.shading.projection`: ADBSat's ``shadowAnaly``.
- :mod:`~adbsat_ros.shading.cache` and :mod:`~adbsat_ros.shading.cube_map`: the shading cache
  by joint configuration and cube-map cell; :mod:`~adbsat_ros.shading.joint_grid` the grid of
  joint configurations; :mod:`~adbsat_ros.shading.cell_triangles` the interpolation triangles.

Imports geometry only. Details and accuracy: docs/shading.md.
"""
