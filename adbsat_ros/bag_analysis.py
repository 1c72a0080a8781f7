"""Offline analysis of recorded flights: the node's wrench at every attitude message of a rosbag2.

:func:`analyze_bag` reads a bag (.mcap or .db3) with ``rosbags`` (no ROS installation needed),
feeds its state and attitude messages in bag order to one
:class:`~adbsat_ros.aero_wrench.AeroWrenchEstimator` per model, with the node's own decoding
rules (:func:`adbsat_ros.bag_io.decode_odometry`) and its handling of rejected inputs, and writes

* a new bag holding every input message plus, per model ``LABEL``, the topics
  ``/adbsat/LABEL/wrench`` (force [N], torque [N m], body frame) and ``/adbsat/LABEL/coefficients``
  (C_F in ``force``, C_M in ``torque``, body frame), both geometry_msgs/WrenchStamped stamped like
  the attitude message and logged at its log time, and ``/diagnostics``
  (diagnostic_msgs/DiagnosticArray, one per model every ``diagnostics_period`` of bag time and one
  at the end of the bag, with the node's keys and levels; the state age is measured in bag time);
* a CSV with one row per attitude message (per state message for models whose
  ``attitude_source`` is odometry) and one column group per model (see :data:`MODEL_COLUMNS`);
* PNG plots of force, torque, density and drag coefficient against time
  (:func:`adbsat_ros.plots.plot_time_series`).

Outputs are written under temporary names and renamed at the end. If the input turns out to be
corrupt or truncated part-way, everything analysed before the fault is still written and the
report says so (:attr:`AnalysisReport.error`, :attr:`AnalysisReport.partial`).
"""

from __future__ import annotations

import collections
import csv
import math
import os
import re
import shutil
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from . import bag_io
from .aero_wrench import AeroWrenchEstimator, Rejection
from .bag_io import BagError
from .frames import angles_of_flow
from .mesh import resolve_mesh
from .wrench_settings import WrenchSettings

#: Name of the node whose section a parameters file is read from, and whose logic is replayed.
NODE_NAME = "adbsat_node"
#: Namespace of the per-model output topics: NAMESPACE/LABEL/wrench and NAMESPACE/LABEL/coefficients.
NAMESPACE = "/adbsat"
DIAGNOSTICS_TOPIC = "/diagnostics"
#: Columns shared by all models.
COMMON_COLUMNS = ("stamp_s", "utc", "time_s", "topic")
#: Columns of each model's group, prefixed with "LABEL." in the CSV. wind_body is the velocity of
#: the gas relative to the body in body axes; aoa/aos are ADBSat's angles of that flow (frames.py).
MODEL_COLUMNS = (
    "status", "altitude_m", "density_kg_m3", "temperature_K", "relative_speed_m_s",
    "wind_body_x_m_s", "wind_body_y_m_s", "wind_body_z_m_s", "aoa_deg", "aos_deg",
    "drag_coefficient", "CF_x", "CF_y", "CF_z", "CM_x", "CM_y", "CM_z",
    "force_x_N", "force_y_N", "force_z_N", "torque_x_Nm", "torque_y_Nm", "torque_z_Nm",
)
_LABEL_RE = re.compile(r"^[A-Za-z][A-Za-z0-9_]*$")
_NS = 1_000_000_000


def label_from_name(name: str) -> str:
    """A topic-safe model label from a file stem: other characters become '_', a leading digit gets 'm'."""
    label = re.sub(r"[^A-Za-z0-9_]", "_", str(name)) or "model"
    return label if label[0].isalpha() else "m" + label


def check_label(label: str) -> str:
    """Return ``label`` if it can be a ROS topic name token, else raise ValueError naming it."""
    if not _LABEL_RE.match(label):
        raise ValueError(f"model label {label!r}: use letters, digits and '_' and start with a letter")
    return label


@dataclass
class ModelSummary:
    """What one model produced: triggers seen, wrenches written, rejections by reason."""

    label: str
    wrench_topic: str
    coefficients_topic: str
    triggers: int = 0
    wrenches: int = 0
    rejections: dict = field(default_factory=dict)
    first_rejection: dict = field(default_factory=dict)


@dataclass
class AnalysisReport:
    """Outcome of :func:`analyze_bag`.

    Attributes
    ----------
    input : Path
    outputs : dict
        'bag', 'csv', 'plots' (list of PNG paths) that were written.
    models : list of ModelSummary
    messages_read : int
        Input messages read (and copied to the output bag).
    messages_total : int
        Messages the input's index announced.
    error : str or None
        Why the input could not be read to its end (the outputs then hold what came before).
    warnings : list of str
    seconds : dict
        Wall time by phase: read (incl. decoding), estimate, write, csv, plots, total.
    """

    input: Path
    outputs: dict = field(default_factory=dict)
    models: list = field(default_factory=list)
    messages_read: int = 0
    messages_total: int = 0
    error: str | None = None
    warnings: list = field(default_factory=list)
    seconds: dict = field(default_factory=dict)

    @property
    def partial(self) -> bool:
        """True if the input could not be read to its end."""
        return self.error is not None

    @property
    def wrenches(self) -> int:
        return sum(m.wrenches for m in self.models)


def diagnostic_values(estimator: AeroWrenchEstimator, last_sample, compute_ms) -> dict:
    """The key/values the node puts in its DiagnosticStatus (same keys, same order)."""
    s = estimator.settings
    values = {
        "gsi_model": s.gsi_model,
        "shading": s.shading,
        "published": estimator.published,
        "shading_cache_hits": estimator.shading_cache_hits,
        "shading_cache_misses": estimator.shading_cache_misses,
        "reference_area_m2": estimator.method.reference.area,
        "reference_length_m": estimator.method.reference.length,
    }
    times = np.asarray(compute_ms)
    if times.size:
        values["compute_ms_p50"] = float(np.percentile(times, 50))
        values["compute_ms_p99"] = float(np.percentile(times, 99))
    if last_sample is not None:
        c = last_sample.conditions
        values.update(
            density_kg_m3=c.mass_density, temperature_K=c.temperature, altitude_m=c.altitude,
            relative_speed_m_s=c.speed, speed_ratio=c.speed_ratio, alpha=c.alpha,
            drag_coefficient=last_sample.drag_coefficient,
        )
    for reason in sorted(estimator.rejections):
        values[f"rejected_{reason}"] = estimator.rejections[reason]
    return values


class _ModelRun:
    """One model: its estimator and the node's per-message handling, writing into the bag."""

    OK, WARN, ERROR = 0, 1, 2

    def __init__(self, label: str, settings: WrenchSettings, mesh):
        self.label = label
        self.estimator = AeroWrenchEstimator(settings, mesh)
        self.settings = settings
        self.summary = ModelSummary(label, f"{NAMESPACE}/{label}/wrench", f"{NAMESPACE}/{label}/coefficients")
        self.compute_ms = collections.deque(maxlen=2000)
        self.last_sample = None
        self.last_rejection = None
        self.last_state_ns = None
        self.diag_period_ns = max(1, int(round(settings.diagnostics_period * _NS)))
        self.next_diag_ns = None

    def _rejected(self, exc: Rejection) -> None:
        self.last_rejection = exc
        self.summary.first_rejection.setdefault(exc.reason, exc.message)

    def _failed(self, exc: Exception) -> None:  # the node counts any other failure as compute_error
        self.estimator.rejections["compute_error"] += 1
        self.summary.first_rejection.setdefault("compute_error", f"{type(exc).__name__}: {exc}")

    def on_state(self, msg, t_ns):
        """The node's _on_state; returns (status, sample) if this state triggered a wrench, else None."""
        est, s = self.estimator, self.settings
        try:
            stamp, position, velocity, in_body, orientation = bag_io.decode_odometry(
                msg, s.body_frame_id, s.state_frame)
        except Rejection as exc:
            est.rejections[exc.reason] += 1
            self._rejected(exc)
            return None
        try:
            est.on_state(stamp, position, velocity, in_body, orientation)
        except Rejection as exc:
            self._rejected(exc)
            return None
        except Exception as exc:  # as the node: never let a message stop the analysis
            self._failed(exc)
            return None
        self.last_state_ns = t_ns
        if s.attitude_source == "odometry":
            return self._compute(msg.header.stamp, orientation)
        return None

    def on_attitude(self, msg):
        """The node's _on_attitude; returns (status, sample) or None if attitudes are not used."""
        if self.settings.attitude_source != "attitude_topic":
            return None
        _, q = bag_io.decode_quaternion_stamped(msg)
        return self._compute(msg.header.stamp, q)

    def _compute(self, stamp_msg, quaternion):
        self.summary.triggers += 1
        try:
            sample = self.estimator.on_attitude(bag_io.stamp_seconds(stamp_msg), quaternion)
        except Rejection as exc:
            self._rejected(exc)
            return exc.reason, None
        except Exception as exc:  # as the node
            self._failed(exc)
            return "compute_error", None
        self.compute_ms.append(1e3 * sample.compute_seconds)
        self.last_sample = sample
        self.summary.wrenches += 1
        return "ok", sample

    def diagnostic_status(self, now_ns: int):
        """The node's DiagnosticStatus, with the state age in bag time."""
        est, s = self.estimator, self.settings
        values = diagnostic_values(est, self.last_sample, self.compute_ms)
        age = None if self.last_state_ns is None else (now_ns - self.last_state_ns) / _NS
        n_rejected = sum(est.rejections.values())
        if age is None or age > max(s.state_timeout, s.diagnostics_period):
            level, message = self.ERROR, "no orbital state" if age is None else f"state is stale ({age:.1f} s old)"
        elif self.last_rejection is not None and self.last_rejection.reason == "stale_state":
            level, message = self.ERROR, "state is stale relative to the attitude stamps"
        elif n_rejected:
            level, message = self.WARN, f"{n_rejected} inputs rejected so far"
        else:
            level, message = self.OK, "ok"
        return bag_io.diagnostic_status(level, f"{NODE_NAME}/{self.label}: aerodynamic wrench", message,
                                        est.mesh.source, values)


def _row_values(status: str, sample) -> list:
    """The model's CSV cells (floats; NaN where nothing was computed)."""
    if sample is None:
        return [status] + [math.nan] * (len(MODEL_COLUMNS) - 1)
    c = sample.conditions
    u = sample.flow_direction_body
    wind = u * c.speed
    if np.any(u):
        aoa, aos = angles_of_flow(u)
        aoa, aos = math.degrees(aoa), math.degrees(aos)
    else:
        aoa = aos = math.nan
    # plain Python floats: the csv module writes them (repr, exact round trip) far faster than numpy's
    return [status, float(c.altitude), float(c.mass_density), float(c.temperature), float(c.speed),
            *wind.tolist(), aoa, aos, float(sample.drag_coefficient),
            *np.concatenate([sample.force_coefficients, sample.moment_coefficients, sample.force,
                             sample.torque]).tolist()]


def _read_messages(reader, path, connections):
    """reader.messages(), with any failure of the reader turned into a BagError naming the file."""
    iterator = reader.messages(connections=connections)
    count = 0
    while True:
        try:
            item = next(iterator)
        except StopIteration:
            return
        except Exception as exc:  # rosbags raises many kinds (ReaderError, struct, zstd, apsw ...)
            raise BagError(f"input bag {path}: corrupt or truncated after {count} messages "
                           f"({type(exc).__name__}: {exc})") from None
        count += 1
        yield item


def _decode(raw, msgtype, topic, index, path):
    try:
        return bag_io.deserialize(raw, msgtype)
    except Exception as exc:
        raise BagError(f"input bag {path}: message {index} on {topic} cannot be decoded as {msgtype} "
                       f"({type(exc).__name__}: {exc})") from None


def _check_topics(reader, path, topics_types):
    """Every (topic, msgtype) required must be in the bag with that type only and have messages."""
    by_topic = collections.defaultdict(set)
    counts = collections.Counter()
    for conn in reader.connections:
        by_topic[conn.topic].add(conn.msgtype)
        counts[conn.topic] += conn.msgcount
    listing = ", ".join(f"{t} ({', '.join(sorted(ty))})" for t, ty in sorted(by_topic.items())) or "none"
    for option, topic, msgtype in topics_types:
        if topic not in by_topic:
            raise BagError(f"input bag {path}: no topic {topic} (given by {option}); the bag has: {listing}")
        other = by_topic[topic] - {msgtype}
        if other:
            raise BagError(f"input bag {path}: topic {topic} (given by {option}) has message type "
                           f"{', '.join(sorted(other))}; expected {msgtype}")
        if counts[topic] == 0:
            raise BagError(f"input bag {path}: topic {topic} (given by {option}) has no messages")
    return by_topic


def _output_path(path, overwrite: bool, what: str) -> Path | None:
    if path is None:
        return None
    path = Path(path)
    if path.exists() and not overwrite:
        raise BagError(f"output {what} {path}: already exists (choose another name, or overwrite it: --overwrite)")
    return path


def analyze_bag(bag, attitude_topic: str = "/attitude", state_topic: str = "/state",
                models=None, out_bag=None, out_csv=None, plots_dir=None, storage: str = "mcap",
                progress: bool = False, overwrite: bool = False) -> AnalysisReport:
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

    Returns
    -------
    AnalysisReport

    Raises
    ------
    BagError
        Before anything is written: the input cannot be opened, a topic is missing, has another
        message type or no messages, or an output exists. (A fault found while reading is
        reported in :attr:`AnalysisReport.error` instead, with the outputs written so far.)
    ValueError, MeshError
        For models that cannot be set up.
    """
    t_start = time.perf_counter()
    bag = Path(bag)
    models = list(models) if models else [("default", WrenchSettings.from_parameters({}))]
    labels = [check_label(label) for label, _ in models]
    if len(set(labels)) != len(labels):
        raise ValueError(f"model labels must differ, got {', '.join(labels)}")
    bag_io.storage_plugin(storage)  # an unknown storage name fails before any work
    out_bag = _output_path(out_bag, overwrite, "bag")
    out_csv = _output_path(out_csv, overwrite, "CSV")
    plots_dir = _output_path(plots_dir, overwrite, "plot directory")

    reader = bag_io.open_bag(bag)
    try:
        needed = []
        if any(s.attitude_source == "attitude_topic" for _, s in models):
            needed.append(("--attitude-topic", attitude_topic, bag_io.QUATERNION_STAMPED))
        needed.append(("--state-topic", state_topic, bag_io.ODOMETRY))
        by_topic = _check_topics(reader, bag, needed)
        meshes = {}
        runs = []
        for label, settings in models:
            key = (settings.mesh, settings.mesh_scale)
            if key not in meshes:
                meshes[key] = resolve_mesh(settings.mesh, settings.mesh_scale)
            runs.append(_ModelRun(label, settings, meshes[key]))
        for run in runs:
            for topic in (run.summary.wrench_topic, run.summary.coefficients_topic):
                if topic in by_topic:
                    raise BagError(f"input bag {bag}: already has topic {topic}; give the model another label")
        if by_topic.get(DIAGNOSTICS_TOPIC, {bag_io.DIAGNOSTIC_ARRAY}) != {bag_io.DIAGNOSTIC_ARRAY}:
            raise BagError(f"input bag {bag}: topic {DIAGNOSTICS_TOPIC} has another type than "
                           f"{bag_io.DIAGNOSTIC_ARRAY}; the diagnostics cannot be added to it")
        report = AnalysisReport(bag, models=[r.summary for r in runs], messages_total=reader.message_count)
        _Analysis(reader, bag, runs, attitude_topic, state_topic, report).run(
            out_bag, out_csv, plots_dir, storage, progress, overwrite)
    finally:
        reader.close()
    report.seconds["total"] = time.perf_counter() - t_start
    _summarise(report, runs, attitude_topic, state_topic)
    return report


class _Analysis:
    """The replay loop and its outputs (one use)."""

    def __init__(self, reader, path, runs, attitude_topic, state_topic, report):
        self.reader, self.path, self.runs, self.report = reader, path, runs, report
        self.attitude_topic, self.state_topic = attitude_topic, state_topic
        self.seconds = collections.Counter()
        self.rows_stamp, self.rows_data = [], {r.label: [] for r in runs}  # stamps [ns], model cells
        self.first_attitude_ns = self.first_state_ns = None

    def run(self, out_bag, out_csv, plots_dir, storage, progress, overwrite):
        report = self.report
        writer = bag_io.BagWriter(out_bag, storage, overwrite) if out_bag is not None else None
        csv_tmp = None
        try:
            csv_file = None
            if out_csv is not None:
                out_csv.parent.mkdir(parents=True, exist_ok=True)
                fd, csv_tmp = tempfile.mkstemp(prefix=f".{out_csv.name}.", suffix=".partial", dir=out_csv.parent)
                csv_file = os.fdopen(fd, "w", newline="", encoding="utf-8")
                self.csv = csv.writer(csv_file)
                self.csv.writerow(list(COMMON_COLUMNS) + [f"{r.label}.{c}" for r in self.runs for c in MODEL_COLUMNS])
            else:
                self.csv = None
            try:
                self._loop(writer, progress)
            except BagError as exc:
                report.error = str(exc)
            last_ns = self._last_ns
            if writer is not None and last_ns is not None:
                for run in self.runs:  # a last status with the final counts, at the end of the bag
                    writer.write(DIAGNOSTICS_TOPIC, last_ns,
                                 bag_io.diagnostic_array_message(last_ns, [run.diagnostic_status(last_ns)]))
            if csv_file is not None:
                csv_file.close()
                os.replace(csv_tmp, out_csv)
                csv_tmp = None
                report.outputs["csv"] = out_csv
            if writer is not None:
                t0 = time.perf_counter()
                report.outputs["bag"] = writer.commit()
                self.seconds["write"] += time.perf_counter() - t0
                writer = None
        finally:
            if writer is not None:
                writer.discard()
            if csv_tmp is not None:
                try:
                    csv_file.close()
                finally:
                    os.unlink(csv_tmp)
        if plots_dir is not None and self.rows_stamp:
            t0 = time.perf_counter()
            self._plots(plots_dir, overwrite)
            self.seconds["plots"] += time.perf_counter() - t0
        report.seconds.update(self.seconds)

    def _loop(self, writer, progress):
        from tqdm import tqdm

        report, runs = self.report, self.runs
        out_conns = {}
        self._last_ns = None
        pc = time.perf_counter
        bar = tqdm(total=report.messages_total, unit="msg", disable=not progress, desc=f"analyse {self.path.name}")
        try:
            t0 = pc()
            for conn, t_ns, raw in _read_messages(self.reader, self.path, self.reader.connections):
                if self._last_ns is None:
                    for run in runs:
                        run.next_diag_ns = t_ns + run.diag_period_ns
                self._last_ns = t_ns
                report.messages_read += 1
                if writer is not None:
                    t1 = pc()
                    self.seconds["read"] += t1 - t0
                    for run in runs:
                        while run.next_diag_ns <= t_ns:
                            writer.write(DIAGNOSTICS_TOPIC, run.next_diag_ns, bag_io.diagnostic_array_message(
                                run.next_diag_ns, [run.diagnostic_status(run.next_diag_ns)]))
                            run.next_diag_ns += run.diag_period_ns
                    out = out_conns.get(conn.id)
                    if out is None:
                        out = out_conns[conn.id] = writer.connection(
                            conn.topic, conn.msgtype, conn.msgdef.data, conn.digest)
                    writer.write_raw(out, t_ns, raw)
                    t0 = pc()
                    self.seconds["write"] += t0 - t1
                topic = conn.topic
                if topic == self.state_topic:
                    msg = _decode(raw, conn.msgtype, topic, report.messages_read, self.path)
                    t1 = pc()
                    self.seconds["read"] += t1 - t0
                    if self.first_state_ns is None:
                        self.first_state_ns = t_ns
                    results = [run.on_state(msg, t_ns) for run in runs]
                    t0 = pc()
                    self.seconds["estimate"] += t0 - t1
                    self._emit(writer, topic, t_ns, msg, results)
                elif topic == self.attitude_topic:
                    msg = _decode(raw, conn.msgtype, topic, report.messages_read, self.path)
                    t1 = pc()
                    self.seconds["read"] += t1 - t0
                    if self.first_attitude_ns is None:
                        self.first_attitude_ns = t_ns
                    results = [run.on_attitude(msg) for run in runs]
                    t0 = pc()
                    self.seconds["estimate"] += t0 - t1
                    self._emit(writer, topic, t_ns, msg, results)
                bar.update(1)
                t0 = pc()
        finally:
            bar.close()

    def _emit(self, writer, topic, t_ns, msg, results):
        """Write the wrenches of one trigger message and its CSV row."""
        if all(r is None for r in results):
            return
        pc = time.perf_counter
        t0 = pc()
        stamp = msg.header.stamp
        if writer is not None:
            for run, result in zip(self.runs, results):
                if result is not None and result[1] is not None:
                    sample, frame = result[1], run.settings.body_frame_id
                    writer.write(run.summary.wrench_topic, t_ns,
                                 bag_io.wrench_stamped_message(stamp, frame, sample.force, sample.torque))
                    writer.write(run.summary.coefficients_topic, t_ns, bag_io.wrench_stamped_message(
                        stamp, frame, sample.force_coefficients, sample.moment_coefficients))
        t1 = pc()
        self.seconds["write"] += t1 - t0
        stamp_s = bag_io.stamp_seconds(stamp)
        stamp_ns = bag_io.stamp_nanoseconds(stamp)
        self.rows_stamp.append(stamp_ns)
        cells = []
        for run, result in zip(self.runs, results):
            status, sample = result if result is not None else ("", None)
            values = _row_values(status, sample)
            self.rows_data[run.label].append(values[1:])
            cells.extend(values)
        if self.csv is not None:
            utc = _utc_text(self.runs[0].estimator, stamp_s)
            self.csv.writerow([stamp_s, utc, (stamp_ns - self.rows_stamp[0]) * 1e-9, topic, *cells])
        self.seconds["csv"] += pc() - t1

    def _plots(self, plots_dir, overwrite):
        try:
            from .plots import plot_time_series
        except ModuleNotFoundError as exc:
            if exc.name != "adbsat_ros.plots":
                raise
            self.report.warnings.append("plots not written: adbsat_ros.plots is not available")
            return
        stamps_ns = np.asarray(self.rows_stamp, dtype=np.int64)
        time_s = (stamps_ns - stamps_ns[0]) * 1e-9
        index = {c: i - 1 for i, c in enumerate(MODEL_COLUMNS)}
        runs = {}
        for run in self.runs:
            data = np.asarray(self.rows_data[run.label], dtype=float)
            cols = lambda *names: data[:, [index[n] for n in names]]  # noqa: E731
            runs[run.label] = {
                "force": cols("force_x_N", "force_y_N", "force_z_N"),
                "torque": cols("torque_x_Nm", "torque_y_Nm", "torque_z_Nm"),
                "density": data[:, index["density_kg_m3"]],
                "drag_coefficient": data[:, index["drag_coefficient"]],
            }
        plots_dir = Path(plots_dir)
        plots_dir.parent.mkdir(parents=True, exist_ok=True)
        tmp = Path(tempfile.mkdtemp(prefix=f".{plots_dir.name}.", suffix=".partial", dir=plots_dir.parent))
        try:
            written = plot_time_series(time_s, runs, tmp)
            if plots_dir.exists():
                shutil.rmtree(plots_dir)
            os.replace(tmp, plots_dir)
        finally:
            shutil.rmtree(tmp, ignore_errors=True)
        self.report.outputs["plots"] = [plots_dir / Path(p).name for p in written]


def _utc_text(estimator, stamp_s: float) -> str:
    try:
        return estimator.utc(stamp_s).isoformat()
    except (OverflowError, ValueError, OSError):
        return ""


def _summarise(report: AnalysisReport, runs, attitude_topic, state_topic) -> None:
    """Turn the rejections into warnings that say what was wrong with the input."""
    for run in runs:
        rejections = dict(run.estimator.rejections)
        run.summary.rejections = rejections
        for reason, count in sorted(rejections.items()):
            if reason == "no_state":
                text = (f"{count} messages on {attitude_topic} came before the first usable state on "
                        f"{state_topic}: no wrench for them")
            else:
                text = f"{count} inputs rejected ({reason}), first: {run.summary.first_rejection.get(reason, '')}"
            report.warnings.append(f"model {run.label}: {text}")
        if run.summary.triggers and not run.summary.wrenches:
            report.warnings.append(f"model {run.label}: no wrench computed from {run.summary.triggers} inputs")
