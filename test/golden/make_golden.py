"""Write golden.json: the outputs of the cases in cases.py, as this tree computes them.

Run from the repository root: ``python test/golden/make_golden.py``. Only to be run on purpose,
when a change of the numbers is intended and understood.
"""

import json
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path[:0] = [str(HERE), str(HERE.parent)]

import cases  # noqa: E402


def main() -> None:
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        meshes = cases.write_meshes(folder / "meshes")
        golden = {
            "coeff": cases.coeff_outputs(meshes),
            "database": cases.database_outputs(meshes, folder),
            "bag_analyze": cases.bag_outputs(meshes, folder),
            "node": cases.node_outputs(meshes),
        }
    (HERE / "golden.json").write_text(json.dumps(golden, indent=None, separators=(",", ":")) + "\n")


if __name__ == "__main__":
    main()
