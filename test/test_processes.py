"""The signal handling of a command (adbsat_ros.processes) in this process: a stop that comes
while an import is under way (in the import machinery or in the code of a module it runs) is
raised once every import has returned, never inside one."""

import importlib
import signal
import sys
import time
import types

import pytest
from waiting import HANG_TIMEOUT

from adbsat_ros.processes import Interrupted, handle_signals, raising_signals, signal_name


def handler():
    return signal.getsignal(signal.SIGTERM)


def wait_for_the_stop(left: list, where: str) -> None:
    """Note ``where`` in ``left``, then wait for the stop that comes a moment later."""
    left.append(where)
    deadline = time.monotonic() + HANG_TIMEOUT
    while time.monotonic() < deadline:
        time.sleep(0.001)


def test_a_stop_inside_the_import_machinery_is_raised_after_it():
    importing = types.SimpleNamespace(
        f_code=types.SimpleNamespace(co_filename="<frozen importlib._bootstrap>"), f_back=None
    )
    left = []
    with handle_signals():
        with pytest.raises(Interrupted) as stopped:
            with raising_signals():
                handler()(signal.SIGTERM, importing)  # (nothing raised inside the import)
                wait_for_the_stop(left, "the import machinery")
        assert stopped.value.signum == signal.SIGTERM and signal_name() == "SIGTERM"
        assert left == ["the import machinery"]
    assert signal.getitimer(signal.ITIMER_REAL) == (0.0, 0.0)


def test_a_stop_in_the_code_of_a_module_being_imported_is_raised_after_the_import(tmp_path):
    """The signal comes while the module's own code runs (what an extension module importing
    another from C also runs): the module is imported whole, then the command stops."""
    (tmp_path / "signalled_module.py").write_text(
        "import signal, sys, time\n"
        "signal.getsignal(signal.SIGINT)(signal.SIGINT, sys._getframe())\n"
        "time.sleep(0.05)  # (the retry comes here, still inside the import)\n"
        "IMPORTED_WHOLE = True\n",
        encoding="utf-8",
    )
    sys.path.insert(0, str(tmp_path))
    left = []
    try:
        with handle_signals():
            with pytest.raises(Interrupted) as stopped:
                with raising_signals():
                    module = importlib.import_module("signalled_module")
                    wait_for_the_stop(left, "the import")
            assert stopped.value.signum == signal.SIGINT and signal_name() == "SIGINT"
    finally:
        sys.path.remove(str(tmp_path))
        sys.modules.pop("signalled_module", None)
    assert module.IMPORTED_WHOLE and left == ["the import"]
    assert signal.getitimer(signal.ITIMER_REAL) == (0.0, 0.0)


def test_a_stop_elsewhere_is_raised_where_it_comes():
    with handle_signals():
        with pytest.raises(Interrupted):
            with raising_signals():
                handler()(signal.SIGINT, None)
        assert signal_name() == "SIGINT"
