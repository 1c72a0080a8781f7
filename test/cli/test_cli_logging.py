"""The command line's log lines: one line per record, a traceback only with --verbose."""

from __future__ import annotations

import logging
import subprocess
import sys

from adbsat_ros.cli import OneLineFormatter


def _record_with_exception() -> logging.LogRecord:
    try:
        raise ConnectionError("Stream is closed")
    except ConnectionError:
        exc_info = sys.exc_info()
    return logging.LogRecord(
        "distributed.worker", logging.ERROR, __file__, 1, "Failed to heartbeat.", (), exc_info
    )


def test_a_library_exception_is_logged_as_its_message_alone():
    record = _record_with_exception()
    line = OneLineFormatter().format(record)
    assert line == "adbsat-ros: ERROR: Failed to heartbeat."
    assert record.exc_info is not None  # (the record itself is left as it was)


def test_verbose_logging_keeps_the_traceback():
    text = OneLineFormatter(tracebacks=True).format(_record_with_exception())
    assert text.startswith("adbsat-ros: ERROR: Failed to heartbeat.\nTraceback")
    assert "ConnectionError: Stream is closed" in text


WORKER_LOGS = """
import logging
from adbsat_ros.cli import OneLineFormatter
from adbsat_ros.tasks import run_chunks

handler = logging.StreamHandler()
handler.setFormatter(OneLineFormatter())
logging.basicConfig(level=logging.WARNING, handlers=[handler])


class Job:
    key = "worker-logs"

    def setup(self):
        return self

    def evaluate(self, chunk):
        try:
            raise OSError("Stream is closed")
        except OSError:  # as a worker logs losing its scheduler while a signal stops a build
            logging.getLogger("distributed.worker").error(
                "Failed to communicate with scheduler during heartbeat.", exc_info=True
            )
        return chunk


done = []
run_chunks(Job(), {0: 0, 1: 1}, lambda index, result: done.append(result), workers=2)
print(sorted(done))
"""


def test_the_local_workers_error_lines_do_not_reach_the_user():
    """A chunk job on two local Dask workers: what a worker logs at ERROR (with a traceback)
    stays out of the command's stderr; the results arrive."""
    proc = subprocess.run(
        [sys.executable, "-c", WORKER_LOGS], capture_output=True, text=True, timeout=120
    )
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.strip() == "[0, 1]"
    # (other lines a busy machine may bring, a Dask warning say, are not this test's concern)
    assert "heartbeat" not in proc.stderr and "Traceback" not in proc.stderr, proc.stderr
