"""The node's parameters keep their declared types, unknown start-up names and out-of-range
epochs stop it, and `adbsat-ros param set` reads a value as its parameter's type (real rclpy, the
node as its own process for the command line)."""

import pytest

pytestmark = pytest.mark.ros
pytest.importorskip("rclpy")

import os
import subprocess
import sys

import rclpy
from rcl_interfaces.msg import ParameterType
from rclpy.parameter import Parameter
from ros_harness import HANG_TIMEOUT, make_context

from adbsat_ros.cli import main
from adbsat_ros.ros.node import AdbsatNode

NODE = [sys.executable, "-m", "adbsat_ros.ros.node", "--ros-args", "-p", "shading:=none"]
#: The node process's name (its own: see node_process)
NAME = f"adbsat_node_parameters_{os.getpid()}"


@pytest.fixture(scope="module")
def node_process(tmp_path_factory):
    """adbsat_node (the example, no shading) as its own process, named :data:`NAME`."""
    # a name of its own, so that no other node of the run can take the requests, and its output
    # in a file (a pipe nobody reads could fill and stop it)
    log = tmp_path_factory.mktemp("node") / "node.log"
    with open(log, "w") as out:
        proc = subprocess.Popen(NODE + ["-r", f"__node:={NAME}"], stdout=out, stderr=out)
    try:  # (whatever happens, the process goes: a stray node would answer other tests)
        # up when it answers (however long this machine takes to start it)
        wait = ["--timeout", str(HANG_TIMEOUT)]
        up = main(["param", "get", NAME, "mesh", *wait]) == 0
        assert up, f"the node did not answer: {log.read_text()}"
        yield proc
    finally:
        proc.terminate()
        try:
            proc.wait(timeout=HANG_TIMEOUT)
        except subprocess.TimeoutExpired:
            proc.kill()


def param(capsys, *args):
    """``adbsat-ros param ARGS``: (exit status, stdout, stderr)."""
    capsys.readouterr()
    status = main(["param", *args, "--timeout", str(HANG_TIMEOUT)])
    out, err = capsys.readouterr()
    return status, out.strip(), err.strip()


@pytest.mark.parametrize(
    "name, text, shown, got",
    [
        ("center_of_mass", "[0.1, 0, 0]", "[0.1, 0.0, 0.0]", "[0.1, 0.0, 0.0]"),
        ("epoch_utc", "2027-01-01T00:00:00", "'2027-01-01T00:00:00'", "'2027-01-01T00:00:00'"),
        ("mass", "2e2", "200.0", "200.0"),
        ("mass", "150", "150.0", "150.0"),
        ("shading_samples", "32.0", "32", "32"),
        ("eci_frame_ids", "[eci, 2027-01-01, 5]", "['eci', '2027-01-01', '5']", None),
        ("shading_interpolation", "false", "False", "False"),
    ],
)
def test_param_set_reads_the_value_as_the_declared_type(
    node_process, capsys, name, text, shown, got
):
    status, out, err = param(capsys, "set", NAME, name, text)
    assert (status, out, err) == (0, f"set {name} = {shown}", "")
    if got is not None:
        assert param(capsys, "get", NAME, name) == (0, got, "")


@pytest.mark.parametrize(
    "name, text, needle",
    [
        ("shading_samples", "99999999999999999999", "shading_samples: 99999999999999999999 "
         "is outside the range of a ROS integer parameter [-9223372036854775808, "
         "9223372036854775807]"),
        ("shading_samples", "2.5", "shading_samples takes a whole number (integer), got '2.5'"),
        ("mass", "heavy", "mass takes a number (double), got 'heavy'"),
        ("center_of_mass", "[0.1, x, 0]", "center_of_mass[1] takes a number (double), got 'x'"),
        ("center_of_mass", "0.1", "center_of_mass takes a list"),
        ("anomalous_oxygen", "maybe", "anomalous_oxygen takes true or false, got 'maybe'"),
    ],
)  # fmt: skip
def test_param_set_refuses_a_value_of_another_type_in_one_line(node_process, capsys, name, text,
                                                               needle):  # fmt: skip
    before = param(capsys, "get", NAME, name)
    status, out, err = param(capsys, "set", NAME, name, text)
    assert status == 2 and out == "" and needle in err and len(err.splitlines()) == 1, err
    assert param(capsys, "get", NAME, name) == before


@pytest.mark.parametrize("epoch", ["1900-01-01T00:00:00", "2200-01-01T00:00:00"])
def test_param_set_refuses_an_epoch_outside_its_range(node_process, capsys, epoch):
    before = param(capsys, "get", NAME, "epoch_utc")
    status, out, err = param(capsys, "set", NAME, "epoch_utc", epoch)
    assert status == 1 and len(err.splitlines()) == 1
    assert "epoch_utc must be from 1958-01-01T00:00:00 to 2100-12-31T23:59:59 UTC" in err
    assert param(capsys, "get", NAME, "epoch_utc") == before


@pytest.mark.parametrize("action", [["list"], ["get", "f107"], ["set", "f107", "150"]])
def test_param_names_an_invalid_node_name_in_one_line(capsys, action):
    status, out, err = param(capsys, action[0], "bad name!", *action[1:])
    assert status == 2 and out == "" and len(err.splitlines()) == 1
    assert err.startswith("adbsat-ros param: error: node 'bad name!': not a valid node name")


@pytest.mark.parametrize(
    "option, needle",
    [
        ("alpah:=0.5", "adbsat_node: error: parameter alpah: unknown (did you mean alpha?)"),
        ("f10:=120.0", "adbsat_node: error: parameter f10: unknown (did you mean f107?)"),
        ("epoch_utc:=2200-01-01T00:00:00", "parameter epoch_utc: epoch_utc must be from "
         "1958-01-01T00:00:00 to 2100-12-31T23:59:59 UTC"),
        ("epoch_utc:=1900-01-01T00:00:00", "got '1900-01-01T00:00:00'"),
        ("f107:=high", "adbsat_node: error: parameter f107: expected a number, got 'high'"),
    ],
)  # fmt: skip
def test_a_bad_start_up_parameter_stops_the_node_in_one_line(option, needle):
    proc = subprocess.run(NODE + ["-p", option], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 1 and needle in proc.stderr
    assert len(proc.stderr.strip().splitlines()) == 1, proc.stderr


@pytest.fixture
def context():
    ctx, executor = make_context()
    try:
        yield ctx
    finally:
        executor.shutdown()
        rclpy.try_shutdown(context=ctx)


def test_parameters_keep_their_declared_types(context):
    """An integer given to a number parameter (at start-up or later) is that double, a whole
    double given to a whole-number parameter that integer; a value of another type is refused
    and the parameter keeps its type."""
    node = AdbsatNode(
        context=context,
        parameter_overrides=[
            Parameter("shading", value="none"),
            Parameter("f107", value=180),
            Parameter("center_of_mass", value=[0, 0, 1]),
            Parameter("shading_samples", value=32.0),
        ],
    )
    try:
        for name, value, kind in (
            ("f107", 180.0, ParameterType.PARAMETER_DOUBLE),
            ("center_of_mass", [0.0, 0.0, 1.0], ParameterType.PARAMETER_DOUBLE_ARRAY),
            ("shading_samples", 32, ParameterType.PARAMETER_INTEGER),
        ):
            got = node.get_parameter(name)
            assert (got.value, got.type_.value) == (value, kind)
            assert type(got.value) is type(value)
            assert not node.describe_parameter(name).dynamic_typing
        assert node.estimator.settings.center_of_mass == (0.0, 0.0, 1.0)
        assert node.set_parameters([Parameter("mass", value=200)])[0].successful
        assert node.get_parameter("mass").type_ == Parameter.Type.DOUBLE
        assert node.get_parameter("mass").value == 200.0
        assert node.set_parameters([Parameter("shading_samples", value=8.0)])[0].successful
        assert node.get_parameter("shading_samples").value == 8
        for name, value in (("mass", "2e2"), ("shading_samples", 2.5), ("alpha", True)):
            assert not node.set_parameters([Parameter(name, value=value)])[0].successful
        assert node.get_parameter("mass").value == 200.0
        assert node.get_parameter("shading_samples").value == 8
    finally:
        node.destroy_node()


def test_an_unknown_override_stops_the_node_with_the_closest_name(context):
    with pytest.raises(ValueError, match=r"^parameter alpah: unknown \(did you mean alpha\?\)$"):
        AdbsatNode(context=context, parameter_overrides=[Parameter("alpah", value=0.5)])
