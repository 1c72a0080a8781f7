"""Offline analysis of recorded flights: the node's wrench at every attitude message of a rosbag2.

:func:`analyze_bag` reads a bag (.mcap or .db3) with ``rosbags`` (no ROS installation needed),
feeds its state and attitude messages in bag order to one
:class:`~adbsat_ros.estimator.estimator.AeroWrenchEstimator` per model through the node's own
per-message path (:class:`~adbsat_ros.estimator.handling.MessageHandler`: the same decoding,
rejections and wrench bytes), and writes

* a new bag holding every input message plus, per model ``LABEL``, the topics
  ``/adbsat/LABEL/wrench`` (force [N], torque [N m], body frame) and ``/adbsat/LABEL/coefficients``
  (C_F in ``force``, C_M in ``torque``, body frame), both geometry_msgs/WrenchStamped stamped like
  the attitude message and logged at its log time, and ``/diagnostics``
  (diagnostic_msgs/DiagnosticArray, one per model every ``diagnostics_period`` of bag time and one
  at the end of the bag, with the node's keys and levels; the state age is measured in bag time);
* a CSV with one row per attitude message (per state message for models whose
  ``attitude_source`` is odometry) and one column group per model (see :data:`MODEL_COLUMNS`);
* PNG plots of force, torque, density and drag coefficient against time
  (:func:`adbsat_ros.plotting.time_series.plot_time_series`).

Outputs are written under temporary names and renamed at the end. If the input turns out to be
corrupt or truncated part-way, everything analysed before the fault is still written and the
report says so (:attr:`AnalysisReport.error`, :attr:`AnalysisReport.partial`).

Parallel replay, same results as one estimator fed every message in order:

1. *Read* every message once (:mod:`adbsat_ros.bags.reading`: raw CDR bytes, held in memory,
   about the bag's size) and the header stamps of the state and attitude ("trigger") messages.
2. *Plan* (:mod:`adbsat_ros.bags.planning`): cut the trigger messages into contiguous chunks,
   each starting at a state message where an estimator with no history provably gives the
   sequential outputs (:func:`safe_split_points`, and the state must pass a reset estimator's
   checks); with no such place the chunks are fewer (one, at worst).
3. *Compute* (:mod:`adbsat_ros.bags.worker`): worker processes (``workers``; the estimators and
   shading caches built once per process) decode and replay whole chunks from reset
   estimators, and return per message named records of numbers and bytes.
4. *Merge* in bag order (:mod:`adbsat_ros.bags.outputs`): copy the input messages, write the
   wrenches and CSV rows, and rebuild the node's cumulative state
   (:mod:`adbsat_ros.bags.model_state`) to write the diagnostics.
"""

from __future__ import annotations

import time
from pathlib import Path

from adbsat_ros.bags import io as bag_io
from adbsat_ros.bags import replacing
from adbsat_ros.bags.io import BagError
from adbsat_ros.bags.model_state import ModelState
from adbsat_ros.bags.outputs import Outputs, Replay, write_outputs
from adbsat_ros.bags.planning import (
    MAX_CHUNK_MESSAGES,
    MIN_CHUNK_MESSAGES,
    plan_chunks,
    safe_split_points,
)
from adbsat_ros.bags.reading import check_damage, check_topics, read_bag_messages
from adbsat_ros.bags.report import (
    DIAGNOSTICS_TOPIC,
    NAMESPACE,
    NODE_NAME,
    AnalysisReport,
    ModelSummary,
    check_label,
    label_from_name,
)
from adbsat_ros.bags.table import COMMON_COLUMNS, MODEL_COLUMNS
from adbsat_ros.bags.worker import chunk_results
from adbsat_ros.estimator.settings import WrenchSettings
from adbsat_ros.geometry.loading import resolve_mesh
from adbsat_ros.messages.decoding import UndecodableMessage, decode_odometry
from adbsat_ros.processes import interruptible, worker_count

__all__ = [
    "COMMON_COLUMNS",
    "DIAGNOSTICS_TOPIC",
    "MAX_CHUNK_MESSAGES",
    "MIN_CHUNK_MESSAGES",
    "MODEL_COLUMNS",
    "NAMESPACE",
    "NODE_NAME",
    "AnalysisReport",
    "ModelSummary",
    "analyze_bag",
    "check_label",
    "label_from_name",
    "safe_split_points",
]


def _output_path(path, overwrite: bool, what: str) -> Path | None:
    """``path`` as a Path, or BagError if something is there: without ``overwrite``, or with it
    when that is not an output of the kind ``what`` (named: it is never removed)."""
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
    """The models' output topics must not be in the input, and its /diagnostics (if any) must
    be diagnostic_msgs/DiagnosticArray."""
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

    Parameters
    ----------
    bag : str or Path
        Input rosbag2 (directory, .mcap or .db3 file).
    attitude_topic, state_topic : str
        geometry_msgs/QuaternionStamped and nav_msgs/Odometry topics (as the node subscribes).
    models : list of (label, WrenchSettings), optional
        One entry per model (default: the node's defaults, label 'default').
    out_bag : path, optional
        Output bag directory (None: no bag).
    out_csv : path, optional
        CSV file (None: no CSV).
    plots_dir : path, optional
        Directory for PNG plots (None: no plots).
    storage : str
        'mcap' or 'sqlite3' for the output bag.
    progress : bool
        Show a tqdm progress bar (on stderr).
    overwrite : bool
        Replace existing outputs.
    workers : int, optional
        Processes computing wrenches (default ``os.cpu_count()``). The outputs are the same
        for any number: the messages are cut into chunks only where a fresh estimator provably
        gives the sequential results (:func:`safe_split_points`), and counters and diagnostics
        are rebuilt in bag order.
    chunk_messages : int, optional
        State + attitude messages per chunk (default: enough chunks for 8 per worker, at least
        :data:`MIN_CHUNK_MESSAGES` and at most :data:`MAX_CHUNK_MESSAGES` each).
    stop : threading.Event, optional
        Set to stop at the next message (e.g. by :func:`adbsat_ros.processes.stop_on_signals`):
        the report's error says so and the outputs so far are kept as PARTIAL.
    joint_topic : str
        sensor_msgs/JointState topic of the joint positions, read when a model is an
        articulated body (as the node subscribes ``joint_states``).
    skip_damaged : bool
        Leave out the chunks of an MCAP input that fail their CRC (their messages are not
        read; the report counts them, :attr:`AnalysisReport.skipped_chunks`) instead of
        refusing the bag.

    Returns
    -------
    AnalysisReport

    Raises
    ------
    BagError
        Before anything is written: the input cannot be opened, fails its checksums (naming
        the file and the damaged chunk; see ``skip_damaged``), a topic is missing, has another
        message type or no messages, or an output exists. (A fault found while reading, or a
        stop, is reported in :attr:`AnalysisReport.error` instead; the outputs written so far
        are then kept under names that say PARTIAL, never the final ones:
        :func:`adbsat_ros.bags.outputs.partial_path`.)
    ValueError, MeshError
        For models that cannot be set up, or ``workers`` / ``chunk_messages`` < 1.
    """
    t_start = time.perf_counter()
    bag = Path(bag)
    models = list(models) if models else [("default", WrenchSettings.from_parameters({}))]
    labels = [check_label(label) for label, _ in models]
    if len(set(labels)) != len(labels):
        raise ValueError(f"model labels must differ, got {', '.join(labels)}")
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

    uses_attitudes = any(s.attitude_source == "attitude_topic" for _, s in models)
    with interruptible():  # (nothing is written before the walk: a signal ends it at once)
        read, states, chunks, report, t0 = _read_and_plan(
            bag,
            models,
            attitude_topic,
            state_topic,
            joint_topic,
            uses_attitudes,
            capped,
            workers,
            chunk_messages,
            skip_damaged,
        )
    report.workers, report.chunks = min(workers, len(chunks)) or 1, len(chunks)
    report.seconds["read"] = time.perf_counter() - t0
    read.state_raws.clear()  # (only the planning needed them)
    stream = read.stream()
    try:
        results = chunk_results(
            [(s.settings, s.mesh) for s in states], stream.chunks(chunks), report.workers, stop
        )
        write_outputs(
            Replay(read, stream, chunks, results, states, report),
            Outputs(out_bag, out_csv, plots_dir, storage, overwrite, progress),
            stop,
        )
    finally:
        stream.close()
    report.seconds["total"] = time.perf_counter() - t_start
    for state in states:
        state.finish()
    report.add_rejection_warnings(attitude_topic, state_topic)
    return report


def _read_and_plan(
    bag,
    models,
    attitude_topic,
    state_topic,
    joint_topic,
    uses_attitudes,
    capped,
    workers,
    chunk_messages,
    skip_damaged,
) -> tuple:
    """Open and read the bag, set the models up and plan the chunks:
    ``(read, states, chunks, report, t0)``."""
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
        if capped:
            report.warnings.append(f"workers: {capped}")
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
