"""Checked meshes kept on disk by their file's content, read back instead of parsed again.

Loading a mesh file parses it with trimesh and checks it (orientation, closedness, convexity
per connected component); importing trimesh alone takes about 0.6 s, more than a one-attitude
``adbsat-ros coeff`` may take (docs/benchmarks.md, command line start-up). :class:`MeshStore`
keeps what the checks made, so that the next load of the same file reads the panels back
with numpy alone, as ADBSat reads a mesh once imported to a .mat file.

Key: the SHA-256 of the file's bytes, the scale to metres, whether normals are fixed, the
store's format and the package version (a new release parses files anew). Value: the
:class:`~adbsat_ros.geometry.mesh.PanelMesh` arrays, material names and report, one ``.npz``
file per key (no pickles). Bound: the ``max_entries`` most recently used files (a hit touches
its file; the oldest beyond the bound are removed after a write). Counters: ``hits``,
``misses``, ``writes``.

Where: ``$ADBSAT_ROS_CACHE_DIR/meshes``, by default ``$XDG_CACHE_HOME/adbsat_ros/meshes`` or
``~/.cache/adbsat_ros/meshes``; ``ADBSAT_ROS_CACHE_DIR=off`` turns the store off. A store that
cannot be written (a read-only home, a full disk) or an entry that cannot be read is passed
over with a debug message: loading then works as without the store.
"""

from __future__ import annotations

import hashlib
import logging
import os
import tempfile
from pathlib import Path

import numpy as np

from adbsat_ros._version import __version__
from adbsat_ros.geometry.mesh import MeshReport, PanelMesh

log = logging.getLogger(__name__)

#: Environment variable naming the cache directory (``off``: no store).
CACHE_DIR_VARIABLE = "ADBSAT_ROS_CACHE_DIR"
#: Version of the entries' layout (part of the key).
FORMAT = 1
#: Files kept by default.
DEFAULT_MAX_ENTRIES = 64
#: The report's fields, in the order they are stored.
_REPORT_FIELDS = (
    "dropped_zero_area",
    "flipped_components",
    "open_components",
    "watertight",
    "convex",
    "components",
)
_ARRAYS = ("vertices", "normals", "areas", "barycentres", "material_index")


class MeshStore:
    """Checked meshes on disk, by the content of the file they were loaded from.

    Parameters
    ----------
    directory : path-like
        Where the entries are kept (made when first written).
    max_entries : int
        Entries kept, >= 1.

    Attributes
    ----------
    hits, misses, writes : int
        Loads served from the store, loads that were not, and entries written.
    """

    def __init__(self, directory, max_entries: int = DEFAULT_MAX_ENTRIES):
        if int(max_entries) < 1:
            raise ValueError(f"max_entries must be >= 1, got {max_entries!r}")
        self.directory = Path(directory)
        self.max_entries = int(max_entries)
        self.hits = self.misses = self.writes = 0

    @staticmethod
    def key(path, scale: float, fix_normals: bool) -> str:
        """The key of the file ``path`` loaded at ``scale`` with or without ``fix_normals``
        (hex SHA-256). Raises OSError if the file cannot be read."""
        digest = hashlib.sha256(Path(path).read_bytes())
        digest.update(f"|{float(scale)!r}|{bool(fix_normals)}|{FORMAT}|{__version__}".encode())
        return digest.hexdigest()

    def _entry(self, key: str) -> Path:
        return self.directory / f"{key}.npz"

    def get(self, key: str, source: str) -> PanelMesh | None:
        """The mesh kept for ``key`` (named ``source``), or None (counted as a miss)."""
        entry = self._entry(key)
        try:
            with np.load(entry, allow_pickle=False) as data:
                arrays = {name: np.ascontiguousarray(data[name]) for name in _ARRAYS}
                names = tuple(str(name) for name in data["material_names"])
                report = data["report"].tolist()
        except FileNotFoundError:
            self.misses += 1
            return None
        except (OSError, ValueError, KeyError) as exc:  # unreadable or damaged: made anew
            log.debug("mesh store: cannot read %s (%s)", entry, exc)
            self.misses += 1
            return None
        try:
            os.utime(entry)  # (the most recently used now)
        except OSError:  # (a store one may read but not write)
            pass
        self.hits += 1
        return PanelMesh(
            **arrays,
            material_names=names,
            report=MeshReport(
                **{
                    name: (bool(value) if name in ("watertight", "convex") else int(value))
                    for name, value in zip(_REPORT_FIELDS, report)
                }
            ),
            source=source,
        )

    def put(self, key: str, mesh: PanelMesh) -> None:
        """Keep ``mesh`` for ``key`` (written whole or not at all), then drop the least
        recently used entries beyond the bound."""
        try:
            self.directory.mkdir(parents=True, exist_ok=True)
            handle, temporary = tempfile.mkstemp(suffix=".npz.part", dir=self.directory)
            try:
                with os.fdopen(handle, "wb") as fh:
                    np.savez(
                        fh,
                        **{name: getattr(mesh, name) for name in _ARRAYS},
                        material_names=np.array(mesh.material_names, dtype=str),
                        report=np.array(
                            [int(getattr(mesh.report, name)) for name in _REPORT_FIELDS]
                        ),
                    )
                os.replace(temporary, self._entry(key))
            except BaseException:
                Path(temporary).unlink(missing_ok=True)
                raise
            self.writes += 1
            self._prune()
        except OSError as exc:
            log.debug("mesh store: cannot write to %s (%s)", self.directory, exc)

    def _prune(self) -> None:
        """Remove the least recently used entries beyond ``max_entries``."""
        entries = []
        for entry in self.directory.glob("*.npz"):
            try:
                entries.append((entry.stat().st_mtime_ns, entry))
            except FileNotFoundError:  # (removed meanwhile by another process)
                continue
        entries.sort(reverse=True)
        for _, entry in entries[self.max_entries :]:
            entry.unlink(missing_ok=True)

    def __len__(self) -> int:
        return sum(1 for _ in self.directory.glob("*.npz")) if self.directory.is_dir() else 0

    def info(self) -> dict:
        """Directory, bound, entries and counters, for reports."""
        return {
            "directory": str(self.directory),
            "max_entries": self.max_entries,
            "entries": len(self),
            "hits": self.hits,
            "misses": self.misses,
            "writes": self.writes,
        }


_stores: dict = {}  # directory -> its MeshStore (one per directory, its counters the process's)


def default_store() -> MeshStore | None:
    """The store of :data:`CACHE_DIR_VARIABLE`'s directory (read now), or None if it is
    ``off``."""
    base = os.environ.get(CACHE_DIR_VARIABLE)
    if base is None:
        xdg = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
        base = os.path.join(xdg, "adbsat_ros")
    elif base.strip().lower() == "off":
        return None
    directory = os.path.join(base, "meshes")
    store = _stores.get(directory)
    if store is None:
        store = _stores[directory] = MeshStore(directory)
    return store
