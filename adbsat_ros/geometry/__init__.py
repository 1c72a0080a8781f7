"""The satellite's surface: triangulated meshes, their checks, and ADBSat's frames.

Modules:

- :mod:`~adbsat_ros.geometry.mesh`: :class:`PanelMesh` (vertices, outward normals, areas,
  barycentres, materials of every panel, in metres, mesh frame G) and the checks that make one.
- :mod:`~adbsat_ros.geometry.loading`: mesh files (any format trimesh reads; .obj materials from
  ``usemtl``) and the bundled bodies by name.
- :mod:`~adbsat_ros.geometry.mesh_files`: mesh files read whole: text decoded by its byte-order
  mark, .obj and .off line by line (a line that cannot be read whole refused with its number).
- :mod:`~adbsat_ros.geometry.shapes`: closed shapes with regular face grids, parts joined.
- :mod:`~adbsat_ros.geometry.example_satellite`: the bundled example satellite.
- :mod:`~adbsat_ros.geometry.articulated`: a URDF's links and joints as panels for any joint
  configuration, and the loads per link and joint; :mod:`~adbsat_ros.geometry.example_urdf` the
  bundled URDFs (the example satellite with hinged wings, a body with four steerable fins).
- :mod:`~adbsat_ros.geometry.poses`: a URDF's joint tree, checked, and its links' poses by
  yourdfpy's forward kinematics.
- :mod:`~adbsat_ros.geometry.concave_bodies`: bundled bodies where molecules meet the surface
  more than once (a cylinder with deep grooves in its front face, the plain cylinder, a box
  with a deep intake).
- :mod:`~adbsat_ros.geometry.frames`: the mesh, body, wind and flight frames, aoa/aos and the flow
  direction, quaternions (docs/physics.md, section 2).

Next to the bottom layer: of adbsat_ros it imports only the table of valid ranges (a mesh's size).
"""
