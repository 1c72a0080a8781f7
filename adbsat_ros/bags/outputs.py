"""The bag analysis's outputs, written in bag order; bag and CSV moved in only when complete."""

from __future__ import annotations

import collections
import csv
import os
import shutil
import tempfile
import time
from pathlib import Path

from tqdm import tqdm

from adbsat_ros.bags import io as bag_io
from adbsat_ros.bags.report import DIAGNOSTICS_TOPIC
from adbsat_ros.bags.table import PLOT_SERIES, header, model_extra_columns
from adbsat_ros.plotting.envelope import MinMaxEnvelope
from adbsat_ros.processes import umask

_NS = 1_000_000_000


class _CsvFile:
    """The CSV written under a temporary name beside ``path``, put there by :meth:`commit`."""

    def __init__(self, path: Path, labels, extras=()):
        self.path = path
        path.parent.mkdir(parents=True, exist_ok=True)
        fd, self.tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".partial", dir=path.parent)
        # mkstemp makes it 0600; the file the user gets follows their umask, as open's would
        os.chmod(fd, 0o666 & ~umask())
        self.file = os.fdopen(fd, "w", newline="", encoding="utf-8")
        csv.writer(self.file).writerow(header(labels, extras))

    def commit(self, path: Path | None = None) -> Path:
        """Close the file and move it to ``path`` (default its own); returns where it is."""
        self.file.close()
        path = self.path if path is None else path
        os.replace(self.tmp, path)
        return path

    def discard(self) -> None:
        try:
            self.file.close()
        finally:
            os.unlink(self.tmp)


class _Walk:
    """One walk over the messages in bag order (see :func:`write_outputs`)."""

    def __init__(self, replay: tuple, writer, csv_file, seconds, keep_plot_rows: bool):
        self.read, self.stream, self.chunks, self.results, self.states, self.report = replay
        self.writer, self.csv_file, self.seconds = writer, csv_file, seconds
        self.last_ns = None
        # the plots' numbers, when plots are asked for, as a min/max envelope over time bins:
        # memory bounded by the bins, not the flight
        self.plot_envelope = (
            MinMaxEnvelope(len(self.states) * PLOT_SERIES) if keep_plot_rows else None
        )
        self.out_connections = {}
        self.topics = {cid: c.topic for cid, c in self.read.connections.items()}
        if writer is not None:
            self.model_connections = [_model_connections(writer, s) for s in self.states]

    def diagnostics(self, state, t_ns: int) -> None:
        self.writer.write(
            DIAGNOSTICS_TOPIC,
            t_ns,
            bag_io.diagnostic_array_message(t_ns, [state.diagnostic_status(t_ns)]),
        )

    def copy(self, conn_id: int, t_ns: int, raw: bytes) -> None:
        """Copy an input message, after the diagnostics due by its log time."""
        writer = self.writer
        for state in self.states:
            while state.next_diagnostics_ns <= t_ns:
                self.diagnostics(state, state.next_diagnostics_ns)
                state.next_diagnostics_ns += state.diagnostics_period_ns
        out = self.out_connections.get(conn_id)
        if out is None:
            c = self.read.connections[conn_id]
            out = self.out_connections[conn_id] = writer.connection(
                c.topic, c.msgtype, c.msgdef.data, c.digest
            )
        writer.write_raw(out, t_ns, raw)

    def run(self, progress: bool, stop=None) -> None:
        report, states, seconds, writer = self.report, self.states, self.seconds, self.writer
        pc = time.perf_counter
        bounds = iter(self.chunks)
        chunk_start = chunk_stop = 0  # trigger indices of the current chunk result
        result = None
        trigger = 0
        first_row_ns = None
        bar = tqdm(
            total=report.messages_total,
            unit="msg",
            disable=not progress,
            desc=f"analyse {report.input.name}",
        )
        done = 0
        try:
            t0 = pc()
            for conn_id, t_ns, raw in self.stream.messages():
                if stop is not None and stop.is_set():
                    report.error = f"stopped by a signal after {report.messages_read} messages"
                    break
                if self.last_ns is None:
                    for state in states:
                        state.next_diagnostics_ns = t_ns + state.diagnostics_period_ns
                self.last_ns = t_ns
                report.messages_read += 1
                done += 1
                if writer is not None:
                    self.copy(conn_id, t_ns, raw)
                if conn_id not in self.read.kind_of:
                    continue
                if trigger == chunk_stop:  # the next chunk's results
                    t1 = pc()
                    seconds["write"] += t1 - t0
                    bar.update(done)
                    done = 0
                    result = next(self.results)
                    chunk_start, chunk_stop = next(bounds)
                    t0 = pc()
                    seconds["estimate"] += t0 - t1
                i = trigger - chunk_start
                trigger += 1
                if i == len(result.records):  # this message could not be decoded: stop here
                    c = self.read.connections[conn_id]
                    report.error = (
                        f"input bag {report.input}: message {report.messages_read} on {c.topic} "
                        f"cannot be decoded as {c.msgtype} ({result.error})"
                    )
                    break
                records = result.records[i]
                for state, record in zip(states, records):
                    state.apply(record, t_ns)
                row = result.rows[i]
                if row is None:
                    continue
                if writer is not None:
                    for record, connections in zip(records, self.model_connections):
                        for field, connection in connections:
                            raw = getattr(record, field)
                            if raw is not None:
                                writer.write_raw(connection, t_ns, raw)
                t1 = pc()
                seconds["write"] += t1 - t0
                sec, nanosec = row.stamp_sec, row.stamp_nanosec  # (as decoded, either way)
                stamp_ns = sec * _NS + nanosec
                if first_row_ns is None:
                    first_row_ns = stamp_ns
                if self.plot_envelope is not None:
                    self.plot_envelope.add((stamp_ns - first_row_ns) * 1e-9, row.plot)
                if self.csv_file is not None:
                    stamp_s = sec + 1e-9 * nanosec
                    self.csv_file.file.write(
                        f"{stamp_s!r},{row.utc},{(stamp_ns - first_row_ns) * 1e-9!r},"
                        f"{self.topics[conn_id]},{row.cells}\r\n"
                    )
                t0 = pc()
                seconds["csv"] += t0 - t1
            seconds["write"] += pc() - t0
        finally:
            bar.update(done)
            bar.close()
            self.results.close()


def _model_connections(writer, state) -> list:
    """``(record field, connection)`` of each message a model writes, in the order written."""
    s, wrench = state.summary, bag_io.WRENCH_STAMPED
    topics = [("wrench_cdr", s.wrench_topic), ("coefficients_cdr", s.coefficients_topic)]
    if state.settings.solar_pressure:
        topics += [("solar_cdr", s.solar_topic), ("total_cdr", s.total_topic)]
    connections = [(field, writer.connection(topic, wrench)) for field, topic in topics]
    if state.estimator.body is not None:
        joints = writer.connection(s.joint_torques_topic, bag_io.JOINT_STATE)
        connections.append(("joint_torques_cdr", joints))
    return connections


def partial_path(path) -> Path:
    """Where an output goes after an early stop: ``flight.PARTIAL.csv``, ``out.PARTIAL``."""
    path = Path(path)
    return path.with_name(f"{path.stem}.PARTIAL{path.suffix}")


def write_outputs(replay: tuple, outputs: tuple, stop=None) -> None:
    """Walk the messages in bag order and write the outputs; ``replay``: what the walk goes
    through, ``(read, stream, chunks, results, states, report)``: both passes over the input,
    the chunks and their results, the models' states and the report; ``outputs``: ``(bag, csv,
    plots, storage, overwrite, progress)``, the paths None when not asked for."""
    states, report = replay[4:]
    out_bag, out_csv, plots_dir, storage, overwrite, progress = outputs
    seconds = collections.Counter()
    writer = bag_io.BagWriter(out_bag, storage, overwrite) if out_bag is not None else None
    csv_file = None
    try:
        if out_csv is not None:
            csv_file = _CsvFile(
                out_csv,
                [s.label for s in states],
                [model_extra_columns(s.estimator) for s in states],
            )
        walk = _Walk(replay, writer, csv_file, seconds, keep_plot_rows=plots_dir is not None)
        walk.run(progress, stop)
        if report.error is not None:  # kept, under names that say so
            out_csv = None if out_csv is None else partial_path(out_csv)
            plots_dir = None if plots_dir is None else partial_path(plots_dir)
        if writer is not None and walk.last_ns is not None:
            for state in states:  # a last status with the final counts, at the end of the bag
                walk.diagnostics(state, walk.last_ns)
        if csv_file is not None:
            report.outputs["csv"] = csv_file.commit(out_csv)
            csv_file = None
        if writer is not None:
            t0 = time.perf_counter()
            report.outputs["bag"] = writer.commit(
                None if report.error is None else partial_path(out_bag)
            )
            seconds["write"] += time.perf_counter() - t0
            writer = None
    finally:
        if writer is not None:
            writer.discard()
        if csv_file is not None:
            csv_file.discard()
    signalled = report.error is not None and stop is not None and stop.is_set()
    if plots_dir is not None and len(walk.plot_envelope) and not signalled:  # (a signal: stop now)
        t0 = time.perf_counter()
        historical = [s.label for s in states if s.settings.space_weather != "fixed"]
        write_plots(plots_dir, walk.plot_envelope, [s.label for s in states], report, historical)
        seconds["plots"] += time.perf_counter() - t0
    report.seconds.update(seconds)


_WEATHER = ((8, "drag"), (9, "f107"), (10, "ap"))  # (their series after the model's first)


def write_plots(plots_dir, envelope, labels, report, historical=()) -> None:
    """PNGs of force, torque, density and C_D of every model against time into ``plots_dir``;
    with models of ``historical`` labels, their density and drag with F10.7 and Ap."""
    # imported when plots are asked for: matplotlib is slow to import
    from adbsat_ros.plotting.figures import save_figures
    from adbsat_ros.plotting.time_series import make_line_figures, make_space_weather_figure

    n = PLOT_SERIES
    lines, weather = {}, {}
    for k, label in enumerate(labels):
        series = [envelope.series(k * n + j) for j in range(n)]
        lines[label] = {
            "force": series[0:3],
            "torque": series[3:6],
            "density": series[6:7],
            "drag_coefficient": series[7:8],
        }
        if label in historical:
            weather[label] = {key: series[j : j + 1] for j, key in ((6, "density"), *_WEATHER)}
    plots_dir = Path(plots_dir)
    plots_dir.parent.mkdir(parents=True, exist_ok=True)
    tmp = Path(
        tempfile.mkdtemp(prefix=f".{plots_dir.name}.", suffix=".partial", dir=plots_dir.parent)
    )
    os.chmod(tmp, 0o777 & ~umask())  # (mkdtemp makes it 0700: the directory follows the umask)
    try:
        figures = make_line_figures(lines)
        if weather:
            figures["space_weather"] = make_space_weather_figure(weather)
        written = save_figures(figures, tmp)
        if plots_dir.exists():
            shutil.rmtree(plots_dir)
        os.replace(tmp, plots_dir)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    report.outputs["plots"] = [plots_dir / Path(p).name for p in written]
