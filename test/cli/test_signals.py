"""SIGINT and SIGTERM at any moment of an ``adbsat-ros`` command: from its first instruction on,
one line on stderr, the documented exit status, no traceback; long work stops at its next
boundary; worker processes never outlive the command."""

from __future__ import annotations

import json
import os
import signal

import pytest
import xarray as xr
import yaml
from signal_probes import (
    Run,
    alive,
    console_script,
    cpu_seconds,
    descendants,
    signal_in_start_up,
    wait_gone,
)

from adbsat_ros.bags import io as bag_io
from adbsat_ros.bags import scenario
from adbsat_ros.cli import main

FLOW = ["--speed", "7700", "--temperature", "900", "--mean-mass", "16"]
CLI = console_script("adbsat-ros")

#: How far into its start-up each run signals a command: once it has mapped this many more
#: files (0: as soon as it handles signals).
START_UP_POINTS = (0, 30, 70)


@pytest.fixture(scope="module")
def inputs(tmp_path_factory):
    """A long bag, a small database and a sweep spec."""
    root = tmp_path_factory.mktemp("inputs")
    messages = scenario.generate(scenario.Scenario(duration_s=1200, rate_hz=100, state_rate_hz=10))
    bag_io.write_scenario_bag(messages, root / "long")
    argv = ["database", "example", *FLOW, "--aoa", "0,10", "--aos", "0", "--workers", "1"]
    assert main([*argv, "--out", str(root / "db.npz")]) == 0
    spec = {
        "mesh": "example",
        "shading": "raycast",
        "fixed": {"temperature": 900, "mean_mass_amu": 16, "speed": 7500},
        "axes": {"aoa": "-180:0.5:180", "aos": "0:5:90"},  # (workers busy for seconds each)
        "chunk_points": 60,
    }
    (root / "spec.yaml").write_text(yaml.safe_dump(spec), encoding="utf-8")
    return root


def command(name: str, inputs, out) -> list:
    """A long run of subcommand ``name``, its outputs in ``out``."""
    return {
        "coeff": ["coeff", "example", *FLOW, "--aoa=-180:1:180", "--aos=-90:1:90", "--json"],
        "atmosphere": [
            "atmosphere",
            "--time",
            "2015-01-19T00:00:00Z",
            "--altitude",
            "300",
            "--lat",
            "0",
            "--lon",
            "0",
        ],
        "database": ["database", "example", *FLOW, "--out", str(out / "db.npz"), "--workers", "2"],
        "plot": ["plot", str(inputs / "db.npz"), "--out-dir", str(out / "plots")],
        "sweep": [
            "sweep",
            str(inputs / "spec.yaml"),
            "--out",
            str(out / "s.zarr"),
            "--workers",
            "2",
        ],
        "simulate": ["simulate", "--out", str(out / "sim"), "--duration", "20000"],
        "bag analyze": [
            "bag",
            "analyze",
            str(inputs / "long"),
            "--out",
            str(out / "out"),
            "--workers",
            "2",
        ],
    }[name]


@pytest.mark.parametrize(
    "name", ["coeff", "atmosphere", "database", "plot", "sweep", "simulate", "bag analyze"]
)
def test_a_signal_in_start_up_ends_the_command_with_one_line(name, inputs, tmp_path):
    hit = 0
    for k, more in enumerate(START_UP_POINTS):
        out = tmp_path / str(k)
        out.mkdir()
        signum = signal.SIGTERM if k == 1 else signal.SIGINT
        ended = signal_in_start_up([*CLI, *command(name, inputs, out)], more, signum)
        if ended is None:  # (it finished before this point: a short command)
            continue
        hit += 1
        status, _, err = ended
        assert "Traceback" not in err, (name, more, err)
        lines = err.strip().splitlines()
        assert len(lines) == 1, (name, more, err)
        assert "stopped" in lines[0] or "interrupted" in lines[0], (name, more, err)
        assert status == 1, (name, more, status, err)
        # nothing under a final name: a database, bag or CSV is complete or not there
        assert not (out / "db.npz").exists() and not (out / "out").exists()
        assert not (out / "out.csv").exists()
    assert hit >= 1, f"{name} never ran long enough to be signalled"


def test_ctrl_c_in_a_long_coeff_writes_the_attitudes_done():
    """A SIGINT while the panel method goes over many attitudes: those done are printed, one
    line says how many, status 1, no traceback."""
    run = Run([*CLI, "coeff", "example", *FLOW, "--aoa=-180:1:180", "--aos=-90:1:90", "--json"])
    try:
        # well into the attitudes: it has computed for a while after its start-up
        assert run.wait_for(lambda: cpu_seconds(run.proc.pid) > 8.0, "computation")
        run.proc.send_signal(signal.SIGINT)
        status, out, err = run.finish()
    finally:
        run.kill()
    assert status == 1 and "Traceback" not in err, err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "interrupted" in lines[0], err
    done = int(lines[0].split("those of the ")[1].split(" of ")[0])
    rows = json.loads(out)
    assert len(rows) == done > 0
    assert rows[-1]["aoa_deg"] == -180.0 + (done - 1) // 181


def test_a_sweep_stops_in_the_middle_of_its_chunks_and_stays_resumable(tmp_path):
    """SIGINT while the workers are inside chunks that take minutes: the sweep stops at once
    (the chunks running are dropped), says so in one line, status 1; its workers are gone and
    its store is there to resume."""
    spec = {
        "mesh": "example",
        "shading": "raycast",
        "fixed": {"temperature": 900, "mean_mass_amu": 16, "speed": 7500},
        "axes": {"aoa": "-180:0.5:180", "aos": "0:1:90"},
        "chunk_points": 40000,
    }
    (tmp_path / "spec.yaml").write_text(yaml.safe_dump(spec), encoding="utf-8")
    out = tmp_path / "s.zarr"
    run = Run([*CLI, "sweep", str(tmp_path / "spec.yaml"), "--out", str(out), "--workers", "2"])
    try:
        pid = run.proc.pid

        def computing():  # two workers, each into its chunk
            busy = [p for p in descendants(pid) if cpu_seconds(p) > 3.0]
            return len(busy) >= 2

        assert run.wait_for(computing, "workers computing")
        workers = descendants(pid)
        run.proc.send_signal(signal.SIGINT)
        status, _, err = run.finish()
    finally:
        run.kill()
    assert status == 1 and "Traceback" not in err, err
    lines = err.strip().splitlines()
    assert len(lines) == 1 and "run the same command again" in lines[0], err
    assert not [p for p in workers if alive(p)]
    done = xr.open_zarr(out, consolidated=False)["chunk_done"].values
    assert not done.any()  # (a rerun computes every chunk, into the same store)


@pytest.mark.parametrize("command_name", ["bag analyze", "sweep"])
def test_workers_die_with_a_killed_command(command_name, inputs, tmp_path):
    """kill -9 of a command with worker processes (bag analysis' pool, a sweep's Dask
    workers): every worker ends too."""
    run = Run([*CLI, *command(command_name, inputs, tmp_path)])
    try:
        pid = run.proc.pid
        assert run.wait_for(
            lambda: len([p for p in descendants(pid) if cpu_seconds(p) > 1.0]) >= 2, "workers"
        )
        workers = descendants(pid)
        os.kill(pid, signal.SIGKILL)
        run.proc.wait()
        left = wait_gone(workers)
        assert not left, f"workers {sorted(left)} outlived the killed command"
    finally:
        run.kill()
