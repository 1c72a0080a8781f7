"""Write golden.json: the outputs of the cases in cases.py and joint_cases.py, as this tree
computes them.

Run from the repository root, with the package and its dependencies (ROS 2 for the node group)
importable:

    python test/golden/make_golden.py                  # every group, golden.json rewritten
    python test/golden/make_golden.py --new coeff ...  # only cases golden.json lacks

``--new GROUP ...`` computes the named groups (coeff, database, bag_analyze, estimator, node)
and adds the cases, columns and keys that golden.json does not have yet, leaving those it has
as they were recorded: the way to add a case. Only to be run on purpose, when a change of the
numbers is intended and understood.
"""

import argparse
import json
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path[:0] = [str(HERE), str(HERE.parent)]

import cases  # noqa: E402
import joint_cases  # noqa: E402

GROUPS = {
    "coeff": lambda meshes, folder: cases.coeff_outputs(meshes),
    "database": cases.database_outputs,
    "bag_analyze": cases.bag_outputs,
    "estimator": lambda meshes, folder: joint_cases.estimator_outputs(),
    "node": lambda meshes, folder: cases.node_outputs(meshes),
}


def add_missing(recorded, computed):
    """``recorded`` with the keys of ``computed`` it lacks (at any depth of nested objects)."""
    if not isinstance(recorded, dict) or not isinstance(computed, dict):
        return recorded
    merged = dict(recorded)
    for key, value in computed.items():
        merged[key] = add_missing(recorded[key], value) if key in recorded else value
    return merged


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--new",
        nargs="+",
        choices=sorted(GROUPS),
        metavar="GROUP",
        help=f"add the missing cases of these groups ({', '.join(GROUPS)}) only",
    )
    args = parser.parse_args(argv)
    path = HERE / "golden.json"
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        meshes = cases.write_meshes(folder / "meshes")
        names = args.new or list(GROUPS)
        computed = {name: GROUPS[name](meshes, folder) for name in names}
    golden = add_missing(json.loads(path.read_text()), computed) if args.new else computed
    path.write_text(json.dumps(golden, indent=None, separators=(",", ":")) + "\n")


if __name__ == "__main__":
    main()
