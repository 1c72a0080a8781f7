"""Offline analysis of recorded flights: the node's wrench at every attitude message of a rosbag2.

:func:`analyze_bag` reads a bag (.mcap or .db3) with ``rosbags`` (no ROS installation needed),
feeds its state and attitude messages in bag order to one
:class:`~adbsat_ros.estimator.estimator.AeroWrenchEstimator` per model, with the node's own decoding
rules (:meth:`adbsat_ros.estimator.estimator.AeroWrenchEstimator.on_odometry`) and its handling of rejected inputs, and writes

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

1. *Read* every message once (raw CDR bytes, held in memory: about the bag's size) and the
   header stamps of the state and attitude ("trigger") messages.
2. *Plan*: cut the trigger messages into contiguous chunks, each starting at a state message
   where an estimator with no history provably gives the sequential outputs
   (:func:`safe_split_points`, and the state must pass a reset estimator's checks); with no
   such place the chunks are fewer (one, at worst).
3. *Compute*: worker processes (``workers``; the estimators and shading caches built once per
   process) decode and replay whole chunks from a reset estimator, and return per message only
   numbers and bytes: rejection reason, latest-sample numbers, compute time, the serialised
   wrench and coefficient messages, the CSV cells, the shading-cache cells queried.
4. *Merge* in bag order: copy the input messages, write the wrenches and CSV rows, and rebuild
   the node's cumulative state (rejection counters, published count, latest sample, state age,
   and the cache hits/misses of one cache fed every query in order) to write the diagnostics.
"""

from __future__ import annotations

import collections
import csv
import itertools
import math
import os
import re
import shutil
import tempfile
import time
import types
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from adbsat_ros.bags import io as bag_io
from adbsat_ros.bags.io import BagError
from adbsat_ros.estimator.estimator import AeroWrenchEstimator
from adbsat_ros.estimator.samples import Rejection
from adbsat_ros.messages.stamps import stamp_seconds
from adbsat_ros.estimator.settings import WrenchSettings
from adbsat_ros.geometry.frames import angles_of_flow
from adbsat_ros.geometry.loading import resolve_mesh
from adbsat_ros.messages.cdr import (
    OdometryFields,
    header_stamp,
    odometry_fields,
    quaternion_stamped_fields,
    wrench_stamped_cdr,
)

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
    "status",
    "altitude_m",
    "density_kg_m3",
    "temperature_K",
    "relative_speed_m_s",
    "wind_body_x_m_s",
    "wind_body_y_m_s",
    "wind_body_z_m_s",
    "aoa_deg",
    "aos_deg",
    "drag_coefficient",
    "CF_x",
    "CF_y",
    "CF_z",
    "CM_x",
    "CM_y",
    "CM_z",
    "force_x_N",
    "force_y_N",
    "force_z_N",
    "torque_x_Nm",
    "torque_y_Nm",
    "torque_z_Nm",
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
        raise ValueError(
            f"model label {label!r}: use letters, digits and '_' and start with a letter"
        )
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
        Wall time by phase: read (reading, and planning the chunks), estimate (computing the
        chunks here, or waiting for the workers: decoding and estimator), write (output bag),
        csv, plots, total.
    workers : int
        Processes that computed the wrenches (1: this process).
    chunks : int
        Chunks the messages were cut into.
    """

    input: Path
    outputs: dict = field(default_factory=dict)
    models: list = field(default_factory=list)
    messages_read: int = 0
    messages_total: int = 0
    error: str | None = None
    warnings: list = field(default_factory=list)
    seconds: dict = field(default_factory=dict)
    workers: int = 1
    chunks: int = 0

    @property
    def partial(self) -> bool:
        """True if the input could not be read to its end."""
        return self.error is not None

    @property
    def wrenches(self) -> int:
        return sum(m.wrenches for m in self.models)


# ================================================================================= worker side
# A worker replays a contiguous chunk of the trigger messages (state and attitude messages in bag
# order) through its own estimators, reset at the chunk's start, and returns per message only
# the numbers and bytes the merge writes (never PanelMethod results).

#: Per model and trigger message: (state_accepted, status, rejection, diagnostics numbers,
#: compute seconds, wrench CDR, coefficients CDR, shading-cache keys queried).
#: status is None (not a trigger for this model), 'ok' or the rejection reason; rejection is
#: None or (reason, text, counts_as_last_rejection).
_NO_RESULT = (False, None, None, None, None, None, None, ())
#: Numbers of the latest sample in the node's DiagnosticStatus (WrenchSample attribute paths).
_DIAG_FIELDS = ("mass_density", "temperature", "altitude", "speed", "speed_ratio", "alpha")
#: Plot columns of MODEL_COLUMNS (force, torque, density, drag coefficient).
_PLOT_COLUMNS = (
    "force_x_N",
    "force_y_N",
    "force_z_N",
    "torque_x_Nm",
    "torque_y_Nm",
    "torque_z_Nm",
    "density_kg_m3",
    "drag_coefficient",
)
_PLOT_INDEX = [MODEL_COLUMNS.index(c) for c in _PLOT_COLUMNS]
_STATE, _ATTITUDE = 0, 1


class _WorkerModel:
    """One model's estimator in a worker, and the node's per-message handling around it."""

    def __init__(self, label: str, settings: WrenchSettings, mesh):
        self.estimator = AeroWrenchEstimator(settings, mesh)
        self.settings = settings
        self.on_attitude_topic = settings.attitude_source == "attitude_topic"
        self.frame = settings.body_frame_id
        self._cache = self.estimator.shading_cache
        self._queries = self._query_count()

    def start_chunk(self) -> None:
        """Reset for a chunk: it starts at a state message a fresh estimator accepts alike."""
        self.estimator.reset()
        self._queries = self._query_count()

    def _query_count(self) -> int:
        return 0 if self._cache is None else self._cache.hits + self._cache.misses

    def _keys(self):
        """The cell key of the shading-cache query made since the last call, if any, so that the
        merge can count hits and misses as one sequential cache would (a worker's cache only saw
        its own chunks). An attitude makes at most one query."""
        count = self._query_count()
        if count == self._queries:
            return ()
        self._queries = count
        return (self._cache.last_key,)

    def on_state(self, msg):
        """The node's _on_state: one record (see _NO_RESULT)."""
        try:
            _, orientation = self.estimator.on_odometry(msg)
        except Rejection as exc:
            return (
                False,
                None,
                (exc.reason, exc.message, True),
                None,
                None,
                None,
                None,
                self._keys(),
            )
        except Exception as exc:  # as the node: never let a message stop the analysis
            return (
                False,
                None,
                ("compute_error", f"{type(exc).__name__}: {exc}", False),
                None,
                None,
                None,
                None,
                self._keys(),
            )
        if self.on_attitude_topic:
            return (True, None, None, None, None, None, None, self._keys())
        return (True, *self._compute(msg.stamp, orientation))

    def on_attitude(self, stamp, quaternion_xyzw):
        """The node's _on_attitude: one record, or None if this model does not use attitudes."""
        if not self.on_attitude_topic:
            return None
        return (False, *self._compute(stamp, list(quaternion_xyzw)))

    def _compute(self, stamp, quaternion):
        try:
            sample = self.estimator.on_attitude(stamp_seconds(stamp), quaternion)
        except Rejection as exc:
            return exc.reason, (exc.reason, exc.message, True), None, None, None, None, self._keys()
        except Exception as exc:  # as the node
            return (
                "compute_error",
                ("compute_error", f"{type(exc).__name__}: {exc}", False),
                None,
                None,
                None,
                None,
                self._keys(),
            )
        c = sample.conditions
        diag = tuple(float(getattr(c, name)) for name in _DIAG_FIELDS) + (
            float(sample.drag_coefficient),
        )
        wrench = wrench_stamped_cdr(
            stamp.sec, stamp.nanosec, self.frame, sample.force, sample.torque
        )
        coefficients = wrench_stamped_cdr(
            stamp.sec,
            stamp.nanosec,
            self.frame,
            sample.force_coefficients,
            sample.moment_coefficients,
        )
        return "ok", None, diag, sample.compute_seconds, wrench, coefficients, self._keys(), sample


class _Undecodable(Exception):
    """A trigger message that cannot be decoded (the analysis stops there)."""


def _attitude_fields(raw):
    """(stamp with .sec/.nanosec, [x, y, z, w]) of a QuaternionStamped's CDR bytes."""
    try:
        return quaternion_stamped_fields(raw)
    except ValueError:
        pass
    try:  # not plain CDR as expected: rosbags decodes it, or says what is wrong
        msg = bag_io.deserialize(raw, bag_io.QUATERNION_STAMPED)
    except Exception as exc:
        raise _Undecodable(f"{type(exc).__name__}: {exc}") from None
    q = msg.quaternion
    return msg.header.stamp, [q.x, q.y, q.z, q.w]


def _decode_odometry(raw) -> OdometryFields:
    """The fields of an Odometry's CDR bytes (as the node reads them: struct, else rosbags)."""
    try:
        return odometry_fields(raw)
    except ValueError:
        pass
    try:  # not plain CDR as expected: rosbags decodes it, or says what is wrong
        return OdometryFields.of_message(bag_io.deserialize(raw, bag_io.ODOMETRY))
    except Exception as exc:
        raise _Undecodable(f"{type(exc).__name__}: {exc}") from None


_NAN_CELLS = ",nan" * (len(MODEL_COLUMNS) - 1)
_NAN_PLOT = [math.nan] * len(_PLOT_COLUMNS)


@dataclass
class _ChunkResult:
    """What a worker returns for one chunk of trigger messages.

    records[i] is a tuple over models of records (see _NO_RESULT); rows[i] is None or
    (utc text, model cells as CSV text, plot numbers) for the CSV row of message i. If message
    ``len(records)`` could not be decoded, ``error`` says why.
    """

    records: list
    rows: list
    error: str | None = None


class _Worker:
    """The models of one process; :meth:`run` replays a chunk from a reset state."""

    def __init__(self, specs):
        self.models = [_WorkerModel(label, settings, mesh) for label, settings, mesh in specs]

    def run(self, chunk) -> _ChunkResult:
        kinds, raws = chunk
        models = self.models
        for m in models:
            m.start_chunk()
        utc_of = models[0].estimator.utc
        records, rows = [], []
        for kind, raw in zip(kinds, raws):
            try:
                if kind == _STATE:
                    msg = _decode_odometry(raw)
                    stamp = msg.stamp
                else:
                    stamp, q = _attitude_fields(raw)
            except _Undecodable as exc:
                return _ChunkResult(records, rows, str(exc))
            if kind == _STATE:
                results = [m.on_state(msg) for m in models]
            else:
                results = [m.on_attitude(stamp, q) for m in models]
            row = None
            if any(r is not None and r[1] is not None for r in results):
                cells, plot = [], []
                for r in results:
                    if r is None or r[1] != "ok":
                        cells.append(("" if r is None or r[1] is None else r[1]) + _NAN_CELLS)
                        plot.extend(_NAN_PLOT)
                    else:
                        values = _row_values("ok", r[8])
                        cells.append(",".join(["ok", *map(repr, values[1:])]))
                        plot.extend(values[i] for i in _PLOT_INDEX)
                row = (_utc_text(utc_of, stamp_seconds(stamp)), ",".join(cells), plot)
            records.append(tuple(_NO_RESULT if r is None else r[:8] for r in results))
            rows.append(row)
        return _ChunkResult(records, rows)


_WORKER: _Worker | None = None


def _init_worker(specs) -> None:
    """Process-pool initializer: load the estimators once per process (mesh, shading cache)."""
    global _WORKER
    _WORKER = _Worker(specs)


def _run_chunk(chunk) -> _ChunkResult:
    return _WORKER.run(chunk)


# ================================================================================= merge side
class _SequentialCacheCount:
    """Hits and misses of one ShadingCache fed every query in bag order (same policy: a repeat of
    the latest cell is a hit without reordering; otherwise LRU with ``max_entries``)."""

    def __init__(self, max_entries):
        self.max_entries = max_entries
        self.store = collections.OrderedDict()
        self.last = None
        self.hits = self.misses = 0

    def query(self, key) -> None:
        if key == self.last:
            self.hits += 1
            return
        store = self.store
        if key in store:
            store.move_to_end(key)
            self.hits += 1
        else:
            self.misses += 1
            store[key] = None
            if self.max_entries is not None and len(store) > self.max_entries:
                store.popitem(last=False)
        self.last = key


class _LatestSample:
    """The numbers of the latest sample that the node's diagnostics read (conditions, C_D)."""

    def __init__(self, numbers):
        self.conditions = types.SimpleNamespace(**dict(zip(_DIAG_FIELDS, numbers)))
        self.drag_coefficient = numbers[-1]


class _ModelRun:
    """One model on the merge side: the node's cumulative state rebuilt from per-message records
    in bag order (counters, latest sample, latest rejection, state age), and its diagnostics."""

    OK, WARN, ERROR = 0, 1, 2

    def __init__(self, label: str, settings: WrenchSettings, mesh):
        self.label = label
        self.settings = settings
        self.mesh = mesh
        # Checks the settings before anything is written; gives diagnostic_values() its static
        # part (reference, database) and probes chunk split points. It never computes a wrench.
        self.estimator = AeroWrenchEstimator(settings, mesh)
        self.summary = ModelSummary(
            label, f"{NAMESPACE}/{label}/wrench", f"{NAMESPACE}/{label}/coefficients"
        )
        self.rejections = collections.Counter()
        self.published = 0
        self.cache = _SequentialCacheCount(settings.shading_cache_size)
        self.compute_ms = collections.deque(maxlen=2000)
        self.last_sample = None
        self.last_rejection_reason = None
        self.last_state_ns = None
        self.diag_period_ns = max(1, int(round(settings.diagnostics_period * _NS)))
        self.next_diag_ns = None

    def apply(self, record, t_ns: int) -> None:
        """Account for one message's record (see _NO_RESULT), logged at t_ns."""
        state_ok, status, rejection, diag, compute_s, _, _, keys = record
        if state_ok:
            self.last_state_ns = t_ns
        if status is not None:
            self.summary.triggers += 1
        if rejection is not None:
            reason, text, is_rejection = rejection
            self.rejections[reason] += 1
            self.summary.first_rejection.setdefault(reason, text)
            if is_rejection:
                self.last_rejection_reason = reason
        if diag is not None:
            self.published += 1
            self.summary.wrenches += 1
            self.compute_ms.append(1e3 * compute_s)
            self.last_sample = diag
        for key in keys:
            self.cache.query(key)

    def diagnostic_status(self, now_ns: int):
        """The node's DiagnosticStatus after the records applied so far, state age in bag time."""
        est, s = self.estimator, self.settings
        est.rejections = collections.Counter(self.rejections)
        est.published = self.published
        sample = None if self.last_sample is None else _LatestSample(self.last_sample)
        values = est.diagnostic_values(sample, self.compute_ms)
        values["shading_cache_hits"] = self.cache.hits  # as one cache fed every query in bag order
        values["shading_cache_misses"] = self.cache.misses
        age = None if self.last_state_ns is None else (now_ns - self.last_state_ns) / _NS
        n_rejected = sum(self.rejections.values())
        if age is None or age > max(s.state_timeout, s.diagnostics_period):
            level, message = (
                self.ERROR,
                "no orbital state" if age is None else f"state is stale ({age:.1f} s old)",
            )
        elif self.last_rejection_reason == "stale_state":
            level, message = self.ERROR, "state is stale relative to the attitude stamps"
        elif n_rejected:
            level, message = self.WARN, f"{n_rejected} inputs rejected so far"
        else:
            level, message = self.OK, "ok"
        return bag_io.diagnostic_status(
            level, f"{NODE_NAME}/{self.label}: aerodynamic wrench", message, est.mesh.source, values
        )

    def accepts_state(self, msg) -> bool:
        """Whether a freshly reset estimator accepts this Odometry (no rejection, no error)."""
        est = self.estimator
        est.reset()
        try:
            est.on_odometry(msg)
        except Exception:
            return False
        return True


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
    return [
        status,
        float(c.altitude),
        float(c.mass_density),
        float(c.temperature),
        float(c.speed),
        *wind.tolist(),
        aoa,
        aos,
        float(sample.drag_coefficient),
        *np.concatenate(
            [sample.force_coefficients, sample.moment_coefficients, sample.force, sample.torque]
        ).tolist(),
    ]


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
            raise BagError(
                f"input bag {path}: corrupt or truncated after {count} messages "
                f"({type(exc).__name__}: {exc})"
            ) from None
        count += 1
        yield item


def safe_split_points(kinds, stamps, attitude_sources) -> np.ndarray:
    """Trigger-message indices where a freshly reset estimator gives the sequential results.

    A chunk starting at index k is replayed by an estimator with no state and no last stamps.
    The sequential estimator at k differs only in its latest state and its last state and
    attitude stamps (the shading cache answers the lighting of the cell centre, whatever it
    holds). Both give the same outputs from k on if the state message at k is accepted by both
    and no later time-goes-backwards test can tell them apart:

    * k is a state message whose stamp is >= every earlier state stamp (so the sequential
      estimator takes it without a time-backwards reset; after it both hold the same state and
      last state stamp), and
    * for every model, no stamp it treats as an attitude (attitude messages, or state messages
      when ``attitude_source`` is odometry) at or after k is earlier than one before k (the
      sequential last attitude stamp is one of the latter, so it never rejects where the fresh
      estimator, with none, accepts; from the first accepted attitude on both hold the same).

    That the state at k passes the message's own checks (frames, finite values, quaternion) is
    tested separately on the decoded message (:meth:`_ModelRun.accepts_state`).

    Parameters
    ----------
    kinds : array_like of int, shape (N,)
        0 for a state message, 1 for an attitude message, in bag order.
    stamps : array_like of float, shape (N,)
        Header stamps [s] as the estimator reads them (sec + 1e-9 nanosec).
    attitude_sources : sequence of str
        Each model's ``attitude_source`` ('attitude_topic' or 'odometry').

    Returns
    -------
    ndarray of int
        Increasing indices k >= 1 (index 0 always starts the first chunk).
    """
    kinds = np.asarray(kinds)
    stamps = np.asarray(stamps, dtype=float)
    n = len(kinds)
    if n < 2:
        return np.zeros(0, dtype=np.int64)
    finite = np.isfinite(stamps)

    def before_max(mask):  # max over j < k of stamps[j] where mask, -inf if none
        x = np.where(mask & finite, stamps, -np.inf)
        out = np.empty(n)
        out[0] = -np.inf
        np.maximum.accumulate(x[:-1], out=out[1:])
        return out

    def from_min(mask):  # min over j >= k of stamps[j] where mask, +inf if none
        x = np.where(mask & finite, stamps, np.inf)
        return np.minimum.accumulate(x[::-1])[::-1]

    is_state = kinds == _STATE
    ok = is_state & finite & (stamps >= before_max(is_state))
    for source in set(attitude_sources):
        trigger = is_state if source == "odometry" else kinds == _ATTITUDE
        ok &= from_min(trigger) >= before_max(trigger)
    ok[0] = False
    return np.flatnonzero(ok)


def _check_topics(reader, path, topics_types):
    """Every (topic, msgtype) required must be in the bag with that type only and have messages."""
    by_topic = collections.defaultdict(set)
    counts = collections.Counter()
    for conn in reader.connections:
        by_topic[conn.topic].add(conn.msgtype)
        counts[conn.topic] += conn.msgcount
    listing = (
        ", ".join(f"{t} ({', '.join(sorted(ty))})" for t, ty in sorted(by_topic.items())) or "none"
    )
    for option, topic, msgtype in topics_types:
        if topic not in by_topic:
            raise BagError(
                f"input bag {path}: no topic {topic} (given by {option}); the bag has: {listing}"
            )
        other = by_topic[topic] - {msgtype}
        if other:
            raise BagError(
                f"input bag {path}: topic {topic} (given by {option}) has message type "
                f"{', '.join(sorted(other))}; expected {msgtype}"
            )
        if counts[topic] == 0:
            raise BagError(f"input bag {path}: topic {topic} (given by {option}) has no messages")
    return by_topic


def _output_path(path, overwrite: bool, what: str) -> Path | None:
    if path is None:
        return None
    path = Path(path)
    if path.exists() and not overwrite:
        raise BagError(
            f"output {what} {path}: already exists (choose another name, or overwrite it: --overwrite)"
        )
    return path


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
        State + attitude messages per chunk (default: enough chunks for 4 per worker, at least
        :data:`MIN_CHUNK_MESSAGES` each; one chunk with one worker).

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
        For models that cannot be set up, or ``workers`` / ``chunk_messages`` < 1.
    """
    t_start = time.perf_counter()
    bag = Path(bag)
    models = list(models) if models else [("default", WrenchSettings.from_parameters({}))]
    labels = [check_label(label) for label, _ in models]
    if len(set(labels)) != len(labels):
        raise ValueError(f"model labels must differ, got {', '.join(labels)}")
    workers = (os.cpu_count() or 1) if workers is None else int(workers)
    if workers < 1:
        raise ValueError(f"workers must be >= 1, got {workers}")
    if chunk_messages is not None and int(chunk_messages) < 1:
        raise ValueError(f"chunk_messages must be >= 1, got {chunk_messages}")
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
                    raise BagError(
                        f"input bag {bag}: already has topic {topic}; give the model another label"
                    )
        if by_topic.get(DIAGNOSTICS_TOPIC, {bag_io.DIAGNOSTIC_ARRAY}) != {bag_io.DIAGNOSTIC_ARRAY}:
            raise BagError(
                f"input bag {bag}: topic {DIAGNOSTICS_TOPIC} has another type than "
                f"{bag_io.DIAGNOSTIC_ARRAY}; the diagnostics cannot be added to it"
            )
        report = AnalysisReport(
            bag, models=[r.summary for r in runs], messages_total=reader.message_count
        )
        analysis = _Analysis(reader, bag, runs, attitude_topic, state_topic, report)
        analysis.read()
    finally:
        reader.close()
    analysis.plan(workers, chunk_messages)
    analysis.run(out_bag, out_csv, plots_dir, storage, progress, overwrite)
    report.seconds["total"] = time.perf_counter() - t_start
    _summarise(report, runs, attitude_topic, state_topic)
    return report


#: Smallest default chunk: below this a process pool costs more than it saves.
MIN_CHUNK_MESSAGES = 250
#: Chunks per worker by default (load balance, and the merge writes while workers compute).
CHUNKS_PER_WORKER = 8


def _pool_context():
    """Fork where available (workers start at once and inherit the imports and meshes)."""
    import multiprocessing

    if "fork" in multiprocessing.get_all_start_methods():
        return multiprocessing.get_context("fork")
    return multiprocessing.get_context()


class _Analysis:
    """Read, plan chunks, compute them (in worker processes or here), merge in bag order (one use)."""

    def __init__(self, reader, path, runs, attitude_topic, state_topic, report):
        self.reader, self.path, self.runs, self.report = reader, path, runs, report
        self.attitude_topic, self.state_topic = attitude_topic, state_topic
        self.seconds = collections.Counter()
        self.rows_stamp, self.rows_plot = [], []  # CSV/plot rows: stamps [ns], plot numbers
        self.specs = [(r.label, r.settings, r.mesh) for r in runs]

    # ----------------------------------------------------------------------------- read
    def read(self):
        """Every message (raw CDR) in bag order, and the header stamps of the trigger messages."""
        t0 = time.perf_counter()
        use_attitudes = any(r.settings.attitude_source == "attitude_topic" for r in self.runs)
        self.connections = {c.id: c for c in self.reader.connections}
        kind_of = {}
        for c in self.reader.connections:
            if c.topic == self.state_topic:
                kind_of[c.id] = _STATE
            elif c.topic == self.attitude_topic and use_attitudes:
                kind_of[c.id] = _ATTITUDE
        self.kind_of = kind_of
        self.messages = []  # (connection id, log time [ns], raw CDR)
        self.trigger_kinds, self.trigger_raws, self.trigger_stamps = [], [], []
        stamps_ok = True
        try:
            for conn, t_ns, raw in _read_messages(self.reader, self.path, self.reader.connections):
                raw = bytes(raw)
                self.messages.append((conn.id, t_ns, raw))
                kind = kind_of.get(conn.id)
                if kind is None:
                    continue
                self.trigger_kinds.append(kind)
                self.trigger_raws.append(raw)
                if stamps_ok:
                    try:
                        sec, nanosec = header_stamp(raw)
                    except ValueError:  # the worker reports it when decoding; no split after it
                        stamps_ok = False
                    else:
                        self.trigger_stamps.append(sec + 1e-9 * nanosec)  # as stamp_seconds()
        except BagError as exc:
            self.report.error = str(exc)
        self.seconds["read"] += time.perf_counter() - t0

    # ----------------------------------------------------------------------------- chunks
    def plan(self, workers: int, chunk_messages: int | None):
        """Cut the trigger messages into chunks [start, stop) at safe split points."""
        t0 = time.perf_counter()
        n = len(self.trigger_kinds)
        if chunk_messages is None:
            chunk_messages = (
                n
                if workers == 1
                else max(MIN_CHUNK_MESSAGES, -(-n // (CHUNKS_PER_WORKER * workers)))
            )
        splits = []
        if chunk_messages < n:
            m = len(self.trigger_stamps)  # stamps known up to here
            candidates = safe_split_points(
                self.trigger_kinds[:m],
                self.trigger_stamps,
                [r.settings.attitude_source for r in self.runs],
            )
            target = chunk_messages
            for k in candidates.tolist():
                if k < target or n - k < max(1, chunk_messages // 4):
                    continue
                if self._accepted_by_fresh_estimators(k):
                    splits.append(k)
                    target = k + chunk_messages
        bounds = [0, *splits, n]
        self.chunks = [(a, b) for a, b in zip(bounds[:-1], bounds[1:]) if b > a]
        self.workers = min(workers, len(self.chunks)) or 1
        self.report.workers, self.report.chunks = self.workers, len(self.chunks)
        self.seconds["read"] += time.perf_counter() - t0

    def _accepted_by_fresh_estimators(self, k: int) -> bool:
        try:
            msg = _decode_odometry(self.trigger_raws[k])
        except _Undecodable:
            return False
        return all(run.accepts_state(msg) for run in self.runs)

    def _chunk_payload(self, chunk):
        a, b = chunk
        return self.trigger_kinds[a:b], self.trigger_raws[a:b]

    def _chunk_results(self):
        """_ChunkResult of each chunk, in order (computed here, or by a pool a few chunks ahead)."""
        if self.workers <= 1:
            worker = _Worker(self.specs)
            for chunk in self.chunks:
                yield worker.run(self._chunk_payload(chunk))
            return
        from concurrent.futures import ProcessPoolExecutor

        with ProcessPoolExecutor(
            max_workers=self.workers,
            mp_context=_pool_context(),
            initializer=_init_worker,
            initargs=(self.specs,),
        ) as pool:
            todo = iter(self.chunks)
            pending = collections.deque(
                pool.submit(_run_chunk, self._chunk_payload(c))
                for c in itertools.islice(todo, 2 * self.workers)
            )
            try:
                while pending:
                    result = pending.popleft().result()
                    chunk = next(todo, None)
                    if chunk is not None:
                        pending.append(pool.submit(_run_chunk, self._chunk_payload(chunk)))
                    yield result
            finally:
                for future in pending:
                    future.cancel()

    # ----------------------------------------------------------------------------- outputs
    def run(self, out_bag, out_csv, plots_dir, storage, progress, overwrite):
        report = self.report
        writer = bag_io.BagWriter(out_bag, storage, overwrite) if out_bag is not None else None
        csv_tmp = csv_file = None
        try:
            if out_csv is not None:
                out_csv.parent.mkdir(parents=True, exist_ok=True)
                fd, csv_tmp = tempfile.mkstemp(
                    prefix=f".{out_csv.name}.", suffix=".partial", dir=out_csv.parent
                )
                csv_file = os.fdopen(fd, "w", newline="", encoding="utf-8")
                csv.writer(csv_file).writerow(
                    list(COMMON_COLUMNS)
                    + [f"{r.label}.{c}" for r in self.runs for c in MODEL_COLUMNS]
                )
            self._merge(writer, csv_file, progress)
            last_ns = self._last_ns
            if writer is not None and last_ns is not None:
                for run in self.runs:  # a last status with the final counts, at the end of the bag
                    writer.write(
                        DIAGNOSTICS_TOPIC,
                        last_ns,
                        bag_io.diagnostic_array_message(last_ns, [run.diagnostic_status(last_ns)]),
                    )
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

    def _merge(self, writer, csv_file, progress):
        """Walk the messages in bag order: copy each, apply its chunk records, write diagnostics,
        wrenches and CSV rows. 'estimate' is the time spent waiting for (or computing) chunks."""
        from tqdm import tqdm

        report, runs, seconds = self.report, self.runs, self.seconds
        pc = time.perf_counter
        self._last_ns = None
        out_conns = {}
        topics = {cid: c.topic for cid, c in self.connections.items()}
        wrench_conns = coeff_conns = None
        if writer is not None:
            wrench_conns = [
                writer.connection(r.summary.wrench_topic, bag_io.WRENCH_STAMPED) for r in runs
            ]
            coeff_conns = [
                writer.connection(r.summary.coefficients_topic, bag_io.WRENCH_STAMPED) for r in runs
            ]
        results = self._chunk_results()
        bounds = iter(self.chunks)
        chunk_stop = 0  # trigger index where the current chunk result ends
        result = None
        trigger = 0
        first_row_ns = None
        bar = tqdm(
            total=report.messages_total,
            unit="msg",
            disable=not progress,
            desc=f"analyse {self.path.name}",
        )
        done = 0
        try:
            t0 = pc()
            for conn_id, t_ns, raw in self.messages:
                if self._last_ns is None:
                    for run in runs:
                        run.next_diag_ns = t_ns + run.diag_period_ns
                self._last_ns = t_ns
                report.messages_read += 1
                done += 1
                if writer is not None:
                    for run in runs:
                        while run.next_diag_ns <= t_ns:
                            writer.write(
                                DIAGNOSTICS_TOPIC,
                                run.next_diag_ns,
                                bag_io.diagnostic_array_message(
                                    run.next_diag_ns, [run.diagnostic_status(run.next_diag_ns)]
                                ),
                            )
                            run.next_diag_ns += run.diag_period_ns
                    out = out_conns.get(conn_id)
                    if out is None:
                        c = self.connections[conn_id]
                        out = out_conns[conn_id] = writer.connection(
                            c.topic, c.msgtype, c.msgdef.data, c.digest
                        )
                    writer.write_raw(out, t_ns, raw)
                if conn_id not in self.kind_of:
                    continue
                if trigger == chunk_stop:  # the next chunk's results
                    t1 = pc()
                    seconds["write"] += t1 - t0
                    bar.update(done)
                    done = 0
                    result = next(results)
                    chunk_start, chunk_stop = next(bounds)
                    t0 = pc()
                    seconds["estimate"] += t0 - t1
                i = trigger - chunk_start
                trigger += 1
                if i == len(result.records):  # this message could not be decoded: stop here
                    c = self.connections[conn_id]
                    report.error = (
                        f"input bag {self.path}: message {report.messages_read} on {c.topic} cannot be "
                        f"decoded as {c.msgtype} ({result.error})"
                    )
                    break
                records = result.records[i]
                for run, record in zip(runs, records):
                    run.apply(record, t_ns)
                row = result.rows[i]
                if row is None:
                    continue
                if writer is not None:
                    for k, record in enumerate(records):
                        if record[5] is not None:
                            writer.write_raw(wrench_conns[k], t_ns, record[5])
                            writer.write_raw(coeff_conns[k], t_ns, record[6])
                t1 = pc()
                seconds["write"] += t1 - t0
                sec, nanosec = header_stamp(raw)
                stamp_ns = sec * _NS + nanosec
                if first_row_ns is None:
                    first_row_ns = stamp_ns
                self.rows_stamp.append(stamp_ns)
                self.rows_plot.append(row[2])
                if csv_file is not None:
                    stamp_s = sec + 1e-9 * nanosec
                    csv_file.write(
                        f"{stamp_s!r},{row[0]},{(stamp_ns - first_row_ns) * 1e-9!r},"
                        f"{topics[conn_id]},{row[1]}\r\n"
                    )
                t0 = pc()
                seconds["csv"] += t0 - t1
            seconds["write"] += pc() - t0
        finally:
            bar.update(done)
            bar.close()
            results.close()

    def _plots(self, plots_dir, overwrite):
        try:
            from adbsat_ros.plotting.time_series import plot_time_series
        except ModuleNotFoundError as exc:
            if exc.name != "adbsat_ros.plotting.time_series":
                raise
            self.report.warnings.append(
                "plots not written: adbsat_ros.plotting.time_series is not available"
            )
            return
        stamps_ns = np.asarray(self.rows_stamp, dtype=np.int64)
        time_s = (stamps_ns - stamps_ns[0]) * 1e-9
        data = np.asarray(self.rows_plot, dtype=float).reshape(
            len(stamps_ns), len(self.runs), len(_PLOT_COLUMNS)
        )
        runs = {}
        for k, run in enumerate(self.runs):
            runs[run.label] = {
                "force": data[:, k, 0:3],
                "torque": data[:, k, 3:6],
                "density": data[:, k, 6],
                "drag_coefficient": data[:, k, 7],
            }
        plots_dir = Path(plots_dir)
        plots_dir.parent.mkdir(parents=True, exist_ok=True)
        tmp = Path(
            tempfile.mkdtemp(prefix=f".{plots_dir.name}.", suffix=".partial", dir=plots_dir.parent)
        )
        try:
            written = plot_time_series(time_s, runs, tmp)
            if plots_dir.exists():
                shutil.rmtree(plots_dir)
            os.replace(tmp, plots_dir)
        finally:
            shutil.rmtree(tmp, ignore_errors=True)
        self.report.outputs["plots"] = [plots_dir / Path(p).name for p in written]


def _utc_text(utc_of, stamp_s: float) -> str:
    try:
        return utc_of(stamp_s).isoformat()
    except (OverflowError, ValueError, OSError):
        return ""


def _summarise(report: AnalysisReport, runs, attitude_topic, state_topic) -> None:
    """Turn the rejections into warnings that say what was wrong with the input."""
    for run in runs:
        rejections = dict(run.rejections)
        run.summary.rejections = rejections
        for reason, count in sorted(rejections.items()):
            if reason == "no_state":
                text = (
                    f"{count} messages on {attitude_topic} came before the first usable state on "
                    f"{state_topic}: no wrench for them"
                )
            else:
                text = f"{count} inputs rejected ({reason}), first: {run.summary.first_rejection.get(reason, '')}"
            report.warnings.append(f"model {run.label}: {text}")
        if run.summary.triggers and not run.summary.wrenches:
            report.warnings.append(
                f"model {run.label}: no wrench computed from {run.summary.triggers} inputs"
            )
