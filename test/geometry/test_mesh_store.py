"""The store of checked meshes: what it reads back is what loading made, keyed by content."""

import dataclasses
import logging
import os
import subprocess
import sys

import numpy as np
import pytest
import trimesh
from meshes import write_obj

from adbsat_ros.geometry.example_satellite import example_satellite
from adbsat_ros.geometry.loading import load_mesh
from adbsat_ros.geometry.mesh import MeshError
from adbsat_ros.geometry.mesh_store import MeshStore
from adbsat_ros.npz_store import CACHE_DIR_VARIABLE

ARRAYS = ("vertices", "normals", "areas", "barycentres", "material_index")


def assert_same_mesh(a, b):
    """Bit for bit: every array, the material names and the report."""
    for name in ARRAYS:
        x, y = getattr(a, name), getattr(b, name)
        assert x.dtype == y.dtype and x.shape == y.shape
        assert x.tobytes() == y.tobytes(), name
    assert a.material_names == b.material_names
    assert dataclasses.astuple(a.report) == dataclasses.astuple(b.report)


@pytest.fixture
def satellite_obj(tmp_path):
    """The example satellite (two materials, closed, not convex) as an OBJ file."""
    path = tmp_path / "sat.obj"
    write_obj(example_satellite(), path)
    return path


def test_a_second_load_reads_back_exactly_what_the_first_made(tmp_path, satellite_obj):
    store = MeshStore(tmp_path / "store")
    first = load_mesh(satellite_obj, store=store)
    assert (store.hits, store.misses, store.writes) == (0, 1, 1)
    again = load_mesh(satellite_obj, store=store)
    assert (store.hits, store.misses, store.writes) == (1, 1, 1)
    assert_same_mesh(again, first)
    assert_same_mesh(again, load_mesh(satellite_obj, store=None))
    assert again.source == str(satellite_obj)
    assert again.report.components == 3 and not again.report.convex  # (body and two wings)
    assert again.fingerprint() == first.fingerprint()


def test_the_key_is_the_content_with_the_scale_and_the_normal_fixing(tmp_path):
    store = MeshStore(tmp_path / "store")
    box = trimesh.creation.box(extents=(1.0, 2.0, 3.0))
    a, b = tmp_path / "a.stl", tmp_path / "b.stl"
    box.export(a)
    box.export(b)
    load_mesh(a, store=store)
    load_mesh(b, store=store)  # the same bytes under another name
    assert (store.hits, store.misses) == (1, 1)
    scaled = load_mesh(a, scale=2.0, store=store)
    assert store.misses == 2 and scaled.total_area == pytest.approx(4 * 22.0)
    load_mesh(a, fix_normals=False, store=store)
    assert store.misses == 3
    box.copy().apply_translation((0.5, 0.0, 0.0)).export(a)  # the file changed
    moved = load_mesh(a, store=store)
    assert store.misses == 4
    assert moved.barycentres[:, 0].mean() == pytest.approx(0.5)


def test_warnings_of_the_checks_are_told_again_on_a_hit(tmp_path, caplog):
    # a box wound inside out: flipped by the checks, and the warning comes with every load
    path = tmp_path / "inside_out.stl"
    box = trimesh.creation.box(extents=(1.0, 2.0, 3.0))
    trimesh.Trimesh(box.vertices, box.faces[:, ::-1], process=False).export(path)
    store = MeshStore(tmp_path / "store")
    for _ in range(2):
        caplog.clear()
        with caplog.at_level(logging.WARNING):
            mesh = load_mesh(path, store=store)
        assert "inward-facing normals" in caplog.text
        assert mesh.report.flipped_components == 1
    assert store.hits == 1


def test_a_damaged_entry_is_made_again(tmp_path, satellite_obj):
    store = MeshStore(tmp_path / "store")
    first = load_mesh(satellite_obj, store=store)
    (entry,) = (tmp_path / "store").glob("*.npz")
    entry.write_bytes(b"not a numpy file")
    again = load_mesh(satellite_obj, store=store)
    assert (store.hits, store.misses, store.writes) == (0, 2, 2)
    assert_same_mesh(again, first)
    assert_same_mesh(load_mesh(satellite_obj, store=store), first)
    assert store.hits == 1


def test_a_store_on_a_file_is_passed_over(tmp_path, satellite_obj):
    blocker = tmp_path / "a_file"
    blocker.write_text("")
    store = MeshStore(blocker / "store")  # a directory that cannot be made
    mesh = load_mesh(satellite_obj, store=store)
    assert store.writes == 0 and store.misses == 1
    assert_same_mesh(mesh, load_mesh(satellite_obj, store=None))


def test_the_least_recently_used_entries_go_beyond_the_bound(tmp_path):
    store = MeshStore(tmp_path / "store", max_entries=2)
    paths = []
    for k in range(3):
        path = tmp_path / f"box{k}.stl"
        trimesh.creation.box(extents=(1.0 + k, 1.0, 1.0)).export(path)
        paths.append(path)
    entries = [tmp_path / "store" / f"{MeshStore.key(p, 1.0, True)}.npz" for p in paths]
    load_mesh(paths[0], store=store)
    load_mesh(paths[1], store=store)
    os.utime(entries[1], (1, 1))  # box1 the least recently used
    load_mesh(paths[0], store=store)  # a hit: box0 used again
    load_mesh(paths[2], store=store)
    assert [e.exists() for e in entries] == [True, False, True]
    assert len(store) == 2
    # a temporary file a killed writer left: removed at a later write once it is a day old
    fresh, old = tmp_path / "store" / "a.npz.part", tmp_path / "store" / "b.npz.part"
    fresh.write_bytes(b"")
    old.write_bytes(b"")
    os.utime(old, (1, 1))
    trimesh.creation.box(extents=(5.0, 1.0, 1.0)).export(paths[1])
    load_mesh(paths[1], store=store)
    assert fresh.exists() and not old.exists()
    with pytest.raises(ValueError, match="max_entries"):
        MeshStore(tmp_path, max_entries=0)


def test_a_missing_or_unreadable_file_is_still_a_mesh_error(tmp_path):
    store = MeshStore(tmp_path / "store")
    with pytest.raises(MeshError, match="not found"):
        load_mesh(tmp_path / "none.stl", store=store)
    junk = tmp_path / "junk.stl"
    junk.write_bytes(b"\x00\x01garbage")
    with pytest.raises(MeshError, match="junk.stl"):
        load_mesh(junk, store=store)
    assert store.writes == 0
    with pytest.raises(ValueError, match="store"):
        load_mesh(junk, store="elsewhere")


def test_the_default_store_follows_the_environment(tmp_path, monkeypatch):
    monkeypatch.setenv(CACHE_DIR_VARIABLE, str(tmp_path / "here"))
    store = MeshStore.resolve("default")
    assert store.directory == tmp_path / "here" / "meshes"
    assert (
        MeshStore.resolve("default") is store
    )  # one per directory: its counters are the process's
    monkeypatch.setenv(CACHE_DIR_VARIABLE, "off")
    assert MeshStore.resolve("default") is None
    monkeypatch.delenv(CACHE_DIR_VARIABLE)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    assert MeshStore.resolve("default").directory == tmp_path / "xdg" / "adbsat_ros" / "meshes"


def test_a_mesh_read_back_needs_no_trimesh(tmp_path):
    """The point of the store: a mesh loaded before is loaded again without importing trimesh
    (a fresh interpreter, the mesh's shading trivial: a convex body)."""
    path = tmp_path / "sphere.stl"
    trimesh.creation.icosphere(subdivisions=2).export(path)
    code = (
        "import sys; from adbsat_ros.geometry.loading import load_mesh; "
        "from adbsat_ros.physics.panel_method import PanelMethod; "
        "from adbsat_ros.physics.freestream import FreeStream; "
        f"m = load_mesh({str(path)!r}); "
        "PanelMethod(m, 'sentman').coefficients(FreeStream(7700.0, 900.0, mean_mass_amu=16.0)); "
        "print(int('trimesh' in sys.modules), m.n_panels)"
    )
    env = {**os.environ, CACHE_DIR_VARIABLE: str(tmp_path / "cache")}
    runs = [
        subprocess.run(
            [sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True
        ).stdout.split()
        for _ in range(2)
    ]
    assert runs == [["1", "320"], ["0", "320"]]
    assert len(list((tmp_path / "cache" / "meshes").glob("*.npz"))) == 1


def test_entries_made_by_other_code_are_not_read_back(tmp_path, satellite_obj, monkeypatch):
    """The key holds the code that makes the entries: another parser or checks (here a
    changed fingerprint of them) miss, and the file is parsed again."""
    store = MeshStore(tmp_path / "store")
    load_mesh(satellite_obj, store=store)
    # other code making the entries: one more module among their makers
    monkeypatch.setattr(MeshStore, "MAKERS", (*MeshStore.MAKERS, "adbsat_ros.bounds"))
    load_mesh(satellite_obj, store=store)
    assert (store.hits, store.misses) == (0, 2)


def test_formats_with_other_files_are_not_kept(tmp_path):
    store = MeshStore(tmp_path / "store")
    path = tmp_path / "box.glb"
    trimesh.creation.box(extents=(1.0, 2.0, 3.0)).export(path)
    for _ in range(2):
        assert load_mesh(path, store=store).n_panels == 12
    assert (store.hits, store.misses, store.writes) == (0, 0, 0)


def test_every_warning_of_the_checks_is_told_again(tmp_path, caplog):
    # an open box (two faces missing) with a zero-area face
    box = trimesh.creation.box(extents=(1.0, 2.0, 3.0))
    faces = np.vstack([box.faces[:10], [[0, 0, 1]]])
    path = tmp_path / "open.stl"
    trimesh.Trimesh(box.vertices, faces, process=False).export(path)
    store = MeshStore(tmp_path / "store")
    texts = []
    for _ in range(2):
        caplog.clear()
        with caplog.at_level(logging.WARNING):
            load_mesh(path, store=store)
        texts.append([r.getMessage() for r in caplog.records])
    assert store.hits == 1 and texts[0] == texts[1]
    assert any("open or non-manifold" in t for t in texts[1])


def test_an_empty_cache_variable_means_the_default_place(tmp_path, monkeypatch):
    monkeypatch.setenv(CACHE_DIR_VARIABLE, "")
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    assert MeshStore.resolve("default").directory == tmp_path / "xdg" / "adbsat_ros" / "meshes"


def test_entries_are_readable_by_others(tmp_path, satellite_obj):
    store = MeshStore(tmp_path / "store")
    load_mesh(satellite_obj, store=store)
    (entry,) = (tmp_path / "store").glob("*.npz")
    assert entry.stat().st_mode & 0o777 == 0o644
