"""adbsat_node with its callback's parts timed, for bench_node_latency's --trace.

Runs ``adbsat_ros.ros.node.main`` with these parts wrapped in ``time.perf_counter`` calls (a few
microseconds of their own per message): the attitude callback (``AdbsatNode._on_attitude``), the
decoding of its bytes (``decode_attitude`` as the node's core module calls it), the per-message
handler (``MessageHandler.on_attitude``), the estimator alone (``AeroWrenchEstimator.on_attitude``),
the CDR encoding (``encode_wrench``), the publishing and bookkeeping (``AdbsatNode._serve``) and
the preparing of the next stamp (``AeroWrenchEstimator.prepare``); and every garbage collection
(``gc.callbacks``) by generation. ``TRACED_PARTS`` in the environment (comma-separated
``module:Class.method`` or ``module:function``, e.g.
``adbsat_ros.physics.panel_method:PanelMethod.coefficients``) adds parts, timed on every call
after the warm-up (a function is replaced in its own module: one that another module imported by
name is timed there only if given as that module's). At exit it writes one JSON line to stderr,
``TRACE {"part": [microseconds, ...], ...}``, the durations of every call (and collection) after
the first 500 attitudes (the first ray cast and the warm-up). Run it as the node is run: ``python
bench/traced_node.py --ros-args ...``.
"""

import atexit
import gc
import importlib
import json
import os
import sys
import time

from adbsat_ros.estimator import estimator as estimator_module
from adbsat_ros.estimator import handling
from adbsat_ros.ros import node, node_core

WARM_UP_CALLS = 500
#: Parts timed on every call, whose first WARM_UP_CALLS calls are left out at the end; the others
#: (garbage collections, the TRACED_PARTS) are recorded after the warm-up only.
_PARTS = (
    "attitude callback",
    "decode_attitude",
    "handler.on_attitude",
    "estimator.on_attitude",
    "encode_wrench",
    "node._serve",
    "estimator.prepare",
)
_durations = {part: [] for part in _PARTS}
_durations.update({f"gc generation {g}": [] for g in range(3)})
_gc_started = [0.0]


def _on_gc(phase, info):
    if phase == "start":
        _gc_started[0] = time.perf_counter()
    elif _warm():
        _durations[f"gc generation {info['generation']}"].append(
            time.perf_counter() - _gc_started[0]
        )


gc.callbacks.append(_on_gc)

_EVERY_MESSAGE = (*_PARTS, *(f"{part} [thread CPU]" for part in _PARTS))


def _warm() -> bool:
    return len(_durations["attitude callback"]) >= WARM_UP_CALLS


#: With TRACE_CPU=1 in the environment every part also records the CPU time its thread spent in
#: it (``time.thread_time``, a system call of its own per reading), as "PART [thread CPU]": wall
#: time well above it is time the thread waited (preempted, or on a lock), not time it computed.
TRACE_CPU = os.environ.get("TRACE_CPU", "") == "1"


def _timed(function, part, clock=time.perf_counter, suffix=""):
    """``function`` wrapped so that each call's ``clock`` time is recorded under ``part +
    suffix``."""
    record = _durations.setdefault(part + suffix, []).append
    every = part in _EVERY_MESSAGE

    def wrapper(*args, **kwargs):
        t0 = clock()
        try:
            return function(*args, **kwargs)
        finally:
            if every or _warm():
                record(clock() - t0)

    return wrapper


def _traced(function, part):
    """``function`` with its wall time recorded under ``part`` (and with TRACE_CPU its thread's
    CPU time under "PART [thread CPU]", read around the wall-time wrapper)."""
    timed = _timed(function, part)
    return _timed(timed, part, time.thread_time, " [thread CPU]") if TRACE_CPU else timed


node.AdbsatNode._on_attitude = _traced(node.AdbsatNode._on_attitude, "attitude callback")
node_core.decode_attitude = _traced(node_core.decode_attitude, "decode_attitude")
node_core.encode_wrench = _traced(node_core.encode_wrench, "encode_wrench")
handling.MessageHandler.on_attitude = _traced(
    handling.MessageHandler.on_attitude, "handler.on_attitude"
)
estimator_module.AeroWrenchEstimator.on_attitude = _traced(
    estimator_module.AeroWrenchEstimator.on_attitude, "estimator.on_attitude"
)
node.AdbsatNode._serve = _traced(node.AdbsatNode._serve, "node._serve")
estimator_module.AeroWrenchEstimator.prepare = _traced(
    estimator_module.AeroWrenchEstimator.prepare, "estimator.prepare"
)

for _path in filter(None, os.environ.get("TRACED_PARTS", "").split(",")):
    _module_name, _, _attribute = _path.strip().partition(":")
    _owner = importlib.import_module(_module_name)
    *_outer, _name = _attribute.split(".")
    for _part in _outer:
        _owner = getattr(_owner, _part)
    setattr(_owner, _name, _traced(getattr(_owner, _name), _attribute))


@atexit.register
def _report():
    out = {
        part: [
            round(1e6 * d, 1)
            for d in (durations[WARM_UP_CALLS:] if part in _EVERY_MESSAGE else durations)
        ]
        for part, durations in _durations.items()
    }
    print("TRACE " + json.dumps(out), file=sys.stderr, flush=True)


if __name__ == "__main__":
    sys.exit(node.main())
