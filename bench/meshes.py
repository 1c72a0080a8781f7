"""The tests' mesh helpers (test/meshes.py), for the benches: ``grid_box`` and ``write_obj``."""

import runpy
from pathlib import Path

_HELPERS = runpy.run_path(str(Path(__file__).resolve().parents[1] / "test" / "meshes.py"))
grid_box, write_obj = _HELPERS["grid_box"], _HELPERS["write_obj"]
