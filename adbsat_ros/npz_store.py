"""Named numpy arrays kept on disk by key: the stores of checked meshes and shader topology.

One ``.npz`` per key (no pickles), written whole or not at all, the ``max_entries`` most recently
used kept. An unwritable directory or unreadable entry is passed over: the data is made again.
Directories: ``$ADBSAT_ROS_CACHE_DIR/<kind>``, by default ``$XDG_CACHE_HOME/adbsat_ros/<kind>``
or ``~/.cache/adbsat_ros/<kind>``; ``ADBSAT_ROS_CACHE_DIR=off`` turns every store off.
"""

from __future__ import annotations

import contextlib
import hashlib
import importlib.util
import logging
import os
import tempfile
import time
import zipfile
from pathlib import Path

import numpy as np

log = logging.getLogger(__name__)

#: Environment variable naming the cache directory (``off``: no store).
CACHE_DIR_VARIABLE = "ADBSAT_ROS_CACHE_DIR"
#: Entries kept by default.
DEFAULT_MAX_ENTRIES = 64
#: Age [s] beyond which a temporary file of a write is taken as left by a killed process.
STALE_PART_S = 86400.0


class NpzStore:
    """Named arrays on disk by key, in ``directory`` (made when first written), at most
    ``max_entries`` (>= 1); ``hits``, ``misses`` and ``writes`` count reads and writes."""

    #: Set by each kind of store: its directory's name under the cache directory, its
    #: entries' layout version, and the modules and packages whose code makes its entries
    #: (:func:`code_fingerprint`), all part of its keys (:meth:`finish_key`).
    KIND = "arrays"
    FORMAT = 1
    MAKERS: tuple = ()
    PACKAGES: tuple = ()

    def __init__(self, directory, max_entries: int = DEFAULT_MAX_ENTRIES):
        if int(max_entries) < 1:
            raise ValueError(f"max_entries must be >= 1, got {max_entries!r}")
        self.directory = Path(directory)
        self.max_entries = int(max_entries)
        self.hits = self.misses = self.writes = 0

    @classmethod
    def finish_key(cls, digest, *parts) -> str:
        """The key (hex SHA-256) of ``digest`` (a hashlib SHA-256 of the entry's data), the
        ``parts`` that also change the entry, the store's format and the code that makes it."""
        code = code_fingerprint(cls.MAKERS, cls.PACKAGES)
        digest.update("|".join(map(repr, (*parts, cls.KIND, cls.FORMAT, code))).encode())
        return digest.hexdigest()

    @classmethod
    def resolve(cls, store, name: str = "store"):
        """``store`` as a user's parameter ``name`` gives it: ``"default"`` is :func:`shared_store`
        (None if stores are off), a store or None as is; ValueError naming it for another string."""
        if isinstance(store, str):
            if store != "default":
                raise ValueError(
                    f"{name} must be a {cls.__name__}, 'default' or None, got {store!r}"
                )
            return shared_store(cls)
        return store

    def entry(self, key: str) -> Path:
        """The file of ``key``."""
        return self.directory / f"{key}.npz"

    def read(self, key: str, names) -> dict | None:
        """The arrays ``names`` kept for ``key``, or None (counted as a miss) if there is no
        entry or it cannot be read whole."""
        entry = self.entry(key)
        try:
            with np.load(entry, allow_pickle=False) as data:
                arrays = {name: np.ascontiguousarray(data[name]) for name in names}
        except FileNotFoundError:
            self.misses += 1
            return None
        except (OSError, ValueError, KeyError, EOFError, zipfile.BadZipFile) as exc:  # (damaged)
            log.debug("%s: cannot read %s (%s)", type(self).__name__, entry, exc)
            self.misses += 1
            return None
        with contextlib.suppress(OSError):  # (a store one may read but not write)
            os.utime(entry)  # (the most recently used now)
        self.hits += 1
        return arrays

    def write(self, key: str, arrays: dict) -> bool:
        """Keep ``arrays`` (name to array) for ``key``; whether they were written."""
        try:
            self.directory.mkdir(parents=True, exist_ok=True)
            handle, temporary = tempfile.mkstemp(suffix=".npz.part", dir=self.directory)
            try:
                with os.fdopen(handle, "wb") as fh:
                    np.savez(fh, **arrays)
                os.chmod(temporary, 0o644)  # (mkstemp makes it 0600: a shared cache reads it)
                os.replace(temporary, self.entry(key))
            except BaseException:
                Path(temporary).unlink(missing_ok=True)
                raise
        except OSError as exc:
            log.debug("%s: cannot write to %s (%s)", type(self).__name__, self.directory, exc)
            self._prune()  # (a full disk: room for the next write)
            return False
        self.writes += 1
        self._prune()
        return True

    def _prune(self) -> None:
        """Remove the entries beyond ``max_entries`` and, after a day, temporary files of
        killed writes; a file that cannot be removed (another user's) is left."""
        try:
            self._remove_old()
        except OSError as exc:
            log.debug("%s: cannot prune %s (%s)", type(self).__name__, self.directory, exc)

    def _remove_old(self) -> None:
        stale = time.time() - STALE_PART_S
        for part in self.directory.glob("*.npz.part"):
            try:
                if part.stat().st_mtime < stale:
                    part.unlink()
            except FileNotFoundError:  # (renamed or removed meanwhile by another process)
                continue
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


def cache_directory(kind: str) -> Path | None:
    """The directory of the stores of ``kind`` (:data:`CACHE_DIR_VARIABLE` read now), or None
    if ``off``."""
    base = os.environ.get(CACHE_DIR_VARIABLE)
    if not base or not base.strip():  # (unset or empty: the default place)
        xdg = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
        base = os.path.join(xdg, "adbsat_ros")
    elif base.strip().lower() == "off":
        return None
    return Path(base) / kind


def code_fingerprint(modules: tuple, packages: tuple = ()) -> str:
    """A short hash of the source of ``modules`` and the installed files (path, size, mtime) of
    ``packages``, found without importing them. Part of the stores' keys, so
    entries made by other code are never read back."""
    digest = hashlib.sha256()
    for name in modules:
        spec = importlib.util.find_spec(name)
        digest.update(Path(spec.origin).read_bytes())
    for name in packages:
        spec = importlib.util.find_spec(name)
        if spec is None or spec.origin is None:
            digest.update(f"{name}: none".encode())
            continue
        stat = os.stat(spec.origin)
        digest.update(f"{spec.origin}|{stat.st_size}|{stat.st_mtime_ns}".encode())
    return digest.hexdigest()[:16]


def file_digest(path) -> "hashlib._Hash":
    """SHA-256 of a file's bytes, read in chunks (OSError if it cannot be read)."""
    digest = hashlib.sha256()
    with open(path, "rb") as fh:
        for chunk in iter(lambda: fh.read(1 << 20), b""):
            digest.update(chunk)
    return digest


_shared: dict = {}  # (store class, directory) -> the store (its counters the process's)


def shared_store(cls):
    """The process's one ``cls`` store of the environment's directory, or None if stores are off."""
    directory = cache_directory(cls.KIND)
    if directory is None:
        return None
    store = _shared.get((cls, directory))
    if store is None:
        store = _shared[(cls, directory)] = cls(directory)
    return store
