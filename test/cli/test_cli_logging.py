"""The command line's log lines: one line per record, a traceback only with --verbose."""

from __future__ import annotations

import logging
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
