"""The satellite's surface: triangulated meshes, their checks, and ADBSat's frames.

Modules:

- :mod:`~adbsat_ros.geometry.mesh`: :class:`PanelMesh` (metres, frame G) and its checks.
- :mod:`~adbsat_ros.geometry.loading`: mesh files (trimesh formats), bundled bodies by name.
- :mod:`~adbsat_ros.geometry.mesh_files`: mesh files read whole, .obj and .off line by line.
- :mod:`~adbsat_ros.geometry.shapes`: closed shapes with regular face grids, parts joined.
- :mod:`~adbsat_ros.geometry.example_satellite`: the bundled example satellite.
- :mod:`~adbsat_ros.geometry.articulated`: a URDF's links and joints as panels for any joint
  configuration; :mod:`~adbsat_ros.geometry.example_urdf` the bundled URDFs.
- :mod:`~adbsat_ros.geometry.poses`: a URDF's joint tree and its links' poses (yourdfpy).
- :mod:`~adbsat_ros.geometry.concave_bodies`: bundled concave bodies.
- :mod:`~adbsat_ros.geometry.frames`: the mesh, body, wind and flight frames, aoa/aos,
  quaternions (docs/physics.md, section 2).

Next to the bottom layer: of adbsat_ros it imports only the table of valid ranges.
"""
