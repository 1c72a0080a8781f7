"""Test-wide settings: ROS 2 discovery kept on this machine, a ROS domain per run, no skips in CI.

Tests that need ROS 2 carry the ``ros`` marker and call ``pytest.importorskip("rclpy")``, so the
rest of the suite runs without the ROS wheels. With ``ADBSAT_ROS_FAIL_ON_SKIP=1`` (set by .ci/run)
every skipped test, and every test module skipped at collection, counts as a failure instead:
CI installs everything and must run everything.
"""

import os
import shutil
import tempfile

import pytest

# Default Fast DDS discovery multicasts out of the machine: keep it on localhost.
os.environ.setdefault("ROS_AUTOMATIC_DISCOVERY_RANGE", "LOCALHOST")
# One ROS domain per test run (0-101 are valid), so parallel runs do not see each other.
os.environ.setdefault("ROS_DOMAIN_ID", str(10 + os.getpid() % 90))

# Meshes checked during the run are kept in a store of the run's own, not in the user's cache
# (adbsat_ros.geometry.mesh_store); command lines started by tests inherit it.
RUN_CACHE_DIR = tempfile.mkdtemp(prefix="adbsat_ros_test_cache_")
os.environ["ADBSAT_ROS_CACHE_DIR"] = RUN_CACHE_DIR

FAIL_ON_SKIP = "ADBSAT_ROS_FAIL_ON_SKIP"


def failing_on_skip():
    """True when a skip must count as a failure (``ADBSAT_ROS_FAIL_ON_SKIP=1``)."""
    return os.environ.get(FAIL_ON_SKIP, "") == "1"


def skip_reason(longrepr):
    """The reason text of a skip report (pytest stores ``(path, line, reason)`` for skips)."""
    if isinstance(longrepr, tuple) and len(longrepr) == 3:
        return str(longrepr[2])
    return str(longrepr)


def pytest_unconfigure(config):
    """Remove the run's mesh store."""
    shutil.rmtree(RUN_CACHE_DIR, ignore_errors=True)


def pytest_configure(config):
    """Under ``ADBSAT_ROS_FAIL_ON_SKIP=1`` keep running after a module failed at collection."""
    if failing_on_skip():
        # a module skipped at collection becomes a collection error below; run the others anyway
        config.option.continue_on_collection_errors = True


@pytest.hookimpl(hookwrapper=True)
def pytest_make_collect_report(collector):
    """A test module skipped at collection (e.g. no rclpy) fails under ``FAIL_ON_SKIP``."""
    outcome = yield
    report = outcome.get_result()
    if failing_on_skip() and report.skipped:
        report.outcome = "failed"
        report.longrepr = (
            f"{collector.nodeid} was skipped while {FAIL_ON_SKIP}=1 (CI runs every test): "
            f"{skip_reason(report.longrepr)}"
        )


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_makereport(item, call):
    """A skipped test fails under ``FAIL_ON_SKIP`` (expected failures, xfail, are left alone)."""
    outcome = yield
    report = outcome.get_result()
    if failing_on_skip() and report.skipped and not hasattr(report, "wasxfail"):
        report.outcome = "failed"
        report.longrepr = (
            f"{item.nodeid} was skipped while {FAIL_ON_SKIP}=1 (CI runs every test): "
            f"{skip_reason(report.longrepr)}"
        )
