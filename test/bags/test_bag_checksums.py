"""Bag checksums: every MCAP file the package writes carries its CRCs (checked here by reading
the MCAP records independently of the package), and bag analysis refuses a bag whose chunk fails
its CRC, naming the file and the chunk, or, asked to skip damaged chunks, leaves the chunk out,
counts it, and gives the undamaged bag's rows for the rest."""

import csv
import shutil
import struct
from binascii import crc32
from pathlib import Path

import pytest

try:  # the zstd that rosbags reads with
    from compression import zstd
except ImportError:
    from backports import zstd
from rosbags.rosbag2 import CompressionFormat, CompressionMode, StoragePlugin, Writer

from adbsat_ros.bags import io as bag_io
from adbsat_ros.bags import scenario
from adbsat_ros.bags.analysis import analyze_bag
from adbsat_ros.bags.checksums import CheckedWriter
from adbsat_ros.cli import main
from adbsat_ros.estimator.settings import WrenchSettings

FAST = 'adbsat_node:\n  ros__parameters:\n    shading: "none"\n'
MAGIC = b"\x89MCAP0\r\n"


# ------------------------------------------------------------------- an independent MCAP reading
def mcap_records(data: bytes):
    """(offset, opcode, body) of every record of an MCAP file, in file order, to the footer."""
    assert data[:8] == MAGIC and data[-8:] == MAGIC
    at = 8
    while at < len(data) - 8:
        opcode = data[at]
        (length,) = struct.unpack_from("<Q", data, at + 1)
        yield at, opcode, data[at + 9 : at + 9 + length]
        at += 9 + length


def chunk_fields(body: bytes):
    """A chunk record's start and end times, its stored CRC, compression and its records."""
    start, end, size, crc, name_length = struct.unpack_from("<QQQII", body)
    compression = body[32 : 32 + name_length].decode()
    (data_length,) = struct.unpack_from("<Q", body, 32 + name_length)
    data = body[40 + name_length : 40 + name_length + data_length]
    if compression == "zstd":
        data = zstd.decompress(data)
    assert compression in ("", "zstd") and len(data) == size
    return start, end, crc, data


def message_count(records: bytes) -> int:
    """Message records (opcode 0x05) in a chunk's records."""
    count, at = 0, 0
    while at < len(records):
        (length,) = struct.unpack_from("<Q", records, at + 1)
        count += records[at] == 0x05
        at += 9 + length
    return count


def mcap_chunks(path):
    """[(offset, start time, end time, messages, offset and size of its records)] of the chunks
    (uncompressed ones)."""
    data = Path(path).read_bytes()
    chunks = []
    for at, opcode, body in mcap_records(data):
        if opcode == 0x06:
            start, end, _, records = chunk_fields(body)
            name_length = struct.unpack_from("<I", body, 28)[0]
            chunks.append(
                (at, start, end, message_count(records), at + 9 + 40 + name_length, len(records))
            )
    return chunks


def assert_crcs_valid(path):
    """Every chunk's, the data section's and the summary's CRC is there (not 0) and right."""
    data = Path(path).read_bytes()
    chunks = 0
    for at, opcode, body in mcap_records(data):
        if opcode == 0x06:
            _, _, crc, records = chunk_fields(body)
            assert crc != 0 and crc == crc32(records), f"{path}: chunk at {at}"
            chunks += 1
        elif opcode == 0x0F:
            (crc,) = struct.unpack("<I", body)
            assert crc != 0 and crc == crc32(data[:at]), f"{path}: data section"
        elif opcode == 0x02:
            summary_start, _, crc = struct.unpack("<QQI", body)
            assert summary_start and crc == crc32(data[summary_start : at + 1 + 8 + 16])
    assert chunks >= 1
    return chunks


def flip_bits(path, offset, count=5, spacing=997):
    """Flip ``count`` bits from ``offset`` on, ``spacing`` bytes apart."""
    data = bytearray(Path(path).read_bytes())
    for i in range(count):
        data[offset + i * spacing] ^= 1 << (i % 8)
    Path(path).write_bytes(bytes(data))


def run(capsys, *argv):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def outputs_of(directory):
    return sorted(p.name for p in Path(directory).iterdir() if "aero" in p.name)


# ------------------------------------------------------------------------------ the flights
@pytest.fixture(scope="module")
def flight(tmp_path_factory):
    """A 60 s flight with states at 50 Hz (large messages: three chunks of about 1 MiB) and
    attitudes at 10 Hz, analysed undamaged (CSV); its scenario messages."""
    root = tmp_path_factory.mktemp("crc")
    messages = scenario.generate(scenario.Scenario(duration_s=60, rate_hz=10, state_rate_hz=50))
    bag_io.write_scenario_bag(messages, root / "flight")
    (root / "fast.yaml").write_text(FAST)
    clean = root / "clean"
    clean.mkdir()
    code = main(
        [
            "bag",
            "analyze",
            str(root / "flight"),
            "--params",
            str(root / "fast.yaml"),
            "--out",
            str(clean / "out"),
            "--no-plots",
            "--workers",
            "1",
        ]
    )
    assert code == 0
    return root, messages


def damaged_copy(flight, tmp_path, chunk=1):
    """A copy of the flight with five bits flipped in the records of its chunk ``chunk``
    (counting from 0); the copy and the chunk's (offset, start, end, messages, ...)."""
    root, _ = flight
    bag = tmp_path / "flight"
    shutil.copytree(root / "flight", bag)
    chunks = mcap_chunks(bag / "flight.mcap")
    assert len(chunks) == 3
    at, _, _, _, records_at, records_size = chunks[chunk]
    flip_bits(bag / "flight.mcap", records_at + records_size // 3)
    return bag, chunks[chunk]


def stamp_ns_of(row) -> int:
    """A CSV row's stamp [ns] (the flights' stamps are whole milliseconds)."""
    return round(float(row[0]) * 1e3) * 1_000_000


def read_rows(path):
    with open(path, newline="") as fh:
        rows = list(csv.reader(fh))
    return rows[0], rows[1:]


# ------------------------------------------------------------------------------ the tests
def test_written_bags_carry_valid_crcs(flight, capsys, tmp_path):
    root, _ = flight
    assert assert_crcs_valid(root / "flight" / "flight.mcap") == 3
    assert_crcs_valid(root / "clean" / "out" / "out.mcap")  # bag analysis' output bag
    code, _, err = run(capsys, "simulate", "--duration", 5, "--rate", 2, "--out", tmp_path / "sim")
    assert code == 0, err
    assert_crcs_valid(tmp_path / "sim" / "sim.mcap")


def test_a_damaged_chunk_is_refused_naming_the_file_and_the_chunk(flight, capsys, tmp_path):
    bag, (offset, start, end, messages, *_) = damaged_copy(flight, tmp_path)
    code, out, err = run(capsys, "bag", "analyze", bag, "--no-plots")
    assert code == 1 and out == ""
    assert err.count("\n") == 1 and "Traceback" not in err
    assert (
        f"input bag {bag}: flight.mcap: chunk 2 of 3 (at byte {offset}, log time "
        f"{start * 1e-9:.3f} to {end * 1e-9:.3f} s, {messages} messages) fails its CRC" in err
    )
    assert "--skip-damaged" in err
    assert outputs_of(tmp_path) == []  # nothing written, not even a partial output


def test_skip_damaged_leaves_the_chunk_out_and_keeps_the_other_rows(flight, capsys, tmp_path):
    root, messages = flight
    bag, (_, start, end, messages_in_chunk, *_) = damaged_copy(flight, tmp_path)
    code, out, err = run(
        capsys,
        "bag",
        "analyze",
        bag,
        "--params",
        root / "fast.yaml",
        "--no-plots",
        "--workers",
        1,
        "--skip-damaged",
    )
    assert code == 0, err
    assert f"skipped 1 damaged chunk(s) of the input holding {messages_in_chunk} messages" in out
    assert "chunk 2 of 3" in err and f"skipped its {messages_in_chunk} messages" in err
    header, rows = read_rows(tmp_path / "flight_aero.csv")
    clean_header, clean_rows = read_rows(root / "clean" / "out.csv")
    assert header == clean_header
    stamp_ns = [stamp_ns_of(r) for r in rows]
    clean_ns = [stamp_ns_of(r) for r in clean_rows]
    in_chunk = [t for t in clean_ns if start <= t <= end]
    assert in_chunk and not set(in_chunk) & set(stamp_ns)
    # the rows before the chunk, and from the first state after it on, are the undamaged ones
    next_state = min(t for t in messages.states.stamps_ns if t > end)
    clean_by_stamp = dict(zip(clean_ns, clean_rows))
    kept = [(t, r) for t, r in zip(stamp_ns, rows) if t < start or t >= next_state]
    assert [r for _, r in kept] == [clean_by_stamp[t] for t, _ in kept]
    assert len(kept) == sum(1 for t in clean_ns if t < start or t >= next_state)
    total = len(messages.states.stamps_ns) + len(messages.attitudes.stamps_ns)
    assert f"{total - messages_in_chunk} messages read" in out


def test_a_damaged_compressed_chunk_is_refused(tmp_path):
    """Chunks compressed with zstd (as rosbags writes them with storage compression): the CRC
    is of the uncompressed records; bits flipped in the compressed ones are found too."""
    writer = CheckedWriter(tmp_path / "z", version=9, storage_plugin=StoragePlugin.MCAP)
    writer.set_compression(CompressionMode.STORAGE, CompressionFormat.ZSTD)
    writer.open()
    r, v = [6.7e6, 0, 0], [0, 7.7e3, 0]
    states = writer.add_connection("/state", bag_io.ODOMETRY, typestore=bag_io.TYPESTORE)
    attitudes = writer.add_connection(
        "/attitude", bag_io.QUATERNION_STAMPED, typestore=bag_io.TYPESTORE
    )
    t0 = 1_767_225_600_000_000_000
    for k in range(20):
        t = t0 + k * 100_000_000
        writer.write(states, t, bag_io.serialize(bag_io.odometry_message(t, "eci", "eci", r, v)))
        q = bag_io.quaternion_stamped_message(t, "eci", [0, 0, 0, 1])
        writer.write(attitudes, t, bag_io.serialize(q))
    writer.close()
    path = tmp_path / "z" / "z.mcap"
    assert_crcs_valid(path)
    data = path.read_bytes()
    (chunk,) = [(at, body) for at, opcode, body in mcap_records(data) if opcode == 0x06]
    assert struct.unpack_from("<I", chunk[1], 28)[0] == 4  # 'zstd'
    flip_bits(path, chunk[0] + 9 + 44 + 40, count=1)  # inside the compressed records
    settings = WrenchSettings.from_parameters({"shading": "none"})
    with pytest.raises(
        bag_io.BagError,
        match=r"z\.mcap: chunk 1 of 1 \(at byte \d+, .*\) (fails its CRC|cannot be decompressed)",
    ):
        analyze_bag(tmp_path / "z", models=[("m", settings)])


def test_damage_outside_the_chunks(flight, capsys, tmp_path):
    """Bits flipped in a message index (outside the chunks, in the data section): refused, or
    with --skip-damaged analysed with a warning (no message is in it); in the summary (the index
    of the chunks): refused either way."""
    root, _ = flight
    bag = tmp_path / "flight"
    shutil.copytree(root / "flight", bag)
    path = bag / "flight.mcap"
    data = path.read_bytes()
    index = next(at for at, opcode, _ in mcap_records(data) if opcode == 0x07)
    flip_bits(path, index + 9 + 2 + 4 + 3, count=1)  # a message's log time in the index
    code, _, err = run(capsys, "bag", "analyze", bag, "--no-plots")
    assert code == 1 and "flight.mcap: the data section fails its CRC" in err
    code, out, err = run(
        capsys,
        "bag",
        "analyze",
        bag,
        "--params",
        root / "fast.yaml",
        "--no-plots",
        "--skip-damaged",
        "--workers",
        1,
        "--out",
        tmp_path / "skip",
    )
    assert code == 0 and "the data section fails its CRC" in err and "no message" in err
    assert read_rows(tmp_path / "skip.csv") == read_rows(root / "clean" / "out.csv")

    shutil.copy(root / "flight" / "flight.mcap", path)
    footer_start = len(data) - 37
    summary_start = struct.unpack_from("<Q", data, footer_start + 9)[0]
    schema = next(
        at for at, opcode, _ in mcap_records(data) if opcode == 0x03 and at >= summary_start
    )
    flip_bits(path, schema + 60, count=1)  # a message definition's text, in the summary
    for extra in ((), ("--skip-damaged",)):
        code, _, err = run(capsys, "bag", "analyze", bag, "--no-plots", *extra)
        assert code == 1
        assert "flight.mcap: the summary (the index of its chunks) fails its CRC" in err


def test_a_bag_without_crcs_is_read_with_a_warning(tmp_path):
    """Other writers may leave the CRC fields zero: the bag is read, and the report says that
    damage to its chunks cannot be found."""
    with Writer(tmp_path / "plain", version=9, storage_plugin=StoragePlugin.MCAP) as writer:
        states = writer.add_connection("/state", bag_io.ODOMETRY, typestore=bag_io.TYPESTORE)
        attitudes = writer.add_connection(
            "/attitude", bag_io.QUATERNION_STAMPED, typestore=bag_io.TYPESTORE
        )
        t = 1_767_225_600_000_000_000
        odometry = bag_io.odometry_message(t, "eci", "eci", [6.7e6, 0, 0], [0, 7.7e3, 0])
        writer.write(states, t, bag_io.serialize(odometry))
        q = bag_io.quaternion_stamped_message(t, "eci", [0, 0, 0, 1])
        writer.write(attitudes, t, bag_io.serialize(q))
    settings = WrenchSettings.from_parameters({"shading": "none"})
    report = analyze_bag(tmp_path / "plain", models=[("m", settings)], workers=1)
    assert report.wrenches == 1
    assert report.warnings == [
        f"input bag {tmp_path / 'plain'}: 1 of 1 chunks carry no CRC (damage to them cannot be "
        "found)"
    ]


def test_a_damaged_sqlite_bag_gives_a_named_error(capsys, tmp_path):
    """SQLite bags carry no checksums; damage to the file's structure is found (by SQLite) and
    named in one line."""
    code, _, err = run(
        capsys,
        "simulate",
        "--duration",
        60,
        "--storage",
        "sqlite3",
        "--out",
        tmp_path / "db",
    )
    assert code == 0, err
    path = tmp_path / "db" / "db.db3"
    page = 4096
    assert path.stat().st_size > 8 * page
    flip_bits(path, 6 * page, count=1, spacing=1)  # a b-tree page's type
    flip_bits(path, 6 * page + 5, count=8, spacing=1)  # and its cell content offset
    code, out, err = run(capsys, "bag", "analyze", tmp_path / "db", "--no-plots")
    assert code == 1 and out == "" and err.count("\n") == 1 and "Traceback" not in err
    assert f"input bag {tmp_path / 'db'}" in err and "malformed" in err
