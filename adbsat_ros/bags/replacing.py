"""Which outputs of the bag tools an output path holds: ``--overwrite`` replaces only these
(a rosbag2 bag, a directory of the analysis's PNGs, a CSV with its header).
"""

from __future__ import annotations

from pathlib import Path

import yaml

from adbsat_ros.bags.table import COMMON_COLUMNS
from adbsat_ros.validation import foreign_entry, foreign_file

_PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


def foreign_in_bag(path) -> Path | None:
    """What at ``path`` is not a rosbag2 bag's (or None: a bag, or an empty directory)."""
    path = Path(path)
    listed = set()
    try:
        meta = yaml.safe_load((path / "metadata.yaml").read_text(encoding="utf-8"))
        files = meta["rosbag2_bagfile_information"]["relative_file_paths"]
        listed = {Path(str(name)).parts for name in files} | {("metadata.yaml",)}
    except (OSError, UnicodeError, yaml.YAMLError, KeyError, TypeError):
        pass  # (then metadata.yaml, if there, is no bag's either)
    return foreign_entry(path, lambda parts: parts in listed)


def foreign_in_plots(path) -> Path | None:
    """What at ``path`` is not one of the analysis's plots (or None)."""
    from adbsat_ros.plotting.time_series import TIME_SERIES_KEYS

    names = {f"{key}.png" for key in TIME_SERIES_KEYS}

    def own(parts):
        return len(parts) == 1 and parts[0] in names and _is_png(Path(path, *parts))

    return foreign_entry(path, own)


def foreign_csv(path) -> Path | None:
    """``path`` if it is not a CSV file of the analysis (or None)."""
    start = ",".join(COMMON_COLUMNS).encode()

    def own(file):
        with open(file, "rb") as stream:
            return stream.read(len(start)) == start

    return foreign_file(path, own)


def _is_png(path: Path) -> bool:
    with open(path, "rb") as stream:
        return stream.read(len(_PNG_SIGNATURE)) == _PNG_SIGNATURE


#: What each output may be replaced as, for :func:`refusal`.
KINDS = {
    "bag": (foreign_in_bag, "a rosbag2 bag (metadata.yaml and the files it lists)"),
    "plot directory": (foreign_in_plots, "the PNGs of bag analyze"),
    "CSV": (foreign_csv, "a CSV file of bag analyze"),
}


def refusal(path, what: str) -> str | None:
    """Why ``what`` at ``path`` cannot be replaced, naming the entry; None if it can."""
    find, kind = KINDS[what]
    entry = find(path)
    if entry is None:
        return None
    held = "is not" if Path(entry) == Path(path) else f"holds {entry}, which is not part of"
    return (
        f"output {what} {path}: {held} {kind}; --overwrite replaces only that: remove it "
        "yourself or choose another name"
    )
