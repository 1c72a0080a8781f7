"""The satellite's surface: triangulated meshes, their checks, and ADBSat's frames.

- :mod:`.mesh`: :class:`PanelMesh` (metres, frame G); :mod:`.loading`, :mod:`.mesh_files`,
  :mod:`.mesh_store`: mesh files and bundled bodies.
- :mod:`.example_satellite` (and parts joined into one mesh), :mod:`.concave_bodies`,
  :mod:`.example_urdf`: bundled bodies.
- :mod:`.articulated`, :mod:`.poses`: a URDF's links and joints as panels (yourdfpy).
- :mod:`.frames`: mesh, body, wind and flight frames, aoa/aos (docs/physics.md, section 2).
"""
