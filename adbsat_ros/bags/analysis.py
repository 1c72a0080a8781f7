"""Offline analysis of recorded flights: the node's wrench at every attitude message of a
rosbag2. The bag's messages go through the node's per-message path, one estimator per model, in
parallel chunks merged in bag order; docs/cli.md, "Recorded flights"."""

from __future__ import annotations

import time
from pathlib import Path

from adbsat_ros.bags import io as bag_io
from adbsat_ros.bags import replacing
from adbsat_ros.bags.io import BagError
from adbsat_ros.bags.model_state import ModelState
from adbsat_ros.bags.outputs import write_outputs
from adbsat_ros.bags.planning import plan_chunks
from adbsat_ros.bags.reading import check_damage, check_topics, read_bag_messages
from adbsat_ros.bags.report import DIAGNOSTICS_TOPIC, AnalysisReport, check_label
from adbsat_ros.bags.worker import chunk_results
from adbsat_ros.estimator.settings import WrenchSettings
from adbsat_ros.geometry.loading import resolve_mesh
from adbsat_ros.messages.decoding import UndecodableMessage, decode_odometry
from adbsat_ros.processes import interruptible, worker_count


def _output_path(path, overwrite: bool, what: str) -> Path | None:
    """``path`` as a Path; BagError if ``overwrite`` may not replace what is there."""
    if path is None:
        return None
    path = Path(path)
    if not (path.exists() or path.is_symlink()):
        return path
    if not overwrite:
        raise BagError(
            f"output {what} {path}: already exists (choose another name, or overwrite it: "
            "--overwrite)"
        )
    reason = replacing.refusal(path, what)
    if reason is not None:
        raise BagError(reason)
    return path


def _holds(path: Path, bag: Path) -> bool:
    """Whether ``path`` is the input ``bag`` or a directory it is in."""
    path, bag = path.resolve(), bag.resolve()
    return path == bag or path in bag.parents


def _model_states(models) -> list:
    """A ModelState per (label, settings), each mesh loaded once."""
    meshes = {}
    states = []
    for label, settings in models:
        key = (settings.mesh, settings.mesh_scale)
        if key not in meshes:
            meshes[key] = resolve_mesh(settings.mesh, settings.mesh_scale)
        states.append(ModelState(label, settings, meshes[key]))
    return states


def _check_output_topics(bag, by_topic: dict, states) -> None:
    """The models' output topics must not be in the input, its /diagnostics a DiagnosticArray."""
    for state in states:
        for topic in (state.summary.wrench_topic, state.summary.coefficients_topic):
            if topic in by_topic:
                raise BagError(
                    f"input bag {bag}: already has topic {topic}; give the model another label"
                )
    if by_topic.get(DIAGNOSTICS_TOPIC, {bag_io.DIAGNOSTIC_ARRAY}) != {bag_io.DIAGNOSTIC_ARRAY}:
        raise BagError(
            f"input bag {bag}: topic {DIAGNOSTICS_TOPIC} has another type than "
            f"{bag_io.DIAGNOSTIC_ARRAY}; the diagnostics cannot be added to it"
        )


def _accepted_by_fresh_estimators(read, states, k: int) -> bool:
    """Whether every model's reset estimator accepts trigger message k (a state)."""
    try:
        odometry = decode_odometry(read.state_raws[k], bag_io.deserialize_odometry)
    except UndecodableMessage:
        return False
    return all(state.accepts_state(odometry) for state in states)


def analyze_bag(
    bag,
    attitude_topic: str = "/attitude",
    state_topic: str = "/state",
    models=None,
    out_bag=None,
    out_csv=None,
    plots_dir=None,
    storage: str = "mcap",
    progress: bool = False,
    overwrite: bool = False,
    workers: int | None = None,
    chunk_messages: int | None = None,
    stop=None,
    joint_topic: str = "/joint_states",
    skip_damaged: bool = False,
) -> AnalysisReport:
    """Replay a bag through the node's logic for each model and write bag, CSV and plots.
    bag: input rosbag2 (directory, .mcap or .db3 file).
    attitude_topic, state_topic: QuaternionStamped and Odometry topics (as the node subscribes).
    models: list of (label, WrenchSettings) (default: the node's defaults, label 'default').
    overwrite: replace outputs of the same kind only (:mod:`adbsat_ros.bags.replacing`).
    workers: processes (default: this one, and every usable CPU for what is left once the chunks,
      timed here, are worth them: :func:`adbsat_ros.bags.worker.chunk_results`); the outputs are
      the same for any number.
    chunk_messages: trigger messages per chunk, >= 1 (default: planned, :mod:`.planning`).
    stop: a threading.Event; stops at the next message, the outputs so far kept as PARTIAL.
    skip_damaged: leave out MCAP chunks failing their CRC instead of refusing the bag.
    Returns an AnalysisReport; a fault while reading, or a stop, is in its ``error``, the outputs
    so far under :func:`adbsat_ros.bags.outputs.partial_path`.
    BagError: before anything is written, a bad input (checksums, topics) or an existing output.
    ValueError: a model that cannot be set up (or MeshError), ``workers``/``chunk_messages`` < 1."""
    t_start = time.perf_counter()
    bag = Path(bag)
    models = list(models) if models else [("default", WrenchSettings.from_parameters({}))]
    labels = [check_label(label) for label, _ in models]
    if len(set(labels)) != len(labels):
        raise ValueError(f"model labels must differ, got {', '.join(labels)}")
    chosen = workers is not None
    workers, capped = worker_count(workers)
    if chunk_messages is not None and int(chunk_messages) < 1:
        raise ValueError(f"chunk_messages must be >= 1, got {chunk_messages}")
    bag_io.storage_plugin(storage)  # an unknown storage name fails before any work
    out_bag = _output_path(out_bag, overwrite, "bag")
    out_csv = _output_path(out_csv, overwrite, "CSV")
    plots_dir = _output_path(plots_dir, overwrite, "plot directory")
    for what, path in (("bag", out_bag), ("CSV", out_csv), ("plot directory", plots_dir)):
        if path is not None and _holds(path, bag):
            raise BagError(f"output {what} {path}: holds the input bag {bag}; choose another name")

    topics = attitude_topic, state_topic, joint_topic
    with interruptible():  # (nothing is written before the walk: a signal ends it at once)
        read, states, chunks, report, t0 = _read_and_plan(
            bag, models, topics, workers, chunk_messages, skip_damaged
        )
    if capped:
        report.warnings.append(f"workers: {capped}")
    count, report.chunks = min(workers, len(chunks)) or 1, len(chunks)
    report.workers = count if chosen else 1  # (by default, more once the pool starts)
    report.seconds["read"] = time.perf_counter() - t0
    read.state_raws.clear()  # (only the planning needed them)
    stream = read.stream()
    try:
        specs = [(s.settings, s.mesh) for s in states]
        planned = None if chosen else len(chunks)
        results = chunk_results(specs, stream.chunks(chunks), count, stop, planned, report)
        write_outputs(
            (read, stream, chunks, results, states, report),
            (out_bag, out_csv, plots_dir, storage, overwrite, progress),
            stop,
        )
    finally:
        stream.close()
    report.seconds["total"] = time.perf_counter() - t_start
    for state in states:
        state.finish()
    report.add_rejection_warnings(attitude_topic, state_topic)
    return report


def _read_and_plan(bag, models, topics, workers, chunk_messages, skip_damaged) -> tuple:
    """Read the bag, set the models up, plan the chunks: ``(read, states, chunks, report, t0)``."""
    attitude_topic, state_topic, joint_topic = topics
    uses_attitudes = any(s.attitude_source == "attitude_topic" for _, s in models)
    reader = bag_io.open_bag(bag)
    try:
        needed = []
        if uses_attitudes:
            needed.append(("--attitude-topic", attitude_topic, bag_io.QUATERNION_STAMPED))
        needed.append(("--state-topic", state_topic, bag_io.ODOMETRY))
        states = _model_states(models)
        articulated = any(s.estimator.body is not None for s in states)
        if articulated:
            needed.append(("--joint-states-topic", joint_topic, bag_io.JOINT_STATE))
        by_topic = check_topics(reader, bag, needed)
        _check_output_topics(bag, by_topic, states)
        skipped, warnings = check_damage(reader, bag, skip_damaged)
        report = AnalysisReport(bag, models=[s.summary for s in states], warnings=warnings)
        report.skipped_chunks = len(skipped)
        report.skipped_messages = sum(d.messages for d in skipped)
        report.messages_total = reader.message_count - report.skipped_messages
        t0 = time.perf_counter()
        read = read_bag_messages(
            reader,
            bag,
            state_topic,
            attitude_topic if uses_attitudes else None,
            joint_topic if articulated else None,
            skipped,
        )
        report.error = read.error
    finally:
        reader.close()
    chunks = plan_chunks(
        read.trigger_kinds,
        read.trigger_stamps,
        [s.settings.attitude_source for s in states],
        workers,
        None if chunk_messages is None else int(chunk_messages),
        lambda k: _accepted_by_fresh_estimators(read, states, k),
    )
    return read, states, chunks, report, t0
