"""The signal handling of a command (adbsat_ros.processes) in this process: a stop that comes
inside the import machinery is raised once that frame is left, never inside it."""

import signal
import time
import types

import pytest
from waiting import HANG_TIMEOUT

from adbsat_ros.processes import Interrupted, handle_signals, raising_signals, signal_name


def handler():
    return signal.getsignal(signal.SIGTERM)


def test_a_stop_inside_the_import_machinery_is_raised_after_it():
    importing = types.SimpleNamespace(
        f_code=types.SimpleNamespace(co_filename="<frozen importlib._bootstrap>")
    )
    left = []
    with handle_signals():
        with pytest.raises(Interrupted) as stopped:
            with raising_signals():
                handler()(signal.SIGTERM, importing)  # (nothing raised inside the import)
                left.append("the import machinery")
                deadline = time.monotonic() + HANG_TIMEOUT
                while time.monotonic() < deadline:  # (the stop comes here, a moment later)
                    time.sleep(0.001)
        assert stopped.value.signum == signal.SIGTERM and signal_name() == "SIGTERM"
        assert left == ["the import machinery"]
    assert signal.getitimer(signal.ITIMER_REAL) == (0.0, 0.0)


def test_a_stop_elsewhere_is_raised_where_it_comes():
    with handle_signals():
        with pytest.raises(Interrupted):
            with raising_signals():
                handler()(signal.SIGINT, None)
        assert signal_name() == "SIGINT"
