"""Checksums of the bags: written into every MCAP file the package writes, checked before analysis.

:class:`CheckedWriter` fills in the MCAP CRCs rosbags leaves zero; :func:`check_bag` checks
MCAP CRCs (a zero CRC counted, not failed) or SQLite's ``quick_check`` (it has no checksums).
"""

from __future__ import annotations

import sqlite3
import struct
from binascii import crc32
from contextlib import closing
from dataclasses import dataclass, field
from pathlib import Path

from rosbags.rosbag2 import StoragePlugin, Writer
from rosbags.rosbag2.storage_mcap import DECOMPRESSORS, McapReader, McapWriter

_MAGIC = b"\x89MCAP0\r\n"
_CHUNK, _DATA_END, _FOOTER = 0x06, 0x0F, 0x02
#: A chunk record's CRC field: after its opcode and length (9 bytes) and its start time, end
#: time and uncompressed size (3 x 8 bytes).
_CHUNK_CRC_AT = 9 + 24
#: The footer record (opcode, length, summary start, summary offset start, summary CRC) and the
#: closing magic.
_FOOTER_SIZE = 1 + 8 + 8 + 8 + 4 + len(_MAGIC)
#: The DataEnd record: opcode, length, data section CRC.
_DATA_END_SIZE = 1 + 8 + 4
_BLOCK = 1 << 20


def _crc_of_range(fh, start: int, stop: int, crc: int = 0) -> int:
    """The CRC-32 of bytes [start, stop) of an open file, continuing ``crc``, read in blocks."""
    fh.seek(start)
    remaining = stop - start
    while remaining > 0:
        block = fh.read(min(_BLOCK, remaining))
        if not block:
            break
        crc = crc32(block, crc)
        remaining -= len(block)
    return crc


def _footer(fh):
    """(file size, summary start, footer start) of an MCAP file, or None if it has no footer."""
    size = fh.seek(0, 2)
    if size < len(_MAGIC) + _FOOTER_SIZE:
        return None
    fh.seek(size - _FOOTER_SIZE)
    footer = fh.read(_FOOTER_SIZE)
    if footer[0] != _FOOTER or footer[-len(_MAGIC) :] != _MAGIC:
        return None
    (summary_start,) = struct.unpack_from("<Q", footer, 9)
    return size, summary_start, size - _FOOTER_SIZE


class _CheckedMcapWriter(McapWriter):
    """rosbags' MCAP storage writer, with every CRC of the format filled in."""

    def close_chunk(self) -> None:
        with self.chunk.bio.getbuffer() as records:
            crc = crc32(records)
        start = self.bio.tell()  # the chunk record is written first, here
        super().close_chunk()
        end = self.bio.tell()
        self.bio.seek(start + _CHUNK_CRC_AT)
        self.bio.write(struct.pack("<I", crc))
        self.bio.seek(end)

    def close(self, version: int, metadata: str) -> None:
        super().close(version, metadata)
        with open(self.path, "r+b") as fh:
            size, summary_start, footer_start = _footer(fh)
            data_end = (summary_start or footer_start) - _DATA_END_SIZE
            data_crc = _crc_of_range(fh, 0, data_end)
            fh.seek(data_end + _DATA_END_SIZE - 4)
            fh.write(struct.pack("<I", data_crc))
            if summary_start:  # the summary, up to the footer's summary CRC field
                summary_crc = _crc_of_range(fh, summary_start, size - len(_MAGIC) - 4)
                fh.seek(size - len(_MAGIC) - 4)
                fh.write(struct.pack("<I", summary_crc))


class CheckedWriter(Writer):
    """rosbags' rosbag2 Writer whose MCAP files carry their chunk, data and summary CRCs."""

    STORAGE_PLUGINS = {**Writer.STORAGE_PLUGINS, StoragePlugin.MCAP: _CheckedMcapWriter}


# --------------------------------------------------------------------------------- checking
@dataclass(frozen=True)
class Damage:
    """A part of a bag that fails its check; ``offset`` [bytes] of a chunk, else None."""

    file: Path
    what: str
    reason: str
    offset: int | None = None
    messages: int = 0

    @property
    def skippable(self) -> bool:
        """Whether the rest of the bag can be read without it (a chunk)."""
        return self.offset is not None

    @property
    def fatal(self) -> bool:
        """Whether its summary (chunk index) or SQLite structure is damaged."""
        return self.offset is None and self.what != "the data section"

    def __str__(self) -> str:
        return f"{self.file.name}: {self.what} {self.reason}"


@dataclass
class BagCheck:
    """What :func:`check_bag` found: the damaged parts, the chunks checked, those without a CRC."""

    damaged: list = field(default_factory=list)
    chunks: int = 0
    unchecked_chunks: int = 0


def storages(reader) -> list:
    """The storage readers of an open rosbags Reader: one per file."""
    storage = reader.storage
    return list(getattr(storage, "storages", [storage]))


def check_bag(reader) -> BagCheck:
    """Check every file of an open bag (see the module's docstring); reads each file once."""
    check = BagCheck()
    for storage in storages(reader):
        if isinstance(storage, McapReader):
            _check_mcap(storage, check)
        else:
            _check_sqlite(Path(storage.path), check)
    return check


def _check_sqlite(path: Path, check: BagCheck) -> None:
    try:
        with closing(sqlite3.connect(f"{path.resolve().as_uri()}?mode=ro", uri=True)) as db:
            found = [row[0] for row in db.execute("PRAGMA quick_check(3)")]
    except sqlite3.Error as exc:
        found = [str(exc)]
    if found != ["ok"]:
        check.damaged.append(
            Damage(path, "the file", f"fails SQLite's integrity check ({'; '.join(found)})")
        )


def _chunk_problem(record: bytes, chunk) -> str | None:
    """Why a chunk does not match its index entry or fails its CRC; ``'no CRC'``; None if sound."""
    if len(record) < _CHUNK_CRC_AT + 4 + 4 or record[0] != _CHUNK:
        return "is not where the index says"
    length, start, end, size, crc, name_length = struct.unpack_from("<QQQQII", record, 1)
    name_end = _CHUNK_CRC_AT + 8 + name_length
    if length != chunk.chunk_length - 9 or name_end + 8 > len(record):
        return "does not match its index entry (its length)"
    compression = record[_CHUNK_CRC_AT + 8 : name_end].decode("utf-8", "replace")
    (data_length,) = struct.unpack_from("<Q", record, name_end)
    if (start, end, size, compression, data_length) != (
        chunk.message_start_time,
        chunk.message_end_time,
        chunk.uncompressed_size,
        chunk.compression,
        chunk.compressed_size,
    ) or name_end + 8 + data_length > len(record):
        return "does not match its index entry (its times, sizes or compression)"
    if crc == 0:
        return "no CRC"
    data = record[name_end + 8 : name_end + 8 + data_length]
    try:
        records = DECOMPRESSORS[compression](data, size)
    except Exception as exc:  # any decompressor's error: the data is damaged
        return f"cannot be decompressed ({type(exc).__name__}: {exc})"
    if len(records) != size or crc32(records) != crc:
        return "fails its CRC"
    return None


def _check_mcap(storage, check: BagCheck) -> None:
    path = Path(storage.path)
    chunks = sorted(storage.chunks, key=lambda c: c.chunk_start_offset)
    check.chunks += len(chunks)
    with open(path, "rb") as fh:
        ends = _footer(fh)
        if ends is None:
            check.damaged.append(Damage(path, "the file", "has no MCAP footer"))
            return
        size, summary_start, footer_start = ends
        data_end = (summary_start or footer_start) - _DATA_END_SIZE
        fh.seek(data_end)
        data_end_record = fh.read(_DATA_END_SIZE)
        data_crc = 0
        if data_end_record[:9] == bytes([_DATA_END]) + struct.pack("<Q", 4):
            (data_crc,) = struct.unpack_from("<I", data_end_record, 9)
        running, at = 0, 0  # the data section's CRC up to byte `at`
        for k, chunk in enumerate(chunks, 1):
            start = chunk.chunk_start_offset
            if start < at or start + chunk.chunk_length > data_end:
                problem, record = "is not where the index says", b""
            else:
                if data_crc:
                    running = _crc_of_range(fh, at, start, running)
                fh.seek(start)
                record = fh.read(chunk.chunk_length)
                problem = _chunk_problem(record, chunk)
            if data_crc and record:
                running, at = crc32(record, running), start + len(record)
            if problem == "no CRC":
                check.unchecked_chunks += 1
            elif problem is not None:
                messages = sum(chunk.channel_count.values())
                what = (
                    f"chunk {k} of {len(chunks)} (at byte {start}, log time "
                    f"{chunk.message_start_time * 1e-9:.3f} to "
                    f"{chunk.message_end_time * 1e-9:.3f} s, {messages} messages)"
                )
                check.damaged.append(Damage(path, what, problem, start, messages))
        if data_crc and not any(d.file == path for d in check.damaged):
            if _crc_of_range(fh, at, data_end, running) != data_crc:
                check.damaged.append(
                    Damage(path, "the data section", "fails its CRC (outside its chunks)")
                )
        fh.seek(size - len(_MAGIC) - 4)
        (summary_crc,) = struct.unpack("<I", fh.read(4))
        if summary_start and summary_crc:
            if _crc_of_range(fh, summary_start, size - len(_MAGIC) - 4) != summary_crc:
                check.damaged.append(
                    Damage(path, "the summary (the index of its chunks)", "fails its CRC")
                )


def drop_chunks(reader, damaged) -> int:
    """Take damaged chunks out of an open bag's index so reading skips them; returns how many."""
    offsets = {(d.file, d.offset) for d in damaged if d.skippable}
    dropped = 0
    for storage in storages(reader):
        if isinstance(storage, McapReader):
            path = Path(storage.path)
            kept = [c for c in storage.chunks if (path, c.chunk_start_offset) not in offsets]
            dropped += len(storage.chunks) - len(kept)
            storage.chunks[:] = kept
    return dropped
