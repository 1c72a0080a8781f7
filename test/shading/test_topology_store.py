"""The shader's topology kept on disk: a shader made from it shades exactly as one made anew."""

import os
import subprocess
import sys

import numpy as np
import pytest
from meshes import write_obj

from adbsat_ros.geometry import frames
from adbsat_ros.geometry.example_satellite import example_satellite
from adbsat_ros.npz_store import CACHE_DIR_VARIABLE
from adbsat_ros.shading.shader import make_shader
from adbsat_ros.shading.topology_store import TopologyStore

#: Flow directions where the example satellite's body and wings shade each other.
DIRECTIONS = [
    frames.flow_direction(np.radians(a), np.radians(b))
    for a, b in [(0.0, 90.0), (20.0, 75.0), (-35.0, -100.0), (60.0, 170.0)]
]


def test_a_shader_from_the_store_shades_as_one_made_anew(tmp_path):
    mesh = example_satellite()
    store = TopologyStore(tmp_path / "store")
    made = make_shader(mesh, topology_store=store)
    assert (store.hits, store.misses, store.writes) == (0, 1, 1)
    again = make_shader(mesh, topology_store=store)
    assert (store.hits, store.misses, store.writes) == (1, 1, 1)
    plain = make_shader(mesh, topology_store=None)
    shaded = 0
    for u in DIRECTIONS:
        expected = plain.lighting(u)
        for shader in (made, again):
            lighting = shader.lighting(u)
            assert lighting.lit_fraction.tobytes() == expected.lit_fraction.tobytes()
            assert lighting.shift_index.tobytes() == expected.shift_index.tobytes()
            assert lighting.shift.tobytes() == expected.shift.tobytes()
        shaded += int((expected.lit_fraction < 1.0).sum())
    assert shaded > 0  # (the parts do shade each other there)


def test_other_panels_are_another_entry(tmp_path):
    store = TopologyStore(tmp_path / "store")
    make_shader(example_satellite(), topology_store=store)
    make_shader(example_satellite(max_edge=0.2), topology_store=store)
    assert (store.hits, store.misses) == (0, 2) and len(store) == 2


def test_a_damaged_entry_is_made_again(tmp_path):
    mesh = example_satellite()
    store = TopologyStore(tmp_path / "store")
    make_shader(mesh, topology_store=store)
    (entry,) = (tmp_path / "store").glob("*.npz")
    entry.write_bytes(entry.read_bytes()[:100])  # cut short
    u = DIRECTIONS[1]
    lighting = make_shader(mesh, topology_store=store).lighting(u)
    assert (store.hits, store.misses, store.writes) == (0, 2, 2)
    expected = make_shader(mesh, topology_store=None).lighting(u)
    assert lighting.lit_fraction.tobytes() == expected.lit_fraction.tobytes()


def test_a_concave_mesh_loaded_again_is_shaded_without_trimesh(tmp_path):
    """A mesh file and its shader's topology both read back: the second process imports no
    trimesh, and its lit area is the first one's."""
    path = tmp_path / "sat.obj"
    write_obj(example_satellite(), path)
    u = DIRECTIONS[1].tolist()
    code = (
        "import sys; from adbsat_ros.geometry.loading import load_mesh; "
        "from adbsat_ros.shading.shader import make_shader; "
        "from adbsat_ros.shading.lighting import lit_projected_area; "
        f"m = load_mesh({str(path)!r}); u = {u!r}; "
        "area = lit_projected_area(m, u, make_shader(m).lighting(u)); "
        "print(int('trimesh' in sys.modules), repr(area))"
    )
    env = {**os.environ, CACHE_DIR_VARIABLE: str(tmp_path / "cache")}
    first, second = (
        subprocess.run(
            [sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True
        ).stdout.split()
        for _ in range(2)
    )
    assert first[0] == "1" and second[0] == "0"
    assert first[1] == second[1]


def test_a_store_named_wrongly_is_refused():
    with pytest.raises(ValueError, match="topology_store"):
        make_shader(example_satellite(), topology_store="defualt")
