"""Golden outputs: coeff, database, bag analyze, the estimator of an articulated body and node
wrenches as recorded in test/golden.

The reference numbers (test/golden/golden.json) were written by test/golden/make_golden.py from
the user-facing entry points; any change of behaviour on those paths (models, shading and its
interpolation, URDF bodies and their joints, test particles with a seed, flight conditions,
solar pressure, database, bag analysis, the node) shows here. Equal within 1e-12 of each list's
largest magnitude. To record a new case, add it to test/golden/cases.py or joint_cases.py and
run ``python test/golden/make_golden.py --new GROUP`` from the repository root (the recorded
cases stay as they are); ``python test/golden/make_golden.py`` records every group again.
"""

import json
import sys
from pathlib import Path

import pytest

GOLDEN = Path(__file__).resolve().parent / "golden"
sys.path.insert(0, str(GOLDEN))

import cases  # noqa: E402
import joint_cases  # noqa: E402

RTOL = 1e-12


@pytest.fixture(scope="module")
def golden():
    return json.loads((GOLDEN / "golden.json").read_text())


@pytest.fixture(scope="module")
def meshes(tmp_path_factory):
    return cases.write_meshes(tmp_path_factory.mktemp("golden_meshes"))


def check(reference, actual):
    problems = cases.compare(reference, actual, RTOL)
    assert not problems, f"{len(problems)} differences, first: " + "; ".join(problems[:5])


def test_coeff(golden, meshes):
    check(golden["coeff"], cases.coeff_outputs(meshes))


def test_database(golden, meshes, tmp_path):
    check(golden["database"], cases.database_outputs(meshes, tmp_path))


def test_bag_analyze(golden, meshes, tmp_path):
    check(golden["bag_analyze"], cases.bag_outputs(meshes, tmp_path))


def test_estimator_joints(golden):
    check(golden["estimator"], joint_cases.estimator_outputs())


@pytest.mark.ros
def test_node_wrenches(golden, meshes):
    pytest.importorskip("rclpy")
    check(golden["node"], cases.node_outputs(meshes))
