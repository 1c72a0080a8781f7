"""One model's cumulative state rebuilt in bag order from the workers' records, and its diagnostics.

What the node would have accumulated over the bag (counters, latest sample and rejection, state
age in bag time, one shading cache's counts), written as the node's DiagnosticStatus.
"""

from __future__ import annotations

import collections

from adbsat_ros.bags import io as bag_io
from adbsat_ros.bags.report import NODE_NAME, ModelSummary
from adbsat_ros.bags.worker import MessageRecord
from adbsat_ros.estimator.estimator import AeroWrenchEstimator
from adbsat_ros.estimator.health import Health
from adbsat_ros.estimator.settings import WrenchSettings
from adbsat_ros.lru import LruStore

_NS = 1_000_000_000


def _cell() -> bool:
    """What the merge keeps of a cell: that it is stored."""
    return True


#: Diagnostic keys of the live node that bag analysis leaves out: its knot grid's counters (the
#: workers evaluate the knots; the merge, which writes the diagnostics, does not see them).
LIVE_ONLY_KEYS = (
    "conditions_prepared_used",
    "conditions_knot_hits",
    "conditions_knot_misses",
    "conditions_evaluations",
)


class ModelState:
    """One model on the merge side: the node's cumulative state after the records applied so far."""

    def __init__(self, label: str, settings: WrenchSettings, mesh):
        self.label = label
        self.settings = settings
        self.mesh = mesh
        # Checks the settings before anything is written; gives diagnostic_values() its static
        # part (reference, database) and probes chunk split points. It never computes a wrench.
        self.estimator = AeroWrenchEstimator(settings, mesh)
        self.summary = ModelSummary.of_label(label)
        self.rejections = collections.Counter()
        self.published = 0
        # the keys of one ShadingCache fed every query in bag order (its bound, its counts)
        self.cache = LruStore(settings.shading_cache_size)
        self.health = Health(ticks_per_second=_NS)
        self.diagnostics_period_ns = max(1, int(round(settings.diagnostics_period * _NS)))
        self.next_diagnostics_ns = None

    def apply(self, record: MessageRecord, t_ns: int) -> None:
        """Account for one message's record, logged at t_ns [ns]."""
        if record.state_accepted:
            self.health.state_accepted(t_ns)
        if record.status is not None:
            self.summary.triggers += 1
        if record.reason is not None:
            self.rejections[record.reason] += 1
            self.summary.first_rejection.setdefault(record.reason, record.reason_text)
            if record.latest_rejection:
                self.health.rejected(record.reason)
        if record.numbers is not None:
            self.published += 1
            self.summary.wrenches += 1
            self.health.sample_computed(record.compute_seconds, record.numbers)
        for key in record.cache_keys:
            self.cache.get(key, _cell)
        for key in record.uncounted_keys:  # (after the flow's, as the estimator reads them)
            self.cache.get(key, _cell, count=False)

    def diagnostic_status(self, now_ns: int):
        """The node's DiagnosticStatus (rosbags message) after the records applied so far."""
        est, health = self.estimator, self.health
        est.rejections = collections.Counter(self.rejections)
        est.published = self.published
        values = est.diagnostic_values(health.last_sample, health.compute_ms())
        values["shading_cache_hits"] = self.cache.hits  # one cache fed every query in bag order
        values["shading_cache_misses"] = self.cache.misses
        # the live node's knots and their prefetching; the workers' knots are not seen here
        for key in LIVE_ONLY_KEYS:
            del values[key]
        level, message = health.level(now_ns, self.settings, sum(self.rejections.values()))
        return bag_io.diagnostic_status(
            level, f"{NODE_NAME}/{self.label}: aerodynamic wrench", message, est.mesh.source, values
        )

    def accepts_state(self, odometry) -> bool:
        """Whether a freshly reset estimator accepts this Odometry (no rejection, no error)."""
        est = self.estimator
        est.reset()
        try:
            est.on_odometry(odometry)
        except Exception:
            return False
        return True

    def finish(self) -> None:
        """Copy the rejection counts into the summary."""
        self.summary.rejections = dict(self.rejections)
