"""Every table the package writes names its columns from one vocabulary, docs/outputs.md's."""

import re
from pathlib import Path
from types import SimpleNamespace

from adbsat_ros.bags.table import extra_columns, header
from adbsat_ros.database.format import AeroDatabase
from adbsat_ros.ros import demo_joints, demo_report

DOC = Path(__file__).resolve().parents[1] / "docs" / "outputs.md"


def vocabulary() -> set:
    """The column names of docs/outputs.md's table, a vector's ``_x`` given its y and z too."""
    names = set()
    for line in DOC.read_text(encoding="utf-8").splitlines():
        if line.startswith("| `"):
            for name in re.findall(r"`([^`]+)`", line.split("|")[1]):
                names |= {re.sub(r"_x(_|$)", rf"_{c}\1", name) for c in "xyz"}
    return names


def joint_free(columns) -> list:
    """``columns`` without their ``joint.NAME.`` columns, which must carry their unit."""
    units = {"position_rad", "effort_Nm", "position_m", "effort_N"}
    joints = [c for c in columns if c.startswith("joint.")]
    assert all(c.rsplit(".", 1)[1] in units for c in joints), joints
    return [c for c in columns if not c.startswith("joint.")]


BODY = {"hinge": SimpleNamespace(kind="revolute"), "mast": SimpleNamespace(kind="prismatic")}
BAG = [c[2:] for c in header(["m"], [extra_columns(True, BODY, True)]) if c.startswith("m.")]
BAG_COMMON = header([], [])
DEMO = demo_report.CSV_COLUMNS + demo_joints.CSV_COLUMNS
DATABASE = AeroDatabase.csv_columns(None)


def test_every_column_of_every_writer_is_in_the_documented_vocabulary():
    known = vocabulary()
    for writer, columns in (("bag", BAG_COMMON + BAG), ("demo", DEMO), ("database", DATABASE)):
        unknown = [c for c in joint_free(columns) if c not in known]
        assert not unknown, f"{writer} writes columns docs/outputs.md does not name: {unknown}"
    assert "joint.hinge.effort_Nm" in BAG and "joint.mast.position_m" in BAG


def test_the_writers_share_the_names_of_the_quantities_they_share():
    shared = {"drag_coefficient", *(f"c{k}_{a}" for k in "fm" for a in "xyz")}
    assert shared <= set(BAG) & set(DEMO) & set(DATABASE)
    assert {"altitude_m", "density_kg_m3", "relative_speed_m_s", "force_x_N", "torque_z_Nm"} <= (
        set(BAG) & set(DEMO)
    )
    assert {"time_s", "stamp_s"} <= set(BAG_COMMON) & set(DEMO)
    assert {"aoa_deg", "aos_deg"} <= set(BAG) & set(DATABASE)
    revolute = dict.fromkeys(demo_joints.JOINTS, SimpleNamespace(kind="revolute"))
    assert demo_joints.CSV_COLUMNS == extra_columns(False, revolute)
