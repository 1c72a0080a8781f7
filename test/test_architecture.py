"""The package's architecture, checked: the rules of the developers' guide as tests.

* every subpackage (and top-level module) of adbsat_ros imports alone, in a fresh interpreter;
* only modules under ``adbsat_ros/ros`` import rclpy or ROS message packages: in their source
  (every import statement, function-level ones included) and when imported (``sys.modules``);
* no import cycles between modules (grimp's import graph, strongly connected components), and the
  subpackages form the layers below: a subpackage imports only from layers beneath its own;
* no module over 450 lines;
* every third-party package it imports is declared in setup.py (``install_requires``; ROS 2
  packages come with the ``ros`` extra).
"""

from __future__ import annotations

import ast
import copy
import importlib.metadata
import importlib.util
import json
import re
import subprocess
import sys
from pathlib import Path

import grimp
import pytest

PACKAGE = "adbsat_ros"
PACKAGE_DIR = Path(importlib.util.find_spec(PACKAGE).submodule_search_locations[0])
ROS_SUBPACKAGE = f"{PACKAGE}.ros"
MAX_LINES = 450

# From the top: a layer may import from the layers below it, never from one above. Names in one
# layer are independent: they do not import each other.
LAYERS = (
    {"cli"},
    {"ros"},
    {"bags", "sweep"},
    {"estimator"},
    {"database", "environment", "plotting"},
    {"physics"},
    {"shading"},
    {"tasks"},
    {"geometry", "messages", "processes", "validation"},
    {"bounds", "lru", "npz_store", "_version"},
)

# Top-level names of ROS 2 Python packages: the client library, its support packages and every
# interface package (message, service and action definitions).
ROS_NAMES = {"rclpy", "rpyutils", "ament_index_python", "launch", "launch_ros", "tf2_ros"}
ROS_PREFIXES = ("rcl_", "rmw", "rosidl_", "ament_")
ROS_SUFFIXES = ("_msgs", "_srvs", "_interfaces", "_actions")


def is_ros_module(name: str) -> bool:
    """True if ``name`` (a dotted module name) belongs to a ROS 2 Python package."""
    top = name.split(".")[0]
    return top in ROS_NAMES or top.startswith(ROS_PREFIXES) or top.endswith(ROS_SUFFIXES)


def module_name(path: Path) -> str:
    """Dotted module name of a source file under PACKAGE_DIR."""
    parts = path.relative_to(PACKAGE_DIR.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


MODULE_FILES = {
    module_name(path): path
    for path in sorted(PACKAGE_DIR.rglob("*.py"))
    if "__pycache__" not in path.parts
}
# The units that must import alone: the package, each subpackage and each top-level module.
UNITS = sorted(
    {PACKAGE} | {f"{PACKAGE}.{name.split('.')[1]}" for name in MODULE_FILES if name != PACKAGE}
)
NON_ROS_UNITS = [unit for unit in UNITS if unit != ROS_SUBPACKAGE]


def in_unit(module: str, unit: str) -> bool:
    """True if ``module`` is ``unit`` or inside it (the package itself is its own unit)."""
    if unit == PACKAGE:
        return module == PACKAGE
    return module == unit or module.startswith(unit + ".")


def is_in_ros_subpackage(module: str) -> bool:
    """True for adbsat_ros.ros and its modules, the only ones allowed to import ROS."""
    return in_unit(module, ROS_SUBPACKAGE)


# ----------------------------------------------------------------------------------------------
# Imports in the source


def imports_in_source(source: str) -> list[tuple[int, str]]:
    """(line, module) of every absolute import in ``source``, at any depth.

    Import statements anywhere (module level, in functions, under ``if TYPE_CHECKING`` or
    ``try``) and ``importlib.import_module`` / ``__import__`` calls with a literal name.
    """
    found = []
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Import):
            found += [(node.lineno, alias.name) for alias in node.names]
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            found.append((node.lineno, node.module))
        elif isinstance(node, ast.Call) and node.args:
            func = node.func
            called = func.attr if isinstance(func, ast.Attribute) else getattr(func, "id", "")
            first = node.args[0]
            if called in ("import_module", "__import__") and isinstance(first, ast.Constant):
                if isinstance(first.value, str):
                    found.append((node.lineno, first.value))
    return found


def test_the_source_scan_finds_function_level_and_dynamic_imports():
    """The scan below can fail: it sees imports inside functions and literal dynamic imports."""
    source = (
        "import numpy\n"
        "def f():\n"
        "    from geometry_msgs.msg import Wrench\n"
        "    return importlib.import_module('rclpy.node')\n"
    )
    ros = [name for _, name in imports_in_source(source) if is_ros_module(name)]
    assert ros == ["geometry_msgs.msg", "rclpy.node"]
    assert not is_ros_module("rosbags.rosbag2") and not is_ros_module("numpy")
    node_imports = imports_in_source(MODULE_FILES[f"{ROS_SUBPACKAGE}.node"].read_text("utf-8"))
    assert any(name == "rclpy" or name.startswith("rclpy.") for _, name in node_imports)


@pytest.mark.parametrize(
    "module", [m for m in MODULE_FILES if not is_in_ros_subpackage(m)], ids=str
)
def test_only_the_ros_subpackage_imports_ros_in_its_source(module):
    imports = imports_in_source(MODULE_FILES[module].read_text(encoding="utf-8"))
    ros = [f"line {line}: {name}" for line, name in imports if is_ros_module(name)]
    assert not ros, f"{module} imports ROS 2 packages (only {ROS_SUBPACKAGE} may): {ros}"


# ----------------------------------------------------------------------------------------------
# Imports when run: each unit alone in a fresh interpreter

PROBE = r"""
import importlib, json, sys, traceback

unit, modules, names, prefixes, suffixes = json.loads(sys.argv[1])
prefixes, suffixes = tuple(prefixes), tuple(suffixes)

def is_ros(top):
    return top in names or top.startswith(prefixes) or top.endswith(suffixes)

def ros_loaded():
    return {top for top in {name.split(".")[0] for name in sys.modules} if is_ros(top)}

result = {"alone": None, "ros": {}, "errors": {}}
try:
    importlib.import_module(unit)
except BaseException:
    result["alone"] = traceback.format_exc()
if ros_loaded():
    result["ros"][unit] = sorted(ros_loaded())
for name in modules:
    before = ros_loaded()
    try:
        importlib.import_module(name)
        if name == "adbsat_ros.cli":
            importlib.import_module(name).build_parser()
    except BaseException:
        result["errors"][name] = traceback.format_exc()
    brought = ros_loaded() - before
    if brought:
        result["ros"][name] = sorted(brought)
print(json.dumps(result))
"""


def start_probe(unit: str, modules: list[str]) -> subprocess.Popen:
    """A fresh interpreter that imports ``unit`` first, then each of ``modules``."""
    argument = json.dumps(
        [unit, modules, sorted(ROS_NAMES), list(ROS_PREFIXES), list(ROS_SUFFIXES)]
    )
    return subprocess.Popen(
        [sys.executable, "-c", PROBE, argument],
        cwd=PACKAGE_DIR.parent,  # the package under test comes first on sys.path
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )


def finish_probe(process: subprocess.Popen) -> dict:
    """The JSON result of a probe; an interpreter that died is a failure with its stderr."""
    out, err = process.communicate(timeout=300)
    assert process.returncode == 0, err
    return json.loads(out.splitlines()[-1])


@pytest.fixture(scope="module")
def probes():
    """Per unit: a traceback if it does not import alone, and the ROS modules each module brings.

    The units run in parallel, one fresh interpreter each. The ROS subpackage is only imported
    (its modules need rclpy; a test of their own checks that the probe sees it); ``__main__``
    modules are not imported (importing one runs the program).
    """
    running = {}
    for unit in UNITS:
        modules = [
            m
            for m in MODULE_FILES
            if in_unit(m, unit) and unit != ROS_SUBPACKAGE and not m.endswith(".__main__")
        ]
        running[unit] = start_probe(unit, modules)
    return {unit: finish_probe(process) for unit, process in running.items()}


@pytest.mark.parametrize("unit", UNITS, ids=str)
def test_each_subpackage_imports_alone(unit, probes):
    assert probes[unit]["alone"] is None, f"{unit} does not import alone:\n{probes[unit]['alone']}"


@pytest.mark.parametrize("unit", NON_ROS_UNITS, ids=str)
def test_importing_a_subpackage_outside_ros_loads_no_ros(unit, probes):
    result = probes[unit]
    assert not result["errors"], f"modules of {unit} that fail to import: {result['errors']}"
    assert not result["ros"], f"modules of {unit} that load ROS 2 packages: {result['ros']}"


@pytest.mark.ros
def test_the_import_probe_sees_the_node_load_rclpy():
    """The check above can fail: importing the node really brings rclpy in."""
    pytest.importorskip("rclpy")
    result = finish_probe(start_probe(ROS_SUBPACKAGE, [f"{ROS_SUBPACKAGE}.node"]))
    assert not result["errors"], result["errors"]
    assert "rclpy" in result["ros"].get(f"{ROS_SUBPACKAGE}.node", [])


# ----------------------------------------------------------------------------------------------
# The import graph: no cycles, layers


@pytest.fixture(scope="module")
def graph():
    """grimp's graph of every import between adbsat_ros modules (function-level ones included)."""
    built = grimp.build_graph(PACKAGE, cache_dir=None)
    assert set(built.modules) == set(MODULE_FILES), "grimp read another copy of the package"
    return built


def strongly_connected_components(graph) -> list[list[str]]:
    """The import cycles of ``graph``: its strongly connected components of more than one module,
    and modules that import themselves (Tarjan's algorithm, iterative)."""
    index, low, on_stack, stack, components = {}, {}, set(), [], []
    successors = {m: sorted(graph.find_modules_directly_imported_by(m)) for m in graph.modules}
    for root in sorted(successors):
        if root in index:
            continue
        work = [(root, iter(successors[root]))]
        index[root] = low[root] = len(index)
        stack.append(root)
        on_stack.add(root)
        while work:
            node, children = work[-1]
            child = next(children, None)
            if child is not None:
                if child not in index:
                    index[child] = low[child] = len(index)
                    stack.append(child)
                    on_stack.add(child)
                    work.append((child, iter(successors[child])))
                elif child in on_stack:
                    low[node] = min(low[node], index[child])
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[node])
            if low[node] == index[node]:
                component = []
                while True:
                    member = stack.pop()
                    on_stack.discard(member)
                    component.append(member)
                    if member == node:
                        break
                if len(component) > 1 or node in successors[node]:
                    components.append(sorted(component))
    return components


def describe_cycle(graph, component: list[str]) -> str:
    """One shortest import cycle through the first module of a strongly connected component."""
    start = component[0]
    chains = [
        graph.find_shortest_chain(importer=child, imported=start)
        for child in graph.find_modules_directly_imported_by(start)
        if child in component
    ]
    chain = min((c for c in chains if c), key=len)
    return " -> ".join((start,) + tuple(chain))


def test_the_cycle_finder_finds_a_cycle(graph):
    """The check below can fail: an import added from a low module to a high one is a cycle."""
    looped = copy.deepcopy(graph)
    looped.add_import(importer=f"{PACKAGE}.geometry.mesh", imported=f"{PACKAGE}.cli.coeff")
    cycles = strongly_connected_components(looped)
    assert any(f"{PACKAGE}.geometry.mesh" in c and f"{PACKAGE}.cli.coeff" in c for c in cycles)


def test_no_import_cycles_between_modules(graph):
    cycles = [
        describe_cycle(graph, component) for component in strongly_connected_components(graph)
    ]
    assert not cycles, "import cycles:\n" + "\n".join(cycles)


def test_every_subpackage_has_a_layer():
    layered = set().union(*LAYERS)
    units = {unit.split(".")[1] for unit in UNITS if unit != PACKAGE}
    assert units == layered, (
        f"not in LAYERS: {sorted(units - layered)}; no longer in the package: "
        f"{sorted(layered - units)}"
    )


def test_subpackages_import_only_from_layers_below(graph):
    layers = [{f"{PACKAGE}.{name}" for name in layer} for layer in LAYERS]
    present = [layer & set(graph.modules) for layer in layers]
    illegal = graph.find_illegal_dependencies_for_layers(layers=[p for p in present if p])
    found = []
    for dependency in sorted(illegal, key=lambda d: (d.importer, d.imported)):
        route = min(dependency.routes, key=lambda r: (len(r.middle), sorted(r.heads)))
        chain = " -> ".join([min(route.heads), *route.middle, min(route.tails)])
        found.append(f"{dependency.importer} imports {dependency.imported}: {chain}")
    assert not found, "imports against the layers (LAYERS, top first):\n" + "\n".join(found)


# ----------------------------------------------------------------------------------------------
# Declared dependencies


def distribution_key(requirement: str) -> str:
    """The normalised distribution name of a requirement string (PEP 503)."""
    name = re.split(r"[<>=!~;\[ ]", requirement, maxsplit=1)[0]
    return re.sub(r"[-_.]+", "-", name).lower()


def setup_py_list(name: str) -> list[str]:
    """The literal list assigned to ``name`` at the top of setup.py."""
    tree = ast.parse((Path(__file__).resolve().parents[1] / "setup.py").read_text("utf-8"))
    for node in tree.body:
        if isinstance(node, ast.Assign) and [t.id for t in node.targets] == [name]:
            return ast.literal_eval(node.value)
    raise AssertionError(f"setup.py has no list {name}")


def test_every_imported_package_is_declared_in_setup_py():
    declared = {distribution_key(r) for r in setup_py_list("REQUIRES")}
    providers = importlib.metadata.packages_distributions()
    imported = {
        name.split(".")[0]
        for path in MODULE_FILES.values()
        for _, name in imports_in_source(path.read_text(encoding="utf-8"))
    }
    third_party = {
        top
        for top in imported
        if top != PACKAGE and top not in sys.stdlib_module_names and not is_ros_module(top)
    }
    assert {"numpy", "yaml"} <= third_party  # the scan sees module- and function-level imports
    missing = {
        top: providers.get(top, [top])
        for top in sorted(third_party)
        if not any(distribution_key(d) in declared for d in providers.get(top, [top]))
    }
    assert not missing, f"imported but not in setup.py's install_requires: {missing}"


# ----------------------------------------------------------------------------------------------
# Size


@pytest.mark.parametrize("module", list(MODULE_FILES), ids=str)
def test_module_is_at_most_450_lines(module):
    lines = len(MODULE_FILES[module].read_text(encoding="utf-8").splitlines())
    assert lines <= MAX_LINES, f"{module} has {lines} lines (at most {MAX_LINES})"
